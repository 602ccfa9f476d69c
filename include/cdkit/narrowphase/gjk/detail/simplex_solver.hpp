#pragma once
/// \file GJK's sub-simplex step: the point of a simplex (point, segment, triangle, tetrahedron) nearest the origin
/// and the smallest sub-simplex holding it, with barycentric weights (Johnson's distance sub-algorithm of Gilbert,
/// Johnson, Keerthi, "A fast procedure for computing the distance between complex objects in three-dimensional
/// space", IEEE J. Robotics and Automation 4(2), 1988, in the Voronoi-region form of van den Bergen, "A fast and
/// robust GJK implementation for collision detection of convex objects", J. Graphics Tools 4(2), 1999), with
/// flatness and origin-side guards for degenerate simplices (Montaut et al., "Collision detection accelerated: an
/// optimization perspective", RSS 2022), and the step again in `wider_t` where its rounding may exceed the
/// tolerance.

#include <cdkit/narrowphase/gjk/types.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace cdkit {
namespace detail {

/// Closest point to the origin on the simplex `s` (point, segment, triangle or tetrahedron), computed
/// without touching `s`: the result names the vertices of the smallest sub-simplex holding that point (by
/// index into `s`, ascending) with their barycentric weights. The caller applies it only when it accepts
/// the step, so GJK's "no progress: keep the previous simplex" rule needs no copy of the simplex, and the
/// tetrahedron case evaluates its faces in place instead of copying each into a temporary simplex.
template <class S> struct SimplexSelection {
    std::array<int, 4> idx{};
    std::array<S, 4> lambda{};
    int size = 0;
    bool inside = false;  ///< origin inside a full-dimensional tetrahedron (v = 0, nothing dropped)
    Vec3<S> v = Vec3<S>::Zero();
    /// Triangle steps (size 3): |e1|²·|e2|² and |e1 × e2|² of the two edges the normal was built from, so that
    /// 1/sin² of their angle (the normal's rounding, see `triangle_step_unreliable`) costs no recomputation.
    S edges2 = S(0), normal2 = S(0);
};

template <class S> class SimplexSolver {
public:
    using Sel = SimplexSelection<S>;

    static void point(const GjkSimplex<S>& s, int i, Sel& r) noexcept {
        r.size = 1;
        r.idx[0] = i;
        r.lambda[0] = S(1);
        r.v = s.v[std::size_t(i)].w;
    }

    /// Segment i0–i1 (the closest point is measured from i0, as in the classic formulation).
    static void segment(const GjkSimplex<S>& s, int i0, int i1, Sel& r) noexcept {
        const Vec3<S>& p0 = s.v[std::size_t(i0)].w;
        const Vec3<S> d = s.v[std::size_t(i1)].w - p0;
        const S dd = d.squaredNorm();
        const S t = dd > S(0) ? -p0.dot(d) / dd : S(0);
        if (!(t > S(0))) { point(s, i0, r); return; }
        if (t >= S(1)) { point(s, i1, r); return; }
        r.size = 2;
        r.v = p0 + t * d;
        if (i0 < i1) {
            r.idx[0] = i0; r.idx[1] = i1; r.lambda[0] = S(1) - t; r.lambda[1] = t;
        } else {
            r.idx[0] = i1; r.idx[1] = i0; r.lambda[0] = t; r.lambda[1] = S(1) - t;
        }
    }

    /// Voronoi-region walk over triangle i0, i1, i2 (Ericson, "Real-Time Collision Detection", 2005,
    /// §5.1.5). On slivers the weights are as ill-conditioned as Ericson's products at a make them: callers
    /// that turn them into witness points fix them once, at the end (`sliver_weights`).
    static void triangle(const GjkSimplex<S>& s, int i0, int i1, int i2, Sel& r) noexcept {
        const Vec3<S>& a = s.v[std::size_t(i0)].w;
        const Vec3<S>& b = s.v[std::size_t(i1)].w;
        const Vec3<S>& c = s.v[std::size_t(i2)].w;
        const Vec3<S> ab = b - a, ac = c - a;
        const S d1 = -ab.dot(a), d2 = -ac.dot(a);
        if (d1 <= S(0) && d2 <= S(0)) { point(s, i0, r); return; }
        const S d3 = -ab.dot(b), d4 = -ac.dot(b);
        if (d3 >= S(0) && d4 <= d3) { point(s, i1, r); return; }
        const S vc = d1 * d4 - d3 * d2;
        if (vc <= S(0) && d1 >= S(0) && d3 <= S(0)) { segment(s, i0, i1, r); return; }
        const S d5 = -ab.dot(c), d6 = -ac.dot(c);
        if (d6 >= S(0) && d5 <= d6) { point(s, i2, r); return; }
        const S vb = d5 * d2 - d1 * d6;
        if (vb <= S(0) && d2 >= S(0) && d6 <= S(0)) { segment(s, i0, i2, r); return; }
        const S va = d3 * d6 - d5 * d4;
        if (va <= S(0) && (d4 - d3) >= S(0) && (d5 - d6) >= S(0)) { segment(s, i2, i1, r); return; }
        const S denom = va + vb + vc;
        // Squared edge lengths from the region tests' dot products (rounding only blurs which vertex is
        // chosen). The normal at a is kept unless a's angle is below 30° (then the largest is elsewhere).
        const S ab2 = d1 - d3, ac2 = d2 - d6;
        Vec3<S> n = ab.cross(ac);
        S nn = n.squaredNorm();
        r.edges2 = ab2 * ac2;
        const bool sliver = nn < S(0.25) * r.edges2;
        if (sliver) {
            n = stable_normal(b, c, ab, ac, ab2, ac2, ab2 + ac2 - S(2) * (d2 - d4), r.edges2);
            nn = n.squaredNorm();
        }
        r.normal2 = nn;
        auto best_edge = [&] {
            Sel e;
            S best = std::numeric_limits<S>::infinity();
            const int edges[3][2] = {{i0, i1}, {i1, i2}, {i0, i2}};
            for (const auto& ed : edges) {
                segment(s, ed[0], ed[1], e);
                const S dd = e.v.squaredNorm();
                if (dd < best) { best = dd; r = e; }
            }
            if (!(best < std::numeric_limits<S>::infinity())) segment(s, i0, i1, r);  // NaN data: any edge
        };
        // Degenerate (collinear) triangle that the region tests did not resolve: best edge.
        if (!(denom > S(0)) || !(nn > S(0))) { best_edge(); return; }
        // The plane projection is a point of the triangle only where it lies inside. On a sliver the
        // edge-region tests above are differences of products that cancel to rounding (a triangle 0.16 long and
        // 1e-15 wide: its squared area 4e-32 against products of 6e-4), so they may call a projection interior
        // that lies 1e-9 beyond a long edge: v then sits off the simplex, nearer than any of its points (|v|
        // 7 % below the distance between a capsule of radius 1e-9 and a box needle, in long double: a separated
        // pair answered intersecting). The projection's side of each edge, from the stable normal, decides it.
        // The plane projection is more accurate than the barycentric sum when v is small against a, b, c.
        const Vec3<S> v = n * (n.dot(a) / nn);
        if (sliver) {
            const bool inside = !(ab.cross(Vec3<S>(v - a)).dot(n) < S(0)) &&
                                !(Vec3<S>(c - b).cross(Vec3<S>(v - b)).dot(n) < S(0)) &&
                                !(Vec3<S>(a - c).cross(Vec3<S>(v - c)).dot(n) < S(0));
            if (!inside) { best_edge(); return; }
        }
        // Weights in ascending index order.
        const S l1 = vb / denom, l2 = vc / denom;
        const int ids[3] = {i0, i1, i2};
        const S lam[3] = {S(1) - l1 - l2, l1, l2};
        int o[3] = {0, 1, 2};
        if (ids[o[0]] > ids[o[1]]) std::swap(o[0], o[1]);
        if (ids[o[1]] > ids[o[2]]) std::swap(o[1], o[2]);
        if (ids[o[0]] > ids[o[1]]) std::swap(o[0], o[1]);
        r.size = 3;
        for (int k = 0; k < 3; ++k) { r.idx[std::size_t(k)] = ids[o[k]]; r.lambda[std::size_t(k)] = lam[o[k]]; }
        r.v = v;
    }

    /// Normal of triangle a, b, c as the cross product of the two edges at the vertex opposite the longest
    /// edge (its angle is the largest, ≥ 60°). The cross product of two edges rounds to a normal tilted by
    /// about ε over the sine of their angle; near contact on curved shapes GJK builds needles (two support
    /// points 1e-8 apart, the third 0.2 away), whose angle at the far vertex is ~1e-7: ab × ac from there
    /// tilted the plane enough to put |v| 1e-9 relative below the distance, even in long double.
    /// ab2, ac2, bc2: the squared edge lengths (approximate). The short edge is taken as c − b from the
    /// points, not ac − ab (which carries the rounding of the long edges).
    /// `edges2` receives the product of the two edges' squared lengths.
    static Vec3<S> stable_normal(const Vec3<S>& b, const Vec3<S>& c, const Vec3<S>& ab, const Vec3<S>& ac, S ab2,
                                 S ac2, S bc2, S& edges2) noexcept {
        if (bc2 >= ab2 && bc2 >= ac2) { edges2 = ab2 * ac2; return ab.cross(ac); }  // largest angle at a
        const Vec3<S> bc = c - b;
        if (ac2 >= ab2) { edges2 = ab2 * bc2; return ab.cross(bc); }  // at b: (b − a) × (c − b)
        edges2 = ac2 * bc2;
        return ac.cross(bc);  // at c: (c − a) × (c − b)
    }

    /// True when the origin's side of a face may be taken from side_o = −(n·p), n = e1 × e2, the face through p with
    /// edges e1, e2 (computed differences of the points). Its rounding is 16ε times the triple product's
    /// permanent, bounded by |e1|₁·|e2|₁·|p|₁ (Shewchuk, "Adaptive precision floating-point arithmetic and fast
    /// robust geometric predicates", DCG 1997: orient3d's stage-A bound is about 7ε·permanent); beyond it the sign
    /// is exact for those points. Within it, as a distance from the face's plane (bound/|n|), the rounding matters
    /// where it exceeds a few touching tolerances (1024ε·scale, scale the largest coordinate): on a sliver face
    /// (three support points along a needle 1e-8 wide and 0.02 long) the rounded normal tilts by ε over the sine of
    /// its angle, and the origin 3.5e-14 beyond such a face was called inside even in long double (a separated pair
    /// answered intersecting; an exact plane proves it apart, test_gjk_exact_plane_cgal.cpp). There the face counts as
    /// outside and the search goes on from it, as for a flat tetrahedron. On a well-shaped face the sign is kept: its
    /// error is below the tolerance, and the origin on a face of a tetrahedron deep inside D (coincident, nested
    /// shapes) stays "intersecting".
    static bool origin_side_certain(S side_o, const Vec3<S>& n, const Vec3<S>& e1, const Vec3<S>& e2,
                                    const Vec3<S>& p, S scale) noexcept {
        const S eps = std::numeric_limits<S>::epsilon();
        const S bound = S(16) * eps * (norm1(e1) * norm1(e2) * norm1(p));
        if (std::abs(side_o) > bound) return true;
        const S tol = S(1024) * eps * scale;
        return bound * bound <= tol * tol * norm2(n);
    }

    static void tetrahedron(const GjkSimplex<S>& s, Sel& r) noexcept {
        static constexpr int faces[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {0, 2, 3, 1}, {1, 3, 2, 0}};
        const S eps = std::numeric_limits<S>::epsilon();
        // A (numerically) flat tetrahedron cannot prove the origin inside: face normals built from nearly
        // coincident points are noise. Rounding in the coordinates is relative to their magnitude, so the
        // test compares the volume with ε·scale³ (treating a thin-but-real tetrahedron as flat is safe: it
        // only sends the search to the faces). The origin's side of each face is decided only beyond its own
        // rounding (`origin_side_certain`).
        S scale = S(0);
        for (std::size_t i = 0; i < 4; ++i) scale = std::max(scale, s.v[i].w.cwiseAbs().maxCoeff());
        const S vol6 = (s.v[1].w - s.v[0].w).dot((s.v[2].w - s.v[0].w).cross(s.v[3].w - s.v[0].w));
        const bool flat = !(std::abs(vol6) > S(256) * eps * scale * scale * scale);
        bool outside[4];
        bool any = false;
        for (int f = 0; f < 4; ++f) {
            const Vec3<S>& p = s.v[std::size_t(faces[f][0])].w;
            const Vec3<S> e1 = s.v[std::size_t(faces[f][1])].w - p, e2 = s.v[std::size_t(faces[f][2])].w - p;
            const Vec3<S> n = e1.cross(e2);
            const S side_l = n.dot(s.v[std::size_t(faces[f][3])].w - p);
            const S side_o = -n.dot(p);
            outside[f] = flat || !(side_o * side_l > S(0)) || !origin_side_certain(side_o, n, e1, e2, p, scale);
            any = any || outside[f];
        }
        if (!any) {
            r.inside = true;
            r.size = 4;
            r.v.setZero();
            return;
        }
        S best_d = std::numeric_limits<S>::infinity();
        bool found = false;
        Sel t;
        for (int f = 0; f < 4; ++f) {
            if (!outside[f]) continue;
            triangle(s, faces[f][0], faces[f][1], faces[f][2], t);
            const S d = t.v.squaredNorm();
            if (d < best_d || !found) { best_d = d; r = t; found = true; }
        }
    }

    /// The tetrahedron step of the cold boolean query, where vertex 3 is the newest support point. The same
    /// decisions as `tetrahedron` from fewer products: the edges from the new vertex give the three faces through
    /// it and the volume; the volume is the side of the opposite vertex for those three faces (n·(o − p) is 6 V
    /// for every face, up to orientation), so only the origin's side is evaluated per face. The flatness guard
    /// and the four origin-side tests are kept: "inside" is the overlap certificate. Only the boolean uses it, so
    /// the distance query's arithmetic is unchanged.
    static void tetrahedron_newest_last(const GjkSimplex<S>& s, Sel& r) noexcept {
        const S eps = std::numeric_limits<S>::epsilon();
        const Vec3<S>& p0 = s.v[0].w;
        const Vec3<S>& p1 = s.v[1].w;
        const Vec3<S>& p2 = s.v[2].w;
        const Vec3<S>& p3 = s.v[3].w;
        S scale = S(0);
        for (int k = 0; k < 3; ++k)
            scale = std::max({scale, std::abs(p0[k]), std::abs(p1[k]), std::abs(p2[k]), std::abs(p3[k])});
        const Vec3<S> e0 = minus(p0, p3), e1 = minus(p1, p3), e2 = minus(p2, p3);
        const Vec3<S> n01 = cross3(e0, e1), n12 = cross3(e1, e2), n20 = cross3(e2, e0);
        const S vol6 = dot3(e0, n12);  // = e1·n20 = e2·n01: the side of the opposite vertex, faces through p3
        const bool flat = !(std::abs(vol6) > S(256) * eps * scale * scale * scale);
        // Origin side of each face through p3: n·(0 − p3); outside when it differs in sign from the volume or
        // is within its rounding (`origin_side_certain`).
        auto out = [&](const Vec3<S>& n, S side_l, const Vec3<S>& ea, const Vec3<S>& eb, const Vec3<S>& p) {
            const S side_o = -dot3(n, p);
            return flat || !(side_o * side_l > S(0)) || !origin_side_certain(side_o, n, ea, eb, p, scale);
        };
        const bool out01 = out(n01, vol6, e0, e1, p3);  // face 3-0-1, opposite p2
        const bool out12 = out(n12, vol6, e1, e2, p3);  // face 3-1-2, opposite p0
        const bool out20 = out(n20, vol6, e2, e0, p3);  // face 3-2-0, opposite p1
        // The old face 0-1-2: the origin is on p3's side in exact arithmetic (p3 was found along −v), but the
        // certificate needs the test.
        const Vec3<S> f1 = minus(p1, p0), f2 = minus(p2, p0);
        const Vec3<S> m = cross3(f1, f2);
        const bool out012 = out(m, dot3(m, minus(p3, p0)), f1, f2, p0);
        if (!(out01 || out12 || out20 || out012)) {
            r.inside = true;
            r.size = 4;
            r.v.setZero();
            return;
        }
        S best_d = std::numeric_limits<S>::infinity();
        bool found = false;
        Sel t;
        auto consider = [&](bool out, int i0, int i1, int i2) {
            if (!out) return;
            triangle(s, i0, i1, i2, t);
            const S d = norm2(t.v);
            if (d < best_d || !found) { best_d = d; r = t; found = true; }
        };
        consider(out01, 0, 3, 1);
        consider(out20, 0, 2, 3);
        consider(out12, 1, 3, 2);
        consider(out012, 0, 1, 2);
    }

    /// True when the origin lies strictly inside conv(T ∪ {wp, wm}), T the triangle t0, t1, t2, with every sign
    /// beyond its rounding (`origin_side_certain`): wp and wm on opposite sides of T's plane, and the origin on
    /// the inner side of the six faces (edge of T, apex). The origin's side of T's own plane is not needed: on
    /// wp's side the three faces through wp and T's plane bound the tetrahedron (T, wp), on the other side
    /// those through wm bound (T, wm). This decides an origin that lies within rounding of a sliver T — GJK's
    /// "touching" for nested needles, whose Minkowski difference is 1e-8 thick around a plane the origin is on.
    static bool origin_in_bipyramid(const Vec3<S>& t0, const Vec3<S>& t1, const Vec3<S>& t2, const Vec3<S>& wp,
                                    const Vec3<S>& wm) noexcept {
        const Vec3<S>* t[3] = {&t0, &t1, &t2};
        S scale = S(0);
        for (const Vec3<S>* q : {t[0], t[1], t[2], &wp, &wm})
            for (int k = 0; k < 3; ++k) scale = std::max(scale, std::abs((*q)[k]));
        // The apexes' sides of T's plane: the origin test in coordinates shifted by the apex.
        const Vec3<S>& p = *t[0];
        const Vec3<S> e1 = minus(*t[1], p), e2 = minus(*t[2], p);
        const Vec3<S> n = cross3(e1, e2);
        const S sp = dot3(n, minus(wp, p)), sm = dot3(n, minus(wm, p));
        if (!(sp * sm < S(0)) || !origin_side_certain(sp, n, e1, e2, minus(p, wp), scale) ||
            !origin_side_certain(sm, n, e1, e2, minus(p, wm), scale))
            return false;
        for (const Vec3<S>* apex : {&wp, &wm})
            for (int i = 0; i < 3; ++i) {
                const Vec3<S>& pi = *t[i];
                const Vec3<S> f1 = minus(*t[(i + 1) % 3], pi), f2 = minus(*apex, pi);
                const Vec3<S> nf = cross3(f1, f2);
                const S side_l = dot3(nf, minus(*t[(i + 2) % 3], pi));
                const S side_o = -dot3(nf, pi);
                if (!(side_o * side_l > S(0)) || !origin_side_certain(side_o, nf, f1, f2, pi, scale)) return false;
            }
        return true;
    }

    /// Witness-point weights of a final triangle simplex `s` (size 3) whose closest point is `v`, recomputed where
    /// the triangle is a sliver (smallest angle below 30°). Ericson's weights are ratios of products taken at
    /// one vertex, whose cancellation on a needle (two support points ~1e-8 apart, the third ~0.2 away) slid
    /// the witness points along it — by up to 3.7e-3 (the needle ~0.2 long) with the far vertex first, 1e-11
    /// otherwise — while |v| was right. Here, with the short edge u–w taken from the points (exact for a needle), the
    /// normal n built at the largest angle (`stable_normal`) and f the vertex opposite the short edge: f's
    /// weight is the area of (v, u, w) over the triangle's, n·((w − u) × (v − u)) / |n|², and the rest is
    /// split by where the line from f through v meets u–w. Done once per query, on the final simplex, so the
    /// iterations (and every distance) keep their bits.
    static void sliver_weights(GjkSimplex<S>& s, const Vec3<S>& v) noexcept {
        if (s.size != 3) return;
        const Vec3<S>& a = s.v[0].w;
        const Vec3<S>& b = s.v[1].w;
        const Vec3<S>& c = s.v[2].w;
        const Vec3<S> ab = b - a, ac = c - a;
        const S ab2 = ab.squaredNorm(), ac2 = ac.squaredNorm(), bc2 = (c - b).squaredNorm();
        const Vec3<S> n0 = ab.cross(ac);
        if (!(n0.squaredNorm() < S(0.25) * std::max({ab2 * ac2, ab2 * bc2, ac2 * bc2}))) return;
        S edges2 = S(0);
        const Vec3<S> n = stable_normal(b, c, ab, ac, ab2, ac2, bc2, edges2);
        const S nn = n.squaredNorm();
        if (!(nn > S(0))) return;
        const Vec3<S>* pts[3] = {&a, &b, &c};
        const int f = bc2 <= ab2 && bc2 <= ac2 ? 0 : (ac2 <= ab2 ? 1 : 2);  // opposite the shortest edge
        const Vec3<S>& pf = *pts[f];
        const Vec3<S>& pu = *pts[(f + 1) % 3];
        const Vec3<S>& pw = *pts[(f + 2) % 3];
        const Vec3<S> uw = pw - pu;
        const S lf = n.dot(uw.cross(Vec3<S>(v - pu))) / nn;
        const S uw2 = uw.squaredNorm();
        if (!(lf >= S(0) && lf < S(1) && uw2 > S(0))) return;
        const Vec3<S> q = pf + (v - pf) / (S(1) - lf);  // on the line u–w
        const S t = std::clamp(S((q - pu).dot(uw) / uw2), S(0), S(1));
        S lam[3];
        lam[f] = lf;
        lam[(f + 1) % 3] = (S(1) - lf) * (S(1) - t);
        lam[(f + 2) % 3] = (S(1) - lf) * t;
        if (!(std::isfinite(lam[0]) && std::isfinite(lam[1]) && std::isfinite(lam[2]))) return;
        for (std::size_t k = 0; k < 3; ++k) s.lambda[k] = lam[k];
    }

    /// Closest point of the whole simplex `s` (size 1..4).
    static void select(const GjkSimplex<S>& s, Sel& r) noexcept {
        r.inside = false;
        switch (s.size) {
            case 1: point(s, 0, r); return;
            case 2: segment(s, 0, 1, r); return;
            case 3: triangle(s, 0, 1, 2, r); return;
            default: tetrahedron(s, r); return;
        }
    }

    /// Reduces `s` to the selection (indices ascending, so moving down in place is safe).
    static void apply(GjkSimplex<S>& s, const Sel& r) noexcept {
        if (r.inside) return;
        for (int k = 0; k < r.size; ++k) {
            const std::size_t from = std::size_t(r.idx[std::size_t(k)]);
            if (from != std::size_t(k)) s.v[std::size_t(k)] = s.v[from];
            s.lambda[std::size_t(k)] = r.lambda[std::size_t(k)];
        }
        s.size = r.size;
    }

    /// Reduces `s` to the sub-simplex holding its closest point `v`; true when the origin is inside a
    /// full-dimensional tetrahedron (then `v` is zero and `s` is unchanged).
    static bool solve(GjkSimplex<S>& s, Vec3<S>& v) noexcept {
        Sel r;
        select(s, r);
        apply(s, r);
        v = r.v;
        return r.inside;
    }
};

/// True when the rounding of the triangle step `sel` (closest point v on triangle s.v[sel.idx[0..2]]) may
/// exceed `tol`: the computed normal tilts by about ε over the sine of the angle it is built at (the largest,
/// see `SimplexSolver::stable_normal`), which moves the projection by that angle times the lever arm, the
/// farthest vertex from v. Compared in squares, without division.
template <class S> [[nodiscard]] inline bool triangle_step_unreliable(const GjkSimplex<S>& s,
                                                                      const SimplexSelection<S>& sel, S tol) noexcept {
    if (!(sel.normal2 > S(0))) return true;
    S lever2 = S(0);
    for (int k = 0; k < 3; ++k)
        lever2 = std::max(lever2, (s.v[std::size_t(sel.idx[std::size_t(k)])].w - sel.v).squaredNorm());
    const S eps = std::numeric_limits<S>::epsilon();
    return eps * eps * sel.edges2 * lever2 > tol * tol * sel.normal2;
}

/// True when the triangle step on s.v[0..2] may move its closest point by `tol` (tol2 = tol²) or more through
/// rounding. The edges carry the coordinates' absolute rounding, ε·M (M the largest |w|), which on a short edge
/// tilts the normal by ε·M·P/|n| (P the perimeter, |n| twice the area) and moves the projection by that times a
/// lever arm ≤ P; a factor 4 covers the step's own operations. triangle_step_unreliable measures the rounding
/// relative to the edges' lengths, which misses it where a short edge sits far from the origin. Compared in
/// squares (P² ≤ 3·Σ|e|²), no root.
template <class S> [[nodiscard]] inline bool sliver_step_may_reach(const GjkSimplex<S>& s, S tol2) noexcept {
    const Vec3<S>& a = s.v[0].w;
    const Vec3<S>& b = s.v[1].w;
    const Vec3<S>& c = s.v[2].w;
    const S m2 = std::max({a.squaredNorm(), b.squaredNorm(), c.squaredNorm()});
    const S p2 = S(3) * ((b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm());
    const S nn = (b - a).cross(c - a).squaredNorm();
    const S eps = std::numeric_limits<S>::epsilon();
    return S(16) * eps * eps * m2 * p2 * p2 > tol2 * nn;
}

/// The sub-simplex step on the first `n + 1` vertices of `s`, in `wider_t<S>`. With `always` false: true
/// (and `sel` set) when that step's closest point is strictly nearer than the one of the first `n` vertices,
/// both in the wide type. With `always` true: `sel` is the step's selection whenever it is not "inside".
template <class S> inline bool refine_step(const GjkSimplex<S>& s, int n, SimplexSelection<S>& sel,
                                           bool always = false) noexcept {
    using W = wider_t<S>;
    GjkSimplex<W> ws;
    for (int i = 0; i <= n; ++i) ws.v[std::size_t(i)].w = s.v[std::size_t(i)].w.template cast<W>();
    SimplexSelection<W> full, prev;
    ws.size = n + 1;
    SimplexSolver<W>::select(ws, full);
    if (full.inside || !full.v.allFinite()) return false;
    if (!always) {
        ws.size = n;
        SimplexSolver<W>::select(ws, prev);
        if (!(full.v.squaredNorm() < prev.v.squaredNorm())) return false;
    }
    sel.inside = false;
    sel.size = full.size;
    for (int k = 0; k < full.size; ++k) {
        sel.idx[std::size_t(k)] = full.idx[std::size_t(k)];
        sel.lambda[std::size_t(k)] = S(full.lambda[std::size_t(k)]);
    }
    sel.v = full.v.template cast<S>();
    return true;
}

}  // namespace detail
}  // namespace cdkit
