#pragma once
// CGAL's exact kernel as the referee for triangle pairs (tests and the accuracy benchmark). CGAL's triangle
// do_intersect requires non-degenerate triangles, so a triangle is first reduced, exactly, to what it is: a
// triangle, the segment between its two farthest vertices (collinear), or a point. Include only in the few
// translation units that may pay for CGAL's headers.
#include "cdkit/core/math.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <array>

namespace cdkit::test::cgal {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;

template <class S> EK::Point_3 exact_point(const Vec3<S>& v) { return {double(v.x()), double(v.y()), double(v.z())}; }

/// A triangle as it is in exact arithmetic: dim 2 triangle (a, b, c), 1 segment (a, b), 0 point a.
struct Simplex {
    int dim = 2;
    EK::Point_3 a, b, c;
};

template <class S> Simplex simplex(const std::array<Vec3<S>, 3>& t) {
    const EK::Point_3 a = exact_point(t[0]), b = exact_point(t[1]), c = exact_point(t[2]);
    if (!CGAL::collinear(a, b, c)) return {2, a, b, c};
    if (a == b && b == c) return {0, a, a, a};
    // Collinear: the segment between the farthest pair contains the third point.
    const auto ab = CGAL::squared_distance(a, b), bc = CGAL::squared_distance(b, c), ca = CGAL::squared_distance(c, a);
    if (ab >= bc && ab >= ca) return {1, a, b, a};
    if (bc >= ca) return {1, b, c, b};
    return {1, c, a, c};
}

/// Do the two closed simplices share a point? Exact.
inline bool intersect(const Simplex& s, const Simplex& t) {
    if (s.dim < t.dim) return intersect(t, s);
    switch (s.dim * 3 + t.dim) {
    case 8: return CGAL::do_intersect(EK::Triangle_3(s.a, s.b, s.c), EK::Triangle_3(t.a, t.b, t.c));
    case 7: return CGAL::do_intersect(EK::Segment_3(t.a, t.b), EK::Triangle_3(s.a, s.b, s.c));
    case 6: return EK::Triangle_3(s.a, s.b, s.c).has_on(t.a);
    case 4: return CGAL::do_intersect(EK::Segment_3(s.a, s.b), EK::Segment_3(t.a, t.b));
    case 3: return EK::Segment_3(s.a, s.b).has_on(t.a);
    default: return s.a == t.a;
    }
}

/// Exact squared distance from x to the simplex.
inline EK::FT squared_distance(const EK::Point_3& x, const Simplex& s) {
    if (s.dim == 2) return CGAL::squared_distance(x, EK::Triangle_3(s.a, s.b, s.c));
    if (s.dim == 1) return CGAL::squared_distance(x, EK::Segment_3(s.a, s.b));
    return CGAL::squared_distance(x, s.a);
}

}  // namespace cdkit::test::cgal
