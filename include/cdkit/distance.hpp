#pragma once
/// \file distance(): separation distance between two meshes on their trees (MeshModel<BV, M> of any bounding
/// volume, RestrictedBoxtree<S>), with closest points, and distance_brute_force(), the all-pairs reference.
///
/// Method: branch and bound over both trees (the scheme of Larsen, Gottschalk, Lin, Manocha, "Fast
/// proximity queries with swept sphere volumes", UNC TR99-018, 1999, used by PQP and FCL). The query works
/// in A's model frame with the relative transform pose_a⁻¹·pose_b, like collide(). Open node pairs are kept
/// in a heap by their BV lower bound (bv/bv_distance.hpp; bv/rss.hpp) and the smallest is always expanded
/// next (pure best first; the nearer child skips the heap while it is still the smallest). A pair is thus
/// expanded only when its bound is below the current answer and, since the pair holding the closest
/// triangles is reached before any pair whose bound exceeds their distance, almost only the pairs whose
/// bound is below the final answer. Each bound is told the current threshold and stops as soon as the pair
/// is known to be pruned or kept (the Rss bound's projections: rectangle_gap in bv/rss.hpp), except that Rss
/// trees bound both children of the split node together, in two SIMD lanes and without early stops
/// (bv/detail/distance_rss_pair.hpp): on the bunny benchmark 13–25% faster, with 5–8% fewer bound
/// evaluations.
/// A node pair is pruned when its lower bound is at least (best − abs_err)/(1 + rel_err), which guarantees
///   best ≤ (1 + rel_err)·true + abs_err.
/// With both errors 0 the answer is the minimum of triangle_distance() over all pairs, bit for bit the
/// value distance_brute_force() computes (same routine, same rounded vertices): a pair is pruned only when
/// its bound, which never exceeds any of its triangle pairs' computed distances, reaches the best value.
/// The tightest volume for this is Rss (a rectangle swept by a sphere); Obb and Aabb work too, and so do
/// the restricted boxtree's implied boxes (a one-child node has one child: it is the only open pair made).
/// A leaf pair whose bound is positive holds disjoint triangles (the bound never exceeds their computed
/// distance), so its triangle pairs skip triangle_distance()'s exact intersection test, with the same result.
/// Such a pair is skipped altogether when a projection gap of the two triangles (the 11 separating axes,
/// bvh/detail/distance_triangle_gap.hpp) already exceeds the threshold: it could not lower the answer.
/// On the bunny benchmark that skips 43–59% of the triangle pairs (docs/distance.md).
/// Queries are const and thread-safe, and never throw (except std::bad_alloc when the open-pair heap grows:
/// a thread_local vector whose storage the thread's later queries reuse, so no allocation per query).

#include "cdkit/bvh/boxtree_descent.hpp"
#include "cdkit/bvh/bvh_descent.hpp"
#include "cdkit/bvh/detail/distance_triangle_gap.hpp"
#include "cdkit/bvh/traverse.hpp"
#include "cdkit/core/distance_result.hpp"
#include "cdkit/narrowphase/triangle_distance.hpp"
#include "cdkit/query.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace cdkit {

namespace detail {
/// Distance of triangle ta of A and tb of B (B carried to A's frame); records it in `out` (A's frame
/// points, converted to world at the end) when strictly below the best so far. `disjoint`: the triangles
/// are known to be disjoint; then the pair is skipped without measuring it when a projection gap shows
/// its distance to be above `skip_from` (it could not become the answer).
template <class S>
inline void distance_triangle_pair(const TriangleMesh<S>& ma, Index ta, const TriangleMesh<S>& mb, Index tb,
                                   const Transform<S>& b_to_a, DistanceResult<S>& out, bool disjoint = false,
                                   S skip_from = std::numeric_limits<S>::infinity()) noexcept {
    const auto& A = ma.triangles[ta];
    const auto& B = mb.triangles[tb];
    TriangleDistance<S> d;
    if (disjoint) {
        // What triangle_distance computes for disjoint triangles, without its exact intersection test.
        const Vec3<S> P[3] = {ma.vertices[A[0]], ma.vertices[A[1]], ma.vertices[A[2]]};
        const Vec3<S> Q[3] = {to_frame_a(b_to_a, mb.vertices[B[0]]), to_frame_a(b_to_a, mb.vertices[B[1]]),
                              to_frame_a(b_to_a, mb.vertices[B[2]])};
        if (triangle_gap_reaches(P, Q, skip_from)) {
            ++out.stats.primitive_skips;
            return;
        }
        ++out.stats.primitive_tests;
        d.distance = std::sqrt(triangle_feature_dist2(P, Q, d.point_on_p, d.point_on_q));
    } else {
        ++out.stats.primitive_tests;
        d = triangle_distance(ma.vertices[A[0]], ma.vertices[A[1]], ma.vertices[A[2]], to_frame_a(b_to_a, mb.vertices[B[0]]),
                              to_frame_a(b_to_a, mb.vertices[B[1]]), to_frame_a(b_to_a, mb.vertices[B[2]]));
    }
    if (d.distance < out.distance) {
        out.distance = d.distance;
        out.point_a = d.point_on_p;
        out.point_b = d.point_on_q;
        out.triangle_a = ta;
        out.triangle_b = tb;
    }
}

/// An open node pair of distance(): the two trees' cursors (node indices, with the boxtree's implied boxes)
/// and the pair's lower bound.
template <class CursorA, class CursorB, class S> struct OpenPair {
    CursorA a;
    CursorB b;
    S bound;
};

/// A binary min-heap on OpenPair::bound, in a vector (std::push_heap's order, with a replace-top that sifts
/// once where pop then push would sift twice).
template <class Item> inline void heap_push(std::vector<Item>& h, const Item& x) {
    std::size_t i = h.size();
    h.push_back(x);
    while (i > 0) {
        const std::size_t parent = (i - 1) / 2;
        if (!(x.bound < h[parent].bound)) break;
        h[i] = h[parent];
        i = parent;
    }
    h[i] = x;
}
/// Replaces the smallest item by x and restores the heap.
template <class Item> inline void heap_replace_top(std::vector<Item>& h, const Item& x) noexcept {
    const std::size_t n = h.size();
    std::size_t i = 0;
    while (true) {
        std::size_t c = 2 * i + 1;
        if (c >= n) break;
        if (c + 1 < n && h[c + 1].bound < h[c].bound) ++c;
        if (!(h[c].bound < x.bound)) break;
        h[i] = h[c];
        i = c;
    }
    h[i] = x;
}
/// Removes and returns the smallest item (h not empty).
template <class Item> [[nodiscard]] inline Item heap_pop(std::vector<Item>& h) noexcept {
    const Item top = h.front();
    const Item last = h.back();
    h.pop_back();
    if (!h.empty()) heap_replace_top(h, last);
    return top;
}

template <class S> inline void distance_to_world(const Transform<S>& pose_a, DistanceResult<S>& out) noexcept {
    out.point_a = pose_a * out.point_a;
    out.point_b = pose_a * out.point_b;
}
}  // namespace detail

/// Separation distance between two mesh models at the given world poses (model frame → world): the
/// smallest distance between a triangle of A and a triangle of B, with a closest pair of points (world
/// frame) and the two triangles. 0 with a witness point when the meshes intersect. `request` trades
/// accuracy for speed and may bound the range of interest (see DistanceRequest; status invalid_input for a
/// request out of range). Models: MeshModel<BV, M> with any BV of the family (Aabb, Obb,
/// Rss, Kdop, BoundingSphere) or a volume of one's own with distance_lower_bound (Rss trees built with
/// SplitStrategy::sah are the fastest, see docs/bvh.md; the boxes and k-DOPs next, the spheres' bound is the
/// loosest), and RestrictedBoxtree<S> (boxes implied by one plane per node: bvh/boxtree_descent.hpp).
/// The poses' scalar is the models' mesh scalar; with float BVs over double meshes the bounds are computed
/// in float (see MeshModel).
template <class A, class B>
    requires DescentModels<A, B>
[[nodiscard]] DistanceResult<typename A::Scalar> distance(const A& a, const std::type_identity_t<Transform<typename A::Scalar>>& pose_a,
                                                          const B& b, const std::type_identity_t<Transform<typename A::Scalar>>& pose_b,
                                                          const DistanceRequest<typename A::Scalar>& request = {}) {
    using S = typename A::Scalar;
    DistanceResult<S> out;
    if (!pose_is_usable(pose_a) || !pose_is_usable(pose_b)) {
        out.status = QueryStatus::invalid_pose;
        return out;
    }
    if (!detail::distance_request_is_valid(request)) {
        out.status = QueryStatus::invalid_input;
        return out;
    }
    const Transform<S> b_to_a = pose_a.inverse() * pose_b;
    const auto pair = detail::descent_pair(a, b, b_to_a, true);
    using Pair = std::remove_const_t<decltype(pair)>;
    if (pair.a.empty() || pair.b.empty()) return out;
    const auto& ma = a.mesh();
    const auto& mb = b.mesh();
    // Pairs whose bound reaches this are pruned; the request's cut (+inf without max_distance) until a first
    // triangle pair is measured.
    const detail::DistancePruning<S> pruning(request);
    const auto threshold = [&]() noexcept { return pruning.threshold(out.distance); };

    using Item = detail::OpenPair<typename Pair::TreeA::Cursor, typename Pair::TreeB::Cursor, S>;
    // Best first: the open pair of smallest bound is expanded next, so only pairs whose bound is below the
    // answer are expanded (the pair holding the closest triangles is reached before any pair whose bound
    // exceeds their distance), and once the smallest open bound reaches the threshold everything left is
    // pruned. The nearer child is expanded directly when it is still the smallest (no heap round trip);
    // otherwise it swaps places with the heap's top. (A depth-first dive along the nearer child to a first
    // leaf pair, which this replaced, found its upper bound sooner but needed a third more bound evaluations on
    // the bunny benchmark at δ = 0.005 r: 1013 against 756.)
    // The heap's storage is reused by the thread's later queries: no allocation once it has grown.
    static thread_local std::vector<Item> heap;
    heap.clear();
    ++out.stats.bv_tests;
    Item it{pair.a.root(), pair.b.root(), S(0)};
    it.bound = pair.root_bound(it.a, it.b);
    while (it.bound < threshold()) {  // `it` is the smallest open pair: when it fails, all do
        const bool xl = pair.a.is_leaf(it.a), yl = pair.b.is_leaf(it.b);
        if (xl && yl) {
            // A positive bound proves the leaves' triangles disjoint: skip the exact intersection test, and
            // skip pairs that a projection gap shows to be no nearer than the threshold.
            const bool disjoint = it.bound > S(0);
            pair.a.for_each_triangle(it.a, [&](Index ta) {
                return pair.b.for_each_triangle(it.b, [&](Index tb) {
                    detail::distance_triangle_pair(ma, ta, mb, tb, b_to_a, out, disjoint, threshold());
                    return true;
                });
            });
            if (heap.empty() || out.distance == S(0)) break;  // 0: intersecting, nothing can be nearer
            it = detail::heap_pop(heap);
            continue;
        }
        // Split the node the descent rule picks (bvh/traverse.hpp); a one-child node gives c1 a bound of +inf.
        Item c0, c1;
        const S th = threshold();
        out.stats.bv_tests += detail::descends_a(pair, it.a, it.b, xl, yl) ? pair.template child_bounds<true>(it, th, c0, c1)
                                                                           : pair.template child_bounds<false>(it, th, c0, c1);
        if (c1.bound < c0.bound) std::swap(c0, c1);
        if (c1.bound < th) detail::heap_push(heap, c1);
        if (!(c0.bound < th)) {
            if (heap.empty()) break;
            it = detail::heap_pop(heap);
        } else if (!heap.empty() && heap.front().bound < c0.bound) {
            it = heap.front();
            detail::heap_replace_top(heap, c0);
        } else {
            it = c0;
        }
    }
    if (detail::beyond_max_distance(out.distance, request)) return DistanceResult<S>{.stats = out.stats};
    detail::distance_to_world(pose_a, out);
    return out;
}

/// The reference: every triangle pair, in index order; the first pair attaining the minimum is reported.
/// O(n·m); for tests and small meshes. Same result struct and frames as distance().
template <class S>
[[nodiscard]] DistanceResult<S> distance_brute_force(const TriangleMesh<S>& a, const Transform<S>& pose_a,
                                                     const TriangleMesh<S>& b, const Transform<S>& pose_b) {
    DistanceResult<S> out;
    if (!pose_is_usable(pose_a) || !pose_is_usable(pose_b)) {
        out.status = QueryStatus::invalid_pose;
        return out;
    }
    const Transform<S> b_to_a = pose_a.inverse() * pose_b;
    for (Index i = 0; i < a.triangles.size(); ++i)
        for (Index j = 0; j < b.triangles.size(); ++j) {
            detail::distance_triangle_pair(a, i, b, j, b_to_a, out);
            if (out.distance == S(0)) {
                detail::distance_to_world(pose_a, out);
                return out;
            }
        }
    detail::distance_to_world(pose_a, out);
    return out;
}

}  // namespace cdkit
