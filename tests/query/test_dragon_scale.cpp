// collide() and distance() at scale: the Stanford dragon at 203k and 871k triangles (scripts/fetch-data, which
// scripts/test runs; a missing file fails the test) against itself at P2-style poses, judged by a reference that
// shares no code with the trees: a uniform grid over the triangles' boxes, every candidate pair tested.
//  - collide, ContactMode::all: the set of intersecting triangle pairs equals the grid's exactly (both run the
//    exact-predicate triangle test on the same rounded points of B in A's frame; that test is judged against CGAL
//    in tests/narrowphase); ContactMode::first reports one of those pairs.
//  - distance: equals the grid's minimum over every pair whose boxes lie within the answer, measured with this
//    file's own point–triangle and segment–segment distances (not cdkit's triangle_distance).
// Poses: a random rotation R and direction u, bisection along u to first contact, then B pushed in or pulled out
// by a fraction of the bounding-box diagonal (BENCHMARKS.md P2).
#include "bvh/brute_force_check.hpp"
#include "mesh_factory.hpp"
#include "oracles/grid_reference.hpp"
#include "test_common.hpp"

#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/rss.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/distance.hpp"
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/query.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

using namespace cdkit;

// Named: the unity build compiles this file with others of tests/query whose helpers share names.
namespace dragon_scale {

using V = Vec3<double>;
using Pairs = std::vector<std::pair<Index, Index>>;
using namespace cdkit::test::grid;

const TriangleMesh<double>& dragon(const char* file) {
    static std::map<std::string, TriangleMesh<double>> cache;
    auto it = cache.find(file);
    if (it == cache.end()) {
        const std::string path = test::data_path(file);
        INFO(path << " is missing: scripts/fetch-data downloads it (scripts/test runs it)");
        REQUIRE(std::filesystem::exists(path));
        it = cache.emplace(file, load_mesh(path)).first;
    }
    return it->second;
}

void check_dragon(const char* file, int poses, std::uint64_t seed) {
    const TriangleMesh<double>& mesh = dragon(file);
    const auto shared = std::make_shared<const TriangleMesh<double>>(mesh);
    const MeshModel<Obb<double>> obb(shared);
    const MeshModel<Rss<double>> rss(shared);
    V lo = mesh.vertices[0], hi = lo;
    for (const V& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double diag = (hi - lo).norm();
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> uni(-1, 1);
    CollisionRequest all;
    all.mode = ContactMode::all;
    int pairs_total = 0;
    for (int i = 0; i < poses; ++i) {
        const Transform<double> pa(test::random_rotation(rng), diag * V(uni(rng), uni(rng), uni(rng)));
        const Mat3<double> R = test::random_rotation(rng);
        V u(g(rng), g(rng), g(rng));
        u.normalize();
        auto pose_b = [&](double s) { return Transform<double>(pa.R * R, pa.t + s * u); };
        double in = 0, out = 2 * diag;
        for (int it = 0; it < 24; ++it) {
            const double mid = (in + out) / 2;
            (collide(obb, pa, obb, pose_b(mid)).colliding ? in : out) = mid;
        }
        for (const double delta : {-0.02, -0.002, 0.002, 0.02}) {
            const Transform<double> pb = pose_b((delta < 0 ? in : out) + delta * diag);
            INFO(file << " pose " << i << " δ = " << delta);
            const PosedPair p = posed(mesh, pa, mesh, pb);
            if (delta < 0) {
                const Pairs ref = grid_intersecting_pairs(p);
                const auto got = collide(obb, pa, obb, pb, all);
                INFO("cdkit " << got.contacts.size() << " pairs, grid " << ref.size());
                CHECK(test::contact_pairs(got) == ref);
                // Pushed in past first contact, B can still clear a thin part of A (a horn, a whisker): no pairs.
                const auto first = collide(rss, pa, rss, pb);
                REQUIRE(first.colliding == !ref.empty());
                if (first.colliding)
                    CHECK(std::binary_search(ref.begin(), ref.end(),
                                         std::pair(first.contacts[0].triangle_a, first.contacts[0].triangle_b)));
                pairs_total += int(ref.size());
            } else {
                const auto got = distance(rss, pa, rss, pb);
                REQUIRE(got.distance > 0);
                const double ref = grid_distance(p, double(got.distance) * (1 + 1e-9) + 1e-12 * diag);
                CHECK(std::abs(ref - double(got.distance)) <= 1e-10 * diag);
                CHECK(triangle_gap(p.ta[got.triangle_a], p.tb[got.triangle_b]) <= double(got.distance) + 1e-10 * diag);
                // the obb tree finds the same distance
                CHECK(std::abs(double(distance(obb, pa, obb, pb).distance) - ref) <= 1e-10 * diag);
            }
        }
    }
    WARN(file << ": " << poses << " poses, " << pairs_total << " intersecting pairs judged by the grid");
    CHECK(pairs_total > 0);
}

}  // namespace dragon_scale

TEST_CASE("collide and distance on the 203k dragon against a uniform-grid reference", "[query][dragon]") {
    dragon_scale::check_dragon("dragon/dragon_203k.ply", test::scaled(4, 1), 11);
}

TEST_CASE("collide and distance on the 871k dragon against a uniform-grid reference", "[query][dragon]") {
    dragon_scale::check_dragon("dragon/dragon_871k.ply", test::scaled(2, 1), 12);
}
