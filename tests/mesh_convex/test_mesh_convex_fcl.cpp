// Mesh–convex collide() and distance() against an independent oracle: FCL 0.7's fcl::collide / fcl::distance
// between a BVHModel<OBBRSSd> of the bunny and fcl::Sphere / Box / Capsule / Convex, at seeded poses near contact
// (bisection to touching, then offset by δ·size along the approach direction, δ from −0.05 to +0.05).
//
// Tolerance band: FCL decides each triangle with its own GJK (libccd, tolerance 1e-6), so within ~1e-6 of
// touching the two libraries may differ. A boolean disagreement at a pose whose offset from touching is at most
// 1e-5 (the δ = 0 poses) is counted as undecided and printed, never dropped; any other disagreement fails.
// Distances (δ > 0) must agree within 1e-5 absolute + 1e-4 relative (FCL's GJK tolerance); the largest difference
// is printed. FCL headers are slow to compile: this is the only mesh-convex TU that includes them.
#include "mesh_factory.hpp"
#include "oracles/fcl_mesh.hpp"
#include "test_common.hpp"

#include "cdkit/io/load_mesh.hpp"
#include "cdkit/mesh_convex.hpp"
#include "cdkit/narrowphase/convex_polyhedron.hpp"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <catch2/catch.hpp>

#include <cstdio>
#include <memory>
#include <random>

using namespace cdkit;

namespace {

using T3 = Transform<double>;
using V3 = Vec3<double>;

template <class C, class F>
void fcl_compare(const char* name, const C& shape, std::shared_ptr<fcl::CollisionGeometryd> fshape, double size,
                 std::uint64_t seed) {
    const auto mesh =
        std::make_shared<const TriangleMesh<double>>(test::unit_scaled(load_mesh(test::data_path("bunny.obj"))));
    const MeshModel<Obb<double>> model(mesh);
    const MeshModel<Rss<double>> rss(mesh);
    const auto fmesh = test::fcl_mesh<fcl::OBBRSSd>(*mesh);
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    const double deltas[] = {-0.05, -0.01, -0.001, 0.0, 0.001, 0.01, 0.05};
    int poses = 0, hits = 0, disagree = 0, undecided = 0, dist_checked = 0, dist_wrong = 0;
    double max_diff = 0;
    for (int k = 0; k < test::scaled(12, 3); ++k) {
        const Mat3<double> R = test::random_rotation<double>(rng);
        const V3 u = V3(g(rng), g(rng), g(rng)).normalized();
        auto at = [&](double s) { return T3(R, s * u); };
        auto cd_hits = [&](double s) { return collide(model, T3(), shape, at(s)).colliding; };
        double lo = -1, hi = 3;
        for (double s = 3; s >= 0; s -= 0.05)
            if (cd_hits(s)) {
                lo = s, hi = s + 0.05;
                break;
            }
        if (lo < 0) continue;
        for (int it = 0; it < 50; ++it) ((cd_hits(0.5 * (lo + hi))) ? lo : hi) = 0.5 * (lo + hi);
        for (double d : deltas) {
            const T3 p = at(lo + d * size);
            ++poses;
            const bool c = collide(model, T3(), shape, p).colliding;
            hits += c;
            fcl::CollisionObjectd om(fmesh, fcl::Transform3d::Identity());
            fcl::CollisionObjectd os(fshape, p.to_isometry());
            fcl::CollisionRequestd creq;
            fcl::CollisionResultd cres;
            fcl::collide(&om, &os, creq, cres);
            if (cres.isCollision() != c) {
                if (std::abs(d * size) <= 1e-5) ++undecided;
                else {
                    ++disagree;
                    UNSCOPED_INFO(name << ": boolean differs from FCL at delta " << d << " (cdkit " << c << ")");
                }
            }
            if (d > 0) {
                const auto cd = distance(rss, T3(), shape, p);
                fcl::DistanceRequestd dreq;
                fcl::DistanceResultd dres;
                fcl::distance(&om, &os, dreq, dres);
                const double diff = std::abs(cd.distance - dres.min_distance);
                max_diff = std::max(max_diff, diff);
                ++dist_checked;
                if (diff > 1e-5 + 1e-4 * cd.distance) {
                    ++dist_wrong;
                    UNSCOPED_INFO(name << ": distance " << cd.distance << " vs FCL " << dres.min_distance << " at delta " << d);
                }
            }
        }
    }
    std::printf("mesh-convex vs FCL, %s: %d poses, %d colliding, %d boolean disagreements, %d undecided within 1e-5 "
                "of touching; %d distances, largest difference %.3g, %d beyond tolerance\n",
                name, poses, hits, disagree, undecided, dist_checked, max_diff, dist_wrong);
    CHECK(poses >= 14);
    CHECK(hits >= poses / 4);
    CHECK(disagree == 0);
    CHECK(dist_wrong == 0);
}

}  // namespace

TEST_CASE("mesh-convex collide and distance agree with FCL on the bunny", "[mesh_convex][fcl]") {
    SECTION("sphere") {
        fcl_compare<Sphere<double>, void>("sphere", Sphere<double>(0.12), std::make_shared<fcl::Sphered>(0.12), 0.12, 1);
    }
    SECTION("box") {
        const V3 h(0.1, 0.05, 0.15);
        fcl_compare<Box<double>, void>("box", Box<double>(h), std::make_shared<fcl::Boxd>(2 * h.x(), 2 * h.y(), 2 * h.z()),
                                       0.15, 2);
    }
    SECTION("capsule") {
        fcl_compare<Capsule<double>, void>("capsule", Capsule<double>(0.06, 0.15),
                                           std::make_shared<fcl::Capsuled>(0.06, 0.3), 0.2, 3);
    }
    SECTION("convex hull") {
        std::mt19937_64 rng(9);
        std::normal_distribution<double> g;
        std::vector<V3> pts;
        for (int i = 0; i < 80; ++i) pts.push_back(V3(g(rng), 0.6 * g(rng), 0.8 * g(rng)).normalized() * 0.15);
        const ConvexPolyhedron<double> hull(pts);
        auto v = std::make_shared<std::vector<fcl::Vector3d>>(hull.vertices().begin(), hull.vertices().end());
        auto faces = std::make_shared<std::vector<int>>();
        for (const auto& t : hull.triangles()) faces->insert(faces->end(), {3, int(t[0]), int(t[1]), int(t[2])});
        fcl_compare<ConvexPolyhedron<double>, void>(
            "convex hull", hull, std::make_shared<fcl::Convexd>(v, int(hull.triangles().size()), faces), 0.15, 4);
    }
}
