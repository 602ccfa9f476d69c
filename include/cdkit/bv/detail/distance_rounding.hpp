#pragma once
/// \file The rounding margin of the BV distance lower bounds (bv_distance.hpp, rss.hpp): a gap computed in
/// floating point is lowered by a few ulps of the magnitudes involved, so that it stays below the distance
/// triangle_distance() computes for any triangle pair inside the two volumes.

#include "cdkit/core/math.hpp"

#include <algorithm>
#include <limits>

namespace cdkit::detail {

/// `gap` lowered for the rounding of T (the centres' offset), the extents a and b and the division by an
/// axis length: a relative 16 ulps of the gap and 64 ulps of |T| + Σa + Σb. 0 when gap ≤ 0.
template <class S> [[nodiscard]] inline S lowered(S gap, const Vec3<S>& a, const Vec3<S>& b, const Vec3<S>& T) noexcept {
    if (gap <= S(0)) return S(0);
    const S mag = T.cwiseAbs().maxCoeff() + a.sum() + b.sum();
    return std::max(S(0), gap * (S(1) - S(16) * std::numeric_limits<S>::epsilon()) -
                              S(64) * std::numeric_limits<S>::epsilon() * mag);
}

}  // namespace cdkit::detail
