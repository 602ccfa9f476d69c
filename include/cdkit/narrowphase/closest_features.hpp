#pragma once
/// \file Closest-feature tracking between two convex polyhedra (a feature walk over external Voronoi regions).
///
/// After M. C. Lin and J. F. Canny, "A fast algorithm for incremental distance calculation", ICRA 1991, and
/// B. Mirtich, "V-Clip: fast and robust polyhedral collision detection", ACM Trans. on Graphics 17(3), 1998.
/// The features of a polyhedron are its vertices, edges and (polygonal) faces. Two points p ∈ A and q ∈ B
/// are the closest pair iff n = q − p lies in A's normal cone at p and −n in B's normal cone at q — which
/// is the same as "q lies in the external Voronoi region of p's feature, and p in that of q's". The
/// normal cone of a vertex is bounded by its edges (n·(u − v) ≤ 0 for every neighbour u), that of an edge by
/// its two faces (the `side_left` / `side_right` planes), that of a face is its outward normal.
///
/// Each step computes the closest points of the current feature pair (features are closed sets), moves each
/// feature to the lowest-dimensional sub-feature holding its closest point (V-Clip's demotion), and checks
/// both normal cones. A violated bound moves the feature across it to the neighbour whose region the other
/// point lies in; in exact arithmetic every such step strictly shortens the feature distance, and coherent
/// motion needs one or two steps per frame. The one local minimum — the other point below the plane of a
/// face — is resolved as in V-Clip: scan all faces for the largest signed distance; none positive means the
/// point is inside, i.e. penetration. A pair of features that meet (an edge through a face, or distance 0)
/// also reports penetration. Every "separated" answer is therefore certified by the plane through the
/// witness points, and every "intersecting" answer by a common point; a walk that revisits a feature pair
/// (a cycle: rounding ties, or penetration without a witness) or runs out of steps is answered by GJK,
/// so the answer is never silently wrong.
///
/// Queries are const on the shapes, noexcept and thread-safe; the only mutable state is the caller-owned
/// per-pair `ClosestFeatureCache` (one per pair and thread).

#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace cdkit {

/// Kind of a polyhedron feature: index into vertices(), edges() or the faces.
enum class FeatureType : std::uint8_t { vertex, edge, face };

/// A vertex, edge or face of a ConvexPolyhedron.
struct Feature {
    FeatureType type = FeatureType::vertex;
    std::uint32_t index = 0;
    friend bool operator==(const Feature&, const Feature&) = default;
};

/// Tuning of the feature walk.
template <class S = double> struct ClosestFeatureSettings {
    /// Walk steps before GJK takes over (V-Clip needs O(|V|) in the worst case, one or two when coherent).
    int max_iterations = 256;
    /// Feature distances within touch_factor·ε·(size of the scene) count as touching.
    S touch_factor = S(256);
    /// A Voronoi bound counts as violated only beyond a direction cosine of cone_factor·ε (when n is a face
    /// normal or an edge–edge cross product) or cone_factor·ε·(1 + size/distance) (when n is a difference of
    /// coordinates): the rounding of the test. Ignoring a violation of cosine δ can move the distance by
    /// about δ·size, so the tolerance is also capped at rel_tolerance·distance/size; where the rounding is
    /// larger than that cap the test is strict, and a walk that then cycles is answered by GJK.
    S cone_factor = S(64);
    S rel_tolerance = std::max(S(1e-10), S(64) * std::numeric_limits<S>::epsilon());
};

/// Caller-owned per-pair state: the last closest feature pair (walked from in the next query) and a GJK
/// cache for the fallback. Not shared between threads.
template <class S = double> struct ClosestFeatureCache {
    Feature a{}, b{};
    bool valid = false;
    GjkCache<S> gjk{};
};

/// Result of `closest_features`.
template <class S> struct ClosestFeatureResult {
    /// `separated` (distance > 0, certified by the witness points), `touching` (features meet within the
    /// touching tolerance), `intersecting` (an edge crosses a face, or a point of one lies inside the other),
    /// or GJK's status when GJK answered (`used_gjk`), which includes `max_iterations` / `degenerate`.
    /// `degenerate` with a NaN distance also reports non-finite poses.
    GjkStatus status = GjkStatus::degenerate;
    /// Separation distance (0 when touching or intersecting).
    S distance = S(0);
    /// Closest points on A and B in the world frame (a common point when colliding and the walk answered).
    Vec3<S> point_a = Vec3<S>::Zero(), point_b = Vec3<S>::Zero();
    /// Unit direction from A towards B, world frame (valid when separated).
    Vec3<S> normal = Vec3<S>::Zero();
    /// The final feature pair (A's and B's); meaningful when the walk answered.
    Feature feature_a{}, feature_b{};
    int iterations = 0;     ///< walk steps
    bool cycle = false;     ///< the walk revisited a feature pair (then GJK answered)
    bool used_gjk = false;  ///< GJK answered (cycle, step cap, missing topology)
    bool colliding = false;  ///< `is_colliding(status)`: touching or intersecting
};

namespace detail {

/// A polyhedron seen from the query frame: identity (A) or through a rigid pose (B in A's frame).
template <class S> struct PlacedHull {
    const ConvexPolyhedron<S>& p;
    const Transform<S>* pose = nullptr;
    [[nodiscard]] Vec3<S> vertex(std::uint32_t i) const noexcept {
        return pose ? place(*pose, p.vertices()[i]) : p.vertices()[i];
    }
    [[nodiscard]] Vec3<S> dir(const Vec3<S>& d) const noexcept { return pose ? rotate(pose->R, d) : d; }
};

/// Closest points of two features, and the sub-features (lowest dimension) that hold them.
template <class S> struct FeatureContact {
    S d2 = std::numeric_limits<S>::infinity();
    Vec3<S> pa = Vec3<S>::Zero(), pb = Vec3<S>::Zero();
    Feature fa{}, fb{};
    bool crossing = false;  ///< an edge of one passes through a face of the other
    void offer(const Vec3<S>& a, const Vec3<S>& b, Feature sa, Feature sb) noexcept {
        S d = (b - a).squaredNorm();
        if (d < d2) { d2 = d; pa = a; pb = b; fa = sa; fb = sb; }
    }
    [[nodiscard]] FeatureContact swapped() const noexcept {
        FeatureContact r = *this;
        std::swap(r.pa, r.pb);
        std::swap(r.fa, r.fb);
        return r;
    }
};

template <class S> struct PointOnFeature {
    Vec3<S> q;
    Feature f;
};

template <class S>
[[nodiscard]] inline PointOnFeature<S> closest_on_edge(const PlacedHull<S>& h, std::uint32_t e,
                                                       const Vec3<S>& p) noexcept {
    const PolyhedronEdge<S>& E = h.p.edges()[e];
    const Vec3<S> a = h.vertex(E.v0), b = h.vertex(E.v1);
    const Vec3<S> d = b - a;
    const S dd = d.squaredNorm();
    const S t = dd > S(0) ? (p - a).dot(d) / dd : S(0);
    if (!(t > S(0))) return {a, {FeatureType::vertex, E.v0}};
    if (t >= S(1)) return {b, {FeatureType::vertex, E.v1}};
    return {a + t * d, {FeatureType::edge, e}};
}

/// True when x (in face f's plane) is inside the polygon, boundary included.
template <class S>
[[nodiscard]] inline bool inside_face(const PlacedHull<S>& h, std::uint32_t f, const Vec3<S>& x) noexcept {
    const auto loop = h.p.face_vertices(f);
    const auto edges = h.p.face_edges(f);
    for (std::size_t k = 0; k < loop.size(); ++k)
        if (h.dir(h.p.edge_inward(edges[k], f)).dot(x - h.vertex(loop[k])) < S(0)) return false;
    return true;
}

template <class S>
[[nodiscard]] inline PointOnFeature<S> closest_on_face(const PlacedHull<S>& h, std::uint32_t f,
                                                       const Vec3<S>& p) noexcept {
    const Vec3<S> n = h.dir(h.p.face_normal(f));
    const Vec3<S> x0 = h.vertex(h.p.face_vertices(f)[0]);
    const Vec3<S> q = p - n * n.dot(p - x0);
    if (inside_face(h, f, q)) return {q, {FeatureType::face, f}};
    // Outside the polygon: the nearest boundary point (the perpendicular part is the same for all edges).
    PointOnFeature<S> best{q, {FeatureType::face, f}};
    S best_d = std::numeric_limits<S>::infinity();
    for (std::uint32_t e : h.p.face_edges(f)) {
        PointOnFeature<S> c = closest_on_edge(h, e, p);
        S d = (c.q - p).squaredNorm();
        if (d < best_d) { best_d = d; best = c; }
    }
    return best;
}

/// Closest points of edge ea of ha and edge eb of hb (Ericson, "Real-Time Collision Detection", §5.1.9).
template <class S>
inline void edge_edge(const PlacedHull<S>& ha, std::uint32_t ea, const PlacedHull<S>& hb, std::uint32_t eb,
                      FeatureContact<S>& out) noexcept {
    const PolyhedronEdge<S>& A = ha.p.edges()[ea];
    const PolyhedronEdge<S>& B = hb.p.edges()[eb];
    const Vec3<S> p1 = ha.vertex(A.v0), q1 = ha.vertex(A.v1), p2 = hb.vertex(B.v0), q2 = hb.vertex(B.v1);
    const Vec3<S> d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    const S a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r), c = d1.dot(r), b = d1.dot(d2);
    if (!(a > S(0)) || !(e > S(0))) return;  // zero-length edges do not exist in a valid topology
    const S den = a * e - b * b;
    S s = den > S(0) ? std::clamp((b * f - c * e) / den, S(0), S(1)) : S(0);
    S t = (b * s + f) / e;
    if (t < S(0)) { t = S(0); s = std::clamp(-c / a, S(0), S(1)); }
    else if (t > S(1)) { t = S(1); s = std::clamp((b - c) / a, S(0), S(1)); }
    const Feature fa = s <= S(0) ? Feature{FeatureType::vertex, A.v0}
                       : s >= S(1) ? Feature{FeatureType::vertex, A.v1} : Feature{FeatureType::edge, ea};
    const Feature fb = t <= S(0) ? Feature{FeatureType::vertex, B.v0}
                       : t >= S(1) ? Feature{FeatureType::vertex, B.v1} : Feature{FeatureType::edge, eb};
    out.offer(p1 + s * d1, p2 + t * d2, fa, fb);
}

/// Edge e of `he` against face f of `hf`; `out` is in (edge side, face side) order. Returns true when the
/// edge passes through the face (then `out` holds the crossing point and crossing = true).
template <class S>
inline bool edge_face(const PlacedHull<S>& he, std::uint32_t e, const PlacedHull<S>& hf, std::uint32_t f,
                      FeatureContact<S>& out) noexcept {
    const PolyhedronEdge<S>& E = he.p.edges()[e];
    const Vec3<S> p0 = he.vertex(E.v0), p1 = he.vertex(E.v1);
    const Vec3<S> n = hf.dir(hf.p.face_normal(f));
    const Vec3<S> x0 = hf.vertex(hf.p.face_vertices(f)[0]);
    const S s0 = n.dot(p0 - x0), s1 = n.dot(p1 - x0);
    if ((s0 > S(0) && s1 < S(0)) || (s0 < S(0) && s1 > S(0))) {
        const Vec3<S> x = p0 + (p1 - p0) * (s0 / (s0 - s1));
        if (inside_face(hf, f, x)) {
            out.d2 = S(0);
            out.pa = out.pb = x;
            out.fa = {FeatureType::edge, e};
            out.fb = {FeatureType::face, f};
            out.crossing = true;
            return true;
        }
    }
    const PointOnFeature<S> c0 = closest_on_face(hf, f, p0), c1 = closest_on_face(hf, f, p1);
    out.offer(p0, c0.q, {FeatureType::vertex, E.v0}, c0.f);
    out.offer(p1, c1.q, {FeatureType::vertex, E.v1}, c1.f);
    for (std::uint32_t g : hf.p.face_edges(f)) edge_edge(he, e, hf, g, out);
    return false;
}

/// Closest points of feature fa of ha and feature fb of hb, with their sub-features.
template <class S>
[[nodiscard]] inline FeatureContact<S> feature_contact(const PlacedHull<S>& ha, Feature fa, const PlacedHull<S>& hb,
                                                       Feature fb) noexcept {
    FeatureContact<S> out;
    using FT = FeatureType;
    if (fa.type == FT::vertex && fb.type == FT::vertex) {
        out.offer(ha.vertex(fa.index), hb.vertex(fb.index), fa, fb);
    } else if (fa.type == FT::vertex && fb.type == FT::edge) {
        const Vec3<S> p = ha.vertex(fa.index);
        const PointOnFeature<S> c = closest_on_edge(hb, fb.index, p);
        out.offer(p, c.q, fa, c.f);
    } else if (fa.type == FT::edge && fb.type == FT::vertex) {
        const Vec3<S> p = hb.vertex(fb.index);
        const PointOnFeature<S> c = closest_on_edge(ha, fa.index, p);
        out.offer(c.q, p, c.f, fb);
    } else if (fa.type == FT::vertex && fb.type == FT::face) {
        const Vec3<S> p = ha.vertex(fa.index);
        const PointOnFeature<S> c = closest_on_face(hb, fb.index, p);
        out.offer(p, c.q, fa, c.f);
    } else if (fa.type == FT::face && fb.type == FT::vertex) {
        const Vec3<S> p = hb.vertex(fb.index);
        const PointOnFeature<S> c = closest_on_face(ha, fa.index, p);
        out.offer(c.q, p, c.f, fb);
    } else if (fa.type == FT::edge && fb.type == FT::edge) {
        edge_edge(ha, fa.index, hb, fb.index, out);
    } else if (fa.type == FT::edge && fb.type == FT::face) {
        edge_face(ha, fa.index, hb, fb.index, out);
    } else if (fa.type == FT::face && fb.type == FT::edge) {
        FeatureContact<S> r;
        edge_face(hb, fb.index, ha, fa.index, r);
        out = r.swapped();
    } else {
        // Face against face: an edge of either through the other, else a vertex against the other face or
        // an edge pair.
        for (std::uint32_t e : ha.p.face_edges(fa.index)) {
            FeatureContact<S> r;
            if (edge_face(ha, e, hb, fb.index, r)) return r;
            if (r.d2 < out.d2) out = r;
        }
        for (std::uint32_t v : hb.p.face_vertices(fb.index)) {
            const Vec3<S> p = hb.vertex(v);
            const PointOnFeature<S> c = closest_on_face(ha, fa.index, p);
            out.offer(c.q, p, c.f, {FeatureType::vertex, v});
        }
        for (std::uint32_t e : hb.p.face_edges(fb.index)) {
            const PolyhedronEdge<S>& E = hb.p.edges()[e];
            const Vec3<S> p0 = hb.vertex(E.v0), p1 = hb.vertex(E.v1);
            const Vec3<S> n = ha.dir(ha.p.face_normal(fa.index));
            const Vec3<S> x0 = ha.vertex(ha.p.face_vertices(fa.index)[0]);
            const S s0 = n.dot(p0 - x0), s1 = n.dot(p1 - x0);
            if ((s0 > S(0) && s1 < S(0)) || (s0 < S(0) && s1 > S(0))) {
                const Vec3<S> x = p0 + (p1 - p0) * (s0 / (s0 - s1));
                if (inside_face(ha, fa.index, x)) {
                    out.d2 = S(0);
                    out.pa = out.pb = x;
                    out.fa = fa;
                    out.fb = {FeatureType::edge, e};
                    out.crossing = true;
                    return out;
                }
            }
        }
    }
    return out;
}

/// Checks that direction n (local frame of `p`, from p's closest point towards the other shape's point
/// `other`, also local; |n| = len) lies in the normal cone of feature f. Returns 0 when it does, 1 with
/// `next` set to the neighbouring feature to move to, or 2 when `other` lies inside p (penetration).
template <class S>
[[nodiscard]] inline int voronoi_check(const ConvexPolyhedron<S>& p, Feature f, const Vec3<S>& n, S len, S cos_tol,
                                       const Vec3<S>& other, S tiny, Feature& next) noexcept {
    S worst = cos_tol * len;
    int verdict = 0;
    switch (f.type) {
        case FeatureType::vertex: {
            const auto edges = p.vertex_edges(f.index);
            const auto dirs = p.vertex_edge_directions(f.index);
            for (std::size_t k = 0; k < edges.size(); ++k) {
                const S x = dirs[k].dot(n);
                if (x > worst) { worst = x; next = {FeatureType::edge, edges[k]}; verdict = 1; }
            }
            return verdict;
        }
        case FeatureType::edge: {
            const PolyhedronEdge<S>& e = p.edges()[f.index];
            const S l = e.side_left.dot(n), r = e.side_right.dot(n);
            if (l > worst && l >= r) { next = {FeatureType::face, e.face_left}; return 1; }
            if (r > worst) { next = {FeatureType::face, e.face_right}; return 1; }
            return 0;
        }
        case FeatureType::face:
        default: {
            if (p.face_normal(f.index).dot(n) > S(0)) return 0;
            // Local minimum: the other point is below this face's plane. The face it is farthest above is
            // where the walk goes on; above none of them, it is inside (V-Clip's vertex–face handling).
            S best = -std::numeric_limits<S>::infinity();
            std::uint32_t best_face = f.index;
            for (std::uint32_t g = 0; g < p.face_count(); ++g) {
                const S h = p.face_normal(g).dot(other) - p.face_offset(g);
                if (h > best) { best = h; best_face = g; }
            }
            if (!(best > tiny)) return 2;
            next = {FeatureType::face, best_face};
            return 1;
        }
    }
}

template <class S> [[nodiscard]] inline bool feature_in_range(const ConvexPolyhedron<S>& p, Feature f) noexcept {
    switch (f.type) {
        case FeatureType::vertex: return f.index < p.vertices().size();
        case FeatureType::edge: return f.index < p.edges().size();
        default: return f.index < p.face_count();
    }
}

[[nodiscard]] inline std::uint64_t feature_pair_key(Feature a, Feature b) noexcept {
    return (std::uint64_t(a.type) << 62) | (std::uint64_t(a.index) << 32) | (std::uint64_t(b.type) << 30) |
           std::uint64_t(b.index);
}

}  // namespace detail

namespace detail {
template <class S>
[[nodiscard]] inline ClosestFeatureResult<S> closest_feature_walk(const ConvexPolyhedron<S>& a, const Transform<S>& pose_a,
                                                                  const ConvexPolyhedron<S>& b, const Transform<S>& pose_b,
                                                                  ClosestFeatureCache<S>* cache,
                                                                  const ClosestFeatureSettings<S>& settings) noexcept {
    ClosestFeatureResult<S> r;
    // Per-component rotations (detail::relative_pose, place, rotate, rotate_back): Eigen's 3×3 products were
    // out-of-line calls in this per-frame path.
    const Transform<S> rel = detail::relative_pose(pose_a, pose_b);
    if (!rel.R.allFinite() || !rel.t.allFinite()) {
        r.status = GjkStatus::degenerate;
        r.distance = std::numeric_limits<S>::quiet_NaN();
        return r;
    }
    auto fallback = [&](Feature fa, Feature fb) {
        GjkResult<S> g = gjk_distance(a, pose_a, b, pose_b, cache ? &cache->gjk : nullptr);
        r.used_gjk = true;
        r.status = g.status;
        r.distance = g.distance;
        r.point_a = g.point_a;
        r.point_b = g.point_b;
        r.normal = g.normal;
        r.feature_a = fa;
        r.feature_b = fb;
        if (cache) { cache->a = fa; cache->b = fb; cache->valid = a.has_topology() && b.has_topology(); }
        return r;
    };
    if (!a.has_topology() || !b.has_topology()) return fallback({}, {});

    const S eps = std::numeric_limits<S>::epsilon();
    const S scale = a.radius() + b.radius() + rel.t.norm();
    const S tiny = settings.touch_factor * eps * scale;
    const detail::PlacedHull<S> ha{a, nullptr}, hb{b, &rel};
    Feature fa, fb;
    if (cache && cache->valid && detail::feature_in_range(a, cache->a) && detail::feature_in_range(b, cache->b)) {
        fa = cache->a;
        fb = cache->b;
    } else {
        Vec3<S> d = detail::place(rel, b.center()) - a.center();
        if (!(d.squaredNorm() > S(0))) d = Vec3<S>::UnitX();
        fa = {FeatureType::vertex, a.support_index(d)};
        fb = {FeatureType::vertex, b.support_index(Vec3<S>(-detail::rotate_back(rel.R, d)))};
    }
    // Feature pairs seen in this query: a repeat is a cycle.
    constexpr int history_size = 32;
    std::array<std::uint64_t, history_size> history;  // only the first `seen` entries are read
    int seen = 0;
    for (int it = 0; it < settings.max_iterations; ++it) {
        r.iterations = it + 1;
        const detail::FeatureContact<S> c = detail::feature_contact(ha, fa, hb, fb);
        if (!(c.d2 < std::numeric_limits<S>::infinity()) || !c.pa.allFinite() || !c.pb.allFinite())
            return fallback(fa, fb);
        fa = c.fa;
        fb = c.fb;
        const std::uint64_t key = detail::feature_pair_key(fa, fb);
        for (int k = 0; k < std::min(seen, history_size); ++k)
            if (history[std::size_t(k)] == key) { r.cycle = true; return fallback(fa, fb); }
        history[std::size_t(seen % history_size)] = key;
        ++seen;

        r.feature_a = fa;
        r.feature_b = fb;
        if (cache) { cache->a = fa; cache->b = fb; cache->valid = true; }
        const S len = std::sqrt(c.d2);
        if (c.crossing || len <= tiny) {
            r.status = c.crossing ? GjkStatus::intersecting : GjkStatus::touching;
            r.distance = S(0);
            r.point_a = detail::place(pose_a, c.pa);
            r.point_b = detail::place(pose_a, c.pb);
            return r;
        }
        const Vec3<S> n = c.pb - c.pa;
        // The direction the Voronoi tests use: a face normal or an edge–edge cross product where the pair
        // defines one (accurate to ε), else n itself (accurate to ε·size/|n|).
        Vec3<S> u = n / len;
        S floor_factor = S(1) + scale / len;
        if (fa.type == FeatureType::face && a.face_normal(fa.index).dot(n) > S(0)) {
            u = a.face_normal(fa.index);
            floor_factor = S(1);
        } else if (fb.type == FeatureType::face) {
            const Vec3<S> nb = detail::rotate(rel.R, b.face_normal(fb.index));
            if (nb.dot(n) < S(0)) { u = -nb; floor_factor = S(1); }
        } else if (fa.type == FeatureType::edge && fb.type == FeatureType::edge) {
            const auto& ea = a.edges()[fa.index];
            const auto& eb = b.edges()[fb.index];
            const Vec3<S> da = a.vertices()[ea.v1] - a.vertices()[ea.v0];
            const Vec3<S> db = detail::rotate(rel.R, Vec3<S>(b.vertices()[eb.v1] - b.vertices()[eb.v0]));
            Vec3<S> cr = da.cross(db);
            const S sine = cr.norm() / (da.norm() * db.norm());
            if (sine > S(1e-3)) {
                cr /= cr.norm();
                u = cr.dot(n) >= S(0) ? cr : Vec3<S>(-cr);
                floor_factor = S(1) / sine;
            }
        }
        const S extent = a.radius() + b.radius();
        const S cap = std::max(settings.rel_tolerance * len / extent, settings.cone_factor * eps);
        const S cos_tol = std::min(settings.cone_factor * eps * floor_factor, cap);
        Feature next;
        int v = detail::voronoi_check(a, fa, u, S(1), cos_tol, c.pb, tiny, next);
        if (v == 1) { fa = next; continue; }
        Vec3<S> inside_point = c.pb;
        if (v == 0) {
            const Vec3<S> m = detail::rotate_back(rel.R, Vec3<S>(-u));
            const Vec3<S> pa_in_b = detail::rotate_back(rel.R, Vec3<S>(c.pa - rel.t));
            v = detail::voronoi_check(b, fb, m, S(1), cos_tol, pa_in_b, tiny, next);
            if (v == 1) { fb = next; continue; }
            inside_point = c.pa;
        }
        if (v == 2) {
            r.status = GjkStatus::intersecting;
            r.distance = S(0);
            r.point_a = r.point_b = detail::place(pose_a, inside_point);
            return r;
        }
        r.status = GjkStatus::separated;
        r.distance = len;
        r.point_a = detail::place(pose_a, c.pa);
        r.point_b = detail::place(pose_a, c.pb);
        r.normal = detail::rotate(pose_a.R, Vec3<S>(n / len));
        return r;
    }
    return fallback(fa, fb);
}

}  // namespace detail

/// Distance between convex polyhedra `a` at `pose_a` and `b` at `pose_b` by walking their closest features,
/// starting from `cache`'s pair (or from the support vertices along the centre line when the cache is empty
/// or stale) and storing the final pair there. Closest points, normal and distance in the world frame.
/// Const, noexcept, thread-safe with one cache per thread and pair.
template <class S>
[[nodiscard]] inline ClosestFeatureResult<S> closest_features(const ConvexPolyhedron<S>& a, const Transform<S>& pose_a,
                                                              const ConvexPolyhedron<S>& b, const Transform<S>& pose_b,
                                                              ClosestFeatureCache<S>* cache = nullptr,
                                                              const ClosestFeatureSettings<S>& settings = {}) noexcept {
    ClosestFeatureResult<S> r = detail::closest_feature_walk(a, pose_a, b, pose_b, cache, settings);
    r.colliding = is_colliding(r.status);
    return r;
}

}  // namespace cdkit
