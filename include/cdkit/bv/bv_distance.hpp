#pragma once
/// \file Lower bounds on the Euclidean distance between two bounding volumes of one kind (Aabb, Obb, BoundingSphere,
/// Kdop; Rss has its own in rss.hpp) under the per-query relative transform, for branch-and-bound distance queries.
///
/// For any unit direction n, the gap between the boxes' projections onto n is at most their distance
/// (the projection onto a line is 1-Lipschitz). The 15 axes of the box–box separating-axis test
/// (Gottschalk, Lin, Manocha, "OBBTree", SIGGRAPH 1996) are natural candidates: the bound is the largest
/// projection gap over them, each divided by its axis' length (the cross axes A_i × B_j are not unit).
/// The circumscribed spheres' gap is a second candidate. Two bounding spheres: their gap. Two k-DOPs: the largest gap
/// along one of A's K/2 slab directions between A's slab and the slab of A's frame that encloses B's DOP (the
/// re-alignment of the overlap test, kdop.hpp), divided by the direction's length. Rounding: the projected radii are widened as in
/// detail::boxes_disjoint, and the result is lowered by a few ulps of the coordinates' magnitude, so the
/// bound stays below the distance that triangle_distance computes for any triangle pair inside the boxes.

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/detail/distance_rounding.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/rss.hpp"
#include "cdkit/bv/sphere.hpp"

#include <algorithm>
#include <cmath>

namespace cdkit {

namespace detail {

/// The circumscribed spheres' gap |T| − |a| − |b| (lowered for rounding): the cheap first candidate.
template <class S> [[nodiscard]] inline S sphere_gap_lower_bound(Vec3<S> a, const Vec3<S>& b, const Vec3<S>& T, S slack) noexcept {
    a = a + Vec3<S>::Constant(slack);
    return lowered(T.norm() - a.norm() - b.norm(), a, b, T);
}

/// Largest separating-axis gap of box A (axis-aligned in its frame, half extents a) and box B (half
/// extents b, axes the columns of Rb, centre T, in A's frame), as a lower bound on their distance.
/// `absRb` is |Rb| with slack (abs_with_slack); `slack` widens the radii (translation_slack).
template <class S>
[[nodiscard]] inline S box_gap_lower_bound(Vec3<S> a, const Vec3<S>& b, const Mat3<S>& Rb, const Mat3<S>& absRb,
                                           const Vec3<S>& T, S slack) noexcept {
    a = a + Vec3<S>::Constant(slack);
    S gap = 0;
    for (int i = 0; i < 3; ++i) gap = std::max(gap, std::abs(T[i]) - (a[i] + absRb.row(i).dot(b)));
    for (int j = 0; j < 3; ++j) gap = std::max(gap, std::abs(Rb.col(j).dot(T)) - (b[j] + absRb.col(j).dot(a)));
    // Cross axes L = A_i × B_j. Its length² is the sum of the squares of B_j's two other components in A's
    // frame, computed without the cancellation of 1 − Rb(i,j)². Near-parallel pairs (|L| tiny) are skipped:
    // their gap is close to a face axis' gap anyway, and dividing by a tiny rounded |L| could overshoot.
    const S min_len2 = std::is_same_v<S, float> ? S(1e-4) : S(1e-8);
    for (int i = 0; i < 3; ++i) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        for (int j = 0; j < 3; ++j) {
            const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            const S len2 = Rb(i1, j) * Rb(i1, j) + Rb(i2, j) * Rb(i2, j);
            if (len2 < min_len2) continue;
            const S ra = a[i1] * absRb(i2, j) + a[i2] * absRb(i1, j);
            const S rb = b[j1] * absRb(i, j2) + b[j2] * absRb(i, j1);
            const S t = T[i2] * Rb(i1, j) - T[i1] * Rb(i2, j);
            const S g = std::abs(t) - (ra + rb);
            // g / |L| > gap  ⇔  g² > gap²·|L|² (g > 0): the square root only for a new maximum.
            if (g > S(0) && g * g > gap * gap * len2) gap = g / std::sqrt(len2);
        }
    }
    return lowered(gap, a, b, T);
}

}  // namespace detail

/// A lower bound on the distance between box `a` (in A's frame) and box `b` (in B's frame), `rel` taking
/// B's frame to A's. 0 when the boxes may overlap. Never exceeds the true distance (up to rounding that it
/// compensates for; see the file comment).
/// `cutoff`: the caller prunes every pair whose bound reaches it, so once the cheap sphere bound does, it is
/// returned without the 15-axis pass (still a valid lower bound, possibly smaller than the full one).
template <class S>
[[nodiscard]] inline S distance_lower_bound(const Aabb<S>& a, const Aabb<S>& b, const typename Aabb<S>::Relative& rel,
                                            S cutoff = std::numeric_limits<S>::infinity()) noexcept {
    const Vec3<S> T = rel.R * b.center + rel.t - a.center;
    const S sphere = detail::sphere_gap_lower_bound(a.half, b.half, T, rel.slack);
    if (sphere >= cutoff) return sphere;
    return std::max(sphere, detail::box_gap_lower_bound(a.half, b.half, rel.R, rel.absR, T, rel.slack));
}

/// Obb version of distance_lower_bound (same contract).
template <class S>
[[nodiscard]] inline S distance_lower_bound(const Obb<S>& a, const Obb<S>& b, const typename Obb<S>::Relative& rel,
                                            S cutoff = std::numeric_limits<S>::infinity()) noexcept {
    // The centre distance does not depend on the frame: the sphere test needs no rotation into a's axes.
    const Vec3<S> d = rel.R * b.center + rel.t - a.center;
    const S sphere = detail::sphere_gap_lower_bound(a.half, b.half, d, rel.slack);
    if (sphere >= cutoff) return sphere;
    const Mat3<S> at = a.axes.transpose();
    const Mat3<S> Rb = at * (rel.R * b.axes);
    const Vec3<S> T = at * d;
    return std::max(sphere, detail::box_gap_lower_bound(a.half, b.half, Rb, detail::abs_with_slack(Rb), T, rel.slack));
}

/// BoundingSphere version of distance_lower_bound (same contract): the gap of the two balls.
template <class S>
[[nodiscard]] inline S distance_lower_bound(const BoundingSphere<S>& a, const BoundingSphere<S>& b,
                                            const typename BoundingSphere<S>::Relative& rel,
                                            [[maybe_unused]] S cutoff = std::numeric_limits<S>::infinity()) noexcept {
    const Vec3<S> T = rel.R * b.center + rel.t - a.center;
    const S gap = T.norm() - a.radius - b.radius - rel.t_slack;
    return detail::lowered(gap, Vec3<S>(a.center.cwiseAbs() + Vec3<S>::Constant(a.radius)),
                           Vec3<S>(b.center.cwiseAbs() + Vec3<S>::Constant(b.radius)), T);
}

/// Kdop version of distance_lower_bound (same contract): B's DOP enclosed in the slabs of A's frame as by overlap()
/// (kdop.hpp), and the largest gap between those slabs and A's along one direction, over its length.
template <class S, int K>
[[nodiscard]] inline S distance_lower_bound(const Kdop<S, K>& a, const Kdop<S, K>& b, const typename Kdop<S, K>::Relative& rel,
                                            [[maybe_unused]] S cutoff = std::numeric_limits<S>::infinity()) noexcept {
    constexpr int N = K / 2;
    constexpr int C = Kdop<S, K>::Relative::C;
    S magnitude = 0, a_magnitude = 0;
    for (int i = 0; i < 3; ++i) {
        magnitude = std::max({magnitude, std::abs(b.h[i]), std::abs(b.h[N + i])});
        a_magnitude = std::max({a_magnitude, std::abs(a.h[i]), std::abs(a.h[N + i])});
    }
    const S slack = rel.scale * magnitude + rel.t_slack;
    const auto extent = [&](int k) {
        const auto& p = rel.plane[k];
        const auto& l = rel.lambda[k];
        S e = l[0] * b.h[p[0]] + l[1] * b.h[p[1]] + l[2] * b.h[p[2]];
        if constexpr (C == 6) e = std::min(e, l[3] * b.h[p[3]] + l[4] * b.h[p[4]] + l[5] * b.h[p[5]]);
        return e + slack;
    };
    S best = 0;
    for (int j = 0; j < N; ++j) {
        const auto& d = Kdop<S, K>::directions[j];
        const S length = std::sqrt(S(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        const S above = rel.dt[j] - extent(N + j) - a.h[j];    // B's slab above A's
        const S below = -a.h[N + j] - (rel.dt[j] + extent(j));  // below it
        best = std::max(best, std::max(above, below) / length);
    }
    return detail::lowered(best, Vec3<S>(Vec3<S>::Constant(a_magnitude)), Vec3<S>(Vec3<S>::Constant(2 * magnitude)),
                           Vec3<S>(Vec3<S>::Constant(std::abs(rel.dt[0]) + std::abs(rel.dt[1]) + std::abs(rel.dt[2]))));
}

}  // namespace cdkit
