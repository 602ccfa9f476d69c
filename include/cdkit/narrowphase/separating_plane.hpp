#pragma once
/// \file Separating-plane test with temporal coherence (perceptron learning rule), GJK as fallback.
///
/// After G. Zachmann's lecture notes "Collision Detection" (Virtual Reality and Physically-Based Simulation,
/// "The separating planes algorithm"), built on the perceptron rule (Rosenblatt 1958; finite convergence for
/// separable sets, Novikoff 1962). A plane H = {x : n·x + c = 0} with A on its front (n·a + c > 0) and B on
/// its back is kept per pair. Each query checks it with one support query per shape (the most offending
/// point of each): when the normal separates those two points the plane is proven and re-centred midway
/// between them. A failing plane is repaired as the lecture says — perceptron updates h ← h ± η·(p, 1) over the
/// offending vertices (found by steepest descent on a hull's vertex graph), η ← 0.97·η, a bounded number of
/// them (`SeparatingPlaneSettings::repair_iterations`) — and without a plane (first frame) the same search starts
/// from the centre line. What the search leaves undecided, warm-started GJK answers. A plane is only reported
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
    GjkStatus status = GjkStatus::separated;  ///< separated by the plane, or GJK's status when it answered
    bool colliding = false;
    bool used_gjk = false;   ///< the plane search was undecided and GJK answered
    bool repaired = false;   ///< the cached plane failed and perceptron updates found a new one (no GJK)
    int iterations = 0;      ///< plane updates (support-query pairs)
};

/// Tuning of the plane search.
struct SeparatingPlaneSettings {
    /// Perceptron updates without a cached plane (the pair's first frame, or after GJK answered "colliding" and
    /// then "separated" without a plane) before GJK answers.
    int max_iterations = 16;
    /// Perceptron updates that repair a failing cached plane before GJK answers (the lecture's "repeat max n
    /// times" on every frame); 0 sends a failing plane straight to warm GJK. Measured in docs/convex.md
    /// ("Separating planes"): repairs pay where the plane moves but the pair stays apart by a margin.
    int repair_iterations = 4;
    /// The first step's learning rate η in the search frame (centred between the shapes, unit = their centre
    /// distance), from the centre line and when repairing; η ← eta_decay·η after each update (the lecture's
    /// 0.97: a decelerating step prevents cycling).
    double eta = 1.0;
    /// A failing cached plane is nearly right: a smaller first step. On 4,000 frames of two hulls spinning 3° and
    /// 4° a frame, 0.02 … 0.3 apart, one frame in five overlapping (the scene of the repair test in
    /// tests/narrowphase/test_gjk_separating_plane.cpp), GJK answered 1698 frames without repairs and 1609 with 4
    /// updates from η = 0.1 (1654 from η = 1, 1639 from η = 0.03; 1600 are colliding frames and the frames after
    /// them, where no plane is cached).
    double repair_eta = 0.1;
    double eta_decay = 0.97;
};

namespace detail {

/// The perceptron search of the lecture from the plane n·x + c = 0 (world frame; A on its front): per step the
/// most offending vertex of each shape — the support point against the normal, found on a polyhedron by hill
/// climbing its vertex graph from the last query's vertex (steepest descent of n·x, `support_hinted`) — and,
/// while one lies on the wrong side, the update h ← h ± η·(x, 1) in homogeneous coordinates with η ← decay·η.
/// The steps run in a frame centred between the shapes and scaled by their centre distance, so that the
/// homogeneous step (which depends on the origin and the units) behaves the same everywhere; the starting
/// offset is carried into that frame. Returns true with the plane stored in `cache` once the support pair
/// proves it (`proves`); false after `steps` updates.
template <class A, class B, class S, class Proves>
bool perceptron_search(const A& a, const Transform<S>& pose_a, const B& b, const Transform<S>& pose_b, Vec3<S> n,
                       S c, int steps, S eta, S decay, SeparatingPlaneCache<S>& cache, SeparatingPlaneResult<S>& r,
                       const Proves& proves) noexcept {
    const Vec3<S> ca = Transformed<A>{a, pose_a}.center(), cb = Transformed<B>{b, pose_b}.center();
    const Vec3<S> o = (ca + cb) / S(2);
    S len = (ca - cb).norm();
    if (!(len > S(0))) len = S(1);
    c = (c + n.dot(o)) / len;  // n·x + c = 0 with x = o + len·x'
    for (int it = 0; it < steps && n.allFinite(); ++it) {
        const S nn = n.norm();
        if (!(nn > S(0))) break;
        n /= nn;
        c /= nn;
        const Vec3<S> pw = place(pose_a, support_hinted(a, rotate_back(pose_a.R, Vec3<S>(-n)), &cache.gjk.hint_a));
        const Vec3<S> qw = place(pose_b, support_hinted(b, rotate_back(pose_b.R, n), &cache.gjk.hint_b));
        const Vec3<S> p = (pw - o) / len;
        const Vec3<S> q = (qw - o) / len;
        const S sp = n.dot(p) + c, sq = n.dot(q) + c;
        if (proves(n, pw, qw)) {
            // Stored in the world frame, re-centred midway between the two support points (the scaling is
            // uniform, so n is the world normal): n·(x − o)/len + c − (sp + sq)/2 = 0.
            cache.n = n;
            cache.c = (c - (sp + sq) / S(2)) * len - n.dot(o);
            cache.valid = true;
            cache.last_colliding = false;
            return true;
        }
        ++r.iterations;
        if (!(sp > S(0))) { n += eta * p; c += eta; }
        if (!(sq < S(0))) { n -= eta * q; c -= eta; }
        eta *= decay;
    }
    return false;
}

}  // namespace detail

/// Boolean intersection of `a` at `pose_a` and `b` at `pose_b` using and updating `cache` (optional, caller-owned,
/// one per pair, as every cdkit cache; without one the query is a first frame and keeps nothing). A cached plane
/// that still separates answers with one support pair; a failing one gets `settings.repair_iterations`
/// perceptron updates from its normal and offset; without a plane the search runs `settings.max_iterations`
/// updates from the centre line; GJK (warm, from the cache) answers what the plane search leaves undecided, so
/// the answer is always GJK-exact: "separated" only with a proving support pair or GJK's certificate.
/// Const on the shapes, noexcept; thread-safe as long as each thread uses its own cache.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
[[nodiscard]] inline SeparatingPlaneResult<typename A::Scalar> separating_plane_intersect(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    SeparatingPlaneCache<typename A::Scalar>* cache_ptr = nullptr,
    const SeparatingPlaneSettings& settings = {}) noexcept {
    using S = typename A::Scalar;
    SeparatingPlaneResult<S> r;
    SeparatingPlaneCache<S> cold;  // without a caller's cache: the first-frame search, nothing kept
    SeparatingPlaneCache<S>& cache = cache_ptr ? *cache_ptr : cold;
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
    const S decay = S(settings.eta_decay);
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
        // The lecture's repair: perceptron updates from the failing plane, its offset included (its first step
        // meets the pair just found again, through the hints at no climbing cost).
        if (settings.repair_iterations > 0 &&
            detail::perceptron_search(a, pose_a, b, pose_b, n, cache.c, settings.repair_iterations,
                                      S(settings.repair_eta), decay, cache, r, proves)) {
            r.repaired = true;
            return r;
        }
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
        // No plane yet (and no overlap last frame, after which none exists nearby): the search from the centre
        // line, through the midpoint of the centres.
        const Vec3<S> ca = Transformed<A>{a, pose_a}.center(), cb = Transformed<B>{b, pose_b}.center();
        const S len = (ca - cb).norm();
        const Vec3<S> n = len > S(0) ? Vec3<S>((ca - cb) / len) : Vec3<S>(S(1), S(0), S(0));
        if (detail::perceptron_search(a, pose_a, b, pose_b, n, S(-n.dot((ca + cb) / S(2))), settings.max_iterations,
                                      S(settings.eta), decay, cache, r, proves))
            return r;
    }
    r.used_gjk = true;
    // After a failing plane the GJK cache's first slot is that plane's support pair (or, with margins, the
    // direction the plane was seeded from), just found not to separate: its own test is skipped.
    const bool plane_failed = cache.valid;
    GjkResult<S> g = detail::gjk_query(a, pose_a, b, pose_b, &cache.gjk, GjkSettings<S>{}, true, !plane_failed);
    r.status = g.status;
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
