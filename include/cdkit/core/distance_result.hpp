#pragma once
/// \file The request and result of mesh–mesh distance() (distance.hpp). They sit below the trees and the
/// queries that fill them, so a tree never includes a query.

#include "cdkit/core/math.hpp"
#include "cdkit/core/mesh.hpp"
#include "cdkit/core/status.hpp"

#include <cstdint>
#include <limits>

namespace cdkit {

/// Accuracy wanted from distance(). The result satisfies distance ≤ (1 + rel_err)·true + abs_err (and
/// distance ≥ true up to rounding); larger errors prune more and answer sooner. Both must be ≥ 0.
template <class S = double> struct DistanceRequest {
    S rel_err = 0;
    S abs_err = 0;
};

/// Work counters of one distance query.
struct DistanceStats {
    std::uint64_t bv_tests = 0;        ///< BV lower-bound evaluations
    std::uint64_t primitive_tests = 0; ///< triangle_distance evaluations
    std::uint64_t primitive_skips = 0; ///< triangle pairs skipped by a projection gap (bvh/detail/distance_triangle_gap.hpp)
};

/// Result of distance(). Points are in the world frame.
template <class S> struct DistanceResult {
    QueryStatus status = QueryStatus::ok;  ///< invalid_pose: a pose was not a rigid motion; distance stays +inf
    S distance = std::numeric_limits<S>::infinity();  ///< 0 when the meshes intersect (touching counts)
    Vec3<S> point_a = Vec3<S>::Zero();  ///< on triangle_a of A, at `distance` from point_b
    Vec3<S> point_b = Vec3<S>::Zero();  ///< on triangle_b of B
    Index triangle_a = 0;               ///< index into A's mesh.triangles
    Index triangle_b = 0;
    DistanceStats stats;
};

}  // namespace cdkit
