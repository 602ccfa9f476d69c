// Mesh penetration depth against a reference that shares no code with it: FCL's boolean collide() at translated
// poses. Along the query's own normal, the first translation at which FCL sees the surfaces apart (march and bisect)
// must equal the query's depth; and the refined depth must be no worse than the smallest such translation over 200
// directions spread over the sphere (the sampled minimum), on the bunny and the Armadillo at P2 poses.
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/mesh_depth/penetration_depth.hpp"
#include "mesh_factory.hpp"
#include "oracles/fcl_mesh.hpp"
#include "oracles/sampled_translation.hpp"
#include "test_common.hpp"

#include <catch2/catch.hpp>
#include <fcl/narrowphase/collision.h>

using namespace cdkit;
using V = Vec3<double>;
using T = Transform<double>;

TEST_CASE("mesh depth agrees with FCL's collide at translated poses", "[mesh_depth][fcl]") {
    for (const char* file : {"bunny.obj", "armadillo.obj"}) {
        const TriangleMesh<double> mesh = test::unit_scaled(load_mesh(test::data_path(file)));
        const MeshModel<Obb<double>> model(mesh);
        const auto fcl_model = test::fcl_mesh<fcl::OBBRSSd>(mesh);
        double r = 0;
        for (const V& v : mesh.vertices) r = std::max(r, v.norm());
        const T pa;
        fcl::CollisionObjectd fa(fcl_model, test::fcl_pose(pa));
        const auto dirs = test::sphere_directions(200);
        std::mt19937_64 rng(21);
        int poses = 0;
        for (const double delta : {-0.01, -0.05, -0.2})
            for (int k = 0; k < 3; ++k) {
                T pb;
                pb.R = test::random_rotation(rng);
                std::normal_distribution<double> g;
                const V u = V(g(rng), g(rng), g(rng)).normalized();
                double lo = 0, hi = 4 * r;
                for (int i = 0; i < 60; ++i) {
                    pb.t = 0.5 * (lo + hi) * u;
                    (collide(model, pa, model, pb).colliding ? lo : hi) = 0.5 * (lo + hi);
                }
                pb.t = (hi + delta * r) * u;
                const auto crossing = [&](const V& v) {
                    T q = pb;
                    q.t += v;
                    fcl::CollisionObjectd fq(fcl_model, test::fcl_pose(q));
                    fcl::CollisionRequestd req;
                    fcl::CollisionResultd res;
                    return fcl::collide(&fa, &fq, req, res) > 0;
                };
                REQUIRE(crossing(V::Zero()));
                const double step = 0.002 * r, tol = 1e-7 * r;
                const MeshDepthResult d = penetration_depth(model, pa, model, pb);
                INFO(file << " delta " << delta << " pose " << k);
                REQUIRE(d.colliding);
                // Along its own normal: FCL finds the same first gap (to within the march's step: a gap shorter
                // than one step would be stepped over, so FCL's can only be later).
                const double along = test::first_gap_along(crossing, d.normal, step, 10 * r, tol);
                CHECK(along >= d.depth - 2 * tol);
                CHECK(along <= d.depth + step);
                // Refined, no worse than the best of 200 sampled directions (plus the step).
                MeshDepthRequest refine;
                refine.refine_steps = 4;
                const MeshDepthResult e = penetration_depth(model, pa, model, pb, refine);
                const double sampled = test::sampled_min_translation(crossing, dirs, step, tol).depth;
                CHECK(e.depth <= d.depth);
                CHECK(e.depth <= 1.02 * sampled + step);
                ++poses;
            }
        CHECK(poses == 9);
    }
}
