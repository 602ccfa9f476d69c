#pragma once
/// \file The accuracy benchmark's referees and peers behind plain declarations, so that CGAL's headers are
/// compiled only in oracle_cgal.cpp and FCL's only in peer_fcl.cpp.

#include "cdkit/core/mesh.hpp"

#include <array>
#include <cstddef>
#include <utility>
#include <vector>

namespace cdkit::accuracy {

using Tri3 = std::array<Vec3<double>, 3>;
using PairList = std::vector<std::pair<Index, Index>>;  ///< (triangle of A, triangle of B), sorted

/// CGAL's exact answer: do the closed triangles share a point? A zero-area triangle (decided exactly) is
/// reduced to the segment between its two farthest vertices, or to a point, for CGAL's predicates.
[[nodiscard]] bool exact_triangles_intersect(const Tri3& p, const Tri3& q);

/// Every intersecting triangle pair of two meshes given in one frame, decided by exact_triangles_intersect
/// on the pairs whose (closed, exactly computed) bounding boxes overlap. Sorted.
[[nodiscard]] PairList exact_intersecting_pairs(const TriangleMesh<double>& a, const TriangleMesh<double>& b);

/// FCL 0.7's triangle–triangle test, fcl::detail::Intersect<double>::intersect_Triangle.
[[nodiscard]] bool fcl_triangles_intersect(const Tri3& p, const Tri3& q);

/// FCL's mesh–mesh collision (BVHModel<OBBRSSd>, identity poses, all contacts up to max_contacts): the
/// intersecting triangle pairs it reports, sorted and deduplicated.
[[nodiscard]] PairList fcl_intersecting_pairs(const TriangleMesh<double>& a, const TriangleMesh<double>& b,
                                              std::size_t max_contacts);

}  // namespace cdkit::accuracy
