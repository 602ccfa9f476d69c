#pragma once
/// \file Time of impact of two convex shapes moving with constant linear and angular velocity over a step:
/// conservative advancement (B. Mirtich, "Impulse-based Dynamic Simulation of Rigid Body Systems", PhD thesis,
/// UC Berkeley 1996; the bound on the approach speed as in M. Tang, Y. J. Kim, D. Manocha, "C2A: Controlled
/// Conservative Advancement for Continuous Collision Detection of Polygonal Models", ICRA 2009).
///
/// Each shape's pose moves from `start` to `end`: its origin on a straight line, its rotation about one fixed
/// axis of its own frame at a constant rate (R(t) = R0·exp(t·log(R0ᵀR1))). At time t GJK gives the distance d and
/// the direction n from A to B. No point of A gains on B along n faster than
///     μ = max(0, (v_A − v_B)·n) + |n × ω_A|·r_A + |n × ω_B|·r_B
/// (v the origins' velocities, ω the angular velocities — fixed in the world frame, since each shape turns about one
/// axis at a constant rate — and r each shape's radius about that axis through its origin: a point p relative to
/// the origin moves along n at n·(ω × p) = p·(n × ω), and n × ω ⟂ ω sees only p's part off the axis), and the
/// distance is at least the gap along n, so the shapes cannot touch before t + d/μ: the query advances to there
/// and repeats, and reports contact when d falls to the tolerance. Every step is a lower bound, so a contact is
/// never skipped, whatever the shapes' sizes or speeds (only GJK's distance must be right, which it certifies).
/// A pure translation (equal rotations at both ends) is the shape cast: there a GJK ray cast (detail/gjk_ray_cast.hpp)
/// answers the same question in one GJK loop instead of a distance query per step.

#include "cdkit/ccd/ccd_result.hpp"
#include "cdkit/ccd/detail/gjk_ray_cast.hpp"
#include "cdkit/core/mesh.hpp"
#include "cdkit/narrowphase/gjk.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>

namespace cdkit {

struct ToiRequest {
    /// Contact when the distance falls to this (absolute, > 0): always reported when the shapes come within half
    /// of it (a step passes a plane only while it is over tolerance / 2 away), not when they stay farther than it
    /// (unless the query runs out of steps: `capped`).
    double tolerance = 1e-6;
    int max_iterations = 512;  ///< advancement steps before the query gives up (then `capped`, contact assumed)
    /// Contact when the distance falls to `separation` (≥ 0, finite) plus the tolerance: the time of impact of the
    /// shapes grown by it (rounded shapes, whose roundings add up to it: World), or of a gap a simulator keeps.
    /// Above 0 the query advances on distances (no ray cast); the points are the cores', `separation` apart.
    double separation = 0;
};

struct ToiResult {
    QueryStatus status = QueryStatus::ok;  ///< invalid_pose: a pose is not a rigid motion; invalid_input: settings
    bool colliding = false;                ///< the shapes come within `tolerance` during [0, 1]
    double toi = 1;  ///< no contact before this time (the advancement never passes one); 1 when none
    Vec3<double> point_a = Vec3<double>::Zero(), point_b = Vec3<double>::Zero();  ///< closest points at toi (world)
    Vec3<double> normal = Vec3<double>::Zero();  ///< unit direction from A to B at toi
    int iterations = 0;                          ///< advancement steps (one GJK distance each)
    bool capped = false;                         ///< max_iterations reached: `colliding` is the conservative answer
};

namespace detail {

/// Radius of a shape about its own origin: the corner of its local bounding box farthest from the origin (six
/// support calls; the shape lies in that box, so the radius is an upper bound).
template <SupportMapped A> [[nodiscard]] double radius_about_origin(const A& shape) noexcept {
    const auto box = support_box(shape);
    return box.lo.template cast<double>().cwiseAbs().cwiseMax(box.hi.template cast<double>().cwiseAbs()).norm() *
           (1 + 1e-12);
}

/// Radius of a shape about a line through its origin along the unit `axis` (its own frame): the farthest corner of
/// its local bounding box from that line. A shape turning about that axis moves its points at |ω| times their
/// distance from the line, so this bounds their speed more tightly than the radius about the origin.
template <SupportMapped A> [[nodiscard]] double radius_about_axis(const A& shape, const Vec3<double>& axis) noexcept {
    const auto box = support_box(shape);
    const Vec3<double> lo = box.lo.template cast<double>(), hi = box.hi.template cast<double>();
    double r2 = 0;
    for (int c = 0; c < 8; ++c) {
        const Vec3<double> p((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
        r2 = std::max(r2, (p - p.dot(axis) * axis).squaredNorm());
    }
    return std::sqrt(r2) * (1 + 1e-12);
}

/// A pose moving with constant velocities between two poses.
struct PoseMotion {
    Transform<double> start;
    Vec3<double> velocity;  ///< of the origin, per unit of t
    Vec3<double> axis;      ///< rotation axis in the shape's frame (unit)
    double angle = 0;       ///< rotation over the step (|ω|)
    PoseMotion(const Transform<double>& s, const Transform<double>& e) : start(s), velocity(e.t - s.t) {
        const Eigen::AngleAxisd aa(Mat3<double>(s.R.transpose() * e.R));
        axis = aa.axis();
        angle = std::abs(aa.angle());
        if (aa.angle() < 0) axis = -axis;
    }
    /// Angular velocity in the world frame (constant: the axis turns with the shape, but R·axis does not).
    [[nodiscard]] Vec3<double> omega() const { return start.R * axis * angle; }
    [[nodiscard]] Transform<double> at(double t) const {
        return {start.R * Eigen::AngleAxisd(t * angle, axis).toRotationMatrix(), start.t + t * velocity};
    }
};

}  // namespace detail

namespace detail {

/// One distance query of the advancement at time t: whether the objects touch (or the query could not certify
/// a separation), their distance, and the closest points and unit direction from the first to the second.
struct AdvanceStep {
    bool contact = false;
    double distance = 0;
    Vec3<double> point_a = Vec3<double>::Zero(), point_b = Vec3<double>::Zero(), normal = Vec3<double>::Zero();
};

/// Radius of a mesh about its origin when `motion` turns it (0 when it does not: a translation needs none).
/// O(vertices), once per query.
[[nodiscard]] inline double turning_radius(const TriangleMesh<double>& mesh, const PoseMotion& motion) noexcept {
    double r = 0;
    if (motion.angle > 0)
        for (const Vec3<double>& v : mesh.vertices) r = std::max(r, v.norm());
    return r * (1 + 1e-12);
}

/// The advancement loop shared by the convex, the mesh–convex and the mesh–mesh time of impact. `distance_at(pa, pb)` answers
/// at the poses of time t; `radius_a`, `radius_b` bound each object's points' distance from its rotation axis
/// through its origin (the radius about the origin does). With
/// `separating_normal` (two convex shapes) the plane through the closest points orthogonal to n separates the whole
/// shapes, so only the approach along n counts: (v_a − v_b)·n + |n × ω_a|·r_a + |n × ω_b|·r_b; otherwise (a mesh:
/// the closest pair may switch to another part) any point may approach at up to |v_a − v_b| + |ω_a|·r_a +
/// |ω_b|·r_b. Every step is a lower bound on the first contact time.
template <class DistanceAt>
[[nodiscard]] ToiResult advance(const PoseMotion& ma, const PoseMotion& mb, double radius_a, double radius_b,
                                bool separating_normal, const ToiRequest& request, DistanceAt&& distance_at) {
    ToiResult out;
    const double sweep = (ma.velocity - mb.velocity).norm();
    const Vec3<double> omega_a = ma.omega(), omega_b = mb.omega();
    const double spin = ma.angle * radius_a + mb.angle * radius_b;
    double t = 0;
    for (out.iterations = 1; out.iterations <= request.max_iterations; ++out.iterations) {
        const AdvanceStep g = distance_at(ma.at(t), mb.at(t));
        out.point_a = g.point_a, out.point_b = g.point_b, out.normal = g.normal;
        out.toi = t;
        if (g.contact || g.distance - request.separation <= request.tolerance) {
            out.colliding = true;  // contact, or a query that could not certify a separation: conservative
            return out;
        }
        // The distances hold to a relative tolerance of their query; the advancement uses a slightly smaller one.
        const double d = g.distance * (1 - 1e-8) - request.separation - request.tolerance * 0.5;
        const double approach =
            separating_normal ? std::max(0.0, (ma.velocity - mb.velocity).dot(g.normal)) +
                                    g.normal.cross(omega_a).norm() * radius_a + g.normal.cross(omega_b).norm() * radius_b
                              : sweep + spin;
        if (!(approach > 0)) {  // nothing gains on anything: the gap never closes
            out.toi = 1;
            return out;
        }
        t += d / approach;
        if (t > 1) {
            out.toi = 1;
            return out;
        }
    }
    out.capped = true;
    out.colliding = true;
    return out;
}

/// The request and poses every time-of-impact query checks first; a status other than ok ends the query.
[[nodiscard]] inline QueryStatus toi_inputs_usable(std::initializer_list<const Transform<double>*> poses,
                                                   const ToiRequest& request) noexcept {
    if (!motion_poses_usable(poses)) return QueryStatus::invalid_pose;
    if (!(request.tolerance > 0) || !std::isfinite(request.tolerance) || request.max_iterations < 1 ||
        !(request.separation >= 0) || !std::isfinite(request.separation))
        return QueryStatus::invalid_input;
    return QueryStatus::ok;
}

}  // namespace detail

namespace detail {

/// convex_toi by conservative advancement (any motion; convex_toi takes it when a shape turns).
template <SupportMapped A, SupportMapped B>
[[nodiscard]] ToiResult convex_toi_advancement(const A& a, const PoseMotion& ma, const B& b, const PoseMotion& mb,
                                               const ToiRequest& request) {
    GjkCache<double> cache;
    // Each shape turns about one axis of its own frame, so its distance from that axis bounds its points' speed.
    const double ra = ma.angle > 0 ? radius_about_axis(a, ma.axis) : 0.0;
    const double rb = mb.angle > 0 ? radius_about_axis(b, mb.axis) : 0.0;
    return advance(ma, mb, ra, rb, true, request,
                   [&](const Transform<double>& pa, const Transform<double>& pb) {
                       const GjkResult<double> g = gjk_distance(a, pa, b, pb, &cache);
                       return AdvanceStep{g.colliding || g.status == GjkStatus::max_iterations ||
                                              g.status == GjkStatus::degenerate,
                                          g.distance, g.point_a, g.point_b, g.normal};
                   });
}

/// convex_toi when neither shape turns (the shape cast): a GJK ray cast of the relative motion r = v_B − v_A
/// against A − B at the start poses (A(t) − B(t) = A − B − t·r holds the origin exactly when t·r is in A − B).
template <SupportMapped A, SupportMapped B>
[[nodiscard]] ToiResult convex_shape_cast(const A& a, const PoseMotion& ma, const B& b, const PoseMotion& mb,
                                          const ToiRequest& request) {
    const Transform<double>&pa = ma.start, &pb = mb.start;
    const Vec3<double> r = mb.velocity - ma.velocity;
    Vec3<double> start = pb.t - pa.t;  // from a point of A − B (its origins' difference) towards x = 0
    if (!(start.squaredNorm() > 0)) start = r.squaredNorm() > 0 ? Vec3<double>(-r) : Vec3<double>::UnitX();
    const GjkRayCastResult c = gjk_ray_cast(
        [&](const Vec3<double>& d, Vec3<double>& sa, Vec3<double>& sb) {
            sa = pa.R * a.support(pa.R.transpose() * d) + pa.t;
            sb = pb.R * b.support(pb.R.transpose() * -d) + pb.t;
        },
        r, start, 1.0, request.tolerance, request.max_iterations);
    ToiResult out;
    out.iterations = c.iterations;
    out.capped = c.end == GjkRayCastResult::End::capped;
    out.colliding = c.end != GjkRayCastResult::End::miss;
    out.toi = out.colliding ? c.lambda : 1.0;
    out.point_a = c.point_a + c.lambda * ma.velocity;
    out.point_b = c.point_b + c.lambda * mb.velocity;
    out.normal = c.normal;
    return out;
}

}  // namespace detail

/// First time in [0, 1] at which `a` (moving from pose a_start to a_end) and `b` (b_start to b_end) come within
/// request.tolerance (plus request.separation): by conservative advancement on GJK distance with a warm-started cache when either shape
/// turns, by a GJK ray cast when both only translate (the shape cast). Const, thread-safe.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, double> && std::same_as<typename B::Scalar, double>
[[nodiscard]] ToiResult convex_toi(const A& a, const Transform<double>& a_start, const Transform<double>& a_end,
                                   const B& b, const Transform<double>& b_start, const Transform<double>& b_end,
                                   const ToiRequest& request = {}) {
    ToiResult out;
    out.status = detail::toi_inputs_usable({&a_start, &a_end, &b_start, &b_end}, request);
    if (out.status != QueryStatus::ok) return out;
    const detail::PoseMotion ma(a_start, a_end), mb(b_start, b_end);
    if (ma.angle == 0 && mb.angle == 0 && request.separation == 0) return detail::convex_shape_cast(a, ma, b, mb, request);
    return detail::convex_toi_advancement(a, ma, b, mb, request);
}

}  // namespace cdkit
