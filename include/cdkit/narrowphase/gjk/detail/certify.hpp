#pragma once
/// \file The support of D = A − B, GJK's exit tests on |v| (the gap test) and the certification of its exits:
/// a "separated" answer only with a separating plane, the lower bound v·w/|v| of van den Bergen, "A fast and robust
/// GJK implementation for collision detection of convex objects", J. Graphics Tools 4(2), 1999 (§3), found where
/// needed by the sub-simplex steps in `wider_t`; a "touching" exit turned into a proven overlap by a bipyramid of
/// support points around the origin (docs/convex.md, "Certified separation").

#include <cdkit/narrowphase/gjk/detail/simplex_solver.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace cdkit {
namespace detail {

/// Support of D = A − B on the cores (or full shapes when `use_cores` is false), in A's frame;
/// `rel` maps B's frame into A's. `hints` (optional): start vertices {A, B} for `HintedSupport` shapes.
template <bool use_cores, SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE void minkowski_support_into(GjkVertex<typename A::Scalar>& x, const A& a, const B& b,
                                                const Transform<typename A::Scalar>& rel,
                                                const Vec3<typename A::Scalar>& d,
                                                std::uint32_t* hints = nullptr) noexcept {
    using S = typename A::Scalar;
    const Vec3<S> db = rotate_back(rel.R, neg(d));
    if constexpr (use_cores) {
        x.a = core_support_hinted(a, d, hints);
        x.b_local = core_support_hinted(b, db, hints ? hints + 1 : nullptr);
    } else {
        x.a = a.support(d);
        x.b_local = b.support(db);
    }
    x.b = place(rel, x.b_local);
    x.w = minus(x.a, x.b);
    x.d = d;
}
/// The same, returned by value.
template <bool use_cores, SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE GjkVertex<typename A::Scalar> minkowski_support(const A& a, const B& b,
                                                                    const Transform<typename A::Scalar>& rel,
                                                                    const Vec3<typename A::Scalar>& d,
                                                                    std::uint32_t* hints = nullptr) noexcept {
    GjkVertex<typename A::Scalar> x;
    minkowski_support_into<use_cores>(x, a, b, rel, d, hints);
    return x;
}

/// The tolerance term of the gap test below: ε_rel·|v|², or ε_rel·|v|·(|v| − margin) beyond a margin.
template <class S> [[nodiscard]] inline S gap_tolerance(S vv, S margin, S rel_tolerance) noexcept {
    if (margin > S(0)) {
        const S core = std::sqrt(vv);
        if (core > margin) return rel_tolerance * core * (core - margin);
    }
    return rel_tolerance * vv;
}

/// GJK's convergence test on |v| (v the point of the simplex nearest the origin, w the support point along
/// −v, vw = v·w, vv = |v|², size2 = the squared size of D's support points): the gap |v| − v·w/|v| between
/// the upper and lower bound is within ε_rel·|v|² + 16·ε·|v|·size, compared in squares (no sqrt per
/// iteration). With margins (capsules, spheres, Inflated: GJK runs on the cores) the caller gets
/// |v| − margin, so the relative term is ε_rel·|v|·(|v| − margin): ε_rel·|v|² would be
/// ε_rel·(1 + margin/distance) relative on the result (2e-8 on close capsule pairs). Within the margin
/// (overlap) only the decision matters and ε_rel·|v|² stays.
template <class S>
[[nodiscard]] inline bool gap_converged(S vv, S vw, S margin, S size2, S rel_tolerance) noexcept {
    constexpr S eps = std::numeric_limits<S>::epsilon();
    const S excess = vv - vw - gap_tolerance(vv, margin, rel_tolerance);
    return excess <= S(0) || excess * excess <= S(256) * eps * eps * vv * size2;
}

/// True when a loop's closest point v (vv = |v|²) lies beyond margin + tf·max(size, margin), gjk_finish's
/// touching tolerance: an exit there would be reported as "separated".
template <class S> [[nodiscard]] inline bool separation_claimed(S vv, S margin, S tf, S size2) noexcept {
    const S thr = margin + tf * std::max(std::sqrt(size2), margin);
    return vv > thr * thr;
}

/// Certification of a "separated" outcome that no supporting plane backs. A separated answer claims a plane
/// between the shapes; its proof is a lower bound on the distance, v·w/|v| for a direction v and the support
/// point w of D along −v (van den Bergen 1999, §3: the plane through w orthogonal to v supports D), above the
/// touching tolerance. GJK's other exits — the gap test, a repeated support point, a step without progress —
/// stop on |v|, an upper bound only while the sub-simplex steps are exact: near contact on curved shapes the
/// support points cluster into needle triangles and flat tetrahedra, the double step misplaces v and GJK
/// stopped with |v| above the tolerance on pairs that overlap by 1e-12 … 1e-9 of their size (24 of 3,600 such
/// pairs in a driver: cones, cylinders, ellipsoids). For those rare exits this continues from the final simplex
/// with the sub-simplex steps in `wider_t<S>` (the support points stay exact points of D, now combined with
/// a 2048× finer rounding) until a plane proves separation (`separated`, `lower` > margin + tolerance), four
/// points enclose the origin (`intersecting`), or |v| reaches the tolerance; when it stops without deciding,
/// the answer is `touching`: conservative for collision detection, and no plane was found above the
/// tolerance. `s` holds a, b, w of its first s.size vertices (A's frame); `v`, `s`, `size2`, `lower`, `sep`
/// and `iterations` are updated.
template <bool use_cores, SupportMapped A, SupportMapped B>
inline GjkStatus certify_separation(const A& a, const B& b, const Transform<typename A::Scalar>& rel,
                                    const GjkSettings<typename A::Scalar>& settings, typename A::Scalar margin,
                                    GjkSimplex<typename A::Scalar>& s, Vec3<typename A::Scalar>& v,
                                    typename A::Scalar& size2, typename A::Scalar& lower,
                                    GjkVertex<typename A::Scalar>& sep, std::uint32_t* hints,
                                    int& iterations) noexcept {
    using S = typename A::Scalar;
    using W = wider_t<S>;
    const S tf = settings.touch_factor * std::numeric_limits<S>::epsilon();
    GjkSimplex<W> ws;
    auto widen = [](const GjkVertex<S>& x) { return Vec3<W>(x.a.template cast<W>() - x.b.template cast<W>()); };
    ws.size = s.size;
    for (int i = 0; i < s.size; ++i) ws.v[std::size_t(i)].w = widen(s.v[std::size_t(i)]);
    SimplexSelection<W> sel;
    // Moves both simplices to the selection (indices ascending: moving down in place is safe).
    auto apply = [&]() {
        for (int k = 0; k < sel.size; ++k) {
            const std::size_t from = std::size_t(sel.idx[std::size_t(k)]);
            if (from != std::size_t(k)) { s.v[std::size_t(k)] = s.v[from]; ws.v[std::size_t(k)].w = ws.v[from].w; }
            s.lambda[std::size_t(k)] = S(sel.lambda[std::size_t(k)]);
        }
        s.size = ws.size = sel.size;
    };
    Vec3<W> vw = v.template cast<W>();
    if (ws.size > 0) {
        SimplexSolver<W>::select(ws, sel);
        if (sel.inside) { v.setZero(); return GjkStatus::intersecting; }
        if (!all_finite(sel.v)) return GjkStatus::touching;
        apply();
        vw = sel.v;
    }
    for (int k = 0; k < settings.max_iterations; ++k) {
        const W thr = W(margin) + W(tf) * W(std::max(std::sqrt(size2), margin));
        const W vv = vw.squaredNorm();
        if (!(vv > thr * thr)) break;  // |v| within the tolerance: no separation left to prove
        const Vec3<S> d = (-vw).template cast<S>();
        ++iterations;
        GjkVertex<S>& x = s.v[std::size_t(s.size)];
        minkowski_support_into<use_cores>(x, a, b, rel, d, hints);
        if (!all_finite(x.w)) { v = vw.template cast<S>(); return GjkStatus::degenerate; }
        size2 = std::max(size2, norm2(x.w));
        // The bound along the direction actually queried (−d, exact in W), from the exact points of D.
        const Vec3<W> u = (-d).template cast<W>();
        const Vec3<W> wx = widen(x);
        const W lb = u.dot(wx) / u.norm();
        lower = std::max(lower, S(lb));
        if (lb > thr) {
            sep = x;
            v = -d;
            return GjkStatus::separated;
        }
        bool duplicate = false;
        for (int i = 0; i < s.size; ++i) duplicate = duplicate || s.v[std::size_t(i)].w == x.w;
        if (duplicate) break;
        ws.v[std::size_t(ws.size++)].w = wx;
        ++s.size;
        SimplexSolver<W>::select(ws, sel);
        if (sel.inside) { v.setZero(); return GjkStatus::intersecting; }
        if (!(sel.v.squaredNorm() < vv)) { --s.size; --ws.size; break; }  // the wide rounding floor
        apply();
        vw = sel.v;
    }
    v = vw.template cast<S>();
    return GjkStatus::touching;
}

/// What `certify_exit` found (see certify_separation).
template <class S> struct CertifiedExit {
    GjkStatus status;
    Vec3<S> v;
    S size2, lower;
    GjkVertex<S> sep;
    int iterations;
};

/// certify_separation for gjk_loop's exits, out of line and on copies (v, size², bound, hints, relative pose), so
/// that the loop's own state never has its address taken on the common path (taking it cost the cold boolean's
/// box cells 8–13 %: values reloaded after stores through the simplex).
template <bool use_cores, SupportMapped A, SupportMapped B>
CDKIT_COLD_PATH CertifiedExit<typename A::Scalar> certify_exit(const A& a, const B& b,
                                                                Transform<typename A::Scalar> rel,
                                                                const GjkSettings<typename A::Scalar>& settings,
                                                                typename A::Scalar margin,
                                                                GjkSimplex<typename A::Scalar>& s,
                                                                Vec3<typename A::Scalar> v, typename A::Scalar size2,
                                                                typename A::Scalar lower, std::uint32_t hint_a,
                                                                std::uint32_t hint_b) noexcept {
    using S = typename A::Scalar;
    CertifiedExit<S> c;
    std::uint32_t hints[2] = {hint_a, hint_b};
    c.sep.w.setConstant(std::numeric_limits<S>::quiet_NaN());
    c.iterations = 0;
    c.status = certify_separation<use_cores>(a, b, rel, settings, margin, s, v, size2, lower, c.sep, hints,
                                             c.iterations);
    c.v = v;
    c.size2 = size2;
    c.lower = lower;
    return c;
}

/// GJK's touching exit (|v| within the touching tolerance of zero, no margins): the origin may lie deep inside D
/// with the final simplex through it — nested needles, whose Minkowski difference is 1e-8 thick around the plane or
/// the axis the origin is on (the hard-case count's nested and near-contact needle pairs ended "touching", in long
/// double too). A bipyramid of points of D around the origin proves the overlap
/// (`SimplexSolver::origin_in_bipyramid`): on a triangle, D's support points along ±n (n its normal) as apexes;
/// on a segment p–q — or a triangle whose edge nearest the origin carries it — p and q as apexes over the triangle
/// of D's support points along three directions 120° apart around the segment. Out of line: rare.
template <bool use_cores, SupportMapped A, SupportMapped B>
CDKIT_COLD_PATH bool touching_simplex_proves_overlap(const A& a, const B& b, Transform<typename A::Scalar> rel,
                                                     const GjkSimplex<typename A::Scalar>& s) noexcept {
    using S = typename A::Scalar;
    auto support = [&](const Vec3<S>& d) { return minkowski_support<use_cores>(a, b, rel, d).w; };
    // Decided in the wider type (the points are exact there): across a needle 1e-8 thick and 0.1 long the side
    // products' rounding in double (ε times the cube of the length) exceeds them where thickness/length < 6e-8.
    using W = wider_t<S>;
    auto in_bipyramid = [](const Vec3<S>& t0, const Vec3<S>& t1, const Vec3<S>& t2, const Vec3<S>& wp,
                           const Vec3<S>& wm) {
        return SimplexSolver<W>::origin_in_bipyramid(t0.template cast<W>(), t1.template cast<W>(),
                                                     t2.template cast<W>(), wp.template cast<W>(),
                                                     wm.template cast<W>());
    };
    // Around segment p–q: three support points whose triangle the segment pierces.
    auto around_segment = [&](const Vec3<S>& p, const Vec3<S>& q) {
        const Vec3<S> axis = minus(q, p);
        int k = 0;  // the coordinate axis least aligned with the segment
        for (int i = 1; i < 3; ++i) k = std::abs(axis[i]) < std::abs(axis[k]) ? i : k;
        const Vec3<S> u = cross3(axis, Vec3<S>(Vec3<S>::Unit(k)));
        const Vec3<S> w = cross3(axis, u);
        const S nu = std::sqrt(norm2(u)), nw = std::sqrt(norm2(w));
        if (!(nu > S(0) && nw > S(0)) || !all_finite(u) || !all_finite(w)) return false;
        const S c = S(-0.5), sn = S(0.86602540378443864676);  // cos, sin 120°
        const Vec3<S> uu = u / nu, ww = w / nw;
        const Vec3<S> e0 = support(uu);
        const Vec3<S> e1 = support(Vec3<S>(c * uu + sn * ww)), e2 = support(Vec3<S>(c * uu - sn * ww));
        if (!all_finite(e0) || !all_finite(e1) || !all_finite(e2)) return false;
        return in_bipyramid(e0, e1, e2, p, q);
    };
    if (s.size == 2) return around_segment(s.v[0].w, s.v[1].w);
    if (s.size != 3) return false;
    const Vec3<S>& p0 = s.v[0].w;
    const Vec3<S> ab = minus(s.v[1].w, p0), ac = minus(s.v[2].w, p0);
    const S ab2 = norm2(ab), ac2 = norm2(ac), bc2 = norm2(minus(s.v[2].w, s.v[1].w));
    S edges2 = S(0);
    const Vec3<S> n = SimplexSolver<S>::stable_normal(s.v[1].w, s.v[2].w, ab, ac, ab2, ac2, bc2, edges2);
    if (norm2(n) > S(0) && all_finite(n)) {
        const Vec3<S> wp = support(n), wm = support(neg(n));
        if (all_finite(wp) && all_finite(wm) && in_bipyramid(s.v[0].w, s.v[1].w, s.v[2].w, wp, wm)) return true;
    }
    // The origin on (within rounding of) an edge: that edge as the segment.
    int best = 0;
    S best_d = std::numeric_limits<S>::infinity();
    for (int e = 0; e < 3; ++e) {
        typename SimplexSolver<S>::Sel sel;
        SimplexSolver<S>::segment(s, e, (e + 1) % 3, sel);
        const S d = norm2(sel.v);
        if (d < best_d) { best_d = d; best = e; }
    }
    return around_segment(s.v[std::size_t(best)].w, s.v[std::size_t((best + 1) % 3)].w);
}

/// A touching result (no margins) whose final simplex proves the overlap (`touching_simplex_proves_overlap`)
/// becomes intersecting, reported as every proven overlap is: distance 0, no witness points.
template <SupportMapped A, SupportMapped B>
inline void prove_touching_overlap(const A& a, const B& b, const Transform<typename A::Scalar>& rel,
                                   GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    if (r.status != GjkStatus::touching || margin_of(a) + margin_of(b) > S(0)) return;
    if (!touching_simplex_proves_overlap<true>(a, b, rel, r.simplex)) return;
    r.status = GjkStatus::intersecting;
    r.distance = S(0);
    r.point_a.setZero();
    r.point_b.setZero();
    r.normal.setZero();
}

}  // namespace detail
}  // namespace cdkit
