#pragma once
/// \file The boolean queries' tests before and beside the loop, each a function of its own that a setting
/// switches off (GjkSettings): bounding balls, containment of a support point, candidate axes (face normals and
/// edge cross products: the separating axis test of Gottschalk, Lin, Manocha, "OBBTree: a hierarchical structure
/// for rapid interference detection", SIGGRAPH 1996), the world-frame first support pair and the warm query's
/// cached direction.

#include <cdkit/narrowphase/gjk/detail/loop.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace cdkit {
namespace detail {

/// The bounding-ball pre-test of the cold boolean query (`GjkSettings::bounding_ball_test`): true, with `r`
/// filled in, when the balls decide the pair. ca, cb: the computed world centres, delta = ca − cb, dd = |delta|²,
/// tf = touch_factor·ε. The slack tf·(|t_a|₁ + |t_b|₁ + |ca|₁ + |cb|₁ + R_a + R_b) exceeds the rounding of the
/// centres (a rotation and a translation, a few ε of those magnitudes), of delta and of the squares many
/// times over, and is at least the touching tolerance gjk_finish applies (256ε·max(|w|, margin) with
/// |w| ≤ |ca − cb| + R_a + R_b): an answer given here is the one the full query would give, only sooner.
/// `beyond` (a bounded distance query's bound, gjk_distance_within; 0 for the boolean): "separated" only for balls
/// apart by more than that.
template <SupportMapped A, SupportMapped B>
inline bool bounding_ball_decides(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                  const Transform<typename A::Scalar>& pose_b, const Vec3<typename A::Scalar>& ca,
                                  const Vec3<typename A::Scalar>& cb, const Vec3<typename A::Scalar>& delta,
                                  typename A::Scalar dd, typename A::Scalar tf, GjkResult<typename A::Scalar>& r,
                                  typename A::Scalar beyond = 0) noexcept {
    using S = typename A::Scalar;
    const S ra = a.bounding_radius(), rb = b.bounding_radius();
    const S slack = tf * (norm1(pose_a.t) + norm1(pose_b.t) + norm1(ca) + norm1(cb) + ra + rb);
    const S outer = ra + rb + slack;
    const S reach = outer + beyond;
    if (dd > reach * reach) {
        const S len = std::sqrt(dd);
        const S gap = len - outer;
        if (!(gap > beyond)) return false;
        const S inv = S(1) / len;
        const Vec3<S> n(-delta[0] * inv, -delta[1] * inv, -delta[2] * inv);  // A towards B
        r.iterations = 0;
        r.simplex.size = 0;
        r.status = GjkStatus::separated;
        r.distance = gap;
        r.normal = n;
        r.point_a = plus_scaled(ca, ra, n);
        r.point_b = plus_scaled(cb, -rb, n);
        return true;
    }
    const S inner = a.inner_radius() + b.inner_radius() - slack;
    if (inner > S(0) && dd < inner * inner) {
        r.iterations = 0;
        r.simplex.size = 0;
        r.status = GjkStatus::intersecting;
        r.distance = S(0);
        return true;
    }
    return false;
}

/// The containment certificate of the cold boolean query (`GjkSettings::containment_test`): true when the first
/// simplex vertex's point of B (`x.b`, A's frame) lies inside A, or its point of A (`x.a`) inside B, by more than the
/// slack — a point of one shape strictly inside the other proves overlap, no tetrahedron around the origin
/// needed (the P3 overlaps are 1e-5…1e-2 of the size: GJK needs 5.5 to 10 rounds for the tetrahedron, while
/// the first support pair, along the centre line, is the deepest pair often enough, see docs/convex.md). Only
/// the first pair is tested: a test in every round of the loop saved more rounds on cylinders and cones but
/// cost the separated ("close") queries 5–13 % (the loop's code, not the tests' flops). Slack: that of
/// `bounding_ball_decides` with the radii counted twice, tf·(|t_a|₁ + |t_b|₁ + 2(R_a + R_b)); a point taken
/// into the other frame is off by a few ε of |t_a| + |t_b| + its distance from its own centre, the shape's
/// test rounds by a few ε of its size, and the slack is at least gjk_finish's touching tolerance (256ε·|w|,
/// |w| ≤ |t_b − t_a| + R_a + R_b + the centres' offsets): a pair within that tolerance of touching is never
/// called intersecting here.
template <SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE typename A::Scalar containment_slack(const A& a, const Transform<typename A::Scalar>& pose_a,
                                                         const B& b, const Transform<typename A::Scalar>& pose_b,
                                                         typename A::Scalar tf) noexcept {
    using S = typename A::Scalar;
    // At least 16ε, so that a touch_factor of 0 still leaves the transforms' rounding covered.
    const S t = std::max(tf, S(16) * std::numeric_limits<S>::epsilon());
    return t * (norm1(pose_a.t) + norm1(pose_b.t) + S(2) * (a.bounding_radius() + b.bounding_radius()));
}
template <SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE bool containment_decides(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                             const Transform<typename A::Scalar>& pose_b,
                                             const GjkVertex<typename A::Scalar>& x,
                                             const Vec3<typename A::Scalar>& a_in_b,
                                             typename A::Scalar tf) noexcept {
    using S = typename A::Scalar;
    // B's point is already in A's frame (x.b); A's point in B's frame is a_in_b (unused unless B has the test).
    // Both tests evaluated (no short circuit: which one holds is data-dependent), first without the slack: on
    // separated pairs the points lie outside, and the slack (two sqrt for the radii) is only paid for a candidate.
    auto inside = [&](S slack) {
        bool in = false;
        if constexpr (HasContainmentTest<A>) in = a.contains_strictly(x.b, slack);
        if constexpr (HasContainmentTest<B>) in = in | b.contains_strictly(a_in_b, slack);
        return in;
    };
    if (!inside(S(0))) return false;
    // At least 16ε, so that a touch_factor of 0 still leaves the transforms' rounding covered.
    const S t = std::max(tf, S(16) * std::numeric_limits<S>::epsilon());
    return inside(t * (norm1(pose_a.t) + norm1(pose_b.t) + S(2) * (a.bounding_radius() + b.bounding_radius())));
}
/// The same for shapes that locate points by walking (HasPointLocation, a hull): one pass with the slack, B's
/// location first and A's only when B does not contain A's point, each walk starting among the triangles around
/// the shape's first support vertex (`hint_a`, `hint_b`). The face planes the points were found beyond are
/// returned (`axis_a`, A's frame; `axis_b`, B's; zero if none) for candidate_axes_decide. Out of line: inlined
/// into the cold query it slowed the separated pairs by 12 % even when it returned at once (layout, not work).
template <SupportMapped A, SupportMapped B>
CDKIT_NOINLINE bool containment_decides_walking(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    const GjkVertex<typename A::Scalar>& x, const Vec3<typename A::Scalar>& a_in_b, typename A::Scalar tf,
    std::uint32_t hint_a, std::uint32_t hint_b, Vec3<typename A::Scalar>& axis_a,
    Vec3<typename A::Scalar>& axis_b) noexcept {
    const typename A::Scalar slack = containment_slack(a, pose_a, b, pose_b, tf);
    if constexpr (HasPointLocation<B>) {
        const auto where = b.locate(a_in_b, slack, hint_b);
        if (where.inside) return true;
        axis_b = where.axis;
    } else if constexpr (HasContainmentTest<B>) {
        if (b.contains_strictly(a_in_b, slack)) return true;
    }
    if constexpr (HasPointLocation<A>) {
        const auto where = a.locate(x.b, slack, hint_a);
        axis_a = where.axis;
        return where.inside;
    } else if constexpr (HasContainmentTest<A>) {
        return a.contains_strictly(x.b, slack);
    }
    return false;
}

/// The containment certificate on a support pair of the cold boolean's loop (`x`, A's frame; `rel` B's pose in A's
/// frame), for pairs of shapes with cheap tests and no candidate axes: shallow overlaps of curved shapes, whose
/// first pair is often on a rim or apex and not inside, have a point inside the other shape after a few rounds
/// (P3 cylinder / cone overlaps: 7.7 → 5.6 and 6.1 → 4.9 rounds). Out of line: a test in every round inlined into
/// the loop cost the separated pairs 5–13 % (the loop's code; tenth session), out of line 1–3 % in the A/B driver.
template <SupportMapped A, SupportMapped B>
CDKIT_NOINLINE bool loop_containment_decides(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                             const Transform<typename A::Scalar>& pose_b,
                                             const Transform<typename A::Scalar>& rel,
                                             const GjkVertex<typename A::Scalar>& x, typename A::Scalar tf) noexcept {
    const Vec3<typename A::Scalar> a_in_b = rotate_back(rel.R, minus(x.a, rel.t));
    return containment_decides(a, pose_a, b, pose_b, x, a_in_b, tf);
}

/// The boolean queries' plane test in squares: v·w/|v| > margin + tf·max(size, margin) (tf = touch_factor·ε,
/// the threshold gjk_finish uses) with vv = |v|² and size2 = size², so that a failing test costs no sqrt (none at
/// all without margins).
template <class S>
CDKIT_ALWAYS_INLINE bool plane_separates_squared(S vw, S vv, S size2, S margin, S tf) noexcept {
    if (!(vw > S(0))) return false;
    S thr2;
    if (margin > S(0)) {
        const S thr = margin + tf * std::max(std::sqrt(size2), margin);
        thr2 = thr * thr;
    } else {
        thr2 = tf * tf * size2;
    }
    return vw * vw > thr2 * vv;
}

/// The candidate-axis test of the cold boolean query (`GjkSettings::candidate_axes`): the face normal of A towards
/// B's first support point (`x.b`, A's frame), the one of B towards A's (`a_in_b`, B's frame) and, where both
/// shapes name edges, the cross product of their edges nearest those points, each given the loop's plane test
/// along that direction d (A's frame): the support point w of D along −d with d·w > (margin + tol)·|d|, tol as in
/// the loop with the points' magnitudes counted in the size. Such a plane proves separation whatever d is, so the
/// answer is the one the loop would certify, only sooner. Why these: on close box pairs the closest features are
/// a vertex and a face, or two edges, whose face normal or edge cross product is then the separating axis (and,
/// below a gap of about the features' rounding, the only one; Gottschalk, Lin, Manocha, "OBBTree: a hierarchical
/// structure for rapid interference detection", SIGGRAPH 1996, the separating axis theorem for boxes); the
/// first support pair along the centre line is usually at those features. GJK reaches the same plane only after
/// 3–6 simplex steps. A cone's face normal at the other point's azimuth does the same for a rim or the apex
/// against its side or base (P3 cone close 114 → 91–97 ns). True, with `r` filled in as the loop's early exit, when
/// a plane is found; `pairs` counts the support pairs used (kept apart from the loop's counter, which schedules
/// its momentum).
template <SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE bool candidate_axes_decide(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                               const Transform<typename A::Scalar>& rel,
                                               const GjkVertex<typename A::Scalar>& x,
                                               const Vec3<typename A::Scalar>& a_in_b,
                                               const Vec3<typename A::Scalar>& located_a,
                                               const Vec3<typename A::Scalar>& located_b, typename A::Scalar size2,
                                               typename A::Scalar tf, int& pairs,
                                               GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    const S ma = margin_of(a), mb = margin_of(b), margin = ma + mb;
    auto plane_along = [&](const Vec3<S>& d) {
        ++pairs;
        const Vec3<S> pa = core_support(a, neg(d));
        const Vec3<S> pb_local = core_support(b, rotate_back(rel.R, d));
        const Vec3<S> pb = place(rel, pb_local);
        const Vec3<S> w = minus(pa, pb);
        const S w2 = norm2(w);
        if (!(w2 <= std::numeric_limits<S>::max())) return false;  // NaN or inf: the loop will report it
        // The size the tolerance scales with: |w| and the magnitudes the rounding of w acts on (A's point, B's
        // point in its own frame and the translation that moves it into A's). On a touching pair w is tiny, and
        // |w| alone would let a gap at the level of that rounding pass as a plane.
        const S sz2 = std::max(std::max(std::max(size2, w2), norm2(pa)), std::max(norm2(pb_local), norm2(rel.t)));
        const S dw = dot3(d, w);
        const S dd = norm2(d);
        if (!plane_separates_squared(dw, dd, sz2, margin, tf)) return false;
        const S inv = S(1) / std::sqrt(dd);
        const Vec3<S> n = Vec3<S>(-d[0] * inv, -d[1] * inv, -d[2] * inv);  // A towards B, in A's frame
        r.iterations = 1 + pairs;
        r.status = GjkStatus::separated;
        r.distance = dw * inv - margin;
        r.normal = rotate(pose_a.R, n);
        r.point_a = place(pose_a, plus_scaled(pa, ma, n));
        r.point_b = place(pose_a, plus_scaled(pb, -mb, n));
        return true;
    };
    // B lies outside A's face n_a, so D = A − B lies on the −n_a side; A outside B's face n_b: on the +n_b side.
    // First the faces a hull's point location found the points beyond (`located_a`, A's frame; `located_b`, B's;
    // zero when none): on close hull pairs with a vertex–face contact that face is the separating axis.
    if constexpr (HasPointLocation<A>) {
        if (norm2(located_a) > S(0) && plane_along(neg(located_a))) return true;
    }
    if constexpr (HasPointLocation<B>) {
        if (norm2(located_b) > S(0) && plane_along(rotate(rel.R, located_b))) return true;
    }
    if constexpr (HasCandidateAxes<A>) {
        if (plane_along(neg(Vec3<S>(a.candidate_axis(x.b))))) return true;
    }
    if constexpr (HasCandidateAxes<B>) {
        if (plane_along(rotate(rel.R, Vec3<S>(b.candidate_axis(a_in_b))))) return true;
    }
    // Both faces failed: an edge–edge contact, whose separating axis is the cross product of the two edges
    // nearest the other shape's point (skipped for near-parallel edges), turned so that D's first point lies on
    // its positive side (where all of D must lie if it separates).
    if constexpr (HasCandidateEdges<A> && HasCandidateEdges<B>) {
        const Vec3<S> c = cross3(Vec3<S>(a.candidate_edge(x.b)), rotate(rel.R, Vec3<S>(b.candidate_edge(a_in_b))));
        if (norm2(c) > S(1e-6)) {
            if (plane_along(dot3(c, x.w) < S(0) ? neg(c) : c)) return true;
        }
    }
    (void)x;
    (void)a_in_b;
    (void)located_a;
    (void)located_b;
    return false;
}

/// One support pair of the boolean queries' world-frame first step: A's point along `da` (A's frame), B's along
/// v (world axes, B's frame after the rotation), both placed; then the plane test of the cold query's loop along
/// v, the direction from B towards A (`plane_separates_squared`, with |w| and then the points' world magnitudes
/// as the size). The returned step: `separated`, `r` holds the separated result (status, lower-bound distance,
/// world normal, the two shapes' extreme points along it), all but the iteration count; `open`, no plane, the
/// pair's points are for the caller's next step; `non_finite`, w is NaN or infinite. Shared by the cold query's
/// first iteration (v the centre line, da = R_aᵀ·(−v)) and the warm query's cached direction (da the cached one,
/// v = −R_a·da: the same bits as that query had on its own). Returned by value, the caller copying the points
/// into locals: filled through a reference, the cold query kept them in memory (hull pairs 4–12 % slower).
/// `beyond` (a bounded distance query's bound; 0 for the booleans): the plane must clear the margins + beyond.
enum class WorldStep { separated, open, non_finite };
template <class S> struct WorldPair {
    Vec3<S> sa, sb;  ///< the support points, each in its shape's frame
    S size2;         ///< |w|², w = A's point − B's in world axes
    WorldStep step;
};
template <SupportMapped A, SupportMapped B>
CDKIT_ALWAYS_INLINE WorldPair<typename A::Scalar> world_plane_step(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                               const Transform<typename A::Scalar>& pose_b,
                                               const Vec3<typename A::Scalar>& v, typename A::Scalar vv,
                                               const Vec3<typename A::Scalar>& da, typename A::Scalar tf,
                                               std::uint32_t* hints, GjkResult<typename A::Scalar>& r,
                                               typename A::Scalar beyond = 0) noexcept {
    using S = typename A::Scalar;
    const S ma = margin_of(a), mb = margin_of(b), margin = ma + mb;
    const S level = margin + beyond;
    WorldPair<S> pair;
    pair.sa = core_support_hinted(a, da, hints);
    pair.sb = core_support_hinted(b, rotate_back(pose_b.R, v), hints + 1);
    const Vec3<S> pa = place(pose_a, pair.sa), pb = place(pose_b, pair.sb);
    const Vec3<S> w = minus(pa, pb);
    pair.size2 = norm2(w);
    pair.step = WorldStep::non_finite;
    if (!(pair.size2 <= std::numeric_limits<S>::max())) return pair;
    const S vw = dot3(v, w);
    // The tolerance scales with the magnitudes whose rounding w carries: world coordinates, up to |t| away from
    // the origin. |w| alone shrinks to nothing on a touching pair and let a rounding-level gap pass as a plane
    // (a cone–hull pair at gap 0, 100 sizes from the origin: "separated" at 2e-16 of the size). The |w| test
    // first: the magnitudes are only needed when it passes.
    if (!(plane_separates_squared(vw, vv, pair.size2, level, tf) &&
          plane_separates_squared(vw, vv, std::max(pair.size2, std::max(norm2(pa), norm2(pb))), level, tf))) {
        pair.step = WorldStep::open;
        return pair;
    }
    const S inv = S(1) / std::sqrt(vv);
    const Vec3<S> n = Vec3<S>(-v[0] * inv, -v[1] * inv, -v[2] * inv);  // A towards B
    r.status = GjkStatus::separated;
    r.distance = vw * inv - margin;
    r.normal = n;
    r.point_a = plus_scaled(pa, ma, n);
    r.point_b = plus_scaled(pb, -mb, n);
    pair.step = WorldStep::separated;
    return pair;
}

/// The warm boolean query's first test (a cache from an earlier frame), in world axes: a fresh support pair
/// along the cache's first direction (the last separating one), with the plane test of gjk_intersect_cold's
/// first step — no relative pose, no square root unless it separates, the result's normal and points already
/// in world axes. The loop's former test of that direction (A's frame, square roots for the bound and the
/// tolerance, the result rotated back) made a warm boolean dearer than a cold one on separated frames (126 vs
/// 96 ns in the coherent benchmark). True, with `r` and the cache's hints set, when the pair separates
/// (iterations 0); otherwise the pair goes into the cache's first slot for the loop (see below). `beyond`: as for
/// world_plane_step (a bounded distance query's bound). A bounded query leaves the slot as it is (`refill` false):
/// its pairs within the bound converge from last frame's final simplex, which the fresh point along that simplex's
/// first direction served worse (cylinder–hull pairs within a 2 cm margin: 16.0 against 15.0 iterations).
template <SupportMapped A, SupportMapped B>
inline bool warm_direction_separates(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                     const Transform<typename A::Scalar>& pose_b,
                                     const GjkSettings<typename A::Scalar>& settings,
                                     GjkCache<typename A::Scalar>& cache, GjkResult<typename A::Scalar>& r,
                                     typename A::Scalar beyond = 0, bool refill = true) noexcept {
    using S = typename A::Scalar;
    const S tf = settings.touch_factor * std::numeric_limits<S>::epsilon();
    const Vec3<S>& d = cache.directions[0];  // A's support direction (towards B), A's frame
    const Vec3<S> v = neg(rotate(pose_a.R, d));  // from B towards A in world axes, as the cold query's centre line
    std::uint32_t hints[2] = {cache.hint_a, cache.hint_b};
    const WorldPair<S> pair = world_plane_step(a, pose_a, b, pose_b, v, norm2(v), d, tf, hints, r, beyond);
    switch (pair.step) {
        case WorldStep::separated:
            r.iterations = 0;
            r.simplex.size = 0;
            cache.hint_a = hints[0];
            cache.hint_b = hints[1];
            return true;
        case WorldStep::open:
            // No plane: the pair is this frame's point of D along the cached direction. In the cache's first
            // slot (when its points are these shapes') the loop rebuilds it there instead of querying it again.
            if (refill && cache.shape_a == static_cast<const void*>(&a) &&
                cache.shape_b == static_cast<const void*>(&b)) {
                cache.point_a[0] = pair.sa;
                cache.point_b[0] = pair.sb;
            }
            return false;
        case WorldStep::non_finite: break;  // gjk_loop's checks decide
    }
    return false;
}

}  // namespace detail
}  // namespace cdkit
