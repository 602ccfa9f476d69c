/// \file CGAL's exact kernel as the referee of the accuracy benchmark (the only TU that includes CGAL).

#include "oracles.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <numeric>

namespace cdkit::accuracy {
namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using P = EK::Point_3;

/// A triangle as it is in exact arithmetic: dim 2 triangle (a, b, c), 1 segment (a, b), 0 point a.
struct Simplex {
    int dim = 2;
    P a, b, c;
};

Simplex simplex(const Tri3& t) {
    const P a(t[0].x(), t[0].y(), t[0].z()), b(t[1].x(), t[1].y(), t[1].z()), c(t[2].x(), t[2].y(), t[2].z());
    if (!CGAL::collinear(a, b, c)) return {2, a, b, c};
    if (a == b && b == c) return {0, a, a, a};
    // Collinear: the segment between the farthest pair contains the third point.
    const auto ab = CGAL::squared_distance(a, b), bc = CGAL::squared_distance(b, c), ca = CGAL::squared_distance(c, a);
    if (ab >= bc && ab >= ca) return {1, a, b, a};
    if (bc >= ca) return {1, b, c, b};
    return {1, c, a, c};
}

bool intersect(const Simplex& s, const Simplex& t) {
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

}  // namespace

bool exact_triangles_intersect(const Tri3& p, const Tri3& q) { return intersect(simplex(p), simplex(q)); }

PairList exact_intersecting_pairs(const TriangleMesh<double>& a, const TriangleMesh<double>& b) {
    struct Box {
        Vec3<double> lo, hi;
    };
    auto boxes = [](const TriangleMesh<double>& m) {
        std::vector<Box> out;
        out.reserve(m.triangles.size());
        for (const auto& t : m.triangles) {
            const auto& v0 = m.vertices[t[0]];
            const auto& v1 = m.vertices[t[1]];
            const auto& v2 = m.vertices[t[2]];
            out.push_back({v0.cwiseMin(v1).cwiseMin(v2), v0.cwiseMax(v1).cwiseMax(v2)});  // min/max are exact
        }
        return out;
    };
    const std::vector<Box> ba = boxes(a), bb = boxes(b);
    // Sweep along x: B's triangles sorted by lo.x; for each A triangle scan those with lo.x <= its hi.x.
    std::vector<Index> order(bb.size());
    std::iota(order.begin(), order.end(), Index(0));
    std::sort(order.begin(), order.end(), [&](Index i, Index j) { return bb[i].lo.x() < bb[j].lo.x(); });
    std::vector<Simplex> sb(b.triangles.size());
    std::vector<char> have_sb(b.triangles.size(), 0);
    PairList out;
    for (Index i = 0; i < a.triangles.size(); ++i) {
        const Box& x = ba[i];
        const Simplex sa = simplex(a.triangle(i));
        for (Index j : order) {
            const Box& y = bb[j];
            if (y.lo.x() > x.hi.x()) break;
            if ((y.hi.array() < x.lo.array()).any() || (y.lo.array() > x.hi.array()).any()) continue;
            if (!have_sb[j]) sb[j] = simplex(b.triangle(j)), have_sb[j] = 1;
            if (intersect(sa, sb[j])) out.emplace_back(i, j);
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace cdkit::accuracy
