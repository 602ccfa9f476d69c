#pragma once
/// \file Time of impact of two triangle meshes, each moving with constant linear and angular velocity over a step
/// (a screw-like motion: the origin on a line, the rotation about one fixed axis at a constant rate): conservative
/// advancement (B. Mirtich, PhD thesis, UC Berkeley 1996) on the BVH distance of distance.hpp.
///
/// mesh_ccd (mesh_ccd.hpp) moves every vertex on a straight line between its two posed positions, which is exact
/// for that motion but not for a rotation, whose vertices travel on arcs. This query follows the rigid motion
/// itself: no distance between a point of A and a point of B shrinks faster than
/// μ = |v_a − v_b| + |ω_a|·r_a + |ω_b|·r_b (r each mesh's radius about its origin), so nothing touches before
/// t + d/μ, and the query advances there until the distance falls to the tolerance.

#include "cdkit/ccd/convex_toi.hpp"
#include "cdkit/distance.hpp"

namespace cdkit {

/// First time in [0, 1] at which `a` (moving from a_start to a_end) and `b` (b_start to b_end) come within
/// request.tolerance. `point_a` / `point_b` are the closest points at that time (world), `normal` points from a to
/// b. Any BV that `distance()` takes. Status invalid_pose / invalid_input as convex_toi's. Const, thread-safe.
template <class BV>
[[nodiscard]] ToiResult mesh_toi(const MeshModel<BV, double>& a, const Transform<double>& a_start,
                                 const Transform<double>& a_end, const MeshModel<BV, double>& b,
                                 const Transform<double>& b_start, const Transform<double>& b_end,
                                 const ToiRequest& request = {}) {
    ToiResult out;
    out.status = detail::toi_inputs_usable({&a_start, &a_end, &b_start, &b_end}, request);
    if (out.status != QueryStatus::ok) return out;
    const detail::PoseMotion ma(a_start, a_end), mb(b_start, b_end);
    const double radius_a = detail::turning_radius(a.mesh(), ma), radius_b = detail::turning_radius(b.mesh(), mb);
    return detail::advance(ma, mb, radius_a, radius_b, false, request, [&](const Transform<double>& pa, const Transform<double>& pb) {
        const DistanceResult<double> d = distance(a, pa, b, pb);
        detail::AdvanceStep step;
        step.contact = d.status != QueryStatus::ok || d.distance == 0;
        step.distance = d.distance;
        step.point_a = d.point_a;
        step.point_b = d.point_b;
        if (d.distance > 0 && std::isfinite(d.distance)) step.normal = (d.point_b - d.point_a) / d.distance;
        return step;
    });
}

}  // namespace cdkit
