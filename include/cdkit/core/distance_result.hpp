#pragma once
/// \file The request and result of mesh–mesh distance() (distance.hpp). They sit below the trees and the
/// queries that fill them, so a tree never includes a query.

#include "cdkit/core/math.hpp"
#include "cdkit/core/mesh.hpp"
#include "cdkit/core/status.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace cdkit {

/// Accuracy and range wanted from distance(). The result satisfies distance ≤ (1 + rel_err)·true + abs_err (and
/// distance ≥ true up to rounding); larger errors prune more and answer sooner. `max_distance` says how far
/// apart is still of interest (a contact margin, a safety distance): everything that cannot come nearer is
/// pruned, so a pair far beyond it costs a few bound tests. When the models are farther apart than
/// (1 + rel_err)·max_distance + abs_err the result's distance stays +inf (no points, no triangles); when they
/// are within max_distance the answer is the one without the bound. rel_err and abs_err must be finite and
/// ≥ 0, max_distance ≥ 0 (+inf, the default, for no bound), else the query returns status invalid_input.
template <class S = double> struct DistanceRequest {
    S rel_err = 0;
    S abs_err = 0;
    S max_distance = std::numeric_limits<S>::infinity();
};

namespace detail {
/// The request's validity (every field ≥ 0, none NaN) and its pruning cut: bounds at or beyond it cannot hold a
/// pair within max_distance (one ulp above it, so a pair exactly at max_distance is kept).
template <class S> [[nodiscard]] inline bool distance_request_is_valid(const DistanceRequest<S>& r) noexcept {
    return r.rel_err >= S(0) && r.abs_err >= S(0) && r.max_distance >= S(0) && std::isfinite(r.rel_err) &&
           std::isfinite(r.abs_err);
}
template <class S> [[nodiscard]] inline S distance_request_cut(const DistanceRequest<S>& r) noexcept {
    return std::nextafter(r.max_distance, std::numeric_limits<S>::infinity());
}
/// The level a node pair's lower bound must stay under to be expanded, given the best distance found so far:
/// (best − abs_err)/(1 + rel_err), which keeps best ≤ (1 + rel_err)·true + abs_err, and never above the request's
/// cut (+inf without max_distance). One rule for every distance() descent.
template <class S> struct DistancePruning {
    S scale, abs_err, cut;
    explicit DistancePruning(const DistanceRequest<S>& r) noexcept
        : scale(S(1) / (S(1) + r.rel_err)), abs_err(r.abs_err), cut(distance_request_cut(r)) {}
    [[nodiscard]] S threshold(S best) const noexcept { return std::min((best - abs_err) * scale, cut); }
};
/// Whether a found distance lies beyond what the request wants reported (see DistanceRequest).
template <class S> [[nodiscard]] inline bool beyond_max_distance(S found, const DistanceRequest<S>& r) noexcept {
    return found > (S(1) + r.rel_err) * r.max_distance + r.abs_err;
}
}  // namespace detail

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
