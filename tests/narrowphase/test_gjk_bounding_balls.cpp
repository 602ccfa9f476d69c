// The bounding-ball pre-test of the cold boolean GJK (GjkSettings::bounding_ball_test): the balls each shape
// reports contain it / lie inside it (sampled support maps, and tight), and the pre-test changes no answer —
// pairs placed at the balls' boundaries (centre distance = sum of radii ± 1e-3 … 0 relative, poses far from
// the origin) answer as with the test off, and as closed forms for spheres — while deciding clear cases
// without a support query (iterations == 0, with a certified separating plane).
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <random>

using namespace cdkit;

namespace {

std::vector<Vec3<double>> cloud(std::mt19937_64& rng, int n, double r, const Vec3<double>& offset) {
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0.3, 1.0);
    std::vector<Vec3<double>> p;
    for (int i = 0; i < n; ++i) p.push_back(offset + Vec3<double>(g(rng), g(rng), g(rng)).normalized() * r * u(rng));
    return p;
}

Vec3<double> unit(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    return Vec3<double>(g(rng), g(rng), g(rng)).normalized();
}

/// Samples the support map: the farthest support point from center() and the smallest support height
/// n·(s(n) − c) over unit n (the inner ball fits iff that height is ≥ its radius for every n).
template <class Shape> void check_balls(const Shape& s, std::mt19937_64& rng, double tight_outer, double tight_inner) {
    const Vec3<double> c = s.center();
    const double R = s.bounding_radius(), rho = s.inner_radius();
    double far = 0, low = std::numeric_limits<double>::infinity();
    auto probe = [&](const Vec3<double>& n) {
        const Vec3<double> p = s.support(n);
        far = std::max(far, (p - c).norm());
        low = std::min(low, n.dot(p - c));
    };
    for (int i = 0; i < test::scaled(20000, 2000); ++i) probe(unit(rng));
    for (int k = 0; k < 3; ++k)
        for (double sg : {-1.0, 1.0}) {
            Vec3<double> n = Vec3<double>::Zero();
            n[k] = sg;
            probe(n);
        }
    INFO("R " << R << " sampled " << far << "; inner " << rho << " sampled " << low);
    CHECK(far <= R * (1 + 1e-14));
    CHECK(low >= rho - 1e-14 * R);
    CHECK(far >= tight_outer * R);                   // not a loose bound
    CHECK(rho >= tight_inner * low - 1e-14 * R);     // nor a useless inner one
}

}  // namespace

TEST_CASE("bounding balls contain each shape and lie inside it", "[gjk][bounding_balls]") {
    std::mt19937_64 rng(601);
    check_balls(Sphere<double>(0.3), rng, 0.9999, 0.9999);
    check_balls(Box<double>(Vec3<double>(0.1, 0.3, 0.05)), rng, 0.999, 0.9999);
    check_balls(Capsule<double>(0.05, 0.2), rng, 0.999, 0.9999);
    check_balls(Cylinder<double>(0.1, 0.3), rng, 0.999, 0.99);
    check_balls(Cylinder<double>(0.3, 0.1), rng, 0.999, 0.99);
    // Cones: the inner radius is a lower bound (√(4h² + r²) ≤ 2h + r) at most 30 % below the exact ball.
    check_balls(Cone<double>(0.1, 0.3), rng, 0.999, 0.7);
    check_balls(Cone<double>(0.3, 0.05), rng, 0.999, 0.7);
    check_balls(Cone<double>(0.2, 0.2), rng, 0.999, 0.7);
    check_balls(Ellipsoid<double>(Vec3<double>(0.1, 0.25, 0.05)), rng, 0.999, 0.9999);
    check_balls(ConvexTriangle<double>(Vec3<double>(1, 0, 0), Vec3<double>(0, 2, 0), Vec3<double>(0, 0, 0.5)), rng,
                0.9999, 0.0);
    for (int n : {12, 100, 1000}) {
        // Off-centre hulls too: the balls are about center(), not the frame's origin.
        ConvexPolyhedron<double> hull(cloud(rng, n, 0.1, Vec3<double>(3, -2, 1)));
        check_balls(hull, rng, 0.9999, 0.9);
        CHECK(hull.inner_radius() > 0);
    }
    const Box<double> box(Vec3<double>(0.1, 0.2, 0.3));
    check_balls(Inflated<Box<double>>{box, 0.05}, rng, 0.999, 0.9999);
}

TEST_CASE("bounding-ball pre-test changes no boolean answer at the balls' boundaries", "[gjk][bounding_balls]") {
    // For each pair the centre distance is set to R_a + R_b or ρ_a + ρ_b times (1 + f), f ∈ ±{1e-3, 1e-9,
    // 1e-13, 1e-15} and 0, along a random direction, with both poses moved by a common offset of up to 1e3
    // (the rounding slack must cover the translation's magnitude). The answer with the pre-test must equal
    // the answer without it, and on sphere pairs (whose balls are the shapes) the closed form where it is
    // clear-cut.
    std::mt19937_64 rng(602);
    std::uniform_real_distribution<double> u(0.5, 1.0);
    GjkSettings<double> off;
    off.bounding_ball_test = false;
    int cases = 0, differ = 0, decided_out = 0, decided_in = 0, sphere_wrong = 0, uncertified = 0;
    const double factors[] = {1e-3, -1e-3, 1e-9, -1e-9, 1e-13, -1e-13, 1e-15, -1e-15, 0};
    auto run = [&](const auto& a, const auto& b, bool spheres) {
        for (int which = 0; which < 2; ++which)
            for (double f : factors) {
                const double offset_scale = std::pow(10.0, std::uniform_int_distribution<int>(-1, 3)(rng));
                const Vec3<double> offset = unit(rng) * offset_scale;
                Transform<double> pa(test::random_rotation(rng), Vec3<double>::Zero());
                Transform<double> pb(test::random_rotation(rng), Vec3<double>::Zero());
                const double target = which == 0 ? a.bounding_radius() + b.bounding_radius()
                                                 : a.inner_radius() + b.inner_radius();
                if (!(target > 0)) continue;
                // Place the centres (not the frame origins) target·(1 + f) apart.
                const Vec3<double> dir = unit(rng);
                pa.t = offset - pa.R * a.center();
                pb.t = offset + dir * (target * (1 + f)) - pb.R * b.center();
                ++cases;
                const auto on = gjk_intersect(a, pa, b, pb);
                const auto plain = gjk_intersect(a, pa, b, pb, nullptr, off);
                if (on.colliding != plain.colliding) ++differ;
                if (on.iterations == 0) (on.colliding ? decided_in : decided_out) += 1;
                if (on.iterations == 0 && on.status == GjkStatus::separated) {
                    // Certified: the planes through point_a / point_b orthogonal to the normal bound the shapes.
                    const Vec3<double> n = on.normal;
                    const double ha = n.dot(pa * Vec3<double>(a.support(pa.R.transpose() * n)));
                    const double hb = n.dot(pb * Vec3<double>(b.support(pb.R.transpose() * Vec3<double>(-n))));
                    const double tol = 1e-12 * (1 + offset_scale);
                    if (!(on.distance > 0) || std::abs(n.norm() - 1) > 1e-12 || ha > n.dot(on.point_a) + tol ||
                        hb < n.dot(on.point_b) - tol || std::abs(n.dot(on.point_b - on.point_a) - on.distance) > tol ||
                        hb - ha < on.distance - tol)
                        ++uncertified;
                }
                if (spheres && std::abs(f) >= 1e-9) {
                    // Closed form: the spheres overlap iff their centre distance is below r_a + r_b.
                    const bool hit = f < 0;  // both balls are the spheres themselves
                    if (on.colliding != hit) ++sphere_wrong;
                }
            }
    };
    for (int k = 0; k < test::scaled(40, 8); ++k) {
        const double r1 = 0.1 * u(rng), r2 = 0.1 * u(rng), h1 = 0.1 * u(rng), h2 = 0.1 * u(rng);
        run(Sphere<double>(r1), Sphere<double>(r2), true);
        run(Box<double>(Vec3<double>(r1, h1, r2)), Box<double>(Vec3<double>(h2, r1, h1)), false);
        run(Capsule<double>(r1 / 2, h1), Sphere<double>(r2), false);
        run(Cylinder<double>(r1, h1), Cone<double>(r2, h2), false);
        run(Ellipsoid<double>(Vec3<double>(r1, h1, r2)), Box<double>(Vec3<double>(h2, r2, r1)), false);
        const ConvexPolyhedron<double> hull(cloud(rng, 60, 0.1, Vec3<double>(0.5, 0, 0)));
        run(hull, Cylinder<double>(r2, h2), false);
        run(ConvexTriangle<double>(Vec3<double>(r1, 0, 0), Vec3<double>(0, h1, 0), Vec3<double>(0, 0, r2)),
            Box<double>(Vec3<double>(h2, r2, r1)), false);
    }
    INFO(cases << " cases, decided by the balls: " << decided_out << " separated, " << decided_in << " overlapping");
    CHECK(differ == 0);
    CHECK(sphere_wrong == 0);
    CHECK(uncertified == 0);
    // The test decides what is clear: beyond the slack (f = ±1e-3, ±1e-9 on the outside and inside), a good
    // share of the cases (the balls are tight for spheres, boxes' inner and ellipsoids' outer ones).
    CHECK(decided_out >= cases / 10);
    CHECK(decided_in >= cases / 20);
}

TEST_CASE("bounding-ball pre-test: distant and deep pairs take no support query", "[gjk][bounding_balls]") {
    std::mt19937_64 rng(603);
    const ConvexPolyhedron<double> hull(cloud(rng, 200, 0.1, Vec3<double>::Zero()));
    const Cone<double> cone(0.08, 0.1);
    int far_decided = 0, deep_decided = 0;
    const int n = test::scaled(200, 20);
    for (int i = 0; i < n; ++i) {
        const Transform<double> pa(test::random_rotation(rng), Vec3<double>::Zero());
        Transform<double> pb(test::random_rotation(rng), unit(rng) * 0.5);
        auto r = gjk_intersect(hull, pa, cone, pb);
        CHECK(r.status == GjkStatus::separated);
        far_decided += r.iterations == 0;
        const double d = gjk_distance(hull, pa, cone, pb).distance;
        CHECK(r.distance <= d * (1 + 1e-12));  // a lower bound
        pb.t = pa.R * hull.center() - pb.R * cone.center() + unit(rng) * 1e-3;
        r = gjk_intersect(hull, pa, cone, pb);
        CHECK(r.status == GjkStatus::intersecting);
        deep_decided += r.iterations == 0;
    }
    CHECK(far_decided == n);
    CHECK(deep_decided == n);
}
