#pragma once
/// \file Vertex–face continuous collision: a vertex and a triangle, all four points moving linearly over t ∈ [0, 1].
/// The method (conservative inclusion with separating directions, after Wang et al. 2021) is described in
/// ccd/detail/inclusion_search.hpp and docs/ccd.md.

#include "cdkit/ccd/detail/primitive_setup.hpp"

namespace cdkit {

/// First contact of vertex p with triangle (a, b, c) while each point moves linearly from its position at t = 0
/// (`*_t0`) to the one at t = 1 (`*_t1`). Never misses a contact (floating-point error included in every
/// exclusion); may report one where the vertex passes within about `request.tolerance` of the triangle.
/// Non-finite coordinates or settings give status invalid_input. Thread-safe; allocates only when the first box
/// must be split.
[[nodiscard]] inline CcdResult vertex_face_ccd(const Vec3<double>& p_t0, const Vec3<double>& a_t0,
                                              const Vec3<double>& b_t0, const Vec3<double>& c_t0,
                                              const Vec3<double>& p_t1, const Vec3<double>& a_t1,
                                              const Vec3<double>& b_t1, const Vec3<double>& c_t1,
                                              const CcdRequest& request = {}) {
    // F = (p − a) + u·(a − b) + v·(a − c) = p − (a + u(b − a) + v(c − a)); the contact point is on the face.
    return detail::primitive_ccd({&p_t0, &a_t0, &b_t0, &c_t0, &p_t1, &a_t1, &b_t1, &c_t1}, {0, 1}, {1, 2}, {1, 3}, true,
                                 {1, 2, 3}, request);
}

}  // namespace cdkit
