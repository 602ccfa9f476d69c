// distance() on restricted boxtrees: bit for bit distance_brute_force() with no error allowed (random soups,
// spheres, near-touching and intersecting poses, degenerate triangles, huge offsets and extreme scales, float
// and double), within the error bound when one is allowed, closest points on their triangles, invalid poses,
// and concurrent queries. Fixed seeds.
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/bvh/boxtree.hpp"
#include "cdkit/distance.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <thread>

using namespace cdkit;

namespace {
template <class S> Transform<S> random_pose(std::mt19937_64& rng, double spread) {
    std::uniform_real_distribution<double> u(-spread, spread);
    return Transform<double>(test::random_rotation<double>(rng), Vec3<double>(u(rng), u(rng), u(rng))).template cast<S>();
}

/// The result's points lie on its triangles (world frame) and are `distance` apart.
template <class S>
void check_witness(const RestrictedBoxtree<S>& a, const Transform<S>& pa, const RestrictedBoxtree<S>& b,
                   const Transform<S>& pb, const DistanceResult<S>& r) {
    const double tol = std::is_same_v<S, float> ? 1e-4 : 1e-10;
    const auto on = [&](const RestrictedBoxtree<S>& m, Index t, const Transform<S>& pose, const Vec3<S>& p) {
        const auto tri = m.mesh().triangle(t);
        const Vec3<S> local = pose.inverse() * p;
        return double(triangle_distance(tri[0], tri[1], tri[2], local, local, local).distance);
    };
    CHECK(on(a, r.triangle_a, pa, r.point_a) <= tol);
    CHECK(on(b, r.triangle_b, pb, r.point_b) <= tol);
    CHECK(std::abs((r.point_a - r.point_b).template cast<double>().norm() - double(r.distance)) <= tol);
}
}  // namespace

TEMPLATE_TEST_CASE("Boxtree distance equals brute force on soups and spheres, and keeps the error bound", "[boxtree][distance]",
                   float, double) {
    using S = TestType;
    std::mt19937_64 rng(31);
    const RestrictedBoxtree<S> soup_a(test::random_soup<S>(90, S(0.3), 1));
    const RestrictedBoxtree<S> soup_b(test::random_soup<S>(70, S(0.2), 2));
    const RestrictedBoxtree<S> sphere(test::uv_sphere<S>(S(0.8), 8, 10));
    const RestrictedBoxtree<S> plain(test::uv_sphere<S>(S(0.5), 6, 9), BoxtreeOptions{BoxtreeSplit::median, 0});
    const std::pair<const RestrictedBoxtree<S>*, const RestrictedBoxtree<S>*> pairs[] = {
        {&soup_a, &soup_b}, {&sphere, &soup_b}, {&sphere, &sphere}, {&plain, &soup_a}};
    int intersecting = 0, separated = 0;
    for (const auto& [a, b] : pairs)
        for (int k = 0; k < test::scaled(30, 4); ++k) {
            const Transform<S> pa = random_pose<S>(rng, 1.0), pb = random_pose<S>(rng, 2.5);
            const DistanceResult<S> r = distance(*a, pa, *b, pb);
            const DistanceResult<S> ref = distance_brute_force(a->mesh(), pa, b->mesh(), pb);
            INFO("pose " << k);
            REQUIRE(r.distance == ref.distance);
            check_witness(*a, pa, *b, pb, r);
            CHECK((r.distance == S(0)) == collide(*a, pa, *b, pb).colliding);
            (r.distance == S(0) ? intersecting : separated) += 1;
            CHECK(r.stats.primitive_tests <= a->mesh().num_triangles() * b->mesh().num_triangles());
            for (const auto& [rel, abs] : {std::pair<S, S>{S(0.05), S(0)}, {S(0), S(0.05)}, {S(0.5), S(0.1)}}) {
                const DistanceResult<S> e = distance(*a, pa, *b, pb, {rel, abs});
                CHECK(e.distance >= ref.distance);
                CHECK(e.distance <= (1 + rel) * ref.distance + abs);
                check_witness(*a, pa, *b, pb, e);
            }
        }
    CHECK(intersecting > 0);
    CHECK(separated > 0);
}

TEMPLATE_TEST_CASE("Boxtree distance: boxes face to face, where the box bound is exact", "[boxtree][distance]", float, double) {
    using S = TestType;
    const RestrictedBoxtree<S> box(test::grid_box<S>({0.5, 0.3, 0.2}, 4));
    std::mt19937_64 rng(5);
    for (double gap : {0.0, 1e-6, 1e-3, 0.01, 0.1, 0.7}) {
        // B shifted along x by the sum of half extents + gap (axis-aligned: a bound too large by a hair
        // prunes the closest pair), then the same with both rotated rigidly together.
        const Transform<double> common(test::random_rotation<double>(rng), Vec3<double>(0.3, -0.2, 0.1));
        const Transform<double> shift = Transform<double>::translation({1.0 + gap, 0.05, -0.02});
        for (const auto& [pa, pb] : {std::pair{Transform<double>(), shift}, std::pair{common, common * shift}}) {
            const Transform<S> fa = pa.template cast<S>(), fb = pb.template cast<S>();
            const DistanceResult<S> r = distance(box, fa, box, fb);
            INFO("gap " << gap);
            CHECK(r.distance == distance_brute_force(box.mesh(), fa, box.mesh(), fb).distance);
            CHECK(std::abs(double(r.distance) - gap) <= (std::is_same_v<S, float> ? 1e-6 : 1e-14));
            check_witness(box, fa, box, fb, r);
        }
    }
}

TEST_CASE("Boxtree distance prunes, and agrees with brute force just off contact", "[boxtree][distance]") {
    // The brute-force reference is quadratic: the reduced (sanitizer) run takes a coarser sphere.
    const bool reduced = test::scale() < 1;
    const RestrictedBoxtree<double> m(test::uv_sphere<double>(1.0, reduced ? 8 : 16, reduced ? 16 : 32));
    const std::size_t all_pairs = m.mesh().num_triangles() * m.mesh().num_triangles();
    std::mt19937_64 rng(8);
    for (int k = 0; k < test::scaled(12, 3); ++k) {
        const Mat3<double> R = test::random_rotation<double>(rng);
        const Vec3<double> dir = test::random_rotation<double>(rng).col(0);
        for (double gap : {0.0, 1e-9, 1e-4, 0.05, 1.0}) {
            const Transform<double> pb(R, (2.0 + gap) * dir);
            const auto r = distance(m, Transform<double>(), m, pb);
            const auto ref = distance_brute_force(m.mesh(), Transform<double>(), m.mesh(), pb);
            INFO("pose " << k << " gap " << gap);
            REQUIRE(r.distance == ref.distance);
            CHECK(r.stats.primitive_tests * 20 < all_pairs);
        }
    }
}

TEST_CASE("Boxtree distance: degenerate triangles, huge offsets and extreme scales", "[boxtree][distance]") {
    TriangleMesh<double> base = test::random_soup<double>(120, 0.2, 21);
    // Collapse every fourth triangle to a segment and every seventh to a point.
    for (std::size_t i = 0; i < base.triangles.size(); i += 4) base.triangles[i][2] = base.triangles[i][1];
    for (std::size_t i = 1; i < base.triangles.size(); i += 7) base.triangles[i] = {base.triangles[i][0], base.triangles[i][0], base.triangles[i][0]};
    std::mt19937_64 rng(4);
    for (int i = 0; i < test::scaled(15, 4); ++i) {
        const Transform<double> pb(test::random_rotation(rng), Vec3<double>(0.6, -0.4, 0.2));
        const RestrictedBoxtree<double> m(base);
        const double exact = distance_brute_force(base, Transform<double>(), base, pb).distance;
        CHECK(distance(m, Transform<double>(), m, pb).distance == exact);
        // Powers of two scale exactly: the answer scales exactly too.
        for (double s : {std::ldexp(1.0, -20), std::ldexp(1.0, 20)}) {
            auto scaled = base;
            for (auto& v : scaled.vertices) v *= s;
            const RestrictedBoxtree<double> ms(scaled);
            const Transform<double> ps(pb.R, pb.t * s);
            const double got = distance(ms, Transform<double>(), ms, ps).distance;
            CHECK(got == distance_brute_force(scaled, Transform<double>(), scaled, ps).distance);
            CHECK(got == exact * s);
        }
        // Both poses far from the origin, and the mesh itself far from it.
        const Transform<double> shift = Transform<double>::translation({1e6, -1e6, 1e6});
        CHECK(distance(m, shift, m, shift * pb).distance == distance_brute_force(base, shift, base, shift * pb).distance);
        auto far = base;
        for (auto& v : far.vertices) v += Vec3<double>(1e6, 2e6, -1e6);
        const RestrictedBoxtree<double> mf(far);
        const Transform<double> back = Transform<double>::translation({-1e6, -2e6, 1e6});
        CHECK(distance(mf, back, mf, pb * back).distance == distance_brute_force(far, back, far, pb * back).distance);
    }
}

TEST_CASE("Boxtree distance: invalid poses, touching and coincident meshes", "[boxtree][distance]") {
    const RestrictedBoxtree<double> m(test::uv_sphere<double>(1.0, 8, 16));
    Transform<double> bad;
    bad.R(0, 0) = std::nan("");
    const auto r = distance(m, Transform<double>(), m, bad);
    CHECK(r.status == QueryStatus::invalid_pose);
    CHECK(std::isinf(r.distance));
    CHECK(distance(m, Transform<double>(), m, Transform<double>()).distance == 0);
    const auto touch = distance(m, Transform<double>(), m, Transform<double>::translation({0, 0, 2}));
    CHECK(touch.distance == 0);
    CHECK((touch.point_a - Vec3<double>(0, 0, 1)).norm() < 1e-12);
    const auto apart = distance(m, Transform<double>(), m, Transform<double>::translation({0, 0, 3}));
    CHECK(apart.distance == distance_brute_force(m.mesh(), Transform<double>(), m.mesh(), Transform<double>::translation({0, 0, 3})).distance);
    CHECK(std::abs(apart.distance - 1.0) < 1e-12);
}

TEST_CASE("Boxtree distance queries are thread-safe", "[boxtree][distance][threads]") {
    const RestrictedBoxtree<double> a(test::uv_sphere<double>(1.0, 12, 24));
    const RestrictedBoxtree<double> b(test::random_soup<double>(300, 0.2, 3));
    std::mt19937_64 rng(12);
    std::vector<Transform<double>> poses;
    std::vector<double> expected;
    for (int k = 0; k < test::scaled(40, 8); ++k) {
        poses.push_back(random_pose<double>(rng, 2.0));
        expected.push_back(distance(a, Transform<double>(), b, poses.back()).distance);
    }
    std::vector<int> wrong(4, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (int rep = 0; rep < 3; ++rep)
                for (std::size_t k = 0; k < poses.size(); ++k)
                    wrong[t] += distance(a, Transform<double>(), b, poses[(k + t) % poses.size()]).distance !=
                                expected[(k + t) % poses.size()];
        });
    for (auto& th : threads) th.join();
    for (int w : wrong) CHECK(w == 0);
}
