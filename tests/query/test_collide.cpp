// collide() against the all-pairs reference: in ContactMode::all the set of intersecting triangle pairs
// must equal brute force's exactly, for every BV and scalar type, on closed meshes and polygon soups.
#include "bvh/brute_force_check.hpp"
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/cdkit.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <thread>

using namespace cdkit;

namespace {
template <class BV>
void check_against_brute_force(const TriangleMesh<typename BV::Scalar>& ma, const TriangleMesh<typename BV::Scalar>& mb,
                               int poses, double reach, unsigned seed) {
    using S = typename BV::Scalar;
    const MeshModel<BV> a(ma), b(mb);
    std::mt19937_64 rng(seed);
    int hits = 0;
    CollisionRequest all;
    all.mode = ContactMode::all;
    for (int i = 0; i < poses; ++i) {
        const Transform<S> pa = test::near_pose<S>(rng, 0.5), pb = test::near_pose<S>(rng, reach);
        const auto ref = collide_brute_force(ma, pa, mb, pb, all);
        const auto got = collide(a, pa, b, pb, all);
        REQUIRE(got.colliding == ref.colliding);
        REQUIRE(test::contact_pairs(got) == test::contact_pairs(ref));
        const auto first = collide(a, pa, b, pb);
        REQUIRE(first.colliding == ref.colliding);
        if (first.colliding) {
            REQUIRE(first.contacts.size() == 1);
            // The witness is one of the reference's pairs, and its point lies on both triangles (world frame).
            const auto& c = first.contacts[0];
            const auto rp = test::contact_pairs(ref);
            REQUIRE(std::binary_search(rp.begin(), rp.end(), std::make_pair(c.triangle_a, c.triangle_b)));
            ++hits;
        }
        // BV culling must do real work: far fewer triangle tests than all pairs.
        if (!ref.colliding) CHECK(got.stats.primitive_tests < ma.num_triangles() * mb.num_triangles());
    }
    CHECK(hits > poses / 5);          // the poses do collide often...
    CHECK(hits < poses - poses / 10);  // ...and often do not
}
}  // namespace

TEMPLATE_PRODUCT_TEST_CASE("collide equals brute force on closed spheres", "[collide]", (cdkit::Aabb, cdkit::Obb, cdkit::Rss),
                           (float, double)) {
    using S = typename TestType::Scalar;
    const auto sphere = test::uv_sphere<S>(S(1), 10, 20);
    check_against_brute_force<TestType>(sphere, sphere, test::scaled(60, 10), 2.6, 11);
}

TEMPLATE_PRODUCT_TEST_CASE("collide equals brute force on polygon soups", "[collide]", (cdkit::Aabb, cdkit::Obb, cdkit::Rss),
                           (float, double)) {
    using S = typename TestType::Scalar;
    const auto a = test::random_soup<S>(300, S(0.15), 5);
    const auto b = test::random_soup<S>(200, S(0.2), 6);
    check_against_brute_force<TestType>(a, b, test::scaled(60, 10), 3.5, 12);
}

TEST_CASE("collide equals brute force on the teapot (open, real)", "[collide]") {
    // Scaled into the unit cube so the pose ranges mean the same as for the spheres.
    const auto teapot = test::unit_scaled(load_mesh(test::data_path("teapot.obj")));
    check_against_brute_force<Obb<double>>(teapot, teapot, test::scaled(12, 4), 2.0, 13);
    check_against_brute_force<Aabb<float>>(teapot.cast<float>(), teapot.cast<float>(), test::scaled(12, 4), 2.0, 14);
}

TEST_CASE("collide: touching and coincident configurations", "[collide]") {
    const auto sphere = test::uv_sphere<double>(1.0, 8, 16);
    const MeshModel<Obb<double>> m(sphere);
    // Coincident copies: every triangle touches its twin.
    const auto same = collide(m, Transform<double>(), m, Transform<double>(), {ContactMode::all});
    CHECK(same.colliding);
    CHECK(same.contacts.size() >= sphere.num_triangles());
    // Two spheres whose poles touch exactly: the pole vertex (0,0,1) meets (0,0,-1) moved up by 2.
    const auto touch = collide(m, Transform<double>(), m, Transform<double>::translation({0, 0, 2}));
    CHECK(touch.colliding);
    CHECK((touch.contacts[0].point - Vec3<double>(0, 0, 1)).norm() < 1e-12);
    // Apart by one ulp of 2 along z: no contact.
    const auto apart = collide(m, Transform<double>(), m, Transform<double>::translation({0, 0, std::nextafter(2.0, 3.0)}));
    CHECK_FALSE(apart.colliding);
    // Far apart: the roots' BVs reject at once.
    const auto far = collide(m, Transform<double>(), m, Transform<double>::translation({10, 0, 0}));
    CHECK_FALSE(far.colliding);
    CHECK(far.stats.bv_tests == 1);
}

TEST_CASE("collide: huge offsets and tiny scales", "[collide]") {
    // The same configuration at 1e6 offset and at 1e-6 scale must give the same pair set.
    const auto base = test::random_soup<double>(150, 0.2, 21);
    CollisionRequest all{ContactMode::all};
    std::mt19937_64 rng(4);
    for (int i = 0; i < test::scaled(20, 5); ++i) {
        const Transform<double> pb(test::random_rotation(rng), Vec3<double>(0.3, -0.2, 0.1));
        const auto ref = collide_brute_force(base, Transform<double>(), base, pb, all);
        // Powers of two scale exactly, so the answers must be identical, not merely close.
        for (double s : {std::ldexp(1.0, -20), std::ldexp(1.0, 20)}) {
            auto scaled = base;
            for (auto& v : scaled.vertices) v *= s;
            const MeshModel<Obb<double>> m(scaled);
            const Transform<double> ps(pb.R, pb.t * s);
            const auto got = collide(m, Transform<double>(), m, ps, all);
            CHECK(test::contact_pairs(got) == test::contact_pairs(collide_brute_force(scaled, Transform<double>(), scaled, ps, all)));
            CHECK(got.colliding == ref.colliding);
        }
        // Both far from the origin: the relative transform stays small, the poses do not.
        const Transform<double> shift = Transform<double>::translation({1e6, -1e6, 1e6});
        const MeshModel<Aabb<double>> m(base);
        const auto got = collide(m, shift, m, shift * pb, all);
        CHECK(test::contact_pairs(got) == test::contact_pairs(collide_brute_force(base, shift, base, shift * pb, all)));
        CHECK(got.colliding == ref.colliding);  // 1e6 + 0.3 rounds, but no pair here is that close to touching
    }
}

TEST_CASE("collide: max_contacts truncates", "[collide]") {
    const MeshModel<Aabb<double>> m(test::uv_sphere<double>(1.0, 8, 16));
    CollisionRequest req{ContactMode::all, 5};
    const auto r = collide(m, Transform<double>(), m, Transform<double>(), req);
    CHECK(r.contacts.size() == 5);
    CHECK(r.truncated);
}

TEST_CASE("collide is thread-safe: concurrent queries on shared models", "[collide][threads]") {
    const MeshModel<Obb<double>> a(test::uv_sphere<double>(1.0, 16, 32));
    const MeshModel<Obb<double>> b(test::random_soup<double>(400, 0.2, 3));
    test::check_concurrent_collide(a, b, 200, 3, 20);
}
