#pragma once
/// \file Distance between two triangles, with a closest pair of points.
///
/// The distance of two disjoint closed triangles is attained by a vertex of one and the interior of the
/// other's face, or by an edge of one and an edge of the other (Ericson, "Real-Time Collision Detection",
/// Morgan Kaufmann 2005, sec. 5.1.5, 5.1.9: the 6 vertex–face + 9 edge–edge candidates). Edge–edge
/// closest points follow Lumelsky, "On fast computation of distance between line segments", Information
/// Processing Letters 21(2), 1985, with the parallel and zero-length cases of Ericson sec. 5.1.9 handled
/// explicitly. A vertex–face candidate counts only when the vertex projects inside the face; otherwise the
/// vertex's closest point lies on an edge, which the edge–edge candidates already cover (an edge end point
/// is a vertex). Hence a zero-area triangle needs no special path: its face term is skipped and its edges,
/// possibly of zero length, are segments like any other.
///
/// Intersecting triangles have distance 0, which the 15 candidates cannot see when an edge pierces a face;
/// that case is decided by the exact triangles_intersect() (narrowphase/triangle.hpp) and its witness.

#include "cdkit/narrowphase/triangle.hpp"

#include <algorithm>
#include <cmath>

namespace cdkit {

/// Result of triangle_distance(). Points are in the frame of the input vertices.
template <class S> struct TriangleDistance {
    S distance = S(0);                      ///< Euclidean distance; 0 when the closed triangles intersect
    Vec3<S> point_on_p = Vec3<S>::Zero();   ///< a point of triangle p at `distance` from point_on_q
    Vec3<S> point_on_q = Vec3<S>::Zero();   ///< a point of triangle q (equal to point_on_p on intersection)
};

namespace detail {

/// Closest points of segments [p1,q1] and [p2,q2]: parameters s, t in [0,1] and the squared distance.
/// Robust for parallel segments (any closest pair is returned) and zero-length segments (points).
template <class S> struct SegmentClosest {
    S s, t, dist2;
    Vec3<S> c1, c2;
};

template <class S>
[[nodiscard]] inline SegmentClosest<S> closest_points_segments(const Vec3<S>& p1, const Vec3<S>& q1, const Vec3<S>& p2,
                                                               const Vec3<S>& q2) noexcept {
    const Vec3<S> d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    const S a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    const auto clamp01 = [](S x) { return x < S(0) ? S(0) : (x > S(1) ? S(1) : x); };
    S s = 0, t = 0;
    // A segment whose squared length is exactly zero is a point; tiny but non-zero lengths go through the
    // general path, whose divisions by a or e stay finite and whose clamps keep s, t in range.
    if (a == S(0) && e == S(0)) {
        s = t = 0;
    } else if (a == S(0)) {
        t = clamp01(f / e);
    } else {
        const S c = d1.dot(r);
        if (e == S(0)) {
            s = clamp01(-c / a);
        } else {
            const S b = d1.dot(d2);
            const S denom = a * e - b * b;  // = |d1 × d2|², ≥ 0 up to rounding
            // Near-parallel: the unconstrained s is ill-conditioned; any s works as a start because t is
            // re-derived from s and s from the clamped t below, which yields a true closest pair.
            s = denom > S(64) * std::numeric_limits<S>::epsilon() * a * e ? clamp01((b * f - c * e) / denom) : S(0);
            t = (b * s + f) / e;
            if (t < S(0)) {
                t = 0;
                s = clamp01(-c / a);
            } else if (t > S(1)) {
                t = 1;
                s = clamp01((b - c) / a);
            }
        }
    }
    SegmentClosest<S> out;
    out.s = s;
    out.t = t;
    out.c1 = p1 + d1 * s;
    out.c2 = p2 + d2 * t;
    out.dist2 = (out.c1 - out.c2).squaredNorm();
    return out;
}

/// Vertex–face candidate: when `p` projects into the interior or boundary of the non-degenerate triangle
/// (a,b,c), writes the projection and returns the squared distance; otherwise returns +inf (the closest
/// point is then on an edge, covered by the edge–edge candidates).
template <class S>
[[nodiscard]] inline S point_face_dist2(const Vec3<S>& p, const Vec3<S>& a, const Vec3<S>& b, const Vec3<S>& c,
                                        const Vec3<S>& n, S nn, Vec3<S>& proj) noexcept {
    constexpr S inf = std::numeric_limits<S>::infinity();
    if (nn == S(0)) return inf;
    if (n.dot((b - a).cross(p - a)) < S(0)) return inf;
    if (n.dot((c - b).cross(p - b)) < S(0)) return inf;
    if (n.dot((a - c).cross(p - c)) < S(0)) return inf;
    const S h = n.dot(p - a);
    proj = p - n * (h / nn);
    return (p - proj).squaredNorm();
}

/// The 6 + 9 candidates, without the intersection test. Returns the squared distance.
template <class S>
[[nodiscard]] inline S triangle_feature_dist2(const Vec3<S> (&P)[3], const Vec3<S> (&Q)[3], Vec3<S>& cp,
                                              Vec3<S>& cq) noexcept {
    S best = std::numeric_limits<S>::infinity();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const SegmentClosest<S> sc = closest_points_segments(P[i], P[(i + 1) % 3], Q[j], Q[(j + 1) % 3]);
            if (sc.dist2 < best) best = sc.dist2, cp = sc.c1, cq = sc.c2;
        }
    const Vec3<S> np = (P[1] - P[0]).cross(P[2] - P[0]);
    const Vec3<S> nq = (Q[1] - Q[0]).cross(Q[2] - Q[0]);
    const S npp = np.squaredNorm(), nqq = nq.squaredNorm();
    Vec3<S> proj = Vec3<S>::Zero();
    for (int i = 0; i < 3; ++i) {
        S d2 = point_face_dist2(Q[i], P[0], P[1], P[2], np, npp, proj);
        if (d2 < best) best = d2, cp = proj, cq = Q[i];
        d2 = point_face_dist2(P[i], Q[0], Q[1], Q[2], nq, nqq, proj);
        if (d2 < best) best = d2, cp = P[i], cq = proj;
    }
    return best;
}

}  // namespace detail

/// Distance between the closed triangles (p0,p1,p2) and (q0,q1,q2), with a closest pair of points, for
/// S = float or double. Zero-area triangles (segments, points) are allowed. When the triangles intersect
/// (decided exactly by triangles_intersect), the distance is 0 and both points are one point of the
/// intersection (the midpoint of triangle_intersection's witness segment). Otherwise the distance is the
/// minimum of the 15 feature candidates computed in S: its error is a few ulps of the coordinates'
/// magnitude. Never throws, never allocates.
template <class S>
[[nodiscard]] inline TriangleDistance<S> triangle_distance(const Vec3<S>& p0, const Vec3<S>& p1, const Vec3<S>& p2,
                                                           const Vec3<S>& q0, const Vec3<S>& q1,
                                                           const Vec3<S>& q2) noexcept {
    static_assert(std::is_same_v<S, float> || std::is_same_v<S, double>, "triangle_distance: S must be float or double");
    TriangleDistance<S> out;
    if (triangles_intersect(p0, p1, p2, q0, q1, q2)) {
        const TriangleIntersection<S> x = triangle_intersection(p0, p1, p2, q0, q1, q2);
        out.distance = S(0);
        out.point_on_p = out.point_on_q = (x.a + x.b) * S(0.5);
        return out;
    }
    const Vec3<S> P[3] = {p0, p1, p2};
    const Vec3<S> Q[3] = {q0, q1, q2};
    out.distance = std::sqrt(detail::triangle_feature_dist2(P, Q, out.point_on_p, out.point_on_q));
    return out;
}

}  // namespace cdkit
