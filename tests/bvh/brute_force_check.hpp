#pragma once
// The brute-force equality check of tests/query/test_collide.cpp, shared by the BV-family tests: in
// ContactMode::all, collide() must find exactly the triangle pairs that collide_brute_force() finds.
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/bv/fit.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/query.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <random>
#include <thread>
#include <vector>

namespace cdkit::test {

template <class S> std::vector<std::pair<Index, Index>> contact_pairs(const CollisionResult<S>& r) {
    std::vector<std::pair<Index, Index>> p;
    for (const auto& c : r.contacts) p.emplace_back(c.triangle_a, c.triangle_b);
    std::sort(p.begin(), p.end());
    return p;
}

/// A random rotation and a translation of length in [0, reach).
template <class S> Transform<S> near_pose(std::mt19937_64& rng, double reach) {
    std::uniform_real_distribution<double> u(-1, 1);
    Vec3<double> d(u(rng), u(rng), u(rng));
    d *= reach * std::abs(u(rng)) / std::max(1e-9, d.norm());
    return Transform<S>(random_rotation<S>(rng), d.cast<S>());
}

/// Checks collide() on the two models (MeshModel or RestrictedBoxtree) against brute force over `poses` random
/// poses: the same triangle pairs in ContactMode::all, and a first contact that is one of them. Returns the
/// number of colliding poses (the caller checks the hit rate). Culling must do real work: on poses that do not
/// collide, fewer triangle tests than `max_pair_fraction` of all pairs.
template <class Model>
int collide_equals_brute_force(const Model& a, const Model& b, int poses, double reach, unsigned seed,
                               double max_pair_fraction = 1.0) {
    using S = typename Model::Scalar;
    std::mt19937_64 rng(seed);
    int hits = 0;
    const CollisionRequest all{ContactMode::all};
    for (int i = 0; i < poses; ++i) {
        const Transform<S> pa = near_pose<S>(rng, 0.5), pb = near_pose<S>(rng, reach);
        const auto ref = collide_brute_force(a.mesh(), pa, b.mesh(), pb, all);
        const auto got = collide(a, pa, b, pb, all);
        REQUIRE(got.status == QueryStatus::ok);
        REQUIRE(got.colliding == ref.colliding);
        const auto ref_pairs = contact_pairs(ref);
        REQUIRE(contact_pairs(got) == ref_pairs);
        const auto first = collide(a, pa, b, pb);
        REQUIRE(first.colliding == ref.colliding);
        if (first.colliding) {
            REQUIRE(first.contacts.size() == 1);
            const auto& c = first.contacts[0];
            REQUIRE(std::binary_search(ref_pairs.begin(), ref_pairs.end(), std::make_pair(c.triangle_a, c.triangle_b)));
            ++hits;
        }
        if (!ref.colliding)
            CHECK(double(got.stats.primitive_tests) <
                  max_pair_fraction * double(a.mesh().num_triangles()) * double(b.mesh().num_triangles()));
    }
    return hits;
}

/// Const queries from four threads at once on shared models (MeshModel or RestrictedBoxtree): every thread
/// must get the serial answers (contact counts) on `poses` near poses, `reps` times over (fewer in reduced
/// runs); at least `min_hits` poses must collide so that the check means something.
template <class ModelA, class ModelB>
void check_concurrent_collide(const ModelA& a, const ModelB& b, int poses, int reps, int min_hits) {
    std::mt19937_64 rng(99);
    std::vector<Transform<double>> pose;
    for (int i = 0; i < poses; ++i) pose.push_back(near_pose<double>(rng, 2.0));
    std::vector<std::size_t> expected;
    for (const auto& p : pose) expected.push_back(collide(a, Transform<double>(), b, p, {ContactMode::all}).contacts.size());
    std::vector<int> mismatches(4, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (int rep = 0; rep < scaled(reps); ++rep)
                for (std::size_t i = 0; i < pose.size(); ++i)
                    if (collide(a, Transform<double>(), b, pose[i], {ContactMode::all}).contacts.size() != expected[i])
                        ++mismatches[t];
        });
    for (auto& th : threads) th.join();
    CHECK(mismatches == std::vector<int>(4, 0));
    CHECK(std::count_if(expected.begin(), expected.end(), [](std::size_t n) { return n > 0; }) > min_hits);
}

template <class BV> BV fit_all(const TriangleMesh<typename BV::Scalar>& m) {
    std::vector<Index> all(m.triangles.size());
    std::iota(all.begin(), all.end(), Index(0));
    return BV::fit(m, TriangleRange(all));
}

/// Outcomes of record_overlap() over many random configurations.
struct OverlapCounts {
    int configurations = 0, overlaps = 0, disjoint = 0, point_hits = 0;
};

/// A BV overlap test must be conservative: records overlap(a, b, rel) for B at `b_to_a`, then tries `tries`
/// sample points of b (`sample(p)` fills p in b's frame, or returns false to skip); one that lands in a
/// proves the volumes overlap, and the test must have said so.
template <class BV, class S, class Sample>
void record_overlap(const BV& a, const BV& b, const Transform<S>& b_to_a, Sample&& sample, OverlapCounts& c,
                    int tries = 64) {
    const bool o = overlap(a, b, BV::relative(b_to_a));
    ++c.configurations;
    o ? ++c.overlaps : ++c.disjoint;
    for (int k = 0; k < tries; ++k) {
        Vec3<S> p;
        if (!sample(p)) continue;
        if (a.contains(b_to_a * p)) {
            ++c.point_hits;
            REQUIRE(o);
            return;
        }
    }
}

/// Both answers occur often and sample points prove overlaps often: the test cannot pass by always
/// answering one way.
inline void check_hit_rates(const OverlapCounts& c) {
    CHECK(c.overlaps > c.configurations / 10);
    CHECK(c.disjoint > c.configurations / 10);
    CHECK(c.point_hits > c.configurations / 20);
}

}  // namespace cdkit::test
