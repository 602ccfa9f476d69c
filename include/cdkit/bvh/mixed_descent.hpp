#pragma once
/// \file Mixed trees: two mesh models of different bounding volumes (a robot link's MeshModel<Obb> against an
/// environment's MeshModel<Rss>, say) descend together. Every node is seen as the oriented box that encloses its
/// volume (`enclosing_obb`), and a node pair is tested as two boxes: the 15-axis test of Gottschalk, Lin, Manocha
/// ("OBBTree", SIGGRAPH 1996) for collide()'s roots, the box gap for distance(); below the roots collide() tests a
/// split node's children in the two-lane test, every volume as its rounded box (bv/rounded_box.hpp: exact for
/// Rss and spheres). The boxes contain the volumes, so no pair the volumes' own test would keep is dropped, and
/// the triangles decide as in every descent: the answers are those of the brute force
/// (tests/query/test_mixed_trees.cpp). What it costs: the box of a sphere or an Rss is looser than the volume for
/// distance(), and an Aabb node pays the rotated-box test; two trees of one BV keep their own test.

#include "cdkit/bv/bv_distance.hpp"
#include "cdkit/bv/enclosing_obb.hpp"
#include "cdkit/bvh/bvh_descent.hpp"
#include "cdkit/bvh/mesh_model.hpp"

#include <concepts>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace cdkit {

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
    /// As BvhDescentPair::siblings_overlap: the split node's two children against the other node in one two-lane
    /// test (bv/detail/obb_sibling_test.hpp), every volume as its rounded box (bv/rounded_box.hpp).
    template <bool DescendA> [[nodiscard]] SiblingOverlap siblings_overlap(std::uint32_t x, std::uint32_t y) const noexcept {
        return rounded_siblings_overlap<DescendA>(a, b, x, y, rel);
    }

    [[nodiscard]] B root_bound(std::uint32_t x, std::uint32_t y) const noexcept {
        return distance_lower_bound(enclosing_obb(a.nodes[x].bv), enclosing_obb(b.nodes[y].bv), rel);
    }
    /// As BvhDescentPair::child_bounds: the two children of the node the descent splits, with their bounds (the
    /// node that stays is boxed once for both).
    template <bool DescendA, class Item, class S>
    std::uint32_t child_bounds(const Item& it, S th, Item& c0, Item& c1) const noexcept {
        const auto cut = static_cast<B>(std::min<S>(th, S(std::numeric_limits<B>::max())));
        if constexpr (DescendA) {
            const std::uint32_t c = a.nodes[it.a].first;
            const auto& other = enclosing_obb(b.nodes[it.b].bv);
            c0 = {c, it.b, distance_lower_bound(enclosing_obb(a.nodes[c].bv), other, rel, cut)};
            c1 = {c + 1, it.b, distance_lower_bound(enclosing_obb(a.nodes[c + 1].bv), other, rel, cut)};
        } else {
            const std::uint32_t c = b.nodes[it.b].first;
            const auto& other = enclosing_obb(a.nodes[it.a].bv);
            c0 = {it.a, c, distance_lower_bound(other, enclosing_obb(b.nodes[c].bv), rel, cut)};
            c1 = {it.a, c + 1, distance_lower_bound(other, enclosing_obb(b.nodes[c + 1].bv), rel, cut)};
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
