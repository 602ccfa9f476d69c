#pragma once
/// \file A BV's world-space box under a pose, for every BV of the tree family: what a tree node covers while its
/// mesh moves from one pose to another (the box of the node's BV at both poses: with every vertex moving on the
/// segment between its two posed positions, the node's triangles stay in the hull of the two posed BVs).

#include "cdkit/broadphase/box.hpp"
#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/rss.hpp"
#include "cdkit/bv/sphere.hpp"

#include <cmath>
#include <limits>

namespace cdkit::detail {

/// The box centre ± extent mapped by `pose` (R·c + t ± |R|·e), grown by the rounding of that map and of the
/// posed vertices R·v + t that the primitive tests then see.
inline BroadBox<double> posed_box(const Vec3<double>& centre, const Vec3<double>& extent,
                                  const Transform<double>& pose) noexcept {
    const Vec3<double> c = pose.R * centre + pose.t;
    const Vec3<double> e = pose.R.cwiseAbs() * extent;
    const Vec3<double> slack = 16 * std::numeric_limits<double>::epsilon() *
                               (pose.t.cwiseAbs() + pose.R.cwiseAbs() * centre.cwiseAbs() + e);
    return {c - e - slack, c + e + slack};
}

template <class S> [[nodiscard]] BroadBox<double> world_box(const Aabb<S>& b, const Transform<double>& pose) noexcept {
    return posed_box(b.center.template cast<double>(), b.half.template cast<double>(), pose);
}
template <class S> [[nodiscard]] BroadBox<double> world_box(const Obb<S>& b, const Transform<double>& pose) noexcept {
    const Transform<double> frame(b.axes.template cast<double>(), b.center.template cast<double>());
    return posed_box(Vec3<double>::Zero(), b.half.template cast<double>(), pose * frame);
}
template <class S> [[nodiscard]] BroadBox<double> world_box(const Rss<S>& b, const Transform<double>& pose) noexcept {
    const Transform<double> frame(b.axes.template cast<double>(), b.center.template cast<double>());
    const Vec3<double> rect(double(b.half[0]), double(b.half[1]), 0.0);
    BroadBox<double> box = posed_box(Vec3<double>::Zero(), rect, pose * frame);
    const double r = double(b.radius) * (1 + 4 * std::numeric_limits<double>::epsilon());
    box.lo.array() -= r;
    box.hi.array() += r;
    return box;
}
template <class S>
[[nodiscard]] BroadBox<double> world_box(const BoundingSphere<S>& b, const Transform<double>& pose) noexcept {
    return posed_box(b.center.template cast<double>(), Vec3<double>::Constant(double(b.radius)), pose);
}
template <class S, int K>
[[nodiscard]] BroadBox<double> world_box(const Kdop<S, K>& b, const Transform<double>& pose) noexcept {
    // Slabs 0–2 are the coordinate axes: the K-DOP lies in their box.
    static_assert(Kdop<S, K>::directions[0] == std::array<int, 3>{1, 0, 0} &&
                      Kdop<S, K>::directions[1] == std::array<int, 3>{0, 1, 0} &&
                      Kdop<S, K>::directions[2] == std::array<int, 3>{0, 0, 1},
                  "a K-DOP's first three slabs are expected along x, y, z");
    constexpr int N = Kdop<S, K>::N;
    Vec3<double> lo, hi;
    for (int k = 0; k < 3; ++k) lo[k] = -double(b.h[N + k]), hi[k] = double(b.h[k]);
    return posed_box((lo + hi) * 0.5, (hi - lo) * 0.5, pose);
}

/// The node's box over the whole motion from `start` to `end`.
template <class BV>
[[nodiscard]] BroadBox<double> swept_world_box(const BV& bv, const Transform<double>& start,
                                               const Transform<double>& end) noexcept {
    BroadBox<double> a = world_box(bv, start);
    const BroadBox<double> b = world_box(bv, end);
    a.lo = a.lo.cwiseMin(b.lo);
    a.hi = a.hi.cwiseMax(b.hi);
    return a;
}

}  // namespace cdkit::detail
