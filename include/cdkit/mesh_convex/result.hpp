#pragma once
/// \file Requests and results of the mesh–convex queries (collide, distance, penetration between a MeshModel and
/// a support-mapped convex shape). Plain structs, in the library's one vocabulary: a `QueryStatus status`, a
/// `bool colliding` field, the answer, and `stats` work counters (TraversalStats / DistanceStats).

#include "cdkit/core/collision_result.hpp"
#include "cdkit/core/contact_mode.hpp"
#include "cdkit/core/distance_result.hpp"
#include "cdkit/core/math.hpp"
#include "cdkit/core/mesh.hpp"
#include "cdkit/core/status.hpp"

#include <cstddef>
#include <limits>
#include <vector>

namespace cdkit {

/// What collide() and penetration() between a mesh and a convex shape report.
struct MeshConvexRequest {
    /// collide(): `first` stops at the first touching triangle, `all` reports every touching triangle.
    /// penetration(): `first` keeps only the deepest touching triangle (every one is examined), `all` every one.
    ContactMode mode = ContactMode::first;
    /// In ContactMode::all, stop after this many contacts (the result says it was truncated).
    std::size_t max_contacts = std::numeric_limits<std::size_t>::max();
    /// collide(): compute a witness point per contact. Off, collide() is a pure boolean / triangle-index query:
    /// contacts carry their triangle only (point zero), which spares an EPA run per reported contact on shapes
    /// without a specialised test (the sphere and capsule tests give their point for free either way).
    bool witness_points = true;
};

/// One triangle of the mesh that touches or crosses the convex shape. World frame.
template <class S> struct MeshConvexContact {
    Index triangle = 0;             ///< index into the model's mesh.triangles
    Vec3<S> point = Vec3<S>::Zero();  ///< a point of the triangle in (or on) the shape; zero without witness_points
};

/// Result of collide(mesh, pose, shape, pose).
template <class S> struct MeshConvexResult {
    /// invalid_pose: a pose failed pose_is_usable(); invalid_input: the shape's support map gave a non-finite
    /// point (NaN or infinite sizes). Then nothing was tested and colliding is false.
    QueryStatus status = QueryStatus::ok;
    bool colliding = false;
    bool truncated = false;  ///< ContactMode::all stopped at max_contacts
    std::vector<MeshConvexContact<S>> contacts;
    TraversalStats stats;    ///< bv_tests: node tests; leaf_pairs: leaves reached; primitive_tests: triangles tested
};

/// Result of distance(mesh, pose, shape, pose). World frame.
template <class S> struct MeshConvexDistanceResult {
    QueryStatus status = QueryStatus::ok;  ///< as MeshConvexResult's; distance stays +inf when not ok
    bool colliding = false;  ///< distance == 0: some triangle touches or crosses the shape
    S distance = std::numeric_limits<S>::infinity();
    Vec3<S> point_mesh = Vec3<S>::Zero();   ///< on `triangle`, at `distance` from point_shape
    Vec3<S> point_shape = Vec3<S>::Zero();  ///< on the shape's surface (equal to point_mesh when colliding)
    Index triangle = 0;                     ///< index into the model's mesh.triangles
    DistanceStats stats;                    ///< bv_tests: node lower bounds; primitive_tests: triangle distances
};

/// One touching triangle's penetration: EPA between the triangle and the shape (van den Bergen 2001).
template <class S> struct MeshConvexPenetration {
    Index triangle = 0;
    /// Length of the shortest translation of the shape that separates it from this triangle (≥ 0; 0 touching).
    /// A triangle is flat: this is the depth against that one triangle, not against the mesh's volume.
    S depth = S(0);
    Vec3<S> normal = Vec3<S>::Zero();       ///< unit, world frame, from the triangle towards the shape
    Vec3<S> point_mesh = Vec3<S>::Zero();   ///< deepest point of the triangle (inside the shape)
    Vec3<S> point_shape = Vec3<S>::Zero();  ///< deepest point of the shape; point_mesh − point_shape = depth·normal
};

/// Result of penetration(mesh, pose, shape, pose).
template <class S> struct MeshConvexPenetrationResult {
    QueryStatus status = QueryStatus::ok;  ///< as MeshConvexResult's
    bool colliding = false;
    bool truncated = false;                ///< ContactMode::all stopped at max_contacts
    MeshConvexPenetration<S> deepest;      ///< the deepest touching triangle (valid when colliding)
    std::vector<MeshConvexPenetration<S>> contacts;  ///< all: every touching triangle; first: {deepest}
    TraversalStats stats;
};

}  // namespace cdkit
