#pragma once
/// \file Helpers shared by the bounding-volume fits: a conservative padding and the range of triangles.

#include "cdkit/core/mesh.hpp"

#include <cmath>
#include <limits>
#include <span>

namespace cdkit {

/// The triangles a node covers: indices into mesh.triangles.
using TriangleRange = std::span<const Index>;

namespace detail {
/// Padding added to every fitted extent: a few ulps of the largest coordinate magnitude involved, so that a
/// point computed by transforming a vertex (R·v + t, rounded) cannot fall outside the box its exact
/// position lies in. This keeps BV culling conservative: a BVH query never misses a pair that brute force
/// over the same transformed points finds.
template <class S> [[nodiscard]] inline S fit_padding(S magnitude) noexcept {
    return S(16) * std::numeric_limits<S>::epsilon() * (magnitude + std::numeric_limits<S>::min());
}
}  // namespace detail

}  // namespace cdkit
