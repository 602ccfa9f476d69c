#pragma once
/// \file Simultaneous descent of two trees (the classic recursive scheme of the lecture: test the two
/// nodes' volumes; if they overlap, descend into the larger one; at two leaves, hand the pair to a visitor),
/// written once for every tree of the family. A tree plugs in through a node concept (DescentTree: a root,
/// children, a leaf's triangles, which node to split first) and a pair test (DescentPair: the volume test of
/// two nodes under the relative transform B → A, computed once per query). Bvh<BV> of every bounding volume
/// (bvh/bvh_descent.hpp) and the restricted boxtree (bvh/boxtree_descent.hpp) are such trees; collide()
/// (query.hpp) and distance() (distance.hpp) descend them all through this file and DescentPair.

#include "cdkit/bvh/bvh.hpp"
#include "cdkit/bvh/bvh_descent.hpp"
#include "cdkit/bvh/mixed_descent.hpp"
#include "cdkit/core/collision_result.hpp"

#include <array>
#include <concepts>
#include <cstdint>
#include <utility>
#include <vector>

namespace cdkit {

/// A tree the simultaneous descent walks. A cursor names a node during one descent: its index, and whatever
/// the tree carries down (the restricted boxtree's implied box). Also `for_each_triangle(c, f)`: f(Index) for
/// a leaf's triangles until f returns false (returns false then).
template <class T>
concept DescentTree = std::copyable<typename T::Cursor> &&
                      requires(const T& t, const typename T::Cursor& c, typename T::Cursor& cc, std::uint32_t i) {
    { t.empty() } -> std::same_as<bool>;
    { t.root() } -> std::same_as<typename T::Cursor>;
    { t.is_leaf(c) } -> std::same_as<bool>;
    { t.child_count(c) } -> std::same_as<std::uint32_t>;  ///< 0 at a leaf, else 1 or 2
    { t.descend(cc, i) };  ///< moves the cursor to its i-th child
    { t.split_priority(c) < t.split_priority(c) } -> std::convertible_to<bool>;  ///< the larger is split first
};

/// Two trees and the test of a node pair under the relative transform B → A: `roots_overlap` (the first
/// pair), `children_overlap<DescendedA>` (a pair one of whose nodes just descended from a pair that
/// overlapped: a tree may test only what changed), and, when `tests_leaf_pairs`, `leaves_overlap` (one more
/// filter before a leaf pair is visited, counted as a BV test). distance() also needs `root_bound` and
/// `child_bounds` (see BvhDescentPair).
template <class P>
concept DescentPair = DescentTree<typename P::TreeA> && DescentTree<typename P::TreeB> &&
                      requires(const P& p, const typename P::TreeA::Cursor& x, const typename P::TreeB::Cursor& y) {
    { p.a } -> std::convertible_to<const typename P::TreeA&>;
    { p.b } -> std::convertible_to<const typename P::TreeB&>;
    { p.roots_overlap(x, y) } -> std::same_as<bool>;
    { p.template children_overlap<true>(x, y) } -> std::same_as<bool>;
    { p.template children_overlap<false>(x, y) } -> std::same_as<bool>;
    { p.leaves_overlap(x, y) } -> std::same_as<bool>;
    { P::tests_leaf_pairs } -> std::convertible_to<bool>;
};

/// A pair that tests both children of a split node at once and ranks them (Obb trees: bvh/bvh_descent.hpp):
/// `siblings_overlap<DescendA>(x, y)` for the children of x (DescendA) or of y against the other node,
/// returning `overlap[2]` and `second_first` (enter the second child first). Its trees' inner nodes have
/// two children.
template <class P>
concept SiblingDescentPair =
    DescentPair<P> && requires(const P& p, const typename P::TreeA::Cursor& x, const typename P::TreeB::Cursor& y) {
    { p.template siblings_overlap<true>(x, y).overlap[0] } -> std::convertible_to<bool>;
    { p.template siblings_overlap<false>(x, y).second_first } -> std::convertible_to<bool>;
};

namespace detail {
/// A stack that lives on the call stack while it fits (balanced trees of up to 2^60 leaves), and spills to
/// the heap only for degenerate trees.
template <class T, std::size_t N> class SmallStack {
public:
    void push(const T& v) {
        if (size_ < N) local_[size_] = v;
        else heap_.push_back(v);
        ++size_;
    }
    T pop() noexcept {
        --size_;
        if (size_ < N) return local_[size_];
        T v = heap_.back();
        heap_.pop_back();
        return v;
    }
    [[nodiscard]] bool empty() const noexcept { return size_ == 0; }

private:
    std::array<T, N> local_;
    std::vector<T> heap_;
    std::size_t size_ = 0;
};

/// Which node of the pair (x, y), not both leaves, the descent splits: the one that is not a leaf, else the
/// one of larger split_priority (A's on a tie). True: A's.
/// `xl`, `yl`: whether x, y are leaves.
template <DescentPair P>
[[nodiscard]] inline bool descends_a(const P& p, const typename P::TreeA::Cursor& x, const typename P::TreeB::Cursor& y,
                                     bool xl, bool yl) noexcept {
    return yl || (!xl && !(p.a.split_priority(x) < p.b.split_priority(y)));
}
}  // namespace detail

/// Visits every pair of leaves (one of each tree) whose nodes, and all of whose ancestors' pairs, overlap,
/// depth first (the first child's pairs before the second's). `visit(cursor_a, cursor_b)` returns false to
/// stop the traversal. Returns false when stopped early. Each child pair is tested when its parent pair is
/// split; the pair in hand goes on with its first overlapping child pair and the second waits on a stack.
template <DescentPair P, class Visitor>
bool traverse_overlapping_leaves(const P& pair, Visitor&& visit, TraversalStats& stats) {
    using CursorA = typename P::TreeA::Cursor;
    using CursorB = typename P::TreeB::Cursor;
    const auto& ta = pair.a;
    const auto& tb = pair.b;
    if (ta.empty() || tb.empty()) return true;
    struct Pair {
        CursorA a;
        CursorB b;
    };
    Pair p{ta.root(), tb.root()};
    ++stats.bv_tests;
    if (!pair.roots_overlap(p.a, p.b)) return true;
    detail::SmallStack<Pair, 128> stack;
    for (;;) {
        const bool xl = ta.is_leaf(p.a), yl = tb.is_leaf(p.b);
        if (xl && yl) {
            bool reached = true;
            if constexpr (P::tests_leaf_pairs) {
                ++stats.bv_tests;
                reached = pair.leaves_overlap(p.a, p.b);
            }
            if (reached) {
                ++stats.leaf_pairs;
                if (!visit(p.a, p.b)) return false;
            }
        } else {
            // Both child pairs are made and tested before either is entered. The pair in hand becomes the first
            // (its cursor moves to the child in place: the boxtree's implied box changes by one face, and a copy
            // of the whole pair right after that narrow store would stall on store forwarding), q1 the second.
            Pair q1 = p;
            bool ok0, ok1 = false;
            std::uint32_t n;
            if constexpr (SiblingDescentPair<P>) {
                // Both children in one test; the deeper-overlapping child first (a first contact sooner).
                const bool da = detail::descends_a(pair, p.a, p.b, xl, yl);
                const auto s = da ? pair.template siblings_overlap<true>(p.a, p.b)
                                  : pair.template siblings_overlap<false>(p.a, p.b);
                if (da) ta.descend(q1.a, 1), ta.descend(p.a, 0);
                else tb.descend(q1.b, 1), tb.descend(p.b, 0);
                ok0 = s.overlap[0], ok1 = s.overlap[1], n = 2;
                if (s.second_first) std::swap(p, q1);  // both overlap
            } else if (detail::descends_a(pair, p.a, p.b, xl, yl)) {
                n = ta.child_count(p.a);
                if (n == 2) ta.descend(q1.a, 1), ok1 = pair.template children_overlap<true>(q1.a, q1.b);
                ta.descend(p.a, 0);
                ok0 = pair.template children_overlap<true>(p.a, p.b);
            } else {
                n = tb.child_count(p.b);
                if (n == 2) tb.descend(q1.b, 1), ok1 = pair.template children_overlap<false>(q1.a, q1.b);
                tb.descend(p.b, 0);
                ok0 = pair.template children_overlap<false>(p.a, p.b);
            }
            stats.bv_tests += n;
            if (ok0) {
                if (ok1) stack.push(q1);
                continue;
            }
            if (ok1) {
                p = q1;
                continue;
            }
        }
        if (stack.empty()) break;
        p = stack.pop();
    }
    return true;
}

/// Visits every pair of leaves (one of `a`, one of `b`) whose BVs and all of whose ancestors' BVs overlap.
/// `rel` takes B's model frame into A's. `visit(leaf_a, leaf_b)` (the two BvhNodes) returns false to stop
/// the traversal. Returns false when stopped early.
template <class BV, class Visitor>
bool traverse_overlapping_leaves(const Bvh<BV>& a, const Bvh<BV>& b, const typename BV::Relative& rel,
                                 Visitor&& visit, TraversalStats& stats) {
    detail::BvhDescentPair<BV> pair(a, b, Transform<typename BV::Scalar>(), false);
    pair.rel = rel;
    return traverse_overlapping_leaves(
        pair, [&](std::uint32_t x, std::uint32_t y) { return visit(a.nodes()[x], b.nodes()[y]); }, stats);
}

}  // namespace cdkit
