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

/// Checks collide() on the two models against brute force over `poses` random poses; returns the number of
/// colliding poses (the caller checks the hit rate).
template <class BV, class M>
int collide_equals_brute_force(const MeshModel<BV, M>& a, const MeshModel<BV, M>& b, int poses, double reach, unsigned seed) {
    using S = M;
    std::mt19937_64 rng(seed);
    int hits = 0;
    CollisionRequest all;
    all.mode = ContactMode::all;
    for (int i = 0; i < poses; ++i) {
        const Transform<S> pa = near_pose<S>(rng, 0.5), pb = near_pose<S>(rng, reach);
        const auto ref = collide_brute_force(a.mesh(), pa, b.mesh(), pb, all);
        const auto got = collide(a, pa, b, pb, all);
        REQUIRE(got.colliding == ref.colliding);
        REQUIRE(contact_pairs(got) == contact_pairs(ref));
        const auto first = collide(a, pa, b, pb);
        REQUIRE(first.colliding == ref.colliding);
        if (first.colliding) ++hits;
        // BV culling must do real work.
        if (!ref.colliding) CHECK(got.stats.primitive_tests < a.mesh().num_triangles() * b.mesh().num_triangles());
    }
    return hits;
}

/// Const queries from four threads at once on shared models (MeshModel or RestrictedBoxtree): every thread
/// must get the serial answers (contact counts) on `poses` near poses, `reps` times over; at least
/// `min_hits` poses must collide so that the check means something.
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
            for (int rep = 0; rep < reps; ++rep)
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

}  // namespace cdkit::test
