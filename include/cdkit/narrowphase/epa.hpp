#pragma once
/// \file EPA: penetration depth, normal and contact points of two intersecting convex shapes.
///
/// Expanding Polytope Algorithm: van den Bergen, "Proximity queries and penetration depth computation
/// on 3D game objects", GDC 2001 (and "Collision Detection in Interactive 3D Environments", 2003, §4.3.6).
/// The penetration depth is the distance from the origin to the boundary of D = A − B; EPA starts from a
/// polytope inside D that contains the origin (GJK's final tetrahedron) and repeatedly pushes out its face
/// nearest to the origin with the support point of D along that face's normal, until the support point
/// no longer moves the face (within tolerance).
///
/// Robustness (the failure modes reported for libccd/FCL: hangs, NaN normals, "origin outside polytope"):
/// fixed-capacity storage and an iteration cap guarantee termination without allocation; every new face
/// is checked (finite, non-zero normal, origin not clearly outside) before the polytope is changed, and on
/// failure the best face found so far is returned with status `degenerate`; flat Minkowski differences
/// (coplanar triangles, touching shapes) return depth 0 with status `touching`. Shapes with margins
/// whose cores are apart are solved exactly from GJK's core distance without EPA.

#include <cdkit/narrowphase/gjk.hpp>

#include <array>

namespace cdkit {

/// Settings of `penetration`.
template <class S = double> struct EpaSettings {
    int max_iterations = 128;
    /// Stop when the support along the nearest face's normal is within rel_tolerance·depth of the face.
    S rel_tolerance = std::max(S(1e-8), S(64) * std::numeric_limits<S>::epsilon());
    GjkSettings<S> gjk{};
};

/// Result of `penetration`.
template <class S> struct PenetrationResult {
    /// separated (see distance), touching, intersecting (depth valid), or max_iterations/degenerate (depth
    /// and normal hold the best estimate found, finite).
    GjkStatus status = GjkStatus::degenerate;
    int gjk_iterations = 0, epa_iterations = 0;
    /// Penetration depth ≥ 0: the shortest translation of B that separates the shapes has this length.
    /// EPA brackets it: `depth` is D's support value along `normal` (moving B by depth·normal separates the
    /// shapes: an upper bound, the least one EPA met), `depth_lower` the distance of the polytope's nearest face
    /// (inside D: a lower bound, in exact arithmetic). Converged (intersecting) they agree within
    /// rel_tolerance; after max_iterations or degenerate the bracket says how far off the estimate can be.
    S depth = S(0), depth_lower = S(0);
    /// Separation distance when the shapes are separated (then depth is 0).
    S distance = S(0);
    /// Unit direction (world frame) along which B must move by `depth` to separate from A (from A to B).
    Vec3<S> normal = Vec3<S>::Zero();
    /// World-frame witness points: point_a on A's boundary, point_b on B's boundary, point_a − point_b =
    /// depth·normal when intersecting (the deepest points); the closest points when separated.
    Vec3<S> point_a = Vec3<S>::Zero(), point_b = Vec3<S>::Zero();
    bool colliding = false;  ///< `is_colliding(status)`: touching or intersecting
};

namespace detail {

/// A polytope face. No default member initialisers, on purpose: the polytope's 320 faces and the 320 fresh
/// faces of every iteration were constructed (zeroed) on each query, ~30 KB of stores that cost more than
/// the whole EPA on boxes; faces are only read once `epa_make_face` wrote them (index < nf). A face that
/// must start out dead is value-initialised (`EpaFace<S> f{}`).
template <class S> struct EpaFace {
    std::array<int, 3> v;
    Vec3<S> n;
    S dist;
    bool alive;
};

template <class S> struct EpaPolytope {
    static constexpr int max_vertices = 160;
    static constexpr int max_faces = 2 * max_vertices;  // Euler: F = 2V − 4 for a closed triangulation
    std::array<GjkVertex<S>, max_vertices> vert;          // only [0, nv) and [0, nf) are ever read
    std::array<EpaFace<S>, max_faces> face;
    int nv = 0, nf = 0;
};

/// Builds face (i, j, k) with an outward normal; false when the normal is degenerate.
template <class S> inline bool epa_make_face(const EpaPolytope<S>& P, int i, int j, int k, EpaFace<S>& f) noexcept {
    const Vec3<S>& a = P.vert[std::size_t(i)].w;
    Vec3<S> n = (P.vert[std::size_t(j)].w - a).cross(P.vert[std::size_t(k)].w - a);
    S len = n.norm();
    if (!(len > S(0)) || !std::isfinite(len)) return false;
    f.v = {i, j, k};
    f.n = n / len;
    f.dist = f.n.dot(a);
    f.alive = true;
    return std::isfinite(f.dist);
}

/// Grows the start simplex `s` (points of D with the origin in or on it) to a tetrahedron by supports
/// along directions away from its affine hull. Returns false when D is flat (depth 0).
template <bool use_cores, SupportMapped A, SupportMapped B>
inline bool epa_grow(const A& a, const B& b, const Transform<typename A::Scalar>& rel, GjkSimplex<typename A::Scalar>& s,
                     typename A::Scalar tiny) noexcept {
    using S = typename A::Scalar;
    auto sup = [&](const Vec3<S>& d) { return minkowski_support<use_cores>(a, b, rel, d); };
    if (s.size == 0) { s.v[0] = sup(Vec3<S>::UnitX()); s.size = 1; }
    if (s.size == 1) {
        int best = -1;
        S best_d = tiny;
        GjkVertex<S> cand[6];
        for (int k = 0; k < 6; ++k) {
            Vec3<S> d = Vec3<S>::Zero();
            d[k / 2] = (k % 2) ? S(-1) : S(1);
            cand[k] = sup(d);
            S dd = (cand[k].w - s.v[0].w).norm();
            if (dd > best_d) { best_d = dd; best = k; }
        }
        if (best < 0) return false;
        s.v[1] = cand[best];
        s.size = 2;
    }
    if (s.size == 2) {
        Vec3<S> e = s.v[1].w - s.v[0].w;
        // Two directions orthogonal to the segment, from the axis least aligned with it.
        int k;
        e.cwiseAbs().minCoeff(&k);
        Vec3<S> u = e.cross(Vec3<S>::Unit(k)).normalized(), w = e.normalized().cross(u);
        int best = -1;
        S best_d = tiny;
        GjkVertex<S> cand[6];
        const Vec3<S> dirs[6] = {u, -u, w, -w, (u + w), -(u + w)};
        for (int i = 0; i < 6; ++i) {
            cand[i] = sup(dirs[i]);
            Vec3<S> r = cand[i].w - s.v[0].w;
            S dd = (r - e * (r.dot(e) / e.squaredNorm())).norm();
            if (dd > best_d) { best_d = dd; best = i; }
        }
        if (best < 0) return false;
        s.v[2] = cand[best];
        s.size = 3;
    }
    if (s.size == 3) {
        Vec3<S> n = (s.v[1].w - s.v[0].w).cross(s.v[2].w - s.v[0].w);
        S len = n.norm();
        if (!(len > S(0))) return false;
        n /= len;
        GjkVertex<S> p = sup(n), q = sup(Vec3<S>(-n));
        S dp = n.dot(p.w - s.v[0].w), dq = -n.dot(q.w - s.v[0].w);
        if (std::max(dp, dq) <= tiny) return false;
        s.v[3] = dp >= dq ? p : q;
        s.size = 4;
    }
    return true;
}

template <bool use_cores, SupportMapped A, SupportMapped B>
inline GjkStatus epa_run(const A& a, const B& b, const Transform<typename A::Scalar>& rel,
                         const GjkSimplex<typename A::Scalar>& start, const EpaSettings<typename A::Scalar>& settings,
                         typename A::Scalar size, EpaFace<typename A::Scalar>& best, EpaPolytope<typename A::Scalar>& P,
                         int& iterations, EpaFace<typename A::Scalar>& upper_face,
                         typename A::Scalar& upper) noexcept {
    using S = typename A::Scalar;
    const S eps = std::numeric_limits<S>::epsilon();
    const S tiny = settings.gjk.touch_factor * eps * size;
    for (int i = 0; i < 4; ++i) P.vert[std::size_t(i)] = start.v[std::size_t(i)];
    P.nv = 4;
    P.nf = 0;
    static constexpr int tet[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {0, 2, 3, 1}, {1, 3, 2, 0}};
    for (const auto& t : tet) {
        EpaFace<S> f;
        if (!epa_make_face(P, t[0], t[1], t[2], f)) return GjkStatus::touching;  // flat start
        if (f.n.dot(P.vert[std::size_t(t[3])].w) > f.dist) {                     // orient outward
            epa_make_face(P, t[0], t[2], t[1], f);
        }
        // The origin may lie outside the start tetrahedron (beyond tiny): GJK's "inside" test and a grown lower
        // simplex carry rounding, and nested needles end GJK on a triangle through the origin. The loop below
        // then pushes out the faces that have the origin beyond them first (the most negative distance is the
        // nearest face) until the polytope holds it — the count found 12k such starts in 100k nested, touching
        // and coincident cases, all answered "degenerate" before.
        P.face[std::size_t(P.nf++)] = f;
    }
    iterations = 0;
    best = P.face[0];
    for (int it = 0; it < settings.max_iterations; ++it) {
        iterations = it + 1;
        int fi = -1;
        for (int i = 0; i < P.nf; ++i)
            if (P.face[std::size_t(i)].alive && (fi < 0 || P.face[std::size_t(i)].dist < P.face[std::size_t(fi)].dist))
                fi = i;
        if (fi < 0) return GjkStatus::degenerate;
        best = P.face[std::size_t(fi)];
        GjkVertex<S> w = minkowski_support<use_cores>(a, b, rel, best.n);
        if (!w.w.allFinite()) return GjkStatus::degenerate;
        S wd = best.n.dot(w.w);
        // D's support value along a face normal bounds the depth from above: keep the least (the answer's
        // normal), so an exit before convergence still reports a translation that separates.
        if (wd < upper) {
            upper = wd;
            upper_face = best;
        }
        const bool outside = best.dist < -tiny;  // the origin lies beyond this face: not enclosed yet
        if (outside && wd <= tiny) return GjkStatus::touching;  // and beyond D's supporting plane: no overlap
        if (!outside && wd - best.dist <= settings.rel_tolerance * std::abs(best.dist) + tiny)
            return GjkStatus::intersecting;
        if (P.nv >= P.max_vertices) return GjkStatus::max_iterations;
        // Horizon: directed edges of visible faces whose twin is not visible.
        std::array<std::array<int, 2>, EpaPolytope<S>::max_faces> edges;
        int ne = 0;
        std::array<int, EpaPolytope<S>::max_faces> visible;
        int nvis = 0;
        for (int i = 0; i < P.nf; ++i) {
            const auto& f = P.face[std::size_t(i)];
            if (!f.alive) continue;
            if (i != fi && !(f.n.dot(w.w) - f.dist > tiny)) continue;
            visible[std::size_t(nvis++)] = i;
            for (int k = 0; k < 3; ++k) {
                int e0 = f.v[std::size_t(k)], e1 = f.v[std::size_t((k + 1) % 3)];
                int found = -1;
                for (int m = 0; m < ne; ++m)
                    if (edges[std::size_t(m)][0] == e1 && edges[std::size_t(m)][1] == e0) { found = m; break; }
                if (found >= 0) edges[std::size_t(found)] = edges[std::size_t(--ne)];
                else if (ne < int(edges.size())) edges[std::size_t(ne++)] = {e0, e1};
                else return GjkStatus::degenerate;
            }
        }
        // Check the new faces before touching the polytope, so a failure leaves `best` meaningful.
        int nw = P.nv;
        P.vert[std::size_t(nw)] = w;
        std::array<EpaFace<S>, EpaPolytope<S>::max_faces> fresh;
        if (ne < 3 || P.nf - nvis + ne > P.max_faces) return GjkStatus::degenerate;
        for (int m = 0; m < ne; ++m) {
            if (!epa_make_face(P, edges[std::size_t(m)][0], edges[std::size_t(m)][1], nw, fresh[std::size_t(m)]))
                return GjkStatus::degenerate;
            // A new face nearer than the current best (beyond rounding) means the origin fell outside.
            if (!outside && fresh[std::size_t(m)].dist < best.dist - tiny - settings.rel_tolerance * best.dist)
                return GjkStatus::degenerate;
        }
        P.nv = nw + 1;
        for (int i = 0; i < nvis; ++i) P.face[std::size_t(visible[std::size_t(i)])].alive = false;
        int m = 0;
        for (int i = 0; i < P.nf && m < ne; ++i)
            if (!P.face[std::size_t(i)].alive) P.face[std::size_t(i)] = fresh[std::size_t(m++)];
        while (m < ne) P.face[std::size_t(P.nf++)] = fresh[std::size_t(m++)];
    }
    return GjkStatus::max_iterations;
}


/// EPA from simplex `s` on the cores (`use_cores`, then `margin` = sum of margins is added to the depth)
/// or on the full shapes; fills `r` (world frame).
template <bool use_cores, SupportMapped A, SupportMapped B>
inline PenetrationResult<typename A::Scalar> epa_stage(const A& a, const B& b, const Transform<typename A::Scalar>& rel,
                                                       const Transform<typename A::Scalar>& pose_a,
                                                       GjkSimplex<typename A::Scalar> s,
                                                       const EpaSettings<typename A::Scalar>& settings,
                                                       typename A::Scalar margin, typename A::Scalar ma,
                                                       typename A::Scalar mb, PenetrationResult<typename A::Scalar> r) noexcept {
    using S = typename A::Scalar;
    const S eps = std::numeric_limits<S>::epsilon();
    S size = margin;
    for (int i = 0; i < s.size; ++i) size = std::max(size, s.v[std::size_t(i)].w.norm());
    const S tiny = settings.gjk.touch_factor * eps * std::max(size, S(1e-30));
    auto finish_flat = [&](const Vec3<S>& n_local, const Vec3<S>& pa_core, const Vec3<S>& pb_core) {
        // Zero-volume overlap of the cores: depth is the margins alone (0 without margins).
        if (margin > S(0)) {
            r.status = GjkStatus::intersecting;
            r.depth = r.depth_lower = margin;
            r.normal = pose_a.R * n_local;
            r.point_a = pose_a * Vec3<S>(pa_core + ma * n_local);
            r.point_b = pose_a * Vec3<S>(pb_core - mb * n_local);
        } else {
            r.status = GjkStatus::touching;
            r.normal = pose_a.R * n_local;
            r.point_a = pose_a * pa_core;
            r.point_b = pose_a * pb_core;
        }
        return r;
    };
    if (s.size < 4 && !epa_grow<use_cores>(a, b, rel, s, tiny)) {
        // Normal of the flat set: the plane normal of a triangle, else any direction orthogonal to it.
        Vec3<S> n = Vec3<S>::UnitX();
        if (s.size >= 3) {
            Vec3<S> c = (s.v[1].w - s.v[0].w).cross(s.v[2].w - s.v[0].w);
            if (c.norm() > S(0)) n = c.normalized();
        } else if (s.size == 2) {
            Vec3<S> e = s.v[1].w - s.v[0].w;
            int k;
            e.cwiseAbs().minCoeff(&k);
            Vec3<S> c = e.cross(Vec3<S>::Unit(k));
            if (c.norm() > S(0)) n = c.normalized();
        }
        return finish_flat(n, s.v[0].a, s.v[0].b);
    }
    EpaPolytope<S> P;
    EpaFace<S> best{}, face{};  // dead until epa_run finds a face
    S upper = std::numeric_limits<S>::infinity();
    GjkStatus es = epa_run<use_cores>(a, b, rel, s, settings, size, best, P, r.epa_iterations, face, upper);
    if (es == GjkStatus::touching || !best.alive || !best.n.allFinite()) {
        // Touching: a flat start (no face), or the origin found beyond D's supporting plane along a face's
        // normal (that normal).
        if (es == GjkStatus::touching)
            return finish_flat(best.alive && best.n.allFinite() ? best.n : Vec3<S>::UnitX(), s.v[0].a, s.v[0].b);
        r.status = GjkStatus::degenerate;
        return r;
    }
    if (!face.alive || !(upper < std::numeric_limits<S>::infinity())) {  // no support query made it: best alone
        face = best;
        upper = best.dist;
    }
    const S depth = std::max(upper, S(0)), lower = std::clamp(best.dist, S(0), depth);
    // Barycentric coordinates of the origin's projection onto the answer's face give the witness points; B's is
    // moved on by the bracket's width, so that point_a − point_b = depth·normal.
    const auto& A0 = P.vert[std::size_t(face.v[0])];
    const auto& B0 = P.vert[std::size_t(face.v[1])];
    const auto& C0 = P.vert[std::size_t(face.v[2])];
    Vec3<S> p = face.n * face.dist;
    S area = face.n.dot((B0.w - A0.w).cross(C0.w - A0.w));
    S la = face.n.dot((B0.w - p).cross(C0.w - p)), lb = face.n.dot((C0.w - p).cross(A0.w - p));
    Vec3<S> pa = A0.a, pb = A0.b;
    if (area > S(0) && std::isfinite(la / area) && std::isfinite(lb / area)) {
        la /= area;
        lb /= area;
        S lc = S(1) - la - lb;
        pa = la * A0.a + lb * B0.a + lc * C0.a;
        pb = la * A0.b + lb * B0.b + lc * C0.b;
    }
    pb -= (depth - face.dist) * face.n;
    if (margin == S(0) && depth <= tiny) {
        r.status = GjkStatus::touching;
        r.depth = r.depth_lower = S(0);
    } else {
        r.status = es;
        r.depth = depth + margin;
        r.depth_lower = lower + margin;
    }
    r.normal = pose_a.R * face.n;
    r.point_a = pose_a * Vec3<S>(pa + ma * face.n);
    r.point_b = pose_a * Vec3<S>(pb - mb * face.n);
    return r;
}

}  // namespace detail

namespace detail {

/// `penetration` without its long-double retry.
template <SupportMapped A, SupportMapped B>
[[nodiscard]] PenetrationResult<typename A::Scalar> penetration_query(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    const EpaSettings<typename A::Scalar>& settings) noexcept {
    using S = typename A::Scalar;
    PenetrationResult<S> r;
    const Transform<S> rel = pose_a.inverse() * pose_b;
    const S ma = margin_of(a), mb = margin_of(b);
    // 1. GJK on the cores.
    GjkSimplex<S> s;
    Vec3<S> v;
    S size, lower;
    // The margins as gjk_distance passes them: they set the touching threshold that a "separated" exit must
    // beat with a proven plane (with 0, capsule–cone pairs overlapping by 1e-12 of their size came out apart).
    GjkStatus st = detail::gjk_loop<true, false>(a, b, rel, settings.gjk, nullptr, ma + mb, s, v, size, r.gjk_iterations,
                                          lower);
    const S eps = std::numeric_limits<S>::epsilon();
    S tiny = settings.gjk.touch_factor * eps * std::max(size, ma + mb);
    if (st == GjkStatus::separated && ma + mb > S(0) && !(lower > tiny)) {
        // Within the margins GJK stops once the overlap is decided, and |v| is then no core distance: a
        // 10⁵-long capsule through a hull came out "cores 1.3e-8 apart" (depth = the radius alone, 1/17 of the
        // true depth). Without a plane proving the cores apart, decide on the cores alone.
        int more = 0;
        st = detail::gjk_loop<true, false>(a, b, rel, settings.gjk, nullptr, S(0), s, v, size, more, lower);
        r.gjk_iterations += more;
        tiny = settings.gjk.touch_factor * eps * std::max(size, ma + mb);
    }
    if (st != GjkStatus::intersecting && st != GjkStatus::touching && !(v.norm() <= tiny)) {
        // Cores apart: exact answer from the core distance and the margins.
        Vec3<S> pa = Vec3<S>::Zero(), pb = Vec3<S>::Zero();
        for (int i = 0; i < s.size; ++i) {
            pa += s.lambda[std::size_t(i)] * s.v[std::size_t(i)].a;
            pb += s.lambda[std::size_t(i)] * s.v[std::size_t(i)].b;
        }
        S core = v.norm();
        Vec3<S> n = -v / core;
        S dist = core - ma - mb;
        r.normal = pose_a.R * n;
        r.point_a = pose_a * Vec3<S>(pa + ma * n);
        r.point_b = pose_a * Vec3<S>(pb - mb * n);
        if (std::abs(dist) <= tiny) r.status = GjkStatus::touching;
        else if (dist > 0) { r.status = st == GjkStatus::separated ? GjkStatus::separated : st; r.distance = dist; }
        else { r.status = GjkStatus::intersecting; r.depth = r.depth_lower = -dist; }
        return r;
    }
    // 2. The cores touch or overlap. With margins, the depth is the cores' depth plus the margins
    //    (EPA on the cores, exact for spheres/capsules); without, EPA on the full shapes. EPA starts from
    //    GJK's final tetrahedron (it contains the origin), grown to a tetrahedron when GJK ended on a
    //    lower simplex (the origin then lies on it).
    const S margin = ma + mb;
    if (margin > S(0)) return detail::epa_stage<true>(a, b, rel, pose_a, s, settings, margin, ma, mb, r);
    // Shapes without margins have their full shapes as cores: the loop above already ran on them (the same support
    // queries, hinted where a polyhedron has hints), so its simplex starts EPA without a second GJK run.
    if constexpr (!HasMargin<A> && !HasMargin<B>) {
        return detail::epa_stage<false>(a, b, rel, pose_a, s, settings, S(0), S(0), S(0), r);
    }
    int it2 = 0;
    st = detail::gjk_loop<false, false>(a, b, rel, settings.gjk, nullptr, S(0), s, v, size, it2, lower);
    r.gjk_iterations += it2;
    tiny = settings.gjk.touch_factor * eps * size;
    if (st == GjkStatus::separated && v.norm() > tiny) {
        r.status = GjkStatus::touching;  // full shapes apart while cores touch: only rounding; depth 0
        return r;
    }
    return detail::epa_stage<false>(a, b, rel, pose_a, s, settings, S(0), S(0), S(0), r);
}

/// A `degenerate` EPA in double, run again in `wider_t` on the shapes widened (`widened_shape`), in world axes
/// with the origin at A's (as `refine_near_contact`), with S's touching tolerance. Degenerate exits are rounding
/// (a new face nearer than the nearest one, a zero normal): shallow overlaps of shapes 1e5 apart in size, where
/// D's polytope is a pancake around the origin. The wider answer replaces `r` when it converged or brackets the
/// depth tighter. Out of line: rare.
template <SupportMapped A, SupportMapped B>
CDKIT_COLD_PATH void refine_penetration(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                        const Transform<typename A::Scalar>& pose_b,
                                        const EpaSettings<typename A::Scalar>& settings,
                                        PenetrationResult<typename A::Scalar>& r) noexcept {
    using S = typename A::Scalar;
    using W = wider_t<S>;
    const auto wa = widened_shape(a);
    const auto wb = widened_shape(b);
    const WideningFrame<S> frame(pose_a, pose_b);
    EpaSettings<W> ws;
    ws.max_iterations = settings.max_iterations;
    ws.rel_tolerance = W(settings.rel_tolerance);
    ws.gjk = widened_settings(settings.gjk);  // as GJK's refine_near_contact
    const PenetrationResult<W> w = penetration_query(wa, frame.pose_a, wb, frame.pose_b, ws);
    const bool finite = std::isfinite(w.depth) && std::isfinite(w.depth_lower) && w.normal.allFinite() &&
                        w.point_a.allFinite() && w.point_b.allFinite();
    if (!finite || w.status == GjkStatus::separated || w.status == GjkStatus::touching) return;
    const bool converged = w.status == GjkStatus::intersecting;
    if (!converged && !(W(w.depth) - w.depth_lower < W(r.depth) - W(r.depth_lower))) return;
    r.status = w.status;
    r.depth = S(w.depth);
    r.depth_lower = std::min(S(w.depth_lower), r.depth);
    r.normal = w.normal.template cast<S>();
    r.point_a = Vec3<W>(w.point_a + frame.origin).template cast<S>();
    r.point_b = Vec3<W>(w.point_b + frame.origin).template cast<S>();
    r.gjk_iterations += w.gjk_iterations;
    r.epa_iterations += w.epa_iterations;
}

}  // namespace detail

/// Penetration query: separation distance when apart, otherwise penetration depth, normal and deepest
/// points (world frame). Const, noexcept, thread-safe, never NaN: every outcome carries finite numbers.
/// In double, an EPA that degenerates (rounding) is run again in long double (`detail::refine_penetration`).
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
[[nodiscard]] inline PenetrationResult<typename A::Scalar> penetration(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    const EpaSettings<typename A::Scalar>& settings = {}) noexcept {
    using S = typename A::Scalar;
    PenetrationResult<S> r = detail::penetration_query(a, pose_a, b, pose_b, settings);
    if constexpr (detail::refines_near_contact<S>) {
        if (r.status == GjkStatus::degenerate) detail::refine_penetration(a, pose_a, b, pose_b, settings, r);
    }
    r.colliding = is_colliding(r.status);
    return r;
}

namespace detail {

/// True when EPA can start from `g`'s final simplex (`penetration` with a GjkResult): shapes without margins (their
/// cores are the full shapes EPA walks on; with margins the depth needs the cores' distance, which an early boolean
/// exit inside the margins does not give), GJK proved the overlap with four finite points of D around the origin
/// (every exit on `sel.inside`; a containment, bounding-ball or touching-proof exit leaves fewer).
template <SupportMapped A, SupportMapped B>
[[nodiscard]] inline bool epa_starts_from(const GjkResult<typename A::Scalar>& g) noexcept {
    if constexpr (HasMargin<A> || HasMargin<B>) {
        return false;
    } else {
        if (g.status != GjkStatus::intersecting || g.simplex.size != 4) return false;
        for (int i = 0; i < 4; ++i) {
            const GjkVertex<typename A::Scalar>& x = g.simplex.v[std::size_t(i)];
            if (!x.w.allFinite() || !x.a.allFinite() || !x.b.allFinite()) return false;
        }
        return true;
    }
}

/// EPA from GJK's final simplex `s` (four points of D around the origin, A's frame, placed by
/// `relative_pose(pose_a, pose_b)` as gjk_query places them; `epa_starts_from` holds), with `penetration`'s
/// long-double retry of a degenerate answer. For shapes with margins, which never start from a simplex, it is
/// `penetration_query` (so that the precompiled instances of every built-in pair stay small).
template <SupportMapped A, SupportMapped B>
[[nodiscard]] PenetrationResult<typename A::Scalar> penetration_from_simplex(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    const GjkSimplex<typename A::Scalar>& s, const EpaSettings<typename A::Scalar>& settings) noexcept {
    using S = typename A::Scalar;
    if constexpr (HasMargin<A> || HasMargin<B>) {
        (void)s;
        return penetration_query(a, pose_a, b, pose_b, settings);
    } else {
        // The relative pose GJK's points were placed with, so that EPA's new support points and the simplex's lie
        // in one frame.
        const Transform<S> rel = relative_pose(pose_a, pose_b);
        PenetrationResult<S> r =
            epa_stage<false>(a, b, rel, pose_a, s, settings, S(0), S(0), S(0), PenetrationResult<S>{});
        if constexpr (refines_near_contact<S>) {
            if (r.status == GjkStatus::degenerate) refine_penetration(a, pose_a, b, pose_b, settings, r);
        }
        return r;
    }
}

}  // namespace detail

/// Penetration query after a GJK query of the same pair at the same poses (`gjk`, from `gjk_intersect`,
/// `gjk_distance` or `gjk_distance_within`, cold or warm): where GJK proved the overlap with a tetrahedron of
/// A − B around the origin (`detail::epa_starts_from`), EPA starts from that final simplex (the one GjkResult
/// keeps for it) and no GJK runs again (`gjk_iterations` 0); otherwise the same as `penetration` without it. A caller that decides the pair with
/// GJK first (contact_manifold, the World's contacts) so pays for GJK once. The answer is EPA's from another start
/// than `penetration`'s own GJK would give: the same depth within `rel_tolerance`, not the same bits.
/// Const, noexcept, thread-safe, never NaN.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
[[nodiscard]] inline PenetrationResult<typename A::Scalar> penetration(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    const GjkResult<typename A::Scalar>& gjk, const EpaSettings<typename A::Scalar>& settings = {}) noexcept {
    if (!detail::epa_starts_from<A, B>(gjk)) return penetration(a, pose_a, b, pose_b, settings);
    PenetrationResult<typename A::Scalar> r =
        detail::penetration_from_simplex(a, pose_a, b, pose_b, gjk.simplex, settings);
    r.colliding = is_colliding(r.status);
    return r;
}

}  // namespace cdkit

// The built-in shapes' EPA queries in double are compiled into libcdkit (precompiled_queries.hpp).
#ifndef CDKIT_NO_PRECOMPILED_QUERIES
namespace cdkit {
CDKIT_FOR_EACH_BUILTIN_PAIR(CDKIT_PENETRATION_QUERY_INSTANCE, extern)
}  // namespace cdkit
#endif
