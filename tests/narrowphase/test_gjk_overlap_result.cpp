// What a GJK result says about an overlap, on every path that can prove one: the cold boolean's tetrahedron
// exit (which builds the result itself, without gjk_finish; also run with the containment certificate off so that
// it is always reached) and its containment exit, the cached boolean and the distance query (both
// through gjk_finish, which returns before any witness-point work for an overlap). All three must report
// `intersecting` with distance 0 on shallow overlaps (1e-4 … 1e-1 of the size), where the bounding balls
// rarely decide: a hit-rate check makes sure the loop's tetrahedron exit is what the test exercises.
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <random>

using namespace cdkit;

namespace {

using test::random_rotation;

/// Places b at signed distance `gap` from a (along the distance query's normal) and checks the three paths.
template <class A, class B> void check_overlaps(const A& a, const B& b, std::mt19937_64& rng, int& loop_proofs) {
    const double gaps[4] = {-1e-1, -1e-2, -1e-3, -1e-4};
    for (double gap_rel : gaps) {
        const Transform<double> pa(random_rotation(rng), Vec3<double>(0.3, -0.2, 0.1));
        Transform<double> pb(random_rotation(rng), pa.t + Vec3<double>(0.4, 0.1, -0.3));
        const auto d0 = gjk_distance(a, pa, b, pb);
        REQUIRE(d0.status == GjkStatus::separated);
        pb.t += (gap_rel * 0.1 - d0.distance) * d0.normal;

        const auto cold = gjk_intersect(a, pa, b, pb);
        CHECK(cold.status == GjkStatus::intersecting);
        CHECK(cold.distance == 0.0);
        CHECK(cold.colliding);
        if (cold.iterations > 0) {
            ++loop_proofs;
            // The certificate: the tetrahedron around the origin, or (no simplex) a support point strictly inside
            // the other shape (GjkSettings::containment_test: the first pair's, or for cylinders and cones a later
            // round's).
            CHECK((cold.simplex.size == 4 || cold.simplex.size == 0));
        }
        // The tetrahedron exit itself, with the containment certificate off.
        GjkSettings<double> no_containment;
        no_containment.containment_test = false;
        const auto tet = gjk_intersect(a, pa, b, pb, nullptr, no_containment);
        CHECK(tet.status == GjkStatus::intersecting);
        CHECK(tet.distance == 0.0);
        if (tet.iterations > 0) CHECK(tet.simplex.size == 4);

        GjkCache<double> cache;
        const auto warm = gjk_intersect(a, pa, b, pb, &cache);
        CHECK(warm.status == GjkStatus::intersecting);
        CHECK(warm.distance == 0.0);

        const auto dist = gjk_distance(a, pa, b, pb);
        CHECK(dist.status == GjkStatus::intersecting);
        CHECK(dist.distance == 0.0);
        CHECK(dist.simplex.size == 4);
    }
}

}  // namespace

TEST_CASE("GJK results of proven overlaps: intersecting, distance 0, on the cold, cached and distance paths",
          "[gjk]") {
    std::mt19937_64 rng(5150);
    std::uniform_real_distribution<double> u(0.5, 1.0);
    const int n = test::scaled(40, 4);
    int loop_proofs = 0, queries = 0;
    for (int k = 0; k < n; ++k) {
        const Box<double> ba(Vec3<double>(0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng)));
        const Box<double> bb(Vec3<double>(0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng)));
        check_overlaps(ba, bb, rng, loop_proofs);
        const Cylinder<double> cy(0.1 * u(rng), 0.1 * u(rng));
        const Cone<double> co(0.1 * u(rng), 0.1 * u(rng));
        check_overlaps(cy, co, rng, loop_proofs);
        std::normal_distribution<double> g;
        std::vector<Vec3<double>> p;
        for (int i = 0; i < 60; ++i) p.push_back(Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 0.1 * u(rng));
        const ConvexPolyhedron<double> hull(p);
        check_overlaps(hull, ba, rng, loop_proofs);
        queries += 12;
    }
    // Shallow overlaps: nearly all must be proven by the loop (tetrahedron or containment), not by the inner balls.
    CHECK(loop_proofs >= queries * 9 / 10);
}
