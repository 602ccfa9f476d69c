#pragma once
/// \file collide(mesh, pose, shape, pose): which triangles of a MeshModel touch or cross a convex shape, through
/// the mesh's BVH; collide_brute_force(), the reference that tests every triangle.
///
/// Method: the shape's bound is carried into the mesh's model frame once per query (mesh_convex/shape_bound.hpp:
/// its local box as an oriented box, or the exact swept sphere of a sphere or capsule, or its own k-DOP), the tree
/// is descended depth first with every node tested against it (Gottschalk, Lin, Manocha, "OBBTree", SIGGRAPH
/// 1996, with one side a single volume), and the triangles of the leaves reached are tested against the shape
/// (mesh_convex/triangle_shape.hpp: exact sphere and capsule tests, GJK for every other shape). No mesh or shape is
/// copied or transformed as a whole. Touching counts as colliding. A shape lying wholly inside a closed mesh
/// touches no triangle and is not reported (this is a surface query).

#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/bvh/traverse.hpp"
#include "cdkit/mesh_convex/result.hpp"
#include "cdkit/mesh_convex/shape_bound.hpp"
#include "cdkit/mesh_convex/triangle_shape.hpp"

#include <concepts>
#include <cstdint>
#include <type_traits>

namespace cdkit {
namespace detail {

/// The checks every mesh–convex query makes before any work: rigid poses, a finite shape. Returns the status and,
/// when ok, the shape's bound in the mesh frame.
template <SupportMapped C, class S>
[[nodiscard]] QueryStatus mesh_convex_setup(const Transform<S>& pose_mesh, const C& shape, const Transform<S>& pose_shape,
                                            ShapeBound<S>& bound) noexcept {
    if (!pose_is_usable(pose_mesh) || !pose_is_usable(pose_shape)) return QueryStatus::invalid_pose;
    bound = make_shape_bound(shape, relative_pose(pose_mesh, pose_shape));
    if (!bound.finite) return QueryStatus::invalid_input;
    if constexpr (is_sphere_v<C> || is_capsule_v<C>)
        if (!(bound.radius >= S(0)) || !bound.seg0.allFinite() || !bound.seg1.allFinite()) return QueryStatus::invalid_input;
    return QueryStatus::ok;
}

/// Records a touching triangle; returns whether the query goes on.
template <class S>
[[nodiscard]] inline bool mesh_convex_record(Index t, const Vec3<S>& point, const Transform<S>& pose_mesh,
                                             const MeshConvexRequest& req, MeshConvexResult<S>& out) {
    out.colliding = true;
    out.contacts.push_back({t, req.witness_points ? Vec3<S>(pose_mesh * point) : Vec3<S>::Zero()});
    if (req.mode == ContactMode::first) return false;
    if (out.contacts.size() >= req.max_contacts) {
        out.truncated = true;
        return false;
    }
    return true;
}

template <SupportMapped C, class S>
[[nodiscard]] inline bool mesh_convex_test_triangle(const TriangleMesh<S>& mesh, Index t, const C& shape,
                                                    const ShapeBound<S>& bound, const Transform<S>& pose_mesh,
                                                    const MeshConvexRequest& req, MeshConvexResult<S>& out) {
    const auto& tri = mesh.triangles[t];
    Vec3<S> witness = Vec3<S>::Zero();
    ++out.stats.primitive_tests;
    if (!triangle_touches(mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]], shape, bound,
                          req.witness_points ? &witness : nullptr))
        return true;
    return mesh_convex_record(t, witness, pose_mesh, req, out);
}

/// A node tester that can test both children of a node at once (NodeTester<Obb>: two SIMD lanes), where its
/// `tests_siblings()` says so for the shape at hand.
template <class Tester, class BV>
concept TestsSiblings = requires(const Tester& t, const BV& v) {
    { t.children_overlap(v, v).second_first } -> std::convertible_to<bool>;
    { t.tests_siblings() } -> std::convertible_to<bool>;
};

/// The descent every mesh–convex query but distance makes: depth first through the nodes whose BV `tester` finds
/// overlapping the shape's bound, `visit(triangle)` on each triangle of the leaves reached until it returns false.
/// Where the tester takes both children of a node in one test, each node is tested when its parent is split and
/// the deeper-overlapping child is entered first (as the mesh–mesh descent, bvh/traverse.hpp); otherwise each node
/// is tested when it is taken from the stack.
template <class BV, class M, class Tester, class Visit>
void for_each_candidate_triangle(const MeshModel<BV, M>& mesh, const Tester& tester, TraversalStats& stats,
                                 Visit&& visit) {
    const auto& nodes = mesh.bvh().nodes();
    const auto& order = mesh.bvh().triangle_order();
    if (nodes.empty()) return;
    SmallStack<std::uint32_t, 64> stack;
    if constexpr (TestsSiblings<Tester, BV>) {
        if (tester.tests_siblings()) {
            ++stats.bv_tests;
            if (!tester.overlaps(nodes[0].bv)) return;
            std::uint32_t at = 0;
            for (;;) {
                const BvhNode<BV>& node = nodes[at];
                if (node.is_leaf()) {
                    ++stats.leaf_pairs;
                    for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
                        if (!visit(order[i])) return;
                } else {
                    const std::uint32_t c = node.first;  // the children are c and c + 1
                    const SiblingOverlap s = tester.children_overlap(nodes[c].bv, nodes[c + 1].bv);
                    stats.bv_tests += 2;
                    if (s.overlap[0] && s.overlap[1]) {
                        stack.push(s.second_first ? c : c + 1);
                        at = s.second_first ? c + 1 : c;
                        continue;
                    }
                    if (s.overlap[0] || s.overlap[1]) {
                        at = s.overlap[0] ? c : c + 1;
                        continue;
                    }
                }
                if (stack.empty()) return;
                at = stack.pop();
            }
        }
    }
    stack.push(0);
    while (!stack.empty()) {
        const BvhNode<BV>& node = nodes[stack.pop()];
        ++stats.bv_tests;
        if (!tester.overlaps(node.bv)) continue;
        if (!node.is_leaf()) {
            stack.push(node.first + 1);
            stack.push(node.first);
            continue;
        }
        ++stats.leaf_pairs;
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
            if (!visit(order[i])) return;
    }
}

}  // namespace detail

/// Collision between the triangles of `mesh` (model frame → world by `pose_mesh`) and the convex `shape` (its
/// local frame → world by `pose_shape`): whether any triangle touches or crosses the shape, with the first touching
/// triangle found (ContactMode::first) or all of them (ContactMode::all, in traversal order), each with a witness
/// point in the world frame (MeshConvexRequest::witness_points). Works for a tree of any BV with a NodeTester
/// (Aabb, Obb, Rss, Kdop<K>, BoundingSphere; float BVs over double meshes too) and any support-mapped shape.
/// Poses that are not rigid give status invalid_pose, a shape whose support map answers non-finite points
/// (NaN sizes) invalid_input; nothing is tested then. Const and thread-safe: any number of threads may query the
/// same model and shape at once. Never throws except std::bad_alloc for the contacts.
template <class BV, class M, SupportMapped C>
    requires std::same_as<typename C::Scalar, M>
[[nodiscard]] MeshConvexResult<M> collide(const MeshModel<BV, M>& mesh,
                                          const std::type_identity_t<Transform<M>>& pose_mesh, const C& shape,
                                          const std::type_identity_t<Transform<M>>& pose_shape,
                                          const MeshConvexRequest& request = {}) {
    MeshConvexResult<M> out;
    detail::ShapeBound<M> bound;
    out.status = detail::mesh_convex_setup(pose_mesh, shape, pose_shape, bound);
    if (out.status != QueryStatus::ok) return out;
    const detail::NodeTester<BV, M> tester(bound, shape);
    detail::for_each_candidate_triangle(mesh, tester, out.stats, [&](Index t) {
        return detail::mesh_convex_test_triangle(mesh.mesh(), t, shape, bound, pose_mesh, request, out);
    });
    return out;
}

/// The reference: every triangle of `mesh`, in index order, with the same triangle test as collide(). O(n).
template <class S, SupportMapped C>
    requires std::same_as<typename C::Scalar, S>
[[nodiscard]] MeshConvexResult<S> collide_brute_force(const TriangleMesh<S>& mesh, const Transform<S>& pose_mesh,
                                                      const C& shape, const Transform<S>& pose_shape,
                                                      const MeshConvexRequest& request = {}) {
    MeshConvexResult<S> out;
    detail::ShapeBound<S> bound;
    out.status = detail::mesh_convex_setup(pose_mesh, shape, pose_shape, bound);
    if (out.status != QueryStatus::ok) return out;
    for (Index t = 0; t < mesh.triangles.size(); ++t)
        if (!detail::mesh_convex_test_triangle(mesh, t, shape, bound, pose_mesh, request, out)) return out;
    return out;
}

}  // namespace cdkit
