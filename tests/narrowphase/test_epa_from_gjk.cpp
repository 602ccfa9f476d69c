// EPA started from GJK's final simplex (`penetration(a, pa, b, pb, gjk_result)`, what contact_manifold and the World
// use) against EPA after its own GJK run (`penetration(a, pa, b, pb)`), on seeded overlapping pairs of the built-in
// shapes, after cold and warm GJK booleans: the depth brackets [depth_lower, depth] of the two overlap (each is
// certified, so the true depth lies in both), the witness points are depth·normal apart, and where EPA cannot start
// from GJK's result (a containment or bounding-ball exit, margins) the answer is `penetration`'s bit for bit. The
// start from the simplex must actually be taken (hit-rate check).
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/epa.hpp>

#include "mesh_factory.hpp"
#include "test_common.hpp"

using namespace cdkit;

namespace {

using V = Vec3<double>;
using T = Transform<double>;

struct Tally {
    int colliding = 0, from_simplex = 0, fallback = 0;
};

template <class A, class B> void compare(const A& a, const B& b, std::mt19937_64& rng, int n, Tally& t) {
    std::uniform_real_distribution<double> u(-0.6, 0.6);
    for (int i = 0; i < n; ++i) {
        const T pa(test::random_rotation(rng), V(u(rng), u(rng), u(rng)));
        const T pb(test::random_rotation(rng), V(u(rng), u(rng), u(rng)));
        GjkCache<double> cache;
        const GjkResult<double> cold = gjk_intersect(a, pa, b, pb);
        (void)gjk_intersect(a, pa, b, pb, &cache);
        const GjkResult<double> warm = gjk_intersect(a, pa, b, pb, &cache);  // rebuilt from the cache
        REQUIRE(cold.colliding == warm.colliding);
        if (!cold.colliding) continue;
        ++t.colliding;
        const PenetrationResult<double> own = penetration(a, pa, b, pb);
        for (const GjkResult<double>* g : {&cold, &warm}) {
            const PenetrationResult<double> p = penetration(a, pa, b, pb, *g);
            REQUIRE(p.colliding);
            if (!detail::epa_starts_from<A, B>(*g)) {
                ++t.fallback;
                CHECK(p.depth == own.depth);
                CHECK(p.depth_lower == own.depth_lower);
                CHECK(p.normal == own.normal);
                continue;
            }
            ++t.from_simplex;
            CHECK(p.gjk_iterations == 0);
            if (own.status != GjkStatus::intersecting || p.status != GjkStatus::intersecting) {
                // Touching or within rounding of it: both depths at the rounding level.
                CHECK(std::max(p.depth, own.depth) < 1e-9);
                continue;
            }
            const double slack = 1e-9 * std::max(1.0, own.depth);
            CHECK(p.depth_lower <= own.depth + slack);
            CHECK(own.depth_lower <= p.depth + slack);
            CHECK(std::abs(p.normal.norm() - 1.0) < 1e-12);
            CHECK((p.point_a - p.point_b - p.depth * p.normal).norm() < 1e-9);
        }
    }
}

}  // namespace

TEST_CASE("EPA from GJK's final simplex agrees with EPA after its own GJK", "[epa][gjk]") {
    std::mt19937_64 rng(3503);
    std::uniform_real_distribution<double> c(-0.5, 0.5);
    std::vector<V> cloud;
    for (int i = 0; i < 60; ++i) cloud.emplace_back(c(rng), 0.8 * c(rng), 0.6 * c(rng));
    const ConvexPolyhedron<double> hull(cloud);
    const Box<double> box(V(0.5, 0.3, 0.2));
    const Cylinder<double> cylinder(0.3, 0.4);
    const Cone<double> cone(0.35, 0.4);
    const Ellipsoid<double> ellipsoid(V(0.4, 0.25, 0.3));
    const ConvexTriangle<double> triangle(V(-0.5, -0.3, 0), V(0.6, -0.2, 0.05), V(0, 0.5, -0.05));
    const Capsule<double> capsule(0.2, 0.3);
    const int n = test::scaled(300, 30);
    Tally t;
    compare(box, box, rng, n, t);
    compare(hull, box, rng, n, t);
    compare(hull, hull, rng, n, t);
    compare(cylinder, box, rng, n, t);
    compare(cone, hull, rng, n, t);
    compare(ellipsoid, cylinder, rng, n, t);
    compare(triangle, hull, rng, n, t);
    compare(capsule, box, rng, n, t);  // margins: always penetration's own answer
    INFO("colliding " << t.colliding << ", EPA from GJK's simplex " << t.from_simplex << ", fallbacks " << t.fallback);
    CHECK(t.colliding > n);
    CHECK(t.from_simplex > t.colliding / 4);  // the new start is exercised, not only the fallback
    CHECK(t.fallback > 0);
}
