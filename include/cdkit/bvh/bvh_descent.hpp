#pragma once
/// \file Bvh<BV> as a tree of the simultaneous descent (bvh/traverse.hpp): cursors are node indices, each node
/// stores its volume, and a node pair's test is the BV's own overlap() or distance_lower_bound() under the
/// relative transform, in the BV's scalar (float volumes over a double mesh test in float, see MeshModel); an Rss
/// tree's collide() tests the children below its roots as rounded boxes in the two-lane test (siblings_overlap).

#include "cdkit/bv/bv_distance.hpp"
#include "cdkit/bv/detail/distance_rss_pair.hpp"
#include "cdkit/bv/detail/obb_sibling_test.hpp"
#include "cdkit/bv/rounded_box.hpp"
#include "cdkit/bvh/bvh.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/core/inlining.hpp"

#include <algorithm>
#include <concepts>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace cdkit {

/// A volume distance() can descend: a free distance_lower_bound(a, b, rel, cutoff) (every BV of the family has one).
template <class BV>
concept HasDistanceLowerBound = requires(const BV& x, const typename BV::Relative& rel, typename BV::Scalar s) {
    { distance_lower_bound(x, x, rel, s) } -> std::convertible_to<typename BV::Scalar>;
};

namespace detail {

/// Volumes with transformed(bv, R, t) and distance_lower_bound_same_frame (Rss): when one node is tested
/// against both children of the other, it is moved into their frame once instead of once per child.
template <class BV>
concept MovableDistanceBound = requires(const BV& b, const Mat3<typename BV::Scalar>& R, const Vec3<typename BV::Scalar>& t,
                                        typename BV::Scalar s) {
    { transformed(b, R, t) } -> std::same_as<BV>;
    { distance_lower_bound_same_frame(b, b, s, s) } -> std::same_as<typename BV::Scalar>;
};

/// Lower bounds of two sibling volumes a0, a1 against b (all in one frame): the Rss bounds in two SIMD lanes
/// (bv/detail/distance_rss_pair.hpp), other volumes one at a time.
template <class BV, class B>
inline void children_lower_bounds(const BV& a0, const BV& a1, const BV& b, B slack, B cutoff, B out[2]) noexcept {
    if constexpr (std::is_same_v<BV, Rss<B>>) {
        rss_pair_lower_bounds(a0, a1, b, slack, out);  // always the full bound: no cutoff
    } else {
        out[0] = distance_lower_bound_same_frame(a0, b, slack, cutoff);
        out[1] = distance_lower_bound_same_frame(a1, b, slack, cutoff);
    }
}

/// One Bvh seen by the descent: a cursor is a node index; inner nodes have two children at `first`, `first + 1`.
template <class BV> struct BvhDescentTree {
    using Cursor = std::uint32_t;
    const BvhNode<BV>* nodes = nullptr;
    const Index* order = nullptr;
    bool is_empty = true;

    explicit BvhDescentTree(const Bvh<BV>& t) noexcept
        : nodes(t.nodes().data()), order(t.triangle_order().data()), is_empty(t.empty()) {}
    [[nodiscard]] bool empty() const noexcept { return is_empty; }
    [[nodiscard]] Cursor root() const noexcept { return 0; }
    [[nodiscard]] const BvhNode<BV>& node(Cursor c) const noexcept { return nodes[c]; }
    [[nodiscard]] bool is_leaf(Cursor c) const noexcept { return nodes[c].is_leaf(); }
    [[nodiscard]] std::uint32_t child_count(Cursor c) const noexcept { return nodes[c].is_leaf() ? 0u : 2u; }
    void descend(Cursor& c, std::uint32_t i) const noexcept { c = nodes[c].first + i; }
    /// The descent splits the node of larger volume size first.
    [[nodiscard]] auto split_priority(Cursor c) const noexcept { return nodes[c].bv.size(); }
    /// Calls f(triangle) for the leaf's triangles until f returns false; returns false when stopped.
    template <class F> bool for_each_triangle(Cursor c, F&& f) const {
        const BvhNode<BV>& n = nodes[c];
        for (std::uint32_t i = n.first; i < n.first + n.count; ++i)
            if (!f(order[i])) return false;
        return true;
    }
};

/// Both children of the node the descent splits (x's in tree `ta` when DescendA, else y's in `tb`) against the
/// other node, every volume as its rounded box (bv/rounded_box.hpp), in one two-lane test (bv/detail/
/// obb_sibling_test.hpp), with the order to enter them. `rel` takes B's frame to A's. Boxes test as they are;
/// where a volume has a ball (Rss, sphere), the rounded test adds the radii once per axis, which is tighter than
/// the enclosing boxes (they pay the radius along every box axis at once) for one more addition per axis.
template <bool DescendA, class BVA, class BVB, class S = typename BVA::Scalar>
[[nodiscard]] CDKIT_ALWAYS_INLINE SiblingOverlap rounded_siblings_overlap(const BvhDescentTree<BVA>& ta,
                                                                         const BvhDescentTree<BVB>& tb, std::uint32_t x,
                                                                         std::uint32_t y,
                                                                         const typename Obb<S>::Relative& rel) noexcept {
    constexpr bool rounded = has_core_radius<BVA> || has_core_radius<BVB>;
    const auto radii = [](const auto& c0, const auto& c1, const auto& o) CDKIT_LAMBDA_INLINE {
        return Lanes2::of(radius_sum_up(core_radius(c0), core_radius(o)),
                          radius_sum_up(core_radius(c1), core_radius(o)));
    };
    if constexpr (DescendA) {
        const std::uint32_t c = ta.nodes[x].first;
        const BVA &c0 = ta.nodes[c].bv, &c1 = ta.nodes[c + 1].bv;
        const BVB& o = tb.nodes[y].bv;
        if constexpr (rounded)
            return children_overlap_box<S, Lanes2, true>(core_box(c0), core_box(c1), core_box(o), rel,
                                                         radii(c0, c1, o));
        else return children_overlap_box(core_box(c0), core_box(c1), core_box(o), rel);
    } else {
        const std::uint32_t c = tb.nodes[y].first;
        const BVA& o = ta.nodes[x].bv;
        const BVB &c0 = tb.nodes[c].bv, &c1 = tb.nodes[c + 1].bv;
        if constexpr (rounded)
            return box_overlap_children<S, Lanes2, true>(core_box(o), core_box(c0), core_box(c1), rel,
                                                         radii(c0, c1, o));
        else return box_overlap_children(core_box(o), core_box(c0), core_box(c1), rel);
    }
}

/// Two Bvhs of one BV under the relative transform B → A (BV::Relative, computed once per query).
template <class BV> struct BvhDescentPair {
    using TreeA = BvhDescentTree<BV>;
    using TreeB = BvhDescentTree<BV>;
    using B = typename BV::Scalar;
    /// No extra test at leaf pairs: the leaves' volumes were tested on the way down.
    static constexpr bool tests_leaf_pairs = false;

    TreeA a;
    TreeB b;
    typename BV::Relative rel;  ///< B's frame → A's
    typename BV::Relative inv;  ///< A's frame → B's: set for distance queries on MovableDistanceBound volumes

    template <class S>
    BvhDescentPair(const Bvh<BV>& ta, const Bvh<BV>& tb, const Transform<S>& b_to_a, bool for_distance) noexcept
        : a(ta), b(tb), rel(BV::relative(b_to_a.template cast<B>())), inv(rel) {
        if constexpr (MovableDistanceBound<BV>)
            if (for_distance) inv = BV::relative(b_to_a.inverse().template cast<B>());
    }

    [[nodiscard]] bool roots_overlap(std::uint32_t x, std::uint32_t y) const noexcept { return test(x, y); }
    /// A child pair: x (DescendedA) or y just descended from a pair that overlapped.
    template <bool DescendedA> [[nodiscard]] bool children_overlap(std::uint32_t x, std::uint32_t y) const noexcept {
        return test(x, y);
    }
    [[nodiscard]] bool leaves_overlap(std::uint32_t, std::uint32_t) const noexcept { return true; }

    /// The volumes' own overlap(), with everything it calls inlined into this one function: the traversal
    /// calls it from four places, and GCC then stopped inlining Obb's overlap() there and called it and
    /// boxes_disjoint() apart (13 % slower Obb queries on the bunny). Small tests (spheres, Aabb) are still
    /// inlined into the traversal whole.
    [[nodiscard]] CDKIT_FLATTEN bool test(std::uint32_t x, std::uint32_t y) const noexcept {
        return overlap(a.nodes[x].bv, b.nodes[y].bv, rel);
    }

    /// Obb trees: both children of the node the descent splits (x's when DescendA, else y's) against the
    /// other node, in one two-lane test (bv/detail/obb_sibling_test.hpp), with the order to enter them.
    /// Forced inline: in a large translation unit (the Python module's) GCC kept it out of line, one call per
    /// split. Rss trees take the same test on their volumes as rounded boxes (rounded_siblings_overlap): the Rss's own
    /// overlap is a distance bound (rectangles, then spheres), several times the box test's cost, and the
    /// children's ranking finds a first contact sooner (on the bunny at P1 d = 0.2: 6,032 → 3,134 node tests,
    /// 11.9 → 2.2 µs per first-contact query; results/rss_collide_ab.csv for the benchmark).
    template <bool DescendA>
        requires std::same_as<BV, Obb<B>> || std::same_as<BV, Rss<B>>
    [[nodiscard]] CDKIT_ALWAYS_INLINE SiblingOverlap siblings_overlap(std::uint32_t x, std::uint32_t y) const noexcept {
        return rounded_siblings_overlap<DescendA>(a, b, x, y, rel);
    }

    /// Lower bound on the distance of the two roots.
    [[nodiscard]] B root_bound(std::uint32_t x, std::uint32_t y) const noexcept {
        static_assert(HasDistanceLowerBound<BV>,
                      "distance(): the BV needs a free distance_lower_bound(a, b, rel, cutoff) (bv/bv_distance.hpp)");
        return distance_lower_bound(a.nodes[x].bv, b.nodes[y].bv, rel);
    }
    /// The open pairs of `it`'s split node's children (A's when DescendA) with their bounds; returns how many
    /// (two). `th`: pairs whose bound reaches it are pruned; the scalar bounds stop early once they know.
    template <bool DescendA, class Item, class S>
    std::uint32_t child_bounds(const Item& it, S th, Item& c0, Item& c1) const noexcept {
        const BvhNode<BV>& x = a.nodes[it.a];
        const BvhNode<BV>& y = b.nodes[it.b];
        // Only an early-out hint to the scalar bounds, finite even before the first triangle pair: they stop
        // once a pair is known to be pruned or kept (see rectangle_gap). The Rss pair bound ignores it.
        const auto bv_th = static_cast<B>(std::min<S>(th, S(std::numeric_limits<B>::max())));
        if constexpr (DescendA) {
            if constexpr (MovableDistanceBound<BV>) {
                // y moved into A's frame once for both children of x.
                const BV moved = transformed(y.bv, rel.R, rel.t);
                B bound[2];
                children_lower_bounds(a.nodes[x.first].bv, a.nodes[x.first + 1].bv, moved, rel.slack, bv_th, bound);
                c0 = {x.first, it.b, bound[0]};
                c1 = {x.first + 1, it.b, bound[1]};
            } else {
                c0 = {x.first, it.b, distance_lower_bound(a.nodes[x.first].bv, y.bv, rel, bv_th)};
                c1 = {x.first + 1, it.b, distance_lower_bound(a.nodes[x.first + 1].bv, y.bv, rel, bv_th)};
            }
        } else {
            if constexpr (MovableDistanceBound<BV>) {
                // x moved into B's frame once for both children of y.
                const BV moved = transformed(x.bv, inv.R, inv.t);
                B bound[2];
                children_lower_bounds(b.nodes[y.first].bv, b.nodes[y.first + 1].bv, moved, inv.slack, bv_th, bound);
                c0 = {it.a, y.first, bound[0]};
                c1 = {it.a, y.first + 1, bound[1]};
            } else {
                c0 = {it.a, y.first, distance_lower_bound(x.bv, b.nodes[y.first].bv, rel, bv_th)};
                c1 = {it.a, y.first + 1, distance_lower_bound(x.bv, b.nodes[y.first + 1].bv, rel, bv_th)};
            }
        }
        return 2;
    }
};

/// The descent pair of two mesh models, `b_to_a` taking B's model frame into A's.
template <class BV, class M>
[[nodiscard]] BvhDescentPair<BV> descent_pair(const MeshModel<BV, M>& a, const MeshModel<BV, M>& b,
                                              const Transform<M>& b_to_a, bool for_distance = false) noexcept {
    return BvhDescentPair<BV>(a.bvh(), b.bvh(), b_to_a, for_distance);
}

}  // namespace detail

}  // namespace cdkit
