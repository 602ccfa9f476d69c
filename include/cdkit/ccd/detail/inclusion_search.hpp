#pragma once
/// \file The root search behind vertex–face and edge–edge CCD: is there (t, u, v) in the domain where the gap
/// function F(t, u, v) = B(t) + u·E1(t) + v·E2(t) comes within the minimum separation of 0?
///
/// Method: conservative inclusion over domain boxes, after Wang, Ferguson, Schneider, Jiang, Attene, Panozzo,
/// "A Large Scale Benchmark and an Inclusion-Based Algorithm for Continuous Collision Detection", ACM TOG 40(5),
/// 2021. With linear motion F is multilinear in (t, u, v), so over a box its values lie in the convex hull of
/// its 8 corner values; a box is excluded when a plane through the origin separates those 8 values (widened by
/// a proven floating-point error bound and the minimum separation). Unlike the paper, which tests only the
/// axis-aligned hull of the corners, we also try the face (edge-pair) normal and the direction of the corners'
/// centroid: a vertex sliding over a face, or an edge over a parallel edge, at a small gap is excluded at once
/// instead of by splitting down to the gap in every dimension, which is what makes the paper's tail long.
/// Besides those planes, a box's time interval alone is tested (for contact at distance 0): F = 0 needs B, E1, E2
/// coplanar, so the cubic c(t) = det(B(t), E1(t), E2(t)) (Provot 1997) must vanish; its Bernstein coefficients on
/// [t_lo, t_hi] all of one sign beyond their error bound exclude every (u, v) at once — the sign test of Tang,
/// Tong, Wang, Manocha, "Fast and Exact Continuous Collision Detection with Bernstein Sign Classification", ACM
/// TOG 33(6), 2014. The control polygon approaches c quadratically in the width, so boxes before the first
/// contact go at far coarser t than under the fixed-normal plane, which needs them split down to about their
/// distance from that contact: those splits were most of the slow tail of the handcrafted edge–edge set.
/// Boxes are searched earliest-t first (a heap on t), so the first box accepted bounds the first contact from
/// below; a work cap bounds the worst case and then answers conservatively (contact).

#include "cdkit/ccd/ccd_result.hpp"
#include "cdkit/ccd/detail/gap_function.hpp"
#include "cdkit/ccd/detail/krawczyk.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace cdkit::detail {

/// The 8 corner values of F over a box, one array per axis (index: 4·t + 2·u + v, each bit the upper end;
/// per axis so that the loops over corners vectorise), and E1 × E2 at the box's lower t (the face normal, or the
/// common normal of two edges).
struct BoxCorners {
    double f[3][8];
    double normal[3];
    double B[2][3], E1[2][3], E2[2][3];  ///< F's terms at the box's lower [0] and upper [1] t
};

inline void evaluate_corners(const GapFunction& g, const InclusionBox& box, BoxCorners& out) noexcept {
    const double t[2] = {box.lo[0], box.hi[0]};
    const double u[4] = {box.lo[1], box.lo[1], box.hi[1], box.hi[1]};
    const double v[4] = {box.lo[2], box.hi[2], box.lo[2], box.hi[2]};
    double e1_lo[3], e2_lo[3];
    for (int k = 0; k < 3; ++k) {
        for (int ti = 0; ti < 2; ++ti) {
            const double B = g.b0[k] + t[ti] * (g.b1[k] - g.b0[k]);
            const double E1 = g.e10[k] + t[ti] * (g.e11[k] - g.e10[k]);
            const double E2 = g.e20[k] + t[ti] * (g.e21[k] - g.e20[k]);
            if (ti == 0) e1_lo[k] = E1, e2_lo[k] = E2;
            out.B[ti][k] = B, out.E1[ti][k] = E1, out.E2[ti][k] = E2;
            for (int j = 0; j < 4; ++j) out.f[k][4 * ti + j] = B + u[j] * E1 + v[j] * E2;
        }
    }
    out.normal[0] = e1_lo[1] * e2_lo[2] - e1_lo[2] * e2_lo[1];
    out.normal[1] = e1_lo[2] * e2_lo[0] - e1_lo[0] * e2_lo[2];
    out.normal[2] = e1_lo[0] * e2_lo[1] - e1_lo[1] * e2_lo[0];
}

/// True when the plane through the origin with normal n proves every value of F over the box farther than
/// `separation` from 0: all corners on one side, beyond the separation, the corners' error and the rounding
/// of the dot products (γ₃ ≤ 2ε relative to Σ|n_k|·max|f_k|; `magnitude` holds max over the corners of |f_k|).
[[nodiscard]] inline bool direction_excludes(const BoxCorners& c, const double n[3], const double magnitude[3],
                                             const GapFunction& g, double separation) noexcept {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const double an0 = std::abs(n[0]), an1 = std::abs(n[1]), an2 = std::abs(n[2]);
    const double norm_bound = an0 + an1 + an2;  // ≥ |n|₂, no square root
    if (!(norm_bound > 0) || !std::isfinite(norm_bound)) return false;
    const double margin = (separation * norm_bound + an0 * (g.error[0] + 2 * eps * magnitude[0]) +
                           an1 * (g.error[1] + 2 * eps * magnitude[1]) + an2 * (g.error[2] + 2 * eps * magnitude[2])) *
                          (1 + 8 * eps);
    const double s0 = n[0] * c.f[0][0] + n[1] * c.f[1][0] + n[2] * c.f[2][0];
    if (s0 > margin) {
        for (int i = 1; i < 8; ++i)
            if (!(n[0] * c.f[0][i] + n[1] * c.f[1][i] + n[2] * c.f[2][i] > margin)) return false;
        return true;
    }
    if (s0 < -margin) {
        for (int i = 1; i < 8; ++i)
            if (!(n[0] * c.f[0][i] + n[1] * c.f[1][i] + n[2] * c.f[2][i] < -margin)) return false;
        return true;
    }
    return false;
}

/// True when c(t) = det(B(t), E1(t), E2(t)) has no zero on the box's time interval [a, b], so F has none either
/// (F = 0 makes B, E1, E2 linearly dependent). c is cubic; its Bernstein coefficients on [a, b] are the values of
/// its blossom with k arguments at b (k = 0…3): det(B(r), E1(s), E2(t)) averaged over the ways to put k of
/// r, s, t at b. All beyond coplanarity_error and of one sign, c keeps that sign on [a, b] (convex hull property).
[[nodiscard]] inline bool coplanarity_excludes(const BoxCorners& c, const GapFunction& g) noexcept {
    auto det = [&](int r, int s, int t) {
        const double *x = c.B[r], *y = c.E1[s], *z = c.E2[t];
        return x[0] * (y[1] * z[2] - y[2] * z[1]) + x[1] * (y[2] * z[0] - y[0] * z[2]) +
               x[2] * (y[0] * z[1] - y[1] * z[0]);
    };
    const double e = g.coplanarity_error;
    const double c0 = det(0, 0, 0), c3 = det(1, 1, 1);
    if (!(std::abs(c0) > e) || !(std::abs(c3) > e) || !(c0 * c3 > 0)) return false;
    const double c1 = (det(1, 0, 0) + det(0, 1, 0) + det(0, 0, 1)) / 3;
    const double c2 = (det(0, 1, 1) + det(1, 0, 1) + det(1, 1, 0)) / 3;
    return c0 > 0 ? c1 > e && c2 > e : c1 < -e && c2 < -e;
}

/// Boxes this many splits deep get a Newton (Krawczyk) step before they are split again: larger ones rarely
/// pass it, and the step costs about as much as a box.
inline constexpr int kNewtonDepth = 6;
inline constexpr int kNewtonEvery = 3;

enum class BoxVerdict { excluded, accepted, split_t, split_u, split_v };

/// Decides one box: excluded (no contact in it), accepted (its values all lie within the tolerance of each other
/// and none of the tests excludes it: a contact, or a near-miss closer than about the tolerance), or split.
[[nodiscard]] inline BoxVerdict judge_box(const GapFunction& g, const InclusionBox& box, const CcdRequest& req,
                                          BoxCorners& c) noexcept {
    if (g.triangle_domain && box.lo[1] + box.lo[2] > 1) return BoxVerdict::excluded;  // rounding only lowers "> 1"
    evaluate_corners(g, box, c);
    double width = 0;
    double centre[3], magnitude[3];
    for (int k = 0; k < 3; ++k) {
        double lo = c.f[k][0], hi = c.f[k][0], sum = c.f[k][0];
        for (int i = 1; i < 8; ++i) {
            lo = std::min(lo, c.f[k][i]);
            hi = std::max(hi, c.f[k][i]);
            sum += c.f[k][i];
        }
        const double margin = req.min_separation + g.error[k];
        if (lo > margin || hi < -margin) return BoxVerdict::excluded;
        width = std::max(width, hi - lo + 2 * g.error[k]);
        centre[k] = sum;
        magnitude[k] = std::max(hi, -lo);
    }
    if (direction_excludes(c, c.normal, magnitude, g, req.min_separation)) return BoxVerdict::excluded;
    // The time-only test, for touching contact, after the cheaper fixed-normal test, and only on a time interval
    // its parent did not already fail on.
    if (req.min_separation == 0 && box.new_time && coplanarity_excludes(c, g)) return BoxVerdict::excluded;
    if (direction_excludes(c, centre, magnitude, g, req.min_separation)) return BoxVerdict::excluded;
    {
        // The centroid's direction without its component along E1: for (nearly) parallel edges, where E1 × E2
        // vanishes and the values spread along the edges, this is the direction of the gap between them.
        double e[3];
        for (int k = 0; k < 3; ++k) e[k] = c.f[k][2] - c.f[k][0];  // u-edge of the box: (Δu)·E1 at t_lo
        const double ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        if (ee > 0) {
            const double s = (centre[0] * e[0] + centre[1] * e[1] + centre[2] * e[2]) / ee;
            double perp[3];
            for (int k = 0; k < 3; ++k) perp[k] = centre[k] - s * e[k];
            if (direction_excludes(c, perp, magnitude, g, req.min_separation)) return BoxVerdict::excluded;
        }
    }
    if (width <= req.tolerance) return BoxVerdict::accepted;

    // Split t while F changes along t by more than the tolerance: the search orders boxes by time slot, so
    // resolving t first lets a contact set spread over (u, v) at one time (parallel edges, sliding) be dived
    // into instead of being refined everywhere at each t. Then split where F changes most.
    double change[3] = {0, 0, 0};
    for (int d = 0; d < 3; ++d) {
        const int bit = 4 >> d;
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 8; ++i)
                if (!(i & bit)) change[d] = std::max(change[d], std::abs(c.f[k][i | bit] - c.f[k][i]));
    }
    // A parameter interval this narrow cannot usefully be halved again (its midpoint may round to an end).
    constexpr double min_width = 0x1p-50;
    int best = change[0] > req.tolerance && box.hi[0] - box.lo[0] > min_width ? 0 : -1;
    for (int d = 1; d < 3 && best != 0; ++d)
        if (box.hi[d] - box.lo[d] > min_width && (best < 0 || change[d] > change[best])) best = d;
    if (best < 0 && box.hi[0] - box.lo[0] > min_width) best = 0;
    if (best < 0) return BoxVerdict::accepted;
    return static_cast<BoxVerdict>(static_cast<int>(BoxVerdict::split_t) + best);
}

/// A box of the search, and whether F's zero in it is proven (Krawczyk) or still to be decided.
struct SearchBox {
    InclusionBox box;
    bool proven = false;  ///< F has exactly one zero in `box`'s parent and it lies in `box`
    double slot = 0;      ///< ⌊t_lo / time_tolerance⌋: the search order's first key
};

/// Tries to prove a zero of F in `box` (for contact at distance 0 only, and inside the triangle for
/// vertex–face); on success `out` is the smaller box that holds it.
[[nodiscard]] inline bool prove_zero(const GapFunction& g, const CcdRequest& req, const InclusionBox& box,
                                     InclusionBox& out, CcdStats& stats) noexcept {
    if (req.min_separation > 0) return false;  // then contact begins before F's zero: the zero says nothing
    ++stats.newton_steps;
    // The test needs the zero inside the box, not on its boundary; bisection puts boundaries on dyadic values,
    // where zeros of handcrafted (and snapped) inputs lie. So the box is widened by a quarter on each side, within
    // the domain; a zero proven there is still X's only one.
    InclusionBox wide = box;
    for (int d = 0; d < 3; ++d) {
        const double grow = 0.25 * (box.hi[d] - box.lo[d]);
        wide.lo[d] = std::max(0.0, box.lo[d] - grow);
        wide.hi[d] = std::min(d == 0 ? req.t_max : 1.0, box.hi[d] + grow);
    }
    if (!krawczyk_contract(g, wide, out)) return false;
    return !g.triangle_domain || out.hi[1] + out.hi[2] < 1;
}

/// Earliest-t search over t ∈ [0, t_max], u, v ∈ [0, 1]. Fills colliding, proven, toi, toi_upper, u, v, stats.
inline void inclusion_search(const GapFunction& g, const CcdRequest& req, CcdResult& out) {
    out.colliding = false;
    out.toi = out.toi_upper = req.t_max;
    std::vector<SearchBox> heap;
    // Every contact lies in the current box or a queued one, so the smallest t_lo among them bounds the first
    // contact from below (a scan: the queue is ordered by slot, not by t_lo).
    auto earliest = [&](const InclusionBox& b) {
        double t = b.lo[0];
        for (const SearchBox& q : heap) t = std::min(t, q.box.lo[0]);
        return t;
    };
    auto accept = [&](const InclusionBox& b, bool proven) {
        out.colliding = true;
        out.proven = proven;
        out.toi = earliest(b);
        out.toi_upper = b.hi[0];
        out.u = 0.5 * (b.lo[1] + b.hi[1]);
        out.v = 0.5 * (b.lo[2] + b.hi[2]);
    };
    // Earliest time slot (of width time_tolerance) first; within a slot, the deepest box first. A contact set
    // spread at one t (parallel edges, a face sliding in its plane) is then followed down one path instead of
    // refined everywhere at once, and the answer is still within the time tolerance of the first contact.
    auto later = [](const SearchBox& a, const SearchBox& b) {
        if (a.slot != b.slot) return a.slot > b.slot;
        if (a.box.depth != b.box.depth) return a.box.depth < b.box.depth;
        return a.box.lo[0] > b.box.lo[0];
    };
    auto push = [&](SearchBox b) {
        b.slot = std::floor(b.box.lo[0] / req.time_tolerance);
        if (heap.empty()) heap.reserve(64);
        heap.push_back(b);
        std::push_heap(heap.begin(), heap.end(), later);
    };
    double t_limit = req.t_max;  // a proven zero at t ≤ t_limit makes every later box irrelevant
    SearchBox current{InclusionBox{{0, 0, 0}, {req.t_max, 1, 1}, 0}, false, 0};
    BoxCorners corners;
    InclusionBox contracted;
    for (;;) {
        ++out.stats.boxes;
        if (current.proven) {
            // Every box of an earlier slot is decided: the first contact is this zero, or within the time
            // tolerance before it. Narrow its time, then answer.
            const InclusionBox& b = current.box;
            if (b.hi[0] - b.lo[0] <= req.time_tolerance || !prove_zero(g, req, b, contracted, out.stats) ||
                contracted.hi[0] - contracted.lo[0] > 0.5 * (b.hi[0] - b.lo[0])) {
                accept(b, true);
                return;
            }
            t_limit = std::min(t_limit, contracted.hi[0]);
            push({contracted, true});
        } else {
            const BoxVerdict verdict = judge_box(g, current.box, req, corners);
            if (verdict == BoxVerdict::accepted) {
                // Small enough to call a contact; prove it if Newton can, so the answer says which it is.
                const bool proven = prove_zero(g, req, current.box, contracted, out.stats);
                accept(proven ? contracted : current.box, proven);
                return;
            }
            if (verdict != BoxVerdict::excluded) {
                if (current.box.depth >= kNewtonDepth && current.box.depth % kNewtonEvery == 0 && prove_zero(g, req, current.box, contracted, out.stats)) {
                    t_limit = std::min(t_limit, contracted.hi[0]);
                    push({contracted, true});
                } else {
                    const int d = static_cast<int>(verdict) - static_cast<int>(BoxVerdict::split_t);
                    const double mid = 0.5 * (current.box.lo[d] + current.box.hi[d]);
                    SearchBox first = current, second = current;
                    first.box.hi[d] = mid;
                    second.box.lo[d] = mid;
                    first.box.depth = second.box.depth = current.box.depth + 1;
                    first.box.new_time = second.box.new_time = d == 0;
                    ++out.stats.subdivisions;
                    push(first);
                    push(second);
                }
            }
        }
        do {
            if (heap.empty()) return;
            std::pop_heap(heap.begin(), heap.end(), later);
            current = heap.back();
            heap.pop_back();
        } while (current.box.lo[0] > t_limit);
        if (out.stats.boxes >= req.max_boxes) {
            // Out of budget: every contact is in a remaining box, so none happens before the earliest of them.
            out.stats.capped = true;
            out.colliding = true;
            out.toi = earliest(current.box);
            out.toi_upper = t_limit;
            out.u = 0.5 * (current.box.lo[1] + current.box.hi[1]);
            out.v = 0.5 * (current.box.lo[2] + current.box.hi[2]);
            return;
        }
    }
}

/// True when the request's settings are usable (finite, non-negative, t_max in [0, 1], a positive tolerance).
[[nodiscard]] inline bool ccd_request_is_valid(const CcdRequest& r) noexcept {
    return std::isfinite(r.min_separation) && r.min_separation >= 0 && std::isfinite(r.tolerance) &&
           r.tolerance > 0 && std::isfinite(r.time_tolerance) && r.time_tolerance > 0 && r.t_max >= 0 &&
           r.t_max <= 1 && r.max_boxes > 0;
}

}  // namespace cdkit::detail
