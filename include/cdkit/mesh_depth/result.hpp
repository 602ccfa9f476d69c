#pragma once
/// \file Request and result of the mesh–mesh penetration depth (penetration_depth.hpp, directional_depth.hpp). Plain
/// structs in the library's one vocabulary: a `QueryStatus status`, a `bool colliding` field, the answer, `stats`.

#include "cdkit/bvh/traverse.hpp"
#include "cdkit/core/math.hpp"
#include "cdkit/core/mesh.hpp"
#include "cdkit/core/status.hpp"

#include <cstdint>
#include <optional>

namespace cdkit {

/// Where the direction of a depth came from.
enum class DepthDirection : std::uint8_t {
    none,            ///< not colliding: no direction
    given,           ///< MeshDepthRequest::direction
    ist_force,       ///< the inner sphere trees' penalty force on B (Σ lens volume × centre direction)
    surface_normal,  ///< the intersection curve's normal: Σ over crossing triangle pairs of |segment|·(n_A − n_B)
    centre_line,     ///< from the crossing segments' centre to B's vertex centroid (the surface normal vanished)
    refined,         ///< found by the search of refine_steps > 0 (a spread direction or a tilt), shorter than the above
};

/// Options of penetration_depth() / directional_depth().
struct MeshDepthRequest {
    /// When set (any non-zero length, world frame, pointing from A towards B): the depth along this direction only.
    std::optional<Vec3<double>> direction;
    /// Search of the sphere of directions after the first answer: 32 directions spread over it (directional depth
    /// has local minima), then a pattern search around the best: four tilts of the best
    /// direction by an angle that starts at 0.5 rad; a shorter answer becomes the centre (at most four moves per
    /// angle), then the angle halves; this many angles. 0 = none. Every tried direction's answer is a separating
    /// translation, so refining only shortens it.
    int refine_steps = 0;
    /// Passes of the fixed-point search per direction (see directional_depth.hpp); the answer is marked incomplete
    /// when they run out.
    int max_passes = 1000;
};

/// Work counters of one depth query.
struct MeshDepthStats {
    TraversalStats traversal;   ///< node-pair interval tests, leaf pairs, triangle-pair intervals
    int directions = 0;         ///< directions whose depth was computed
    int passes = 0;             ///< fixed-point passes over all directions
};

/// Result of penetration_depth() / directional_depth(). World frame.
struct MeshDepthResult {
    QueryStatus status = QueryStatus::ok;  ///< invalid_pose / invalid_input (a zero or non-finite direction)
    bool colliding = false;                ///< some triangle of A crosses or touches some triangle of B
    /// False when max_passes ran out on the chosen direction: `depth` is then a lower bound of the translation.
    bool complete = true;
    /// Length of the translation of B along `normal` after which no triangle of B crosses a triangle of A, the
    /// translation moving B continuously from where it is (the first gap along the line: B moved by any shorter
    /// multiple of `normal` still crosses A's surface). 0 when not colliding.
    double depth = 0;
    Vec3<double> normal = Vec3<double>::Zero();  ///< unit, from A towards B (zero when not colliding)
    /// The triangle pair that separates last, and where it touches at that translation: point_a on A's triangle,
    /// point_b on B's triangle at B's present pose, point_a − point_b = depth·normal.
    Index triangle_a = 0, triangle_b = 0;
    Vec3<double> point_a = Vec3<double>::Zero(), point_b = Vec3<double>::Zero();
    DepthDirection direction = DepthDirection::none;
    /// With inner sphere trees: their penetration volume (Σ lens volumes of overlapping inner spheres; ist_query.hpp)
    /// and the penalty force direction on B (unit; zero when no inner spheres overlap). Otherwise 0 and zero.
    double volume = 0;
    Vec3<double> force_direction = Vec3<double>::Zero();
    MeshDepthStats stats;
};

}  // namespace cdkit
