#pragma once
/// \file The gap function of a primitive CCD query, F(t, u, v) = B(t) + u·E1(t) + v·E2(t), a domain box over
/// (t, u, v), and the rounding bound that every enclosure of F's values uses.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace cdkit::detail {

/// F's three terms at t = 0 and t = 1; each is a difference of two input points.
struct GapFunction {
    std::array<double, 3> b0, b1, e10, e11, e20, e21;
    bool triangle_domain = false;    ///< vertex–face: only u + v ≤ 1 is part of the domain
    std::array<double, 3> error{};   ///< per axis: |computed corner value − exact value| ≤ error
    /// Bound on |computed − exact| of det(B(r), E1(s), E2(t)) for any r, s, t of the domain and of the average of
    /// three such determinants (coplanarity_error_bound).
    double coplanarity_error = 0;
};

/// Per-axis bound on the rounding error of one corner value of F, from M = the largest |coordinate| of the
/// eight input points on that axis. Each of B, E1, E2 at t = 0 or 1 is a difference of two inputs (|·| ≤ 2M,
/// one rounding); the lerp X0 + t·(X1 − X0) adds ≤ 14u·M (u = 2⁻⁵³: the difference ≤ 4M rounded twice, the
/// product and the sum once each); u·E1 and v·E2 one rounding more; the two sums ≤ 4M and 6M. Summed: ≤ 62u·M
/// to first order; we take 128u·M = 64ε·M, and an absolute term for products that underflow.
[[nodiscard]] inline double gap_error_bound(double max_abs_coordinate) noexcept {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    return 64 * eps * max_abs_coordinate + 16 * std::numeric_limits<double>::min();
}

/// The bound GapFunction::coplanarity_error, from the terms and their per-axis error: each component of a computed
/// B(r), E1(s), E2(t) is within e = max error of the exact one and within X = max |term| + e of zero. The six
/// products of a 3×3 determinant then move by ≤ e·(Y·Z + X·Z + X·Y) each under those errors, and evaluating it
/// (a dot product with a cross product) rounds by ≤ 6u per product; averaging three adds a few u more. Taken:
/// 6e·(YZ + XZ + XY) + 384ε·XYZ, widened by 1e-6 relative and an absolute term for underflowing products.
[[nodiscard]] inline double coplanarity_error_bound(const GapFunction& g) noexcept {
    double e = 0, x = 0, y = 0, z = 0;
    for (int k = 0; k < 3; ++k) {
        e = std::max(e, g.error[k]);
        x = std::max({x, std::abs(g.b0[k]), std::abs(g.b1[k])});
        y = std::max({y, std::abs(g.e10[k]), std::abs(g.e11[k])});
        z = std::max({z, std::abs(g.e20[k]), std::abs(g.e21[k])});
    }
    x += e, y += e, z += e;
    constexpr double eps = std::numeric_limits<double>::epsilon();
    return (6 * e * (y * z + x * z + x * y) + 384 * eps * x * y * z) * (1 + 1e-6) +
           64 * std::numeric_limits<double>::denorm_min();
}

struct InclusionBox {
    double lo[3], hi[3];  ///< t, u, v
    int depth = 0;        ///< splits from the root
    /// Its t interval is not its parent's (the root, a split in t, a Newton contraction): only then can a test of
    /// the time interval alone decide anything its parent's did not.
    bool new_time = true;
};

}  // namespace cdkit::detail
