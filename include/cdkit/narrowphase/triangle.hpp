#pragma once
/// \file Triangle–triangle intersection: an exact boolean test for closed triangles, and the
/// intersection segment as a witness.
///
/// Based on: P. Guigue, O. Devillers, "Fast and Robust Triangle-Triangle Overlap Test Using Orientation
/// Predicates", Journal of Graphics Tools 8(1):25–32, 2003. Every decision is the sign of an orientation
/// determinant (cdkit/core/predicates.hpp), so with exact predicates the answer is exact for all finite
/// input: there is no epsilon anywhere in the boolean. Guigue–Devillers assume
/// non-degenerate triangles; zero-area triangles (collinear or coincident vertices, legal in polygon
/// soups) are reduced exactly to the segment or point they are and tested by their own exact paths.
/// See docs/triangle.md for the derivation of the sign conditions and the measured numbers.

#include "cdkit/core/math.hpp"
#include "cdkit/core/predicates.hpp"
#include "cdkit/narrowphase/triangle/detail/overlap.hpp"

namespace cdkit {

/// Result of triangle_intersection(). Points are in the frame of the input vertices.
template <class S> struct TriangleIntersection {
    /// The closed triangles share at least one point (touching counts). Exact in filtered_exact mode.
    bool intersect = false;
    /// Both triangles are non-degenerate, lie in one plane, and intersect; then a and b are two vertices
    /// of the overlap polygon at maximal distance from each other (the overlap's diameter), which may be
    /// equal when the overlap is a single point. False for every other configuration, including
    /// zero-area triangles lying in the other's plane (their intersection is a segment, reported as such).
    bool coplanar = false;
    /// If intersect && !coplanar: the end points of the intersection segment (a == b when the triangles
    /// touch at one point; for a zero-area input the intersection of its segment/point with the other).
    /// Accuracy (filtered_exact): each point is within about 16·2^-52·M of the exact one, M the largest
    /// coordinate magnitude of the six vertices, plus the final rounding to S; so its distance to each
    /// triangle is at most that, while every coordinate is 0 or of magnitude in [2^-280, 2^280] (beyond,
    /// the boolean stays exact and the points lie on the right segments, less accurately). Both zero
    /// when !intersect.
    Vec3<S> a = Vec3<S>::Zero();
    Vec3<S> b = Vec3<S>::Zero();
};

/// Whether the closed triangles (p0,p1,p2) and (q0,q1,q2) share a point; touching counts. Exact in
/// filtered_exact mode (the default) for all finite input, including coplanar
/// and zero-area triangles; the same answer for every vertex order and for swapping the triangles.
/// floating_point mode evaluates the same predicates once in S (see PredicateMode). S: float or double.
/// Never divides, never allocates.
template <class S>
[[nodiscard]] bool triangles_intersect(const Vec3<S>& p0, const Vec3<S>& p1, const Vec3<S>& p2, const Vec3<S>& q0,
                                       const Vec3<S>& q1, const Vec3<S>& q2,
                                       PredicateMode mode = PredicateMode::filtered_exact) noexcept {
    static_assert(detail::is_predicate_scalar_v<S>, "triangles_intersect: S must be float or double");
    using namespace detail::tritri;
    if (mode == PredicateMode::floating_point) return run<FloatKernel<S>, S, false>(p0, p1, p2, q0, q1, q2, nullptr);
    return run<ExactKernel, S, false>(p0, p1, p2, q0, q1, q2, nullptr);
}

/// triangles_intersect() plus a witness: the intersection segment, or for coplanar overlaps two far-apart
/// points of the overlap region (see TriangleIntersection for what is returned and how accurate it is).
/// The boolean is the same as triangles_intersect()'s. Points are computed in double (filtered_exact) or
/// in S (floating_point) and rounded to S.
template <class S>
[[nodiscard]] TriangleIntersection<S> triangle_intersection(const Vec3<S>& p0, const Vec3<S>& p1, const Vec3<S>& p2,
                                                            const Vec3<S>& q0, const Vec3<S>& q1, const Vec3<S>& q2,
                                                            PredicateMode mode = PredicateMode::filtered_exact) noexcept {
    static_assert(detail::is_predicate_scalar_v<S>, "triangle_intersection: S must be float or double");
    using namespace detail::tritri;
    TriangleIntersection<S> r;
    if (mode == PredicateMode::floating_point) {
        Witness<S> w;
        r.intersect = run<FloatKernel<S>, S, true>(p0, p1, p2, q0, q1, q2, &w);
        if (r.intersect) {
            r.coplanar = w.coplanar;
            r.a = to_vec<S>(w.a);
            r.b = to_vec<S>(w.b);
        }
        return r;
    }
    Witness<double> w;
    r.intersect = run<ExactKernel, S, true>(p0, p1, p2, q0, q1, q2, &w);
    if (r.intersect) {
        r.coplanar = w.coplanar;
        r.a = to_vec<S>(w.a);
        r.b = to_vec<S>(w.b);
    }
    return r;
}

}  // namespace cdkit
