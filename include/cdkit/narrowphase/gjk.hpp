#pragma once
/// \file GJK: boolean intersection and separation distance between two support-mapped convex shapes.
///
/// Gilbert, Johnson, Keerthi, "A fast procedure for computing the distance between complex objects in
/// three-dimensional space", IEEE J. Robotics and Automation 4(2), 1988; with the robustness measures of
/// van den Bergen, "A fast and robust GJK implementation for collision detection of convex objects",
/// J. Graphics Tools 4(2), 1999 (termination on the lower bound v·w, progress check, duplicate support
/// points) and the degenerate-simplex discussion of Montaut et al., "Collision detection accelerated: an
/// optimization perspective", RSS 2022.
///
/// GJK walks the Minkowski difference D = A − B (never built): the shapes intersect iff 0 ∈ D and their
/// distance is min_{x∈D} |x|. Each iteration queries the support of D opposite to the current closest
/// point v, adds it to a simplex of ≤ 4 points, and replaces v by the simplex's point closest to the
/// origin (computed with Voronoi-region tests, reducing the simplex to the face/edge/vertex that holds v).
/// Shapes with a margin (spheres, capsules, `Inflated`) run on their cores; the margins are subtracted at
/// the end, which makes sphere and capsule results exact rather than asymptotic.
///
/// All queries are noexcept, const on their inputs and thread-safe; the only mutable state is the
/// caller-owned `GjkCache`.

#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/support.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace cdkit {

/// Outcome of a GJK query.
enum class GjkStatus {
    separated,       ///< distance > 0 (beyond the touching tolerance)
    touching,        ///< distance within the touching tolerance of 0: contact, no proven overlap volume
    intersecting,    ///< the shapes overlap (origin strictly inside the Minkowski difference / margins overlap)
    max_iterations,  ///< iteration cap reached; the result holds the best bound found
    degenerate,      ///< numerical trouble (non-finite support point); the result holds the best bound found
};

/// Tuning of a GJK query. Tolerances are relative; GJK scales them with the size of the shapes.
template <class S = double> struct GjkSettings {
    int max_iterations = 128;
    /// Stop when the distance upper bound |v| is within rel_tolerance·|v| of the lower bound.
    S rel_tolerance = std::max(S(1e-10), S(64) * std::numeric_limits<S>::epsilon());
    /// Distances within touch_factor·ε·(size of D) of zero count as touching.
    S touch_factor = S(256);
};

/// Caller-owned warm start (van den Bergen 1999 §5, "frame coherence"): the search directions that
/// produced the last final simplex, in A's frame. The next query re-evaluates the supports along them
/// (with the new poses) to seed its simplex, so coherent motion usually needs one or two iterations.
/// Keep one per shape pair; a query reads and updates it. Not shared between threads.
template <class S = double> struct GjkCache {
    std::array<Vec3<S>, 4> directions{};
    int size = 0;
};

/// One simplex vertex: w = a − b with a ∈ A, b ∈ B, found as the support of A − B along d
/// (all in A's frame).
template <class S> struct GjkVertex {
    Vec3<S> w, a, b, d;
};

/// The simplex GJK ended with, its barycentric weights and size (1..4), in A's local frame.
template <class S> struct GjkSimplex {
    std::array<GjkVertex<S>, 4> v{};
    std::array<S, 4> lambda{};
    int size = 0;
};

/// Result of `gjk_distance` / `gjk_intersect`.
template <class S> struct GjkResult {
    GjkStatus status = GjkStatus::degenerate;
    int iterations = 0;
    /// Separation distance (≥ 0; 0 when touching or intersecting). `gjk_intersect` only sets it when it
    /// had to converge; after an early "separated" exit it holds a lower bound (> 0).
    S distance = S(0);
    /// Closest points on A and on B in the world frame (valid when separated or touching).
    Vec3<S> point_a = Vec3<S>::Zero(), point_b = Vec3<S>::Zero();
    /// Unit direction from A towards B in the world frame (valid when separated; after gjk_intersect's early
    /// exit it is a separating direction, not necessarily the closest-point direction).
    Vec3<S> normal = Vec3<S>::Zero();
    /// Final simplex on the cores, in A's local frame (used by EPA).
    GjkSimplex<S> simplex{};
    [[nodiscard]] bool colliding() const noexcept {
        return status == GjkStatus::touching || status == GjkStatus::intersecting;
    }
};

namespace detail {

/// Closest point to the origin on segment/triangle/tetrahedron `s`; reduces `s` to the smallest
/// sub-simplex holding that point and sets its barycentric weights. Returns true when the origin lies
/// inside a full-dimensional tetrahedron (then `v` is zero and `s` is unchanged).
template <class S> class SimplexSolver {
public:
    static void point(GjkSimplex<S>& s, Vec3<S>& v) noexcept {
        s.size = 1;
        s.lambda[0] = S(1);
        v = s.v[0].w;
    }

    static void segment(GjkSimplex<S>& s, Vec3<S>& v) noexcept {
        const Vec3<S>& p0 = s.v[0].w;
        Vec3<S> d = s.v[1].w - p0;
        S dd = d.squaredNorm();
        S t = dd > S(0) ? -p0.dot(d) / dd : S(0);
        if (!(t > S(0))) { point(s, v); return; }
        if (t >= S(1)) { s.v[0] = s.v[1]; point(s, v); return; }
        s.size = 2;
        s.lambda[0] = S(1) - t;
        s.lambda[1] = t;
        v = p0 + t * d;
    }

    /// Voronoi-region walk over a triangle (Ericson, "Real-Time Collision Detection", 2005, §5.1.5).
    static void triangle(GjkSimplex<S>& s, Vec3<S>& v) noexcept {
        const Vec3<S>& a = s.v[0].w;
        const Vec3<S>& b = s.v[1].w;
        const Vec3<S>& c = s.v[2].w;
        Vec3<S> ab = b - a, ac = c - a;
        S d1 = -ab.dot(a), d2 = -ac.dot(a);
        if (d1 <= S(0) && d2 <= S(0)) { point(s, v); return; }
        S d3 = -ab.dot(b), d4 = -ac.dot(b);
        if (d3 >= S(0) && d4 <= d3) { s.v[0] = s.v[1]; point(s, v); return; }
        S vc = d1 * d4 - d3 * d2;
        if (vc <= S(0) && d1 >= S(0) && d3 <= S(0)) { s.size = 2; segment(s, v); return; }
        S d5 = -ab.dot(c), d6 = -ac.dot(c);
        if (d6 >= S(0) && d5 <= d6) { s.v[0] = s.v[2]; point(s, v); return; }
        S vb = d5 * d2 - d1 * d6;
        if (vb <= S(0) && d2 >= S(0) && d6 <= S(0)) { s.v[1] = s.v[2]; segment(s, v); return; }
        S va = d3 * d6 - d5 * d4;
        if (va <= S(0) && (d4 - d3) >= S(0) && (d5 - d6) >= S(0)) {
            s.v[0] = s.v[2];  // edge b–c
            segment(s, v);
            return;
        }
        S denom = va + vb + vc;
        Vec3<S> n = ab.cross(ac);
        S nn = n.squaredNorm();
        if (!(denom > S(0)) || !(nn > S(0))) {
            // Degenerate (collinear) triangle that the region tests did not resolve: best edge.
            best_of_edges(s, v);
            return;
        }
        s.size = 3;
        s.lambda[1] = vb / denom;
        s.lambda[2] = vc / denom;
        s.lambda[0] = S(1) - s.lambda[1] - s.lambda[2];
        // The plane projection is more accurate than the barycentric sum when v is small against a, b, c.
        v = n * (n.dot(a) / nn);
    }

    /// Returns true when the origin is inside the tetrahedron.
    static bool tetrahedron(GjkSimplex<S>& s, Vec3<S>& v) noexcept {
        static constexpr int faces[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {0, 2, 3, 1}, {1, 3, 2, 0}};
        const S eps = std::numeric_limits<S>::epsilon();
        // A (numerically) flat tetrahedron cannot prove the origin inside: face normals built from nearly
        // coincident points are noise. Rounding in the coordinates is relative to their magnitude, so the
        // test compares the volume with ε·scale³ (treating a thin-but-real tetrahedron as flat is safe: it
        // only sends the search to the faces).
        S scale = S(0);
        for (int i = 0; i < 4; ++i) scale = std::max(scale, s.v[i].w.cwiseAbs().maxCoeff());
        S vol6 = (s.v[1].w - s.v[0].w).dot((s.v[2].w - s.v[0].w).cross(s.v[3].w - s.v[0].w));
        const bool flat = !(std::abs(vol6) > S(256) * eps * scale * scale * scale);
        bool outside[4];
        bool any = false;
        for (int f = 0; f < 4; ++f) {
            const Vec3<S>& p = s.v[faces[f][0]].w;
            Vec3<S> n = (s.v[faces[f][1]].w - p).cross(s.v[faces[f][2]].w - p);
            S side_l = n.dot(s.v[faces[f][3]].w - p);
            S side_o = -n.dot(p);
            outside[f] = flat || !(side_o * side_l > S(0));
            any = any || outside[f];
        }
        if (!any) {
            v.setZero();
            return true;
        }
        GjkSimplex<S> best{};
        Vec3<S> best_v = Vec3<S>::Zero();
        S best_d = std::numeric_limits<S>::infinity();
        for (int f = 0; f < 4; ++f) {
            if (!outside[f]) continue;
            GjkSimplex<S> t{};
            t.v[0] = s.v[faces[f][0]];
            t.v[1] = s.v[faces[f][1]];
            t.v[2] = s.v[faces[f][2]];
            t.size = 3;
            Vec3<S> tv;
            triangle(t, tv);
            S d = tv.squaredNorm();
            if (d < best_d) { best_d = d; best = t; best_v = tv; }
        }
        s = best;
        v = best_v;
        return false;
    }

    /// Dispatch on s.size (2..4) after a vertex was appended.
    static bool solve(GjkSimplex<S>& s, Vec3<S>& v) noexcept {
        switch (s.size) {
            case 1: point(s, v); return false;
            case 2: segment(s, v); return false;
            case 3: triangle(s, v); return false;
            default: return tetrahedron(s, v);
        }
    }

private:
    static void best_of_edges(GjkSimplex<S>& s, Vec3<S>& v) noexcept {
        static constexpr int edges[3][2] = {{0, 1}, {1, 2}, {0, 2}};
        S best_d = std::numeric_limits<S>::infinity();
        GjkSimplex<S> best{};
        Vec3<S> best_v = Vec3<S>::Zero();
        for (const auto& e : edges) {
            GjkSimplex<S> t{};
            t.v[0] = s.v[e[0]];
            t.v[1] = s.v[e[1]];
            t.size = 2;
            Vec3<S> tv;
            segment(t, tv);
            if (tv.squaredNorm() < best_d) { best_d = tv.squaredNorm(); best = t; best_v = tv; }
        }
        s = best;
        v = best_v;
    }
};

/// Support of D = A − B on the cores (or full shapes when `use_cores` is false), in A's frame;
/// `rel` maps B's frame into A's.
template <bool use_cores, SupportMapped A, SupportMapped B>
inline GjkVertex<typename A::Scalar> minkowski_support(const A& a, const B& b,
                                                     const Transform<typename A::Scalar>& rel,
                                                     const Vec3<typename A::Scalar>& d) noexcept {
    using S = typename A::Scalar;
    GjkVertex<S> x;
    Vec3<S> db = -(rel.R.transpose() * d);
    if constexpr (use_cores) {
        x.a = core_support(a, d);
        x.b = rel * Vec3<S>(core_support(b, db));
    } else {
        x.a = a.support(d);
        x.b = rel * Vec3<S>(b.support(db));
    }
    x.w = x.a - x.b;
    x.d = d;
    return x;
}

/// The GJK loop on D in A's frame. `early_exit_margin` ≥ 0 enables the boolean early exit: stop as
/// soon as a plane proves the core distance exceeds it. Returns the status on the cores; `v` is the
/// final closest point, `size` the largest |w| seen (the scale for tolerances).
template <bool use_cores, SupportMapped A, SupportMapped B>
inline GjkStatus gjk_loop(const A& a, const B& b, const Transform<typename A::Scalar>& rel,
                          const GjkSettings<typename A::Scalar>& settings, GjkCache<typename A::Scalar>* cache,
                          bool boolean, typename A::Scalar early_exit_margin, GjkSimplex<typename A::Scalar>& s,
                          Vec3<typename A::Scalar>& v, typename A::Scalar& size, int& iterations,
                          typename A::Scalar& lower_bound) noexcept {
    using S = typename A::Scalar;
    const S eps = std::numeric_limits<S>::epsilon();
    v = Vec3<S>(Vec3<S>(a.center()) - rel * Vec3<S>(b.center()));
    if (!(v.squaredNorm() > S(0)) || !v.allFinite()) v = Vec3<S>::UnitX();
    s.size = 0;
    size = S(0);
    lower_bound = S(0);
    iterations = 0;
    S vv = std::numeric_limits<S>::infinity();
    GjkStatus status = GjkStatus::max_iterations;
    if (cache && cache->size > 0) {
        // Warm start: rebuild the last simplex from its search directions under the new poses.
        for (int i = 0; i < std::min(cache->size, 4); ++i) {
            GjkVertex<S> x = minkowski_support<use_cores>(a, b, rel, cache->directions[std::size_t(i)]);
            bool dup = !x.w.allFinite();
            for (int j = 0; j < s.size; ++j) dup = dup || s.v[j].w == x.w;
            if (!dup) { s.v[s.size++] = x; size = std::max(size, x.w.norm()); }
        }
        if (s.size > 0) {
            Vec3<S> nv;
            if (SimplexSolver<S>::solve(s, nv)) {
                v.setZero();
                return GjkStatus::intersecting;  // cache still holds the same (useful) directions
            }
            v = nv;
            vv = v.squaredNorm();
            if (!(vv > S(0))) { s.size = 0; vv = std::numeric_limits<S>::infinity(); v = Vec3<S>::UnitX(); }
        }
    }
    for (int it = 0; it < settings.max_iterations; ++it) {
        iterations = it + 1;
        GjkVertex<S> x = minkowski_support<use_cores>(a, b, rel, Vec3<S>(-v));
        if (!x.w.allFinite()) { status = GjkStatus::degenerate; break; }
        size = std::max(size, x.w.norm());
        const S tiny = settings.touch_factor * eps * size;
        if (s.size > 0) {
            S vn = std::sqrt(vv);
            S vw = v.dot(x.w);
            // v·w/|v| is a lower bound on the distance (the plane through w orthogonal to v supports D).
            lower_bound = std::max(lower_bound, vw / vn);
            if (boolean && lower_bound > early_exit_margin + tiny) { status = GjkStatus::separated; break; }
            // Converged: the gap between upper bound |v| and the lower bound is within tolerance (the
            // ε·|v|·size term is the rounding floor of v·w).
            if (vv - vw <= settings.rel_tolerance * vv + S(16) * eps * vn * size) {
                status = GjkStatus::separated;
                break;
            }
            bool duplicate = false;
            for (int i = 0; i < s.size; ++i) duplicate = duplicate || s.v[i].w == x.w;
            if (duplicate) { status = GjkStatus::separated; break; }
        }
        GjkSimplex<S> saved = s;
        Vec3<S> saved_v = v;
        s.v[s.size++] = x;
        Vec3<S> nv;
        bool inside = SimplexSolver<S>::solve(s, nv);
        if (inside) { v.setZero(); status = GjkStatus::intersecting; break; }
        S nvv = nv.squaredNorm();
        if (!(nvv == nvv)) { s = saved; v = saved_v; status = GjkStatus::degenerate; break; }
        if (nvv <= tiny * tiny) { v = nv; status = GjkStatus::touching; break; }
        if (saved.size > 0 && !(nvv < vv)) {
            // No progress: rounding floor reached; keep the better previous simplex.
            s = saved;
            v = saved_v;
            status = GjkStatus::separated;
            break;
        }
        v = nv;
        vv = nvv;
    }
    if (cache) {
        cache->size = s.size;
        for (int i = 0; i < s.size; ++i) cache->directions[std::size_t(i)] = s.v[std::size_t(i)].d;
    }
    return status;
}

template <SupportMapped A, SupportMapped B>
inline GjkResult<typename A::Scalar> gjk_query(const A& a, const Transform<typename A::Scalar>& pose_a, const B& b,
                                               const Transform<typename A::Scalar>& pose_b,
                                               GjkCache<typename A::Scalar>* cache,
                                               const GjkSettings<typename A::Scalar>& settings,
                                               bool boolean) noexcept {
    using S = typename A::Scalar;
    const Transform<S> rel = pose_a.inverse() * pose_b;
    const S margin = margin_of(a) + margin_of(b);
    GjkResult<S> r;
    Vec3<S> v;
    S size, lower;
    GjkStatus st = gjk_loop<true>(a, b, rel, settings, cache, boolean, margin, r.simplex, v, size, r.iterations,
                                  lower);
    const S tiny = settings.touch_factor * std::numeric_limits<S>::epsilon() * std::max(size, margin);
    if (boolean && st == GjkStatus::separated && lower > margin + tiny) {
        r.status = GjkStatus::separated;
        r.distance = lower - margin;
        const S vn = v.norm();
        if (vn > S(0)) r.normal = pose_a.R * Vec3<S>(-v / vn);  // a separating direction, A towards B
        return r;
    }
    // Witness points on the cores, then push them out by the margins along the normal.
    Vec3<S> pa = Vec3<S>::Zero(), pb = Vec3<S>::Zero();
    for (int i = 0; i < r.simplex.size; ++i) {
        pa += r.simplex.lambda[std::size_t(i)] * r.simplex.v[std::size_t(i)].a;
        pb += r.simplex.lambda[std::size_t(i)] * r.simplex.v[std::size_t(i)].b;
    }
    if (st == GjkStatus::intersecting) {
        r.status = GjkStatus::intersecting;
        r.distance = S(0);
        return r;
    }
    S core = v.norm();
    Vec3<S> n = core > S(0) ? Vec3<S>(-v / core) : Vec3<S>::Zero();  // from A towards B
    pa += margin_of(a) * n;
    pb -= margin_of(b) * n;
    S dist = core - margin;
    r.point_a = pose_a * pa;
    r.point_b = pose_a * pb;
    r.normal = pose_a.R * n;
    if (st == GjkStatus::max_iterations || st == GjkStatus::degenerate) {
        r.status = st;
        r.distance = std::max(dist, S(0));
        return r;
    }
    if (st == GjkStatus::touching || std::abs(dist) <= tiny) {
        r.status = margin > S(0) && dist < -tiny ? GjkStatus::intersecting : GjkStatus::touching;
        r.distance = S(0);
        return r;
    }
    r.status = dist > S(0) ? GjkStatus::separated : GjkStatus::intersecting;
    r.distance = std::max(dist, S(0));
    return r;
}

}  // namespace detail

/// Separation distance between shape `a` placed by `pose_a` and shape `b` placed by `pose_b`, with
/// closest points and normal in the world frame. Const, noexcept, thread-safe; `cache` (optional,
/// caller-owned, per pair) warm-starts the search and is updated.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
[[nodiscard]] inline GjkResult<typename A::Scalar> gjk_distance(
    const A& a, const Transform<typename A::Scalar>& pose_a, const B& b, const Transform<typename A::Scalar>& pose_b,
    GjkCache<typename A::Scalar>* cache = nullptr,
    const GjkSettings<typename A::Scalar>& settings = {}) noexcept {
    return detail::gjk_query(a, pose_a, b, pose_b, cache, settings, false);
}

/// Boolean intersection test with early exit as soon as a separating plane is found. `status` is
/// `separated`, `touching` or `intersecting` (or `max_iterations`/`degenerate`); use `colliding()`.
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
