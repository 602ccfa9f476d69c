// DistanceRequest::max_distance for mesh–mesh distance() (every BV family and the restricted boxtree) and
// mesh–convex distance(): against the brute force over every triangle pair (an independent loop), a pair within
// the bound gets the answer it gets without the bound, a pair beyond it +inf (no points), with errors allowed the
// answer keeps the error bound or says +inf only when the pair is beyond max_distance; a pair far beyond the bound
// costs the root test alone; requests out of range are refused with invalid_input. Fixed seeds.
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/bvh/boxtree.hpp"
#include "cdkit/distance.hpp"
#include "cdkit/mesh_convex.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace cdkit;

namespace {

template <class S> Transform<S> max_test_pose(std::mt19937_64& rng, double spread) {
    std::uniform_real_distribution<double> u(-spread, spread);
    return Transform<double>(test::random_rotation<double>(rng), Vec3<double>(u(rng), u(rng), u(rng))).template cast<S>();
}

/// The bounds a test tries around a pair's true distance `d`: below, at, one ulp either side, above, none.
template <class S> std::vector<S> max_bounds_around(S d) {
    const S inf = std::numeric_limits<S>::infinity();
    return {S(0), d / 2, std::nextafter(d, S(0)), d, std::nextafter(d, inf), d * S(1.5) + S(0.01), inf};
}

/// max_distance's contract for one pair (a, b) whose unbounded answer is `full` and true distance `ref`.
template <class Query, class Result, class S>
void check_max_bounded(const Query& query, const Result& full, S ref, int& within, int& beyond) {
    const S inf = std::numeric_limits<S>::infinity();
    for (const S max : max_bounds_around(ref)) {
        DistanceRequest<S> request;
        request.max_distance = max;
        const Result r = query(request);
        INFO("true " << ref << ", max_distance " << max);
        REQUIRE(r.status == QueryStatus::ok);
        if (ref <= max) {  // within: the unbounded answer, bit for bit
            CHECK(r.distance == full.distance);
            ++within;
        } else {  // beyond: nothing reported
            CHECK(r.distance == inf);
            ++beyond;
        }
        // With errors allowed: a finite answer keeps the bound; +inf only beyond max_distance.
        for (const auto& [rel, abs] : {std::pair<S, S>{S(0.05), S(0)}, {S(0), S(0.05)}, {S(0.5), S(0.1)}}) {
            request.rel_err = rel;
            request.abs_err = abs;
            const Result e = query(request);
            if (e.distance == inf) {
                CHECK(ref > max);
            } else {
                CHECK(e.distance >= ref);
                CHECK(e.distance <= (1 + rel) * ref + abs);
                CHECK(e.distance <= (1 + rel) * max + abs);
            }
        }
    }
}

}  // namespace

namespace {
/// A random soup against a sphere mesh, each a `Model` (a MeshModel or a RestrictedBoxtree), at random poses.
template <class Model, class S> void check_max_models(unsigned seed) {
    std::mt19937_64 rng(seed);
    const Model soup(test::random_soup<S>(60, S(0.3), seed));
    const Model sphere(test::uv_sphere<S>(S(0.7), 8, 10));
    int within = 0, beyond = 0;
    for (int k = 0; k < test::scaled(40, 6); ++k) {
        const Transform<S> pa = max_test_pose<S>(rng, 1.0), pb = max_test_pose<S>(rng, 2.5);
        const S ref = distance_brute_force(soup.mesh(), pa, sphere.mesh(), pb).distance;
        const DistanceResult<S> full = distance(soup, pa, sphere, pb);
        REQUIRE(full.distance == ref);
        check_max_bounded([&](const DistanceRequest<S>& q) { return distance(soup, pa, sphere, pb, q); }, full, ref, within,
                      beyond);
    }
    CHECK(within >= 10);
    CHECK(beyond >= 10);
}
}  // namespace

TEMPLATE_TEST_CASE("mesh distance with max_distance: the unbounded answer within it, +inf beyond it", "[distance]",
                   Aabb<double>, Obb<double>, Obb<float>, Rss<double>, (Kdop<double, 18>), BoundingSphere<double>) {
    check_max_models<MeshModel<TestType>, typename TestType::Scalar>(77);
}

TEST_CASE("boxtree distance with max_distance: the unbounded answer within it, +inf beyond it", "[distance][boxtree]") {
    check_max_models<RestrictedBoxtree<double>, double>(78);
}

TEST_CASE("mesh-convex distance with max_distance: the unbounded answer within it, +inf beyond it", "[mesh_convex]") {
    std::mt19937_64 rng(79);
    const MeshModel<Obb<double>> obb(test::uv_sphere<double>(0.7, 8, 10));
    const MeshModel<Rss<double>> rss(test::random_soup<double>(60, 0.3, 7));
    const Box<double> box(Vec3<double>(0.3, 0.2, 0.4));
    const Capsule<double> capsule(0.15, 0.5);
    int within = 0, beyond = 0;
    for (int k = 0; k < test::scaled(30, 6); ++k) {
        const Transform<double> pm = max_test_pose<double>(rng, 1.0), ps = max_test_pose<double>(rng, 2.0);
        const auto one = [&](const auto& model, const auto& shape) {
            const auto ref = distance_brute_force(model.mesh(), pm, shape, ps);
            const auto full = distance(model, pm, shape, ps);
            REQUIRE(full.distance == ref.distance);
            check_max_bounded([&](const DistanceRequest<double>& q) { return distance(model, pm, shape, ps, q); }, full,
                          ref.distance, within, beyond);
        };
        one(obb, box);
        one(rss, capsule);
    }
    CHECK(within >= 10);
    CHECK(beyond >= 10);
}

TEST_CASE("distance with max_distance: a pair far beyond it costs the root test alone", "[distance][mesh_convex]") {
    const MeshModel<Obb<double>> a(test::uv_sphere<double>(0.5, 12, 16));
    const Transform<double> far(Mat3<double>::Identity(), Vec3<double>(10, 0, 0));
    DistanceRequest<double> request;
    request.max_distance = 1;
    const DistanceResult<double> r = distance(a, Transform<double>(), a, far, request);
    CHECK(r.status == QueryStatus::ok);
    CHECK(r.distance == std::numeric_limits<double>::infinity());
    CHECK(r.stats.bv_tests == 1);
    CHECK(r.stats.primitive_tests == 0);
    CHECK(distance(a, Transform<double>(), a, far).stats.primitive_tests > 0);  // unbounded: it measures
    const auto c = distance(a, Transform<double>(), Sphere<double>(0.2), far, request);
    CHECK(c.distance == std::numeric_limits<double>::infinity());
    CHECK(c.stats.bv_tests == 1);
    CHECK(c.stats.primitive_tests == 0);
}

TEST_CASE("distance refuses requests out of range with invalid_input", "[distance][mesh_convex]") {
    const MeshModel<Obb<double>> a(test::uv_sphere<double>(0.5, 6, 8));
    const Transform<double> near(Mat3<double>::Identity(), Vec3<double>(1.5, 0, 0));
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    const DistanceRequest<double> bad[] = {{-1, 0, inf}, {0, -1, inf}, {nan, 0, inf}, {0, nan, inf},
                                           {inf, 0, inf}, {0, inf, inf}, {0, 0, -1},  {0, 0, nan}};
    for (const DistanceRequest<double>& q : bad) {
        INFO("rel " << q.rel_err << " abs " << q.abs_err << " max " << q.max_distance);
        const DistanceResult<double> r = distance(a, Transform<double>(), a, near, q);
        CHECK(r.status == QueryStatus::invalid_input);
        CHECK(r.distance == inf);
        const auto c = distance(a, Transform<double>(), Sphere<double>(0.2), near, q);
        CHECK(c.status == QueryStatus::invalid_input);
        CHECK(c.distance == inf);
    }
    // max_distance 0 is a valid request: touching or nothing.
    CHECK(distance(a, Transform<double>(), a, near, {0, 0, 0}).status == QueryStatus::ok);
}
