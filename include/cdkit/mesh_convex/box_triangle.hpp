#pragma once
/// \file Box against triangle by separating axes: Akenine-Möller, "Fast 3D triangle-box overlap testing", JGT 6(1),
/// 2001. Two convex polytopes are disjoint exactly when one of their face normals or one cross product of an edge
/// of each separates their projections; for a box and a triangle that is 13 axes (the box's 3 face normals, the
/// triangle's normal, the 9 edge cross products). In floating point an axis counts as separating only when the gap
/// along it exceeds `slack` times the axis' length (the bound's rounding and touching padding, which also covers
/// the rounding of the projections: a few ε times |axis|·|coordinates|), so "disjoint" is certain and a pair within
/// the slack is touching — the touching rule every mesh–convex query uses (shape_bound.hpp). No iteration, no
/// tolerance loop: about a hundred flops, where GJK on a box and a triangle takes several iterations.

#include "cdkit/core/math.hpp"

#include <algorithm>
#include <cmath>

namespace cdkit {
namespace detail {

/// Do the box (half extents `h`, centred at the origin of its frame) and the triangle (v0, v1, v2, in the box's
/// frame) touch or overlap? A gap of at most slack·|axis| on every axis counts as touching.
template <class S>
[[nodiscard]] inline bool box_triangle_touch(const Vec3<S>& h, const Vec3<S>& v0, const Vec3<S>& v1, const Vec3<S>& v2,
                                             S slack) noexcept {
    // The box's face normals: the triangle's box against the box.
    for (int i = 0; i < 3; ++i) {
        const S lo = std::min({v0[i], v1[i], v2[i]}), hi = std::max({v0[i], v1[i], v2[i]});
        if (lo > h[i] + slack || hi < -h[i] - slack) return false;
    }
    const Vec3<S> e[3] = {v1 - v0, v2 - v1, v0 - v2};
    auto separates = [&](const Vec3<S>& a) {
        const S p0 = a.dot(v0), p1 = a.dot(v1), p2 = a.dot(v2);
        const S r = h[0] * std::abs(a[0]) + h[1] * std::abs(a[1]) + h[2] * std::abs(a[2]);
        const S pad = slack * (std::abs(a[0]) + std::abs(a[1]) + std::abs(a[2]));  // ≥ slack·|a|
        return std::min({p0, p1, p2}) > r + pad || std::max({p0, p1, p2}) < -r - pad;
    };
    // The triangle's normal.
    if (separates(e[0].cross(e[1]))) return false;
    // Edge × box axis: e × x̂ = (0, e_z, −e_y), and so on.
    for (const Vec3<S>& f : e) {
        if (separates(Vec3<S>(S(0), f.z(), -f.y())) || separates(Vec3<S>(-f.z(), S(0), f.x())) ||
            separates(Vec3<S>(f.y(), -f.x(), S(0))))
            return false;
    }
    return true;
}

}  // namespace detail
}  // namespace cdkit
