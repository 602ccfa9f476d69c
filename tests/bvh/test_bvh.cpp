// BVH construction: invariants hold for every BV, scalar, split strategy and leaf size, including
// degenerate inputs (all triangles at one point, a single triangle).
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/sphere.hpp"
#include "cdkit/bvh/mesh_model.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace cdkit;

TEMPLATE_TEST_CASE("BVH build keeps its invariants with every split strategy", "[bvh][build]", Aabb<float>, Aabb<double>,
                   Obb<float>, Obb<double>, (Kdop<double, 14>), BoundingSphere<double>) {
    using BV = TestType;
    using S = typename BV::Scalar;
    for (SplitStrategy split : {SplitStrategy::median, SplitStrategy::mean, SplitStrategy::sah, SplitStrategy::pca_volume})
        for (std::uint32_t leaf : {1u, 4u}) {
            BuildOptions opt;
            opt.split = split;
            opt.max_leaf_triangles = leaf;
            const MeshModel<BV> sphere(test::uv_sphere<S>(S(1), 20, 40), opt);
            REQUIRE_NOTHROW(sphere.validate());
            const auto st = sphere.bvh().stats();
            CHECK(st.leaves >= sphere.mesh().num_triangles() / leaf);
            CHECK(st.nodes == 2 * st.leaves - 1);
            if (split == SplitStrategy::median)  // balanced
                CHECK(st.depth <= std::size_t(std::ceil(std::log2(double(sphere.mesh().num_triangles())))) + 1);
            const MeshModel<BV> soup(test::random_soup<S>(500, S(0.1), 9), opt);
            REQUIRE_NOTHROW(soup.validate());
        }
}

TEST_CASE("BVH of degenerate input", "[bvh]") {
    TriangleMesh<double> m;
    m.vertices = {{1, 1, 1}};
    for (int i = 0; i < 100; ++i) m.triangles.push_back({0, 0, 0});  // 100 triangles collapsed to one point
    const MeshModel<Obb<double>> obb(m);
    REQUIRE_NOTHROW(obb.validate());
    CHECK(obb.bvh().depth() <= 8);
    const MeshModel<Aabb<double>> aabb(m);
    REQUIRE_NOTHROW(aabb.validate());
    TriangleMesh<double> one;
    one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    one.triangles = {{0, 1, 2}};
    const MeshModel<Obb<double>> single(one);
    CHECK(single.bvh().nodes().size() == 1);
    CHECK(single.bvh().root().is_leaf());
}

TEST_CASE("MeshModel rejects bad meshes with cdkit::Error", "[bvh]") {
    TriangleMesh<double> empty;
    empty.source = "empty.obj";
    CHECK_THROWS_AS(MeshModel<Obb<double>>(empty), Error);
    TriangleMesh<double> nan;
    nan.source = "nan.obj";
    nan.vertices = {{0, 0, 0}, {1, 0, 0}, {0, std::nan(""), 0}};
    nan.triangles = {{0, 1, 2}};
    CHECK_THROWS_WITH(MeshModel<Aabb<double>>(nan), Catch::Contains("nan.obj") && Catch::Contains("vertex 2"));
    TriangleMesh<double> bad_index = nan;
    bad_index.vertices[2] = {0, 1, 0};
    bad_index.triangles = {{0, 1, 3}};
    CHECK_THROWS_WITH(MeshModel<Aabb<double>>(bad_index), Catch::Contains("out of range"));
}

TEST_CASE("Bvh::validate detects a broken tree", "[bvh]") {
    const auto mesh = test::uv_sphere<double>(1.0, 8, 16);
    Bvh<Aabb<double>> bvh = build_bvh<Aabb<double>>(mesh);
    REQUIRE_NOTHROW(bvh.validate(mesh));
    auto nodes = bvh.nodes();
    nodes.back().bv.half *= 0.5;  // shrink a leaf: a vertex falls outside
    Bvh<Aabb<double>> broken(nodes, bvh.triangle_order(), bvh.depth());
    CHECK_THROWS_AS(broken.validate(mesh), Error);
}
