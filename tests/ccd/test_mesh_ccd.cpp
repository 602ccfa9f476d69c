// Continuous collision of two rigid meshes on their trees, against every feature pair tested one by one
// (mesh_ccd_brute_force: the same primitive tests, no tree): the same colliding feature pairs and the same first
// time of contact, for every BV of the family, over random motions with large rotations per step.

#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <cdkit/bv/aabb.hpp>
#include <cdkit/bv/kdop.hpp>
#include <cdkit/bv/obb.hpp>
#include <cdkit/bv/rss.hpp>
#include <cdkit/bv/sphere.hpp>
#include <cdkit/ccd/mesh_ccd.hpp>

#include <set>

namespace {

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

std::set<std::array<cdkit::Index, 5>> feature_keys(const cdkit::DeformableCcdResult& r,
                                                   const cdkit::TriangleMesh<double>& a,
                                                   const cdkit::TriangleMesh<double>& b) {
    std::set<std::array<cdkit::Index, 5>> keys;
    for (const auto& c : r.contacts) keys.insert(cdkit::detail::feature_key(c, a, b));
    return keys;
}

}  // namespace

TEMPLATE_TEST_CASE("mesh CCD on trees equals all feature pairs", "[ccd]", cdkit::Aabb<double>, cdkit::Obb<double>,
                   cdkit::Rss<double>, (cdkit::Kdop<double, 18>), cdkit::BoundingSphere<double>) {
    const auto sphere = cdkit::test::uv_sphere<double>(1.0, 6, 10);
    const auto soup = cdkit::test::random_soup<double>(40, 1.5, 7);
    const cdkit::MeshModel<TestType> a(sphere), b(soup);
    std::mt19937_64 rng(34);
    std::uniform_real_distribution<double> offset(-2.5, 2.5);
    const int n = cdkit::test::scaled(8, 3);
    int hits = 0;
    for (int i = 0; i < n; ++i) {
        // A sweeps from one side of B to the other, turning by up to a full random rotation in the step.
        const T a0(cdkit::test::random_rotation<double>(rng), V(-3, offset(rng) * 0.3, offset(rng) * 0.3));
        const T a1(cdkit::test::random_rotation<double>(rng), V(3, offset(rng) * 0.3, offset(rng) * 0.3));
        const T b0(cdkit::test::random_rotation<double>(rng), V(0, 0, 0));
        const T b1(cdkit::test::random_rotation<double>(rng), V(offset(rng) * 0.1, 0, 0));
        cdkit::DeformableCcdRequest all;
        all.mode = cdkit::ContactMode::all;
        const auto tree = cdkit::mesh_ccd(a, a0, a1, b, b0, b1, all);
        const auto brute = cdkit::mesh_ccd_brute_force(sphere, a0, a1, soup, b0, b1, all);
        REQUIRE(tree.status == cdkit::QueryStatus::ok);
        REQUIRE(tree.colliding == brute.colliding);
        CHECK(feature_keys(tree, sphere, soup) == feature_keys(brute, sphere, soup));
        CHECK(tree.toi == brute.toi);
        hits += tree.colliding;
        // ContactMode::first: the earliest time, to within the time tolerance (each search stops at the earliest
        // contact found so far, and the two searches meet the pairs in different orders).
        const auto first = cdkit::mesh_ccd(a, a0, a1, b, b0, b1);
        REQUIRE(first.colliding == brute.colliding);
        if (first.colliding) {
            CHECK(first.toi <= brute.toi + 1e-6);
            CHECK(first.toi >= brute.toi - 1e-6);
            CHECK(first.contacts.size() == 1);
        }
        CHECK(tree.stats.vertex_face_candidates < brute.stats.vertex_face_candidates);
    }
    CHECK(hits > n / 2);  // the motions do sweep through B
}

TEST_CASE("mesh CCD: a thin plate does not let a fast mesh through; bad poses", "[ccd]") {
    const auto sphere = cdkit::test::uv_sphere<double>(0.2, 6, 8);
    const auto plate = cdkit::test::grid_box<double>(V(2, 2, 1e-3), 4);
    const cdkit::MeshModel<cdkit::Obb<double>> a(sphere), b(plate);
    // The sphere crosses the 2 mm plate in one step; at both ends it is clear of it.
    const T a0 = T::translation(V(0.1, 0.2, 5)), a1 = T::translation(V(0.1, 0.2, -5));
    const T still;
    const auto r = cdkit::mesh_ccd(a, a0, a1, b, still, still);
    REQUIRE(r.colliding);
    // The sphere's lowest point (z = 5 − 0.2 at t = 0) reaches the plate's top (z = 1e-3) at t = (4.8 − 1e-3) / 10.
    CHECK(r.toi <= (4.8 - 1e-3) / 10 + 1e-6);
    CHECK(r.toi >= (4.8 - 1e-3) / 10 - 0.05);  // the sphere is a polygon: its lowest vertex is a little higher
    T bad = still;
    bad.R(0, 0) = 2;
    CHECK(cdkit::mesh_ccd(a, bad, a1, b, still, still).status == cdkit::QueryStatus::invalid_pose);
    cdkit::DeformableCcdRequest bad_request;
    bad_request.primitive.t_max = 2;
    CHECK(cdkit::mesh_ccd(a, a0, a1, b, still, still, bad_request).status == cdkit::QueryStatus::invalid_input);
}
