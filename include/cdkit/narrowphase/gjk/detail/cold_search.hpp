#pragma once
/// \file The cold boolean query (`gjk_intersect` without a cache): the pre-tests, then a lean GJK loop with
/// Nesterov momentum on the search direction in its first iterations (Montaut, Le Lidec, Petrik, Sivic, Carpentier,
/// "Collision detection accelerated: an optimization perspective", RSS 2022) and squared plane tests.

#include <cdkit/narrowphase/gjk/detail/pretests.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace cdkit {
namespace detail {

/// Cold boolean query (no cache): the loop of `gjk_loop` reduced to what a yes/no answer needs, with the
/// early exit's result built in place. The separation test compares squares (v·w > (margin + tol)·|v| needs
/// no sqrt; the margin-free case none at all), the one sqrt and division are paid when a plane is found; no
/// lower-bound bookkeeping, no cache, no wide-type refinement in the loop. The certificates are those of
/// gjk_loop: a support point w along −v with v·w > (margin + tol)·|v| proves separation for any v; four points
/// of D around the origin prove overlap. Since every support point was given the plane test, an exit on |v|
/// (gap test, repeated point, no progress) beyond the tolerance has no plane: `certify_separation` decides it.
/// Out of line from the bounding-ball pre-test (`gjk_intersect_cold`, below): inlined there, the body's register
/// pressure made GCC load both rotations up front and spill them in shuffled copies, which the pairs the balls
/// decide paid for nothing (a hull pair: 355 instructions per query, 220 with the split; 52 → 17–28 ns in P3's
/// hull1000 distant cell). vw_dir = c_a − c_b, the world centres' difference, and vv = |vw_dir|², the
/// pre-test's values, as the first direction.
template <SupportMapped A, SupportMapped B>
CDKIT_NOINLINE void gjk_intersect_cold_search(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                              const Transform<typename A::Scalar>& pose_b,
                                              const GjkSettings<typename A::Scalar>& settings,
                                              Vec3<typename A::Scalar> vw_dir, typename A::Scalar vv,
                                              GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    using Solver = SimplexSolver<S>;
    const S eps = std::numeric_limits<S>::epsilon();
    const S ma = margin_of(a), mb = margin_of(b), margin = ma + mb;
    const S tf = settings.touch_factor * eps;
    GjkSimplex<S>& s = r.simplex;
    s.size = 0;
    // Hill-climbing hints between iterations: a polyhedron tries the previous support vertex with one scan of
    // its neighbours and otherwise climbs from its direction table (ConvexPolyhedron::support_index).
    std::uint32_t hints[2] = {std::uint32_t(-1), std::uint32_t(-1)};
    auto separates = [&](S vw, S vv, S size2) { return plane_separates_squared(vw, vv, size2, margin, tf); };
    // First iteration in the world frame, along the line between the centres (a separating direction for
    // most distant pairs): one support pair decides them without the relative pose, and the exit's normal
    // and supporting points are already world-frame (no transforms back).
    if (!(vv > S(0)) || !(vv <= std::numeric_limits<S>::max())) { vw_dir = Vec3<S>::UnitX(); vv = S(1); }
    const Vec3<S> da = rotate_back(pose_a.R, neg(vw_dir));  // A's support direction, A's frame
    const WorldPair<S> pair = world_plane_step(a, pose_a, b, pose_b, vw_dir, vv, da, tf, hints, r);
    switch (pair.step) {
        case WorldStep::separated: r.iterations = 1; return;
        case WorldStep::non_finite:
            r.iterations = 1;
            s.size = 0;
            r.status = GjkStatus::degenerate;
            r.distance = S(0);
            return;
        case WorldStep::open: break;
    }
    const Vec3<S> sa = pair.sa, sb = pair.sb;
    S size2 = pair.size2;
    // Otherwise the loop, in A's frame, from that support point.
    const Transform<S> rel = relative_pose(pose_a, pose_b);
    {
        GjkVertex<S>& x = s.v[0];
        x.a = sa;
        x.b_local = sb;
        x.b = place(rel, sb);
        x.w = minus(x.a, x.b);
        x.d = da;
        s.size = 1;
        s.lambda[0] = S(1);
    }
    // From here on in A's frame: the rounding of w is that of A's and B's local points and of rel's translation,
    // so a plane or a touching verdict is judged against those magnitudes too (|w| alone vanishes on touching
    // pairs). Computed when a plane test passes or the loop ends, not on every round.
    auto with_magnitudes = [&](S sz2) { return std::max(std::max(sz2, norm2(sa)), std::max(norm2(sb), norm2(rel.t))); };
    // A's first support point in B's frame, for B's containment test and candidate axis.
    Vec3<S> a_in_b = Vec3<S>::Zero();
    if constexpr (HasContainmentTest<B> || HasCandidateAxes<B>) a_in_b = rotate_back(rel.R, minus(sa, rel.t));
    Vec3<S> axis_a = Vec3<S>::Zero(), axis_b = Vec3<S>::Zero();  // face planes a point location found (A's, B's frame)
    if constexpr (HasBoundingBalls<A> && HasBoundingBalls<B> && (HasPointLocation<A> || HasPointLocation<B>)) {
        if (settings.containment_test && containment_decides_walking(a, pose_a, b, pose_b, s.v[0], a_in_b, tf, hints[0],
                                                                     hints[1], axis_a, axis_b)) {
            r.iterations = 1;
            s.size = 0;
            r.status = GjkStatus::intersecting;
            r.distance = S(0);
            return;
        }
    } else if constexpr (HasBoundingBalls<A> && HasBoundingBalls<B> &&
                         (HasContainmentTest<A> || HasContainmentTest<B>)) {
        if (settings.containment_test && containment_decides(a, pose_a, b, pose_b, s.v[0], a_in_b, tf)) {
            r.iterations = 1;
            s.size = 0;
            r.status = GjkStatus::intersecting;
            r.distance = S(0);
            return;
        }
    }
    Vec3<S> v = s.v[0].w;
    vv = norm2(v);
    if (!(vv > tf * tf * size2)) {
        r.iterations = 1;
        gjk_finish(a, pose_a, b, settings, r, GjkStatus::touching, v, std::sqrt(size2), S(0), s.v[0], true);
        return;
    }
    int candidate_pairs = 0;  // support pairs spent on candidate axes, reported in the iteration count
    if constexpr (HasCandidateAxes<A> || HasCandidateAxes<B> || HasPointLocation<A> || HasPointLocation<B>) {
        if (settings.candidate_axes && candidate_axes_decide(a, pose_a, b, rel, s.v[0], a_in_b, axis_a, axis_b, size2,
                                                             tf, candidate_pairs, r))
            return;
    }
    int it = 1;
    typename Solver::Sel sel;
    GjkStatus status = GjkStatus::max_iterations;
    // Nesterov momentum (Montaut et al., RSS 2022, "Collision detection accelerated: an optimization
    // perspective"): query along d_k = δ_k d_{k−1} + (1 − δ_k) y_k with
    // y_k = δ_k v_k + (1 − δ_k) w_k (w_k the last support point), δ_k = (k + 1)/(k + 3), instead of along v_k.
    // The boolean certificates do not depend on the direction (a plane is proven by the direction actually
    // queried; overlap by four points of D around the origin), so momentum only changes the work. When it
    // stalls (a repeated point, or a point that does not shorten v) it is switched off and the query goes on
    // as plain GJK, whose convergence tests need w to be the support along −v.
    // Not on margin pairs: their cores are points and segments (spheres, capsules), polytopes on which plain
    // GJK ends in two or three iterations; momentum took close capsule pairs from 2.3 to 3.0.
    bool momentum = settings.momentum_iterations > 1 && !(margin > S(0));
    // Solver::apply moving only the fields this loop and gjk_finish read (a, b, w; not d and b_local, which
    // only the cache uses and which this loop does not write).
    auto apply_lean = [&s](const typename Solver::Sel& r_) {
        for (int k = 0; k < r_.size; ++k) {
            const std::size_t from = std::size_t(r_.idx[std::size_t(k)]);
            if (from != std::size_t(k)) {
                s.v[std::size_t(k)].a = s.v[from].a;
                s.v[std::size_t(k)].b = s.v[from].b;
                s.v[std::size_t(k)].w = s.v[from].w;
            }
            s.lambda[std::size_t(k)] = r_.lambda[std::size_t(k)];
        }
        s.size = r_.size;
    };
    Vec3<S> d_prev = Vec3<S>(-da), w_last = s.v[0].w;
    while (it < settings.max_iterations) {
        ++it;
        Vec3<S> d = v;
        if (momentum && it > settings.momentum_iterations) momentum = false;
        if (momentum) {
            const S k = S(it - 1);
            const S delta = (k + S(1)) / (k + S(3));
            const S c = S(1) - delta;
            for (int k3 = 0; k3 < 3; ++k3) d[k3] = delta * d_prev[k3] + c * (delta * v[k3] + c * w_last[k3]);
        }
        GjkVertex<S>& x = s.v[std::size_t(s.size)];
        {
            // As minkowski_support_into without the two fields only the cache reads (d, b_local).
            const Vec3<S> nd = neg(d);
            x.a = core_support_hinted(a, nd, hints);
            x.b = place(rel, Vec3<S>(core_support_hinted(b, rotate_back(rel.R, d), hints + 1)));
            x.w = minus(x.a, x.b);
        }
        const S w2 = norm2(x.w);
        if (!(w2 <= std::numeric_limits<S>::max())) { status = GjkStatus::degenerate; break; }  // NaN or inf
        size2 = std::max(size2, w2);
        const S dw = dot3(d, x.w);
        const S dd = momentum ? norm2(d) : vv;
        if (separates(dw, dd, size2) && separates(dw, dd, with_magnitudes(size2))) {
            const S inv = S(1) / std::sqrt(dd);
            const Vec3<S> n = Vec3<S>(-d[0] * inv, -d[1] * inv, -d[2] * inv);  // A towards B, in A's frame
            r.iterations = it + candidate_pairs;
            r.status = GjkStatus::separated;
            r.distance = dw * inv - margin;
            r.normal = rotate(pose_a.R, n);
            r.point_a = place(pose_a, plus_scaled(x.a, ma, n));
            r.point_b = place(pose_a, plus_scaled(x.b, -mb, n));
            return;
        }
        // Each round's support pair gets the containment test too where both shapes have a cheap one and curved
        // cores (cylinders, cones: their rounds are many on shallow overlaps; on boxes it cost more than it saved).
        if constexpr (HasBoundingBalls<A> && HasBoundingBalls<B> && !HasPointLocation<A> && !HasPointLocation<B> &&
                      !HasPolytopeCore<A> && !HasPolytopeCore<B> && HasContainmentTest<A> && HasContainmentTest<B>) {
            if (settings.containment_test && loop_containment_decides(a, pose_a, b, pose_b, rel, x, tf)) {
                r.iterations = it + candidate_pairs;
                r.status = GjkStatus::intersecting;
                r.distance = S(0);
                s.size = 0;
                return;
            }
        }
        bool duplicate = false;
        for (int i = 0; i < s.size; ++i) {
            const Vec3<S>& q = s.v[std::size_t(i)].w;
            duplicate = duplicate || (q[0] == x.w[0] && q[1] == x.w[1] && q[2] == x.w[2]);
        }
        if (momentum) {
            d_prev = d;
            if (duplicate) { momentum = false; continue; }
        } else {
            // Converged on |v| (v a point of D): as gjk_loop; gjk_finish then decides touching / separated.
            if (gap_converged(vv, dw, margin, size2, settings.rel_tolerance)) {
                status = GjkStatus::separated;
                break;
            }
            if (duplicate) { status = GjkStatus::separated; break; }
        }
        const int old_size = s.size++;
        if (s.size == 4) Solver::tetrahedron_newest_last(s, sel);
        else Solver::select(s, sel);
        if (sel.inside) {  // overlap proven: the result gjk_finish would build, without its call
            r.iterations = it + candidate_pairs;
            r.status = GjkStatus::intersecting;
            r.distance = S(0);
            return;
        }
        const S nvv = norm2(sel.v);
        if (!(nvv == nvv)) { s.size = old_size; status = GjkStatus::degenerate; break; }
        if (nvv <= tf * tf * size2) { apply_lean(sel); v = sel.v; status = GjkStatus::touching; break; }
        if (!(nvv < vv)) {
            s.size = old_size;
            if (momentum) { momentum = false; continue; }
            status = GjkStatus::separated;
            break;
        }
        w_last = s.v[std::size_t(old_size)].w;
        apply_lean(sel);
        v = sel.v;
        vv = nvv;
    }
    r.iterations = it + candidate_pairs;
    size2 = with_magnitudes(size2);
    // gjk_finish decides an overlap of the margins on |v| (|v| − margin below −tol), which needs v on the simplex:
    // on a sliver triangle the double step can put it well inside (a capsule of radius 1e-9 beside a 1e-11 wide
    // box, 1e-9 of the size apart: |v| 7.0e-10 in double, 1.07e-9 in long double, and "intersecting" for a
    // separated pair; found by the seeded hard-case count). Where the step's rounding could reach across the
    // margin, it is redone in the wider type. Only on these exits, and only for margins and a final triangle.
    if constexpr (!std::is_same_v<S, wider_t<S>>) {
        if (margin > S(0) && s.size == 3 && status != GjkStatus::degenerate) {
            const S across = std::sqrt(norm2(v)) - margin;
            if (sliver_step_may_reach(s, across * across)) {
                typename Solver::Sel fin;
                if (refine_step(s, 2, fin, true)) {
                    v = fin.v;
                    vv = norm2(v);
                    // Beyond the margins now: claimed only with a plane, as for any exit on |v| (below).
                    if (status == GjkStatus::touching && separation_claimed(vv, margin, tf, size2))
                        status = GjkStatus::separated;
                }
            }
        }
    }
    // Every support plane was tested above with gjk_finish's threshold, so a "separated" exit here (gap test,
    // repeated point, no progress) has no plane behind it: certify it unless |v| already lies within the
    // tolerance (then gjk_finish answers touching, or intersecting inside the margins: no separation claimed).
    if (status == GjkStatus::separated && separation_claimed(vv, margin, tf, size2)) {
        finish_certified(a, pose_a, b, pose_b, settings, r, v, size2, S(0), hints[0], hints[1], true);
        return;
    }
    GjkVertex<S> none;
    none.w.setConstant(std::numeric_limits<S>::quiet_NaN());
    gjk_finish(a, pose_a, b, settings, r, status, v, std::sqrt(size2), S(0), none, true);
    if (r.status == GjkStatus::touching) prove_touching_overlap(a, b, Transform<S>(rel), r);
}

/// Cold boolean query (no cache): the bounding-ball pre-test (`GjkSettings::bounding_ball_test`), then
/// `gjk_intersect_cold_search` from the centre line.
template <SupportMapped A, SupportMapped B>
inline void gjk_intersect_cold(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                               const Transform<typename A::Scalar>& pose_b,
                               const GjkSettings<typename A::Scalar>& settings,
                               GjkResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    const Vec3<S> ca = world_center(a, pose_a), cb = world_center(b, pose_b);
    const Vec3<S> delta = minus(ca, cb);
    const S dd = norm2(delta);
    if constexpr (HasBoundingBalls<A> && HasBoundingBalls<B>) {
        if (settings.bounding_ball_test && dd <= std::numeric_limits<S>::max() &&
            bounding_ball_decides(a, pose_a, b, pose_b, ca, cb, delta, dd,
                                  settings.touch_factor * std::numeric_limits<S>::epsilon(), r))
            return;
    }
    gjk_intersect_cold_search(a, pose_a, b, pose_b, settings, delta, dd, r);
}

}  // namespace detail
}  // namespace cdkit
