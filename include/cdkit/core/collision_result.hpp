#pragma once
/// \file The request and result of mesh–mesh collide() (query.hpp), and the traversal's work counters. They
/// sit below the trees and the queries that fill them, so a tree never includes a query.

#include "cdkit/core/contact_mode.hpp"
#include "cdkit/core/math.hpp"
#include "cdkit/core/mesh.hpp"
#include "cdkit/core/status.hpp"

#include <cstdint>
#include <limits>
#include <vector>

namespace cdkit {

/// Work counters of one query, so that a time can be explained.
struct TraversalStats {
    std::uint64_t bv_tests = 0;        ///< BV overlap tests
    std::uint64_t leaf_pairs = 0;      ///< leaf pairs reached (both BVs overlapping)
    std::uint64_t primitive_tests = 0; ///< triangle pair tests
};

struct CollisionRequest {
    ContactMode mode = ContactMode::first;
    /// In ContactMode::all, stop after this many contacts (the result says it was truncated).
    std::size_t max_contacts = std::numeric_limits<std::size_t>::max();
};

/// One intersecting triangle pair. Points are in the world frame.
template <class S> struct Contact {
    Index triangle_a = 0;      ///< index into model A's mesh.triangles
    Index triangle_b = 0;
    Vec3<S> point;             ///< a witness point on both triangles (the segment's midpoint)
    Vec3<S> segment[2];        ///< the intersection segment (equal end points for a single touching point)
    bool coplanar = false;     ///< the triangles are coplanar; the segment spans part of the overlap region
};

struct CollisionStats : TraversalStats {};

template <class S> struct CollisionResult {
    QueryStatus status = QueryStatus::ok;  ///< invalid_pose: a pose was not a rigid motion; nothing was tested
    bool colliding = false;
    bool truncated = false;  ///< ContactMode::all stopped at max_contacts
    std::vector<Contact<S>> contacts;
    CollisionStats stats;
};

namespace detail {
/// B's vertex in A's frame. Brute force, the trees' leaf filters and the triangle tests share this one
/// function so that they see the same rounded points, and the BV fit's padding covers its rounding.
template <class S> [[nodiscard]] inline Vec3<S> to_frame_a(const Transform<S>& b_to_a, const Vec3<S>& v) noexcept {
    return b_to_a.R * v + b_to_a.t;
}
}  // namespace detail

}  // namespace cdkit
