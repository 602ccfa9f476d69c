#pragma once
/// \file distance(): separation distance between two meshes on their BVHs, with closest points, and
/// distance_brute_force(), the all-pairs reference.
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
/// The tightest volume for this is Rss (a rectangle swept by a sphere); Obb and Aabb work too.
/// A leaf pair whose bound is positive holds disjoint triangles (the bound never exceeds their computed
/// distance), so its triangle pairs skip triangle_distance()'s exact intersection test, with the same result.
/// Such a pair is skipped altogether when a projection gap of the two triangles (the 11 separating axes,
/// bvh/detail/distance_triangle_gap.hpp) already exceeds the threshold: it could not lower the answer.
/// On the bunny benchmark that skips 43–59% of the triangle pairs (docs/distance.md).
/// Queries are const and thread-safe, and never throw (except std::bad_alloc when the open-pair heap grows:
/// a thread_local vector whose storage the thread's later queries reuse, so no allocation per query).

#include "cdkit/bv/bv_distance.hpp"
#include "cdkit/bv/detail/distance_rss_pair.hpp"
#include "cdkit/bvh/detail/distance_triangle_gap.hpp"
#include "cdkit/bvh/mesh_model.hpp"
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

/// An open node pair of distance(): node indices into A's and B's trees and the pair's lower bound.
template <class S> struct OpenPair {
    std::uint32_t a, b;
    S bound;
};

/// A binary min-heap on OpenPair::bound, in a vector (std::push_heap's order, with a replace-top that sifts
/// once where pop then push would sift twice).
template <class S> inline void heap_push(std::vector<OpenPair<S>>& h, const OpenPair<S>& x) {
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
template <class S> inline void heap_replace_top(std::vector<OpenPair<S>>& h, const OpenPair<S>& x) noexcept {
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
template <class S> [[nodiscard]] inline OpenPair<S> heap_pop(std::vector<OpenPair<S>>& h) noexcept {
    const OpenPair<S> top = h.front();
    const OpenPair<S> last = h.back();
    h.pop_back();
    if (!h.empty()) heap_replace_top(h, last);
    return top;
}

template <class S> inline void distance_to_world(const Transform<S>& pose_a, DistanceResult<S>& out) noexcept {
    out.point_a = pose_a * out.point_a;
    out.point_b = pose_a * out.point_b;
}
}  // namespace detail

/// A volume distance() can descend: a free distance_lower_bound(a, b, rel, cutoff) (every BV of the family has one).
template <class BV>
concept HasDistanceLowerBound = requires(const BV& x, const typename BV::Relative& rel, typename BV::Scalar s) {
    { distance_lower_bound(x, x, rel, s) } -> std::convertible_to<typename BV::Scalar>;
};

/// Separation distance between two mesh models at the given world poses (model frame → world): the
/// smallest distance between a triangle of A and a triangle of B, with a closest pair of points (world
/// frame) and the two triangles. 0 with a witness point when the meshes intersect. `request` trades
/// accuracy for speed (see DistanceRequest). BV: any of the family (Aabb, Obb, Rss, Kdop, BoundingSphere), or
/// a volume of one's own with distance_lower_bound (Rss trees built with SplitStrategy::sah are the fastest, see
/// docs/bvh.md; the boxes and k-DOPs next, the spheres' bound is the loosest).
/// M is the meshes' scalar; with float BVs over double meshes the bounds are computed in float (see MeshModel).
template <class BV, class M>
[[nodiscard]] DistanceResult<M> distance(const MeshModel<BV, M>& a, const std::type_identity_t<Transform<M>>& pose_a,
                                         const MeshModel<BV, M>& b, const std::type_identity_t<Transform<M>>& pose_b,
                                         const DistanceRequest<M>& request = {}) {
    static_assert(HasDistanceLowerBound<BV>,
                  "distance(): the BV needs a free distance_lower_bound(a, b, rel, cutoff) (bv/bv_distance.hpp)");
    using S = M;
    DistanceResult<S> out;
    if (!pose_is_usable(pose_a) || !pose_is_usable(pose_b)) {
        out.status = QueryStatus::invalid_pose;
        return out;
    }
    if (a.bvh().empty() || b.bvh().empty()) return out;
    const Transform<S> b_to_a = pose_a.inverse() * pose_b;
    const auto rel = BV::relative(b_to_a.template cast<typename BV::Scalar>());
    // A → B, for bounds computed in B's frame (MovableDistanceBound volumes).
    const auto inv = BV::relative(b_to_a.inverse().template cast<typename BV::Scalar>());
    const auto& ma = a.mesh();
    const auto& mb = b.mesh();
    const auto& order_a = a.bvh().triangle_order();
    const auto& order_b = b.bvh().triangle_order();
    const auto& na = a.bvh().nodes();
    const auto& nb = b.bvh().nodes();
    const S scale = S(1) / (S(1) + std::max(S(0), request.rel_err));
    const S abs_err = std::max(S(0), request.abs_err);
    // Pairs whose bound reaches this are pruned; +inf until a first triangle pair is measured.
    const auto threshold = [&]() noexcept { return (out.distance - abs_err) * scale; };

    using Item = detail::OpenPair<S>;
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
    Item it{0, 0, distance_lower_bound(na[0].bv, nb[0].bv, rel)};
    while (it.bound < threshold()) {  // `it` is the smallest open pair: when it fails, all do
        const BvhNode<BV>& x = na[it.a];
        const BvhNode<BV>& y = nb[it.b];
        const bool xl = x.is_leaf(), yl = y.is_leaf();
        if (xl && yl) {
            // A positive bound proves the leaves' triangles disjoint: skip the exact intersection test, and
            // skip pairs that a projection gap shows to be no nearer than the threshold.
            const bool disjoint = it.bound > S(0);
            for (std::uint32_t i = x.first; i < x.first + x.count; ++i)
                for (std::uint32_t j = y.first; j < y.first + y.count; ++j)
                    detail::distance_triangle_pair(ma, order_a[i], mb, order_b[j], b_to_a, out, disjoint, threshold());
            if (heap.empty() || out.distance == S(0)) break;  // 0: intersecting, nothing can be nearer
            it = detail::heap_pop(heap);
            continue;
        }
        // Split the larger volume (or the one that is not a leaf).
        Item c0, c1;
        const S th = threshold();
        // Only an early-out hint to the scalar bounds, finite even before the first triangle pair: they stop
        // once a pair is known to be pruned or kept (see rectangle_gap). The Rss pair bound ignores it.
        using B = typename BV::Scalar;
        const auto bv_th = static_cast<B>(std::min<S>(th, S(std::numeric_limits<B>::max())));
        if (yl || (!xl && x.bv.size() >= y.bv.size())) {
            if constexpr (detail::MovableDistanceBound<BV>) {
                // y moved into A's frame once for both children of x.
                const BV moved = transformed(y.bv, rel.R, rel.t);
                B bound[2];
                detail::children_lower_bounds(na[x.first].bv, na[x.first + 1].bv, moved, rel.slack, bv_th, bound);
                c0 = {x.first, it.b, bound[0]};
                c1 = {x.first + 1, it.b, bound[1]};
            } else {
                c0 = {x.first, it.b, distance_lower_bound(na[x.first].bv, y.bv, rel, bv_th)};
                c1 = {x.first + 1, it.b, distance_lower_bound(na[x.first + 1].bv, y.bv, rel, bv_th)};
            }
        } else {
            if constexpr (detail::MovableDistanceBound<BV>) {
                // x moved into B's frame once for both children of y.
                const BV moved = transformed(x.bv, inv.R, inv.t);
                B bound[2];
                detail::children_lower_bounds(nb[y.first].bv, nb[y.first + 1].bv, moved, inv.slack, bv_th, bound);
                c0 = {it.a, y.first, bound[0]};
                c1 = {it.a, y.first + 1, bound[1]};
            } else {
                c0 = {it.a, y.first, distance_lower_bound(x.bv, nb[y.first].bv, rel, bv_th)};
                c1 = {it.a, y.first + 1, distance_lower_bound(x.bv, nb[y.first + 1].bv, rel, bv_th)};
            }
        }
        out.stats.bv_tests += 2;
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
