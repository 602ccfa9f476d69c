#pragma once
/// \file The predicate kernels of the triangle–triangle test (narrowphase/triangle.hpp): orientation signs
/// computed exactly (double with filter and expansions; a wide-range variant for coordinates outside the
/// filter's range) or once in floating point, behind one interface the test is written against.

#include "cdkit/core/math.hpp"
#include "cdkit/core/predicates.hpp"

#include <cmath>
#include <type_traits>

namespace cdkit::detail::tritri {

template <class T> [[nodiscard]] inline T coord(const Pt3<T>& p, int k) noexcept {
    return k == 0 ? p.x : (k == 1 ? p.y : p.z);
}
/// Drops axis k keeping a cyclic (right-handed) order, so that orient2d of a projected triangle has the
/// sign of its normal's k-th component: k=2 → (x,y), k=0 → (y,z), k=1 → (z,x).
template <class T> [[nodiscard]] inline Pt2<T> proj(const Pt3<T>& p, int k) noexcept {
    if (k == 0) return {p.y, p.z};
    if (k == 1) return {p.z, p.x};
    return {p.x, p.y};
}

/// Predicates with exact signs (double arithmetic, filter + expansions). Sign convention used throughout
/// this file: above(a,b,c,d) = sign((d−a)·((b−a)×(c−a))) = −orient3d(a,b,c,d), positive when d is on the
/// side the normal of the counterclockwise triangle a,b,c points to.
struct ExactKernel {
    using T = double;
    using P = Pt3<double>;
    class Plane {
    public:
        Plane(const P& a, const P& b, const P& c) noexcept : o_(a, b, c) {}
        int above(const P& d, double& v) const noexcept {
            double o;
            const int s = o_.sign(d, &o);
            v = -o;
            return -s;
        }
        /// above() for three points; returns ±1 (s, v unwritten) when all three are strictly on that side.
        int above3(const P (&d)[3], int (&s)[3], double (&v)[3]) const noexcept {
            const int side = -o_.sign3(d, s, v);
            if (side == 0) negate(s, v);
            return side;
        }

    private:
        static void negate(int (&s)[3], double (&v)[3]) noexcept {
            for (int i = 0; i < 3; ++i) {
                s[i] = -s[i];
                v[i] = -v[i];
            }
        }
        Orient3dPlane o_;
    };
    static int above(const P& a, const P& b, const P& c, const P& d) noexcept { return -orient3d_filtered(a, b, c, d); }
    static int orient2(const P& a, const P& b, const P& c, int k) noexcept {
        return orient2d_filtered(proj(a, k), proj(b, k), proj(c, k));
    }
    static int orient2(const P& a, const P& b, const P& c, int k, double& v) noexcept {
        return orient2d_filtered(proj(a, k), proj(b, k), proj(c, k), &v);
    }
    /// Witness values against one plane ("above" convention), recomputed to a relative error of ~2u: the
    /// filter's values can be far worse, and the witness accuracy rests on these.
    class Values {
    public:
        Values(const P& a, const P& b, const P& c) noexcept : o_(a, b, c) {}
        double operator()(const P& d, double) const noexcept { return -o_.value(d); }

    private:
        Orient3dPlaneAccurate o_;
    };
    static double value2(const P& a, const P& b, const P& c, int k, double) noexcept {
        double v;
        orient2d_exact(proj(a, k), proj(b, k), proj(c, k), &v);
        return v;
    }
};

/// ExactKernel's fallback for input outside the floating-point stages' range (a subnormal or huge
/// coordinate): every determinant in wide integers, exact for all finite input, and slow. Its values are
/// the exact determinants rounded to double (kept nonzero and finite), so witnesses stay on the right
/// segments, without ExactKernel's accuracy bound when a value leaves double's range.
struct WideRangeKernel {
    using T = double;
    using P = Pt3<double>;
    class Plane {
    public:
        Plane(const P& a, const P& b, const P& c) noexcept : a_(a), b_(b), c_(c) {}
        int above(const P& d, double& v) const noexcept {
            double o;
            const int s = orient3d_wide(a_, b_, c_, d, &o);
            v = -o;
            return -s;
        }
        int above3(const P (&d)[3], int (&s)[3], double (&v)[3]) const noexcept {
            for (int i = 0; i < 3; ++i) s[i] = above(d[i], v[i]);
            const bool pos = (s[0] > 0) & (s[1] > 0) & (s[2] > 0), neg = (s[0] < 0) & (s[1] < 0) & (s[2] < 0);
            return pos ? 1 : (neg ? -1 : 0);
        }

    private:
        P a_, b_, c_;
    };
    static int above(const P& a, const P& b, const P& c, const P& d) noexcept { return -orient3d_wide(a, b, c, d); }
    static int orient2(const P& a, const P& b, const P& c, int k) noexcept {
        return orient2d_wide(proj(a, k), proj(b, k), proj(c, k));
    }
    static int orient2(const P& a, const P& b, const P& c, int k, double& v) noexcept {
        return orient2d_wide(proj(a, k), proj(b, k), proj(c, k), &v);
    }
    class Values {
    public:
        Values(const P& a, const P& b, const P& c) noexcept : plane_(a, b, c) {}
        double operator()(const P& d, double) const noexcept {
            double v;
            plane_.above(d, v);
            return v;
        }

    private:
        Plane plane_;
    };
    static double value2(const P& a, const P& b, const P& c, int k, double) noexcept {
        double v;
        orient2d_wide(proj(a, k), proj(b, k), proj(c, k), &v);
        return v;
    }
};

/// PredicateMode::floating_point: the same determinants once in S, their signs taken as they come.
/// Witness values are the very numbers the signs came from, so every sign-guarded division stays safe.
template <class S> struct FloatKernel {
    using T = S;
    using P = Pt3<S>;
    class Plane {
    public:
        Plane(const P& a, const P& b, const P& c) noexcept : a_(a) {
            const S bax = b.x - a.x, bay = b.y - a.y, baz = b.z - a.z;
            const S cax = c.x - a.x, cay = c.y - a.y, caz = c.z - a.z;
            n_ = {bay * caz - baz * cay, baz * cax - bax * caz, bax * cay - bay * cax};
        }
        int above(const P& d, S& v) const noexcept {
            v = (d.x - a_.x) * n_.x + (d.y - a_.y) * n_.y + (d.z - a_.z) * n_.z;
            return (v > S(0)) - (v < S(0));
        }
        int above3(const P (&d)[3], int (&s)[3], S (&v)[3]) const noexcept {
            for (int i = 0; i < 3; ++i) s[i] = above(d[i], v[i]);
            const bool pos = (s[0] > 0) & (s[1] > 0) & (s[2] > 0), neg = (s[0] < 0) & (s[1] < 0) & (s[2] < 0);
            return pos ? 1 : (neg ? -1 : 0);
        }

    private:
        P a_, n_;
    };
    static int above(const P& a, const P& b, const P& c, const P& d) noexcept {
        const S v = orient3d_value(a, b, c, d);
        return (v < S(0)) - (v > S(0));
    }
    static int orient2(const P& a, const P& b, const P& c, int k) noexcept {
        const S v = orient2d_value(proj(a, k), proj(b, k), proj(c, k));
        return (v > S(0)) - (v < S(0));
    }
    static int orient2(const P& a, const P& b, const P& c, int k, S& v) noexcept {
        v = orient2d_value(proj(a, k), proj(b, k), proj(c, k));
        return (v > S(0)) - (v < S(0));
    }
    struct Values {
        Values(const P&, const P&, const P&) noexcept {}
        S operator()(const P&, S stored) const noexcept { return stored; }
    };
    static S value2(const P&, const P&, const P&, int, S stored) noexcept { return stored; }
};

}  // namespace cdkit::detail::tritri
