#pragma once
/// \file distance(mesh, pose, shape, pose): the smallest distance between a MeshModel's triangles and a convex
/// shape, with closest points and the triangle; distance_brute_force(), the reference over every triangle.
///
/// Method: branch and bound over the mesh's tree (Larsen, Gottschalk, Lin, Manocha, "Fast proximity queries with
/// swept sphere volumes", UNC TR99-018, 1999, with one side a single volume): depth first, the child with the
/// smaller lower bound first (mesh_convex/shape_bound.hpp: the node's bound to the shape's box, swept sphere or
/// k-DOP), every node whose bound reaches the best distance so far skipped. The descent towards the nearer child
/// finds a small upper bound early, which then prunes almost all of the rest. Triangle distances come from the
/// exact sphere / capsule tests or GJK (mesh_convex/triangle_shape.hpp); before a GJK run, a triangle whose plane
/// lies at least the best distance beyond the shape's extent along its normal (two support queries) is skipped
/// (stats.primitive_skips). A node is pruned when its bound is at
/// least (best − abs_err)/(1 + rel_err), so the answer is within DistanceRequest's errors; with both 0 it is the
/// minimum over every triangle of the same per-triangle distance that distance_brute_force() takes.

#include "cdkit/mesh_convex/collide.hpp"

#include <utility>

namespace cdkit {
namespace detail {

template <SupportMapped C, class S>
inline void mesh_convex_distance_triangle(const TriangleMesh<S>& mesh, Index t, const C& shape,
                                          const ShapeBound<S>& bound, MeshConvexDistanceResult<S>& out,
                                          bool skip_far = false) noexcept {
    const auto& tri = mesh.triangles[t];
    if constexpr (!is_sphere_v<C> && !is_capsule_v<C>) {
        // Two lower bounds on the triangle's distance, each one to three support queries: the centre gap towards
        // the triangle's point nearest the shape's centre, and the plane gap. At or beyond the best, GJK could
        // not lower it.
        const Vec3<S>&v0 = mesh.vertices[tri[0]], &v1 = mesh.vertices[tri[1]], &v2 = mesh.vertices[tri[2]];
        if (skip_far && out.distance < std::numeric_limits<S>::infinity() &&
            (bound.centre_gap(closest_on_triangle(bound.center, v0, v1, v2)) >= out.distance ||
             plane_gap(v0, v1, v2, shape, bound) >= out.distance)) {
            ++out.stats.primitive_skips;
            return;
        }
    }
    ++out.stats.primitive_tests;
    const TriangleShapeDistance<S> d =
        triangle_shape_distance(mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]], shape, bound);
    if (d.distance < out.distance) {
        out.distance = d.distance;
        out.point_mesh = d.on_triangle;  // mesh frame until the query ends
        out.point_shape = d.on_shape;
        out.triangle = t;
    }
}

template <class S> inline void mesh_convex_distance_finish(const Transform<S>& pose_mesh, MeshConvexDistanceResult<S>& out) noexcept {
    out.colliding = out.distance == S(0);
    out.point_mesh = pose_mesh * out.point_mesh;
    out.point_shape = pose_mesh * out.point_shape;
}

}  // namespace detail

/// Distance between the triangles of `mesh` (model frame → world by `pose_mesh`) and the convex `shape` (local
/// frame → world by `pose_shape`), with the closest points (world frame) and the mesh triangle that attains it;
/// 0 and `colliding` when a triangle touches or crosses the shape (a shape wholly inside a closed mesh is at the
/// distance of the nearest triangle: this is a surface query). The answer satisfies
/// distance ≤ (1 + rel_err)·true + abs_err for `request`'s errors (both 0 by default: the minimum over every
/// triangle); with `request.max_distance`, a mesh and shape farther apart than that answer +inf (DistanceRequest).
/// Any BV with a NodeTester and any support-mapped shape; status invalid_pose / invalid_input as for collide(), then
/// distance stays +inf (also for a request out of range: invalid_input). Const and thread-safe;
/// never throws except std::bad_alloc where a degenerate tree is deeper than 64 levels (the stack spills).
template <class BV, class M, SupportMapped C>
    requires std::same_as<typename C::Scalar, M>
[[nodiscard]] MeshConvexDistanceResult<M> distance(const MeshModel<BV, M>& mesh,
                                                   const std::type_identity_t<Transform<M>>& pose_mesh, const C& shape,
                                                   const std::type_identity_t<Transform<M>>& pose_shape,
                                                   const DistanceRequest<M>& request = {}) {
    using S = M;
    MeshConvexDistanceResult<S> out;
    detail::ShapeBound<S> bound;
    out.status = detail::mesh_convex_setup(pose_mesh, shape, pose_shape, bound);
    if (out.status == QueryStatus::ok && !detail::distance_request_is_valid(request))
        out.status = QueryStatus::invalid_input;
    if (out.status != QueryStatus::ok) return out;
    const auto& nodes = mesh.bvh().nodes();
    const auto& order = mesh.bvh().triangle_order();
    if (nodes.empty()) return out;
    const detail::NodeTester<BV, S> tester(bound, shape);
    const detail::DistancePruning<S> pruning(request);
    auto threshold = [&] { return pruning.threshold(out.distance); };
    struct Open {
        std::uint32_t node;
        S bound;
    };
    detail::SmallStack<Open, 64> stack;
    ++out.stats.bv_tests;
    stack.push({0, tester.lower_bound(nodes[0].bv, std::numeric_limits<S>::infinity())});
    while (!stack.empty()) {
        const Open o = stack.pop();
        if (o.bound >= threshold()) continue;
        const BvhNode<BV>& node = nodes[o.node];
        if (node.is_leaf()) {
            for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
                detail::mesh_convex_distance_triangle(mesh.mesh(), order[i], shape, bound, out, true);
            if (out.distance == S(0)) break;  // nothing is nearer than touching
            continue;
        }
        const S cut = threshold();
        out.stats.bv_tests += 2;
        Open a{node.first, tester.lower_bound(nodes[node.first].bv, cut)};
        Open b{node.first + 1, tester.lower_bound(nodes[node.first + 1].bv, cut)};
        if (b.bound < a.bound) std::swap(a, b);
        // The farther child waits below the nearer one (depth first, nearer first).
        if (b.bound < cut) stack.push(b);
        if (a.bound < cut) stack.push(a);
    }
    if (detail::beyond_max_distance(out.distance, request)) return MeshConvexDistanceResult<S>{.stats = out.stats};
    detail::mesh_convex_distance_finish(pose_mesh, out);
    return out;
}

/// The reference: the distance of every triangle of `mesh` to `shape`, the smallest kept (first index on ties).
template <class S, SupportMapped C>
    requires std::same_as<typename C::Scalar, S>
[[nodiscard]] MeshConvexDistanceResult<S> distance_brute_force(const TriangleMesh<S>& mesh, const Transform<S>& pose_mesh,
                                                               const C& shape, const Transform<S>& pose_shape) noexcept {
    MeshConvexDistanceResult<S> out;
    detail::ShapeBound<S> bound;
    out.status = detail::mesh_convex_setup(pose_mesh, shape, pose_shape, bound);
    if (out.status != QueryStatus::ok) return out;
    for (Index t = 0; t < mesh.triangles.size(); ++t) detail::mesh_convex_distance_triangle(mesh, t, shape, bound, out);
    detail::mesh_convex_distance_finish(pose_mesh, out);
    return out;
}

}  // namespace cdkit
