#pragma once
/// \file Time of impact of a triangle mesh and a convex shape, each moving with constant linear and angular
/// velocity over a step: conservative advancement (B. Mirtich, PhD thesis, UC Berkeley 1996) on the mesh–convex
/// distance through the mesh's BVH (mesh_convex/distance.hpp).
///
/// The plane through the closest points does not separate a non-convex mesh from the shape, so the approach bound
/// is the one that holds for any pair of points: no distance between a point of the mesh and a point of the shape
/// shrinks faster than μ = |v_mesh − v_shape| + |ω_mesh|·r_mesh + |ω_shape|·r_shape (r about each object's origin),
/// and the query advances by d/μ until d falls to the tolerance. A surface query, as the discrete one: a shape
/// moving wholly inside a closed mesh without meeting a triangle is not a contact.

#include "cdkit/ccd/convex_toi.hpp"
#include "cdkit/mesh_convex/distance.hpp"

#include <algorithm>
#include <cmath>

namespace cdkit {

/// First time in [0, 1] at which `mesh` (moving from pose mesh_start to mesh_end) and `shape` (shape_start to
/// shape_end) come within request.tolerance. `point_a` lies on the mesh, `point_b` on the shape, `normal` points
/// from the mesh to the shape. The mesh's radius about its origin is measured once per query (O(vertices)) when
/// the mesh turns. Status invalid_pose / invalid_input as convex_toi's. Const, thread-safe.
template <class BV, SupportMapped C>
    requires std::same_as<typename C::Scalar, double>
[[nodiscard]] ToiResult mesh_convex_toi(const MeshModel<BV, double>& mesh, const Transform<double>& mesh_start,
                                        const Transform<double>& mesh_end, const C& shape,
                                        const Transform<double>& shape_start, const Transform<double>& shape_end,
                                        const ToiRequest& request = {}) {
    ToiResult out;
    out.status = detail::toi_inputs_usable({&mesh_start, &mesh_end, &shape_start, &shape_end}, request);
    if (out.status != QueryStatus::ok) return out;
    const detail::PoseMotion mm(mesh_start, mesh_end), ms(shape_start, shape_end);
    bool bad_input = false;
    const double mesh_radius = detail::turning_radius(mesh.mesh(), mm), shape_radius = detail::radius_about_origin(shape);
    ToiResult r = detail::advance(mm, ms, mesh_radius, shape_radius, false, request, [&](const Transform<double>& pm, const Transform<double>& pc) {
        const MeshConvexDistanceResult<double> d = distance(mesh, pm, shape, pc);
        detail::AdvanceStep step;
        if (d.status != QueryStatus::ok) {  // a shape with non-finite sizes: stop, answered below
            bad_input = true;
            step.contact = true;
            return step;
        }
        step.contact = d.colliding;
        step.distance = d.distance;
        step.point_a = d.point_mesh;
        step.point_b = d.point_shape;
        if (d.distance > 0) step.normal = (d.point_shape - d.point_mesh) / d.distance;
        return step;
    });
    if (bad_input) {
        out.status = QueryStatus::invalid_input;
        return out;
    }
    return r;
}

}  // namespace cdkit
