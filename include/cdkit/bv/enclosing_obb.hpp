#pragma once
/// \file The oriented box around each bounding volume (`enclosing_obb`): the common form in which volumes of
/// different kinds meet in distance() (mixed trees, bvh/mixed_descent.hpp). The box contains the volume, so a box
/// test never drops a pair the volume's own test would keep. (collide() takes them as rounded boxes instead:
/// bv/rounded_box.hpp.)

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/rss.hpp"
#include "cdkit/bv/sphere.hpp"

#include <concepts>
#include <limits>

namespace cdkit {

namespace detail {
/// Half extents grown by a few ulps: a sum such as an Rss's half length plus its radius may round down, and the
/// box must contain the volume.
template <class S> [[nodiscard]] inline Vec3<S> grown_half(const Vec3<S>& h) noexcept {
    return h * (S(1) + S(4) * std::numeric_limits<S>::epsilon());
}
}  // namespace detail

/// The oriented box around a bounding volume, in the volume's frame. Empty volumes give empty boxes. A box is its
/// own (no copy).
template <class S>
[[nodiscard]] inline const Obb<S>& enclosing_obb(const Obb<S>& b) noexcept {
    return b;
}

template <class S>
[[nodiscard]] inline Obb<S> enclosing_obb(const Aabb<S>& b) noexcept {
    Obb<S> o;
    o.center = b.center;
    o.half = b.half;
    return o;
}

/// A rectangle swept by a ball: the rectangle's frame, its half lengths plus the radius, the radius across.
template <class S>
[[nodiscard]] inline Obb<S> enclosing_obb(const Rss<S>& b) noexcept {
    Obb<S> o;
    if (b.is_empty()) return o;
    o.axes = b.axes;
    o.center = b.center;
    o.half = detail::grown_half(Vec3<S>(b.half[0] + b.radius, b.half[1] + b.radius, b.radius));
    return o;
}

template <class S>
[[nodiscard]] inline Obb<S> enclosing_obb(const BoundingSphere<S>& b) noexcept {
    Obb<S> o;
    if (b.is_empty()) return o;
    o.center = b.center;
    o.half = Vec3<S>::Constant(b.radius);
    return o;
}

/// A k-DOP's first three slabs are the coordinate axes' (kdop_directions): their box.
template <class S, int K>
[[nodiscard]] inline Obb<S> enclosing_obb(const Kdop<S, K>& b) noexcept {
    Obb<S> o;
    if (b.is_empty()) return o;
    const Vec3<S> lo(b.lo(0), b.lo(1), b.lo(2)), hi(b.hi(0), b.hi(1), b.hi(2));
    o.center = (lo + hi) * S(0.5);
    o.half = detail::grown_half(Vec3<S>((hi - lo) * S(0.5)));
    return o;
}

/// Volumes that enclosing_obb() turns into a box.
template <class BV>
concept HasEnclosingObb = requires(const BV& b) {
    { enclosing_obb(b) } -> std::convertible_to<Obb<typename BV::Scalar>>;
};

}  // namespace cdkit
