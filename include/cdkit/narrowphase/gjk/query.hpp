#pragma once
/// \file GJK's queries: `gjk_distance`, `gjk_intersect` and `gjk_distance_within` (the algorithm and its papers:
/// narrowphase/gjk.hpp), dispatching to the cold boolean (gjk/detail/cold_search.hpp) or the loop
/// (gjk/detail/loop.hpp), with the long-double refinement of near-contact distances (gjk/detail/widening.hpp).

#include <cdkit/narrowphase/gjk/detail/cold_search.hpp>
#include <cdkit/narrowphase/gjk/detail/widening.hpp>
#include <cdkit/narrowphase/gjk/types.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace cdkit {

namespace detail {

template <SupportMapped A, SupportMapped B>
GjkResult<typename A::Scalar> gjk_query(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                        const Transform<typename A::Scalar>& pose_b,
                                        GjkCache<typename A::Scalar>* cache,
                                        const GjkSettings<typename A::Scalar>& settings, bool boolean,
                                        bool retry_cached_direction = true,
                                        typename A::Scalar within =
                                            std::numeric_limits<typename A::Scalar>::infinity()) noexcept;

/// The near-contact refinement of a separated double distance query: GJK again in long double on the same
/// shapes (`widened_shape`), in world axes (both shapes placed by their poses: the double loop's frame of A
/// takes R_aᵀ for R_a's inverse, off by the rotation's rounding, ~1e-16 of the coordinates — as much as the
/// answer's last digits at a distance of 1e-7), warm-started from the double query's final simplex (a few
/// iterations), with the same tolerance, which the wider arithmetic can now reach. Its result replaces `r` when
/// it is separated (a long-double "touching" or failure keeps the double answer). Out of line: rare, and off the
/// loop's code.
template <SupportMapped A, SupportMapped B>
CDKIT_COLD_PATH void refine_near_contact(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                         const Transform<typename A::Scalar>& pose_b,
                                         const GjkSettings<typename A::Scalar>& settings,
                                         GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    using W = wider_t<S>;
    // The shapes in long double: rebuilt there when they can be (`HasWidened`: a curved primitive's rounded
    // support point is off its surface by ε of its size, 1e-9 relative at 1e-8 of distance), otherwise their double
    // support points widened.
    const auto wa = widened_shape(a);
    const auto wb = widened_shape(b);
    const WideningFrame<S> frame(pose_a, pose_b);
    const Vec3<W>& origin = frame.origin;
    const Transform<W>& pa = frame.pose_a;
    const Transform<W>& pb = frame.pose_b;
    const Transformed<decltype(wa)> ta{wa, pa};
    const Transformed<decltype(wb)> tb{wb, pb};
    const Transform<W> world;  // identity: B "in A's frame" is B in these world axes
    // The final simplex's directions (A's frame → world) start the loop; its points are queried again.
    GjkCache<W> cache;
    cache.size = std::min(r.simplex.size, 4);
    for (int i = 0; i < cache.size; ++i)
        cache.directions[std::size_t(i)] = rotate(pa.R, Vec3<W>(r.simplex.v[std::size_t(i)].d.template cast<W>()));
    const GjkSettings<W> ws = widened_settings(settings);  // the double query's 256ε·size
    // The distance query in W (no refinement of its own: W is the widest type).
    const GjkResult<W> wr = gjk_query(ta, world, tb, world, &cache, ws, false);
    r.iterations += wr.iterations;
    if (wr.status != GjkStatus::separated) return;
    r.distance = S(wr.distance);
    r.normal = wr.normal.template cast<S>();
    r.point_a = Vec3<W>(wr.point_a + origin).template cast<S>();
    r.point_b = Vec3<W>(wr.point_b + origin).template cast<S>();
    // The simplex back in A's frame (its documented frame; informational for a separated result).
    r.simplex.size = wr.simplex.size;
    for (int i = 0; i < wr.simplex.size; ++i) {
        const GjkVertex<W>& x = wr.simplex.v[std::size_t(i)];
        GjkVertex<S>& y = r.simplex.v[std::size_t(i)];
        const Vec3<W> xa = rotate_back(pa.R, Vec3<W>(x.a - pa.t)), xb = rotate_back(pa.R, Vec3<W>(x.b - pa.t));
        y.a = xa.template cast<S>();
        y.b = xb.template cast<S>();
        y.w = Vec3<W>(xa - xb).template cast<S>();
        y.d = rotate_back(pa.R, x.d).template cast<S>();
        y.b_local = rotate_back(pb.R, Vec3<W>(x.b - pb.t)).template cast<S>();
        r.simplex.lambda[std::size_t(i)] = S(wr.simplex.lambda[std::size_t(i)]);
    }
}

/// The queries' one dispatcher: `boolean` (gjk_intersect), else a distance (gjk_distance), bounded when `within` is
/// finite (gjk_distance_within: the distance loop that stops at a plane proving the distance exceeds `within`, ≥ 0).
template <SupportMapped A, SupportMapped B>
GjkResult<typename A::Scalar> gjk_query(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                        const Transform<typename A::Scalar>& pose_b,
                                        GjkCache<typename A::Scalar>* cache,
                                        const GjkSettings<typename A::Scalar>& settings,
                                        bool boolean, bool retry_cached_direction, typename A::Scalar within) noexcept {
    using S = typename A::Scalar;
    GjkResult<S> r;
    if (boolean && !cache) {
        gjk_intersect_cold(a, pose_a, b, pose_b, settings, r);
        r.colliding = is_colliding(r.status);
        return r;
    }
    const bool bounded = !boolean && within < std::numeric_limits<S>::infinity();
    if constexpr (HasBoundingBalls<A> && HasBoundingBalls<B>) {
        // A cold bounded query: the boolean's bounding-ball pre-test, its "apart" beyond the bound.
        if (bounded && !cache && settings.bounding_ball_test) {
            const Vec3<S> ca = world_center(a, pose_a), cb = world_center(b, pose_b);
            const Vec3<S> delta = minus(ca, cb);
            const S dd = norm2(delta);
            if (dd <= std::numeric_limits<S>::max() &&
                bounding_ball_decides(a, pose_a, b, pose_b, ca, cb, delta, dd,
                                      settings.touch_factor * std::numeric_limits<S>::epsilon(), r, within)) {
                r.colliding = is_colliding(r.status);
                return r;
            }
        }
    }
    if ((boolean || bounded) && retry_cached_direction && cache && cache->size > 0) {
        if (bounded ? warm_direction_separates(a, pose_a, b, pose_b, settings, *cache, r, within, false)
                    : warm_direction_separates(a, pose_a, b, pose_b, settings, *cache, r))
            return r;  // separated (beyond the bound)
        // Tried, in world axes: the loop starts from the rebuilt cache (a boolean's first slot now holds that pair).
    }
    const Transform<S> rel = relative_pose(pose_a, pose_b);
    const S margin = margin_of(a) + margin_of(b);
    Vec3<S> v;
    S size, lower;
    GjkVertex<S> sep;
    sep.w.setConstant(std::numeric_limits<S>::quiet_NaN());
    bool tolerance_met = true;
    const S quality = cache ? settings.warm_exit_quality : S(0);
    GjkStatus st = boolean   ? gjk_loop<true, true>(a, b, rel, settings, cache, margin, r.simplex, v, size,
                                                    r.iterations, lower, quality, &sep, nullptr)
                   : bounded ? gjk_loop<true, false, true>(a, b, rel, settings, cache, margin, r.simplex, v, size,
                                                           r.iterations, lower, quality, &sep, &tolerance_met, within)
                             : gjk_loop<true, false>(a, b, rel, settings, cache, margin, r.simplex, v, size,
                                                     r.iterations, lower, S(0), &sep, &tolerance_met);
    const bool by_plane = gjk_finish(a, pose_a, b, settings, r, st, v, size, lower, sep, boolean || bounded,
                                     bounded ? within : S(0));
    if (r.status == GjkStatus::touching) prove_touching_overlap(a, b, rel, r);
    if constexpr (refines_near_contact<S>) {
        // Not an answer by a plane: its distance is a bound beyond `within`, not a distance to refine.
        if (!boolean && !by_plane &&
            near_contact_needs_refinement<A, B>(
                settings, r, size + std::abs(rel.t[0]) + std::abs(rel.t[1]) + std::abs(rel.t[2]), tolerance_met))
            refine_near_contact(a, pose_a, b, pose_b, settings, r);
    }
    r.colliding = is_colliding(r.status);
    return r;
}


}  // namespace detail


/// Separation distance between shape `a` placed by `pose_a` and shape `b` placed by `pose_b`, with
/// closest points and normal in the world frame. `separated` is certified as for gjk_intersect (some support
/// plane bound exceeded the touching tolerance, else the wide-type continuation decides, else `touching`);
/// the distance and normal are those of the closest point |v|. Const, noexcept, thread-safe; `cache`
/// (optional, caller-owned, per pair) warm-starts the search and is updated.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
[[nodiscard]] inline GjkResult<typename A::Scalar> gjk_distance(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    GjkCache<typename A::Scalar>* cache = nullptr,
    const GjkSettings<typename A::Scalar>& settings = {}) noexcept {
    return detail::gjk_query(a, pose_a, b, pose_b, cache, settings, false);
}

/// Distance query that only needs the distance up to `max_distance` (speculative contacts within a margin): one
/// GJK search (Gilbert, Johnson, Keerthi 1988) that stops as soon as a support plane proves the distance exceeds
/// `max_distance` (van den Bergen 1999's lower bound v·w/|v|, the boolean's early exit with the bound added), and
/// otherwise goes on, from the same simplex, to the distance. Three outcomes: colliding (`touching` /
/// `intersecting`, as gjk_distance answers them; an overlap proven by the loop leaves its final tetrahedron in
/// `simplex` for EPA); `separated` with `distance` ≤ max_distance (or within GJK's tolerance of it): distance,
/// closest points and normal as gjk_distance gives them; `separated` with `distance` > max_distance: a lower bound
/// with a separating plane, as gjk_intersect's early exit reports it (`normal`, the plane's supporting points).
/// Replaces gjk_intersect followed by gjk_distance for pairs within the bound, which paid for two searches.
/// `max_distance` < 0 or NaN counts as 0; +∞ gives gjk_distance. Without a cache the bounding balls are tried first
/// (`GjkSettings::bounding_ball_test`, their "apart" beyond the bound); with one, its cached direction's plane.
/// Const, noexcept, thread-safe; `cache` as for gjk_distance.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
[[nodiscard]] inline GjkResult<typename A::Scalar> gjk_distance_within(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    typename A::Scalar max_distance, GjkCache<typename A::Scalar>* cache = nullptr,
    const GjkSettings<typename A::Scalar>& settings = {}) noexcept {
    using S = typename A::Scalar;
    return detail::gjk_query(a, pose_a, b, pose_b, cache, settings, false, true,
                             max_distance > S(0) ? max_distance : S(0));
}

/// Boolean intersection test with early exit as soon as a separating plane is found. `status` is
/// `separated`, `touching` or `intersecting` (or `max_iterations`/`degenerate`); `colliding` says touching or intersecting.
/// Guarantee: `separated` is only answered with a proven plane — a direction u and a support point w of A − B
/// along −u with u·w/|u| above the touching tolerance (256ε·size; van den Bergen 1999's lower bound), or
/// disjoint bounding balls; `normal` is that direction and `distance` that bound (≤ the true distance, up to
/// the support maps' rounding). When GJK stops without such a plane (near contact on curved shapes, where the
/// double sub-simplex step can misplace v), the query goes on with the steps in a wider type
/// (`detail::certify_separation`) and, if that decides nothing, answers `touching`: conservative for collision
/// detection, and only pairs within the rounding of contact get there. `intersecting` is answered with four
/// points of A − B around the origin, a point of one shape strictly inside the other, overlapping inner
/// balls / margins, or — where the loop ended touching on a triangle or segment through the origin (nested
/// needles) — five support points of A − B around it (`detail::touching_simplex_proves_overlap`).
/// Const, noexcept, thread-safe; `cache` as for gjk_distance.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
[[nodiscard]] inline GjkResult<typename A::Scalar> gjk_intersect(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    GjkCache<typename A::Scalar>* cache = nullptr,
    const GjkSettings<typename A::Scalar>& settings = {}) noexcept {
    return detail::gjk_query(a, pose_a, b, pose_b, cache, settings, true);
}

}  // namespace cdkit


// The built-in shapes' GJK queries in double are compiled into libcdkit (precompiled_queries.hpp).
#ifndef CDKIT_NO_PRECOMPILED_QUERIES
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/precompiled_queries.hpp>
namespace cdkit {
CDKIT_FOR_EACH_BUILTIN_PAIR(CDKIT_GJK_QUERY_INSTANCE, extern)
}  // namespace cdkit
#endif
