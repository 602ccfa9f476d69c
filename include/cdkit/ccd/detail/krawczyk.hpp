#pragma once
/// \file Proof that the gap function has a zero in a box, and a smaller box that holds it: the Krawczyk
/// operator (R. Krawczyk, "Newton-Algorithmen zur Bestimmung von Nullstellen mit Fehlerschranken", Computing 4,
/// 1969; R. E. Moore, "A test for existence of solutions to nonlinear systems", SIAM J. Numer. Anal. 14, 1977).
/// For a box X with midpoint m, a point matrix Y ≈ J(m)⁻¹ and an enclosure J(X) of the Jacobian over X,
///     K(X) = m − Y·F(m) + (I − Y·J(X))·(X − m).
/// If K(X) lies in the interior of X, F has exactly one zero in X, and it lies in K(X). Every quantity is
/// enclosed with the same per-axis rounding bounds as the corner values (inclusion_search.hpp), so the proof
/// holds for the exact input coordinates. Near a transversal contact this contracts quadratically, where
/// bisection gains one bit per split; where J is singular (parallel edges, coplanar motion, a contact on the
/// domain's boundary) it fails and the search bisects as before.

#include "cdkit/ccd/detail/gap_function.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <limits>

namespace cdkit::detail {

/// K(X) ∩ X when K(X) ⊂ interior(X) (a zero of F exists in it, and it is X's only one); otherwise false.
[[nodiscard]] inline bool krawczyk_contract(const GapFunction& g, const InclusionBox& x, InclusionBox& out) noexcept {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    double m[3], r[3];
    for (int i = 0; i < 3; ++i) {
        m[i] = 0.5 * (x.lo[i] + x.hi[i]);
        r[i] = std::max(x.hi[i] - m[i], m[i] - x.lo[i]) * (1 + 2 * eps);
        if (!(r[i] > 0)) return false;
    }
    // F(m) and the Jacobian's enclosure (columns ∂/∂t, ∂/∂u, ∂/∂v), each entry as centre ± radius.
    double fm[3];
    Eigen::Matrix3d jc, jr;
    for (int k = 0; k < 3; ++k) {
        const double db = g.b1[k] - g.b0[k], de1 = g.e11[k] - g.e10[k], de2 = g.e21[k] - g.e20[k];
        const double e1m = g.e10[k] + m[0] * de1, e2m = g.e20[k] + m[0] * de2;
        fm[k] = (g.b0[k] + m[0] * db) + m[1] * e1m + m[2] * e2m;
        // ∂F/∂t = db + u·de1 + v·de2 over u, v in the box: linear, so its range is spanned by the corners.
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (double u : {x.lo[1], x.hi[1]})
            for (double v : {x.lo[2], x.hi[2]}) {
                const double d = db + u * de1 + v * de2;
                lo = std::min(lo, d), hi = std::max(hi, d);
            }
        // ∂F/∂u = E1(t), ∂F/∂v = E2(t): linear in t.
        const double u0 = g.e10[k] + x.lo[0] * de1, u1 = g.e10[k] + x.hi[0] * de1;
        const double v0 = g.e20[k] + x.lo[0] * de2, v1 = g.e20[k] + x.hi[0] * de2;
        // Rounding: each entry is a few operations on differences of inputs; twice the corner values' bound.
        const double je = 2 * g.error[k];
        jc(k, 0) = 0.5 * (lo + hi), jr(k, 0) = 0.5 * (hi - lo) + je;
        jc(k, 1) = 0.5 * (u0 + u1), jr(k, 1) = 0.5 * std::abs(u1 - u0) + je;
        jc(k, 2) = 0.5 * (v0 + v1), jr(k, 2) = 0.5 * std::abs(v1 - v0) + je;
    }
    bool invertible = false;
    double det = 0;
    Eigen::Matrix3d y;
    jc.computeInverseAndDetWithCheck(y, det, invertible, 0.0);
    if (!invertible || !y.allFinite()) return false;
    const Eigen::Matrix3d ya = y.cwiseAbs();
    // I − Y·J(X) = (I − Y·Jc) ± (|Y|·Jr + rounding of Y·Jc).
    const Eigen::Matrix3d yj = y * jc;
    const Eigen::Matrix3d mc = Eigen::Matrix3d::Identity() - yj;
    const Eigen::Matrix3d mr = (ya * jr + 4 * eps * (ya * jc.cwiseAbs() + Eigen::Matrix3d::Identity())) * (1 + 8 * eps);
    for (int i = 0; i < 3; ++i) {
        double c = 0, c_abs = 0, c_err = 0, rho = 0;
        for (int k = 0; k < 3; ++k) {
            c += y(i, k) * fm[k];
            c_abs += ya(i, k) * std::abs(fm[k]);
            c_err += ya(i, k) * g.error[k];
            rho += (std::abs(mc(i, k)) + mr(i, k)) * r[k];
        }
        const double centre = m[i] - c;
        const double radius = (c_err + 4 * eps * c_abs + rho + 2 * eps * std::abs(centre)) * (1 + 8 * eps) +
                              std::numeric_limits<double>::denorm_min();
        const double lo = centre - radius, hi = centre + radius;
        if (!(lo > x.lo[i] && hi < x.hi[i])) return false;
        out.lo[i] = lo;
        out.hi[i] = hi;
    }
    out.depth = x.depth + 1;
    out.new_time = true;
    return true;
}

}  // namespace cdkit::detail
