#pragma once
/// \file A cheap test that two triangles are at least a given distance apart, for distance() to skip leaf
/// pairs that cannot lower its answer before the full 15-candidate triangle distance runs.
///
/// The gap between the projections of two convex sets onto any axis is at most their distance (projection
/// is 1-Lipschitz). The axes are those of the triangle–triangle separating-axis test: both face normals and
/// the nine cross products of an edge of each (the separating axis theorem as in Gottschalk, Lin, Manocha,
/// "OBBTree", SIGGRAPH 1996; the 2 + 9 axes of two triangles as listed by Eberly, "Intersection of convex
/// objects: the method of separating axes", Geometric Tools, 2001). For disjoint triangles the closest points are a vertex and a face
/// interior (the gap along that face's normal is the distance) or two edge interiors (the gap along their
/// cross product is the distance), else a vertex against an edge or a vertex, where the gap is smaller but
/// still a lower bound. On the bunny benchmark 43–59% of the leaf pairs that distance() reaches are
/// farther than the current answer along one of these axes (docs/distance.md).
///
/// Everything is branch-free (the axes in lanes, one maximum, no square root, no division): ~1,200
/// instructions, where the full triangle distance costs ~1,900 and ~26 data-dependent branches per pair, most
/// of them mispredicted (callgrind's branch simulator).

#include "cdkit/core/math.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cdkit::detail {

/// True when the distance triangle_feature_dist2() computes for triangles P and Q (the square root of it;
/// the same rounded vertices) is surely at least `threshold`: some axis's projection gap, lowered by a
/// rounding margin, exceeds it. False says nothing. `threshold` ≤ 0: true (no distance is below it).
template <class S>
[[nodiscard]] inline bool triangle_gap_reaches(const Vec3<S> (&P)[3], const Vec3<S> (&Q)[3], S threshold) noexcept {
    if (!(threshold > S(0))) return true;
    // Rounding: the gaps are computed from differences to P[0], and the triangle distance itself is off by a
    // few ulps of the coordinates' magnitude, so the threshold is raised by 256 ulps of that magnitude and
    // 16 ulps relative. Cross axes closer than ~6° to parallel (|a × b|² < 0.01 |a|²|b|²) and slivers' normals
    // are skipped: their gap's rounding, relative to the axis length, would exceed the margin.
    const S eps = std::numeric_limits<S>::epsilon();
    S mag = S(0);
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) mag = std::max(mag, std::max(std::abs(P[i][k]), std::abs(Q[i][k])));
    const S t = (threshold + S(256) * eps * mag) * (S(1) + S(16) * eps);
    const S t2 = t * t;
    // The 11 axes in lanes (12: the last repeats A's normal, so that double lanes fill SSE2 registers): axis
    // k is u_k × v_k. Everything relative to P[0]: p1, p2 the other vertices of P, q0..q2 those of Q.
    using L = Eigen::Array<S, 12, 1>;
    const Vec3<S> p1 = P[1] - P[0], p2 = P[2] - P[0];
    const Vec3<S> q[3] = {Q[0] - P[0], Q[1] - P[0], Q[2] - P[0]};
    const Vec3<S> ea[3] = {p1, P[2] - P[1], P[0] - P[2]};
    const Vec3<S> eb[3] = {Q[1] - Q[0], Q[2] - Q[1], Q[0] - Q[2]};
    L u[3], v[3];
    for (int c = 0; c < 3; ++c) {
        u[c][0] = ea[0][c], v[c][0] = p2[c];             // A's normal
        u[c][1] = eb[0][c], v[c][1] = Q[2][c] - Q[0][c];  // B's normal
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) u[c][2 + 3 * i + j] = ea[i][c], v[c][2 + 3 * i + j] = eb[j][c];
        u[c][11] = u[c][0], v[c][11] = v[c][0];
    }
    const L n0 = u[1] * v[2] - u[2] * v[1], n1 = u[2] * v[0] - u[0] * v[2], n2 = u[0] * v[1] - u[1] * v[0];
    const L nn = n0 * n0 + n1 * n1 + n2 * n2;
    const L uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2], vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    const auto proj = [&](const Vec3<S>& w) -> L { return n0 * w[0] + n1 * w[1] + n2 * w[2]; };
    const L a1 = proj(p1), a2 = proj(p2);  // P[0] projects to 0
    const L b0 = proj(q[0]), b1 = proj(q[1]), b2 = proj(q[2]);
    const L alo = a1.min(a2).min(S(0)), ahi = a1.max(a2).max(S(0));
    const L blo = b0.min(b1).min(b2), bhi = b0.max(b1).max(b2);
    const L g = (blo - ahi).max(alo - bhi);
    // Gap along n above t  ⇔  g > t·|n| with g > 0  ⇔  g·|g| − t²·|n|² > 0; and the axis counts only when
    // |n|² > 0.01·|u|²·|v|² (hence |n| > 0). Both as one sign, so that the lanes reduce with one maximum.
    return (g * g.abs() - t2 * nn).min(nn - S(0.01) * uu * vv).maxCoeff() > S(0);
}

}  // namespace cdkit::detail
