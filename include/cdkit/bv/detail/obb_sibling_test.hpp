#pragma once
/// \file The OBB overlap test (the 15-axis separating-axis test of Gottschalk, Lin, Manocha, "OBBTree",
/// SIGGRAPH 1996) of two sibling boxes against one other box, computed together in two SIMD lanes (one SSE2
/// register of doubles). The descent splits one node of an overlapping pair and tests both children against
/// the other node; the two tests share that node's placement, so it is carried into the common frame once
/// (one 3×3 product instead of two per test), and every later step runs on both children at once. On the
/// bunny and the dragon this made first-contact queries about 1.5× faster at the same number of box tests
/// (docs/bvh.md, "Sibling tests").
///
/// The arithmetic is the scalar test's (boxes_disjoint, bv/detail/separating_axis.hpp) with its slacks: 64 ulps
/// per |R| entry and the translation slack. Where B's node is split, the products are associated the other way
/// (A's box frame composed with the relative transform first), which moves their rounding by a few ulps, well
/// inside those slacks. Float boxes are tested in double lanes (exact conversions; SSE2 holds two doubles):
/// more accurate than float arithmetic, with float's larger slacks.
///
/// When both children overlap, the test also ranks them by how deep each overlaps the other box: the
/// descent enters the deeper one first (see SiblingOverlap).

#include "cdkit/bv/obb.hpp"
#include "cdkit/core/inlining.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cdkit::detail {

/// Both children's answers, and which to enter first.
struct SiblingOverlap {
    bool overlap[2] = {false, false};
    /// Both overlap, and the second child overlaps the other box deeper than the first: a first-contact
    /// descent enters the second first. The depth is the smallest overlap of the two boxes' projections on
    /// the six face axes (how far they must move apart along a face normal to part: an upper bound on the
    /// boxes' penetration depth); a box pair that overlaps deeply is the likelier to hold crossing surfaces. At
    /// overlapping poses this order reaches the first contact with far fewer box tests than the fixed order
    /// (results/descent_ab.csv, docs/bvh.md).
    bool second_first = false;
};

/// Two doubles, one per child, in plain arithmetic: the lanes where there is no SSE2 (and the reference the
/// SSE2 lanes are tested against).
struct ScalarLanes2 {
    double v[2];
    static ScalarLanes2 of(double x0, double x1) noexcept { return {{x0, x1}}; }
    static ScalarLanes2 all(double x) noexcept { return {{x, x}}; }
    friend ScalarLanes2 operator+(ScalarLanes2 x, ScalarLanes2 y) noexcept {
        return {{x.v[0] + y.v[0], x.v[1] + y.v[1]}};
    }
    friend ScalarLanes2 operator-(ScalarLanes2 x, ScalarLanes2 y) noexcept {
        return {{x.v[0] - y.v[0], x.v[1] - y.v[1]}};
    }
    friend ScalarLanes2 operator*(ScalarLanes2 x, ScalarLanes2 y) noexcept {
        return {{x.v[0] * y.v[0], x.v[1] * y.v[1]}};
    }
    friend ScalarLanes2 min(ScalarLanes2 x, ScalarLanes2 y) noexcept {
        return {{std::min(x.v[0], y.v[0]), std::min(x.v[1], y.v[1])}};
    }
    [[nodiscard]] ScalarLanes2 abs() const noexcept { return {{std::abs(v[0]), std::abs(v[1])}}; }
    /// Lane k is 1 where lane k of x exceeds lane k of y, else 0 (a mask: combine with |, read with bits).
    friend ScalarLanes2 greater(ScalarLanes2 x, ScalarLanes2 y) noexcept {
        return {{x.v[0] > y.v[0] ? 1.0 : 0.0, x.v[1] > y.v[1] ? 1.0 : 0.0}};
    }
    friend ScalarLanes2 operator|(ScalarLanes2 x, ScalarLanes2 y) noexcept {
        return {{x.v[0] + y.v[0], x.v[1] + y.v[1]}};
    }
    /// Of a mask: bit k set where lane k is set.
    [[nodiscard]] int bits() const noexcept { return int(v[0] > 0) | int(v[1] > 0) << 1; }
    static ScalarLanes2 none() noexcept { return {{0.0, 0.0}}; }
    [[nodiscard]] double operator[](int k) const noexcept { return v[k]; }
};

#if defined(__SSE2__)
/// The same in one SSE2 register (Eigen's 2-element arrays were 1.5× slower here: their temporaries were not
/// all kept in registers).
struct SseLanes2 {
    __m128d v;
    static SseLanes2 of(double x0, double x1) noexcept { return {_mm_set_pd(x1, x0)}; }
    static SseLanes2 all(double x) noexcept { return {_mm_set1_pd(x)}; }
    friend SseLanes2 operator+(SseLanes2 x, SseLanes2 y) noexcept { return {_mm_add_pd(x.v, y.v)}; }
    friend SseLanes2 operator-(SseLanes2 x, SseLanes2 y) noexcept { return {_mm_sub_pd(x.v, y.v)}; }
    friend SseLanes2 operator*(SseLanes2 x, SseLanes2 y) noexcept { return {_mm_mul_pd(x.v, y.v)}; }
    friend SseLanes2 min(SseLanes2 x, SseLanes2 y) noexcept { return {_mm_min_pd(x.v, y.v)}; }
    [[nodiscard]] SseLanes2 abs() const noexcept { return {_mm_andnot_pd(_mm_set1_pd(-0.0), v)}; }
    friend SseLanes2 greater(SseLanes2 x, SseLanes2 y) noexcept { return {_mm_cmpgt_pd(x.v, y.v)}; }
    friend SseLanes2 operator|(SseLanes2 x, SseLanes2 y) noexcept { return {_mm_or_pd(x.v, y.v)}; }
    [[nodiscard]] int bits() const noexcept { return _mm_movemask_pd(v); }
    static SseLanes2 none() noexcept { return {_mm_setzero_pd()}; }
    [[nodiscard]] double operator[](int k) const noexcept {
        return k == 0 ? _mm_cvtsd_f64(v) : _mm_cvtsd_f64(_mm_unpackhi_pd(v, v));
    }
};
using Lanes2 = SseLanes2;
#else
using Lanes2 = ScalarLanes2;
#endif

/// The 15-axis test in two lanes: A's half extents `a` (per lane), B's `b`, B's axes in A's frame `Rb`
/// (Rb[i][j] = component i of B's axis j) and B's centre in A's frame `T`. As boxes_disjoint, with |Rb| plus
/// 64 ulps of S and A's extents widened by `slack`.
/// `Rounded`: the volumes are the boxes grown by balls (Minkowski sums; an Rss is a flat box grown by its radius),
/// `round` the two radii's sum per lane. A ball projects onto a face axis (unit length) as an interval of that
/// radius and onto an unnormalised cross axis A_i × B_j as one of radius × the axis's length, which the test
/// bounds from above; adding these to the boxes' radius sums keeps the test conservative, and tighter than the
/// test of the enclosing boxes, which pay the radius along every box axis at once (the corners).
/// Inlined into its two callers: out of line, its arrays went through memory (1.3× slower descents).
template <class S, class L, bool Rounded = false>
[[nodiscard]] CDKIT_ALWAYS_INLINE SiblingOverlap sibling_sat(L a[3], const L b[3], const L Rb[3][3], const L T[3],
                                                             double slack, L round = L::none()) noexcept {
    const L eps = L::all(64 * double(std::numeric_limits<S>::epsilon()));
    const auto grown = [&](L r) CDKIT_LAMBDA_INLINE {
        if constexpr (Rounded) return r + round;
        else return r;
    };
    for (int i = 0; i < 3; ++i) a[i] = a[i] + L::all(slack);
    L A[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) A[i][j] = Rb[i][j].abs() + eps;
    L disjoint = L::none();  // lane k set: child k is separated on some axis tested so far
    SiblingOverlap out;
    for (int i = 0; i < 3; ++i)  // A's face axes
        disjoint = disjoint | greater(T[i].abs(), grown(a[i] + (A[i][0] * b[0] + A[i][1] * b[1] + A[i][2] * b[2])));
    if (disjoint.bits() == 3) return out;
    for (int j = 0; j < 3; ++j)  // B's face axes
        disjoint = disjoint | greater((Rb[0][j] * T[0] + Rb[1][j] * T[1] + Rb[2][j] * T[2]).abs(),
                                      grown(b[j] + (A[0][j] * a[0] + A[1][j] * a[1] + A[2][j] * a[2])));
    if (disjoint.bits() == 3) return out;
    for (int i = 0; i < 3; ++i) {  // cross axes A_i × B_j
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        for (int j = 0; j < 3; ++j) {
            const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            const L ra = a[i1] * A[i2][j] + a[i2] * A[i1][j];
            const L rb = b[j1] * A[i][j2] + b[j2] * A[i][j1];
            L r = ra + rb;
            // A ball of radius ρ projects onto the unnormalised axis A_i × B_j as an interval of radius ρ·length;
            // the length, sin ∠(A_i, B_j), is at most 1, |Rb[i1][j]| + |Rb[i2][j]| (B_j across A_i) and
            // |Rb[i][j1]| + |Rb[i][j2]| (A_i across B_j).
            if constexpr (Rounded)
                r = r + round * min(min(A[i1][j] + A[i2][j], A[i][j1] + A[i][j2]), L::all(1.0));
            disjoint = disjoint | greater((T[i2] * Rb[i1][j] - T[i1] * Rb[i2][j]).abs(), r);
        }
        if (disjoint.bits() == 3) return out;
    }
    const int bits = disjoint.bits();
    out.overlap[0] = !(bits & 1);
    out.overlap[1] = !(bits & 2);
    if (bits == 0) {  // both overlap: the smallest overlap over the face axes ranks them
        L depth = L::all(std::numeric_limits<double>::infinity());
        for (int i = 0; i < 3; ++i)
            depth = min(depth, grown(a[i] + (A[i][0] * b[0] + A[i][1] * b[1] + A[i][2] * b[2])) - T[i].abs());
        for (int j = 0; j < 3; ++j)
            depth = min(depth, grown(b[j] + (A[0][j] * a[0] + A[1][j] * a[1] + A[2][j] * a[2])) -
                                   (Rb[0][j] * T[0] + Rb[1][j] * T[1] + Rb[2][j] * T[2]).abs());
        out.second_first = depth[1] > depth[0];
    }
    return out;
}

/// The sum of two balls' radii for the rounded test, rounded up (a sum rounded to nearest may fall short of the
/// true one by half an ulp).
[[nodiscard]] inline double radius_sum_up(double r, double s) noexcept {
    return (r + s) * (1.0 + 4.0 * std::numeric_limits<double>::epsilon());
}

/// Children c0, c1 of a node of A (in A's frame) against box b of B (in B's frame), `rel` taking B's frame
/// to A's: b is carried into A's frame once, then each child's frame is a lane. `Rounded`: the boxes grown by
/// balls whose radii sum to `round` per lane (sibling_sat).
template <class S, class L = Lanes2, bool Rounded = false>
[[nodiscard]] CDKIT_ALWAYS_INLINE SiblingOverlap children_overlap_box(const Obb<S>& c0, const Obb<S>& c1,
                                                                      const Obb<S>& b,
                                                                      const typename Obb<S>::Relative& rel,
                                                                      L round = L::none()) noexcept {
    const Mat3<S> M = rel.R * b.axes;              // b's axes in A's frame
    const Vec3<S> Tb = rel.R * b.center + rel.t;  // b's centre in A's frame
    L ax[3][3];  // ax[k][i]: component k of the children's axis i
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) ax[k][i] = L::of(c0.axes(k, i), c1.axes(k, i));
    L d[3];
    for (int k = 0; k < 3; ++k) d[k] = L::all(Tb[k]) - L::of(c0.center[k], c1.center[k]);
    L Rb[3][3], T[3];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
            Rb[i][j] = ax[0][i] * L::all(M(0, j)) + ax[1][i] * L::all(M(1, j)) + ax[2][i] * L::all(M(2, j));
        T[i] = ax[0][i] * d[0] + ax[1][i] * d[1] + ax[2][i] * d[2];
    }
    L a[3], hb[3];
    for (int k = 0; k < 3; ++k) a[k] = L::of(c0.half[k], c1.half[k]), hb[k] = L::all(b.half[k]);
    return sibling_sat<S, L, Rounded>(a, hb, Rb, T, rel.slack, round);
}

/// Box a of A (in A's frame) against children c0, c1 of a node of B (in B's frame): A's frame is composed
/// with `rel` once, then each child is a lane. `Rounded` as children_overlap_box.
template <class S, class L = Lanes2, bool Rounded = false>
[[nodiscard]] CDKIT_ALWAYS_INLINE SiblingOverlap box_overlap_children(const Obb<S>& a, const Obb<S>& c0,
                                                                      const Obb<S>& c1,
                                                                      const typename Obb<S>::Relative& rel,
                                                                      L round = L::none()) noexcept {
    const Mat3<S> at = a.axes.transpose();
    const Mat3<S> Q = at * rel.R;                 // B's frame → a's box frame
    const Vec3<S> Qt = at * (rel.t - a.center);
    L bx[3][3];  // bx[k][j]: component k of the children's axis j
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) bx[k][j] = L::of(c0.axes(k, j), c1.axes(k, j));
    L c[3];
    for (int k = 0; k < 3; ++k) c[k] = L::of(c0.center[k], c1.center[k]);
    L Rb[3][3], T[3];
    for (int i = 0; i < 3; ++i) {
        const L q0 = L::all(Q(i, 0)), q1 = L::all(Q(i, 1)), q2 = L::all(Q(i, 2));
        for (int j = 0; j < 3; ++j) Rb[i][j] = q0 * bx[0][j] + q1 * bx[1][j] + q2 * bx[2][j];
        T[i] = q0 * c[0] + q1 * c[1] + q2 * c[2] + L::all(Qt[i]);
    }
    L ha[3], b[3];
    for (int k = 0; k < 3; ++k) ha[k] = L::all(a.half[k]), b[k] = L::of(c0.half[k], c1.half[k]);
    return sibling_sat<S, L, Rounded>(ha, b, Rb, T, rel.slack, round);
}

/// Children c0, c1 of a node against a probe box p given in the children's own frame (a convex shape's bound in a
/// mesh–convex query, carried into the mesh frame once per query): no relative transform, p is broadcast to both
/// lanes. First the probe's circumscribed ball (radius `p_radius` ≥ |p.half|) against the children's face axes,
/// which needs only the centre offsets and culls most nodes; then the 15 axes (sibling_sat) where a child is left.
/// Children of scalar C (a float tree over a double mesh too: exact in double lanes) with S's slacks.
template <class S, class C, class L = Lanes2>
[[nodiscard]] CDKIT_ALWAYS_INLINE SiblingOverlap children_overlap_probe(const Obb<C>& c0, const Obb<C>& c1,
                                                                        const Obb<S>& p, S p_radius) noexcept {
    L ax[3][3];  // ax[k][i]: component k of the children's axis i
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) ax[k][i] = L::of(double(c0.axes(k, i)), double(c1.axes(k, i)));
    L d[3], a[3];
    for (int k = 0; k < 3; ++k) {
        d[k] = L::all(double(p.center[k])) - L::of(double(c0.center[k]), double(c1.center[k]));
        a[k] = L::of(double(c0.half[k]), double(c1.half[k]));
    }
    L T[3];
    for (int i = 0; i < 3; ++i) T[i] = ax[0][i] * d[0] + ax[1][i] * d[1] + ax[2][i] * d[2];
    const L r = L::all(double(p_radius));
    const int ball = (greater(T[0].abs(), a[0] + r) | greater(T[1].abs(), a[1] + r) | greater(T[2].abs(), a[2] + r)).bits();
    if (ball == 3) return {};
    L Rb[3][3], hb[3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            Rb[i][j] = ax[0][i] * L::all(double(p.axes(0, j))) + ax[1][i] * L::all(double(p.axes(1, j))) +
                       ax[2][i] * L::all(double(p.axes(2, j)));
    for (int k = 0; k < 3; ++k) hb[k] = L::all(double(p.half[k]));
    SiblingOverlap out = sibling_sat<S, L>(a, hb, Rb, T, 0.0);
    // A child the ball culled stays culled (the 15 axes would agree up to rounding; the scalar test stops there).
    if (ball & 1) out.overlap[0] = false, out.second_first = false;
    if (ball & 2) out.overlap[1] = false, out.second_first = false;
    return out;
}

}  // namespace cdkit::detail
