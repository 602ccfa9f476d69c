// Distance queries near contact (GjkSettings::refine_near_contact): a separated pair closer than 32ε·m /
// rel_tolerance (2ε·m for two polytope cores; m the magnitude of the coordinates in A's frame) is refined by GJK in
// long double, so the double query keeps its 1e-9 relative accuracy at gaps of 1e-5 … 1e-6 of the shapes' size,
// up to 100 sizes from the origin (the double loop alone was off by up to 1e-8 there: its support points carry
// the rounding of the relative pose).
//
// Judged against a certified interval in the world frame. Upper: the witness points of long-double GJK on the
// shapes placed by their poses (Transformed), in both argument orders. Lower: supporting-plane gaps of the cores, minus the margins, along
// the normals found. Not long-double GJK in A's frame, as the benchmark's reference: that frame takes R_aᵀ for
// R_a's inverse, and a double rotation is orthonormal only to ~1e-16, which at a distance of 1e-7 is 1e-9 of it
// (a hull–cylinder pair: 1.0000000000392e-7 in A's frame, 0.99999999899596e-7 certified in the world). Margins
// are counted in the world too (a capsule's ball mapped by a slightly non-orthonormal R is off by 1e-17).
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include "narrowphase/near_contact_pose.hpp"
#include "test_common.hpp"

#include <random>

using namespace cdkit;

namespace {

using L = long double;

struct Tally {
    int attempts = 0, cases = 0, tight = 0, outside = 0, outside_unrefined = 0, refined = 0;
};

/// The gap between the supporting planes orthogonal to u of the two placed cores, less the margins: a lower bound
/// on the world-frame distance.
template <class A, class B> L world_plane_gap(const Transformed<A>& a, const Transformed<B>& b, const Vec3<L>& u) {
    const Vec3<L> n = u.normalized();
    return n.dot(b.core_support(Vec3<L>(-n))) - n.dot(a.core_support(n)) - a.margin() - b.margin();
}

/// Poses pairs at gap·size and checks the double distance against the certified interval (1e-9 relative).
template <class A, class AL, class B, class BL>
void check_pair(const A& a, const AL& a_l, const B& b, const BL& b_l, double gap, int n, std::mt19937_64& rng,
                Tally& t) {
    constexpr double size = 0.1, tol = 1e-9;
    GjkSettings<L> exact;
    exact.rel_tolerance = L(1e-16);
    GjkSettings<double> unrefined;
    unrefined.refine_near_contact = false;
    const Transform<L> world;
    for (int k = 0; k < n; ++k) {
        Transform<double> pa, pb;
        ++t.attempts;
        if (!test::place_near_contact(a_l, b_l, size, gap, rng, pa, pb)) continue;
        const Transformed<AL> ta{a_l, pa.cast<L>()};
        const Transformed<BL> tb{b_l, pb.cast<L>()};
        const auto ref = gjk_distance(ta, world, tb, world, nullptr, exact);
        const auto ref_swapped = gjk_distance(tb, world, ta, world, nullptr, exact);
        const auto d = gjk_distance(a, pa, b, pb);
        const auto plain = gjk_distance(a, pa, b, pb, nullptr, unrefined);
        REQUIRE(ref.status == GjkStatus::separated);
        REQUIRE(ref_swapped.status == GjkStatus::separated);
        REQUIRE(d.status == GjkStatus::separated);
        ++t.cases;
        t.refined += d.iterations > plain.iterations;
        const L lower = std::max({world_plane_gap(ta, tb, ref.normal), world_plane_gap(ta, tb, Vec3<L>(-ref_swapped.normal)),
                                  world_plane_gap(ta, tb, Vec3<L>(d.normal.template cast<L>()))});
        // The references' witness points are points of the placed shapes (up to ε_L of coordinates as large as
        // 10: 1e-11 of these distances): their distance bounds from above.
        const L upper =
            std::min((ref.point_b - ref.point_a).norm(), (ref_swapped.point_b - ref_swapped.point_a).norm());
        REQUIRE(lower <= upper * L(1 + 1e-10));
        t.tight += upper - lower <= L(tol) * lower;
        auto outside = [&](double x) { return L(x) < lower * L(1 - tol) || L(x) > upper * L(1 + tol); };
        t.outside_unrefined += outside(plain.distance);
        if (outside(d.distance)) {
            ++t.outside;
            UNSCOPED_INFO("gap " << gap << " case " << k << ": " << d.distance << " outside [" << double(lower)
                                 << ", " << double(upper) << "]");
        }
        CHECK(std::abs(d.normal.norm() - 1.0) <= 1e-12);
        // The witness points agree with the distance, up to their rounding to double (up to 10 from the origin).
        CHECK(std::abs((d.point_b - d.point_a).norm() - d.distance) <= 1e-13);
    }
}

}  // namespace

TEST_CASE("near-contact distances keep 1e-9 relative accuracy (long-double refinement)", "[gjk][accuracy]") {
    if constexpr (!detail::refines_near_contact<double>) {
        WARN("long double is not wider than double here: no near-contact refinement to test");
        return;
    }
    std::mt19937_64 rng(20261123);
    const Cylinder<double> cyl(0.05, 0.1);
    const Cylinder<L> cyl_l(0.05L, 0.1L);
    const Cone<double> cone(0.06, 0.09);
    const Cone<L> cone_l(0.06L, 0.09L);
    const Ellipsoid<double> ell(Vec3<double>(0.1, 0.05, 0.08));
    const Ellipsoid<L> ell_l(Vec3<L>(0.1L, 0.05L, 0.08L));
    const Box<double> box(Vec3<double>(0.05, 0.07, 0.03));
    const Box<L> box_l(Vec3<L>(0.05L, 0.07L, 0.03L));
    const Capsule<double> cap(0.03, 0.06);
    const Capsule<L> cap_l(0.03L, 0.06L);
    std::vector<Vec3<double>> pts;
    std::normal_distribution<double> g;
    for (int i = 0; i < 80; ++i) pts.push_back(Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 0.1);
    std::vector<Vec3<L>> pts_l;
    for (const auto& p : pts) pts_l.push_back(p.cast<L>());
    const ConvexPolyhedron<double> hull(pts);
    const ConvexPolyhedron<L> hull_l(pts_l);

    Tally t;
    const int n = test::scaled(60, 8);
    for (const double gap : {1e-5, 1e-6}) {
        check_pair(cone, cone_l, cyl, cyl_l, gap, n, rng, t);
        check_pair(cyl, cyl_l, cyl, cyl_l, gap, n, rng, t);
        check_pair(cone, cone_l, cone, cone_l, gap, n, rng, t);
        check_pair(ell, ell_l, cyl, cyl_l, gap, n, rng, t);
        check_pair(box, box_l, cone, cone_l, gap, n, rng, t);
        check_pair(cap, cap_l, cone, cone_l, gap, n, rng, t);
        check_pair(hull, hull_l, cyl, cyl_l, gap, n, rng, t);
        check_pair(ell, ell_l, ell, ell_l, gap, n, rng, t);
        // Polytope cores (HasPolytopeCore): refined from 2ε·m / tolerance on, 16× closer than curved pairs.
        check_pair(box, box_l, hull, hull_l, gap, n, rng, t);
        check_pair(cap, cap_l, box, box_l, gap, n, rng, t);
    }
    INFO(t.cases << " cases, " << t.tight << " with a certified interval within 1e-9, " << t.refined
                 << " refined; outside 1e-9: " << t.outside << " refined, " << t.outside_unrefined << " unrefined");
    CHECK(t.cases >= t.attempts / 2);  // place_near_contact gives up on ~40 % (no long-double normal on the way)
    CHECK(t.outside == 0);
    // The test has teeth: most intervals are tight, and the double loop alone misses them.
    CHECK(t.tight >= t.cases * 9 / 10);
    CHECK(t.outside_unrefined >= t.cases / 20);
    CHECK(t.refined >= t.cases / 2);
}

TEST_CASE("near-contact refinement: far pairs untouched; the widened shapes", "[gjk][accuracy]") {
    // Far pairs are not refined: the same iterations with the setting on and off.
    const Cone<double> cone(0.06, 0.09);
    const Cylinder<double> cyl(0.05, 0.1);
    std::mt19937_64 rng(5);
    GjkSettings<double> off;
    off.refine_near_contact = false;
    for (int k = 0; k < 50; ++k) {
        const Transform<double> pa(test::random_rotation(rng), Vec3<double>(0.2, -0.1, 0.3));
        const Transform<double> pb(test::random_rotation(rng), Vec3<double>(0.2, -0.1, 0.3) + test::random_unit(rng) * 0.4);
        const auto on = gjk_distance(cone, pa, cyl, pb);
        const auto plain = gjk_distance(cone, pa, cyl, pb, nullptr, off);
        CHECK(on.status == plain.status);
        if (on.status == GjkStatus::separated && on.distance > 1e-3) {
            CHECK(on.iterations == plain.iterations);
            CHECK(on.distance == plain.distance);
        }
    }
    // A cone rebuilt in long double has the same dimensions; shapes without widened() are viewed through
    // WidenedShape, which keeps their margin.
    const Cone<L> wide = cone.widened();
    CHECK(wide.radius == L(0.06));
    CHECK(wide.half_height == L(0.09));
    STATIC_REQUIRE(HasPolytopeCore<Box<double>> && HasPolytopeCore<Capsule<double>> &&
                   HasPolytopeCore<ConvexPolyhedron<double>>);
    STATIC_REQUIRE(!HasPolytopeCore<Cone<double>> && !HasPolytopeCore<Transformed<Box<double>>>);
    STATIC_REQUIRE(HasWidened<Cone<double>>);
    STATIC_REQUIRE(!HasWidened<Box<double>>);
    STATIC_REQUIRE(HasMargin<detail::WidenedShape<Capsule<double>>>);
    STATIC_REQUIRE(!HasMargin<detail::WidenedShape<Box<double>>>);
}
