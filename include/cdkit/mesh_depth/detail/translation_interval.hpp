#pragma once
/// \file For two triangles P and Q and a direction n: the interval of t for which Q + t·n meets P, and the same for
/// two boxes (the bound a tree node pair gives).
///
/// P ∩ (Q + t·n) ≠ ∅ iff t·n lies in the Minkowski difference P − Q, a convex set, so the admissible t form one
/// closed interval. We find it without building P − Q: the points x of Q that P's prism along n (the three planes
/// through P's edges that contain n) holds are exactly those whose line x + t·n crosses P, at
/// t(x) = n_P·(p₀ − x) / n_P·n. That set is Q clipped by the prism (Sutherland, Hodgman, CACM 1974), a convex
/// polygon, and t is affine on it, so the interval is spanned by the clipped polygon's vertices. When n runs nearly
/// in P's plane the roles swap (P clipped by Q's prism, t(x) = n_Q·(x − q₀) / n_Q·n), whichever plane n crosses more
/// steeply. Both planes holding n (sliding edge on edge, or a degenerate triangle) is a measure-zero case; it falls
/// back to the pair's boxes, which bound the interval from outside.

#include "cdkit/broadphase/box.hpp"
#include "cdkit/core/math.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace cdkit::detail {

/// A closed interval of translations; empty when lo > hi. `at_hi_a` / `at_hi_b` are where the two features touch at
/// t = hi: a point of the fixed one and the point of the moving one at t = 0 (at_hi_a − at_hi_b = hi·n).
struct TranslationInterval {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -std::numeric_limits<double>::infinity();
    Vec3<double> at_hi_a = Vec3<double>::Zero(), at_hi_b = Vec3<double>::Zero();
    [[nodiscard]] bool empty() const noexcept { return !(lo <= hi); }
};

/// The t for which box b + t·n meets box a (both axis-aligned, in the same frame): per axis an interval, intersected.
[[nodiscard]] inline TranslationInterval box_translation_interval(const BroadBox<double>& a, const BroadBox<double>& b,
                                                                  const Vec3<double>& n) noexcept {
    TranslationInterval r;
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        // Overlap on axis k: a.lo ≤ b.hi + t·n and b.lo + t·n ≤ a.hi.
        const double from = a.lo[k] - b.hi[k], to = a.hi[k] - b.lo[k];
        if (n[k] == 0) {
            if (from > 0 || to < 0) return r;
            continue;
        }
        double t0 = from / n[k], t1 = to / n[k];
        if (t0 > t1) std::swap(t0, t1);
        lo = std::max(lo, t0);
        hi = std::min(hi, t1);
    }
    r.lo = lo;
    r.hi = hi;
    return r;
}

/// The part of the convex polygon `poly` (n ≤ 6 points) inside the prism of triangle T along direction d.
struct SmallPolygon {
    std::array<Vec3<double>, 9> p;
    int n = 0;
};

inline void clip_to_prism(SmallPolygon& poly, const std::array<Vec3<double>, 3>& T, const Vec3<double>& d) noexcept {
    for (int e = 0; e < 3 && poly.n > 0; ++e) {
        const Vec3<double>& p0 = T[e];
        const Vec3<double>& p1 = T[(e + 1) % 3];
        Vec3<double> m = (p1 - p0).cross(d);
        if (m.dot(T[(e + 2) % 3] - p0) < 0) m = -m;  // inward
        const double off = m.dot(p0);
        SmallPolygon out;
        for (int i = 0; i < poly.n; ++i) {
            const Vec3<double>& a = poly.p[i];
            const Vec3<double>& b = poly.p[(i + 1) % poly.n];
            const double da = m.dot(a) - off, db = m.dot(b) - off;
            if (da >= 0 && out.n < 9) out.p[out.n++] = a;
            if (((da < 0) != (db < 0)) && da != db && out.n < 9) out.p[out.n++] = a + (da / (da - db)) * (b - a);
        }
        poly = out;
    }
}

/// The t for which Q + t·n meets P (n need not be unit: t is in units of n). Empty when never.
[[nodiscard]] inline TranslationInterval triangle_translation_interval(const std::array<Vec3<double>, 3>& P,
                                                                       const std::array<Vec3<double>, 3>& Q,
                                                                       const Vec3<double>& n) noexcept {
    TranslationInterval r;
    const Vec3<double> nP = (P[1] - P[0]).cross(P[2] - P[0]), nQ = (Q[1] - Q[0]).cross(Q[2] - Q[0]);
    const double cP = std::abs(nP.dot(n)), cQ = std::abs(nQ.dot(n));
    const double sP = nP.norm(), sQ = nQ.norm();
    constexpr double steep = 1e-9;  // |cos| between the plane's normal and n below this: n runs in the plane
    const bool use_p = cP * sQ >= cQ * sP;  // compare the cosines without dividing
    if (use_p ? !(cP > steep * sP * n.norm()) : !(cQ > steep * sQ * n.norm())) {
        BroadBox<double> a{P[0].cwiseMin(P[1]).cwiseMin(P[2]), P[0].cwiseMax(P[1]).cwiseMax(P[2])};
        BroadBox<double> b{Q[0].cwiseMin(Q[1]).cwiseMin(Q[2]), Q[0].cwiseMax(Q[1]).cwiseMax(Q[2])};
        r = box_translation_interval(a, b, n);
        if (!r.empty()) r.at_hi_b = 0.5 * (b.lo + b.hi), r.at_hi_a = r.at_hi_b + r.hi * n;
        return r;
    }
    SmallPolygon poly;
    poly.n = 3;
    const auto& moving = use_p ? Q : P;  // clipped: the triangle whose points travel along its lines
    const auto& fixed = use_p ? P : Q;
    for (int i = 0; i < 3; ++i) poly.p[i] = moving[i];
    clip_to_prism(poly, fixed, n);
    if (poly.n == 0) return r;
    const Vec3<double> nf = use_p ? nP : nQ;
    const double denom = nf.dot(n);
    for (int i = 0; i < poly.n; ++i) {
        const Vec3<double>& x = poly.p[i];
        // x ∈ Q reaches P's plane at t = n_P·(p₀ − x)/n_P·n; x ∈ P is met by Q's plane moved by t = n_Q·(x − q₀)/n_Q·n.
        const double t = use_p ? nf.dot(fixed[0] - x) / denom : nf.dot(x - fixed[0]) / denom;
        r.lo = std::min(r.lo, t);
        if (t > r.hi) {
            r.hi = t;
            r.at_hi_a = use_p ? Vec3<double>(x + t * n) : x;
            r.at_hi_b = use_p ? x : Vec3<double>(x - t * n);
        }
    }
    return r;
}

}  // namespace cdkit::detail
