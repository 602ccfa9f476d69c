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
    Vec3<S> n = Vec3<S>::Zero();  ///< unit normal, pointing from B towards A
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
    // n separates A's lowest point p and B's highest point q along n (world frame) when n·(p − q) > 0 — beyond the
    // touching tolerance of the GJK queries (touch_factor·ε times the magnitudes whose rounding p and q carry: their
    // world coordinates, and |p − q| itself), compared in squares. With "> 0" alone two coincident flat boxes (zero
    // thickness: p and q on the same plane, n·(p − q) a rounding error of either sign) came out separated; found
    // when the hard-case count took in the plane.
    const S tf = GjkSettings<S>{}.touch_factor * std::numeric_limits<S>::epsilon();
    auto proves = [tf](const Vec3<S>& n, const Vec3<S>& p, const Vec3<S>& q) {
        const Vec3<S> pq = p - q;
        const S size2 = std::max(std::max(p.squaredNorm(), q.squaredNorm()), pq.squaredNorm());
        return detail::plane_separates_squared(n.dot(pq), n.squaredNorm(), size2, S(0), tf);
    };
    if (cache.valid) {
        // The cached plane: one support pair, in world axes, decides it. Its unit normal n proves separation when
        // A's lowest point p and B's highest point q along n are apart along it (all of A at or above p, all of B
        // at or below q: `proves`), whatever the offset; the plane is then re-centred midway between them, which
        // keeps the largest margin for the next frame at no extra query. No centres, square root or division
        // here: on coherent frames this check is the whole query.
        const Vec3<S> n = cache.n;
        const Vec3<S> da = detail::rotate_back(pose_a.R, Vec3<S>(-n));  // A's support direction, A's frame
        const Vec3<S> sa = detail::support_hinted(a, da, &cache.gjk.hint_a);
        const Vec3<S> sb = detail::support_hinted(b, detail::rotate_back(pose_b.R, n), &cache.gjk.hint_b);
        const Vec3<S> p = detail::place(pose_a, sa);
        const Vec3<S> q = detail::place(pose_b, sb);
        if (proves(n, p, q)) {
            cache.c = -(n.dot(p) + n.dot(q)) / S(2);
            cache.last_colliding = false;
            return r;
        }
        r.iterations = 1;
        // A failing cached plane means near contact, where the perceptron rarely converges: warm-started GJK is
        // the cheaper next step. Its cache holds the simplex of the last frame GJK ran, often many frames ago;
        // the pair just found is a point of A − B of this frame, so it goes into the cache's first slot (as the
        // warm boolean does with its own failed direction), which the loop rebuilds without a support query. On
        // the coherent benchmark this takes the fallbacks' GJK iterations from 1435 to 1208 (near-touching) and
        // from 734 to 586 (in-and-out). Only for shapes without margins, whose full supports are the cores' that
        // the cache stores.
        if constexpr (!HasMargin<A> && !HasMargin<B>) {
            GjkCache<S>& g = cache.gjk;
            if (g.size > 0 && g.shape_a == static_cast<const void*>(&a) && g.shape_b == static_cast<const void*>(&b)) {
                g.directions[0] = da;
                g.point_a[0] = sa;
                g.point_b[0] = sb;
            }
        }
    } else if (!cache.last_colliding) {
        // No plane yet (and no overlap last frame, after which none exists nearby): the perceptron search, in a
        // frame centred between the shapes and scaled by their distance, so that the homogeneous step (which
        // depends on the origin and the units) behaves the same everywhere.
        const Transformed<A> ta{a, pose_a};
        const Transformed<B> tb{b, pose_b};
        const Vec3<S> ca = ta.center(), cb = tb.center();
        const Vec3<S> o = (ca + cb) / S(2);
        S len = (ca - cb).norm();
        if (!(len > S(0))) len = S(1);
        Vec3<S> n = (ca - cb) / len;
        S c = S(0);
        S eta = S(1);
        for (int it = 0; it < max_iterations && n.allFinite(); ++it) {
            const S nn = n.norm();
            if (!(nn > S(0))) break;
            n /= nn;
            c /= nn;
            // Most offending points: the lowest point of A and the highest point of B along n (local frame).
            // Hill climbing (polyhedra) starts from the vertices of the last query on this pair (GJK's hints).
            const Vec3<S> pw = detail::place(
                pose_a, detail::support_hinted(a, detail::rotate_back(pose_a.R, Vec3<S>(-n)), &cache.gjk.hint_a));
            const Vec3<S> qw =
                detail::place(pose_b, detail::support_hinted(b, detail::rotate_back(pose_b.R, n), &cache.gjk.hint_b));
            const Vec3<S> p = (pw - o) / len;
            const Vec3<S> q = (qw - o) / len;
            const S sp = n.dot(p) + c, sq = n.dot(q) + c;
            if (proves(n, pw, qw)) {
                // Proven as above; stored in the world frame (the scaling is uniform, so n is the world normal):
                // n·(x − o)/len + c − (sp + sq)/2 = 0.
                cache.n = n;
                cache.c = (c - (sp + sq) / S(2)) * len - n.dot(o);
                cache.valid = true;
                cache.last_colliding = false;
                return r;
            }
            r.iterations = it + 1;
            if (!(sp > S(0))) { n += eta * p; c += eta; }
            if (!(sq < S(0))) { n -= eta * q; c -= eta; }
            eta *= S(0.97);
        }
    }
    r.used_gjk = true;
    // After a failing plane the GJK cache's first slot is that plane's support pair (or, with margins, the
    // direction the plane was seeded from), just found not to separate: its own test is skipped.
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
