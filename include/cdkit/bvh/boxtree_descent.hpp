#pragma once
/// \file The restricted boxtree as a tree of the simultaneous descent (bvh/traverse.hpp), after Zachmann,
/// "Minimal hierarchical collision detection", VRST 2002: a cursor carries its node's implied box (its
/// tree's local frame), and a child's box is its parent's with one face moved.
///
/// The overlap test is re-alignment: a step descends one tree, and its child's box differs from its parent's
/// by one face. The step tests (1) the moved face against the other box's extent along the face's axis,
/// mapped through the relative rotation, and (2) the descending tree's smaller box against the other box
/// along the other tree's three axes, each on the side that moved. Which corner of a box gives an extent
/// depends only on the signs of the rotation's entries, chosen once per query: each projection is three
/// multiply-adds. With 12 multiply-adds and 4 comparisons a step keeps the invariant that no face axis of
/// either current box separates the pair (the bounds that did not move passed at an ancestor). The root pair
/// gets the full 15-axis box test. A leaf pair gets, before the exact triangle test, the two triangles' own
/// bounding boxes in A's frame (the leaves' implied boxes are looser; a 15-axis test of the implied boxes
/// there measured slower: it rejects few pairs that this filter does not). Every test is conservative, and
/// the slack added to every comparison covers the rounding of the transforms, so ContactMode::all returns
/// exactly brute force's pairs.
///
/// The distance bound of a node pair is that of two oriented boxes (as in bv_distance.hpp: the circumscribed
/// spheres' gap, then the gaps along the six face axes), with the same slack, so that with rel_err = abs_err
/// = 0 distance() is bit for bit the minimum of triangle_distance() over all triangle pairs, as for the
/// other trees. Boxes are a looser volume for distance than Rss: this is here so that every tree of the
/// family answers distance queries, not as the fastest (docs/distance.md compares them).

#include "cdkit/bv/bv_distance.hpp"
#include "cdkit/bv/detail/separating_axis.hpp"
#include "cdkit/bvh/boxtree.hpp"
#include "cdkit/core/collision_result.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace cdkit {

namespace detail {
/// A boxtree node during a descent: its index and its implied box (local frame).
struct BoxtreeCursor {
    std::uint32_t node;
    FloatBox box;
};

/// One restricted boxtree seen by the descent.
struct BoxtreeDescentTree {
    using Cursor = BoxtreeCursor;
    const BoxtreeNode* nodes = nullptr;
    FloatBox root_box{};

    template <class S>
    explicit BoxtreeDescentTree(const RestrictedBoxtree<S>& t) noexcept : nodes(t.nodes().data()), root_box(t.root_box()) {}
    [[nodiscard]] bool empty() const noexcept { return false; }  // a boxtree holds at least one triangle
    [[nodiscard]] Cursor root() const noexcept { return {0, restrict_box(root_box, nodes[0])}; }
    [[nodiscard]] bool is_leaf(const Cursor& c) const noexcept { return nodes[c.node].is_leaf(); }
    [[nodiscard]] std::uint32_t child_count(const Cursor& c) const noexcept {
        return std::uint32_t(nodes[c.node].kind());  // leaf 0, one_child 1, two_children 2
    }
    void descend(Cursor& c, std::uint32_t i) const noexcept {
        c.node = nodes[c.node].index() + i;
        const BoxtreeNode& n = nodes[c.node];
        if (n.axis() != BoxtreeNode::no_axis) c.box[n.upper() ? n.axis() + 3 : n.axis()] = n.plane;
    }
    /// A one-child node first (one cheap step that only tightens: 12 % fewer steps on the bunny), else the
    /// larger box by sum of extents.
    [[nodiscard]] float split_priority(const Cursor& c) const noexcept {
        if (nodes[c.node].kind() == BoxtreeNode::Kind::one_child) return std::numeric_limits<float>::infinity();
        const FloatBox& b = c.box;
        return (b[3] - b[0]) + (b[4] - b[1]) + (b[5] - b[2]);
    }
    template <class F> bool for_each_triangle(const Cursor& c, F&& f) const { return f(Index(nodes[c.node].index())); }
};
static_assert(std::uint32_t(BoxtreeNode::Kind::one_child) == 1 && std::uint32_t(BoxtreeNode::Kind::two_children) == 2,
              "child_count reads the kind as the number of children");

/// Per-query data of a boxtree pair: the relative motion of B's local frame into A's, and for each axis
/// which corner of a box is least or greatest along it, from the signs of the rotation's entries.
template <class S> struct BoxtreeRelative {
    using Slots = std::array<std::array<std::uint8_t, 3>, 3>;
    Mat3<S> R;       ///< B's local frame → A's local frame: x_a = R·x_b + t
    Vec3<S> t;
    Vec3<S> t_in_b;  ///< −Rᵀ·t: A's local origin in B's local frame (with Rᵀ for R⁻¹)
    Mat3<S> abs_R;   ///< |R| with the separating-axis test's slack
    /// [k][j]: the slot (0–2 lo, 3–5 hi) of B's box coordinate j at the corner least (greatest) along A's axis k.
    Slots lo_in_a, hi_in_a;
    /// [j][k]: the slot of A's box coordinate k at the corner least (greatest) along B's axis j.
    Slots lo_in_b, hi_in_b;
    /// [2·k + upper][j]: moving A's face (k, upper) inwards moves A's least (true) or greatest (false) extent
    /// along B's axis j.
    std::array<std::array<bool, 3>, 6> moves_lo_in_b;
    /// [2·j + upper][k]: the same for B's faces and A's axes.
    std::array<std::array<bool, 3>, 6> moves_lo_in_a;
    S slack;  ///< added to every comparison: covers the rounding (see boxtree_relative)

    /// Coordinate along A's axis k of B's box corner `slot`, mapped into A's local frame.
    [[nodiscard]] S along_a(const FloatBox& b, std::uint32_t k, const std::array<std::uint8_t, 3>& slot) const noexcept {
        return t[k] + R(k, 0) * S(b[slot[0]]) + R(k, 1) * S(b[slot[1]]) + R(k, 2) * S(b[slot[2]]);
    }
    /// Coordinate along B's axis j of A's box corner `slot`, mapped into B's local frame.
    [[nodiscard]] S along_b(const FloatBox& a, std::uint32_t j, const std::array<std::uint8_t, 3>& slot) const noexcept {
        return t_in_b[j] + R(0, j) * S(a[slot[0]]) + R(1, j) * S(a[slot[1]]) + R(2, j) * S(a[slot[2]]);
    }

    /// One step down tree A (InA) or B: `box` is the child's box, its parent's with `node`'s face (axis and
    /// side) moved to node's plane. Returns false when a face axis of either box then separates `box` from
    /// `other`, the other tree's current box.
    template <bool InA>
    [[nodiscard]] bool step(const BoxtreeNode& node, const FloatBox& box, const FloatBox& other) const noexcept {
        const std::uint32_t k = node.axis();
        if (k == BoxtreeNode::no_axis) return true;
        const bool up = node.upper();
        const S plane = S(node.plane);
        // Coordinates along this tree's axes of the other box's corners, and along the other tree's axes of
        // this box's corners.
        const auto along_own = [&](std::uint32_t i, const auto& slot) { return InA ? along_a(other, i, slot) : along_b(other, i, slot); };
        const auto along_other = [&](std::uint32_t i, const auto& slot) { return InA ? along_b(box, i, slot) : along_a(box, i, slot); };
        const Slots& lo_own = InA ? lo_in_a : lo_in_b;
        const Slots& hi_own = InA ? hi_in_a : hi_in_b;
        const Slots& lo_other = InA ? lo_in_b : lo_in_a;
        const Slots& hi_other = InA ? hi_in_b : hi_in_a;
        bool apart = up ? plane + slack < along_own(k, lo_own[k]) : plane - slack > along_own(k, hi_own[k]);
        // No early exit: the four outcomes are hard to predict, and a mispredicted branch costs more than
        // the projections it would skip.
        const auto& moves_lo = (InA ? moves_lo_in_b : moves_lo_in_a)[2 * k + up];
        for (std::uint32_t j = 0; j < 3; ++j)
            apart |= moves_lo[j] ? along_other(j, lo_other[j]) - slack > S(other[j + 3])
                                 : along_other(j, hi_other[j]) + slack < S(other[j]);
        return !apart;
    }

    /// The full 15-axis box test (face and edge axes) of two current boxes.
    [[nodiscard]] bool boxes_overlap(const FloatBox& a, const FloatBox& b) const noexcept {
        Vec3<S> ca, ha, cb, hb;
        for (int k = 0; k < 3; ++k) {
            ca[k] = S(0.5) * (S(a[k]) + S(a[k + 3])), ha[k] = S(0.5) * (S(a[k + 3]) - S(a[k]));
            cb[k] = S(0.5) * (S(b[k]) + S(b[k + 3])), hb[k] = S(0.5) * (S(b[k + 3]) - S(b[k]));
        }
        return !boxes_disjoint(ha, hb, R, abs_R, Vec3<S>(R * cb + t - ca), slack);
    }

    /// Lower bound on the distance between A's box `a` and B's box `b`; returns the circumscribed spheres'
    /// gap alone once that reaches `cutoff` (the caller prunes it anyway).
    [[nodiscard]] S distance_bound(const FloatBox& a, const FloatBox& b, S cutoff) const noexcept {
        Vec3<S> ca, ha, cb, hb;
        for (int k = 0; k < 3; ++k) {
            ca[k] = S(0.5) * (S(a[k]) + S(a[k + 3])), ha[k] = S(0.5) * (S(a[k + 3]) - S(a[k]));
            cb[k] = S(0.5) * (S(b[k]) + S(b[k + 3])), hb[k] = S(0.5) * (S(b[k + 3]) - S(b[k]));
        }
        const Vec3<S> T = R * cb + t - ca;
        const S sphere = sphere_gap_lower_bound(ha, hb, T, slack);
        if (sphere >= cutoff) return sphere;
        // The six face axes (box_gap_lower_bound without its nine edge axes, which on the bunny cut the bound
        // evaluations by a seventh but cost more than that: 15–20 % slower queries).
        const Vec3<S> wa = ha + Vec3<S>::Constant(slack);
        S gap = sphere;
        for (int i = 0; i < 3; ++i) gap = std::max(gap, std::abs(T[i]) - (wa[i] + abs_R.row(i).dot(hb)));
        for (int j = 0; j < 3; ++j) gap = std::max(gap, std::abs(R.col(j).dot(T)) - (hb[j] + abs_R.col(j).dot(wa)));
        return lowered(gap, wa, hb, T);
    }
};

/// The bounding boxes of triangle ta and of triangle tb carried into A's frame overlap (touching counts).
/// Exact filter: it uses the very points the triangle test gets (to_frame_a), so a pair it rejects cannot
/// intersect. The leaves' implied boxes are looser than their triangle's box; this costs three transforms.
template <class S>
[[nodiscard]] inline bool triangle_boxes_overlap(const TriangleMesh<S>& ma, Index ta, const TriangleMesh<S>& mb, Index tb,
                                                 const Transform<S>& b_to_a) noexcept {
    const auto& A = ma.triangles[ta];
    const auto& B = mb.triangles[tb];
    const Vec3<S>& p0 = ma.vertices[A[0]];
    const Vec3<S>& p1 = ma.vertices[A[1]];
    const Vec3<S>& p2 = ma.vertices[A[2]];
    const Vec3<S> q0 = to_frame_a(b_to_a, mb.vertices[B[0]]);
    const Vec3<S> q1 = to_frame_a(b_to_a, mb.vertices[B[1]]);
    const Vec3<S> q2 = to_frame_a(b_to_a, mb.vertices[B[2]]);
    for (int k = 0; k < 3; ++k) {
        const S pmin = std::min({p0[k], p1[k], p2[k]}), pmax = std::max({p0[k], p1[k], p2[k]});
        const S qmin = std::min({q0[k], q1[k], q2[k]}), qmax = std::max({q0[k], q1[k], q2[k]});
        if (qmax < pmin || qmin > pmax) return false;
    }
    return true;
}

template <class S> [[nodiscard]] S box_magnitude(const FloatBox& b) noexcept {
    S m = 0;
    for (float x : b) m = std::max(m, S(std::abs(x)));
    return m;
}

template <class S>
[[nodiscard]] BoxtreeRelative<S> boxtree_relative(const RestrictedBoxtree<S>& a, const RestrictedBoxtree<S>& b,
                                                  const Transform<S>& b_to_a) noexcept {
    BoxtreeRelative<S> r;
    r.R = b_to_a.R;
    r.t = b_to_a.R * b.centre() + b_to_a.t - a.centre();
    r.t_in_b = -(b_to_a.R.transpose() * r.t);
    r.abs_R = abs_with_slack(r.R);
    for (std::uint8_t k = 0; k < 3; ++k)
        for (std::uint8_t j = 0; j < 3; ++j) {
            const bool positive = r.R(k, j) >= S(0);
            r.lo_in_a[k][j] = std::uint8_t(positive ? j : j + 3);
            r.hi_in_a[k][j] = std::uint8_t(positive ? j + 3 : j);
            r.lo_in_b[j][k] = std::uint8_t(positive ? k : k + 3);
            r.hi_in_b[j][k] = std::uint8_t(positive ? k + 3 : k);
            // Lowering A's hi_k lowers A's greatest extent along B's axis j when R(k, j) ≥ 0 (that corner
            // uses hi_k), else it raises the least; raising lo_k does the opposite. Likewise for B's faces.
            r.moves_lo_in_b[2 * k + 1][j] = !positive;
            r.moves_lo_in_b[2 * k + 0][j] = positive;
            r.moves_lo_in_a[2 * j + 1][k] = !positive;
            r.moves_lo_in_a[2 * j + 0][k] = positive;
        }
    // Rounding: of the vertices' transform R·v + t in the model frame (the fit padding covers |v|, this
    // covers |t|), of t here, of the projections, and of the boxes' centres and half extents in the 15-axis
    // test: each a few ulps of the scale. And Rᵀ stands for R⁻¹ in the tests along B's axes: a pose is
    // accepted with RᵀR off the identity by up to sqrt(eps), which moves a point y of B's box by at most
    // 3·|RᵀR − I|max·|y|.
    const S mag_a = box_magnitude<S>(a.root_box()), mag_b = box_magnitude<S>(b.root_box());
    const S scale = a.centre().cwiseAbs().maxCoeff() + b.centre().cwiseAbs().maxCoeff() +
                    b_to_a.t.cwiseAbs().maxCoeff() + r.t.cwiseAbs().maxCoeff() + mag_a + mag_b;
    const S off = ((r.R.transpose() * r.R) - Mat3<S>::Identity()).cwiseAbs().maxCoeff();
    r.slack = S(40) * std::numeric_limits<S>::epsilon() * scale + S(3) * off * (mag_a + mag_b + r.t.cwiseAbs().maxCoeff());
    return r;
}

/// Two restricted boxtrees under the relative transform of their local frames, with their meshes for the
/// leaf pairs' triangle box filter.
template <class S> struct BoxtreeDescentPair {
    using TreeA = BoxtreeDescentTree;
    using TreeB = BoxtreeDescentTree;
    using Cursor = BoxtreeCursor;
    static constexpr bool tests_leaf_pairs = true;

    TreeA a;
    TreeB b;
    BoxtreeRelative<S> rel;
    const TriangleMesh<S>* mesh_a;
    const TriangleMesh<S>* mesh_b;
    Transform<S> b_to_a;  ///< model frames, for the triangle box filter

    BoxtreeDescentPair(const RestrictedBoxtree<S>& ta, const RestrictedBoxtree<S>& tb, const Transform<S>& b_to_a_) noexcept
        : a(ta), b(tb), rel(boxtree_relative(ta, tb, b_to_a_)), mesh_a(&ta.mesh()), mesh_b(&tb.mesh()), b_to_a(b_to_a_) {}

    [[nodiscard]] bool roots_overlap(const Cursor& x, const Cursor& y) const noexcept { return rel.boxes_overlap(x.box, y.box); }
    template <bool DescendedA> [[nodiscard]] bool children_overlap(const Cursor& x, const Cursor& y) const noexcept {
        if constexpr (DescendedA) return rel.template step<true>(a.nodes[x.node], x.box, y.box);
        else return rel.template step<false>(b.nodes[y.node], y.box, x.box);
    }
    [[nodiscard]] bool leaves_overlap(const Cursor& x, const Cursor& y) const noexcept {
        return triangle_boxes_overlap(*mesh_a, Index(a.nodes[x.node].index()), *mesh_b, Index(b.nodes[y.node].index()), b_to_a);
    }

    [[nodiscard]] S root_bound(const Cursor& x, const Cursor& y) const noexcept {
        return rel.distance_bound(x.box, y.box, std::numeric_limits<S>::infinity());
    }
    /// The open pairs of `it`'s split node's children (A's when DescendA) with their bounds; returns how many
    /// (a one-child node: one, c1 gets +inf).
    template <bool DescendA, class Item>
    std::uint32_t child_bounds(const Item& it, S th, Item& c0, Item& c1) const noexcept {
        const TreeA& t = DescendA ? a : b;
        const Cursor& parent = DescendA ? it.a : it.b;
        const std::uint32_t n = t.child_count(parent);
        c1.bound = std::numeric_limits<S>::infinity();  // stays for a one-child node
        Item* out[2] = {&c0, &c1};
        for (std::uint32_t i = 0; i < n; ++i) {
            Item& c = *out[i];
            c = it;
            t.descend(DescendA ? c.a : c.b, i);
            c.bound = rel.distance_bound(c.a.box, c.b.box, th);
        }
        return n;
    }
};

/// The descent pair of two restricted boxtrees, `b_to_a` taking B's model frame into A's.
template <class S>
[[nodiscard]] BoxtreeDescentPair<S> descent_pair(const RestrictedBoxtree<S>& a, const RestrictedBoxtree<S>& b,
                                                 const Transform<S>& b_to_a, bool /*for_distance*/ = false) noexcept {
    return BoxtreeDescentPair<S>(a, b, b_to_a);
}
}  // namespace detail

}  // namespace cdkit
