#pragma once
/// \file Edge–edge continuous collision: two segments, all four end points moving linearly over t ∈ [0, 1].
/// The method (conservative inclusion with separating directions, after Wang et al. 2021) is described in
/// ccd/detail/inclusion_search.hpp and docs/ccd.md.

#include "cdkit/ccd/detail/primitive_setup.hpp"

namespace cdkit {

/// First contact of edge A (a0, a1) with edge B (b0, b1) while each end point moves linearly from its position at
/// t = 0 (`*_t0`) to the one at t = 1 (`*_t1`). Never misses a contact (floating-point error included in every
/// exclusion); may report one where the edges pass within about `request.tolerance`. Non-finite coordinates or
/// settings give status invalid_input. Thread-safe; allocates only when the first box must be split.
[[nodiscard]] inline CcdResult edge_edge_ccd(const Vec3<double>& a0_t0, const Vec3<double>& a1_t0,
                                            const Vec3<double>& b0_t0, const Vec3<double>& b1_t0,
                                            const Vec3<double>& a0_t1, const Vec3<double>& a1_t1,
                                            const Vec3<double>& b0_t1, const Vec3<double>& b1_t1,
                                            const CcdRequest& request = {}) {
    // F = (a0 − b0) + u·(a1 − a0) + v·(b0 − b1) = (a0 + u(a1 − a0)) − (b0 + v(b1 − b0)); the point is on edge A.
    return detail::primitive_ccd({&a0_t0, &a1_t0, &b0_t0, &b1_t0, &a0_t1, &a1_t1, &b0_t1, &b1_t1}, {0, 2}, {1, 0},
                                 {2, 3}, false, {0, 1, -1}, request);
}

}  // namespace cdkit
