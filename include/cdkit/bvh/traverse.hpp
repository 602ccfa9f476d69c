#pragma once
/// \file Simultaneous descent of two BVHs (the classic recursive scheme of the lecture: test the two
/// nodes' BVs; if they overlap, descend into the larger one; at two leaves, hand the pair to a visitor).
/// Tree B's volumes are tested where they are, through the relative transform B→A computed once per query.

#include "cdkit/bvh/bvh.hpp"
#include "cdkit/core/collision_result.hpp"

#include <array>
#include <cstdint>

namespace cdkit {

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
}  // namespace detail

/// Visits every pair of leaves (one of `a`, one of `b`) whose BVs and all of whose ancestors' BVs overlap.
/// `rel` takes B's model frame into A's. `visit(leaf_a, leaf_b)` returns false to stop the traversal.
/// Returns false when stopped early.
template <class BV, class Visitor>
bool traverse_overlapping_leaves(const Bvh<BV>& a, const Bvh<BV>& b, const typename BV::Relative& rel,
                                 Visitor&& visit, TraversalStats& stats) {
    if (a.empty() || b.empty()) return true;
    const auto& na = a.nodes();
    const auto& nb = b.nodes();
    struct Pair { std::uint32_t a, b; };
    detail::SmallStack<Pair, 128> stack;
    stack.push({0, 0});
    while (!stack.empty()) {
        const Pair p = stack.pop();
        const BvhNode<BV>& x = na[p.a];
        const BvhNode<BV>& y = nb[p.b];
        ++stats.bv_tests;
        if (!overlap(x.bv, y.bv, rel)) continue;
        const bool xl = x.is_leaf(), yl = y.is_leaf();
        if (xl && yl) {
            ++stats.leaf_pairs;
            if (!visit(x, y)) return false;
            continue;
        }
        // Descend the larger volume (or the one that is not a leaf).
        if (yl || (!xl && x.bv.size() >= y.bv.size())) {
            stack.push({x.first + 1, p.b});
            stack.push({x.first, p.b});
        } else {
            stack.push({p.a, y.first + 1});
            stack.push({p.a, y.first});
        }
    }
    return true;
}

}  // namespace cdkit
