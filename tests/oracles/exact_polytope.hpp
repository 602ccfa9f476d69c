#pragma once
// The exact referee for convex polytope pairs (issue 37, "independent oracles"): two convex hulls of vertex lists,
// each posed by a double rotation and translation, judged in exact arithmetic by CGAL (Polytope_distance_d, the
// exact quadratic program of Gärtner's solver, and exact linear programs; CGAL's headers are compiled only in
// exact_polytope_cgal.cpp). The poses are applied exactly: every vertex R·x + t is formed from the given doubles
// without rounding (R need not be orthonormal: the oracle judges the shapes the given numbers describe, which is
// what cdkit's queries are asked about). Curved shapes have no vertex list and are not judged here.
#include <cdkit/core/math.hpp>

#include <vector>

namespace cdkit::test::exact {

/// Exact answer for conv(R_a·A + t_a) and conv(R_b·B + t_b).
struct PolytopePairAnswer {
    /// Exact squared distance (0 when the hulls share a point, touching included), rounded to the nearest double
    /// or so (the exact rational's numerator and denominator each rounded: relative error ≤ ~2ε).
    double squared_distance = 0;
    double distance = 0;  ///< √squared_distance (relative error ≤ ~2ε)
    bool intersect = false;  ///< exact: the closed hulls share a point (squared distance exactly 0)
    /// Only when asked for (`with_depth`) and `intersect`: the exact value of min over |u|∞ = 1 of
    /// h_{A−B}(u) = max_a u·a − min_b u·b (six linear programs, one per face of the L∞ unit cube), rounded. The
    /// Euclidean penetration depth δ satisfies δ ≤ depth_inf ≤ √3·δ; depth_inf is 0 exactly when the hulls
    /// touch without overlap (a weakly separating plane exists: the origin is on the boundary of A − B, e.g.
    /// faces in contact, or two coplanar triangles).
    bool depth_known = false;
    bool touching = false;  ///< exact: intersect and depth_inf == 0
    double depth_inf = 0;
};

/// The exact answer; `with_depth` adds the linear programs of `depth_inf` where the hulls intersect (slower: six
/// exact LPs). Vertex lists must be non-empty; repeated or coplanar vertices are fine (flat and needle hulls,
/// segments, points).
[[nodiscard]] PolytopePairAnswer exact_polytope_pair(const std::vector<Vec3<double>>& a, const Transform<double>& pose_a,
                                                     const std::vector<Vec3<double>>& b, const Transform<double>& pose_b,
                                                     bool with_depth);

/// Exact: the plane through the origin orthogonal to `n`, moved to A's highest point along n, has all of B at or
/// beyond it — max_a n·a ≤ min_b n·b for the posed vertices (n ≠ 0 as given, not normalised). The check of a
/// reported separating direction.
[[nodiscard]] bool exact_direction_separates(const std::vector<Vec3<double>>& a, const Transform<double>& pose_a,
                                             const std::vector<Vec3<double>>& b, const Transform<double>& pose_b,
                                             const Vec3<double>& n);

}  // namespace cdkit::test::exact
