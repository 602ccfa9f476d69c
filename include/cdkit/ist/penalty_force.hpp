#pragma once
/// \file Penalty force and torque from the overlapping inner-sphere pairs of a penetration-volume query
/// (Weller, Zachmann, "A unified approach for physically-based simulations and haptic rendering", 2009, and
/// the RSS 2009 inner sphere tree paper: the penetration volume as penalty).
///
/// Each overlapping pair (i of A, j of B) pushes B away from A along n = (c_j − c_i)/|c_j − c_i| with
/// magnitude stiffness · V_ij (its intersection volume), applied at the centre of the pair's intersection
/// circle. V_ij is a continuous function of the pose that vanishes as the pair separates, so a pair entering
/// or leaving the set adds no jump: the total force and torque are continuous under continuous motion
/// (n is undefined only for concentric spheres; such a pair contributes no force). A gets the opposite
/// force. Pure function, thread-safe.

#include "cdkit/ist/ist_query.hpp"

namespace cdkit {

/// Force and torque in the world frame.
struct Wrench {
    Vec3<double> force = Vec3<double>::Zero();
    Vec3<double> torque = Vec3<double>::Zero();  ///< about the reference point given to penalty_wrench()
};

/// The wrenches on both objects.
struct PenaltyWrench {
    Wrench on_a, on_b;
    std::size_t pairs = 0;  ///< contributing pairs
};

/// Penalty wrenches from `volume.pairs` (a complete query with collect_pairs, run at the same poses).
/// `stiffness` is force per unit volume; torques are taken about `reference_a` / `reference_b` (world
/// points, typically the centres of mass).
[[nodiscard]] inline PenaltyWrench penalty_wrench(const PenetrationVolumeResult& volume, const InnerSphereTree& a,
                                                  const Transform<double>& pose_a, const InnerSphereTree& b,
                                                  const Transform<double>& pose_b, double stiffness,
                                                  const Vec3<double>& reference_a, const Vec3<double>& reference_b) noexcept {
    PenaltyWrench out;
    const auto& sa = a.spheres();
    const auto& sb = b.spheres();
    for (const OverlappingSpheres& p : volume.pairs) {
        if (p.a >= sa.size() || p.b >= sb.size()) continue;
        const InnerSphere& x = sa[p.a];
        const InnerSphere& y = sb[p.b];
        const Vec3<double> ca = pose_a * x.center, cb = pose_b * y.center;
        const Vec3<double> d = cb - ca;
        const double len = d.norm();
        if (!(len > 1e-12 * (x.radius + y.radius))) continue;
        const Vec3<double> n = d / len;
        // Centre of the intersection circle (the radical plane), clamped into the segment between the centres
        // so that nested spheres still get a point on their axis.
        const double s = std::clamp((len * len + x.radius * x.radius - y.radius * y.radius) / (2 * len), 0.0, len);
        const Vec3<double> at = ca + s * n;
        const Vec3<double> f = stiffness * p.volume * n;
        out.on_b.force += f;
        out.on_b.torque += (at - reference_b).cross(f);
        out.on_a.force -= f;
        out.on_a.torque += (at - reference_a).cross(-f);
        ++out.pairs;
    }
    return out;
}

}  // namespace cdkit
