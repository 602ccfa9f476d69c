// collide_many / distance_many (batch.hpp) against the single calls: the same answer for every pose pair, bit for
// bit (the same code on the same inputs, in parallel or not), in order; a mismatched pair of pose lists throws.
#include "bvh/brute_force_check.hpp"
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/batch.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <vector>

using namespace cdkit;

namespace {
template <class BV> void check_batch_equals_single(bool parallel) {
    const auto sphere = test::uv_sphere<double>(1.0, 10, 20);
    const MeshModel<BV> a(sphere), b(sphere);
    std::mt19937_64 rng(5);
    const int n = test::scaled(400, 40);
    std::vector<Transform<double>> pa, pb;
    for (int i = 0; i < n; ++i) {
        pa.push_back(test::near_pose<double>(rng, 0.5));
        pb.push_back(test::near_pose<double>(rng, 2.6));
    }
    pb[3].R(0, 0) = 2;  // not a rigid motion: that entry's status, as in the single call
    BatchRequest batch;
    batch.parallel = parallel;
    batch.grain = 7;
    CollisionRequest all;
    all.mode = ContactMode::all;
    const auto hits = collide_many(a, std::span<const Transform<double>>(pa), b, std::span<const Transform<double>>(pb),
                                   all, batch);
    const auto dists = distance_many<BV, double>(a, pa, b, pb, {}, batch);
    REQUIRE(hits.size() == std::size_t(n));
    REQUIRE(dists.size() == std::size_t(n));
    int colliding = 0;
    for (int i = 0; i < n; ++i) {
        const auto one = collide(a, pa[i], b, pb[i], all);
        REQUIRE(hits[i].status == one.status);
        REQUIRE(hits[i].colliding == one.colliding);
        REQUIRE(hits[i].contacts.size() == one.contacts.size());
        for (std::size_t k = 0; k < one.contacts.size(); ++k) {
            REQUIRE(hits[i].contacts[k].triangle_a == one.contacts[k].triangle_a);
            REQUIRE(hits[i].contacts[k].triangle_b == one.contacts[k].triangle_b);
            REQUIRE(hits[i].contacts[k].point == one.contacts[k].point);
        }
        const auto d = distance(a, pa[i], b, pb[i]);
        REQUIRE(dists[i].status == d.status);
        REQUIRE(dists[i].distance == d.distance);  // bit for bit: same routine, same rounded vertices
        REQUIRE(dists[i].triangle_a == d.triangle_a);
        REQUIRE(dists[i].triangle_b == d.triangle_b);
        REQUIRE(dists[i].point_a == d.point_a);
        colliding += one.colliding;
    }
    REQUIRE(hits[3].status == QueryStatus::invalid_pose);
    REQUIRE(dists[3].status == QueryStatus::invalid_pose);
    CHECK(colliding > n / 5);         // the poses collide often...
    CHECK(colliding < n - n / 10);    // ...and often do not
}
}  // namespace

TEMPLATE_TEST_CASE("collide_many and distance_many equal the single calls", "[batch]", cdkit::Obb<double>,
                   cdkit::Rss<double>, cdkit::Aabb<double>) {
    check_batch_equals_single<TestType>(true);
    check_batch_equals_single<TestType>(false);
}

TEST_CASE("collide_many refuses pose lists of different lengths", "[batch]") {
    const MeshModel<Obb<double>> m(test::uv_sphere<double>(1.0, 6, 8));
    const std::vector<Transform<double>> two(2), three(3);
    REQUIRE_THROWS_AS((collide_many<Obb<double>, double>(m, two, m, three)), Error);
    REQUIRE_THROWS_AS((distance_many<Obb<double>, double>(m, two, m, three)), Error);
    const auto none = collide_many<Obb<double>, double>(m, {}, m, {});
    REQUIRE(none.empty());
}
