// The restricted boxtree descends through the same simultaneous descent as every Bvh (bvh/traverse.hpp), so
// on one mesh and one pose it must answer as the Obb and Aabb trees do: the same contact set (ContactMode::all),
// the same first-contact answer, and the same distance, on the bunny at random poses near contact.
#include "bvh/brute_force_check.hpp"
#include "test_common.hpp"

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bvh/boxtree.hpp"
#include "cdkit/distance.hpp"
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/query.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace cdkit;

namespace {
/// The offset along `dir` at which two copies of a model (B rotated by R) just touch, by bisection.
template <class Model>
typename Model::Scalar descent_touching_offset(const Model& m, const Mat3<typename Model::Scalar>& R,
                                               const Vec3<typename Model::Scalar>& dir) {
    using S = typename Model::Scalar;
    S lo = 0, hi = 4;
    if (!collide(m, Transform<S>(), m, Transform<S>(R, Vec3<S>::Zero())).colliding) return -1;
    for (int it = 0; it < 40; ++it) {
        const S mid = S(0.5) * (lo + hi);
        (collide(m, Transform<S>(), m, Transform<S>(R, mid * dir)).colliding ? lo : hi) = mid;
    }
    return lo;
}

/// |x − y| within `rel` of the larger (exactly equal when both are 0).
template <class S> bool nearly_equal(S x, S y, double rel) {
    return std::abs(double(x) - double(y)) <= rel * std::max(std::abs(double(x)), std::abs(double(y)));
}

/// One mesh as a boxtree, an Obb tree and an Aabb tree; every query's answer compared at poses near contact.
template <class S> void boxtree_answers_as_bvh(const TriangleMesh<S>& mesh, int rotations, unsigned seed, double rel) {
    const RestrictedBoxtree<S> boxtree(mesh);
    const MeshModel<Obb<S>> obb(mesh);
    const MeshModel<Aabb<S>> aabb(mesh);
    const CollisionRequest all{ContactMode::all};
    std::mt19937_64 rng(seed);
    int hits = 0, misses = 0;
    for (int i = 0; i < rotations; ++i) {
        const Mat3<S> R = test::random_rotation<S>(rng);
        const Vec3<S> dir = Vec3<S>(test::random_rotation<S>(rng).col(0));
        const S s = descent_touching_offset(obb, R, dir);
        for (double d : {-0.01, -1e-6, 0.0, 1e-6, 0.02}) {
            const Transform<S> pa = test::near_pose<S>(rng, 0.5);
            const Transform<S> pb = pa * Transform<S>(R, S(std::max<double>(s, 0) + d) * dir);
            const auto box_all = collide(boxtree, pa, boxtree, pb, all);
            const auto obb_all = collide(obb, pa, obb, pb, all);
            const auto aabb_all = collide(aabb, pa, aabb, pb, all);
            REQUIRE(box_all.status == QueryStatus::ok);
            const auto pairs = test::contact_pairs(obb_all);
            REQUIRE(test::contact_pairs(box_all) == pairs);
            REQUIRE(test::contact_pairs(aabb_all) == pairs);

            const auto box_first = collide(boxtree, pa, boxtree, pb);
            REQUIRE(box_first.colliding == collide(obb, pa, obb, pb).colliding);
            REQUIRE(box_first.colliding == obb_all.colliding);
            if (box_first.colliding) {
                REQUIRE(box_first.contacts.size() == 1);
                const auto& c = box_first.contacts[0];
                REQUIRE(std::binary_search(pairs.begin(), pairs.end(), std::make_pair(c.triangle_a, c.triangle_b)));
            }

            const auto box_d = distance(boxtree, pa, boxtree, pb);
            const auto obb_d = distance(obb, pa, obb, pb);
            const auto aabb_d = distance(aabb, pa, aabb, pb);
            REQUIRE(box_d.status == QueryStatus::ok);
            REQUIRE(nearly_equal(box_d.distance, obb_d.distance, rel));
            REQUIRE(nearly_equal(box_d.distance, aabb_d.distance, rel));
            REQUIRE((box_d.distance == S(0)) == box_all.colliding);
            (box_all.colliding ? hits : misses)++;
        }
    }
    CHECK(hits > rotations);
    CHECK(misses > rotations);
}
}  // namespace

TEST_CASE("Boxtree and Bvh trees give the same contacts and distance on the bunny near contact", "[boxtree][descent]") {
    const auto bunny = test::unit_scaled(load_mesh(test::data_path("bunny.obj")));
    SECTION("double") { boxtree_answers_as_bvh<double>(bunny, test::scaled(12, 3), 35, 1e-12); }
    // Float meshes: every tree's distance is the minimum of the same float triangle distances.
    SECTION("float") { boxtree_answers_as_bvh<float>(bunny.cast<float>(), test::scaled(4, 2), 36, 1e-12); }
}
