#pragma once
/// \file The GJK loop (Gilbert, Johnson, Keerthi, "A fast procedure for computing the distance between complex
/// objects in three-dimensional space", IEEE J. Robotics and Automation 4(2), 1988) of the distance query, the warm
/// boolean and EPA's start, with the robustness measures of van den Bergen, "A fast and robust GJK implementation
/// for collision detection of convex objects", J. Graphics Tools 4(2), 1999 (termination on the lower bound v·w,
/// progress check, duplicate support points, the warm start of §5), and `gjk_finish`, which turns the loop's
/// outcome into a result.

#include <cdkit/narrowphase/gjk/detail/certify.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace cdkit {
namespace detail {

/// The GJK loop on D in A's frame. `early_exit_margin` ≥ 0, the shapes' summed margins, enables the boolean
/// early exit (stop as soon as a plane proves the core distance exceeds it) and sets the distance tolerance
/// relative to the distance the caller gets (core distance − margin). Returns the status on the cores; `v` is the
/// final closest point, `size_out` the larger of |t_rel| and the largest |w| seen (the scale for the touching
/// tolerance), `lower_out` the best
/// separating-plane bound the boolean test found (0 for distance queries, which do not need it). `boolean` (a
/// template parameter, so that each query's loop carries none of the other's bookkeeping: 3.6 % fewer instructions
/// per warm distance query in the coherent benchmark) selects the early exit. `bounded` (a distance query with a
/// bound, `gjk_distance_within`): the distance loop with the boolean's plane exit, taken only where the plane proves
/// the core distance exceeds early_exit_margin + `beyond` (the caller's bound); below that the same loop goes on to
/// the distance, so a pair that needs one pays for one search.
///
/// The boolean exit tests every support point, the very first one included: for any direction u, w = s_D(−u)
/// minimises u·x over D, so u·w/|u| > 0 is a separating plane whether or not u is the closest point of the
/// current simplex (distant pairs are then decided by one support pair). A coherent pair's cached direction, the
/// one that separated it the frame before, is tested before the loop (`warm_direction_separates`).
template <bool use_cores, bool boolean, bool bounded = false, SupportMapped A, SupportMapped B>
inline GjkStatus gjk_loop(const A& a, const B& b, const Transform<typename A::Scalar>& rel,
                          const GjkSettings<typename A::Scalar>& settings, GjkCache<typename A::Scalar>* cache,
                          typename A::Scalar early_exit_margin, GjkSimplex<typename A::Scalar>& s,
                          Vec3<typename A::Scalar>& v, typename A::Scalar& size_out, int& iterations,
                          typename A::Scalar& lower_out, typename A::Scalar exit_quality = 0,
                          GjkVertex<typename A::Scalar>* exit_support = nullptr,
                          bool* tolerance_met = nullptr, typename A::Scalar beyond = 0) noexcept {
    using S = typename A::Scalar;
    using Solver = SimplexSolver<S>;
    constexpr bool plane_exit = boolean || bounded;
    const S eps = std::numeric_limits<S>::epsilon();
    // The level a plane must clear for the early exit: the margins, plus a bounded query's bound (0 for a boolean,
    // the same bits as the margins alone).
    const S exit_level = early_exit_margin + beyond;
    // The start direction from the centres; a warm start replaces it with its rebuilt simplex's closest point
    // (for the shapes the cache's points belong to the rebuild usually succeeds; centre_direction if not).
    const bool rebuilds = cache && cache->size > 0 && cache->shape_a == static_cast<const void*>(&a) &&
                          cache->shape_b == static_cast<const void*>(&b);
    auto centre_direction = [&] {
        v = Vec3<S>(Vec3<S>(a.center()) - place(rel, Vec3<S>(b.center())));
        if (!(v.squaredNorm() > S(0)) || !v.allFinite()) v = Vec3<S>::UnitX();
    };
    if (rebuilds) v = Vec3<S>::UnitX();
    else centre_direction();
    s.size = 0;
    // Locals, written out on return: as reference parameters they were reloaded after every store through
    // the simplex (possible aliasing), putting a sqrt/division latency on each iteration's critical path.
    // size2: the largest |w|² seen (tolerances scale with its root, taken only where needed: a sqrt per
    // iteration on the path to the next support query showed in the profile).
    S size2 = S(0), lower_bound = S(0);
    // The touching tolerance (256ε·size) scales with |t_rel| too, the magnitude whose rounding B's points carry in
    // A's frame: |w| alone vanishes on a touching pair, and a warm start has only support points near the contact
    // (the seeded hard-case count found warm booleans and distances answering "separated" at 1e-16 of the size
    // where long double proves the overlap). The convergence test keeps the largest |w| (size2).
    const S mag2 = rel.t.squaredNorm();
    auto tol2 = [&] { return std::max(size2, mag2); };
    // A boolean query waiting for a better plane (exit_quality) keeps the best one's direction and support point:
    // it is the answer if the query ends before (best_saved; otherwise the exit's own direction is the best).
    Vec3<S> best_u = v;
    GjkVertex<S> best_x;
    // Read only when best_saved; zeroed in the boolean loop all the same, where GCC cannot see that through the
    // inlined exits (-Wmaybe-uninitialized).
    if constexpr (plane_exit) best_x.w = best_x.a = best_x.b = best_x.d = best_x.b_local = Vec3<S>::Zero();
    bool best_saved = false;
    // v·w and |v|² at the loop's exits on |v| (gap test, repeated point, no progress): the plane bound there.
    S exit_vw = S(0), exit_vv = S(0);
    // Whether a separated exit's gap |v|² − v·w, the bracket on the distance, is within 4× the tolerance:
    // false where the loop stopped on the rounding floor (the gap test's second term), a repeated point or a
    // step without progress with a wider bracket. gjk_query refines those in long double. (Brackets of 1–1.6×
    // the tolerance are common on close polytope pairs, ~2 % of the coherent near-touching frames; refining
    // them would cost microseconds for nothing the 1e-9 target needs.)
    bool met = true;
    // Hill-climbing starts for polyhedra: each support query starts at the previous one's vertex (under
    // coherence last frame's, from the cache), instead of the hull's fixed seeds.
    std::uint32_t hints[2] = {cache ? cache->hint_a : std::uint32_t(-1), cache ? cache->hint_b : std::uint32_t(-1)};
    auto done = [&](GjkStatus st) CDKIT_LAMBDA_INLINE {
        size_out = std::sqrt(tol2());
        // A separated boolean reports the plane of its best bound (the exit's own direction may be weaker
        // when a warm start waited for exit_quality).
        if (plane_exit && st == GjkStatus::separated && best_saved && exit_support) {
            v = best_u;
            *exit_support = best_x;
        }
        lower_out = lower_bound;
        if (cache) { cache->hint_a = hints[0]; cache->hint_b = hints[1]; }
        if (tolerance_met) *tolerance_met = met;
        return st;
    };
    iterations = 0;
    S vv = std::numeric_limits<S>::infinity();
    GjkStatus status = GjkStatus::max_iterations;
    // Boolean exit on the support point x found along −u: true when the plane proves separation.
    // With `exit_quality` κ > 0 (warm-started queries) a plane is only accepted once its gap is at least κ
    // times the upper bound |v| − margin, so the direction cached for the next frame keeps a margin under
    // coherent motion instead of barely separating (the cached direction's own test, warm_direction_separates
    // before the loop, is exempt).
    auto separates = [&](const Vec3<S>& u, const GjkVertex<S>& x) {
        const S uw = u.dot(x.w);
        // No positive plane now and none before: nothing to test (skips the sqrt and division on the
        // iterations that do not separate).
        if (!(uw > S(0)) && !(lower_bound > S(0))) return false;
        if constexpr (bounded && !boolean) {
            // A bounded query keeps only bounds above its level (nothing else decides anything there), so that the
            // iterations of a pair within the bound pay three products, not a sqrt and a division each.
            if (!(lower_bound > S(0)) && !(uw * uw > exit_level * exit_level * u.squaredNorm())) return false;
        }
        const S un = u.norm();
        if (!(un > S(0))) return false;
        const S bound = uw / un;
        const bool improved = bound > lower_bound;
        if (improved) lower_bound = bound;
        // Same threshold as gjk_query applies to the early exit.
        const S size = std::sqrt(tol2());
        if (!(plane_exit && lower_bound > exit_level + settings.touch_factor * eps * std::max(size, exit_level)))
            return false;
        if (exit_quality > S(0) && !(s.size > 0 && lower_bound - exit_level >= exit_quality * (un - exit_level))) {
            if (improved) {
                best_u = u;
                best_x = x;
                best_saved = true;
            }
            return false;
        }
        if (improved) best_saved = false;
        return true;
    };
    auto store = [&](const GjkVertex<S>* first) {
        if (!cache) return;
        int k = 0;
        auto put = [&](const GjkVertex<S>& x) {
            cache->directions[std::size_t(k)] = x.d;
            cache->point_a[std::size_t(k)] = x.a;
            cache->point_b[std::size_t(k)] = x.b_local;
            ++k;
        };
        if (first) put(*first);
        for (int i = 0; i < s.size && k < 4; ++i) put(s.v[std::size_t(i)]);
        cache->size = k;
        cache->shape_a = &a;
        cache->shape_b = &b;
    };
    auto note_exit = [&](const GjkVertex<S>& x) {
        exit_vw = v.dot(x.w);
        exit_vv = vv;
    };
    typename Solver::Sel sel;
    if (cache && cache->size > 0) {
        const int n = std::min(cache->size, 4);
        for (int i = 0; i < n; ++i) {
            // Built in the simplex's free slot (s.size < 4 here), which it joins by ++s.size.
            GjkVertex<S>& x = s.v[std::size_t(s.size)];
            if (rebuilds) {
                // The stored support points under the new poses: points of D, no support query.
                x.a = cache->point_a[std::size_t(i)];
                x.b_local = cache->point_b[std::size_t(i)];
                x.b = place(rel, x.b_local);
                x.w = x.a - x.b;
                x.d = cache->directions[std::size_t(i)];
            } else {
                x = minkowski_support<use_cores>(a, b, rel, cache->directions[std::size_t(i)], hints);
            }
            if (!x.w.allFinite()) continue;
            size2 = std::max(size2, x.w.squaredNorm());
            bool dup = false;
            for (int j = 0; j < s.size; ++j) dup = dup || s.v[std::size_t(j)].w == x.w;
            if (!dup) ++s.size;
        }
        if (s.size > 0) {
            Solver::select(s, sel);
            if (sel.inside) {
                // Four points of D around the origin: overlap, without a support query when reused.
                v.setZero();
                store(nullptr);
                return done(GjkStatus::intersecting);
            }
            Solver::apply(s, sel);
            v = sel.v;
            vv = v.squaredNorm();
            if (!(vv > S(0))) { s.size = 0; vv = std::numeric_limits<S>::infinity(); v = Vec3<S>::UnitX(); }
        } else if (rebuilds) {
            centre_direction();
        }
    }
    int refinements = 0;
    for (int it = 0; it < settings.max_iterations; ++it) {
        iterations = it + 1;
        const Vec3<S> d = -v;
        // Written straight into the simplex's free slot (s.size ≤ 3 here); it joins the simplex by ++s.size.
        GjkVertex<S>& x = s.v[std::size_t(s.size)];
        minkowski_support_into<use_cores>(x, a, b, rel, d, hints);
        if (!all_finite(x.w)) { status = GjkStatus::degenerate; break; }
        size2 = std::max(size2, x.w.squaredNorm());
        if (plane_exit && separates(v, x)) {
            status = GjkStatus::separated;
            if (exit_support) *exit_support = x;
            store(&x);
            return done(status);
        }
        if (s.size > 0) {
            // v·w/|v| is a lower bound on the distance (the plane through w orthogonal to v supports D; the
            // boolean test above already kept it). Converged: the gap between upper bound |v| and the lower
            // bound is within tolerance (the ε·|v|·size term is the rounding floor of v·w).
            if (gap_converged(vv, v.dot(x.w), early_exit_margin, size2, settings.rel_tolerance)) {
                note_exit(x);
                status = GjkStatus::separated;
                break;
            }
            bool duplicate = false;
            for (int i = 0; i < s.size; ++i) duplicate = duplicate || s.v[std::size_t(i)].w == x.w;
            if (duplicate) {
                note_exit(x);
                // The support point is already in the simplex: in exact arithmetic v is optimal. When the
                // gap test failed, v may be off by the sub-simplex step's rounding (see below): recompute it
                // in the wider type and, if it moved, query again from there.
                if constexpr (!std::is_same_v<S, wider_t<S>>) {
                    if (refinements < 8 && s.size > 1) {
                        ++refinements;
                        if (refine_step(s, s.size - 1, sel, true) && sel.v != v) {
                            Solver::apply(s, sel);
                            v = sel.v;
                            vv = v.squaredNorm();
                            continue;
                        }
                    }
                }
                status = GjkStatus::separated;
                break;
            }
        }
        const int old_size = s.size++;
        Solver::select(s, sel);
        if constexpr (!std::is_same_v<S, wider_t<S>>) {
            // A distance query must not trust a triangle step whose normal rounding (ε over the sine of the
            // triangle's angle, times the lever arm) exceeds a tenth of the tolerance: on curved surfaces the
            // support points cluster into slivers, and the step then puts v *below* the simplex — |v| is no
            // longer an upper bound and the gap test passes short of the distance (issue 5: up to 7e-7
            // relative on close cones). Redo that step in the wider type (x87 long double for double).
            if (!boolean && !sel.inside && sel.size == 3 &&
                triangle_step_unreliable(s, sel, S(0.1) * settings.rel_tolerance * sel.v.norm()))
                refine_step(s, s.size - 1, sel, true);
        }
        if (sel.inside) { v.setZero(); status = GjkStatus::intersecting; break; }
        const S nvv = sel.v.squaredNorm();
        if (!(nvv == nvv)) { s.size = old_size; status = GjkStatus::degenerate; break; }
        const S tiny2 = settings.touch_factor * settings.touch_factor * eps * eps * tol2();  // (256·ε·size)²
        if (nvv <= tiny2) { Solver::apply(s, sel); v = sel.v; status = GjkStatus::touching; break; }
        if (old_size > 0 && !(nvv < vv)) {
            note_exit(x);
            // No progress. On curved shapes the support points cluster and the sub-simplex step loses
            // accuracy before the gap test is met (a sliver triangle's normal is rounding noise: issue 5 found
            // |v| up to 1e-7 relative *below* the distance). Redo this step and the previous simplex's in a
            // wider type: if the new point does make progress, continue; otherwise stop with the previous
            // simplex's accurate closest point. Rare (only at this exit), so the wider arithmetic is cheap.
            if constexpr (!std::is_same_v<S, wider_t<S>>) {
                if (refinements < 8) {
                    ++refinements;
                    if (refine_step(s, old_size, sel)) {
                        Solver::apply(s, sel);
                        v = sel.v;
                        vv = v.squaredNorm();
                        continue;
                    }
                    s.size = old_size;
                    if (refine_step(s, old_size - 1, sel, true)) { Solver::apply(s, sel); v = sel.v; }
                    status = GjkStatus::separated;
                    break;
                }
            }
            // Rounding floor reached; keep the better previous simplex (untouched by select).
            s.size = old_size;
            status = GjkStatus::separated;
            break;
        }
        Solver::apply(s, sel);
        v = sel.v;
        vv = nvv;
    }
    if (status == GjkStatus::separated) {
        // "Separated" claims a plane: v·w/|v| above the touching tolerance for some support point w (van den
        // Bergen 1999's lower bound; compared in squares, no sqrt without margins). An exit on |v| without one
        // (near contact, where the double sub-simplex step can misplace v) is decided by certify_exit.
        const S tf = settings.touch_factor * eps;
        S thr2 = tf * tf * tol2();
        if (early_exit_margin > S(0)) {
            const S thr = early_exit_margin + tf * std::max(std::sqrt(tol2()), early_exit_margin);
            thr2 = thr * thr;
        }
        const bool proven = (lower_bound > S(0) && lower_bound * lower_bound > thr2) ||
                            (exit_vw > S(0) && exit_vw * exit_vw > thr2 * exit_vv);
        if (tolerance_met)
            met = exit_vv - exit_vw <= S(4) * gap_tolerance(exit_vv, early_exit_margin, settings.rel_tolerance);
        if (!proven && v.squaredNorm() > thr2) {
            const CertifiedExit<S> c = certify_exit<use_cores>(a, b, rel, settings, early_exit_margin, s, v, size2,
                                                               lower_bound, hints[0], hints[1]);
            status = c.status;
            v = c.v;
            size2 = c.size2;
            lower_bound = c.lower;
            iterations += c.iterations;
            best_saved = false;
            if (status == GjkStatus::separated && exit_support) *exit_support = c.sep;
        }
    }
    store(nullptr);
    return done(status);
}

/// The result of a query from the loop's outcome: status, distance, normal and world-frame points. `plane_exit`
/// (a boolean, or a bounded distance query whose bound is `beyond`): a separated outcome whose plane bound clears
/// the margins + `beyond` is answered with that plane (the bound as distance), not with |v|. Returns whether it was.
template <SupportMapped A, SupportMapped B>
inline bool gjk_finish(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                       const GjkSettings<typename A::Scalar>& settings, GjkResult<typename A::Scalar>& r,
                       GjkStatus st, const Vec3<typename A::Scalar>& v, typename A::Scalar size,
                       typename A::Scalar lower, const GjkVertex<typename A::Scalar>& sep, bool plane_exit,
                       typename A::Scalar beyond = 0) noexcept {
    using S = typename A::Scalar;
    const S margin = margin_of(a) + margin_of(b);
    const S tiny = settings.touch_factor * std::numeric_limits<S>::epsilon() * std::max(size, margin);
    if (plane_exit && st == GjkStatus::separated && lower > margin + beyond + tiny) {
        r.status = GjkStatus::separated;
        r.distance = lower - margin;
        const S vn = v.norm();
        if (vn > S(0)) {
            const Vec3<S> n = -v / vn;
            r.normal = rotate(pose_a.R, n);  // a separating direction, A towards B
            if (sep.w.allFinite()) {
                // The supporting points of that plane: A's extreme towards B and B's towards A.
                r.point_a = place(pose_a, pushed_out(a, sep.a, n));
                r.point_b = place(pose_a, pushed_out(b, sep.b, Vec3<S>(-n)));
            }
        }
        return true;
    }
    if (st == GjkStatus::intersecting) {  // no witness points: the result reports none for an overlap
        r.status = GjkStatus::intersecting;
        r.distance = S(0);
        return false;
    }
    // Witness points on the cores, then push them out by the margins along the normal.
    SimplexSolver<S>::sliver_weights(r.simplex, v);
    Vec3<S> pa = Vec3<S>::Zero(), pb = Vec3<S>::Zero();
    for (int i = 0; i < r.simplex.size; ++i) {
        pa += r.simplex.lambda[std::size_t(i)] * r.simplex.v[std::size_t(i)].a;
        pb += r.simplex.lambda[std::size_t(i)] * r.simplex.v[std::size_t(i)].b;
    }
    S core = v.norm();
    Vec3<S> n = core > S(0) ? Vec3<S>(-v / core) : Vec3<S>::Zero();  // from A towards B
    S dist = core - margin;
    r.point_a = place(pose_a, pushed_out(a, pa, n));
    r.point_b = place(pose_a, pushed_out(b, pb, Vec3<S>(-n)));
    r.normal = rotate(pose_a.R, n);
    if (st == GjkStatus::max_iterations || st == GjkStatus::degenerate) {
        r.status = st;
        r.distance = std::max(dist, S(0));
        return false;
    }
    if (st == GjkStatus::touching || std::abs(dist) <= tiny) {
        r.status = margin > S(0) && dist < -tiny ? GjkStatus::intersecting : GjkStatus::touching;
        r.distance = S(0);
        return false;
    }
    r.status = dist > S(0) ? GjkStatus::separated : GjkStatus::intersecting;
    r.distance = std::max(dist, S(0));
    return false;
}

/// `certify_separation` and then `gjk_finish`, out of line: the arguments are copies and the relative pose is
/// formed again, so that the callers' loop state (v, size², the hints, their relative pose) never has its address
/// taken — passing `rel` by reference cost the cold boolean's box cells 8–13 % (it was reloaded after stores).
template <SupportMapped A, SupportMapped B>
CDKIT_COLD_PATH void finish_certified(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                      const Transform<typename A::Scalar>& pose_b,
                                      const GjkSettings<typename A::Scalar>& settings,
                                      GjkResult<typename A::Scalar>& r, Vec3<typename A::Scalar> v,
                                      typename A::Scalar size2, typename A::Scalar lower, std::uint32_t hint_a,
                                      std::uint32_t hint_b, bool boolean) noexcept {
    using S = typename A::Scalar;
    const Transform<S> rel = relative_pose(pose_a, pose_b);
    std::uint32_t hints[2] = {hint_a, hint_b};
    GjkVertex<S> sep;
    sep.w.setConstant(std::numeric_limits<S>::quiet_NaN());
    const GjkStatus st = certify_separation<true>(a, b, rel, settings, margin_of(a) + margin_of(b), r.simplex, v,
                                                  size2, lower, sep, hints, r.iterations);
    gjk_finish(a, pose_a, b, settings, r, st, v, std::sqrt(size2), lower, sep, boolean);
}

}  // namespace detail
}  // namespace cdkit
