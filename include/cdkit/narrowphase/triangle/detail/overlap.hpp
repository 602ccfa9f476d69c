#pragma once
/// \file The triangle–triangle test itself (P. Guigue, O. Devillers, "Fast and Robust Triangle-Triangle Overlap
/// Test Using Orientation Predicates", JGT 8(1), 2003), written against a predicate kernel
/// (triangle/detail/kernels.hpp): the general case, the coplanar case, zero-area triangles reduced to the segment or
/// point they are, and the witness segment. narrowphase/triangle.hpp is the public entry.

#include "cdkit/narrowphase/triangle/detail/kernels.hpp"

#include <cmath>
#include <optional>
#include <type_traits>
#include <utility>

namespace cdkit::detail::tritri {

template <class T> struct Witness {
    bool coplanar = false;
    Pt3<T> a{}, b{};
};

/// The point of segment xy where a function that is affine along it, with values vx at x and vy at y,
/// vanishes. Callers guarantee vx·vy <= 0 and not both zero (signs taken from these very values, or
/// exact values with exact signs), so vx − vy has no cancellation and is nonzero; the guard only keeps
/// a broken precondition from dividing by zero. Interpolates from the end nearer the zero for accuracy.
template <class T> [[nodiscard]] inline Pt3<T> zero_on_segment(const Pt3<T>& x, const Pt3<T>& y, T vx, T vy) noexcept {
    if (vx == T(0)) return x;
    if (vy == T(0)) return y;
    const bool from_x = std::abs(vx) <= std::abs(vy);
    const Pt3<T>& o = from_x ? x : y;
    const Pt3<T>& e = from_x ? y : x;
    const T vo = from_x ? vx : vy, ve = from_x ? vy : vx;
    const T den = vo - ve;
    if (!(den != T(0))) return o;
    const T t = vo / den;
    return {o.x + t * (e.x - o.x), o.y + t * (e.y - o.y), o.z + t * (e.z - o.z)};
}
template <class T> [[nodiscard]] inline Pt3<T> along(const Pt3<T>& a, const Pt3<T>& b, T t) noexcept {
    return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.z + t * (b.z - a.z)};
}
template <class T> [[nodiscard]] inline bool same_point(const Pt3<T>& a, const Pt3<T>& b) noexcept {
    return a.x == b.x && a.y == b.y && a.z == b.z;
}
template <class T> [[nodiscard]] inline T dist2(const Pt3<T>& a, const Pt3<T>& b) noexcept {
    const T x = a.x - b.x, y = a.y - b.y, z = a.z - b.z;
    return x * x + y * y + z * z;
}

/// Axes ordered by decreasing |n_k| of an approximate normal: the first is the projection that distorts
/// least, and usually the first one whose exact orient2d is nonzero.
template <class T> inline void axes_by_magnitude(const Pt3<T>& n, int (&order)[3]) noexcept {
    const T ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
    if (ax >= ay && ax >= az) {
        order[0] = 0;
        order[1] = ay >= az ? 1 : 2;
    } else if (ay >= az) {
        order[0] = 1;
        order[1] = ax >= az ? 0 : 2;
    } else {
        order[0] = 2;
        order[1] = ax >= ay ? 0 : 1;
    }
    order[2] = 3 - order[0] - order[1];
}

/// An axis k whose projection maps the triangle's plane one-to-one (exactly: the normal's k-th component
/// is nonzero, decided by orient2d), or −1 when the triangle is degenerate (all three components zero).
/// Choosing the projection by the rounded normal alone would not be robust; here the rounded normal only
/// orders the trials.
template <class K> [[nodiscard]] int plane_axis(const typename K::P (&t)[3]) noexcept {
    using T = typename K::T;
    const T bax = t[1].x - t[0].x, bay = t[1].y - t[0].y, baz = t[1].z - t[0].z;
    const T cax = t[2].x - t[0].x, cay = t[2].y - t[0].y, caz = t[2].z - t[0].z;
    const Pt3<T> n{bay * caz - baz * cay, baz * cax - bax * caz, bax * cay - bay * cax};
    int order[3];
    axes_by_magnitude(n, order);
    for (int k : order)
        if (K::orient2(t[0], t[1], t[2], k) != 0) return k;
    return -1;
}

/// A zero-area triangle as the segment (a, b) between its extreme vertices, or the point a (returns
/// false) when all three coincide. Exact: for collinear points, the order along a coordinate axis with
/// distinct coordinates is their order along the line.
template <class T> bool collapse(const Pt3<T> (&t)[3], Pt3<T>& a, Pt3<T>& b) noexcept {
    int best = -1;
    T best_range = T(0);
    for (int k = 0; k < 3; ++k) {
        int lo = 0, hi = 0;
        for (int i = 1; i < 3; ++i) {
            if (coord(t[i], k) < coord(t[lo], k)) lo = i;
            if (coord(t[i], k) > coord(t[hi], k)) hi = i;
        }
        const T range = coord(t[hi], k) - coord(t[lo], k);
        if (range > best_range) {
            best = k;
            best_range = range;
            a = t[lo];
            b = t[hi];
        }
    }
    if (best < 0) {
        a = b = t[0];
        return false;
    }
    return true;
}

/// The axis of the largest |b − a| component (nonzero when a != b).
template <class T> [[nodiscard]] inline int longest_axis(const Pt3<T>& a, const Pt3<T>& b) noexcept {
    const Pt3<T> d{b.x - a.x, b.y - a.y, b.z - a.z};
    int order[3];
    axes_by_magnitude(d, order);
    return order[0];
}

template <class K> [[nodiscard]] bool collinear(const typename K::P& a, const typename K::P& b, const typename K::P& x) noexcept {
    return K::orient2(a, b, x, 0) == 0 && K::orient2(a, b, x, 1) == 0 && K::orient2(a, b, x, 2) == 0;
}

/// x on the closed segment ab (a != b).
template <class K> [[nodiscard]] bool on_segment(const typename K::P& x, const typename K::P& a, const typename K::P& b) noexcept {
    if (!collinear<K>(a, b, x)) return false;
    const int m = longest_axis(a, b);
    const auto lo = std::min(coord(a, m), coord(b, m)), hi = std::max(coord(a, m), coord(b, m));
    return lo <= coord(x, m) && coord(x, m) <= hi;
}

/// Segment/point (a,b) vs segment/point (c,d): both triangles degenerate.
template <class K, bool W>
bool simplex_simplex(const typename K::P& a, const typename K::P& b, bool seg_ab, const typename K::P& c,
                     const typename K::P& d, bool seg_cd, Witness<typename K::T>* out) noexcept {
    using T = typename K::T;
    using P = typename K::P;
    auto touch = [&](const P& x) {
        if constexpr (W) out->a = out->b = x;
        return true;
    };
    if (!seg_ab && !seg_cd) return same_point(a, c) && touch(a);
    if (!seg_ab) return on_segment<K>(a, c, d) && touch(a);
    if (!seg_cd) return on_segment<K>(c, a, b) && touch(c);
    if (K::above(a, b, c, d) != 0) return false;  // segments not in one plane never meet
    const bool c_on = collinear<K>(a, b, c), d_on = collinear<K>(a, b, d);
    if (c_on && d_on) {
        // All on one line: compare along the axis where the line has its largest component.
        const int m = longest_axis(a, b);
        const bool ab_up = coord(a, m) <= coord(b, m), cd_up = coord(c, m) <= coord(d, m);
        const P& lo1 = ab_up ? a : b;
        const P& hi1 = ab_up ? b : a;
        const P& lo2 = cd_up ? c : d;
        const P& hi2 = cd_up ? d : c;
        if (coord(hi1, m) < coord(lo2, m) || coord(hi2, m) < coord(lo1, m)) return false;
        if constexpr (W) {
            out->a = coord(lo1, m) >= coord(lo2, m) ? lo1 : lo2;
            out->b = coord(hi1, m) <= coord(hi2, m) ? hi1 : hi2;
        }
        return true;
    }
    // One plane, two distinct lines: project along an axis the plane is not parallel to (exactly).
    const P& off = c_on ? d : c;
    int k = -1;
    for (int kk = 0; kk < 3 && k < 0; ++kk)
        if (K::orient2(a, b, off, kk) != 0) k = kk;
    if (k < 0) return false;  // unreachable with exact predicates
    T v1{}, v2{};
    const int o1 = K::orient2(a, b, c, k, v1), o2 = K::orient2(a, b, d, k, v2);
    const int o3 = K::orient2(c, d, a, k), o4 = K::orient2(c, d, b, k);
    if (o1 * o2 > 0 || o3 * o4 > 0) return false;
    if constexpr (W) {
        // The lines meet in one point; an end point on the other line is that point.
        if (o1 == 0) out->a = c;
        else if (o2 == 0) out->a = d;
        else if (o3 == 0) out->a = a;
        else if (o4 == 0) out->a = b;
        else out->a = zero_on_segment(c, d, K::value2(a, b, c, k, v1), K::value2(a, b, d, k, v2));
        out->b = out->a;
    }
    return true;
}

/// Segment/point (a,b) vs a non-degenerate triangle q, all in q's plane; k projects that plane
/// one-to-one. Separating-axis argument: two disjoint compact convex polygons are strictly separated by a
/// line through an edge of one of them, so testing the triangle's edges and the segment's line suffices.
template <class K, bool W>
bool coplanar_simplex_triangle(const typename K::P& a, const typename K::P& b, bool seg, const typename K::P (&q)[3],
                               int k, Witness<typename K::T>* out) noexcept {
    using T = typename K::T;
    using P = typename K::P;
    P t[3] = {q[0], q[1], q[2]};
    if (K::orient2(t[0], t[1], t[2], k) < 0) std::swap(t[1], t[2]);  // counterclockwise: inside is left
    if (!seg) {
        for (int e = 0; e < 3; ++e)
            if (K::orient2(t[e], t[(e + 1) % 3], a, k) < 0) return false;
        if constexpr (W) out->a = out->b = a;
        return true;
    }
    int oa[3], ob[3];
    T va[3], vb[3];
    for (int e = 0; e < 3; ++e) {
        oa[e] = K::orient2(t[e], t[(e + 1) % 3], a, k, va[e]);
        ob[e] = K::orient2(t[e], t[(e + 1) % 3], b, k, vb[e]);
        if (oa[e] < 0 && ob[e] < 0) return false;
    }
    const int s0 = K::orient2(a, b, t[0], k), s1 = K::orient2(a, b, t[1], k), s2 = K::orient2(a, b, t[2], k);
    if ((s0 > 0 && s1 > 0 && s2 > 0) || (s0 < 0 && s1 < 0 && s2 < 0)) return false;
    if constexpr (W) {
        // Clip the parameter range [0,1] of a→b by the three edge half-planes.
        T lo = T(0), hi = T(1);
        for (int e = 0; e < 3; ++e) {
            if (oa[e] >= 0 && ob[e] >= 0) continue;
            const P& e0 = t[e];
            const P& e1 = t[(e + 1) % 3];
            const T x = K::value2(e0, e1, a, k, va[e]), y = K::value2(e0, e1, b, k, vb[e]);
            const T den = x - y;  // x < 0 <= y or y < 0 <= x: no cancellation, nonzero
            const T tt = den != T(0) ? x / den : T(0);
            if (oa[e] < 0) lo = std::max(lo, tt);
            else hi = std::min(hi, tt);
        }
        if (lo > hi) lo = hi = (lo + hi) / T(2);  // a single touching point, split by rounding
        out->a = along(a, b, lo);
        out->b = along(a, b, hi);
    }
    return true;
}

/// Segment/point (a,b) vs a non-degenerate triangle q (kq: an exact projection axis of q's plane).
template <class K, bool W>
bool simplex_triangle(const typename K::P& a, const typename K::P& b, bool seg, const typename K::P (&q)[3], int kq,
                      Witness<typename K::T>* out) noexcept {
    using T = typename K::T;
    const typename K::Plane plane(q[0], q[1], q[2]);
    T va{}, vb{};
    const int sa = plane.above(a, va);
    int sb = sa;
    vb = va;
    if (seg) sb = plane.above(b, vb);
    if (sa == sb && sa != 0) return false;
    if (sa == 0 && sb == 0) return coplanar_simplex_triangle<K, W>(a, b, seg, q, kq, out);
    // The line ab crosses q's plane in one point X. The three volumes det[b−a, q_i−a, q_j−a] are X's
    // barycentric coordinates times the nonzero (b−a)·n_q: X is in the closed triangle iff they do not
    // have strictly opposite signs.
    const int s0 = K::above(a, b, q[0], q[1]), s1 = K::above(a, b, q[1], q[2]), s2 = K::above(a, b, q[2], q[0]);
    if ((s0 > 0 || s1 > 0 || s2 > 0) && (s0 < 0 || s1 < 0 || s2 < 0)) return false;
    if constexpr (W) {
        const typename K::Values value(q[0], q[1], q[2]);
        out->a = zero_on_segment(a, b, value(a, va), value(b, vb));
        out->b = out->a;
    }
    return true;
}

/// Two non-degenerate triangles in one plane; k projects it one-to-one. Same separating-axis argument as
/// above: disjoint iff all vertices of one triangle lie strictly outside one edge of the other.
template <class K, bool W>
bool coplanar_triangles(const typename K::P (&p)[3], const typename K::P (&q)[3], int k, Witness<typename K::T>* out) noexcept {
    using T = typename K::T;
    using P = typename K::P;
    P s[3] = {p[0], p[1], p[2]};
    P t[3] = {q[0], q[1], q[2]};
    if (K::orient2(s[0], s[1], s[2], k) < 0) std::swap(s[1], s[2]);
    if (K::orient2(t[0], t[1], t[2], k) < 0) std::swap(t[1], t[2]);
    if constexpr (!W) {
        for (int e = 0; e < 3; ++e) {
            const P& a = s[e];
            const P& b = s[(e + 1) % 3];
            if (K::orient2(a, b, t[0], k) < 0 && K::orient2(a, b, t[1], k) < 0 && K::orient2(a, b, t[2], k) < 0)
                return false;
        }
        for (int e = 0; e < 3; ++e) {
            const P& a = t[e];
            const P& b = t[(e + 1) % 3];
            if (K::orient2(a, b, s[0], k) < 0 && K::orient2(a, b, s[1], k) < 0 && K::orient2(a, b, s[2], k) < 0)
                return false;
        }
        (void)out;
        return true;
    } else {
        int os[3][3], ot[3][3];  // os[e][j]: side of t[j] w.r.t. edge e of s; ot[e][i]: side of s[i] w.r.t. edge e of t
        T vs[3][3], vt[3][3];
        for (int e = 0; e < 3; ++e) {
            for (int j = 0; j < 3; ++j) {
                os[e][j] = K::orient2(s[e], s[(e + 1) % 3], t[j], k, vs[e][j]);
                ot[e][j] = K::orient2(t[e], t[(e + 1) % 3], s[j], k, vt[e][j]);
            }
        }
        for (int e = 0; e < 3; ++e)
            if ((os[e][0] < 0 && os[e][1] < 0 && os[e][2] < 0) || (ot[e][0] < 0 && ot[e][1] < 0 && ot[e][2] < 0))
                return false;
        // Every vertex of the overlap polygon is a vertex of one triangle inside the other, or a proper
        // crossing of two edges (a crossing at an end point is a vertex inside the other triangle).
        P cand[15];
        int n = 0;
        for (int i = 0; i < 3; ++i)
            if (ot[0][i] >= 0 && ot[1][i] >= 0 && ot[2][i] >= 0) cand[n++] = s[i];
        for (int j = 0; j < 3; ++j)
            if (os[0][j] >= 0 && os[1][j] >= 0 && os[2][j] >= 0) cand[n++] = t[j];
        for (int e = 0; e < 3; ++e) {
            const int e1 = (e + 1) % 3;
            for (int f = 0; f < 3; ++f) {
                const int f1 = (f + 1) % 3;
                if (os[e][f] * os[e][f1] < 0 && ot[f][e] * ot[f][e1] < 0)
                    cand[n++] = zero_on_segment(t[f], t[f1], K::value2(s[e], s[e1], t[f], k, vs[e][f]),
                                                K::value2(s[e], s[e1], t[f1], k, vs[e][f1]));
            }
        }
        out->coplanar = true;
        if (n == 0) {  // unreachable with exact predicates
            out->a = out->b = s[0];
            return true;
        }
        int bi = 0, bj = 0;
        T best = T(-1);
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j) {
                const T d = dist2(cand[i], cand[j]);
                if (d > best) {
                    best = d;
                    bi = i;
                    bj = j;
                }
            }
        out->a = cand[bi];
        out->b = cand[bj];
        return true;
    }
}

/// At least one triangle has all of the other's vertices in its plane: coplanar, or degenerate.
template <class K, bool W>
bool flat_case(const typename K::P (&p)[3], const typename K::P (&q)[3], Witness<typename K::T>* out) noexcept {
    using P = typename K::P;
    const int kp = plane_axis<K>(p), kq = plane_axis<K>(q);
    if (kp >= 0 && kq >= 0) return coplanar_triangles<K, W>(p, q, kp, out);
    P a{}, b{}, c{}, d{};
    if (kp < 0 && kq < 0) {
        const bool sp = collapse(p, a, b), sq = collapse(q, c, d);
        return simplex_simplex<K, W>(a, b, sp, c, d, sq, out);
    }
    if (kp < 0) {
        const bool sp = collapse(p, a, b);
        return simplex_triangle<K, W>(a, b, sp, q, kq, out);
    }
    const bool sq = collapse(q, c, d);
    return simplex_triangle<K, W>(c, d, sq, p, kp, out);
}

/// Rotation r (vertex r comes first) and whether to flip the other triangle's orientation so that the
/// signs become s0 >= 0 >= s1, s2 with s0 == 0 only when s1, s2 < 0: then edges 0–1 and 0–2 each meet the
/// other plane in exactly one point. Precondition: the signs are neither all equal nor all zero.
inline void canonical(const int (&s)[3], int& r, bool& flip) noexcept {
    const int pos = (s[0] > 0) + (s[1] > 0) + (s[2] > 0);
    const int neg = (s[0] < 0) + (s[1] < 0) + (s[2] < 0);
    auto first = [&](int want) { return s[0] == want ? 0 : (s[1] == want ? 1 : 2); };
    if (pos == 1) {  // (+, <=0, <=0)
        r = first(1);
        flip = false;
    } else if (neg == 1) {  // (−, >=0, >=0)
        r = first(-1);
        flip = true;
    } else if (pos == 2) {  // (0, +, +)
        r = first(0);
        flip = true;
    } else {  // (0, −, −)
        r = first(0);
        flip = false;
    }
}

template <class P, class T> inline void rotate3(P (&x)[3], int (&s)[3], T (&v)[3], int r) noexcept {
    if (r == 0) return;
    const P x0 = x[0], x1 = x[1], x2 = x[2];
    const int s0 = s[0], s1 = s[1], s2 = s[2];
    const T v0 = v[0], v1 = v[1], v2 = v[2];
    if (r == 1) {
        x[0] = x1, x[1] = x2, x[2] = x0;
        s[0] = s1, s[1] = s2, s[2] = s0;
        v[0] = v1, v[1] = v2, v[2] = v0;
    } else {
        x[0] = x2, x[1] = x0, x[2] = x1;
        s[0] = s2, s[1] = s0, s[2] = s1;
        v[0] = v2, v[1] = v0, v[2] = v1;
    }
}
template <class P, class T> inline void flip3(P (&x)[3], int (&s)[3], T (&v)[3]) noexcept {
    std::swap(x[1], x[2]);
    std::swap(s[1], s[2]);
    std::swap(v[1], v[2]);
}
template <class T> inline void negate3(int (&s)[3], T (&v)[3]) noexcept {
    for (int i = 0; i < 3; ++i) {
        s[i] = -s[i];
        v[i] = -v[i];
    }
}

/// The test. p and q are permuted in place (canonical form), so callers pass copies.
template <class K, bool W>
bool triangle_triangle(typename K::P (&p)[3], typename K::P (&q)[3], Witness<typename K::T>* out) noexcept {
    using T = typename K::T;
    // 1. P against Q's plane. All three strictly on one side is the common, cheap rejection (filtered
    //    orient3d only). A degenerate Q gives three zeros here and cannot reject wrongly.
    auto one_side = [](const int (&s)[3]) {
        return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
    };
    int sp[3], sq[3];
    T vp[3], vq[3];
    if (typename K::Plane(q[0], q[1], q[2]).above3(p, sp, vp) != 0 || one_side(sp)) return false;
    // 2. Q against P's plane.
    if (typename K::Plane(p[0], p[1], p[2]).above3(q, sq, vq) != 0 || one_side(sq)) return false;
    // 3. All of one triangle in the other's plane: coplanar triangles, or a degenerate triangle (a
    //    degenerate triangle makes the other's signs all zero). Otherwise both are non-degenerate and the
    //    planes cross in a line L.
    if ((sp[0] == 0 && sp[1] == 0 && sp[2] == 0) || (sq[0] == 0 && sq[1] == 0 && sq[2] == 0))
        return flat_case<K, W>(p, q, out);
    // 4. Canonical form (Guigue–Devillers): p0 alone on the positive side of Q's plane (p1, p2 on the
    //    non-positive side), q0 alone on the positive side of P's plane. Rotations keep orientations; a
    //    flip (swapping vertices 1 and 2) reverses one triangle's orientation and so negates the other's
    //    signs. Then P ∩ L = [j, i] with i on p0p1, j on p0p2, and Q ∩ L = [k, l] with k on q0q1, l on
    //    q0q2, ordered along L's direction n_P × n_Q; and for edges p0pa, q0qb meeting L at x and y,
    //    above(p0, pa, q0, qb) has the sign of y − x along L (docs/triangle.md derives this).
    int r;
    bool flip;
    canonical(sp, r, flip);
    rotate3(p, sp, vp, r);
    if (flip) {
        flip3(q, sq, vq);
        negate3(sp, vp);
    }
    canonical(sq, r, flip);
    rotate3(q, sq, vq, r);
    if (flip) {
        flip3(p, sp, vp);
        negate3(sq, vq);
    }
    // 5. The intervals overlap iff k <= i and j <= l.
    if (K::above(p[0], p[1], q[0], q[1]) > 0) return false;
    if (K::above(p[0], p[2], q[0], q[2]) < 0) return false;
    if constexpr (W) {
        // Segment = [max(j, k), min(i, l)], the order decided by two more exact signs.
        const bool k_after_j = K::above(p[0], p[2], q[0], q[1]) > 0;
        const bool l_after_i = K::above(p[0], p[1], q[0], q[2]) > 0;
        // Accurate plane values only for the planes that are needed (their normals cost the most).
        std::optional<typename K::Values> on_q, on_p;  // values against Q's plane, P's plane
        if (!k_after_j || l_after_i) on_q.emplace(q[0], q[1], q[2]);
        if (k_after_j || !l_after_i) on_p.emplace(p[0], p[1], p[2]);
        auto on_p_edge = [&](int e) {  // P's edge p0–pe ∩ Q's plane
            return zero_on_segment(p[0], p[e], (*on_q)(p[0], vp[0]), (*on_q)(p[e], vp[e]));
        };
        auto on_q_edge = [&](int e) {  // Q's edge q0–qe ∩ P's plane
            return zero_on_segment(q[0], q[e], (*on_p)(q[0], vq[0]), (*on_p)(q[e], vq[e]));
        };
        out->coplanar = false;
        out->a = k_after_j ? on_q_edge(1) : on_p_edge(2);
        out->b = l_after_i ? on_p_edge(1) : on_q_edge(2);
    }
    return true;
}

template <class K, class S, bool W>
bool run(const Vec3<S>& p0, const Vec3<S>& p1, const Vec3<S>& p2, const Vec3<S>& q0, const Vec3<S>& q1,
         const Vec3<S>& q2, Witness<typename K::T>* out) noexcept {
    using T = typename K::T;
    Pt3<T> p[3] = {to_pt<T>(p0), to_pt<T>(p1), to_pt<T>(p2)};
    Pt3<T> q[3] = {to_pt<T>(q0), to_pt<T>(q1), to_pt<T>(q2)};
    if constexpr (std::is_same_v<K, ExactKernel> && std::is_same_v<S, double>) {
        // float input is always in range; double input is checked once per pair, not per predicate.
        const double x[18] = {p[0].x, p[0].y, p[0].z, p[1].x, p[1].y, p[1].z, p[2].x, p[2].y, p[2].z,
                              q[0].x, q[0].y, q[0].z, q[1].x, q[1].y, q[1].z, q[2].x, q[2].y, q[2].z};
        if (any_outside_predicate_range(x)) [[unlikely]]
            return triangle_triangle<WideRangeKernel, W>(p, q, out);
    }
    return triangle_triangle<K, W>(p, q, out);
}

template <class S, class T> [[nodiscard]] inline Vec3<S> to_vec(const Pt3<T>& p) noexcept {
    return {static_cast<S>(p.x), static_cast<S>(p.y), static_cast<S>(p.z)};
}

}  // namespace cdkit::detail::tritri
