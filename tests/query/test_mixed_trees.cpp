// Mixed trees (bvh/mixed_descent.hpp): collide() and distance() between mesh models of different bounding volumes
// against the brute force over every triangle pair (an independent loop): the same boolean and contact set in
// ContactMode::all, the same distance bit for bit; every enclosing box contains its volume's sample points; pairs of
// both scalars. Fixed seeds.
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/distance.hpp"
#include "cdkit/query.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <set>
#include <utility>

using namespace cdkit;

namespace {

template <class S> Transform<S> mixed_test_pose(std::mt19937_64& rng, double spread) {
    std::uniform_real_distribution<double> u(-spread, spread);
    return Transform<double>(test::random_rotation<double>(rng), Vec3<double>(u(rng), u(rng), u(rng))).template cast<S>();
}

template <class S> std::set<std::pair<Index, Index>> mixed_contact_set(const CollisionResult<S>& r) {
    std::set<std::pair<Index, Index>> out;
    for (const Contact<S>& c : r.contacts) out.insert({c.triangle_a, c.triangle_b});
    return out;
}

/// Both models of one pair of volumes against the brute force, at random poses; counts both outcomes.
template <class BVA, class BVB> void check_mixed_pair(int seed) {
    using S = typename BVA::Scalar;
    std::mt19937_64 rng(seed);
    const TriangleMesh<S> soup = test::random_soup<S>(70, S(0.3), unsigned(seed));
    const TriangleMesh<S> sphere = test::uv_sphere<S>(S(0.7), 8, 10);
    const MeshModel<BVA> a(soup);
    const MeshModel<BVB> b(sphere);
    int hits = 0, misses = 0;
    const CollisionRequest all{ContactMode::all};
    for (int k = 0; k < test::scaled(40, 6); ++k) {
        const Transform<S> pa = mixed_test_pose<S>(rng, 1.0), pb = mixed_test_pose<S>(rng, 2.0);
        INFO(BVA::name << " vs " << BVB::name << ", pose " << k);
        const CollisionResult<S> ref = collide_brute_force(soup, pa, sphere, pb, all);
        const CollisionResult<S> r = collide(a, pa, b, pb, all);
        REQUIRE(r.status == QueryStatus::ok);
        CHECK(r.colliding == ref.colliding);
        CHECK(mixed_contact_set(r) == mixed_contact_set(ref));
        CHECK(collide(a, pa, b, pb).colliding == ref.colliding);  // first contact
        // B against A too: the mixed pair in the other order.
        CHECK(mixed_contact_set(collide(b, pb, a, pa, all)).size() == ref.contacts.size());
        const DistanceResult<S> d = distance(a, pa, b, pb);
        CHECK(d.distance == distance_brute_force(soup, pa, sphere, pb).distance);
        CHECK(distance(b, pb, a, pa).distance == distance_brute_force(sphere, pb, soup, pa).distance);
        (ref.colliding ? hits : misses) += 1;
    }
    CHECK(hits >= 2);
    CHECK(misses >= 2);
}

// Mixed pairs take the two-lane sibling test of Obb trees on their enclosing boxes (bvh/traverse.hpp).
static_assert(SiblingDescentPair<detail::MixedDescentPair<Rss<double>, Aabb<double>>>);
static_assert(SiblingDescentPair<detail::MixedDescentPair<Obb<float>, BoundingSphere<float>>>);

}  // namespace

TEST_CASE("mixed trees: collide and distance equal the brute force for every pair of volumes", "[collide][distance]") {
    check_mixed_pair<Obb<double>, Rss<double>>(1);
    check_mixed_pair<Aabb<double>, Obb<double>>(2);
    check_mixed_pair<Rss<double>, BoundingSphere<double>>(3);
    check_mixed_pair<Kdop<double, 18>, Rss<double>>(4);
    check_mixed_pair<Kdop<double, 26>, Aabb<double>>(5);
    check_mixed_pair<BoundingSphere<double>, Kdop<double, 14>>(6);
    check_mixed_pair<Obb<float>, Rss<float>>(7);
    check_mixed_pair<Aabb<float>, Kdop<float, 18>>(8);
}

TEST_CASE("mixed trees: float volumes over double meshes mix with each other", "[collide][distance]") {
    std::mt19937_64 rng(9);
    const TriangleMesh<double> soup = test::random_soup<double>(60, 0.3, 9);
    const TriangleMesh<double> sphere = test::uv_sphere<double>(0.7, 8, 10);
    const MeshModel<Obb<float>, double> a(soup);
    const MeshModel<Rss<float>, double> b(sphere);
    for (int k = 0; k < test::scaled(30, 6); ++k) {
        const Transform<double> pa = mixed_test_pose<double>(rng, 1.0), pb = mixed_test_pose<double>(rng, 2.0);
        CHECK(collide(a, pa, b, pb).colliding == collide_brute_force(soup, pa, sphere, pb).colliding);
        CHECK(distance(a, pa, b, pb).distance == distance_brute_force(soup, pa, sphere, pb).distance);
    }
}

TEST_CASE("enclosing_obb contains every point of its volume", "[bv]") {
    std::mt19937_64 rng(10);
    std::uniform_real_distribution<double> u(-1, 1);
    const TriangleMesh<double> soup = test::random_soup<double>(40, 0.4, 10);
    const auto check_model = [&](const auto& model) {
        for (const auto& node : model.bvh().nodes()) {
            const Obb<double> box = enclosing_obb(node.bv);
            // The node's triangles' vertices and points on them lie in the volume, hence in its box.
            for (std::uint32_t i = node.first; i < node.first + (node.is_leaf() ? node.count : 0u); ++i) {
                const auto tri = soup.triangle(model.bvh().triangle_order()[i]);
                for (int s = 0; s < 8; ++s) {
                    double w0 = std::abs(u(rng)), w1 = std::abs(u(rng)) * (1 - w0);
                    const Vec3<double> p = tri[0] + w0 * (tri[1] - tri[0]) + w1 * (tri[2] - tri[0]);
                    CHECK(node.bv.contains(p, 1e-12));
                    CHECK(box.contains(p, 1e-12));
                }
            }
        }
    };
    check_model(MeshModel<Aabb<double>>(soup));
    check_model(MeshModel<Rss<double>>(soup));
    check_model(MeshModel<BoundingSphere<double>>(soup));
    check_model(MeshModel<Kdop<double, 18>>(soup));
    // And points of the volume itself, not only of its triangles: the Rss's corners of its swept ball.
    const Rss<double> r = MeshModel<Rss<double>>(soup).bvh().nodes()[0].bv;
    const Obb<double> box = enclosing_obb(r);
    for (int sx : {-1, 1})
        for (int sy : {-1, 1})
            for (int sz : {-1, 1}) {
                const Vec3<double> p = r.center + r.axes.col(0) * (sx * (r.half[0] + r.radius)) +
                                       r.axes.col(1) * (sy * (r.half[1])) + r.axes.col(2) * (sz * r.radius);
                CHECK(box.contains(p, 1e-12));
            }
}
