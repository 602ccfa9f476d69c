// The two-lane OBB test of sibling boxes (bv/detail/obb_sibling_test.hpp) against the scalar 15-axis test
// (bv/obb.hpp's overlap) on random boxes: the same answer per child, SSE2 lanes and plain lanes bit for bit,
// never "disjoint" where a point lies in both boxes, and the deeper child ranked first. The rounded form (Rss
// trees: rectangles grown by their radii) never "disjoint" where a point lies in both volumes (point-in-Rss by its
// own closed form), and no looser than the enclosing boxes.
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/bv/detail/obb_sibling_test.hpp"
#include "cdkit/bv/enclosing_obb.hpp"
#include "cdkit/bv/rounded_box.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <type_traits>
#include <utility>

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

template <class S> Rss<S> random_sibling_rss(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1, 1), h(0.0, 0.6), r(0.005, 0.3);
    Rss<S> b;
    b.axes = test::random_rotation<S>(rng);
    b.center = Vec3<S>(S(u(rng)), S(u(rng)), S(u(rng)));
    b.half = typename Rss<S>::Vec2(S(h(rng)), S(h(rng)));
    b.radius = S(r(rng));
    return b;
}

/// A point of Rss b (world frame): a point of its rectangle plus one of its ball, drawn by rejection.
template <class S> Vec3<double> point_in_rss(const Rss<S>& b, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    Vec3<double> ball;
    do ball = Vec3<double>(u(rng), u(rng), u(rng));
    while (ball.squaredNorm() > 1);
    const Vec3<double> on_rect(double(b.half[0]) * u(rng), double(b.half[1]) * u(rng), 0.0);
    return b.center.template cast<double>() + b.axes.template cast<double>() * on_rect + double(b.radius) * ball;
}

/// Whether world point p lies in Rss b: its distance to the rectangle, in the rectangle's frame, is at most the radius.
template <class S> bool rss_holds(const Rss<S>& b, const Vec3<double>& p) {
    const Vec3<double> q = b.axes.template cast<double>().transpose() * (p - b.center.template cast<double>());
    const double dx = std::max(std::abs(q[0]) - double(b.half[0]), 0.0);
    const double dy = std::max(std::abs(q[1]) - double(b.half[1]), 0.0);
    return dx * dx + dy * dy + q[2] * q[2] <= double(b.radius) * double(b.radius) * (1 - 1e-9);
}

// A box is its own core (no copy); any other volume with an enclosing box gets that box as its core.
static_assert(std::is_same_v<decltype(core_box(std::declval<const Obb<double>&>())), const Obb<double>&>);
static_assert(std::is_same_v<decltype(core_box(std::declval<const Kdop<double, 18>&>())), Obb<double>>);

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

TEMPLATE_TEST_CASE("Rounded sibling test: never disjoint where two RSS share a point, never looser than their boxes",
                   "[bv]", float, double) {
    using S = TestType;
    using L = detail::Lanes2;
    std::mt19937_64 rng(77);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    const int n = test::scaled(20000, 2000);
    int witnessed = 0, tighter = 0, disjoint = 0;
    for (int i = 0; i < n; ++i) {
        const Rss<S> c0 = random_sibling_rss<S>(rng), c1 = random_sibling_rss<S>(rng);
        const Rss<S> other = random_sibling_rss<S>(rng);
        const Transform<S> b_to_a(test::random_rotation<S>(rng), Vec3<S>(S(u(rng)), S(u(rng)), S(u(rng))));
        const auto rel = Obb<S>::relative(b_to_a);
        const L round =
            L::of(detail::radius_sum_up(c0.radius, other.radius), detail::radius_sum_up(c1.radius, other.radius));
        // Children of A's node against B's volume, and A's volume against children of B's node.
        const detail::SiblingOverlap down_a = detail::children_overlap_box<S, L, true>(
            core_box(c0), core_box(c1), core_box(other), rel, round);
        const detail::SiblingOverlap down_b = detail::box_overlap_children<S, L, true>(
            core_box(other), core_box(c0), core_box(c1), rel, round);
        const detail::SiblingOverlap boxes_a = detail::children_overlap_box(enclosing_obb(c0), enclosing_obb(c1),
                                                                           enclosing_obb(other), rel);
        const Rss<S>* child[2] = {&c0, &c1};
        const Transform<double> to_a = b_to_a.template cast<double>(), to_b = to_a.inverse();
        for (int k = 0; k < 2; ++k) {
            INFO("pair " << i << ", child " << k);
            // Overlap witnessed by a point in both: a point of `in_a` (A's frame) in `in_b` (B's frame), or one of
            // in_b in in_a.
            const auto share = [&](const Rss<S>& in_a, const Rss<S>& in_b) {
                for (int t = 0; t < 24; ++t) {
                    const Vec3<double> p = point_in_rss(in_a, rng), q = point_in_rss(in_b, rng);
                    if (rss_holds(in_b, to_b.R * p + to_b.t) || rss_holds(in_a, to_a.R * q + to_a.t)) return true;
                }
                return false;
            };
            if (share(*child[k], other)) {  // A's children against B's volume
                ++witnessed;
                REQUIRE(down_a.overlap[k]);
            }
            if (share(other, *child[k])) REQUIRE(down_b.overlap[k]);  // A's volume against B's children
            // The boxes contain the volumes: where the rounded test keeps a child, the boxes keep it too.
            if (down_a.overlap[k]) REQUIRE(boxes_a.overlap[k]);
            tighter += boxes_a.overlap[k] && !down_a.overlap[k];
            disjoint += !down_a.overlap[k];
        }
    }
    CHECK(witnessed > n / 20);
    CHECK(disjoint > n / 20);
    CHECK(tighter > 0);
    std::printf("rounded sibling test: %d shared points, %d disjoint, %d culled that the boxes keep\n", witnessed,
                disjoint, tighter);
}
