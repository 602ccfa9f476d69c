#pragma once
/// \file FCL 0.7's two GJK solvers (fcl::detail::GJKSolver_indep, fcl::detail::GJKSolver_libccd) on P3's
/// convex pairs, behind plain declarations: FCL's headers are slow to compile, so only peer_fcl.cpp includes
/// them.

#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace cdkit::bench {

/// A P3 shape in cdkit's conventions (local frame, symmetry axis z, half sizes); peer_fcl.cpp converts it to
/// FCL's (full lengths `lz`, full box sides).
struct FclShapeDesc {
    enum class Kind { ellipsoid, box, capsule, cylinder, cone, convex };
    Kind kind = Kind::ellipsoid;
    /// ellipsoid: semi-axes; box: half extents; capsule: (radius, half length, 0); cylinder and cone:
    /// (radius, half height, 0); convex: unused.
    Vec3<double> size = Vec3<double>::Zero();
    /// convex: hull vertices and outward triangles indexing them (read during fcl_measure only).
    const std::vector<Vec3<double>>* vertices = nullptr;
    const std::vector<std::array<std::uint32_t, 3>>* triangles = nullptr;
};

inline FclShapeDesc fcl_desc(const Ellipsoid<double>& s) { return {FclShapeDesc::Kind::ellipsoid, s.radii}; }
inline FclShapeDesc fcl_desc(const Box<double>& s) { return {FclShapeDesc::Kind::box, s.half}; }
inline FclShapeDesc fcl_desc(const Capsule<double>& s) {
    return {FclShapeDesc::Kind::capsule, {s.radius, s.half_length, 0.0}};
}
inline FclShapeDesc fcl_desc(const Cylinder<double>& s) {
    return {FclShapeDesc::Kind::cylinder, {s.radius, s.half_height, 0.0}};
}
inline FclShapeDesc fcl_desc(const Cone<double>& s) {
    return {FclShapeDesc::Kind::cone, {s.radius, s.half_height, 0.0}};
}
inline FclShapeDesc fcl_desc(const ConvexPolyhedron<double>& s) {
    return {FclShapeDesc::Kind::convex, Vec3<double>::Zero(), &s.vertices(), &s.triangles()};
}

/// One FCL query on one pair: mean ns per call over `reps` calls after one untimed call (as
/// bench_convex.cpp's time_ns), whether FCL reported success, its boolean and its value.
struct FclQuery {
    double ns = 0;
    bool ok = false;   ///< the call's return value (distance: GJK converged to a separation)
    bool hit = false;  ///< boolean queries: FCL says the shapes intersect
    double value = 0;  ///< distance, or penetration depth (≥ 0)
};

/// All FCL queries on one pair. Which FCL code runs (FCL 0.7's dispatch, not ours to choose):
/// - indep boolean: shapeIntersect without contacts = FCL's GJK, then its EPA whenever GJK finds the origin
///   inside (FCL computes the contact even when none is asked for); indep penetration: the same with contacts.
/// - libccd boolean: shapeIntersect without contacts = libccd's MPR (ccdMPRIntersect); libccd penetration:
///   ccdMPRPenetration (MPR's depth estimate, not GJK+EPA).
/// - distances: FCL's GJK (indep) and libccd's GJK (libccd, distance_tolerance 1e-6).
/// - Box/box booleans and penetrations go to FCL's boxBoxIntersect (SAT) in both solvers, capsule/capsule
///   distances to its closed-form capsuleCapsuleDistance.
struct FclPairResult {
    FclQuery indep_bool, indep_dist, indep_pen, ccd_bool, ccd_dist, ccd_pen;
};

/// Builds the FCL shapes of `a` and `b` (same kind; std::invalid_argument otherwise) outside the timed
/// region, then times the queries above. Penetrations only with `with_penetration`.
[[nodiscard]] FclPairResult fcl_measure(const FclShapeDesc& a, const Transform<double>& pa, const FclShapeDesc& b,
                                        const Transform<double>& pb, int reps, bool with_penetration);

}  // namespace cdkit::bench
