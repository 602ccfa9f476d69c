#pragma once
/// \file collide(): mesh–mesh collision on every tree of the family (MeshModel<BV, M> of any bounding volume,
/// RestrictedBoxtree<S>), through the one simultaneous descent of bvh/traverse.hpp, and
/// collide_brute_force(), the all-pairs reference.
///
/// Both work in A's model frame: B's triangles are carried there by the relative transform
/// pose_a⁻¹·pose_b, computed once per query, and no mesh is copied or re-transformed as a whole.
/// Queries are const and thread-safe: any number of threads may query the same models at once.

#include "cdkit/bvh/boxtree_descent.hpp"
#include "cdkit/bvh/bvh_descent.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/bvh/traverse.hpp"
#include "cdkit/core/collision_result.hpp"
#include "cdkit/narrowphase/triangle.hpp"

#include <concepts>
#include <limits>
#include <type_traits>
#include <vector>

namespace cdkit {

namespace detail {
/// Tests triangle ta of A against tb of B (already in A's frame) and records a contact on a hit.
template <class S>
inline bool test_triangle_pair(const TriangleMesh<S>& ma, Index ta, const TriangleMesh<S>& mb, Index tb,
                               const Transform<S>& b_to_a, const Transform<S>& pose_a,
                               CollisionResult<S>& out) noexcept {
    const auto& A = ma.triangles[ta];
    const auto& B = mb.triangles[tb];
    const Vec3<S> q0 = to_frame_a(b_to_a, mb.vertices[B[0]]);
    const Vec3<S> q1 = to_frame_a(b_to_a, mb.vertices[B[1]]);
    const Vec3<S> q2 = to_frame_a(b_to_a, mb.vertices[B[2]]);
    ++out.stats.primitive_tests;
    const Vec3<S>& p0 = ma.vertices[A[0]];
    const Vec3<S>& p1 = ma.vertices[A[1]];
    const Vec3<S>& p2 = ma.vertices[A[2]];
    if (!triangles_intersect(p0, p1, p2, q0, q1, q2)) return false;
    const TriangleIntersection<S> x = triangle_intersection(p0, p1, p2, q0, q1, q2);
    Contact<S> c;
    c.triangle_a = ta;
    c.triangle_b = tb;
    c.segment[0] = pose_a * x.a;
    c.segment[1] = pose_a * x.b;
    c.point = (c.segment[0] + c.segment[1]) * S(0.5);
    c.coplanar = x.coplanar;
    out.colliding = true;
    out.contacts.push_back(c);
    return true;
}

/// After a hit: should the query go on?
template <class S> [[nodiscard]] inline bool keep_going(const CollisionRequest& req, CollisionResult<S>& out) noexcept {
    if (req.mode == ContactMode::first) return false;
    if (out.contacts.size() >= req.max_contacts) {
        out.truncated = true;
        return false;
    }
    return true;
}
}  // namespace detail

/// Two models collide() and distance() descend together: a mesh (`mesh()`) and a tree the simultaneous
/// descent walks (bvh/traverse.hpp), of one mesh scalar: MeshModel<BV, M> (any BV of the family, float BVs
/// over a double mesh included; two different BVs of one scalar descend as boxes, bvh/mixed_descent.hpp) and
/// RestrictedBoxtree<S>, each against its own kind.
template <class A, class B>
concept DescentModels = std::same_as<typename A::Scalar, typename B::Scalar> &&
                        requires(const A& a, const B& b, const Transform<typename A::Scalar>& b_to_a) {
    { a.mesh() } -> std::same_as<const TriangleMesh<typename A::Scalar>&>;
    { b.mesh() } -> std::same_as<const TriangleMesh<typename A::Scalar>&>;
    { detail::descent_pair(a, b, b_to_a) } -> DescentPair;
};

/// Collision between two mesh models at the given world poses (model frame → world). Reports whether any
/// triangle of A intersects any triangle of B (touching counts), with one witness (ContactMode::first) or
/// all intersecting pairs (ContactMode::all, in traversal order). Contacts are in the world frame.
/// Poses that are not rigid motions (see pose_is_usable) give status invalid_pose and no answer.
/// The poses' scalar is the models' mesh scalar (never deduced from the poses); with float BVs over double
/// meshes the BV tests run in float (see MeshModel). On restricted boxtrees `stats.bv_tests` counts descent
/// steps (each a re-aligned face test), the root's 15-axis box test and the leaf pairs' triangle box tests.
template <class A, class B>
    requires DescentModels<A, B>
[[nodiscard]] CollisionResult<typename A::Scalar> collide(const A& a, const std::type_identity_t<Transform<typename A::Scalar>>& pose_a,
                                                          const B& b, const std::type_identity_t<Transform<typename A::Scalar>>& pose_b,
                                                          const CollisionRequest& request = {}) {
    using S = typename A::Scalar;
    CollisionResult<S> out;
    if (!pose_is_usable(pose_a) || !pose_is_usable(pose_b)) {
        out.status = QueryStatus::invalid_pose;
        return out;
    }
    const Transform<S> b_to_a = pose_a.inverse() * pose_b;
    const auto pair = detail::descent_pair(a, b, b_to_a);
    const auto& ma = a.mesh();
    const auto& mb = b.mesh();
    traverse_overlapping_leaves(
        pair,
        [&](const auto& x, const auto& y) {
            return pair.a.for_each_triangle(x, [&](Index ta) {
                return pair.b.for_each_triangle(y, [&](Index tb) {
                    return !(detail::test_triangle_pair(ma, ta, mb, tb, b_to_a, pose_a, out) && !detail::keep_going(request, out));
                });
            });
        },
        out.stats);
    return out;
}

/// The reference: every triangle pair, in index order. O(n·m); for tests and small meshes.
template <class S>
[[nodiscard]] CollisionResult<S> collide_brute_force(const TriangleMesh<S>& a, const Transform<S>& pose_a,
                                                     const TriangleMesh<S>& b, const Transform<S>& pose_b,
                                                     const CollisionRequest& request = {}) {
    CollisionResult<S> out;
    if (!pose_is_usable(pose_a) || !pose_is_usable(pose_b)) {
        out.status = QueryStatus::invalid_pose;
        return out;
    }
    const Transform<S> b_to_a = pose_a.inverse() * pose_b;
    for (Index i = 0; i < a.triangles.size(); ++i)
        for (Index j = 0; j < b.triangles.size(); ++j)
            if (detail::test_triangle_pair(a, i, b, j, b_to_a, pose_a, out) && !detail::keep_going(request, out))
                return out;
    return out;
}

}  // namespace cdkit
