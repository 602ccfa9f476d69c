// Restricted boxtree: the implied boxes hold their triangles exactly (float planes rounded outwards), and
// collide() on boxtrees returns exactly brute force's triangle pairs, in float and double, on closed meshes,
// soups and real meshes, at random and near-contact poses, far from the origin and at extreme scales.
#include "bvh/brute_force_check.hpp"
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/bv/obb.hpp"
#include "cdkit/bvh/boxtree.hpp"
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/query.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <thread>

#if defined(CDKIT_HAS_TBB)
#include <tbb/task_arena.h>
#endif

using namespace cdkit;

namespace {
/// Every vertex of every leaf's triangle inside the leaf's implied box, computed exactly (long double holds
/// a float and a double's difference from the centre); returns the number of leaves seen.
template <class S> std::size_t check_leaf_boxes(const RestrictedBoxtree<S>& tree) {
    std::size_t leaves = 0, outside = 0;
    std::vector<int> seen(tree.mesh().num_triangles(), 0);
    tree.for_each_leaf([&](std::uint32_t t, const FloatBox& box) {
        ++leaves;
        ++seen[t];
        for (Index v : tree.mesh().triangles[t])
            for (int k = 0; k < 3; ++k) {
                const long double local = (long double)tree.mesh().vertices[v][k] - (long double)tree.centre()[k];
                outside += local < (long double)box[k] || local > (long double)box[k + 3];
            }
    });
    CHECK(outside == 0);
    CHECK(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
    return leaves;
}

/// The translation along `dir` at which the two bunny copies just touch, by bisection on a MeshModel.
template <class BV>
double contact_offset(const MeshModel<BV>& m, const Mat3<double>& R, const Vec3<double>& dir) {
    double lo = 0, hi = 4;
    if (!collide(m, Transform<double>(), m, Transform<double>(R, Vec3<double>::Zero())).colliding) return -1;
    for (int it = 0; it < 40; ++it) {
        const double mid = 0.5 * (lo + hi);
        (collide(m, Transform<double>(), m, Transform<double>(R, mid * dir)).colliding ? lo : hi) = mid;
    }
    return lo;
}
}  // namespace

TEST_CASE("Restricted boxtree: 8-byte nodes and build invariants", "[boxtree]") {
    STATIC_REQUIRE(sizeof(BoxtreeNode) == 8);
    for (BoxtreeSplit split : {BoxtreeSplit::median, BoxtreeSplit::implied_sah})
        for (std::uint32_t extra : {0u, 1u, 3u}) {
            BoxtreeOptions opt;
            opt.split = split;
            opt.max_extra_restrictions = extra;
            const RestrictedBoxtree<double> sphere(test::uv_sphere<double>(1.0, 20, 40), opt);
            REQUIRE_NOTHROW(sphere.validate());
            const auto st = sphere.stats();
            CHECK(st.leaves == sphere.mesh().num_triangles());
            CHECK(st.nodes == 2 * st.leaves - 1 + st.one_child_nodes);
            CHECK(st.one_child_nodes <= std::size_t(extra) * (st.nodes - st.one_child_nodes));
            if (extra == 0) CHECK(st.one_child_nodes == 0);
            if (split == BoxtreeSplit::median) {  // balanced, plus at most `extra` one-child levels per level
                const auto levels = std::size_t(std::ceil(std::log2(double(sphere.mesh().num_triangles())))) + 1;
                CHECK(st.depth <= levels * (1 + extra));
            }
            CHECK(check_leaf_boxes(sphere) == sphere.mesh().num_triangles());
            const RestrictedBoxtree<float> soup(test::random_soup<float>(500, 0.1f, 9), opt);
            REQUIRE_NOTHROW(soup.validate());
            CHECK(check_leaf_boxes(soup) == 500);
        }
}

TEST_CASE("Restricted boxtree: the parallel build lays out the same nodes as on one thread", "[boxtree][threads]") {
    // 40,000 triangles: above the size from which subtrees are grown in parallel.
    const auto mesh = std::make_shared<const TriangleMesh<double>>(test::uv_sphere<double>(1.0, 100, 200));
    const RestrictedBoxtree<double> parallel(mesh);
    std::vector<BoxtreeNode> serial;
#if defined(CDKIT_HAS_TBB)
    tbb::task_arena one(1);
    one.execute([&] { serial = RestrictedBoxtree<double>(mesh).nodes(); });
#else
    serial = RestrictedBoxtree<double>(mesh).nodes();
#endif
    REQUIRE(serial.size() == parallel.nodes().size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < serial.size(); ++i)
        differ += serial[i].bits != parallel.nodes()[i].bits || serial[i].plane != parallel.nodes()[i].plane;
    CHECK(differ == 0);
    REQUIRE_NOTHROW(parallel.validate());
    CHECK(check_leaf_boxes(parallel) == mesh->num_triangles());
}

TEST_CASE("Restricted boxtree: degenerate input", "[boxtree]") {
    TriangleMesh<double> point;
    point.vertices = {{1, 1, 1}};
    for (int i = 0; i < 100; ++i) point.triangles.push_back({0, 0, 0});  // 100 triangles at one point
    const RestrictedBoxtree<double> p(point);
    REQUIRE_NOTHROW(p.validate());
    CHECK(p.depth() <= 16);
    CHECK(collide(p, Transform<double>(), p, Transform<double>()).colliding);
    CHECK_FALSE(collide(p, Transform<double>(), p, Transform<double>::translation({0, 0, 1e-9})).colliding);
    TriangleMesh<double> one;
    one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    one.triangles = {{0, 1, 2}};
    const RestrictedBoxtree<double> single(one);
    CHECK(single.nodes().size() == 1);
    CHECK(single.nodes()[0].is_leaf());
    REQUIRE_NOTHROW(single.validate());
    // Two flat triangles in one plane, overlapping: coplanar contact.
    CHECK(collide(single, Transform<double>(), single, Transform<double>::translation({0.2, 0.2, 0})).colliding);
    CHECK_FALSE(collide(single, Transform<double>(), single, Transform<double>::translation({0.2, 0.2, 1e-12})).colliding);
}

TEST_CASE("Restricted boxtree: bad input", "[boxtree]") {
    TriangleMesh<double> empty;
    empty.source = "empty.obj";
    CHECK_THROWS_WITH(RestrictedBoxtree<double>(empty), Catch::Contains("empty.obj"));
    TriangleMesh<double> nan;
    nan.source = "nan.obj";
    nan.vertices = {{0, 0, 0}, {1, 0, 0}, {0, std::nan(""), 0}};
    nan.triangles = {{0, 1, 2}};
    CHECK_THROWS_WITH(RestrictedBoxtree<double>(nan), Catch::Contains("nan.obj") && Catch::Contains("vertex 2"));
    TriangleMesh<double> bad_index = nan;
    bad_index.vertices[2] = {0, 1, 0};
    bad_index.triangles = {{0, 1, 3}};
    CHECK_THROWS_WITH(RestrictedBoxtree<double>(bad_index), Catch::Contains("out of range"));
    CHECK_THROWS_AS(RestrictedBoxtree<double>(std::shared_ptr<const TriangleMesh<double>>()), Error);
    // Finite doubles whose extent no float plane can hold.
    TriangleMesh<double> huge;
    huge.source = "huge.obj";
    huge.vertices = {{-1e300, 0, 0}, {1e300, 0, 0}, {0, 1, 0}};
    huge.triangles = {{0, 1, 2}};
    CHECK_THROWS_WITH(RestrictedBoxtree<double>(huge), Catch::Contains("huge.obj") && Catch::Contains("float"));

    // Poses that are not rigid motions: invalid_pose and no answer.
    const RestrictedBoxtree<double> sphere(test::uv_sphere<double>(1.0, 8, 16));
    Transform<double> scaled;
    scaled.R *= 2;
    Transform<double> not_finite = Transform<double>::translation({std::nan(""), 0, 0});
    Transform<double> mirrored;
    mirrored.R(0, 0) = -1;
    for (const auto& bad : {scaled, not_finite, mirrored}) {
        const auto r = collide(sphere, Transform<double>(), sphere, bad);
        CHECK(r.status == QueryStatus::invalid_pose);
        CHECK_FALSE(r.colliding);
        CHECK(collide(sphere, bad, sphere, Transform<double>()).status == QueryStatus::invalid_pose);
    }
}

TEMPLATE_TEST_CASE("Restricted boxtree collide equals brute force on spheres and soups", "[boxtree]", float, double) {
    using S = TestType;
    for (std::uint32_t extra : {0u, 1u}) {
        BoxtreeOptions opt;
        opt.max_extra_restrictions = extra;
        opt.split = extra == 0 ? BoxtreeSplit::median : BoxtreeSplit::implied_sah;
        const RestrictedBoxtree<S> sphere(test::uv_sphere<S>(S(1), 8, 16), opt);
        const int poses = test::scaled(30, 10);
        int hits = test::collide_equals_brute_force(sphere, sphere, poses, 2.6, 11 + extra, 0.25);
        CHECK(hits > poses / 5);
        CHECK(hits < poses - poses / 10);
        const RestrictedBoxtree<S> a(test::random_soup<S>(300, S(0.15), 5), opt), b(test::random_soup<S>(200, S(0.2), 6), opt);
        hits = test::collide_equals_brute_force(a, b, poses, 3.5, 12 + extra, 0.25);
        CHECK(hits > poses / 5);
        CHECK(hits < poses - poses / 10);
    }
}

TEST_CASE("Restricted boxtree collide equals brute force on the teapot, random and near contact", "[boxtree]") {
    const auto teapot = test::unit_scaled(load_mesh(test::data_path("teapot.obj")));
    const RestrictedBoxtree<double> td(teapot);
    const RestrictedBoxtree<float> tf(teapot.cast<float>());
    const int hits = test::collide_equals_brute_force(td, td, test::scaled(4, 2), 2.0, 13, 0.25) +
                     test::collide_equals_brute_force(tf, tf, test::scaled(2, 1), 2.0, 14, 0.25);
    CHECK(hits >= 1);
    // Near contact: the translation at which the copies just touch (bisection on an Obb tree), and a hair
    // either side, where the boxes are hardest to get right.
    const MeshModel<Obb<double>> obb(teapot);
    std::mt19937_64 rng(15);
    const CollisionRequest all{ContactMode::all};
    int touching = 0;
    for (int i = 0; i < test::scaled(3, 2); ++i) {
        const Mat3<double> R = test::random_rotation(rng);
        const Vec3<double> dir = Vec3<double>(test::random_rotation(rng).col(0));
        const double s = contact_offset(obb, R, dir);
        if (s < 0) continue;
        for (double d : {-1e-6, 0.0, 1e-9}) {
            const Transform<double> pb(R, (s + d) * dir);
            const auto ref = collide_brute_force(teapot, Transform<double>(), teapot, pb, all);
            const auto got = collide(td, Transform<double>(), td, pb, all);
            REQUIRE(test::contact_pairs(got) == test::contact_pairs(ref));
            REQUIRE(collide(td, Transform<double>(), td, pb).colliding == ref.colliding);
            touching += ref.colliding;
        }
    }
    CHECK(touching >= 2);
}

TEST_CASE("Restricted boxtree on the bunny: memory under the mesh's, pairs equal Obb tree's and brute force's", "[boxtree]") {
    const auto bunny = test::unit_scaled(load_mesh(test::data_path("bunny.obj")));
    const RestrictedBoxtree<double> bd(bunny);
    const RestrictedBoxtree<float> bf(bunny.cast<float>());
    REQUIRE_NOTHROW(bd.validate());
    REQUIRE_NOTHROW(bf.validate());
    CHECK(check_leaf_boxes(bd) == bunny.num_triangles());
    CHECK(check_leaf_boxes(bf) == bunny.num_triangles());
    CHECK(bd.memory_bytes() < bd.mesh().memory_bytes());
    // A float mesh is 25 % smaller: the plain binary tree (16 B per triangle) stays under it.
    BoxtreeOptions binary;
    binary.max_extra_restrictions = 0;
    const RestrictedBoxtree<float> bfb(bunny.cast<float>(), binary);
    CHECK(bfb.memory_bytes() < bfb.mesh().memory_bytes());
    CHECK(bfb.stats().nodes == 2 * bunny.num_triangles() - 1);
    // Even with more one-child nodes than the default allows.
    BoxtreeOptions rich;
    rich.max_extra_restrictions = 3;
    rich.min_extra_gain = 0.1f;
    const RestrictedBoxtree<double> br(bunny, rich);
    CHECK(br.stats().one_child_nodes > 0);
    CHECK(br.memory_bytes() < 2 * br.mesh().memory_bytes());

    // Bunny against bunny: brute force is 13.5 M triangle pairs a pose, so the oracle is the Obb tree
    // (itself checked against brute force in tests/query/test_collide.cpp), at random and at touching poses.
    const MeshModel<Obb<double>> obb(bunny);
    const CollisionRequest all{ContactMode::all};
    std::mt19937_64 rng(16);
    int hits = 0, misses = 0;
    for (int i = 0; i < test::scaled(30, 6); ++i) {
        const Mat3<double> R = test::random_rotation(rng);
        const Vec3<double> dir = Vec3<double>(test::random_rotation(rng).col(0));
        const double s = contact_offset(obb, R, dir);
        for (double d : {0.0, 1e-7, -0.01, 0.3 * std::abs(std::sin(double(i)))}) {
            const Transform<double> pb(R, (std::max(s, 0.0) + d) * dir);
            const auto ref = collide(obb, Transform<double>(), obb, pb, all);
            const auto got = collide(br, Transform<double>(), br, pb, all);
            REQUIRE(test::contact_pairs(collide(bd, Transform<double>(), bd, pb, all)) == test::contact_pairs(ref));
            REQUIRE(test::contact_pairs(got) == test::contact_pairs(ref));
            (ref.colliding ? hits : misses)++;
        }
    }
    CHECK(hits > 0);
    CHECK(misses > 0);
    // Brute force over all pairs on a few poses: a small sphere centred near a bunny vertex, so that its
    // surface crosses the bunny's.
    const RestrictedBoxtree<double> ball(test::uv_sphere<double>(0.3, 8, 16));
    int ball_hits = 0;
    const int ball_poses = test::scaled(4, 2);
    for (int i = 0; i < ball_poses; ++i) {
        const Vec3<double> at = bunny.vertices[(rng() % bunny.vertices.size())];
        const Transform<double> pb(test::random_rotation(rng), at + Vec3<double>(0.05, -0.03, 0.02));
        const auto ref = collide_brute_force(bunny, Transform<double>(), ball.mesh(), pb, all);
        REQUIRE(test::contact_pairs(collide(bd, Transform<double>(), ball, pb, all)) == test::contact_pairs(ref));
        ball_hits += ref.colliding;
    }
    CHECK(ball_hits >= ball_poses / 2);
}

TEST_CASE("Restricted boxtree: huge offsets and extreme scales", "[boxtree]") {
    const auto base = test::random_soup<double>(150, 0.2, 21);
    const CollisionRequest all{ContactMode::all};
    std::mt19937_64 rng(4);
    int hits = 0;
    for (int i = 0; i < test::scaled(20, 5); ++i) {
        const Transform<double> pb(test::random_rotation(rng), Vec3<double>(0.3, -0.2, 0.1));
        const auto ref = collide_brute_force(base, Transform<double>(), base, pb, all);
        hits += ref.colliding;
        // Powers of two scale exactly: the answers must be identical, not merely close.
        for (double s : {std::ldexp(1.0, -20), std::ldexp(1.0, 20)}) {
            auto scaled = base;
            for (auto& v : scaled.vertices) v *= s;
            const RestrictedBoxtree<double> m(scaled);
            const Transform<double> ps(pb.R, pb.t * s);
            const auto got = collide(m, Transform<double>(), m, ps, all);
            CHECK(test::contact_pairs(got) == test::contact_pairs(collide_brute_force(scaled, Transform<double>(), scaled, ps, all)));
            CHECK(got.colliding == ref.colliding);
        }
        // Both poses far from the origin.
        const Transform<double> shift = Transform<double>::translation({1e6, -1e6, 1e6});
        const RestrictedBoxtree<double> m(base);
        const auto got = collide(m, shift, m, shift * pb, all);
        CHECK(test::contact_pairs(got) == test::contact_pairs(collide_brute_force(base, shift, base, shift * pb, all)));
        CHECK(got.colliding == ref.colliding);
        // The mesh itself far from the origin (float planes are relative to the tree's centre).
        auto far = base;
        for (auto& v : far.vertices) v += Vec3<double>(1e6, 2e6, -1e6);
        const RestrictedBoxtree<double> mf(far);
        const Transform<double> back = Transform<double>::translation({-1e6, -2e6, 1e6});
        const Transform<double> pf = pb * back;
        const auto got_far = collide(mf, back, mf, pf, all);
        CHECK(test::contact_pairs(got_far) == test::contact_pairs(collide_brute_force(far, back, far, pf, all)));
        // Float planes far out: every triangle still inside its leaf's box.
        if (i == 0) CHECK(check_leaf_boxes(mf) == base.num_triangles());
    }
    CHECK(hits > 0);
}

TEST_CASE("Restricted boxtree: touching, coincident and truncated", "[boxtree]") {
    const RestrictedBoxtree<double> m(test::uv_sphere<double>(1.0, 8, 16));
    const auto same = collide(m, Transform<double>(), m, Transform<double>(), {ContactMode::all});
    CHECK(same.colliding);
    CHECK(same.contacts.size() >= m.mesh().num_triangles());
    // Poles touching exactly, then one ulp apart.
    const auto touch = collide(m, Transform<double>(), m, Transform<double>::translation({0, 0, 2}));
    CHECK(touch.colliding);
    CHECK((touch.contacts[0].point - Vec3<double>(0, 0, 1)).norm() < 1e-12);
    CHECK_FALSE(collide(m, Transform<double>(), m, Transform<double>::translation({0, 0, std::nextafter(2.0, 3.0)})).colliding);
    const auto far = collide(m, Transform<double>(), m, Transform<double>::translation({10, 0, 0}));
    CHECK_FALSE(far.colliding);
    CHECK(far.stats.bv_tests == 1);
    const auto cut = collide(m, Transform<double>(), m, Transform<double>(), {ContactMode::all, 5});
    CHECK(cut.contacts.size() == 5);
    CHECK(cut.truncated);
}

TEST_CASE("Restricted boxtree collide is thread-safe", "[boxtree][threads]") {
    const RestrictedBoxtree<double> a(test::uv_sphere<double>(1.0, 12, 24));
    const RestrictedBoxtree<double> b(test::random_soup<double>(300, 0.2, 3));
    test::check_concurrent_collide(a, b, 120, 2, 12);
}

TEMPLATE_TEST_CASE("Restricted boxtree refit: the same mesh gives the built tree, a deformed one stays exact", "[boxtree][refit]",
                   float, double) {
    using S = TestType;
    const auto base = std::make_shared<const TriangleMesh<S>>(test::uv_sphere<S>(S(1), 8, 16));
    for (std::uint32_t extra : {0u, 1u}) {
        BoxtreeOptions opt;
        opt.max_extra_restrictions = extra;
        RestrictedBoxtree<S> a(base, opt);
        const RestrictedBoxtree<S> built(base, opt);
        const auto same_tree = [](const RestrictedBoxtree<S>& x, const RestrictedBoxtree<S>& y) {
            if (x.root_box() != y.root_box() || x.centre() != y.centre() || x.nodes().size() != y.nodes().size()) return false;
            for (std::size_t i = 0; i < x.nodes().size(); ++i)
                if (x.nodes()[i].plane != y.nodes()[i].plane || x.nodes()[i].bits != y.nodes()[i].bits) return false;
            return true;
        };
        // Bend, then collide against a soup: equal to brute force on the refitted tree.
        const auto bent = std::make_shared<const TriangleMesh<S>>(test::deformed(*base, 0.4));
        a.refit(bent);
        CHECK(&a.mesh() == bent.get());
        REQUIRE_NOTHROW(a.validate());
        CHECK(check_leaf_boxes(a) == base->num_triangles());
        CHECK_FALSE(same_tree(a, built));
        const RestrictedBoxtree<S> soup(test::random_soup<S>(150, S(0.2), 6), opt);
        const int poses = test::scaled(16, 12);
        const int hits = test::collide_equals_brute_force(a, soup, poses, 4.0, 31 + extra, 0.25);
        CHECK(hits > poses / 5);
        CHECK(hits < poses - poses / 10);
        // Refitted back onto the original mesh: the built tree, node for node (the build's plane rule).
        a.refit(std::make_shared<const TriangleMesh<S>>(*base));
        CHECK(same_tree(a, built));
        // Bad input leaves the tree as it was.
        auto other = *base;
        std::swap(other.triangles[0][0], other.triangles[0][1]);
        REQUIRE_THROWS_WITH(a.refit(std::make_shared<const TriangleMesh<S>>(other)), Catch::Contains("topology changed"));
        auto nan = *base;
        nan.source = "nan.obj";
        nan.vertices[3].x() = std::numeric_limits<S>::quiet_NaN();
        REQUIRE_THROWS_WITH(a.refit(std::make_shared<const TriangleMesh<S>>(nan)), Catch::Contains("nan.obj"));
        auto fewer = *base;
        fewer.vertices.push_back(Vec3<S>::Zero());
        REQUIRE_THROWS_WITH(a.refit(std::make_shared<const TriangleMesh<S>>(fewer)), Catch::Contains("vertex count"));
        REQUIRE_THROWS_AS(a.refit(nullptr), Error);
        CHECK(same_tree(a, built));
    }
}
