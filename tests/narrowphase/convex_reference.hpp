#pragma once
// Exact-ish references for the convex narrow-phase tests: polytope distance and intersection by brute force
// over vertex/edge/face pairs in long double, and closed forms for sphere/capsule/box pairs.
#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/support.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace cdkit::test {

using L = long double;
using VL = Vec3<L>;

/// A polytope in world coordinates, long double.
struct RefPolytope {
    std::vector<VL> v;
    std::vector<std::array<std::uint32_t, 3>> tri;
};

template <class S> RefPolytope ref_polytope(const ConvexPolyhedron<S>& p, const Transform<S>& pose) {
    RefPolytope r;
    Mat3<L> R = pose.R.template cast<L>();
    VL t = pose.t.template cast<L>();
    for (const auto& x : p.vertices()) r.v.push_back(R * x.template cast<L>() + t);
    r.tri = p.triangles();
    return r;
}

inline VL closest_on_segment(const VL& p, const VL& a, const VL& b) {
    VL d = b - a;
    L dd = d.squaredNorm();
    L t = dd > 0 ? std::clamp((p - a).dot(d) / dd, L(0), L(1)) : L(0);
    return a + t * d;
}

inline VL closest_on_triangle(const VL& p, const VL& a, const VL& b, const VL& c) {
    VL n = (b - a).cross(c - a);
    L nn = n.squaredNorm();
    if (nn > 0) {
        VL q = p - n * ((p - a).dot(n) / nn);
        // Inside test with edge normals.
        bool in = (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
                  (a - c).cross(q - c).dot(n) >= 0;
        if (in) return q;
    }
    VL best = closest_on_segment(p, a, b);
    for (VL q : {closest_on_segment(p, b, c), closest_on_segment(p, c, a)})
        if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    return best;
}

/// Squared distance between segments (p1,q1) and (p2,q2) (Ericson §5.1.9, with clamping).
inline L segment_segment_dist2(const VL& p1, const VL& q1, const VL& p2, const VL& q2) {
    VL d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    L a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    L s, t;
    if (a <= 0 && e <= 0) return r.squaredNorm();
    if (a <= 0) { s = 0; t = std::clamp(f / e, L(0), L(1)); }
    else {
        L c = d1.dot(r);
        if (e <= 0) { t = 0; s = std::clamp(-c / a, L(0), L(1)); }
        else {
            L b = d1.dot(d2), den = a * e - b * b;
            s = den > 0 ? std::clamp((b * f - c * e) / den, L(0), L(1)) : L(0);
            t = (b * s + f) / e;
            if (t < 0) { t = 0; s = std::clamp(-c / a, L(0), L(1)); }
            else if (t > 1) { t = 1; s = std::clamp((b - c) / a, L(0), L(1)); }
        }
    }
    return ((p1 + d1 * s) - (p2 + d2 * t)).squaredNorm();
}

inline bool inside(const RefPolytope& P, const VL& x) {
    for (const auto& t : P.tri) {
        VL n = (P.v[t[1]] - P.v[t[0]]).cross(P.v[t[2]] - P.v[t[0]]);
        if (n.dot(x - P.v[t[0]]) > 0) return false;
    }
    return true;
}

inline bool segment_hits_triangle(const VL& p, const VL& q, const VL& a, const VL& b, const VL& c) {
    VL n = (b - a).cross(c - a);
    L sp = n.dot(p - a), sq = n.dot(q - a);
    if ((sp > 0 && sq > 0) || (sp < 0 && sq < 0) || sp == sq) return false;
    VL x = p + (q - p) * (sp / (sp - sq));
    return (b - a).cross(x - a).dot(n) >= 0 && (c - b).cross(x - b).dot(n) >= 0 && (a - c).cross(x - c).dot(n) >= 0;
}

/// Two convex polytopes intersect iff a vertex of one lies in the other or an edge of one crosses a face of
/// the other.
inline bool ref_intersect(const RefPolytope& A, const RefPolytope& B) {
    for (const auto& x : A.v) if (inside(B, x)) return true;
    for (const auto& x : B.v) if (inside(A, x)) return true;
    for (int pass = 0; pass < 2; ++pass) {
        const RefPolytope& P = pass ? B : A;
        const RefPolytope& Q = pass ? A : B;
        for (const auto& t : P.tri)
            for (int k = 0; k < 3; ++k)
                for (const auto& u : Q.tri)
                    if (segment_hits_triangle(P.v[t[k]], P.v[t[(k + 1) % 3]], Q.v[u[0]], Q.v[u[1]], Q.v[u[2]]))
                        return true;
    }
    return false;
}

/// Distance between disjoint convex polytopes (min over vertex–face and edge–edge pairs).
inline L ref_distance(const RefPolytope& A, const RefPolytope& B) {
    L best = std::numeric_limits<L>::infinity();
    for (int pass = 0; pass < 2; ++pass) {
        const RefPolytope& P = pass ? B : A;
        const RefPolytope& Q = pass ? A : B;
        for (const auto& x : P.v)
            for (const auto& u : Q.tri)
                best = std::min(best, (closest_on_triangle(x, Q.v[u[0]], Q.v[u[1]], Q.v[u[2]]) - x).squaredNorm());
    }
    for (const auto& t : A.tri)
        for (int k = 0; k < 3; ++k)
            for (const auto& u : B.tri)
                for (int m = 0; m < 3; ++m)
                    best = std::min(best, segment_segment_dist2(A.v[t[k]], A.v[t[(k + 1) % 3]], B.v[u[m]],
                                                                B.v[u[(m + 1) % 3]]));
    return std::sqrt(best);
}

/// Distance from point p to an axis-aligned box [-h, h] (0 inside).
inline L point_box_distance(const VL& p, const VL& h) {
    VL q = (p.cwiseAbs() - h).cwiseMax(VL::Zero());
    return q.norm();
}

/// Lower bound on the distance of A and B: the gap between their supporting planes orthogonal to u (any u).
template <class A, class B> L supporting_plane_gap(const A& a, const Transform<L>& pa, const B& b, const Transform<L>& pb, VL u) {
    const L n = u.norm();
    if (!(n > 0)) return -std::numeric_limits<L>::infinity();
    u /= n;
    const Transformed<A> ta{a, pa};
    const Transformed<B> tb{b, pb};
    return u.dot(tb.support(VL(-u))) - u.dot(ta.support(u));
}

/// Certified bounds [lower, upper] on the distance of A and B around a long-double GJK reference `ref`, which
/// has the rounding floor of its sub-simplex step too (on sliver triangles of curved shapes |v| can fall below
/// the distance: issue 5 found it up to 9e-9 relative below a certified lower bound on close cones). Lower:
/// the supporting-plane gaps along the reference's and a tested answer's normals; upper: the distance of the
/// reference's witness points.
template <class A, class B, class R>
std::pair<L, L> certified_interval(const A& a, const Transform<L>& pa, const B& b, const Transform<L>& pb, const R& ref,
                                   const Vec3<double>& tested_normal) {
    const L lower = std::max(supporting_plane_gap(a, pa, b, pb, ref.normal),
                             supporting_plane_gap(a, pa, b, pb, tested_normal.template cast<L>()));
    return {lower, std::max(lower, L((ref.point_b - ref.point_a).norm()))};
}

}  // namespace cdkit::test
