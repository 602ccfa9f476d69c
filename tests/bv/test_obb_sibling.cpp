// The two-lane OBB test of sibling boxes (bv/detail/obb_sibling_test.hpp) against the scalar 15-axis test
// (bv/obb.hpp's overlap) on random boxes: the same answer per child, SSE2 lanes and plain lanes bit for bit,
// never "disjoint" where a point lies in both boxes, and the deeper child ranked first.
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/bv/detail/obb_sibling_test.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace cdkit;

namespace {

template <class S> Obb<S> random_box(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1, 1), h(0.02, 0.6);
    Obb<S> b;
    b.axes = test::random_rotation<S>(rng);
    b.center = Vec3<S>(S(u(rng)), S(u(rng)), S(u(rng)));
    b.half = Vec3<S>(S(h(rng)), S(h(rng)), S(h(rng)));
    return b;
}

/// A point of box b (its own frame) from three uniform coordinates in [-1, 1].
template <class S> Vec3<S> point_in(const Obb<S>& b, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    return b.center + b.axes * b.half.cwiseProduct(Vec3<S>(S(u(rng)), S(u(rng)), S(u(rng))));
}

template <class S> bool same(const detail::SiblingOverlap& x, const detail::SiblingOverlap& y) {
    return x.overlap[0] == y.overlap[0] && x.overlap[1] == y.overlap[1] && x.second_first == y.second_first;
}

}  // namespace

TEMPLATE_TEST_CASE("OBB sibling test: each lane answers as the scalar 15-axis test", "[bv]", float, double) {
    using S = TestType;
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    const int n = test::scaled(20000, 2000);
    int overlapping = 0, disjoint = 0, witnessed = 0, ranked = 0;
    for (int i = 0; i < n; ++i) {
        const Obb<S> c0 = random_box<S>(rng), c1 = random_box<S>(rng), other = random_box<S>(rng);
        const Transform<S> b_to_a(test::random_rotation<S>(rng), Vec3<S>(S(u(rng)), S(u(rng)), S(u(rng))));
        const auto rel = Obb<S>::relative(b_to_a);
        // Children of A's node against B's box, and A's box against children of B's node.
        const detail::SiblingOverlap down_a = detail::children_overlap_box(c0, c1, other, rel);
        const detail::SiblingOverlap down_b = detail::box_overlap_children(other, c0, c1, rel);
        const bool a0 = overlap(c0, other, rel), a1 = overlap(c1, other, rel);
        const bool b0 = overlap(other, c0, rel), b1 = overlap(other, c1, rel);
        REQUIRE(down_a.overlap[0] == a0);
        REQUIRE(down_a.overlap[1] == a1);
        REQUIRE(down_b.overlap[0] == b0);
        REQUIRE(down_b.overlap[1] == b1);
        REQUIRE((down_a.second_first ? a0 && a1 : true));
        REQUIRE((down_b.second_first ? b0 && b1 : true));
        ranked += down_a.second_first + down_b.second_first;
        overlapping += a0 + a1, disjoint += !a0 + !a1;
        // Plain lanes (the build without SSE2) give the same bits.
        REQUIRE(same<S>(down_a, detail::children_overlap_box<S, detail::ScalarLanes2>(c0, c1, other, rel)));
        REQUIRE(same<S>(down_b, detail::box_overlap_children<S, detail::ScalarLanes2>(other, c0, c1, rel)));
        // Conservative: a point of B's box (in A's frame) inside a child of A means that child overlaps.
        for (int k = 0; k < 8; ++k) {
            const Vec3<S> p = b_to_a * point_in(other, rng);
            if (c0.contains(p)) {
                REQUIRE(down_a.overlap[0]);
                ++witnessed;
            }
            if (c1.contains(p)) {
                REQUIRE(down_a.overlap[1]);
                ++witnessed;
            }
        }
    }
    // Both answers occur often, and the ranking is exercised.
    CHECK(overlapping > n / 10);
    CHECK(disjoint > n / 10);
    CHECK(witnessed > n / 20);
    CHECK(ranked > n / 200);
}

TEMPLATE_TEST_CASE("OBB sibling test: the child that overlaps deeper comes first", "[bv]", float, double) {
    using S = TestType;
    // The other box: a unit cube at the origin. One child sits at its centre, the other straddles its +x face.
    Obb<S> other;
    other.half = Vec3<S>::Constant(S(1));
    other.center = Vec3<S>::Zero();
    Obb<S> deep = other, shallow = other;
    deep.half = Vec3<S>::Constant(S(0.5));
    shallow.half = Vec3<S>::Constant(S(0.5));
    shallow.center = Vec3<S>(S(1.4), S(0), S(0));  // overlaps the cube by 0.1 along x
    std::mt19937_64 rng(5);
    for (int i = 0; i < 50; ++i) {
        const Transform<S> b_to_a(test::random_rotation<S>(rng), Vec3<S>::Zero());
        // The cube turned by b_to_a into A's frame: the children (in A's frame) are turned with it, so that
        // they sit against it as built.
        Obb<S> d = deep, s = shallow;
        d.axes = b_to_a.R, d.center = b_to_a.R * deep.center;
        s.axes = b_to_a.R, s.center = b_to_a.R * shallow.center;
        const auto rel = Obb<S>::relative(b_to_a);
        const detail::SiblingOverlap first_shallow = detail::children_overlap_box(s, d, other, rel);
        const detail::SiblingOverlap first_deep = detail::children_overlap_box(d, s, other, rel);
        REQUIRE(first_shallow.overlap[0]);
        REQUIRE(first_shallow.overlap[1]);
        REQUIRE(first_shallow.second_first);
        REQUIRE_FALSE(first_deep.second_first);
        // And with the cube split instead: B's children (deep, shallow as B boxes) against A's cube.
        const auto rel_identity = Obb<S>::relative(Transform<S>::identity());
        REQUIRE(detail::box_overlap_children(other, shallow, deep, rel_identity).second_first);
        REQUIRE_FALSE(detail::box_overlap_children(other, deep, shallow, rel_identity).second_first);
    }
}
