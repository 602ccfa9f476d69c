#pragma once
/// \file Every bounding volume as a rounded box: a box (its core, an Obb) grown by a ball (its radius), i.e. their
/// Minkowski sum. Boxes are their own core with radius 0; an Rss is its rectangle (a flat box) grown by its radius;
/// a sphere its centre (a box of no extent) grown by its radius; an Aabb or a k-DOP the box of its extents. This is
/// the form in which the two-lane sibling test (bv/detail/obb_sibling_test.hpp) takes two children and another node
/// of any two volumes: exactly the volume for boxes, Rss and spheres, the enclosing box for k-DOPs.

#include "cdkit/bv/enclosing_obb.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/rss.hpp"
#include "cdkit/bv/sphere.hpp"

namespace cdkit {

/// The core box of a volume (see the file comment): by default its enclosing box (Aabb, k-DOP, any volume with an
/// enclosing_obb()); a box is returned as it is, no copy.
template <class BV>
    requires HasEnclosingObb<BV>
[[nodiscard]] inline Obb<typename BV::Scalar> core_box(const BV& b) noexcept { return enclosing_obb(b); }
template <class S>
[[nodiscard]] inline const Obb<S>& core_box(const Obb<S>& b) noexcept { return b; }
/// An Rss's rectangle as a flat box (half extent 0 along its normal).
template <class S>
[[nodiscard]] inline Obb<S> core_box(const Rss<S>& b) noexcept {
    Obb<S> o;
    o.axes = b.axes;
    o.center = b.center;
    o.half = Vec3<S>(b.half[0], b.half[1], S(0));
    return o;
}
/// A sphere's centre as a box of no extent.
template <class S>
[[nodiscard]] inline Obb<S> core_box(const BoundingSphere<S>& b) noexcept {
    Obb<S> o;
    o.center = b.center;
    o.half = Vec3<S>::Zero();
    return o;
}

/// The radius of the ball that grows the core box into the volume (0 for the box-shaped volumes).
template <class BV>
[[nodiscard]] inline typename BV::Scalar core_radius(const BV&) noexcept { return 0; }
template <class S>
[[nodiscard]] inline S core_radius(const Rss<S>& b) noexcept { return b.radius; }
template <class S>
[[nodiscard]] inline S core_radius(const BoundingSphere<S>& b) noexcept { return b.radius; }

namespace detail {
/// Whether a volume's rounded box has a ball (a radius that may be positive): the sibling test then pays for it.
template <class BV> inline constexpr bool has_core_radius = false;
template <class S> inline constexpr bool has_core_radius<Rss<S>> = true;
template <class S> inline constexpr bool has_core_radius<BoundingSphere<S>> = true;
}  // namespace detail

}  // namespace cdkit
