#pragma once
/// \file Mixed trees: two mesh models of different bounding volumes (a robot link's MeshModel<Obb> against an
/// environment's MeshModel<Rss>, say) descend together. Every node is seen as the oriented box that encloses its
/// volume (`enclosing_obb`), and a node pair is tested as two boxes: the 15-axis test of Gottschalk, Lin, Manocha
/// ("OBBTree", SIGGRAPH 1996) for collide(), the box gap for distance(). The boxes contain the volumes, so no pair
/// the volumes' own test would keep is dropped, and the triangles decide as in every descent: the answers are
/// those of the brute force (tests/query/test_mixed_trees.cpp). What it costs: the box of a sphere or an Rss is
/// looser than the volume, and an Aabb node pays the rotated-box test; two trees of one BV keep their own test.

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/bv_distance.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/rss.hpp"
#include "cdkit/bv/sphere.hpp"
#include "cdkit/bvh/bvh_descent.hpp"
#include "cdkit/bvh/mesh_model.hpp"

#include <concepts>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace cdkit {

namespace detail {
/// Half extents grown by a few ulps: a sum such as an Rss's half length plus its radius may round down, and the
/// box must contain the volume.
template <class S> [[nodiscard]] inline Vec3<S> grown_half(const Vec3<S>& h) noexcept {
    return h * (S(1) + S(4) * std::numeric_limits<S>::epsilon());
}
}  // namespace detail

/// The oriented box around a bounding volume, in the volume's frame. Empty volumes give empty boxes.
template <class S>
[[nodiscard]] inline Obb<S> enclosing_obb(const Obb<S>& b) noexcept {
    return b;
}

template <class S>
[[nodiscard]] inline Obb<S> enclosing_obb(const Aabb<S>& b) noexcept {
    Obb<S> o;
    o.center = b.center;
    o.half = b.half;
    return o;
}

/// A rectangle swept by a ball: the rectangle's frame, its half lengths plus the radius, the radius across.
template <class S>
[[nodiscard]] inline Obb<S> enclosing_obb(const Rss<S>& b) noexcept {
    Obb<S> o;
    if (b.is_empty()) return o;
    o.axes = b.axes;
    o.center = b.center;
    o.half = detail::grown_half(Vec3<S>(b.half[0] + b.radius, b.half[1] + b.radius, b.radius));
    return o;
}

template <class S>
[[nodiscard]] inline Obb<S> enclosing_obb(const BoundingSphere<S>& b) noexcept {
    Obb<S> o;
    if (b.is_empty()) return o;
    o.center = b.center;
    o.half = Vec3<S>::Constant(b.radius);
    return o;
}

/// A k-DOP's first three slabs are the coordinate axes' (kdop_directions): their box.
template <class S, int K>
[[nodiscard]] inline Obb<S> enclosing_obb(const Kdop<S, K>& b) noexcept {
    Obb<S> o;
    if (b.is_empty()) return o;
    const Vec3<S> lo(b.lo(0), b.lo(1), b.lo(2)), hi(b.hi(0), b.hi(1), b.hi(2));
    o.center = (lo + hi) * S(0.5);
    o.half = detail::grown_half(Vec3<S>((hi - lo) * S(0.5)));
    return o;
}

/// Volumes that enclosing_obb() turns into a box.
template <class BV>
concept HasEnclosingObb = requires(const BV& b) {
    { enclosing_obb(b) } -> std::same_as<Obb<typename BV::Scalar>>;
};

namespace detail {

/// Two Bvhs of different volumes (one scalar) under the relative transform B → A, every node tested as its
/// enclosing box (see the file comment).
template <class BVA, class BVB> struct MixedDescentPair {
    using TreeA = BvhDescentTree<BVA>;
    using TreeB = BvhDescentTree<BVB>;
    using B = typename BVA::Scalar;
    static constexpr bool tests_leaf_pairs = false;

    TreeA a;
    TreeB b;
    typename Obb<B>::Relative rel;  ///< B's frame → A's

    template <class S>
    MixedDescentPair(const Bvh<BVA>& ta, const Bvh<BVB>& tb, const Transform<S>& b_to_a) noexcept
        : a(ta), b(tb), rel(Obb<B>::relative(b_to_a.template cast<B>())) {}

    [[nodiscard]] bool test(std::uint32_t x, std::uint32_t y) const noexcept {
        return overlap(enclosing_obb(a.nodes[x].bv), enclosing_obb(b.nodes[y].bv), rel);
    }
    [[nodiscard]] bool roots_overlap(std::uint32_t x, std::uint32_t y) const noexcept { return test(x, y); }
    template <bool DescendedA> [[nodiscard]] bool children_overlap(std::uint32_t x, std::uint32_t y) const noexcept {
        return test(x, y);
    }
    [[nodiscard]] bool leaves_overlap(std::uint32_t, std::uint32_t) const noexcept { return true; }

    [[nodiscard]] B bound(std::uint32_t x, std::uint32_t y, B cutoff = std::numeric_limits<B>::infinity()) const noexcept {
        return distance_lower_bound(enclosing_obb(a.nodes[x].bv), enclosing_obb(b.nodes[y].bv), rel, cutoff);
    }
    [[nodiscard]] B root_bound(std::uint32_t x, std::uint32_t y) const noexcept { return bound(x, y); }
    /// As BvhDescentPair::child_bounds: the two children of the node the descent splits, with their bounds.
    template <bool DescendA, class Item, class S>
    std::uint32_t child_bounds(const Item& it, S th, Item& c0, Item& c1) const noexcept {
        const auto cut = static_cast<B>(std::min<S>(th, S(std::numeric_limits<B>::max())));
        if constexpr (DescendA) {
            const std::uint32_t c = a.nodes[it.a].first;
            c0 = {c, it.b, bound(c, it.b, cut)};
            c1 = {c + 1, it.b, bound(c + 1, it.b, cut)};
        } else {
            const std::uint32_t c = b.nodes[it.b].first;
            c0 = {it.a, c, bound(it.a, c, cut)};
            c1 = {it.a, c + 1, bound(it.a, c + 1, cut)};
        }
        return 2;
    }
};

/// The descent pair of two mesh models of different volumes. Their volumes must share a scalar (a float-over-
/// double tree against a double one does not mix) and have a box (HasEnclosingObb).
template <class BVA, class BVB, class M>
    requires(!std::same_as<BVA, BVB>)
[[nodiscard]] MixedDescentPair<BVA, BVB> descent_pair(const MeshModel<BVA, M>& a, const MeshModel<BVB, M>& b,
                                                      const Transform<M>& b_to_a, bool = false) noexcept {
    static_assert(std::same_as<typename BVA::Scalar, typename BVB::Scalar>,
                  "collide()/distance() on mixed trees: both models' bounding volumes need one scalar type "
                  "(e.g. Obb<double> with Rss<double>, not with Rss<float>)");
    static_assert(HasEnclosingObb<BVA> && HasEnclosingObb<BVB>,
                  "collide()/distance() on mixed trees: each volume needs an enclosing_obb() (bvh/mixed_descent.hpp)");
    return MixedDescentPair<BVA, BVB>(a.bvh(), b.bvh(), b_to_a);
}

}  // namespace detail

}  // namespace cdkit
