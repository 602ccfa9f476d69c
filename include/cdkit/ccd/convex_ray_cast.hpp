#pragma once
/// \file Ray cast against a support-mapped convex shape: a GJK ray cast (G. van den Bergen, "Ray Casting against
/// General Convex Objects with Application to Continuous Collision Detection", 2004; ccd/detail/gjk_ray_cast.hpp),
/// the same loop convex_toi's shape cast runs.
///
/// The ray's point x(t) = origin + t·direction moves towards the shape. First the ray is clipped to the shape's
/// bounding ball about its origin (a ray that misses the ball misses the shape; one that starts far away starts at
/// the ball). Then one GJK loop on the shape minus the ray's start: whenever the shape's support plane along the
/// current direction has x in front of it, t jumps to that plane (a lower bound: the shape lies behind it), until x is
/// within the tolerance of the shape (a hit, never later than the true one) or x runs parallel to or away from a
/// separating plane (a miss). Every advance is a support plane of the shape, so a ray never passes through a shape,
/// however thin.

#include "cdkit/ccd/convex_toi.hpp"
#include "cdkit/ccd/detail/gjk_ray_cast.hpp"
#include "cdkit/ccd/ray_cast.hpp"
#include "cdkit/narrowphase/gjk.hpp"

#include <algorithm>
#include <cmath>

namespace cdkit {

struct ConvexRayRequest {
    /// A hit when the ray's point comes within this distance of the shape (absolute, > 0): always when it comes
    /// within half of it (the cast steps past a support plane while the point is more than tolerance / 2 in front),
    /// not when it stays farther than it (unless `capped`). The reported t is never later than the first exact
    /// contact; for a ray meeting the surface at angle θ it is earlier by at most about tolerance / (|direction|·sin θ).
    double tolerance = 1e-9;
    int max_iterations = 256;  ///< GJK iterations before the cast gives up (then `capped`, a hit is assumed)
};

/// Casts `ray` (world) against `shape` placed by `pose`: the first t in [t_min, t_max] at which the ray's point
/// comes within request.tolerance of the shape (`RayMode` does not apply: a convex shape is entered once). The hit
/// has t, point (on the ray), normal (unit, the shape's outward direction towards the ray's point there; for a ray
/// starting inside, the reversed direction) and triangle = u = v = 0; `triangle_tests` counts the ray cast's GJK
/// iterations. Status invalid_pose / invalid_input for a pose that is not a
/// rigid motion, a NaN or zero direction, NaN bounds or bad settings. Const, noexcept, thread-safe.
template <SupportMapped A>
    requires std::same_as<typename A::Scalar, double>
[[nodiscard]] RayCastResult ray_cast(const A& shape, const Transform<double>& pose, const Ray& ray,
                                     const ConvexRayRequest& request = {}) noexcept {
    RayCastResult out;
    if (!pose_is_usable(pose)) {
        out.status = QueryStatus::invalid_pose;
        return out;
    }
    const double speed = ray.direction.norm();
    if (!ray.origin.allFinite() || !ray.direction.allFinite() || !(speed > 0) || std::isnan(ray.t_min) ||
        std::isnan(ray.t_max) || !(request.tolerance > 0) || !std::isfinite(request.tolerance) ||
        request.max_iterations < 1) {
        out.status = QueryStatus::invalid_input;
        return out;
    }
    // The bounding ball about the shape's origin, grown by the tolerance: a hit, if any, lies where the ray is in it.
    const double radius = detail::radius_about_origin(shape) + request.tolerance;
    const Vec3<double> to_centre = pose.t - ray.origin;
    const double along = to_centre.dot(ray.direction) / (speed * speed);
    const double off2 = (to_centre - along * ray.direction).squaredNorm(), r2 = radius * radius;
    if (off2 > r2) return out;  // the ray's line misses the ball
    const double half = std::sqrt((r2 - off2) / (speed * speed));
    const double t0 = std::max(ray.t_min, along - half);
    if (!(t0 <= std::min(ray.t_max, along + half))) return out;  // the ball lies outside [t_min, t_max]
    const Vec3<double> start = ray.origin + t0 * ray.direction;
    const Vec3<double> first =
        (start - pose.t).squaredNorm() > 0 ? Vec3<double>(start - pose.t) : Vec3<double>(-ray.direction);
    const detail::GjkRayCastResult c = detail::gjk_ray_cast(
        [&](const Vec3<double>& d, Vec3<double>& a, Vec3<double>& b) {
            a = pose.R * shape.support(pose.R.transpose() * d) + pose.t;
            b = start;
        },
        ray.direction, first, ray.t_max - t0, request.tolerance, request.max_iterations);
    out.triangle_tests = std::uint64_t(c.iterations);
    if (c.end == detail::GjkRayCastResult::End::miss) return out;
    RayHit h;
    h.t = t0 + c.lambda;
    h.point = start + c.lambda * ray.direction;
    // c.normal points from the shape to the ray's point: the shape's outward normal there; for a ray starting
    // inside, the reversed direction.
    h.normal = c.normal.squaredNorm() > 0 ? c.normal : Vec3<double>(-ray.direction / speed);
    out.hit = true;
    out.capped = c.end == detail::GjkRayCastResult::End::capped;
    out.hits.push_back(h);
    return out;
}

}  // namespace cdkit
