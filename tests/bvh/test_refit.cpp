// Refit after a deformation: the refitted tree keeps its invariants, collide() on it still equals brute
// force, bad topology is rejected, and the degradation measure tells a mild deformation from a scramble.
#include "brute_force_check.hpp"

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/sphere.hpp"
#include "cdkit/bvh/refit.hpp"

using namespace cdkit;

using test::deformed;

TEMPLATE_TEST_CASE("refit keeps the invariants and collide equals brute force", "[bvh][refit]", Aabb<float>,
                   Aabb<double>, Obb<float>, Obb<double>, (Kdop<double, 14>), (Kdop<float, 26>), BoundingSphere<float>,
                   BoundingSphere<double>) {
    using BV = TestType;
    using S = typename BV::Scalar;
    const auto base = test::uv_sphere<S>(S(1), 8, 16);
    MeshModel<BV> a(base);
    const auto bent = std::make_shared<const TriangleMesh<S>>(deformed(base, 0.4));
    a.refit(bent);
    CHECK(&a.mesh() == bent.get());
    REQUIRE_NOTHROW(a.validate());
    CHECK(a.degradation() > 0.5);
    const MeshModel<BV> b(test::random_soup<S>(150, S(0.2), 6));
    const int poses = test::scaled(16, 12);
    const int hits = test::collide_equals_brute_force(a, b, poses, 4.0, 21);
    CHECK(hits > poses / 5);
    CHECK(hits < poses - poses / 10);
    // The same tree refitted twice in a row and refitted back gives back the built tree's containment.
    a.refit(std::make_shared<const TriangleMesh<S>>(base));
    REQUIRE_NOTHROW(a.validate());
    CHECK(test::collide_equals_brute_force(a, a, test::scaled(6, 3), 2.0, 22) > 0);
}

TEST_CASE("refit: degradation and should_rebuild", "[bvh][refit]") {
    const auto base = test::uv_sphere<double>(1.0, 16, 32);
    MeshModel<Aabb<double>> m(base);
    CHECK(m.degradation() == Approx(1.0));
    // A uniform scale and a translation change nothing in the ratio.
    auto moved = base;
    for (auto& v : moved.vertices) v = 2.0 * v + Vec3<double>(5, 0, 0);
    m.refit(std::make_shared<const TriangleMesh<double>>(moved));
    CHECK(m.degradation() == Approx(1.0).epsilon(1e-6));
    CHECK_FALSE(m.should_rebuild());
    // Scrambled vertices (each jumps to a random place): the old topology is useless, the tree bloats.
    auto scrambled = base;
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (auto& v : scrambled.vertices) v = Vec3<double>(u(rng), u(rng), u(rng));
    m.refit(std::make_shared<const TriangleMesh<double>>(scrambled));
    REQUIRE_NOTHROW(m.validate());
    CHECK(m.degradation() > 3);
    CHECK(m.should_rebuild());
    m.rebuild();
    REQUIRE_NOTHROW(m.validate());
    CHECK(m.degradation() == Approx(1.0));
    // The Obb tree keeps its axes and refits every node from its vertices: unmoved, it is the built tree;
    // a mild bend tilts its flat leaves against their axes, which the surface-area measure takes as mild (a
    // volume sum would multiply: those leaves had ~0 volume); a scramble is looser than a fresh tree, but valid.
    MeshModel<Obb<double>> o(base);
    o.refit(std::make_shared<const TriangleMesh<double>>(base));
    CHECK(o.degradation() == Approx(1.0).epsilon(1e-12));
    o.refit(std::make_shared<const TriangleMesh<double>>(deformed(base, 0.02)));
    CHECK(o.degradation() > 1.0);
    CHECK(o.degradation() < 1.2);
    CHECK_FALSE(o.should_rebuild());
    o.refit(std::make_shared<const TriangleMesh<double>>(scrambled));
    REQUIRE_NOTHROW(o.validate());
    CHECK(o.should_rebuild());
    // Free functions on a bare tree.
    Bvh<Kdop<double, 18>> k = build_bvh<Kdop<double, 18>>(base);
    refit(k, deformed(base, 0.2));
    REQUIRE_NOTHROW(k.validate(deformed(base, 0.2)));
    CHECK(total_volume(k) > 0);
    CHECK(total_surface_area(k) > 0);
}

TEST_CASE("refit rejects a changed topology with cdkit::Error", "[bvh][refit]") {
    const auto base = test::uv_sphere<double>(1.0, 8, 16);
    MeshModel<BoundingSphere<double>> m(base);
    auto other = base;
    other.source = "moved.obj";
    std::swap(other.triangles[3][0], other.triangles[3][1]);
    CHECK_THROWS_WITH(m.refit(std::make_shared<const TriangleMesh<double>>(other)),
                      Catch::Contains("moved.obj") && Catch::Contains("triangle 3"));
    other = base;
    other.source = "moved.obj";
    other.vertices.push_back({0, 0, 0});
    CHECK_THROWS_WITH(m.refit(std::make_shared<const TriangleMesh<double>>(other)), Catch::Contains("vertex count"));
    other = base;
    other.vertices[5].x() = std::nan("");
    CHECK_THROWS_AS(m.refit(std::make_shared<const TriangleMesh<double>>(other)), Error);
    CHECK_THROWS_AS(m.refit(nullptr), Error);
    // The model is unchanged after a rejected refit.
    CHECK(&m.mesh() != nullptr);
    CHECK(m.mesh().vertices[5].allFinite());
    REQUIRE_NOTHROW(m.validate());
    auto fewer = base;
    fewer.triangles.pop_back();
    Bvh<Aabb<double>> t = build_bvh<Aabb<double>>(base);
    CHECK_THROWS_AS(refit(t, fewer), Error);
}
