#pragma once
/// \file distance(): separation distance between two meshes on their BVHs, with closest points, and
/// distance_brute_force(), the all-pairs reference.
///
/// Method: branch and bound over both trees (the scheme of Larsen, Gottschalk, Lin, Manocha, "Fast
/// proximity queries with swept sphere volumes", UNC TR99-018, 1999, used by PQP and FCL). The query works
/// in A's model frame with the relative transform pose_a⁻¹·pose_b, like collide(). Open node pairs are kept
/// in a heap by their BV lower bound (bv/bv_distance.hpp; bv/rss.hpp) and the smallest is expanded first,
/// diving along the nearer child down to a leaf pair so that a good upper bound comes at once (the farther
/// child goes to the heap). Best first expands only pairs whose bound is below the current answer: on the
/// benchmark meshes it tests about half the node pairs of a depth-first nearer-child-first descent and a
/// third of its triangle pairs. A node pair is pruned when its lower bound is at least
/// (best − abs_err)/(1 + rel_err), which guarantees   best ≤ (1 + rel_err)·true + abs_err.
/// With both errors 0 the answer is the minimum of triangle_distance() over all pairs, bit for bit the
/// value distance_brute_force() computes (same routine, same rounded vertices): a pair is pruned only when
/// its bound, which never exceeds any of its triangle pairs' computed distances, reaches the best value.
/// The tightest volume for this is Rss (a rectangle swept by a sphere); Obb and Aabb work too.
/// Queries are const and thread-safe, and never throw.

#include "cdkit/bv/bv_distance.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/bvh/traverse.hpp"
#include "cdkit/narrowphase/triangle_distance.hpp"
#include "cdkit/query.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace cdkit {

/// Accuracy wanted from distance(). The result satisfies distance ≤ (1 + rel_err)·true + abs_err (and
/// distance ≥ true up to rounding); larger errors prune more and answer sooner. Both must be ≥ 0.
template <class S = double> struct DistanceRequest {
    S rel_err = 0;
    S abs_err = 0;
};

/// Work counters of one distance query.
struct DistanceStats {
    std::uint64_t bv_tests = 0;        ///< BV lower-bound evaluations
    std::uint64_t primitive_tests = 0; ///< triangle_distance evaluations
};

/// Result of distance(). Points are in the world frame.
template <class S> struct DistanceResult {
    QueryStatus status = QueryStatus::ok;  ///< invalid_pose: a pose was not a rigid motion; distance stays +inf
    S distance = std::numeric_limits<S>::infinity();  ///< 0 when the meshes intersect (touching counts)
    Vec3<S> point_a = Vec3<S>::Zero();  ///< on triangle_a of A, at `distance` from point_b
    Vec3<S> point_b = Vec3<S>::Zero();  ///< on triangle_b of B
    Index triangle_a = 0;               ///< index into A's mesh.triangles
    Index triangle_b = 0;
    DistanceStats stats;
};

namespace detail {
/// Distance of triangle ta of A and tb of B (B carried to A's frame); records it in `out` (A's frame
/// points, converted to world at the end) when strictly below the best so far.
template <class S>
inline void distance_triangle_pair(const TriangleMesh<S>& ma, Index ta, const TriangleMesh<S>& mb, Index tb,
                                   const Transform<S>& b_to_a, DistanceResult<S>& out) noexcept {
    const auto& A = ma.triangles[ta];
    const auto& B = mb.triangles[tb];
    ++out.stats.primitive_tests;
    const TriangleDistance<S> d =
        triangle_distance(ma.vertices[A[0]], ma.vertices[A[1]], ma.vertices[A[2]], to_frame_a(b_to_a, mb.vertices[B[0]]),
                          to_frame_a(b_to_a, mb.vertices[B[1]]), to_frame_a(b_to_a, mb.vertices[B[2]]));
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

template <class S> inline void distance_to_world(const Transform<S>& pose_a, DistanceResult<S>& out) noexcept {
    out.point_a = pose_a * out.point_a;
    out.point_b = pose_a * out.point_b;
}
}  // namespace detail

/// Separation distance between two mesh models at the given world poses (model frame → world): the
/// smallest distance between a triangle of A and a triangle of B, with a closest pair of points (world
/// frame) and the two triangles. 0 with a witness point when the meshes intersect. `request` trades
/// accuracy for speed (see DistanceRequest). BV: a volume with distance_lower_bound (Aabb, Obb, Rss; Rss
/// trees built with SplitStrategy::sah are the fastest, see docs/bvh.md).
/// M is the meshes' scalar; with float BVs over double meshes the bounds are computed in float (see MeshModel).
template <class BV, class M>
[[nodiscard]] DistanceResult<M> distance(const MeshModel<BV, M>& a, const std::type_identity_t<Transform<M>>& pose_a,
                                         const MeshModel<BV, M>& b, const std::type_identity_t<Transform<M>>& pose_b,
                                         const DistanceRequest<M>& request = {}) {
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

    struct Item { std::uint32_t a, b; S bound; };
    // Best first with a dive: the open pair of smallest bound is taken from a heap, then descended along the
    // nearer child down to a leaf pair while the farther child goes to the heap. The dive reaches a good
    // first upper bound at once; the heap order then expands only pairs whose bound is below the answer's
    // current value, and once the smallest open bound reaches the threshold everything left is pruned.
    const auto later = [](const Item& x, const Item& y) noexcept { return x.bound > y.bound; };
    std::vector<Item> heap;
    heap.reserve(128);
    ++out.stats.bv_tests;
    heap.push_back({0, 0, distance_lower_bound(na[0].bv, nb[0].bv, rel)});
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), later);
        Item it = heap.back();
        heap.pop_back();
        if (it.bound >= threshold()) break;  // the smallest open bound: nothing left can improve
        while (true) {
            const BvhNode<BV>& x = na[it.a];
            const BvhNode<BV>& y = nb[it.b];
            const bool xl = x.is_leaf(), yl = y.is_leaf();
            if (xl && yl) {
                for (std::uint32_t i = x.first; i < x.first + x.count; ++i)
                    for (std::uint32_t j = y.first; j < y.first + y.count; ++j)
                        detail::distance_triangle_pair(ma, order_a[i], mb, order_b[j], b_to_a, out);
                break;
            }
            // Split the larger volume (or the one that is not a leaf).
            Item c0, c1;
            const S th = threshold();
            const auto bv_th = static_cast<typename BV::Scalar>(th);  // only an early-out hint to the bound
            if (yl || (!xl && x.bv.size() >= y.bv.size())) {
                if constexpr (detail::MovableDistanceBound<BV>) {
                    // y moved into A's frame once for both children of x.
                    const BV moved = transformed(y.bv, rel.R, rel.t);
                    c0 = {x.first, it.b, distance_lower_bound_same_frame(na[x.first].bv, moved, rel.slack, bv_th)};
                    c1 = {x.first + 1, it.b, distance_lower_bound_same_frame(na[x.first + 1].bv, moved, rel.slack, bv_th)};
                } else {
                    c0 = {x.first, it.b, distance_lower_bound(na[x.first].bv, y.bv, rel, bv_th)};
                    c1 = {x.first + 1, it.b, distance_lower_bound(na[x.first + 1].bv, y.bv, rel, bv_th)};
                }
            } else {
                if constexpr (detail::MovableDistanceBound<BV>) {
                    // x moved into B's frame once for both children of y.
                    const BV moved = transformed(x.bv, inv.R, inv.t);
                    c0 = {it.a, y.first, distance_lower_bound_same_frame(nb[y.first].bv, moved, inv.slack, bv_th)};
                    c1 = {it.a, y.first + 1, distance_lower_bound_same_frame(nb[y.first + 1].bv, moved, inv.slack, bv_th)};
                } else {
                    c0 = {it.a, y.first, distance_lower_bound(x.bv, nb[y.first].bv, rel, bv_th)};
                    c1 = {it.a, y.first + 1, distance_lower_bound(x.bv, nb[y.first + 1].bv, rel, bv_th)};
                }
            }
            out.stats.bv_tests += 2;
            if (c1.bound < c0.bound) std::swap(c0, c1);
            if (c1.bound < th) {
                heap.push_back(c1);
                std::push_heap(heap.begin(), heap.end(), later);
            }
            if (!(c0.bound < th)) break;
            it = c0;
        }
        if (out.distance == S(0)) break;  // intersecting: nothing can be nearer
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
