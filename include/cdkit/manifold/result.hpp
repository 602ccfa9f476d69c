#pragma once
/// \file Request and result of a contact manifold: up to four points per convex pair, each with its depth, sharing
/// one normal, with ids that stay the same from frame to frame while the same features touch (a solver keys its
/// warm-start impulses by them).

#include "cdkit/core/math.hpp"
#include "cdkit/core/status.hpp"
#include "cdkit/narrowphase/gjk.hpp"

#include <array>
#include <cstdint>

namespace cdkit {

/// What contact_manifold() keeps.
struct ManifoldRequest {
    /// Speculative contacts: points whose shapes are apart by at most `margin` (≥ 0) are reported too, with a
    /// negative depth; a separated pair within `margin` gets a manifold with `colliding` false.
    double margin = 0;
    /// A face (or an edge) is the touching feature when its normal lies within this angle (radians, in [0, π/4])
    /// of the contact normal (when the edge lies within it of the contact plane); otherwise the vertex is. Larger
    /// values also take nearly parallel faces as face contacts (a resting box that tilts by less than this keeps
    /// its points); each point still carries its own depth.
    double feature_angle = 0.1;
    /// Only the deepest point (EPA's witness pair): the classic single contact, for comparison.
    bool single_point = false;
    /// The World's narrow phase (collide_shapes) only: contacts with a mesh get a depth and normal (mesh–mesh:
    /// penetration_depth(); convex–mesh: the deepest touching triangle's EPA). Off: a witness point only, as
    /// collide() gives it (cheaper: no crossing set, no EPA per triangle).
    bool mesh_depth = true;
};

/// One contact point of a manifold (world frame).
template <class S = double> struct ManifoldPoint {
    Vec3<S> point_a = Vec3<S>::Zero();  ///< on A's surface
    Vec3<S> point_b = Vec3<S>::Zero();  ///< on B's surface
    /// Penetration along the manifold's normal: (point_a − point_b)·normal. Positive: overlapping; negative: a
    /// speculative point that far apart (only with ManifoldRequest::margin > 0).
    S depth = S(0);
    /// The features that made the point (the reference face, the incident feature and the clipping plane or
    /// vertex): equal ids in two frames mean the same contact, so a solver can carry its impulse over.
    std::uint64_t id = 0;
};

/// A pair's state from one frame to the next (caller-owned, one per pair, passed by pointer like every cache): GJK's
/// warm start, and last frame's points in A's frame with their ids. A new point that lands near an old one (within a
/// tenth of the contact patch's size) takes the old id even when clipping made it from other features (a corner that
/// slid just outside the reference face), so a solver's warm start survives the small motions of a resting stack.
template <class S = double> struct ManifoldCache {
    GjkCache<S> gjk;
    int count = 0;
    std::array<Vec3<S>, 4> local_a{};
    std::array<std::uint64_t, 4> ids{};
};

/// Counters of one manifold query.
struct ManifoldStats {
    /// of the (warm-started) boolean test — with a margin, the one search that also measures a pair within it
    /// (gjk_distance_within) — and EPA's own GJK run (where EPA could not start from that search's final simplex)
    int gjk_iterations = 0;
    int epa_iterations = 0;  ///< of the penetration query
    int clipped_points = 0;  ///< points after clipping, before the reduction to four
    int kept_ids = 0;        ///< points that took last frame's id (ManifoldCache)
};

/// The contact of two convex shapes as up to four points sharing a normal.
template <class S = double> struct ContactManifold {
    QueryStatus status = QueryStatus::ok;
    /// Touching or overlapping. False with count > 0: apart, within ManifoldRequest::margin.
    bool colliding = false;
    /// Separation when apart (0 when colliding); when not colliding and farther than the margin, count is 0.
    S distance = S(0);
    /// Unit, from A towards B: moving B by depth·normal separates the shapes at that point. For a face contact
    /// the reference face's normal; else the penetration (or closest-point) direction.
    Vec3<S> normal = Vec3<S>::Zero();
    int count = 0;
    std::array<ManifoldPoint<S>, 4> points{};
    ManifoldStats stats;
    /// The deepest point's depth (EPA's penetration depth for a single-point manifold).
    [[nodiscard]] S max_depth() const noexcept {
        S d = count > 0 ? points[0].depth : S(0);
        for (int i = 1; i < count; ++i) d = std::max(d, points[i].depth);
        return d;
    }
};

}  // namespace cdkit
