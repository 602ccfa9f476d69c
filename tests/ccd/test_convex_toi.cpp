// Convex time of impact by conservative advancement: an answer known in closed form (spheres head-on), and fast
// seeded pairs of every size ratio against a dense sampling of the motion with GJK's boolean (the sampled first
// contact can only come at or after the true one, so the advancement must not report a later time).

#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <cdkit/ccd/convex_toi.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>

namespace {

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

/// First of `n` + 1 evenly spaced times at which GJK's boolean says the shapes meet (or 2 when never).
template <class A, class B>
double sampled_first_contact(const A& a, const T& a0, const T& a1, const B& b, const T& b0, const T& b1, int n) {
    const cdkit::detail::PoseMotion ma(a0, a1), mb(b0, b1);
    for (int i = 0; i <= n; ++i) {
        const double t = double(i) / n;
        if (cdkit::gjk_intersect(a, ma.at(t), b, mb.at(t)).colliding) return t;
    }
    return 2;
}

/// The checks of one fast pair's answer `r`: a contact the sampling saw (at `first` ≤ 1) is reported, never later;
/// at a reported time GJK measures the shapes within the default tolerance (up to its own accuracy, relative to
/// `scale`).
template <class A, class B>
void check_answer(const cdkit::ToiResult& r, double first, const A& a, const T& a0, const T& a1, const B& b,
                  const T& b0, const T& b1, double scale) {
    if (first <= 1) {
        CAPTURE(first, r.toi, r.iterations);
        REQUIRE(r.colliding);
        CHECK(r.toi <= first);
    }
    if (r.colliding && !r.capped) {
        const cdkit::detail::PoseMotion ma(a0, a1), mb(b0, b1);
        const auto g = cdkit::gjk_distance(a, ma.at(r.toi), b, mb.at(r.toi));
        CAPTURE(r.toi, g.distance);
        CHECK((g.colliding || g.distance <= 1e-6 * (1 + 1e-6) + 1e-9 * scale));
    }
}

}  // namespace

TEST_CASE("convex TOI: spheres head-on, known in closed form", "[ccd]") {
    const cdkit::Sphere<double> a(0.5), b(0.25);
    // A's centre from x = −10 to x = 10, B at rest at x = 2: contact when the gap 2 − x equals 0.75, at x = 1.25,
    // t = 11.25 / 20.
    const auto r = cdkit::convex_toi(a, T::translation(V(-10, 0, 0)), T::translation(V(10, 0, 0)), b,
                                     T::translation(V(2, 0, 0)), T::translation(V(2, 0, 0)));
    REQUIRE(r.status == cdkit::QueryStatus::ok);
    REQUIRE(r.colliding);
    CHECK(r.toi <= 11.25 / 20);
    CHECK(r.toi >= 11.25 / 20 - 1e-6);
    CHECK(r.normal.isApprox(V(1, 0, 0), 1e-6));
    // Passing by at a gap: no contact.
    CHECK_FALSE(cdkit::convex_toi(a, T::translation(V(-10, 1, 0)), T::translation(V(10, 1, 0)), b,
                                  T::translation(V(2, 0, 0)), T::translation(V(2, 0, 0)))
                    .colliding);
}

TEST_CASE("convex TOI: fast pairs of every size ratio never tunnel", "[ccd]") {
    std::mt19937_64 rng(34);
    std::uniform_real_distribution<double> unit(0, 1);
    const int n = cdkit::test::scaled(600, 60);
    int contacts = 0, sampled = 0;
    for (int i = 0; i < n; ++i) {
        // Sizes from 1e-3 to 1e3 (log-uniform), speeds up to 100 of the smaller size per step, rotations up to π.
        const double sa = std::pow(10.0, -3 + 6 * unit(rng)), sb = std::pow(10.0, -3 + 6 * unit(rng));
        const cdkit::Box<double> a(V(sa, 0.5 * sa, 0.3 * sa));
        const cdkit::Capsule<double> b(0.4 * sb, sb);
        const double small = std::min(sa, sb), reach = sa + sb;
        const V dir = cdkit::test::random_rotation<double>(rng).col(0);
        const V side = cdkit::test::random_rotation<double>(rng).col(0) * (unit(rng) * reach);
        const double travel = std::min(100 * small, 4 * reach) + 2 * reach;  // always enough to cross B
        const T a0(cdkit::test::random_rotation<double>(rng), -0.5 * travel * dir + side);
        const T a1(cdkit::test::random_rotation<double>(rng), 0.5 * travel * dir + side);
        const T b0(cdkit::test::random_rotation<double>(rng), V::Zero());
        const T b1 = b0;
        const auto r = cdkit::convex_toi(a, a0, a1, b, b0, b1);
        REQUIRE(r.status == cdkit::QueryStatus::ok);
        const double first = sampled_first_contact(a, a0, a1, b, b0, b1, 400);
        contacts += r.colliding;
        sampled += first <= 1;
        CAPTURE(i, sa, sb);
        check_answer(r, first, a, a0, a1, b, b0, b1, reach);
    }
    CHECK(sampled > n / 4);  // the motions do hit
    CHECK(contacts >= sampled);
}

TEST_CASE("shape cast: translating pairs of every size ratio never tunnel, hit within the tolerance", "[ccd]") {
    // Both shapes only translate, so convex_toi takes the GJK ray cast; the sampled GJK boolean judges it, and the
    // conservative advancement answers the same motions for comparison.
    std::mt19937_64 rng(341);
    std::uniform_real_distribution<double> unit(0, 1);
    const int n = cdkit::test::scaled(600, 60);
    const std::vector<V> octahedron{V(1, 0.2, 0), V(-1, 0.3, 0.1),  V(0, 1, -0.2),
                                    V(0.1, -1, 0.3), V(0.2, 0.1, 1), V(-0.3, 0, -1)};
    int contacts = 0, sampled = 0, agree = 0;
    for (int i = 0; i < n; ++i) {
        const double sa = std::pow(10.0, -3 + 6 * unit(rng)), sb = std::pow(10.0, -3 + 6 * unit(rng));
        const cdkit::Cone<double> a(0.6 * sa, 0.5 * sa);
        const cdkit::Box<double> box(V(sb, 0.6 * sb, 0.3 * sb));
        const double small = std::min(sa, sb), reach = sa + 1.2 * sb;
        const V dir = cdkit::test::random_rotation<double>(rng).col(0);
        const V side = cdkit::test::random_rotation<double>(rng).col(0) * (unit(rng) * reach);
        const double travel = std::min(100 * small, 4 * reach) + 2 * reach;
        const cdkit::Mat3<double> ra = cdkit::test::random_rotation<double>(rng), rb = cdkit::test::random_rotation<double>(rng);
        const V drift = cdkit::test::random_rotation<double>(rng).col(0) * (sb * unit(rng));
        const T a0(ra, -0.5 * travel * dir + side), a1(ra, 0.5 * travel * dir + side);
        const T b0(rb, V::Zero()), b1(rb, drift);
        auto check = [&](const auto& shape_b, double scale) {
            const auto r = cdkit::convex_toi(a, a0, a1, shape_b, b0, b1);
            REQUIRE(r.status == cdkit::QueryStatus::ok);
            const auto ca = cdkit::detail::convex_toi_advancement(a, cdkit::detail::PoseMotion(a0, a1), shape_b,
                                                                  cdkit::detail::PoseMotion(b0, b1), {});
            const double first = sampled_first_contact(a, a0, a1, shape_b, b0, b1, 400);
            contacts += r.colliding;
            sampled += first <= 1;
            agree += r.colliding == ca.colliding;
            CAPTURE(i, sa, sb);
            check_answer(r, first, a, a0, a1, shape_b, b0, b1, scale);
            // The witness points are the shapes' points at toi, within the tolerance of each other.
            if (r.colliding && !r.capped) CHECK((r.point_b - r.point_a).norm() <= 1e-6 + 1e-9 * scale);
        };
        check(box, reach);
        std::vector<V> corners;
        for (const V& p : octahedron) corners.push_back(sb * p);
        check(cdkit::ConvexPolyhedron<double>(corners), reach);
    }
    CHECK(sampled > n / 2);
    CHECK(contacts >= sampled);
    CHECK(agree >= 2 * n - 2 * n / 100);  // the two methods differ only on grazes within the tolerance
}

TEST_CASE("convex TOI: a shape's radius about its rotation axis bounds its points' distance from that axis", "[ccd]") {
    const cdkit::Box<double> box(V(1, 2, 3));
    CHECK(cdkit::detail::radius_about_axis(box, V::UnitZ()) == Approx(std::sqrt(5.0)).epsilon(1e-9));
    CHECK(cdkit::detail::radius_about_axis(box, V::UnitX()) == Approx(std::sqrt(13.0)).epsilon(1e-9));
    CHECK(cdkit::detail::radius_about_origin(box) == Approx(std::sqrt(14.0)).epsilon(1e-9));
    // A capsule turning about its own axis moves its points no faster than its radius says.
    const cdkit::Capsule<double> capsule(0.25, 2.0);
    CHECK(cdkit::detail::radius_about_axis(capsule, V::UnitZ()) == Approx(0.25 * std::sqrt(2.0)).epsilon(1e-9));
    // Over random axes it never undercuts a sampled surface point's distance from the axis.
    std::mt19937_64 rng(7);
    for (int i = 0; i < 200; ++i) {
        const V axis = cdkit::test::random_rotation<double>(rng).col(0);
        const double r = cdkit::detail::radius_about_axis(capsule, axis);
        for (int j = 0; j < 20; ++j) {
            const V p = capsule.support(cdkit::test::random_rotation<double>(rng).col(0));
            CHECK((p - p.dot(axis) * axis).norm() <= r);
        }
    }
}

TEST_CASE("convex TOI: bad poses and settings", "[ccd]") {
    const cdkit::Sphere<double> a(1.0);
    T bad;
    bad.R(1, 1) = -1;  // a reflection
    CHECK(cdkit::convex_toi(a, bad, T(), a, T(), T()).status == cdkit::QueryStatus::invalid_pose);
    cdkit::ToiRequest zero;
    zero.tolerance = 0;
    CHECK(cdkit::convex_toi(a, T(), T(), a, T(), T(), zero).status == cdkit::QueryStatus::invalid_input);
    for (const double separation : {-1e-3, std::nan(""), std::numeric_limits<double>::infinity()}) {
        cdkit::ToiRequest r;
        r.separation = separation;
        CHECK(cdkit::convex_toi(a, T(), T(), a, T(), T(), r).status == cdkit::QueryStatus::invalid_input);
    }
}

TEST_CASE("convex TOI with a separation: the shapes grown by it, in closed form", "[ccd]") {
    // The head-on spheres above with radii 0.5 and 0.25 less 0.2 each, and a separation of 0.4: the same contact time
    // (gap 2 − x = 0.75 at x = 1.25, t = 11.25 / 20), translating (no ray cast then) and turning (the advancement).
    const cdkit::Sphere<double> a(0.3), b(0.05);
    cdkit::ToiRequest req;
    req.separation = 0.4;
    for (const bool turn : {false, true}) {
        const T end(turn ? Eigen::AngleAxisd(1.0, V::UnitY()).toRotationMatrix() : cdkit::Mat3<double>::Identity(),
                    V(10, 0, 0));
        const auto r = cdkit::convex_toi(a, T::translation(V(-10, 0, 0)), end, b, T::translation(V(2, 0, 0)),
                                         T::translation(V(2, 0, 0)), req);
        INFO("turning: " << turn);
        REQUIRE(r.status == cdkit::QueryStatus::ok);
        REQUIRE(r.colliding);
        CHECK(r.toi <= 11.25 / 20);
        CHECK(r.toi >= 11.25 / 20 - 1e-6);
        CHECK((r.point_b - r.point_a).norm() == Approx(0.4).margin(1e-6));  // the cores' points, separation apart
    }
    // Passing by 0.05 beyond the grown radii: no contact.
    CHECK_FALSE(cdkit::convex_toi(a, T::translation(V(-10, 0.8, 0)), T::translation(V(10, 0.8, 0)), b,
                                  T::translation(V(2, 0, 0)), T::translation(V(2, 0, 0)), req)
                    .colliding);
}
