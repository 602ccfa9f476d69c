#pragma once
/// \file penetration(mesh, pose, shape, pose): for each mesh triangle that touches or crosses a convex shape, the
/// depth and normal of their overlap (the deepest one, or all).
///
/// Method: collide()'s descent (mesh_convex/collide.hpp) finds the touching triangles; for each, EPA between the
/// triangle and the shape (van den Bergen, "Proximity queries and penetration depth computation on 3D game
/// objects", GDC 2001; narrowphase/epa.hpp) gives the shortest translation of the shape that separates it from
/// that triangle. What the depth means: a triangle is a flat piece of the surface, so this is the depth against
/// each triangle alone, not against the volume a closed mesh bounds (a shape pushed far into a closed mesh
/// touches no triangle and has no contact here; for volume depth see the inner sphere trees, docs/ist.md).
/// It is what a simulation's contact solver wants per surface triangle: a depth and a push-out direction.

#include "cdkit/mesh_convex/collide.hpp"

namespace cdkit {

/// Penetration between the triangles of `mesh` (model frame → world by `pose_mesh`) and the convex `shape` (local
/// frame → world by `pose_shape`): every touching triangle's depth, normal (world frame, from the triangle towards
/// the shape) and deepest points, keeping the deepest only (`request.mode == ContactMode::first`) or all
/// (`ContactMode::all`, up to max_contacts). Status as for collide(). Const and thread-safe; never throws except
/// std::bad_alloc for the contacts.
template <class BV, class M, SupportMapped C>
    requires std::same_as<typename C::Scalar, M>
[[nodiscard]] MeshConvexPenetrationResult<M> penetration(const MeshModel<BV, M>& mesh,
                                                         const std::type_identity_t<Transform<M>>& pose_mesh,
                                                         const C& shape,
                                                         const std::type_identity_t<Transform<M>>& pose_shape,
                                                         const MeshConvexRequest& request = {}) {
    using S = M;
    MeshConvexPenetrationResult<S> out;
    detail::ShapeBound<S> bound;
    out.status = detail::mesh_convex_setup(pose_mesh, shape, pose_shape, bound);
    if (out.status != QueryStatus::ok) return out;
    const auto& m = mesh.mesh();
    const detail::NodeTester<BV, S> tester(bound, shape);
    detail::for_each_candidate_triangle(mesh, tester, out.stats, [&](Index t) {
        const auto& tri = m.triangles[t];
        const Vec3<S>&v0 = m.vertices[tri[0]], &v1 = m.vertices[tri[1]], &v2 = m.vertices[tri[2]];
        ++out.stats.primitive_tests;
        if (!detail::triangle_touches(v0, v1, v2, shape, bound, static_cast<Vec3<S>*>(nullptr))) return true;
        const ConvexTriangle<S> ct(v0, v1, v2);
        const PenetrationResult<S> p = cdkit::penetration(ct, pose_mesh, shape, pose_shape);
        MeshConvexPenetration<S> c;
        c.triangle = t;
        c.depth = p.status == GjkStatus::separated ? S(0) : p.depth;  // touching within the tests' rounding
        c.normal = p.normal;
        c.point_mesh = p.point_a;
        c.point_shape = p.point_b;
        if (!out.colliding || c.depth > out.deepest.depth) out.deepest = c;
        out.colliding = true;
        if (request.mode != ContactMode::all) return true;
        out.contacts.push_back(c);
        if (out.contacts.size() < request.max_contacts) return true;
        out.truncated = true;
        return false;
    });
    if (out.colliding && request.mode == ContactMode::first) out.contacts.push_back(out.deepest);
    return out;
}

}  // namespace cdkit
