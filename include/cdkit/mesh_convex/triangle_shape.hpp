#pragma once
/// \file One mesh triangle against the convex shape, in the mesh's frame: boolean (touching counts), distance with
/// closest points, and penetration.
///
/// Any support-mapped shape goes through GJK (Gilbert, Johnson, Keerthi 1988; van den Bergen, "A fast and robust
/// GJK implementation for collision detection of convex objects", JGT 1999) with the triangle as a
/// `ConvexTriangle`, and EPA for depth (van den Bergen, GDC 2001). Spheres and capsules, the usual robot-link
/// shapes, have exact closed-form tests instead (Ericson, "Real-Time Collision Detection", 2005: §5.1.5 closest
/// point on a triangle, §5.1.9 segment–segment): a sphere is its centre's distance to the triangle, a capsule its
/// segment's distance (zero where the segment crosses the triangle, otherwise the smallest of the three
/// edge–segment and the two end point–face distances), each against the radius. They need no iteration and no
/// touching tolerance beyond the rounding of a few products. A box's boolean is its separating-axis test against the
/// triangle (mesh_convex/box_triangle.hpp: 13 axes, Akenine-Möller 2001); GJK/EPA then only place its witness. The
/// brute-force reference runs these same functions on every triangle, so the tree query's answer is the reference's
/// exactly.

#include "cdkit/mesh_convex/box_triangle.hpp"
#include "cdkit/mesh_convex/shape_bound.hpp"
#include "cdkit/narrowphase/epa.hpp"
#include "cdkit/narrowphase/gjk.hpp"
#include "cdkit/narrowphase/triangle.hpp"
#include "cdkit/narrowphase/triangle_distance.hpp"

#include <algorithm>
#include <cmath>

namespace cdkit {
namespace detail {

/// The point of triangle (a, b, c) closest to p (Ericson §5.1.5: Voronoi regions of the vertices, then the edges,
/// then the face). Zero-area triangles fall back to their edges.
template <class S>
[[nodiscard]] inline Vec3<S> closest_on_triangle(const Vec3<S>& p, const Vec3<S>& a, const Vec3<S>& b,
                                                 const Vec3<S>& c) noexcept {
    const Vec3<S> ab = b - a, ac = c - a, ap = p - a;
    const S d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= S(0) && d2 <= S(0)) return a;
    const Vec3<S> bp = p - b;
    const S d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= S(0) && d4 <= d3) return b;
    const S vc = d1 * d4 - d3 * d2;
    if (vc <= S(0) && d1 >= S(0) && d3 <= S(0)) return a + ab * (d1 / (d1 - d3));
    const Vec3<S> cp = p - c;
    const S d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= S(0) && d5 <= d6) return c;
    const S vb = d5 * d2 - d1 * d6;
    if (vb <= S(0) && d2 >= S(0) && d6 <= S(0)) return a + ac * (d2 / (d2 - d6));
    const S va = d3 * d6 - d5 * d4;
    if (va <= S(0) && (d4 - d3) >= S(0) && (d5 - d6) >= S(0))
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const S den = va + vb + vc;
    if (!(den > S(0))) {  // degenerate (zero-area) triangle: the nearest of its edges
        Vec3<S> best = a;
        const Vec3<S> e[3][2] = {{a, b}, {b, c}, {c, a}};
        for (const auto& uv : e) {
            const SegmentClosest<S> s = closest_points_segments(p, p, uv[0], uv[1]);
            if (s.dist2 < (best - p).squaredNorm()) best = s.c2;
        }
        return best;
    }
    return a + ab * (vb / den) + ac * (vc / den);
}

/// Closest points of the segment [p, q] and the triangle (a, b, c): squared distance, point on the segment, point
/// on the triangle. Zero when the segment crosses the triangle.
template <class S> struct SegmentTriangleClosest {
    S dist2;
    Vec3<S> on_segment, on_triangle;
};
template <class S>
[[nodiscard]] inline SegmentTriangleClosest<S> segment_triangle_closest(const Vec3<S>& p, const Vec3<S>& q,
                                                                        const Vec3<S>& a, const Vec3<S>& b,
                                                                        const Vec3<S>& c) noexcept {
    const Vec3<S> n = (b - a).cross(c - a);
    const S nn = n.squaredNorm();
    if (nn > S(0)) {
        // The segment crosses the plane at x; inside the triangle (same side of every edge) it is a common point.
        const S sp = n.dot(p - a), sq = n.dot(q - a);
        if ((sp <= S(0) && sq >= S(0)) || (sp >= S(0) && sq <= S(0))) {
            const S den = sp - sq;
            const Vec3<S> x = den != S(0) ? Vec3<S>(p + (q - p) * (sp / den)) : p;
            if (n.dot((b - a).cross(x - a)) >= S(0) && n.dot((c - b).cross(x - b)) >= S(0) &&
                n.dot((a - c).cross(x - c)) >= S(0))
                return {S(0), x, x};
        }
    }
    SegmentTriangleClosest<S> best{std::numeric_limits<S>::infinity(), p, a};
    const Vec3<S> e[3][2] = {{a, b}, {b, c}, {c, a}};
    for (const auto& uv : e) {
        const SegmentClosest<S> s = closest_points_segments(p, q, uv[0], uv[1]);
        if (s.dist2 < best.dist2) best = {s.dist2, s.c1, s.c2};
    }
    Vec3<S> proj;
    for (const Vec3<S>* end : {&p, &q}) {
        const S d2 = point_face_dist2(*end, a, b, c, n, nn, proj);
        if (d2 < best.dist2) best = {d2, *end, proj};
    }
    return best;
}

/// Distance of one triangle (mesh frame) to the shape, with closest points (mesh frame). `distance` is 0 when they
/// touch or overlap (then both points are one common point for spheres and capsules, GJK's witnesses otherwise).
template <class S> struct TriangleShapeDistance {
    S distance;
    Vec3<S> on_triangle, on_shape;
};

/// The core's (point's or segment's) closest points to the triangle, for the swept shapes.
template <class S>
[[nodiscard]] inline SegmentTriangleClosest<S> core_closest(const ShapeBound<S>& b, const Vec3<S>& t0,
                                                            const Vec3<S>& t1, const Vec3<S>& t2) noexcept {
    if (b.seg0 == b.seg1) {
        const Vec3<S> x = closest_on_triangle(b.seg0, t0, t1, t2);
        return {(x - b.seg0).squaredNorm(), b.seg0, x};
    }
    return segment_triangle_closest(b.seg0, b.seg1, t0, t1, t2);
}

/// Gap between the triangle's plane and the shape's extent along its unit normal (two support queries): a lower
/// bound on their distance (≤ 0 when the plane cuts the shape).
template <SupportMapped C, class S>
[[nodiscard]] inline S plane_gap(const Vec3<S>& t0, const Vec3<S>& t1, const Vec3<S>& t2, const C& shape,
                                 const ShapeBound<S>& b) noexcept {
    const Vec3<S> n = (t1 - t0).cross(t2 - t0);
    const S len = n.norm();
    if (!(len > S(0))) return S(0);
    const Vec3<S> u = n / len;
    const Vec3<S> local = b.pose.R.transpose() * u;
    const S plane = u.dot(t0);
    const S hi = u.dot(b.pose * Vec3<S>(shape.support(local)));
    const S lo = u.dot(b.pose * Vec3<S>(shape.support(Vec3<S>(-local))));
    return std::max(lo - plane, plane - hi) - b.slack;
}

/// The triangle's plane separates it from the shape, beyond the rounding and touching slack: a certain "no" that
/// spares the GJK run (near a smooth surface most triangles of the leaves reached are decided so). triangle_touches
/// tries the cheaper centre gap first (ShapeBound::centre_gap: one support query towards the triangle's point
/// nearest the shape's centre).
template <SupportMapped C, class S>
[[nodiscard]] inline bool plane_separates(const Vec3<S>& t0, const Vec3<S>& t1, const Vec3<S>& t2, const C& shape,
                                          const ShapeBound<S>& b) noexcept {
    return plane_gap(t0, t1, t2, shape, b) > b.slack;
}

/// A point of the triangle (mesh frame) in or on the shape, for a pair known to touch or overlap: EPA's deepest
/// point of the triangle when they overlap, else the middle of GJK's closest points (touching, or apart by no more
/// than the box test's slack). `g` is GJK's boolean answer on the pair.
template <SupportMapped C, class S>
[[nodiscard]] Vec3<S> gjk_witness(const ConvexTriangle<S>& tri, const C& shape, const ShapeBound<S>& b,
                                  const GjkResult<S>& g) noexcept {
    if (g.status == GjkStatus::intersecting) return penetration(tri, Transform<S>{}, shape, b.pose, g).point_a;
    if (g.status == GjkStatus::touching) return (g.point_a + g.point_b) * S(0.5);
    const GjkResult<S> d = gjk_distance(tri, Transform<S>{}, shape, b.pose);
    return (d.point_a + d.point_b) * S(0.5);
}

/// A box's boolean against the triangle (mesh frame): the separating-axis test in the box's frame.
template <class S>
[[nodiscard]] inline bool box_touches_triangle(const Box<S>& box, const ShapeBound<S>& b, const Vec3<S>& t0,
                                               const Vec3<S>& t1, const Vec3<S>& t2) noexcept {
    const Mat3<S> to_box = b.pose.R.transpose();
    return box_triangle_touch(box.half, Vec3<S>(to_box * (t0 - b.pose.t)), Vec3<S>(to_box * (t1 - b.pose.t)),
                              Vec3<S>(to_box * (t2 - b.pose.t)), b.slack);
}

/// Does the triangle (mesh frame) touch or cross the shape? `witness` (optional): a point of the triangle in the
/// shape, written on a hit (for GJK-tested shapes from EPA's witnesses, which costs an EPA run).
template <SupportMapped C, class S>
[[nodiscard]] bool triangle_touches(const Vec3<S>& t0, const Vec3<S>& t1, const Vec3<S>& t2, const C& shape,
                                    const ShapeBound<S>& b, Vec3<S>* witness) noexcept {
    if constexpr (is_sphere_v<C> || is_capsule_v<C>) {
        const SegmentTriangleClosest<S> c = core_closest(b, t0, t1, t2);
        if (!(c.dist2 <= b.radius * b.radius)) return false;
        if (witness) *witness = c.on_triangle;
        return true;
    } else if constexpr (is_box_v<C>) {
        if (!box_touches_triangle(shape, b, t0, t1, t2)) return false;
        if (witness) {
            const ConvexTriangle<S> tri(t0, t1, t2);
            *witness = gjk_witness(tri, shape, b, gjk_intersect(tri, Transform<S>{}, shape, b.pose));
        }
        return true;
    } else {
        if (b.centre_gap(closest_on_triangle(b.center, t0, t1, t2)) > b.slack || plane_separates(t0, t1, t2, shape, b))
            return false;
        const ConvexTriangle<S> tri(t0, t1, t2);  // vertices were validated with the mesh
        const GjkResult<S> g = gjk_intersect(tri, Transform<S>{}, shape, b.pose);
        if (!(g.status == GjkStatus::touching || g.status == GjkStatus::intersecting)) return false;
        if (witness) *witness = gjk_witness(tri, shape, b, g);
        return true;
    }
}

/// Distance of the triangle (mesh frame) to the shape.
template <SupportMapped C, class S>
[[nodiscard]] TriangleShapeDistance<S> triangle_shape_distance(const Vec3<S>& t0, const Vec3<S>& t1, const Vec3<S>& t2,
                                                               const C& shape, const ShapeBound<S>& b) noexcept {
    if constexpr (is_sphere_v<C> || is_capsule_v<C>) {
        const SegmentTriangleClosest<S> c = core_closest(b, t0, t1, t2);
        const S d = std::sqrt(c.dist2);
        if (!(d > b.radius)) return {S(0), c.on_triangle, c.on_triangle};
        return {d - b.radius, c.on_triangle, Vec3<S>(c.on_segment + (c.on_triangle - c.on_segment) * (b.radius / d))};
    } else {
        const ConvexTriangle<S> tri(t0, t1, t2);
        if constexpr (is_box_v<C>) {
            // Distance 0 exactly where the boolean says touching (the separating-axis test); apart by more than the
            // slack otherwise, even where GJK's own tolerance would call the pair touching.
            if (box_touches_triangle(shape, b, t0, t1, t2)) {
                const Vec3<S> m = gjk_witness(tri, shape, b, gjk_intersect(tri, Transform<S>{}, shape, b.pose));
                return {S(0), m, m};
            }
            const GjkResult<S> g = gjk_distance(tri, Transform<S>{}, shape, b.pose);
            return {std::max(g.distance, b.slack), g.point_a, g.point_b};
        }
        const GjkResult<S> g = gjk_distance(tri, Transform<S>{}, shape, b.pose);
        if (g.status == GjkStatus::touching || g.status == GjkStatus::intersecting) {
            // Touching: GJK's closest points; overlapping: EPA's deepest point of the triangle (inside the shape),
            // EPA started from this GJK run's tetrahedron where it ended on one (not a GJK run of its own).
            const Vec3<S> m = g.status == GjkStatus::touching
                                  ? Vec3<S>((g.point_a + g.point_b) * S(0.5))
                                  : Vec3<S>(penetration(tri, Transform<S>{}, shape, b.pose, g).point_a);
            return {S(0), m, m};
        }
        return {g.distance, g.point_a, g.point_b};
    }
}

}  // namespace detail
}  // namespace cdkit
