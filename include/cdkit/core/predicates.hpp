#pragma once
/// \file Exact orientation predicates on floating-point input: orient3d and orient2d.
///
/// Based on: J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
/// Predicates", Discrete & Computational Geometry 18(3):305–363, 1997. A determinant is first evaluated in
/// double together with a certified bound on its rounding error (a semi-static filter: the bound scales
/// with the "permanent", the determinant with every term replaced by its absolute value, as in Shewchuk's
/// stage A). Only when |det| does not exceed the bound do slower stages run: for orient3d an error-free
/// re-evaluation, then double-double arithmetic with its own certified bound, and last the determinant
/// computed exactly as a nonoverlapping floating-point expansion (Shewchuk §2: two-sum, two-product,
/// grow-expansion) whose sign is the sign of its largest component; orient2d goes straight to the
/// expansion, which is cheap in 2D. The code is written from the papers, not taken from predicates.c.
///
/// Range: the floating-point stages are exact for input whose nonzero coordinates have magnitudes in
/// [2^-280, 2^280] (about [5e-85, 2e84]); then no intermediate overflows, no rounded intermediate is
/// subnormal, and every product's rounding error is representable. All finite `float` input lies in that
/// range (floats are converted to double exactly). A finite double outside it (a subnormal coordinate, as
/// one ulp away from zero gives, or a huge one) goes to a last stage in wide integer arithmetic
/// (detail/wide_integer.hpp), exact for every finite input; the public orient3d/orient2d and the triangle
/// test check the range once per call. Non-finite input gives an unspecified sign (never UB).
///
/// The code needs IEEE-754 double arithmetic with round-to-nearest and no reassociation: -ffast-math is
/// rejected at compile time. FMA contraction (-ffp-contract=fast, GCC's default in GNU modes) is handled:
/// a product fused into a following error-free two-sum would silently break exactness, so two-product
/// computes its product with std::fma where the target has FMA (nothing left to fuse) and uses Dekker's
/// split only where it has none (nothing can be fused); in the filters and the double-double stage a
/// fused operation only removes a rounding from the error analysis. (MSVC: /fp:contract with a target
/// that has FMA but no __FMA__ macro is not supported.)

#include "cdkit/core/detail/wide_integer.hpp"
#include "cdkit/core/math.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

#if defined(__FAST_MATH__)
#error "cdkit/core/predicates.hpp needs IEEE-754 semantics: do not compile with -ffast-math"
#endif
#if defined(__FLT_EVAL_METHOD__) && __FLT_EVAL_METHOD__ != 0 && __FLT_EVAL_METHOD__ != -1
#error "cdkit/core/predicates.hpp needs double arithmetic evaluated in double (FLT_EVAL_METHOD 0, e.g. SSE2)"
#endif

#if defined(__FMA__) || defined(__aarch64__) || defined(_M_ARM64)
#define CDKIT_PREDICATES_HW_FMA 1
#else
#define CDKIT_PREDICATES_HW_FMA 0
#endif
// The slow stages stay out of line so that the filtered fast path inlines small.
#if defined(__GNUC__) || defined(__clang__)
#define CDKIT_PREDICATES_NOINLINE __attribute__((noinline))
#elif defined(_MSC_VER)
#define CDKIT_PREDICATES_NOINLINE __declspec(noinline)
#else
#define CDKIT_PREDICATES_NOINLINE
#endif

namespace cdkit {

/// How a predicate (and the queries built on predicates) decides a sign.
enum class PredicateMode {
    /// Floating-point evaluation in double with a certified error bound; slower exact stages (ending in
    /// expansion arithmetic) when the bound cannot decide. Always the exact sign (within the range in this
    /// file's header).
    filtered_exact,
    /// The same determinant evaluated once in the input's own scalar type, its sign taken as is: fast but
    /// may be wrong (or zero) for nearly degenerate input. Exists to measure what exactness costs.
    floating_point,
};

namespace detail {

/// A point as plain scalars, the predicates' working type (no alignment or expression templates).
template <class T> struct Pt3 {
    T x, y, z;
};
template <class T> struct Pt2 {
    T x, y;
};
using Point3d = Pt3<double>;
using Point2d = Pt2<double>;

template <class T, class S> [[nodiscard]] inline Pt3<T> to_pt(const Vec3<S>& v) noexcept {
    return {static_cast<T>(v.x()), static_cast<T>(v.y()), static_cast<T>(v.z())};
}

// ---- error-free transformations (Shewchuk 1997 §2.5–2.6; Dekker 1971) ---------------------------

/// s + e == a + b exactly, s = fl(a + b) (Knuth's two-sum; no precondition on magnitudes).
inline void two_sum(double a, double b, double& s, double& e) noexcept {
    s = a + b;
    const double bv = s - a;
    const double av = s - bv;
    e = (a - av) + (b - bv);
}
/// d + e == a - b exactly, d = fl(a - b).
inline void two_diff(double a, double b, double& d, double& e) noexcept {
    d = a - b;
    const double bv = a - d;
    const double av = d + bv;
    e = (a - av) + (bv - b);
}
/// s + e == a + b exactly; valid when a == 0 or exponent(a) >= exponent(b) (e.g. |a| >= |b|).
inline void fast_two_sum(double a, double b, double& s, double& e) noexcept {
    s = a + b;
    e = b - (s - a);
}
#if !CDKIT_PREDICATES_HW_FMA
/// a == hi + lo with hi, lo of at most 26 significant bits (Veltkamp's split; |a| < 2^996).
inline void split(double a, double& hi, double& lo) noexcept {
    const double c = 134217729.0 * a;  // 2^27 + 1
    hi = c - (c - a);
    lo = a - hi;
}
#endif
/// p + e == a * b exactly, p = fl(a * b) (needs no underflow: see the range in the file header).
inline void two_prod(double a, double b, double& p, double& e) noexcept {
#if CDKIT_PREDICATES_HW_FMA
    // p as fma(a, b, 0) rather than a * b: the same correctly rounded product, but not a multiplication
    // the compiler may fuse (-ffp-contract=fast) into a later two-sum, which would break that two-sum's
    // error term and so the exactness of every expansion.
    p = std::fma(a, b, 0.0);
    e = std::fma(a, b, -p);
#else
    p = a * b;
    // Dekker's product: every operation below is exact, so no fma is needed (or wanted).
    double ah, al, bh, bl;
    split(a, ah, al);
    split(b, bh, bl);
    e = al * bl - (((p - ah * bh) - al * bh) - ah * bl);
#endif
}

/// A nonoverlapping expansion (Shewchuk 1997 §2.4): the exact sum of up to N doubles, kept as components
/// of increasing magnitude with zeros removed, so its sign is the sign of the last component. Each add()
/// is Grow-Expansion (Shewchuk's Theorem 10) and appends at most one component, so N adds always fit.
template <int N> class Expansion {
public:
    void add(double b) noexcept {
        if (b == 0.0) return;
        int m = 0;
        double q = b;
        for (int i = 0; i < n_; ++i) {
            double s, e;
            two_sum(q, c_[i], s, e);
            q = s;
            if (e != 0.0) c_[m++] = e;
        }
        if (q != 0.0) c_[m++] = q;
        n_ = m;
    }
    /// Adds a*b exactly (2 components).
    void add_product(double a, double b) noexcept {
        double p, e;
        two_prod(a, b, p, e);
        add(e);
        add(p);
    }
    /// Adds a*b*c exactly (4 components).
    void add_product(double a, double b, double c) noexcept {
        double p, e, p1, e1, p2, e2;
        two_prod(a, b, p, e);
        two_prod(e, c, p2, e2);
        two_prod(p, c, p1, e1);
        add(e2);
        add(p2);
        add(e1);
        add(p1);
    }
    [[nodiscard]] int sign() const noexcept { return n_ == 0 ? 0 : (c_[n_ - 1] > 0.0 ? 1 : -1); }
    [[nodiscard]] int size() const noexcept { return n_; }
    /// The value rounded to double with a relative error of a few ulps, and always with the exact sign
    /// (summed from the smallest component up; the largest alone can be off by up to a factor 2).
    [[nodiscard]] double estimate() const noexcept {
        if (n_ == 0) return 0.0;
        double s = 0.0;
        for (int i = 0; i < n_ - 1; ++i) s += c_[i];
        const double top = c_[n_ - 1];
        const double v = top + s;
        // |sum of the lower components| < |top|, but its rounding may reach |top|: keep the sign exact.
        return (v > 0.0) == (top > 0.0) && v != 0.0 ? v : top;
    }

private:
    double c_[N];
    int n_ = 0;
};

// ---- orient2d -------------------------------------------------------------------------------------

/// Shewchuk's bound for orient2d's stage A is (3 + 16u)u·permanent, u = 2^-53; 4u covers it with room for
/// the rounding of the permanent itself, and a power of two makes bound = coefficient × permanent exact.
inline constexpr double kOrient2dErrBound = 0x1p-51;
/// Shewchuk's orient3d stage-A bound is (7 + 56u)u·permanent; 8u likewise.
inline constexpr double kOrient3dErrBound = 0x1p-50;

/// Exact sign of det[a-c; b-c]; optionally a double approximation of the determinant (exact sign).
CDKIT_PREDICATES_NOINLINE inline int orient2d_exact(const Point2d& a, const Point2d& b, const Point2d& c,
                                                    double* approx = nullptr) noexcept {
    double acx[2], acy[2], bcx[2], bcy[2];
    two_diff(a.x, c.x, acx[0], acx[1]);
    two_diff(a.y, c.y, acy[0], acy[1]);
    two_diff(b.x, c.x, bcx[0], bcx[1]);
    two_diff(b.y, c.y, bcy[0], bcy[1]);
    Expansion<16> e;
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            if (acx[i] != 0.0 && bcy[j] != 0.0) e.add_product(acx[i], bcy[j]);
            if (acy[i] != 0.0 && bcx[j] != 0.0) e.add_product(-acy[i], bcx[j]);
        }
    if (approx) *approx = e.estimate();
    return e.sign();
}

/// Filtered orient2d; `value` receives the floating-point determinant when the filter decides, else the
/// exact expansion's estimate (either way its sign is exact).
inline int orient2d_filtered(const Point2d& a, const Point2d& b, const Point2d& c, double* value = nullptr) noexcept {
    const double acx = a.x - c.x, acy = a.y - c.y;
    const double bcx = b.x - c.x, bcy = b.y - c.y;
    const double l = acx * bcy, r = acy * bcx;
    const double det = l - r;
    const double bound = kOrient2dErrBound * (std::abs(l) + std::abs(r));
    if (det > bound || -det > bound) {
        if (value) *value = det;
        return det > 0.0 ? 1 : -1;
    }
    return orient2d_exact(a, b, c, value);
}

/// orient2d evaluated once in T, no filter (PredicateMode::floating_point).
template <class T> [[nodiscard]] inline T orient2d_value(const Pt2<T>& a, const Pt2<T>& b, const Pt2<T>& c) noexcept {
    return (a.x - c.x) * (b.y - c.y) - (a.y - c.y) * (b.x - c.x);
}

// ---- double-double arithmetic ----------------------------------------------------------------------
// Double-word arithmetic after M. Joldes, J.-M. Muller, V. Popescu, "Tight and rigorous error bounds for
// basic building blocks of double-word arithmetic", ACM TOMS 44(2), 2017. Multiplication is their
// DWTimesDW1 (relative error below 7u²). Addition is their SloppyDWPlusDW with the final Fast2Sum replaced
// by a 2Sum, so the result is normalized even under cancellation; its error is at most
// 3.01u²·(|x| + |y|): not relative to the result, but every use below is bounded against a permanent,
// which needs no more (docs/triangle.md).

struct DoubleDouble {
    double hi, lo;  // |lo| <= ulp(hi)/2
};
inline DoubleDouble dd_diff(double a, double b) noexcept {
    DoubleDouble r;
    two_diff(a, b, r.hi, r.lo);
    return r;
}
inline DoubleDouble dd_mul(const DoubleDouble& x, const DoubleDouble& y) noexcept {
    double p, e;
    two_prod(x.hi, y.hi, p, e);
    e += x.hi * y.lo + x.lo * y.hi;
    DoubleDouble r;
    fast_two_sum(p, e, r.hi, r.lo);
    return r;
}
inline DoubleDouble dd_add(const DoubleDouble& x, const DoubleDouble& y) noexcept {
    double sh, sl;
    two_sum(x.hi, y.hi, sh, sl);
    DoubleDouble r;
    two_sum(sh, sl + (x.lo + y.lo), r.hi, r.lo);
    return r;
}
inline DoubleDouble dd_neg(const DoubleDouble& x) noexcept { return {-x.hi, -x.lo}; }

// ---- orient3d -------------------------------------------------------------------------------------
// Four stages, cheapest first; each later one runs only when the earlier ones cannot decide:
//   A. floating-point determinant with Shewchuk's semi-static bound (orient3d_filtered);
//   B. the same expression with error-free transformations: when every difference, product and sum of
//      stage A happens to be exact (typical of integer or few-bit coordinates, e.g. exactly coplanar
//      input), stage A's value is the exact determinant, zero included;
//   C. double-double evaluation of the determinant from exact differences, error below 23.1u²·permanent
//      (derivation in docs/triangle.md), decided when |det| >= 2^-99·permanent: settles the nearly (but
//      not exactly) degenerate input that rounding and rotations produce;
//   D. the exact expansion (orient3d_exact).

/// Stage D: exact sign of det[a-d; b-d; c-d] (Shewchuk's orient3d convention); optionally a double
/// approximation of the determinant with the exact sign. Expands the determinant into its 6 signed triple
/// products of exact differences (each difference a 2-component expansion), every triple product exactly
/// as 4 doubles; terms with a zero factor are skipped, so few-bit input costs 24 additions, not 192.
CDKIT_PREDICATES_NOINLINE inline int orient3d_exact(const Point3d& a, const Point3d& b, const Point3d& c,
                                                    const Point3d& d, double* approx = nullptr) noexcept {
    double u[3][2], v[3][2], w[3][2];
    two_diff(a.x, d.x, u[0][0], u[0][1]);
    two_diff(a.y, d.y, u[1][0], u[1][1]);
    two_diff(a.z, d.z, u[2][0], u[2][1]);
    two_diff(b.x, d.x, v[0][0], v[0][1]);
    two_diff(b.y, d.y, v[1][0], v[1][1]);
    two_diff(b.z, d.z, v[2][0], v[2][1]);
    two_diff(c.x, d.x, w[0][0], w[0][1]);
    two_diff(c.y, d.y, w[1][0], w[1][1]);
    two_diff(c.z, d.z, w[2][0], w[2][1]);
    Expansion<192> e;
    // det = Σ over the even permutations (i,j,k) of u_i v_j w_k − the odd ones.
    auto term = [&](bool negative, const double (&x)[2], const double (&y)[2], const double (&z)[2]) {
        for (int i = 0; i < 2; ++i) {
            if (x[i] == 0.0) continue;
            const double xi = negative ? -x[i] : x[i];
            for (int j = 0; j < 2; ++j) {
                if (y[j] == 0.0) continue;
                for (int k = 0; k < 2; ++k)
                    if (z[k] != 0.0) e.add_product(xi, y[j], z[k]);
            }
        }
    };
    term(false, u[0], v[1], w[2]);
    term(true, u[0], v[2], w[1]);
    term(false, u[1], v[2], w[0]);
    term(true, u[1], v[0], w[2]);
    term(false, u[2], v[0], w[1]);
    term(true, u[2], v[1], w[0]);
    if (approx) *approx = e.estimate();
    return e.sign();
}

/// Stage B: true (and the sign, and the value) when the floating-point evaluation of det[a-d; b-d; c-d]
/// is free of rounding errors.
inline bool orient3d_if_error_free(const Point3d& a, const Point3d& b, const Point3d& c, const Point3d& d, int& sign,
                                   double* value) noexcept {
    double u[3], v[3], w[3], t[9];
    two_diff(a.x, d.x, u[0], t[0]);
    two_diff(a.y, d.y, u[1], t[1]);
    two_diff(a.z, d.z, u[2], t[2]);
    two_diff(b.x, d.x, v[0], t[3]);
    two_diff(b.y, d.y, v[1], t[4]);
    two_diff(b.z, d.z, v[2], t[5]);
    two_diff(c.x, d.x, w[0], t[6]);
    two_diff(c.y, d.y, w[1], t[7]);
    two_diff(c.z, d.z, w[2], t[8]);
    bool inexact = false;
    for (double x : t) inexact |= x != 0.0;
    if (inexact) return false;
    double n[3], e[6], f[3];
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3, k = (i + 2) % 3;
        double l, r;
        two_prod(v[j], w[k], l, e[2 * i]);
        two_prod(v[k], w[j], r, e[2 * i + 1]);
        two_diff(l, r, n[i], f[i]);
    }
    double p[3], g[3], s, h1, det, h2;
    for (int i = 0; i < 3; ++i) two_prod(u[i], n[i], p[i], g[i]);
    two_sum(p[0], p[1], s, h1);
    two_sum(s, p[2], det, h2);
    for (double x : e) inexact |= x != 0.0;
    for (double x : f) inexact |= x != 0.0;
    for (double x : g) inexact |= x != 0.0;
    if (inexact | (h1 != 0.0) | (h2 != 0.0)) return false;
    sign = (det > 0.0) - (det < 0.0);
    if (value) *value = det;
    return true;
}

/// det[a-d; b-d; c-d] in double-double from exact differences, and its permanent (in double).
inline DoubleDouble orient3d_dd(const Point3d& a, const Point3d& b, const Point3d& c, const Point3d& d,
                                double& permanent) noexcept {
    const DoubleDouble ux = dd_diff(a.x, d.x), uy = dd_diff(a.y, d.y), uz = dd_diff(a.z, d.z);
    const DoubleDouble vx = dd_diff(b.x, d.x), vy = dd_diff(b.y, d.y), vz = dd_diff(b.z, d.z);
    const DoubleDouble wx = dd_diff(c.x, d.x), wy = dd_diff(c.y, d.y), wz = dd_diff(c.z, d.z);
    const DoubleDouble nx = dd_add(dd_mul(vy, wz), dd_neg(dd_mul(vz, wy)));
    const DoubleDouble ny = dd_add(dd_mul(vz, wx), dd_neg(dd_mul(vx, wz)));
    const DoubleDouble nz = dd_add(dd_mul(vx, wy), dd_neg(dd_mul(vy, wx)));
    permanent = std::abs(ux.hi) * (std::abs(vy.hi * wz.hi) + std::abs(vz.hi * wy.hi)) +
                std::abs(uy.hi) * (std::abs(vz.hi * wx.hi) + std::abs(vx.hi * wz.hi)) +
                std::abs(uz.hi) * (std::abs(vx.hi * wy.hi) + std::abs(vy.hi * wx.hi));
    return dd_add(dd_add(dd_mul(ux, nx), dd_mul(uy, ny)), dd_mul(uz, nz));
}

/// Stages B, C and D: the exact sign once the filter has failed; `value` as in orient3d_filtered.
CDKIT_PREDICATES_NOINLINE inline int orient3d_adapt(const Point3d& a, const Point3d& b, const Point3d& c,
                                                    const Point3d& d, double* value) noexcept {
    int sign;
    if (orient3d_if_error_free(a, b, c, d, sign, value)) return sign;
    double perm;
    const DoubleDouble r = orient3d_dd(a, b, c, d, perm);
    // |r − det| <= 23.1u²·perm and |r.lo| <= u|r.hi|; 2^-99 = 128u² leaves room for perm's own rounding.
    if (std::abs(r.hi) > 0x1p-99 * perm) {
        if (value) *value = r.hi;
        return r.hi > 0.0 ? 1 : -1;
    }
    return orient3d_exact(a, b, c, d, value);
}

/// Filtered orient3d (stage A, then orient3d_adapt); `value` receives an approximation of the
/// determinant with the exact sign (stage A's value when it decides).
inline int orient3d_filtered(const Point3d& a, const Point3d& b, const Point3d& c, const Point3d& d,
                             double* value = nullptr) noexcept {
    const double adx = a.x - d.x, ady = a.y - d.y, adz = a.z - d.z;
    const double bdx = b.x - d.x, bdy = b.y - d.y, bdz = b.z - d.z;
    const double cdx = c.x - d.x, cdy = c.y - d.y, cdz = c.z - d.z;
    const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    const double cdxady = cdx * ady, adxcdy = adx * cdy;
    const double adxbdy = adx * bdy, bdxady = bdx * ady;
    const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    const double perm = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                        (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                        (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
    const double bound = kOrient3dErrBound * perm;
    if (det > bound || -det > bound) {
        if (value) *value = det;
        return det > 0.0 ? 1 : -1;
    }
    return orient3d_adapt(a, b, c, d, value);
}

/// orient3d evaluated once in T, no filter (PredicateMode::floating_point).
template <class T>
[[nodiscard]] inline T orient3d_value(const Pt3<T>& a, const Pt3<T>& b, const Pt3<T>& c, const Pt3<T>& d) noexcept {
    const T adx = a.x - d.x, ady = a.y - d.y, adz = a.z - d.z;
    const T bdx = b.x - d.x, bdy = b.y - d.y, bdz = b.z - d.z;
    const T cdx = c.x - d.x, cdy = c.y - d.y, cdz = c.z - d.z;
    return adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady);
}

/// orient3d(a, b, c, ·) against one fixed plane for many query points: the plane's cross product and the
/// filter's weights are computed once, each query then costs one dot product and one bound. Evaluates
/// orient3d as (a−d)·((b−a)×(c−a)), which has the same error structure (three rounded differences,
/// a cross product, a dot product) and therefore the same stage-A bound as Shewchuk's expansion.
/// Keeps references to a, b, c (for the slow stages): they must outlive the object.
class Orient3dPlane {
public:
    Orient3dPlane(const Point3d& a, const Point3d& b, const Point3d& c) noexcept : a_(a), b_(b), c_(c) {
        const double bax = b.x - a.x, bay = b.y - a.y, baz = b.z - a.z;
        const double cax = c.x - a.x, cay = c.y - a.y, caz = c.z - a.z;
        const double xl = bay * caz, xr = baz * cay;
        const double yl = baz * cax, yr = bax * caz;
        const double zl = bax * cay, zr = bay * cax;
        n_ = {xl - xr, yl - yr, zl - zr};
        w_ = {std::abs(xl) + std::abs(xr), std::abs(yl) + std::abs(yr), std::abs(zl) + std::abs(zr)};
    }
    Orient3dPlane(const Orient3dPlane&) = delete;
    Orient3dPlane& operator=(const Orient3dPlane&) = delete;

    /// Exact sign of orient3d(a, b, c, d); `value` as in orient3d_filtered.
    int sign(const Point3d& d, double* value = nullptr) const noexcept {
        double det, bound;
        eval(d, det, bound);
        if (det > bound || -det > bound) {
            if (value) *value = det;
            return det > 0.0 ? 1 : -1;
        }
        return orient3d_adapt(a_, b_, c_, d, value);
    }
    /// Three query points at once, with a single branch in the common case: returns +1 or −1 when the
    /// filter alone puts all three strictly on that side (s and value are then left unwritten); else 0,
    /// with the exact signs in s and values as in orient3d_filtered.
    int sign3(const Point3d (&d)[3], int (&s)[3], double (&value)[3]) const noexcept {
        double det[3], bound[3];
        for (int i = 0; i < 3; ++i) eval(d[i], det[i], bound[i]);
        const bool pos = (det[0] > bound[0]) & (det[1] > bound[1]) & (det[2] > bound[2]);
        const bool neg = (-det[0] > bound[0]) & (-det[1] > bound[1]) & (-det[2] > bound[2]);
        if (pos | neg) return pos ? 1 : -1;
        for (int i = 0; i < 3; ++i) {
            if (det[i] > bound[i] || -det[i] > bound[i]) {
                s[i] = det[i] > 0.0 ? 1 : -1;
                value[i] = det[i];
            } else {
                s[i] = orient3d_adapt(a_, b_, c_, d[i], &value[i]);
            }
        }
        return 0;
    }
    /// The plane's (rounded) normal (b−a)×(c−a).
    [[nodiscard]] const Point3d& normal() const noexcept { return n_; }

private:
    void eval(const Point3d& d, double& det, double& bound) const noexcept {
        const double ux = a_.x - d.x, uy = a_.y - d.y, uz = a_.z - d.z;
        det = ux * n_.x + uy * n_.y + uz * n_.z;
        bound = kOrient3dErrBound * (std::abs(ux) * w_.x + std::abs(uy) * w_.y + std::abs(uz) * w_.z);
    }
    const Point3d& a_;
    const Point3d& b_;
    const Point3d& c_;
    Point3d n_{}, w_{};
};

/// Accurate values, not only signs, of orient3d(a, b, c, ·) against one plane, for witness points: the
/// determinant rounded to double with a relative error of at most about 2u and the exact sign. The normal
/// (b−a)×(c−a) is computed once in double-double from exact differences; each query is then a
/// double-double dot product with the exact difference a−d (same error structure as orient3d_dd, error
/// below 23.1u²·permanent). That is accepted when it guarantees u·|det|, i.e. |det| >= 2^-46·permanent;
/// nearer to degenerate, the exact stages give the value. Keeps references to a, b, c.
class Orient3dPlaneAccurate {
public:
    Orient3dPlaneAccurate(const Point3d& a, const Point3d& b, const Point3d& c) noexcept : a_(a), b_(b), c_(c) {
        const DoubleDouble bx = dd_diff(b.x, a.x), by = dd_diff(b.y, a.y), bz = dd_diff(b.z, a.z);
        const DoubleDouble cx = dd_diff(c.x, a.x), cy = dd_diff(c.y, a.y), cz = dd_diff(c.z, a.z);
        nx_ = dd_add(dd_mul(by, cz), dd_neg(dd_mul(bz, cy)));
        ny_ = dd_add(dd_mul(bz, cx), dd_neg(dd_mul(bx, cz)));
        nz_ = dd_add(dd_mul(bx, cy), dd_neg(dd_mul(by, cx)));
        w_ = {std::abs(by.hi * cz.hi) + std::abs(bz.hi * cy.hi), std::abs(bz.hi * cx.hi) + std::abs(bx.hi * cz.hi),
              std::abs(bx.hi * cy.hi) + std::abs(by.hi * cx.hi)};
    }
    Orient3dPlaneAccurate(const Orient3dPlaneAccurate&) = delete;
    Orient3dPlaneAccurate& operator=(const Orient3dPlaneAccurate&) = delete;

    [[nodiscard]] double value(const Point3d& d) const noexcept {
        const DoubleDouble ux = dd_diff(a_.x, d.x), uy = dd_diff(a_.y, d.y), uz = dd_diff(a_.z, d.z);
        const DoubleDouble r = dd_add(dd_add(dd_mul(ux, nx_), dd_mul(uy, ny_)), dd_mul(uz, nz_));
        const double perm = std::abs(ux.hi) * w_.x + std::abs(uy.hi) * w_.y + std::abs(uz.hi) * w_.z;
        if (std::abs(r.hi) >= 0x1p-46 * perm) return r.hi;
        int sign;
        double v;
        if (orient3d_if_error_free(a_, b_, c_, d, sign, &v)) return v;
        orient3d_exact(a_, b_, c_, d, &v);
        return v;
    }

private:
    const Point3d& a_;
    const Point3d& b_;
    const Point3d& c_;
    DoubleDouble nx_{}, ny_{}, nz_{};
    Point3d w_{};
};

/// orient3d's determinant rounded to double with a relative error of at most about 2u and the exact sign
/// (see Orient3dPlaneAccurate). For witness points, not for decisions.
inline double orient3d_accurate(const Point3d& a, const Point3d& b, const Point3d& c, const Point3d& d) noexcept {
    return Orient3dPlaneAccurate(a, b, c).value(d);
}

// ---- the wide-range stage: any finite input ------------------------------------------------------

/// Whether a finite x lies outside the floating-point stages' range (nonzero with |x| < 2^-280, or
/// |x| > 2^280). Non-finite x: false, as no stage can give it meaning.
[[nodiscard]] inline bool outside_predicate_range(double x) noexcept {
    const double m = std::abs(x);
    return (m < 0x1p-280 && m != 0.0) | ((m > 0x1p280) & (m <= std::numeric_limits<double>::max()));
}
template <std::size_t N> [[nodiscard]] inline bool any_outside_predicate_range(const double (&x)[N]) noexcept {
    bool out = false;
    for (double v : x) out |= outside_predicate_range(v);
    return out;
}

/// The smallest lowest-set-bit exponent over x (every x is then an integer multiple of 2^result).
template <std::size_t N> [[nodiscard]] inline int common_exponent(const double (&x)[N]) noexcept {
    int base = std::numeric_limits<int>::max();
    for (double v : x)
        if (v != 0.0) base = std::min(base, WideInt::lowest_exponent(v));
    return base == std::numeric_limits<int>::max() ? 0 : base;
}

/// A determinant's value for witness interpolation: the wide value in double, kept nonzero with its exact
/// sign when it underflows, and finite when it overflows (callers only form ratios of such values).
[[nodiscard]] inline double wide_value(const WideInt& det, int scale) noexcept {
    const double v = det.to_double(scale);
    const int s = det.sign();
    if (s == 0) return 0.0;
    if (v == 0.0) return s * std::numeric_limits<double>::denorm_min();
    if (std::isinf(v)) return s * std::numeric_limits<double>::max();
    return v;
}

/// Exact sign of det[a-d; b-d; c-d] for any finite input, in wide integers; `value` as in orient3d_filtered.
CDKIT_PREDICATES_NOINLINE inline int orient3d_wide(const Point3d& a, const Point3d& b, const Point3d& c,
                                                   const Point3d& d, double* value = nullptr) noexcept {
    const double x[12] = {a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, d.x, d.y, d.z};
    const int base = common_exponent(x);
    WideInt w[12];
    for (int i = 0; i < 12; ++i) w[i] = WideInt::from_double(x[i], base);
    const WideInt adx = w[0] - w[9], ady = w[1] - w[10], adz = w[2] - w[11];
    const WideInt bdx = w[3] - w[9], bdy = w[4] - w[10], bdz = w[5] - w[11];
    const WideInt cdx = w[6] - w[9], cdy = w[7] - w[10], cdz = w[8] - w[11];
    const WideInt det =
        adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady);
    if (value) *value = wide_value(det, 3 * base);
    return det.sign();
}

/// Exact sign of det[a-c; b-c] for any finite input; `approx` as in orient2d_exact.
CDKIT_PREDICATES_NOINLINE inline int orient2d_wide(const Point2d& a, const Point2d& b, const Point2d& c,
                                                   double* approx = nullptr) noexcept {
    const double x[6] = {a.x, a.y, b.x, b.y, c.x, c.y};
    const int base = common_exponent(x);
    WideInt w[6];
    for (int i = 0; i < 6; ++i) w[i] = WideInt::from_double(x[i], base);
    const WideInt det = (w[0] - w[4]) * (w[3] - w[5]) - (w[1] - w[5]) * (w[2] - w[4]);
    if (approx) *approx = wide_value(det, 2 * base);
    return det.sign();
}

/// orient3d with the exact sign for every finite input: the filtered stages within their range, else
/// the wide stage.
inline int orient3d_any_range(const Point3d& a, const Point3d& b, const Point3d& c, const Point3d& d,
                              double* value = nullptr) noexcept {
    const double x[12] = {a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, d.x, d.y, d.z};
    if (any_outside_predicate_range(x)) return orient3d_wide(a, b, c, d, value);
    return orient3d_filtered(a, b, c, d, value);
}
inline int orient2d_any_range(const Point2d& a, const Point2d& b, const Point2d& c, double* value = nullptr) noexcept {
    const double x[6] = {a.x, a.y, b.x, b.y, c.x, c.y};
    if (any_outside_predicate_range(x)) return orient2d_wide(a, b, c, value);
    return orient2d_filtered(a, b, c, value);
}

template <class S> inline constexpr bool is_predicate_scalar_v = std::is_same_v<S, float> || std::is_same_v<S, double>;

}  // namespace detail

/// Orientation of d relative to the plane through a, b, c (Shewchuk's convention): +1 when d lies below
/// the plane, "below" meaning the side from which a, b, c appear clockwise (equivalently: a, b, c appear
/// counterclockwise seen from above); −1 above; 0 when the four points are coplanar. It is the sign of
/// det[a−d; b−d; c−d] = (a−d)·((b−d)×(c−d)), i.e. −sign((d−a)·((b−a)×(c−a))). In filtered_exact mode the
/// sign is exact for every finite input; S is float or double.
template <class S>
[[nodiscard]] int orient3d(const Vec3<S>& a, const Vec3<S>& b, const Vec3<S>& c, const Vec3<S>& d,
                           PredicateMode mode = PredicateMode::filtered_exact) noexcept {
    static_assert(detail::is_predicate_scalar_v<S>, "orient3d: S must be float or double");
    if (mode == PredicateMode::floating_point) {
        const S v = detail::orient3d_value(detail::to_pt<S>(a), detail::to_pt<S>(b), detail::to_pt<S>(c),
                                           detail::to_pt<S>(d));
        return (v > S(0)) - (v < S(0));
    }
    return detail::orient3d_any_range(detail::to_pt<double>(a), detail::to_pt<double>(b), detail::to_pt<double>(c),
                                      detail::to_pt<double>(d));
}

/// Orientation of the 2D points a, b, c: +1 when they turn counterclockwise (c left of the directed line
/// a→b), −1 clockwise, 0 collinear; the sign of det[a−c; b−c]. Exact in filtered_exact mode.
template <class S>
[[nodiscard]] int orient2d(const Eigen::Matrix<S, 2, 1>& a, const Eigen::Matrix<S, 2, 1>& b,
                           const Eigen::Matrix<S, 2, 1>& c, PredicateMode mode = PredicateMode::filtered_exact) noexcept {
    static_assert(detail::is_predicate_scalar_v<S>, "orient2d: S must be float or double");
    if (mode == PredicateMode::floating_point) {
        const S v = detail::orient2d_value(detail::Pt2<S>{a.x(), a.y()}, detail::Pt2<S>{b.x(), b.y()},
                                           detail::Pt2<S>{c.x(), c.y()});
        return (v > S(0)) - (v < S(0));
    }
    return detail::orient2d_any_range(detail::Point2d{double(a.x()), double(a.y())},
                                      detail::Point2d{double(b.x()), double(b.y())},
                                      detail::Point2d{double(c.x()), double(c.y())});
}

}  // namespace cdkit
