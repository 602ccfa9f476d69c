// Mesh–convex queries (mesh_convex/*.hpp) against the brute force over every triangle (same triangle tests, no
// tree), for every BV type and every built-in shape, at seeded poses near contact (bisection to touching, then
// offset by δ): booleans equal, contact sets equal in ContactMode::all, distances equal. Also: the hit rate (so a
// test cannot pass by never hitting), penetration depth and normal on a flat face where they are known, bad input
// (NaN and non-rigid poses, NaN sizes, an empty mesh) and several threads on one model.
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/io/load_mesh.hpp"
#include "cdkit/mesh_convex.hpp"
#include "cdkit/narrowphase/convex_polyhedron.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <thread>
#include <vector>

using namespace cdkit;

namespace {

using T3 = Transform<double>;
using V3 = Vec3<double>;

std::shared_ptr<const TriangleMesh<double>> mc_bunny() {
    static const auto m =
        std::make_shared<const TriangleMesh<double>>(test::unit_scaled(load_mesh(test::data_path("bunny.obj"))));
    return m;
}

ConvexPolyhedron<double> mc_hull(std::mt19937_64& rng, int n, double size) {
    std::normal_distribution<double> g;
    std::vector<V3> pts;
    for (int i = 0; i < n; ++i) pts.push_back(V3(g(rng), 0.6 * g(rng), 0.8 * g(rng)).normalized() * size);
    return ConvexPolyhedron<double>(pts);
}

/// Seeded poses of a shape about the mesh: random rotation and direction u, the shape's centre at s·u with s
/// bisected to where the tree query first touches, then s* + δ·size for each δ. The mesh itself sits at a random
/// rigid pose too, so both poses go through the relative transform.
struct McPose {
    T3 mesh, shape;
    double delta;
};
template <class Model, class C>
std::vector<McPose> mc_poses(const Model& model, const C& shape, double size, int rotations, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    std::vector<McPose> out;
    const double deltas[] = {-0.05, -0.005, 0.0, 1e-9, 0.005, 0.05};
    for (int k = 0; k < rotations; ++k) {
        const T3 pm(test::random_rotation<double>(rng), V3(g(rng), g(rng), g(rng)));
        const Mat3<double> R = test::random_rotation<double>(rng);
        const V3 u = V3(g(rng), g(rng), g(rng)).normalized();
        auto at = [&](double s) { return T3(pm.R * R, pm * V3(s * u)); };
        auto hits = [&](double s) { return collide(model, pm, shape, at(s)).colliding; };
        // Walk in from outside until the shape first touches a triangle, then bisect that step.
        double lo = -1, hi = 3;
        for (double s = 3; s >= 0; s -= 0.05)
            if (hits(s)) {
                lo = s, hi = s + 0.05;
                break;
            }
        if (lo < 0) continue;
        for (int it = 0; it < 40; ++it) ((hits(0.5 * (lo + hi))) ? lo : hi) = 0.5 * (lo + hi);
        for (double d : deltas) out.push_back({pm, at(lo + d * size), d});
    }
    return out;
}

std::vector<Index> mc_sorted(const MeshConvexResult<double>& r) {
    std::vector<Index> v;
    for (const auto& c : r.contacts) v.push_back(c.triangle);
    std::sort(v.begin(), v.end());
    return v;
}

std::vector<Index> mc_sorted_f(const MeshConvexResult<float>& r) {
    std::vector<Index> v;
    for (const auto& c : r.contacts) v.push_back(c.triangle);
    std::sort(v.begin(), v.end());
    return v;
}

bool mc_same_distance(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(1.0, std::abs(b)); }

/// Every BV type's model of the same mesh against the brute force, for one shape.
template <class C> void mc_check_shape(const C& shape, double size, std::uint64_t seed) {
    const auto mesh = mc_bunny();
    const MeshModel<Obb<double>> obb(mesh);
    const MeshModel<Aabb<double>> aabb(mesh);
    const MeshModel<Rss<double>> rss(mesh);
    const MeshModel<Kdop<double, 14>> k14(mesh);
    const MeshModel<Kdop<double, 26>> k26(mesh);
    const MeshModel<BoundingSphere<double>> sph(mesh);
    const MeshModel<Obb<float>, double> obb_f(mesh);
    const MeshModel<Rss<float>, double> rss_f(mesh);
    const auto poses = mc_poses(obb, shape, size, test::scaled(6, 2), seed);
    REQUIRE(poses.size() >= 6);
    int hits = 0, misses = 0, undecided = 0;
    const MeshConvexRequest all{ContactMode::all};
    for (const auto& p : poses) {
        const auto ref = collide_brute_force(*mesh, p.mesh, shape, p.shape, all);
        const auto ref_d = distance_brute_force(*mesh, p.mesh, shape, p.shape);
        REQUIRE(ref.status == QueryStatus::ok);
        // GJK's boolean and its distance decide touching each within its own tolerance: within 1e-9 of contact
        // (the δ = 0 and 1e-9 poses) they may differ; counted, and both queries must match their own reference.
        if (ref_d.colliding != ref.colliding) {
            CHECK(ref_d.distance < 1e-9);
            ++undecided;
        }
        (ref.colliding ? hits : misses)++;
        auto check = [&](const auto& model, const char* name) {
            INFO(name << " delta " << p.delta);
            const auto first = collide(model, p.mesh, shape, p.shape);
            CHECK(first.status == QueryStatus::ok);
            CHECK(first.colliding == ref.colliding);
            CHECK(first.contacts.size() == (ref.colliding ? 1u : 0u));
            const auto every = collide(model, p.mesh, shape, p.shape, all);
            CHECK(mc_sorted(every) == mc_sorted(ref));
            const auto d = distance(model, p.mesh, shape, p.shape);
            CHECK(d.colliding == ref_d.colliding);
            CHECK(mc_same_distance(d.distance, ref_d.distance));
            if (!ref.colliding) CHECK(mc_same_distance((d.point_mesh - d.point_shape).norm(), d.distance));
            CHECK(d.stats.primitive_tests < mesh->triangles.size());
        };
        check(obb, "obb");
        check(aabb, "aabb");
        check(rss, "rss");
        check(k14, "kdop14");
        check(k26, "kdop26");
        check(sph, "sphere");
        check(obb_f, "obb<float>");
        check(rss_f, "rss<float>");
    }
    WARN("poses " << poses.size() << ", colliding " << hits << ", boolean and distance within 1e-9 of touching "
                  "and differing: " << undecided);
    CHECK(undecided <= int(poses.size()) / 10);
    // Both answers occur: the poses straddle contact.
    CHECK(hits >= int(poses.size()) / 4);
    CHECK(misses >= int(poses.size()) / 4);
}

}  // namespace

TEST_CASE("mesh-convex collide and distance equal the brute force for every BV and shape", "[mesh_convex]") {
    std::mt19937_64 rng(7);
    SECTION("sphere") { mc_check_shape(Sphere<double>(0.12), 0.12, 1); }
    SECTION("capsule") { mc_check_shape(Capsule<double>(0.06, 0.15), 0.2, 2); }
    SECTION("box") { mc_check_shape(Box<double>(V3(0.1, 0.05, 0.15)), 0.15, 3); }
    SECTION("cylinder") { mc_check_shape(Cylinder<double>(0.08, 0.12), 0.12, 4); }
    SECTION("cone") { mc_check_shape(Cone<double>(0.1, 0.12), 0.12, 5); }
    SECTION("ellipsoid") { mc_check_shape(Ellipsoid<double>(V3(0.12, 0.06, 0.09)), 0.12, 6); }
    SECTION("convex hull") { mc_check_shape(mc_hull(rng, 100, 0.15), 0.15, 7); }
}

TEST_CASE("mesh-convex witness points lie on the triangle and in the shape", "[mesh_convex]") {
    const auto mesh = mc_bunny();
    const MeshModel<Obb<double>> model(mesh);
    const Box<double> box(V3(0.1, 0.05, 0.15));
    const Sphere<double> ball(0.1);
    int checked = 0;
    for (const auto& p : mc_poses(model, box, 0.15, 4, 11)) {
        const auto r = collide(model, p.mesh, box, p.shape, MeshConvexRequest{ContactMode::all});
        for (const auto& c : r.contacts) {
            // In the box's frame the point is inside the box (up to EPA's tolerance).
            const V3 q = p.shape.inverse() * c.point;
            CHECK((q.cwiseAbs() - box.half).maxCoeff() <= 1e-7);
            ++checked;
        }
    }
    for (const auto& p : mc_poses(model, ball, 0.1, 4, 12)) {
        const auto r = collide(model, p.mesh, ball, p.shape, MeshConvexRequest{ContactMode::all});
        for (const auto& c : r.contacts) {
            CHECK((c.point - p.shape.t).norm() <= ball.radius * (1 + 1e-12));
            ++checked;
        }
    }
    CHECK(checked > 0);
}

TEST_CASE("mesh-convex penetration on a flat face: depth and normal known", "[mesh_convex]") {
    const auto grid = std::make_shared<const TriangleMesh<double>>(test::grid_box<double>(V3(1, 1, 1), 4));
    const MeshModel<Obb<double>> model(grid);
    const Box<double> box(V3(0.2, 0.2, 0.2));
    const Sphere<double> ball(0.2);
    for (double h : {0.19, 0.15, 0.05}) {
        const T3 at(Mat3<double>::Identity(), V3(0.1, -0.05, 1 + h));
        const auto pb = penetration(model, T3(), ball, at);
        REQUIRE(pb.status == QueryStatus::ok);
        REQUIRE(pb.colliding);
        CHECK(pb.deepest.depth == Approx(0.2 - h).margin(1e-7));
        CHECK(pb.deepest.normal.z() == Approx(1).margin(1e-6));
        const auto px = penetration(model, T3(), box, at);
        REQUIRE(px.colliding);
        CHECK(px.deepest.depth == Approx(0.2 - h).margin(1e-7));
        CHECK(px.deepest.normal.z() == Approx(1).margin(1e-6));
        const auto every = penetration(model, T3(), box, at, MeshConvexRequest{ContactMode::all});
        CHECK(every.contacts.size() >= 2);
        for (const auto& c : every.contacts) CHECK(c.depth <= px.deepest.depth);
        CHECK(collide(model, T3(), box, at, MeshConvexRequest{ContactMode::all}).contacts.size() ==
              every.contacts.size());
    }
    // Apart: no contact.
    CHECK_FALSE(penetration(model, T3(), ball, T3(Mat3<double>::Identity(), V3(0, 0, 1.3))).colliding);
}

TEST_CASE("mesh-convex queries refuse bad input with a status", "[mesh_convex]") {
    const auto mesh = mc_bunny();
    const MeshModel<Obb<double>> model(mesh);
    const Sphere<double> ball(0.1);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    T3 bad;
    bad.t.x() = nan;
    T3 scaled;
    scaled.R *= 1.5;
    for (const T3& p : {bad, scaled}) {
        CHECK(collide(model, p, ball, T3()).status == QueryStatus::invalid_pose);
        CHECK(collide(model, T3(), ball, p).status == QueryStatus::invalid_pose);
        const auto d = distance(model, T3(), ball, p);
        CHECK(d.status == QueryStatus::invalid_pose);
        CHECK(std::isinf(d.distance));
        CHECK(penetration(model, p, ball, T3()).status == QueryStatus::invalid_pose);
        CHECK(collide_brute_force(*mesh, p, ball, T3()).status == QueryStatus::invalid_pose);
    }
    Sphere<double> nan_ball(0.1);
    nan_ball.radius = nan;
    Box<double> nan_box(V3(0.1, 0.1, 0.1));
    nan_box.half.y() = nan;
    Capsule<double> inf_capsule(0.1, 0.1);
    inf_capsule.half_length = std::numeric_limits<double>::infinity();
    const auto r1 = collide(model, T3(), nan_ball, T3());
    CHECK(r1.status == QueryStatus::invalid_input);
    CHECK_FALSE(r1.colliding);
    CHECK(collide(model, T3(), nan_box, T3()).status == QueryStatus::invalid_input);
    CHECK(distance(model, T3(), nan_box, T3()).status == QueryStatus::invalid_input);
    CHECK(penetration(model, T3(), inf_capsule, T3()).status == QueryStatus::invalid_input);
    CHECK(distance(model, T3(), ball, T3(), DistanceRequest<double>{-1, 0}).status == QueryStatus::invalid_input);
    // An empty mesh never becomes a model: its construction names the problem.
    CHECK_THROWS_AS(MeshModel<Obb<double>>(TriangleMesh<double>{}), Error);
}

TEST_CASE("mesh-convex queries give the same answers from several threads", "[mesh_convex]") {
    const auto mesh = mc_bunny();
    const MeshModel<Rss<double>> model(mesh);
    std::mt19937_64 rng(5);
    const auto hull = mc_hull(rng, 60, 0.15);
    const auto poses = mc_poses(model, hull, 0.15, 4, 21);
    REQUIRE(!poses.empty());
    std::vector<int> expect_hit;
    std::vector<double> expect_d;
    for (const auto& p : poses) {
        expect_hit.push_back(collide(model, p.mesh, hull, p.shape).colliding);
        expect_d.push_back(distance(model, p.mesh, hull, p.shape).distance);
    }
    std::vector<int> wrong(4, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (int rep = 0; rep < 5; ++rep)
                for (std::size_t i = 0; i < poses.size(); ++i) {
                    const auto& p = poses[(i + t) % poses.size()];
                    const std::size_t k = (i + t) % poses.size();
                    if (collide(model, p.mesh, hull, p.shape).colliding != bool(expect_hit[k])) ++wrong[t];
                    if (distance(model, p.mesh, hull, p.shape).distance != expect_d[k]) ++wrong[t];
                }
        });
    for (auto& th : threads) th.join();
    for (int w : wrong) CHECK(w == 0);
}

TEST_CASE("mesh-convex queries in float equal the float brute force", "[mesh_convex]") {
    TriangleMesh<float> mesh;
    for (const auto& v : mc_bunny()->vertices) mesh.vertices.push_back(v.cast<float>());
    mesh.triangles = mc_bunny()->triangles;
    const auto shared = std::make_shared<const TriangleMesh<float>>(mesh);
    const MeshModel<Obb<float>> obb(shared);
    const MeshModel<Rss<float>> rss(shared);
    const Box<float> box(Vec3<float>(0.1f, 0.05f, 0.15f));
    const Sphere<float> ball(0.1f);
    std::mt19937_64 rng(3);
    std::normal_distribution<double> g;
    int hits = 0, n = 0;
    for (int k = 0; k < 40; ++k) {
        const Transform<float> p(test::random_rotation<float>(rng),
                                 Vec3<float>(float(g(rng)), float(g(rng)), float(g(rng))) * 0.6f);
        for (int s = 0; s < 2; ++s) {
            const MeshConvexRequest all{ContactMode::all};
            const auto ref = s ? collide_brute_force(*shared, Transform<float>(), box, p, all)
                               : collide_brute_force(*shared, Transform<float>(), ball, p, all);
            const auto got = s ? collide(obb, Transform<float>(), box, p, all) : collide(obb, Transform<float>(), ball, p, all);
            CHECK(mc_sorted_f(got) == mc_sorted_f(ref));
            const auto rd = s ? distance_brute_force(*shared, Transform<float>(), box, p)
                              : distance_brute_force(*shared, Transform<float>(), ball, p);
            const auto d = s ? distance(rss, Transform<float>(), box, p) : distance(rss, Transform<float>(), ball, p);
            CHECK(std::abs(d.distance - rd.distance) <= 1e-6f * std::max(1.0f, rd.distance));
            hits += ref.colliding;
            ++n;
        }
    }
    CHECK(hits > 0);
    CHECK(hits < n);
}
