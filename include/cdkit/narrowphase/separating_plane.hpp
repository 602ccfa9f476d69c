#pragma once
/// \file Separating-plane test with temporal coherence (perceptron learning rule), GJK as fallback.
///
/// After G. Zachmann's lecture notes "Collision Detection" (Virtual Reality and Physically-Based Simulation,
/// "The separating planes algorithm"), built on the perceptron rule (Rosenblatt 1958; finite convergence for
/// separable sets, Novikoff 1962). A plane H = {x : n·x + c = 0} with A on its front (n·a + c > 0) and B on
/// its back is kept per pair. Each query checks it with one support query per shape (the most offending
/// point of each): when the normal separates those two points the plane is proven and re-centred midway
/// between them. A failing cached plane means near contact, where the perceptron rarely converges, so the
/// query goes to warm-started GJK; only without a cached plane (first frame) is the plane searched by the
/// perceptron update h ← h ± η·(p, 1), η ← 0.97·η, for a bounded number of steps. A plane is only reported
/// when the support points prove it, so "separated" is always right; GJK's separating normal and extreme
/// points re-seed the plane.

#include <cdkit/narrowphase/gjk.hpp>

namespace cdkit {

/// Per-pair, caller-owned state: the last separating plane (world frame; n·x + c > 0 on A) and GJK's cache.
template <class S = double> struct SeparatingPlaneCache {
    Vec3<S> n = Vec3<S>::Zero();
    S c = S(0);
    bool valid = false;
    /// The last answer was "colliding" (a hint: the next query then skips the plane search).
    bool last_colliding = false;
    GjkCache<S> gjk{};
};

/// Result of `separating_plane_intersect`.
template <class S> struct SeparatingPlaneResult {
    bool colliding = false;
    bool used_gjk = false;   ///< the plane search was undecided and GJK answered
    int iterations = 0;      ///< plane updates (support-query pairs)
    GjkStatus gjk_status = GjkStatus::separated;
};

/// Boolean intersection of `a` at `pose_a` and `b` at `pose_b` using and updating `cache`.
/// `max_iterations` bounds the perceptron steps (used only without a cached plane) before GJK takes over.
/// Const on the shapes, noexcept;
/// thread-safe as long as each thread uses its own cache.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
[[nodiscard]] inline SeparatingPlaneResult<typename A::Scalar> separating_plane_intersect(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    SeparatingPlaneCache<typename A::Scalar>& cache, int max_iterations = 16) noexcept {
    using S = typename A::Scalar;
    SeparatingPlaneResult<S> r;
    const Transformed<A> ta{a, pose_a};
    const Transformed<B> tb{b, pose_b};
    const Vec3<S> ca = ta.center(), cb = tb.center();
    // Work in a frame centred between the shapes and scaled by their distance, so that the homogeneous
    // perceptron step (which depends on the origin and the units) behaves the same everywhere.
    const Vec3<S> o = (ca + cb) / S(2);
    S len = (ca - cb).norm();
    if (!(len > S(0))) len = S(1);
    Vec3<S> n;
    S c;
    if (cache.valid) {
        n = cache.n * len;
        c = cache.n.dot(o) + cache.c;
    } else {
        n = (ca - cb) / len;
        c = S(0);
    }
    S eta = S(1);
    // After a colliding answer no plane exists nearby: go straight to (warm-started) GJK.
    // When the cached plane fails, the pair is near contact: the perceptron rarely converges there, and warm
    // GJK (whose cache holds the same direction and the last simplex) is the cheaper next step.
    const int steps = cache.valid ? 1 : (cache.last_colliding ? 0 : max_iterations);
    for (int it = 0; it < steps && n.allFinite(); ++it) {
        S nn = n.norm();
        if (!(nn > S(0))) break;
        n /= nn;
        c /= nn;
        // Most offending points: the lowest point of A and the highest point of B along n (local frame).
        // Hill climbing (polyhedra) starts from the vertices of the last query on this pair (GJK's hints).
        const Vec3<S> pw = detail::place(
            pose_a, detail::support_hinted(a, detail::rotate_back(pose_a.R, Vec3<S>(-n)), &cache.gjk.hint_a));
        const Vec3<S> qw =
            detail::place(pose_b, detail::support_hinted(b, detail::rotate_back(pose_b.R, n), &cache.gjk.hint_b));
        Vec3<S> p = (pw - o) / len;
        Vec3<S> q = (qw - o) / len;
        S sp = n.dot(p) + c, sq = n.dot(q) + c;
        if (n.dot(p - q) > S(0)) {
            // n separates the supports (all of A is at or above p, all of B at or below q): the plane
            // through the middle of the gap is proven, whatever c was. Re-centring it costs no query and
            // keeps the largest margin for the next frame.
            c -= (sp + sq) / S(2);
            cache.n = n / len;  // back to the world frame: n·(x − o)/len + c
            cache.c = c - cache.n.dot(o);
            cache.valid = true;
            cache.last_colliding = false;
            return r;
        }
        r.iterations = it + 1;
        if (!(sp > S(0))) { n += eta * p; c += eta; }
        if (!(sq < S(0))) { n -= eta * q; c -= eta; }
        eta *= S(0.97);
    }
    r.used_gjk = true;
    // The GJK cache's first direction is the one the plane came from, just found failing: skip it.
    const bool plane_failed = cache.valid;
    GjkResult<S> g = detail::gjk_query(a, pose_a, b, pose_b, &cache.gjk, GjkSettings<S>{}, true, !plane_failed);
    r.gjk_status = g.status;
    r.colliding = g.status != GjkStatus::separated;
    cache.valid = false;
    cache.last_colliding = r.colliding;
    if (g.status == GjkStatus::separated && g.normal.allFinite() && g.normal.squaredNorm() > S(0)) {
        // GJK's boolean exit returns the shapes' extreme points along its normal: the plane goes midway.
        Vec3<S> m = -g.normal;
        S ha = m.dot(g.point_a), hb = m.dot(g.point_b);
        if (ha > hb) {
            cache.n = m;
            cache.c = -(ha + hb) / S(2);
            cache.valid = true;
        }
    }
    return r;
}

}  // namespace cdkit
