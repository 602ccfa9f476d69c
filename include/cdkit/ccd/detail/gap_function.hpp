#pragma once
/// \file The gap function of a primitive CCD query, F(t, u, v) = B(t) + u·E1(t) + v·E2(t), a domain box over
/// (t, u, v), and the rounding bound that every enclosure of F's values uses.

#include <array>
#include <cmath>
#include <limits>

namespace cdkit::detail {

/// F's three terms at t = 0 and t = 1; each is a difference of two input points.
struct GapFunction {
    std::array<double, 3> b0, b1, e10, e11, e20, e21;
    bool triangle_domain = false;    ///< vertex–face: only u + v ≤ 1 is part of the domain
    std::array<double, 3> error{};   ///< per axis: |computed corner value − exact value| ≤ error
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

struct InclusionBox {
    double lo[3], hi[3];  ///< t, u, v
    int depth = 0;        ///< splits from the root
};

}  // namespace cdkit::detail
