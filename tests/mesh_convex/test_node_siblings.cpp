// The mesh–convex descent's two-child node test (NodeTester<Obb>::children_overlap, two SIMD lanes over
// bv/detail/obb_sibling_test.hpp's children_overlap_probe) against the same tester's one-node test (overlaps),
// on random boxes against a box, a capsule and an ellipsoid placed at random: the same answer per child for double
// trees and for float trees over double meshes (both compute in double), never "disjoint" where a point of the
// shape lies in the child, and the deeper-first flag only where both children overlap.
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/mesh_convex/shape_bound.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

using namespace cdkit;

namespace {

template <class S> Obb<S> random_node(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1, 1), h(0.02, 0.6);
    Obb<S> b;
    b.axes = test::random_rotation<double>(rng).template cast<S>();
    b.center = Vec3<S>(S(u(rng)), S(u(rng)), S(u(rng)));
    b.half = Vec3<S>(S(h(rng)), S(h(rng)), S(h(rng)));
    return b;
}

struct Counts {
    int overlapping = 0, disjoint = 0, witnessed = 0, ranked = 0;
};

/// n random sibling pairs against `shape` under random poses; `inside(p)` says whether a shape-frame point is in it,
/// `extent` the half extents of the shape's local box (the sample points' box).
template <class T, class C, class Inside>
Counts check_shape(const C& shape, const Vec3<double>& extent, Inside inside, int n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1), t(-1.2, 1.2);
    Counts k;
    for (int i = 0; i < n; ++i) {
        const Transform<double> pose(test::random_rotation<double>(rng), Vec3<double>(t(rng), t(rng), t(rng)));
        const detail::ShapeBound<double> bound = detail::make_shape_bound(shape, pose);
        REQUIRE(bound.finite);
        const detail::NodeTester<Obb<T>, double> tester(bound, shape);
        const Obb<T> c0 = random_node<T>(rng), c1 = random_node<T>(rng);
        const detail::SiblingOverlap s = tester.children_overlap(c0, c1);
        const bool o0 = tester.overlaps(c0), o1 = tester.overlaps(c1);
        REQUIRE(s.overlap[0] == o0);
        REQUIRE(s.overlap[1] == o1);
        REQUIRE((s.second_first ? o0 && o1 : true));
        k.ranked += s.second_first;
        k.overlapping += o0 + o1, k.disjoint += !o0 + !o1;
        // Conservative: a point of the shape inside a child means that child overlaps.
        for (int j = 0; j < 16; ++j) {
            const Vec3<double> local = extent.cwiseProduct(Vec3<double>(u(rng), u(rng), u(rng)));
            if (!inside(local)) continue;
            const Vec3<double> p = pose * local;
            for (int c = 0; c < 2; ++c) {
                const Obb<T>& node = c ? c1 : c0;
                const Vec3<double> q = node.axes.template cast<double>().transpose() * (p - node.center.template cast<double>());
                if ((q.cwiseAbs().array() <= node.half.template cast<double>().array()).all()) {
                    REQUIRE(s.overlap[c]);
                    ++k.witnessed;
                }
            }
        }
    }
    return k;
}

}  // namespace

TEMPLATE_TEST_CASE("mesh-convex descent: both children in one test answer as the one-node test", "[mesh_convex]", double,
                   float) {
    using T = TestType;  // the tree's scalar; the mesh and shape are double
    const int n = test::scaled(20000, 2000);
    const Box<double> box(Vec3<double>(0.5, 0.3, 0.7));
    const Capsule<double> capsule(0.3, 0.5);
    const Ellipsoid<double> ellipsoid(Vec3<double>(0.6, 0.35, 0.5));
    const Counts kb = check_shape<T>(box, box.half, [&](const Vec3<double>& p) { return (p.cwiseAbs().array() <= box.half.array()).all(); }, n, 1);
    const Counts kc = check_shape<T>(capsule, Vec3<double>(0.3, 0.3, 0.8), [&](const Vec3<double>& p) {
        const double z = std::clamp(p[2], -capsule.half_length, capsule.half_length);
        return (p - Vec3<double>(0, 0, z)).norm() <= capsule.radius;
    }, n, 2);
    const Counts ke = check_shape<T>(ellipsoid, ellipsoid.radii, [&](const Vec3<double>& p) {
        return p.cwiseQuotient(ellipsoid.radii).squaredNorm() <= 1;
    }, n, 3);
    for (const Counts& k : {kb, kc, ke}) {  // both answers often, points inside children, the ranking exercised
        CHECK(k.overlapping > n / 10);
        CHECK(k.disjoint > n / 10);
        CHECK(k.witnessed > n / 20);
        CHECK(k.ranked > n / 200);
    }
}
