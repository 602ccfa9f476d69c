#pragma once
/// \file Ray cast against a support-mapped convex shape: the shape cast of a point, by conservative advancement
/// (B. Mirtich, PhD thesis, UC Berkeley 1996; for rays and GJK see G. van den Bergen, "Ray Casting against General
/// Convex Objects with Application to Continuous Collision Detection", 2004, who advances the same way along the
/// ray with the support-plane bound).
///
/// The ray's point x(t) = origin + t·direction moves towards the shape; GJK gives its distance d to the shape and
/// the direction n from the point to its closest point. No point of the shape is nearer along n than d, and x
/// gains on the shape along n at most at rate direction·n per unit of t, so nothing is hit before t + d/(direction·n):
/// the cast advances there and repeats until d is within the tolerance (a hit, never later than the true one) or
/// direction·n ≤ 0 (the ray moves away from a separating plane: a miss). Every step is certified by GJK's distance,
/// so a ray never passes through a shape, however thin.

#include "cdkit/ccd/ray_cast.hpp"
#include "cdkit/narrowphase/gjk.hpp"

#include <algorithm>
#include <cmath>

namespace cdkit {

struct ConvexRayRequest {
    /// A hit when the ray's point comes within this distance of the shape (absolute, > 0). The reported t is never
    /// later than the first exact contact; for a ray meeting the surface at angle θ it is earlier by at most about
    /// tolerance / (|direction|·sin θ).
    double tolerance = 1e-9;
    int max_iterations = 256;  ///< advancement steps before the cast gives up (then `capped`, a hit is assumed)
};

namespace detail {

/// A point at the origin of its frame: the ray's moving point as a shape GJK can take.
struct RayPoint {
    using Scalar = double;
    [[nodiscard]] Vec3<double> support(const Vec3<double>&) const noexcept { return Vec3<double>::Zero(); }
    [[nodiscard]] Vec3<double> center() const noexcept { return Vec3<double>::Zero(); }
};

}  // namespace detail

/// Casts `ray` (world) against `shape` placed by `pose`: the first t in [t_min, t_max] at which the ray's point
/// comes within request.tolerance of the shape (`RayMode` does not apply: a convex shape is entered once). The hit
/// has t, point (on the ray), normal (unit, the shape's outward direction towards the ray's point there; for a ray
/// starting inside, the reversed direction) and triangle = u = v = 0; `triangle_tests` counts the GJK distance
/// queries. Status invalid_pose / invalid_input for a pose that is not a
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
    const detail::RayPoint point;
    GjkCache<double> cache;
    double t = std::max(ray.t_min, -std::numeric_limits<double>::max());
    if (!(t <= ray.t_max)) return out;
    for (int it = 0; it < request.max_iterations; ++it) {
        Transform<double> at;
        at.t = ray.origin + t * ray.direction;
        if (!at.t.allFinite()) return out;  // the ray ran past the range of doubles without reaching the shape
        const GjkResult<double> g = gjk_distance(point, at, shape, pose, &cache);
        ++out.triangle_tests;
        if (g.colliding || g.status == GjkStatus::max_iterations || g.status == GjkStatus::degenerate ||
            g.distance <= request.tolerance) {
            RayHit h;
            h.t = t;
            h.point = at.t;
            // g.normal points from the ray's point to the shape; the shape's outward normal there is its reverse.
            h.normal = g.status == GjkStatus::separated || g.normal.squaredNorm() > 0 ? Vec3<double>(-g.normal)
                                                                                        : Vec3<double>(-ray.direction / speed);
            out.hit = true;
            out.hits.push_back(h);
            return out;
        }
        // GJK's distance holds to its relative tolerance: advance by slightly less.
        const double approach = ray.direction.dot(g.normal);
        if (!(approach > 0)) return out;  // moving away from the separating plane through the closest point
        t += (g.distance * (1 - 1e-8) - request.tolerance * 0.5) / approach;
        if (!(t <= ray.t_max)) return out;
    }
    // Out of steps: a hit is assumed at the last certified time (conservative, as convex_toi).
    RayHit h;
    h.t = t;
    h.point = ray.origin + t * ray.direction;
    h.normal = -ray.direction / speed;
    out.hit = true;
    out.capped = true;
    out.hits.push_back(h);
    return out;
}

}  // namespace cdkit
