#pragma once
/// \file distance() on two restricted boxtrees: the separation distance and closest points of two meshes,
/// with the same contract as distance() on MeshModels (distance.hpp).
///
/// Method: best-first branch and bound over both trees (Larsen, Gottschalk, Lin, Manocha, "Fast proximity
/// queries with swept sphere volumes", UNC TR99-018, 1999) on the boxes a restricted boxtree implies
/// (Zachmann, "Minimal hierarchical collision detection", VRST 2002): an open pair carries both trees'
/// current boxes, each in its tree's local frame, and a child's box is its parent's with one face moved.
/// A pair's lower bound is that of two oriented boxes (as in bv_distance.hpp: the circumscribed spheres'
/// gap, then the gaps along the six face axes), with the boxtree collision query's slack (boxtree_relative), which
/// covers the rounding of the model-frame transforms that the triangle test works with. So, as for the
/// other trees, with rel_err = abs_err = 0 the answer is bit for bit the minimum of triangle_distance()
/// over all triangle pairs, the value distance_brute_force() computes.
///
/// Boxes are a looser volume for distance than Rss (no rounding of edges, and axis-aligned in the tree's
/// frame): this query is here so that every tree of the family answers distance queries, not as the fastest
/// (docs/distance.md compares them). Queries are const and thread-safe; the open-pair heap is a thread_local
/// vector reused by the thread's later queries.

#include "cdkit/bv/bv_distance.hpp"
#include "cdkit/bvh/boxtree.hpp"
#include "cdkit/boxtree_collide.hpp"
#include "cdkit/distance.hpp"

#include <algorithm>
#include <vector>

namespace cdkit {

namespace detail {
/// An open node pair of the boxtree distance query with both current boxes (local frames).
template <class S> struct BoxtreeOpenPair {
    S bound;
    std::uint32_t a, b;
    FloatBox box_a, box_b;
};

/// Lower bound on the distance between A's box `a` and B's box `b` (each in its tree's local frame);
/// returns the circumscribed spheres' gap alone once that reaches `cutoff` (the caller prunes it anyway).
template <class S>
[[nodiscard]] inline S boxtree_distance_bound(const BoxtreeRelative<S>& rel, const FloatBox& a, const FloatBox& b,
                                              S cutoff) noexcept {
    Vec3<S> ca, ha, cb, hb;
    for (int k = 0; k < 3; ++k) {
        ca[k] = S(0.5) * (S(a[k]) + S(a[k + 3])), ha[k] = S(0.5) * (S(a[k + 3]) - S(a[k]));
        cb[k] = S(0.5) * (S(b[k]) + S(b[k + 3])), hb[k] = S(0.5) * (S(b[k + 3]) - S(b[k]));
    }
    const Vec3<S> T = rel.R * cb + rel.t - ca;
    const S sphere = sphere_gap_lower_bound(ha, hb, T, rel.slack);
    if (sphere >= cutoff) return sphere;
    // The six face axes (box_gap_lower_bound without its nine edge axes, which on the bunny cut the bound
    // evaluations by a seventh but cost more than that: 15–20 % slower queries).
    const Vec3<S> wa = ha + Vec3<S>::Constant(rel.slack);
    S gap = sphere;
    for (int i = 0; i < 3; ++i) gap = std::max(gap, std::abs(T[i]) - (wa[i] + rel.abs_R.row(i).dot(hb)));
    for (int j = 0; j < 3; ++j) gap = std::max(gap, std::abs(rel.R.col(j).dot(T)) - (hb[j] + rel.abs_R.col(j).dot(wa)));
    return lowered(gap, wa, hb, T);
}
}  // namespace detail

/// Separation distance between two meshes on their restricted boxtrees at the given world poses (model frame
/// → world): the smallest distance between a triangle of A and a triangle of B, the two triangles and a
/// closest pair of points (world frame); 0 when the meshes intersect. Same request, result and guarantees as
/// distance() on MeshModels: distance ≤ (1 + rel_err)·true + abs_err, exact with both 0. Poses that are not
/// rigid motions give status invalid_pose and distance +inf.
template <class S>
[[nodiscard]] DistanceResult<S> distance(const RestrictedBoxtree<S>& a, const std::type_identity_t<Transform<S>>& pose_a,
                                         const RestrictedBoxtree<S>& b, const std::type_identity_t<Transform<S>>& pose_b,
                                         const DistanceRequest<S>& request = {}) {
    using Node = BoxtreeNode;
    using Item = detail::BoxtreeOpenPair<S>;
    DistanceResult<S> out;
    if (!pose_is_usable(pose_a) || !pose_is_usable(pose_b)) {
        out.status = QueryStatus::invalid_pose;
        return out;
    }
    const Transform<S> b_to_a = pose_a.inverse() * pose_b;
    const detail::BoxtreeRelative<S> rel = detail::boxtree_relative(a, b, b_to_a);
    const auto& na = a.nodes();
    const auto& nb = b.nodes();
    const auto& ma = a.mesh();
    const auto& mb = b.mesh();
    const S scale = S(1) / (S(1) + std::max(S(0), request.rel_err));
    const S abs_err = std::max(S(0), request.abs_err);
    const auto threshold = [&]() noexcept { return (out.distance - abs_err) * scale; };
    // Min-heap on the bound (std::push_heap keeps the greatest first, hence the reversed order).
    const auto later = [](const Item& x, const Item& y) { return y.bound < x.bound; };
    static thread_local std::vector<Item> heap;
    heap.clear();

    Item it{0, 0, 0, detail::restrict_box(a.root_box(), na[0]), detail::restrict_box(b.root_box(), nb[0])};
    ++out.stats.bv_tests;
    it.bound = detail::boxtree_distance_bound(rel, it.box_a, it.box_b, threshold());
    for (;;) {
        if (it.bound < threshold()) {  // `it` is the smallest open pair: when it fails, all do
            const Node& x = na[it.a];
            const Node& y = nb[it.b];
            if (x.is_leaf() && y.is_leaf()) {
                // A positive bound proves the triangles disjoint: no exact intersection test, and no
                // measurement when a projection gap reaches the threshold (same result, as in distance()).
                detail::distance_triangle_pair(ma, x.index(), mb, y.index(), b_to_a, out, it.bound > S(0), threshold());
                if (out.distance == S(0)) break;  // intersecting: nothing can be nearer
            } else {
                // The children's bounds go on the heap; the smallest comes back first.
                const bool descend_a = detail::boxtree_descends_a(x, y, it.box_a, it.box_b);
                const Node& parent = descend_a ? x : y;
                const std::uint32_t first = parent.index();
                const std::uint32_t count = parent.kind() == Node::Kind::two_children ? 2 : 1;
                const S th = threshold();
                for (std::uint32_t c = first; c < first + count; ++c) {
                    Item child = it;
                    if (descend_a) child.a = c, child.box_a = detail::restrict_box(it.box_a, na[c]);
                    else child.b = c, child.box_b = detail::restrict_box(it.box_b, nb[c]);
                    ++out.stats.bv_tests;
                    child.bound = detail::boxtree_distance_bound(rel, child.box_a, child.box_b, th);
                    if (child.bound < th) heap.push_back(child), std::push_heap(heap.begin(), heap.end(), later);
                }
            }
        }
        if (heap.empty() || !(heap.front().bound < threshold())) break;
        std::pop_heap(heap.begin(), heap.end(), later);
        it = heap.back();
        heap.pop_back();
    }
    detail::distance_to_world(pose_a, out);
    return out;
}

}  // namespace cdkit
