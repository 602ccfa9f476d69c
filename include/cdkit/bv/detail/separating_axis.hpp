#pragma once
/// \file The 15-axis separating-axis test for two boxes (Gottschalk, Lin, Manocha, "OBBTree: a hierarchical
/// structure for rapid interference detection", SIGGRAPH 1996).

#include "cdkit/core/math.hpp"

namespace cdkit::detail {

/// True when boxes A (axis-aligned in its own frame, half extents `a`) and B (half extents `b`, axes the
/// columns of `Rb`, centre `T`, both given in A's frame) are disjoint. `absRb` is |Rb| plus a small slack
/// so that near-parallel edge pairs (cross product ≈ 0) cannot produce a false "disjoint": the test errs
/// only towards "overlap", which is safe for culling. `slack` widens every projected radius: it absorbs the
/// rounding of T when the translation is large against the boxes (see translation_slack).
template <class S>
[[nodiscard]] inline bool boxes_disjoint(Vec3<S> a, const Vec3<S>& b, const Mat3<S>& Rb,
                                         const Mat3<S>& absRb, const Vec3<S>& T, S slack) noexcept {
    a = a + Vec3<S>::Constant(slack);
    // A's face axes.
    for (int i = 0; i < 3; ++i)
        if (std::abs(T[i]) > a[i] + absRb.row(i).dot(b)) return true;
    // B's face axes.
    for (int j = 0; j < 3; ++j)
        if (std::abs(Rb.col(j).dot(T)) > b[j] + absRb.col(j).dot(a)) return true;
    // Cross axes A_i × B_j.
    S ra, rb, t;
    ra = a[1] * absRb(2, 0) + a[2] * absRb(1, 0); rb = b[1] * absRb(0, 2) + b[2] * absRb(0, 1);
    t = T[2] * Rb(1, 0) - T[1] * Rb(2, 0); if (std::abs(t) > ra + rb) return true;
    ra = a[1] * absRb(2, 1) + a[2] * absRb(1, 1); rb = b[0] * absRb(0, 2) + b[2] * absRb(0, 0);
    t = T[2] * Rb(1, 1) - T[1] * Rb(2, 1); if (std::abs(t) > ra + rb) return true;
    ra = a[1] * absRb(2, 2) + a[2] * absRb(1, 2); rb = b[0] * absRb(0, 1) + b[1] * absRb(0, 0);
    t = T[2] * Rb(1, 2) - T[1] * Rb(2, 2); if (std::abs(t) > ra + rb) return true;
    ra = a[0] * absRb(2, 0) + a[2] * absRb(0, 0); rb = b[1] * absRb(1, 2) + b[2] * absRb(1, 1);
    t = T[0] * Rb(2, 0) - T[2] * Rb(0, 0); if (std::abs(t) > ra + rb) return true;
    ra = a[0] * absRb(2, 1) + a[2] * absRb(0, 1); rb = b[0] * absRb(1, 2) + b[2] * absRb(1, 0);
    t = T[0] * Rb(2, 1) - T[2] * Rb(0, 1); if (std::abs(t) > ra + rb) return true;
    ra = a[0] * absRb(2, 2) + a[2] * absRb(0, 2); rb = b[0] * absRb(1, 1) + b[1] * absRb(1, 0);
    t = T[0] * Rb(2, 2) - T[2] * Rb(0, 2); if (std::abs(t) > ra + rb) return true;
    ra = a[0] * absRb(1, 0) + a[1] * absRb(0, 0); rb = b[1] * absRb(2, 2) + b[2] * absRb(2, 1);
    t = T[1] * Rb(0, 0) - T[0] * Rb(1, 0); if (std::abs(t) > ra + rb) return true;
    ra = a[0] * absRb(1, 1) + a[1] * absRb(0, 1); rb = b[0] * absRb(2, 2) + b[2] * absRb(2, 0);
    t = T[1] * Rb(0, 1) - T[0] * Rb(1, 1); if (std::abs(t) > ra + rb) return true;
    ra = a[0] * absRb(1, 2) + a[1] * absRb(0, 2); rb = b[0] * absRb(2, 1) + b[1] * absRb(2, 0);
    t = T[1] * Rb(0, 2) - T[0] * Rb(1, 2); if (std::abs(t) > ra + rb) return true;
    return false;
}

/// |R| with the slack used by boxes_disjoint.
template <class S> [[nodiscard]] inline Mat3<S> abs_with_slack(const Mat3<S>& R) noexcept {
    return R.cwiseAbs().array() + S(64) * std::numeric_limits<S>::epsilon();
}

/// Rounding of R·c + t − c' grows with |t|; the fit padding covers the |c| parts, this covers |t|.
template <class S> [[nodiscard]] inline S translation_slack(const Vec3<S>& t) noexcept {
    return S(32) * std::numeric_limits<S>::epsilon() * t.cwiseAbs().maxCoeff();
}

}  // namespace cdkit::detail
