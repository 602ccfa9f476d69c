#pragma once
/// \file A convex polyhedron built as the convex hull of a point set, with a support map.
///
/// The hull is computed once at construction by Qhull (Barber, Dobkin, Huhdanpaa, "The Quickhull
/// algorithm for convex hulls", ACM TOMS 1996) in src/convex/convex_hull.cpp, linked privately.
/// Support queries scan all vertices for small hulls and otherwise climb the vertex adjacency graph
/// (a linear function has no local maximum on a convex polytope's graph that is not global; van den
/// Bergen 2003, §4.3.4 "hill climbing"), starting from a caller's hint when its neighbours prove it, else
/// from a vertex looked up by direction in a small table built with the hull (the support vertices of the
/// cells of a cube map around the unit sphere), which is the answer or next to it.
///
/// A strict containment test (`contains_strictly`, the cold boolean GJK's overlap certificate) walks the
/// tetrahedra that join the centre to the hull triangles: the centre is strictly inside, so they tile the hull
/// and central projection makes the triangles a spherical triangulation, located by a visibility walk (Devillers,
/// Pion, Teillaud, "Walking in a triangulation", IJFCS 2002) from the triangles around a support vertex near the
/// point (GJK's hint), or else from a direction table like the support map's.
///
/// It also keeps the boundary as polygons (coplanar facets merged by Qhull) with a face–edge–vertex
/// adjacency, outward unit face normals and the edge and face Voronoi-plane directions that
/// closest-feature tracking (narrowphase/closest_features.hpp) walks.

#include <cdkit/core/error.hpp>
#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/support.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cdkit {

namespace detail {
/// Output of the hull builder: hull vertices (subset of the input, in double), outward-oriented triangles
/// indexing them, the polygonal faces (coplanar facets merged; vertex loops counter-clockwise seen from
/// outside; the triangles are their fans), and the input index each hull vertex came from.
struct HullData {
    std::vector<Vec3<double>> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::vector<std::uint32_t>> faces;
    std::vector<std::uint32_t> source_index;
};
/// Builds the 3-D convex hull of `points`. Raises cdkit::Error for fewer than 4 points, non-finite
/// coordinates, or a flat (coplanar/collinear/coincident) set.
HullData convex_hull(const std::vector<Vec3<double>>& points);
}  // namespace detail

/// An edge of a polyhedron's boundary. `face_left` is the face whose counter-clockwise loop runs v0 → v1,
/// `face_right` the one that runs v1 → v0. `side_left` / `side_right` are unit vectors in those faces'
/// planes, perpendicular to the edge and pointing into the face: n_left × (v1 − v0) and (v1 − v0) × n_right,
/// normalised. They bound the edge's external Voronoi region against the faces' regions.
template <class S> struct PolyhedronEdge {
    std::uint32_t v0 = 0, v1 = 0, face_left = 0, face_right = 0;
    Vec3<S> side_left = Vec3<S>::Zero(), side_right = Vec3<S>::Zero();
};

/// A solid convex polyhedron: the convex hull of the given points, in their frame.
template <class S = double> class ConvexPolyhedron {
public:
    using Scalar = S;
    static constexpr bool polytope_core = true;  ///< HasPolytopeCore: the support is an exact hull vertex
    /// Hulls with at most this many vertices are searched by brute force; larger ones by hill climbing.
    static constexpr std::size_t brute_force_limit = 24;
    /// Larger hulls start hill climbing from a direction table: each face of the cube around the unit sphere
    /// cut into table_res × table_res cells (see build_start_table).
    static constexpr int table_res = 8;

    /// Builds the hull of `points` (throws cdkit::Error on bad input, see detail::convex_hull).
    explicit ConvexPolyhedron(const std::vector<Vec3<S>>& points) {
        std::vector<Vec3<double>> pd;
        pd.reserve(points.size());
        for (const auto& p : points) pd.push_back(p.template cast<double>());
        detail::HullData h = detail::convex_hull(pd);
        vertices_.reserve(h.vertices.size());
        for (const auto& v : h.vertices) vertices_.push_back(v.template cast<S>());
        vertex_count_ = std::uint32_t(vertices_.size());
        triangles_ = std::move(h.triangles);
        Vec3<double> c = Vec3<double>::Zero();
        for (const auto& v : h.vertices) c += v;
        center_ = (c / double(h.vertices.size())).template cast<S>();
        // Adjacency in CSR form, from the triangle edges, each neighbour once (an edge appears in two
        // triangles, in both directions).
        std::vector<std::vector<std::uint32_t>> adj(vertices_.size());
        for (const auto& t : triangles_)
            for (int k = 0; k < 3; ++k) {
                adj[t[k]].push_back(t[(k + 1) % 3]);
                adj[t[(k + 1) % 3]].push_back(t[k]);
            }
        offsets_.assign(1, 0);
        for (auto& a : adj) {
            std::sort(a.begin(), a.end());
            a.erase(std::unique(a.begin(), a.end()), a.end());
            neighbours_.insert(neighbours_.end(), a.begin(), a.end());
            offsets_.push_back(std::uint32_t(neighbours_.size()));
        }
        build_rings();
        build_topology(h.faces);
        build_balls();
        build_cones();
        // Hill-climbing seeds: the extreme vertices along ±x, ±y, ±z.
        for (int axis = 0; axis < 3; ++axis)
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                Vec3<S> d = Vec3<S>::Zero();
                d[axis] = S(sgn);
                seeds_[std::size_t(2 * axis + (sgn + 1) / 2)] = brute_force_index(d);
            }
        build_start_table();
    }

    /// The vertex maximising d·x. Const, noexcept, thread-safe (no cached state).
    [[nodiscard]] Vec3<S> support(const Vec3<S>& d) const noexcept { return vertices_[support_index(d)]; }
    /// Index into vertices() of a vertex maximising d·x.
    [[nodiscard]] std::uint32_t support_index(const Vec3<S>& d) const noexcept {
        if (vertices_.size() <= brute_force_limit) return brute_force_index(d);
        return support_index(d, std::uint32_t(-1));
    }
    /// The same, from vertex `hint` (any index; one out of range is ignored): when no neighbour of the hint is
    /// better it is the answer (one scan: the usual case for the previous answer of a coherent sequence of
    /// directions, last frame's support vertex or the previous GJK iteration's); otherwise the climb goes on
    /// from the better of the hint's best neighbour and the direction table's start vertex
    /// (`build_start_table`), which keeps a poor hint (directions that jump, as in GJK's first iterations)
    /// from costing a long climb. A linear function has no non-global local maximum on the vertex graph, so
    /// any start gives the same maximum.
    [[nodiscard]] CDKIT_ALWAYS_INLINE std::uint32_t support_index(const Vec3<S>& d,
                                                                  std::uint32_t hint) const noexcept {
        if (hint < vertex_count_) {
            // A coherent caller's hint is usually the answer: one scan of its neighbours proves it (a local
            // maximum is the global one) without the table lookup, whose division and load would sit on the
            // query's critical path. This part is inlined into the caller (GJK's loop): most queries end here.
            std::uint32_t best = hint;
            S best_dot = d.dot(vertices_[hint]);
            scan_neighbours(d, hint, best, best_dot);
            // (Not when the products overflowed to −∞ around the hint: a tie there proves nothing.)
            if (best == hint && best_dot >= -std::numeric_limits<S>::max()) return hint;
            return search_from(d, best, best_dot);
        }
        return search_from(d, std::uint32_t(-1), S(0));
    }
    /// The rest of support_index(d, hint) after the hint's scan (best = −1: no hint), out of line.
    [[nodiscard]] CDKIT_NOINLINE std::uint32_t search_from(const Vec3<S>& d, std::uint32_t best,
                                                          S best_dot) const noexcept {
        if (vertices_.size() <= brute_force_limit) return brute_force_index(d);
        S m;
        const int cell = direction_cell(d, m, support_res_);
        if (cell >= 0) {
            const std::uint32_t entry = start_table_[std::size_t(cell)];
            const std::uint32_t start = entry & ~certified_bit;
            // A certified cell (build_start_table): its vertex is the strict maximum over the whole cell, with
            // a margin above the products' rounding, so no scan is needed to prove it.
            if ((entry & certified_bit) && m >= certified_low_ && m <= certified_high_) return start;
            const S t = d.dot(vertices_[start]);
            if (best == std::uint32_t(-1) || t > best_dot) { best_dot = t; best = start; }
            return climb(d, best, best_dot);
        }
        // Not tabulated (a zero, subnormal or non-finite direction): the six axis seeds.
        for (std::uint32_t seed : seeds_) {
            const S v = d.dot(vertices_[seed]);
            if (best == std::uint32_t(-1) || v > best_dot) { best_dot = v; best = seed; }
        }
        return climb(d, best, best_dot);
    }
    /// Support with a caller-kept start vertex, updated to the returned vertex (see support_index).
    [[nodiscard]] Vec3<S> support(const Vec3<S>& d, std::uint32_t& hint) const noexcept {
        hint = support_index(d, hint);
        return vertices_[hint];
    }
    /// The vertex average (an interior point).
    [[nodiscard]] Vec3<S> center() const noexcept { return center_; }
    /// Balls about center() (HasBoundingBalls), precomputed: through the farthest vertex, and touching the
    /// nearest hull triangle's plane (both rounded outwards).
    [[nodiscard]] S bounding_radius() const noexcept { return bounding_radius_; }
    [[nodiscard]] S inner_radius() const noexcept { return inner_radius_; }
    [[nodiscard]] const std::vector<Vec3<S>>& vertices() const noexcept { return vertices_; }
    /// Outward-oriented (counter-clockwise seen from outside) hull triangles indexing vertices().
    [[nodiscard]] const std::vector<std::array<std::uint32_t, 3>>& triangles() const noexcept {
        return triangles_;
    }

    /// True only when the ball of radius `slack` about p (local frame) lies inside the hull (HasContainmentTest);
    /// see locate(). Const, noexcept, thread-safe.
    [[nodiscard]] bool contains_strictly(const Vec3<S>& p, S slack) const noexcept {
        return locate(p, slack, std::uint32_t(-1)).inside;
    }
    /// Point location (HasPointLocation). `inside` only when p lies more than slack + the planes' rounding bound
    /// inside the four planes of one tetrahedron (centre, hull triangle), found by walking towards p across the
    /// side whose plane p lies behind; false, never wrong, for points near the boundary or a side, a walk longer
    /// than `containment_walk_limit` steps, or a hull whose centre is not certified inside (inner_radius() = 0).
    /// The walk starts among the triangles around vertex `near` (a support vertex near p, as GJK's hint; one out
    /// of range is ignored: the direction table's tetrahedron), whose planes are tested first: p outside the hull
    /// near that vertex, as a separated pair's support point is, lies beyond one of them, and `axis` is then the
    /// normal of the one it lies farthest beyond (a candidate separating axis), found without a walk.
    /// Const, noexcept, thread-safe.
    [[nodiscard]] PointLocation<S> locate(const Vec3<S>& p, S slack, std::uint32_t near) const noexcept {
        PointLocation<S> out;
        if (cones_.empty()) return out;
        // Points of the hull lie within radius() of the origin, and the planes' error bound assumes it.
        if (!(std::abs(p[0]) <= radius_ && std::abs(p[1]) <= radius_ && std::abs(p[2]) <= radius_)) return out;
        const S margin = slack + containment_error_;
        std::uint32_t t = 0;
        if (near < vertex_begin_cone_.size() - 1) {
            // The triangles around the vertex: the plane p clears least is the likely exit of the ray from the
            // centre through p (where the walk starts), and one it does not clear proves it outside.
            S least = std::numeric_limits<S>::infinity();
            for (std::uint32_t i = vertex_begin_cone_[near]; i < vertex_begin_cone_[near + 1]; ++i) {
                const CentralCone& k = cones_[vertex_cone_[i]];
                const S d = k.offset - detail::dot3(k.normal, p);
                if (d < least) { least = d; t = vertex_cone_[i]; }
            }
            if (!(least > margin)) {
                if (least < S(0)) out.axis = cones_[t].normal;
                return out;
            }
        } else {
            const int cell = direction_cell(detail::minus(p, center_));
            if (cell < 0) return out;  // p at the centre (or a subnormal offset): left to GJK
            t = cone_table_[std::size_t(cell)];
        }
        for (int step = 0; step < containment_walk_limit; ++step) {
            const CentralCone& k = cones_[t];
            // The triangle's plane supports the hull: a ball that reaches it is not inside.
            const S d = k.offset - detail::dot3(k.normal, p);
            if (!(d > margin)) {
                if (d < S(0)) out.axis = k.normal;
                return out;
            }
            const S s0 = detail::dot3(k.side[0], p) - k.side_offset[0];
            const S s1 = detail::dot3(k.side[1], p) - k.side_offset[1];
            const S s2 = detail::dot3(k.side[2], p) - k.side_offset[2];
            const int e = s0 <= s1 ? (s0 <= s2 ? 0 : 2) : (s1 <= s2 ? 1 : 2);
            const S low = std::min(s0, std::min(s1, s2));
            if (low > margin) {
                out.inside = true;
                return out;
            }
            if (!(low < S(0))) return out;  // in this tetrahedron but too near a side (or NaN)
            t = k.next[std::size_t(e)];
        }
        return out;
    }
    /// Steps the containment walk takes before it gives up (answers false).
    static constexpr int containment_walk_limit = 32;

    /// \name Boundary topology (faces are polygons; all directions are in the local frame)
    /// @{
    /// False when the face/edge structure failed its consistency checks (every edge in exactly two faces,
    /// Euler's V − E + F = 2, unit face normals, every vertex a corner); then only the support map may be
    /// used, and closest-feature tracking answers with GJK.
    [[nodiscard]] bool has_topology() const noexcept { return topology_ok_; }
    [[nodiscard]] std::size_t face_count() const noexcept { return face_normals_.size(); }
    /// Vertex loop of face f, counter-clockwise seen from outside.
    [[nodiscard]] std::span<const std::uint32_t> face_vertices(std::uint32_t f) const noexcept {
        return {face_loop_.data() + face_begin_[f], face_begin_[f + 1] - face_begin_[f]};
    }
    /// Edge indices of face f's loop: entry k joins face_vertices(f)[k] and [k + 1] (cyclically).
    [[nodiscard]] std::span<const std::uint32_t> face_edges(std::uint32_t f) const noexcept {
        return {face_edge_.data() + face_begin_[f], face_begin_[f + 1] - face_begin_[f]};
    }
    /// Outward unit normal of face f and the plane offset: the face lies in {x : normal·x = offset}.
    [[nodiscard]] const Vec3<S>& face_normal(std::uint32_t f) const noexcept { return face_normals_[f]; }
    [[nodiscard]] S face_offset(std::uint32_t f) const noexcept { return face_offsets_[f]; }
    /// Unit vector in face f's plane, perpendicular to edge e of f and pointing into f.
    [[nodiscard]] const Vec3<S>& edge_inward(std::uint32_t e, std::uint32_t f) const noexcept {
        return edges_[e].face_left == f ? edges_[e].side_left : edges_[e].side_right;
    }
    [[nodiscard]] const std::vector<PolyhedronEdge<S>>& edges() const noexcept { return edges_; }
    /// Edges incident to vertex v, and for each the unit direction from v along it.
    [[nodiscard]] std::span<const std::uint32_t> vertex_edges(std::uint32_t v) const noexcept {
        return {vertex_edge_.data() + vertex_begin_[v], vertex_begin_[v + 1] - vertex_begin_[v]};
    }
    [[nodiscard]] std::span<const Vec3<S>> vertex_edge_directions(std::uint32_t v) const noexcept {
        return {vertex_edge_dir_.data() + vertex_begin_[v], vertex_begin_[v + 1] - vertex_begin_[v]};
    }
    /// The largest |v| over the vertices (a scale for tolerances).
    [[nodiscard]] S radius() const noexcept { return radius_; }
    /// @}

private:
    void build_topology(const std::vector<std::vector<std::uint32_t>>& faces) {
        radius_ = S(0);
        for (const auto& v : vertices_) radius_ = std::max(radius_, S(v.norm()));
        face_begin_.assign(1, 0);
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edge_of;
        bool ok = true;
        for (std::uint32_t f = 0; f < faces.size(); ++f) {
            const auto& loop = faces[f];
            // Newell's normal: robust for polygons whose vertices are only nearly coplanar.
            Vec3<S> n = Vec3<S>::Zero();
            for (std::size_t k = 0; k < loop.size(); ++k)
                n += vertices_[loop[k]].cross(vertices_[loop[(k + 1) % loop.size()]]);
            const S len = n.norm();
            ok = ok && len > S(0) && n.allFinite();
            n = len > S(0) ? Vec3<S>(n / len) : Vec3<S>::Zero();
            S off = S(0);
            for (std::uint32_t v : loop) off += n.dot(vertices_[v]);
            face_normals_.push_back(n);
            face_offsets_.push_back(loop.empty() ? S(0) : off / S(loop.size()));
            for (std::size_t k = 0; k < loop.size(); ++k) {
                const std::uint32_t a = loop[k], b = loop[(k + 1) % loop.size()];
                const auto key = std::minmax(a, b);
                auto [it, inserted] = edge_of.try_emplace(key, std::uint32_t(edges_.size()));
                if (inserted) {
                    PolyhedronEdge<S> e;
                    e.v0 = key.first;
                    e.v1 = key.second;
                    e.face_left = e.face_right = std::uint32_t(-1);
                    edges_.push_back(e);
                }
                PolyhedronEdge<S>& e = edges_[it->second];
                std::uint32_t& slot = a < b ? e.face_left : e.face_right;
                ok = ok && slot == std::uint32_t(-1);
                slot = f;
                face_loop_.push_back(a);
                face_edge_.push_back(it->second);
            }
            face_begin_.push_back(std::uint32_t(face_loop_.size()));
        }
        std::vector<std::vector<std::uint32_t>> incident(vertices_.size());
        for (std::uint32_t i = 0; i < edges_.size(); ++i) {
            PolyhedronEdge<S>& e = edges_[i];
            ok = ok && e.face_left != std::uint32_t(-1) && e.face_right != std::uint32_t(-1) && e.v0 != e.v1;
            if (!ok) break;
            const Vec3<S> t = vertices_[e.v1] - vertices_[e.v0];
            e.side_left = detail::safe_normalized(Vec3<S>(face_normals_[e.face_left].cross(t)));
            e.side_right = detail::safe_normalized(Vec3<S>(t.cross(face_normals_[e.face_right])));
            incident[e.v0].push_back(i);
            incident[e.v1].push_back(i);
        }
        ok = ok && vertices_.size() + faces.size() == edges_.size() + 2;  // Euler: V − E + F = 2
        vertex_begin_.assign(1, 0);
        for (std::uint32_t v = 0; ok && v < incident.size(); ++v) {
            // A vertex's normal cone is only described by its edges when it is a corner (extreme point):
            // then the mean of its face normals makes an obtuse angle with every edge. A vertex in the middle
            // of an edge or face would accept inward directions, so such a hull gets no topology.
            Vec3<S> mean = Vec3<S>::Zero();
            for (std::uint32_t e : incident[v])
                mean += face_normals_[edges_[e].face_left] + face_normals_[edges_[e].face_right];
            mean = detail::safe_normalized(mean);
            ok = ok && incident[v].size() >= 3;
            for (std::uint32_t e : incident[v]) {
                const std::uint32_t u = edges_[e].v0 == v ? edges_[e].v1 : edges_[e].v0;
                const Vec3<S> dir = detail::safe_normalized(Vec3<S>(vertices_[u] - vertices_[v]));
                ok = ok && mean.dot(dir) < -S(64) * std::numeric_limits<S>::epsilon();
                vertex_edge_.push_back(e);
                vertex_edge_dir_.push_back(dir);
            }
            vertex_begin_.push_back(std::uint32_t(vertex_edge_.size()));
        }
        topology_ok_ = ok;
    }

    /// The two balls of bounding_radius() / inner_radius(). The inner radius is the smallest distance from the
    /// centre to a hull triangle's plane, computed in long double and lowered by 64ε·(bounding radius + |centre|)
    /// for the rounding of the planes (a ball inside every triangle's half-space is inside the hull).
    void build_balls() {
        using W = long double;
        const Vec3<W> c = center_.template cast<W>();
        W r2 = 0;
        for (const auto& v : vertices_) r2 = std::max(r2, (v.template cast<W>() - c).squaredNorm());
        bounding_radius_ = detail::round_up(S(std::sqrt(r2)));
        W inner = std::numeric_limits<W>::infinity();
        for (const auto& t : triangles_) {
            const Vec3<W> a = vertices_[t[0]].template cast<W>(), b = vertices_[t[1]].template cast<W>(),
                          cc = vertices_[t[2]].template cast<W>();
            const Vec3<W> n = (b - a).cross(cc - a);
            const W len = n.norm();
            if (!(len > W(0))) continue;  // a sliver: its neighbours bound the same region
            inner = std::min(inner, n.dot(a - c) / len);
        }
        const W slack = W(64) * W(std::numeric_limits<S>::epsilon()) *
                        (W(bounding_radius_) + c.cwiseAbs().sum());
        inner -= slack;
        const bool usable = inner > W(0) && inner < std::numeric_limits<W>::infinity();
        inner_radius_ = usable ? detail::round_down(S(inner)) : S(0);
    }

    /// Start vertices for hill climbing by direction: the cube around the unit sphere, each face cut into
    /// table_res × table_res cells, each cell holding the support vertex of its centre direction. A query
    /// direction's cell is found with one division; its support vertex is that entry or a neighbour of it in
    /// most queries (a cell is narrower than the normal cone of a vertex of hulls up to a few hundred vertices),
    /// so the climb is a scan or two instead of the six seeds and a longer climb. Only the start depends on
    /// it: the climb still ends at a vertex no neighbour beats, the global maximum.
    ///
    /// A cell whose vertex v is the only maximiser over the whole cell, by a margin, is marked certified
    /// (`certified_bit`) and answered without any scan (issue 39: on hulls of real meshes most support calls of a
    /// cold GJK query came with a hint that was not the answer, paid a failed scan around it and then one or two
    /// climbing scans from this table). The certificate: on the cube face the cell is a square of directions c
    /// (c's largest component ±1), slightly enlarged (by `cell_slack`, more than the rounding of the cell index),
    /// and for every neighbour n of v, c·(v − n) is linear in c, so its minimum over the square is at a corner;
    /// it must exceed `margin` = 64ε·|vertices|∞ there (evaluated in long double). That bounds every other vertex
    /// u too: u − v = Σ λ_k (n_k − v) with λ ≥ 0 (the polytope lies in v's edge cone) and Σ λ_k ≥ 1 (else u would
    /// be a convex combination of v and its neighbours, not a corner — hence the topology check), so
    /// c·(v − u) ≥ Σ λ_k c·(v − n_k) > margin. A query d = m·c in the cell then has d·(v − u) > m·margin, more than
    /// the rounding of the two products in S (each within 3ε(1+ε)·Σ|d_i||x_i| ≤ 9ε·m·|vertices|∞ while no product
    /// underflows or overflows, which the range [certified_low_, certified_high_] of m ensures), so
    /// fl(d·v) > fl(d·u): v is exactly brute force's answer.
    void build_start_table() {
        using W = long double;
        if (vertices_.size() <= brute_force_limit) return;
        // Finer tables for larger hulls (their vertices' normal cones are narrower): about ≥ 4 cells per vertex,
        // at most 32 × 32 per cube face (24 KiB).
        support_res_ = table_res;
        while (support_res_ < 4 * table_res && 6 * support_res_ * support_res_ < 4 * int(vertices_.size()))
            support_res_ *= 2;
        const int n = 6 * support_res_ * support_res_;
        start_table_.resize(std::size_t(n));
        // Each cell's centre support vertex, climbing from the previous cell's (neighbouring directions);
        // the climb's answer is exact (a vertex no neighbour beats), and only certified cells skip the scan.
        std::uint32_t prev = brute_force_index(cell_direction(0, support_res_));
        for (int cell = 0; cell < n; ++cell) {
            const Vec3<S> d = cell_direction(cell, support_res_);
            prev = climb(d, prev, d.dot(vertices_[prev]));
            start_table_[std::size_t(cell)] = prev;
        }
        if (!topology_ok_) return;  // certificates need every vertex to be a corner (see below)
        W r = 0;  // |vertices|∞
        for (const auto& v : vertices_) r = std::max(r, W(v.cwiseAbs().maxCoeff()));
        const W eps = W(std::numeric_limits<S>::epsilon());
        const W margin = W(64) * eps * r;
        if (!(margin > W(0)) || !(r < W(std::numeric_limits<S>::max()))) return;
        // m·margin above the absolute error of subnormal products (≤ 3 denorm_min per dot product), and
        // m·3·|vertices|∞ far below overflow.
        certified_low_ = detail::round_up(S(W(1 << 20) * W(std::numeric_limits<S>::min()) / margin));
        certified_high_ = detail::round_down(S(W(std::numeric_limits<S>::max()) / (W(16) * r)));
        if (!(certified_low_ < certified_high_)) return;
        const W slack = W(cell_slack) * eps;
        const int res = support_res_;
        for (int cell = 0; cell < n; ++cell) {
            const std::uint32_t v = start_table_[std::size_t(cell)];
            const int face = cell / (res * res), i = cell / res % res, j = cell % res;
            const int axis = face / 2;
            bool ok = true;
            for (int corner = 0; corner < 4 && ok; ++corner) {
                Vec3<W> c;
                c[axis] = face % 2 ? W(-1) : W(1);
                const int ci = i + (corner & 1), cj = j + (corner >> 1);
                c[(axis + 1) % 3] = W(2 * ci) / W(res) - W(1) + (corner & 1 ? slack : -slack);
                c[(axis + 2) % 3] = W(2 * cj) / W(res) - W(1) + (corner >> 1 ? slack : -slack);
                const W cv = c.dot(vertices_[v].template cast<W>());
                for (std::uint32_t e = offsets_[v]; e < offsets_[v + 1] && ok; ++e)
                    ok = cv - c.dot(vertices_[neighbours_[e]].template cast<W>()) > margin;
            }
            if (ok) start_table_[std::size_t(cell)] |= certified_bit;
        }
    }
    /// How far (in units of ε, in the cube-face coordinates, where a face spans [−1, 1]) a certified cell is
    /// enlarged: the cell index of a direction is computed with a handful of roundings (below 8ε there).
    static constexpr int cell_slack = 64;
    static constexpr std::uint32_t certified_bit = 0x80000000u;
    static constexpr int cells = 6 * table_res * table_res;

    /// The tetrahedra (centre, hull triangle) of contains_strictly, their neighbours and error bound, and the
    /// table of the tetrahedron around each cell's centre direction. Planes are computed in long double and
    /// rounded; the error bound covers, for |p|∞ ≤ radius(), the rounding of the stored planes (a normalised
    /// cross product loses about ε_W·|a||b|/|a × b| in the wide type, counted per plane) and of their evaluation
    /// in S, with a factor 4 to spare. Only hulls whose centre is certified inside (inner_radius() > 0) and whose
    /// triangles close up (every edge in two of them, opposite ways) get them.
    void build_cones() {
        using W = long double;
        if (!(inner_radius_ > S(0))) return;
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> owner;  // directed edge → triangle
        for (std::uint32_t t = 0; t < triangles_.size(); ++t)
            for (std::size_t e = 0; e < 3; ++e) owner[{triangles_[t][e], triangles_[t][(e + 1) % 3]}] = t;
        const Vec3<W> c = center_.template cast<W>();
        W worst = 1;  // largest |a||b|/|a × b| over the planes
        std::vector<CentralCone> cones(triangles_.size());
        for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
            const auto& tri = triangles_[t];
            const Vec3<W> v[3] = {vertices_[tri[0]].template cast<W>(), vertices_[tri[1]].template cast<W>(),
                                  vertices_[tri[2]].template cast<W>()};
            CentralCone& k = cones[t];
            const Vec3<W> a = v[1] - v[0], b = v[2] - v[0];
            Vec3<W> n = a.cross(b);
            const W len = n.norm();
            if (!(len > W(0))) return;  // a sliver triangle: no containment test for this hull
            worst = std::max(worst, a.norm() * b.norm() / len);
            n /= len;
            // The centre on the inner side of the (outward, counter-clockwise) triangle: then each side plane's
            // normal (v_e − c) × (v_e+1 − c) points into the tetrahedron, since its product with v_e+2 − c is
            // det(v_e − c, v_e+1 − c, v_e+2 − c) = |a × b|·n·(v_0 − c) > 0. (Not tested by that determinant itself:
            // for a sliver triangle its rounding, ~ε·|v − c|³, exceeds it and once flipped a side plane.)
            if (!(n.dot(v[0] - c) > W(0))) return;
            k.normal = n.template cast<S>();
            k.offset = S(n.dot(v[0]));
            for (int e = 0; e < 3; ++e) {
                const Vec3<W> p = v[e] - c, q = v[(e + 1) % 3] - c;
                Vec3<W> m = p.cross(q);
                const W l = m.norm();
                if (!(l > W(0))) return;
                worst = std::max(worst, p.norm() * q.norm() / l);
                m /= l;
                k.side[std::size_t(e)] = m.template cast<S>();
                k.side_offset[std::size_t(e)] = S(m.dot(c));
                const auto across = owner.find({tri[std::size_t((e + 1) % 3)], tri[std::size_t(e)]});
                if (across == owner.end()) return;
                k.next[std::size_t(e)] = across->second;
            }
        }
        const W eps_s = W(std::numeric_limits<S>::epsilon()), eps_w = std::numeric_limits<W>::epsilon();
        const W bound = W(64) * (eps_s + W(16) * eps_w * worst) * W(radius_);
        if (!(bound < W(radius_))) return;
        containment_error_ = detail::round_up(S(bound));
        cones_ = std::move(cones);
        // The triangles around each vertex, in CSR form.
        vertex_begin_cone_.assign(vertices_.size() + 1, 0);
        for (const auto& tri : triangles_)
            for (std::uint32_t v : tri) ++vertex_begin_cone_[v + 1];
        for (std::size_t v = 0; v < vertices_.size(); ++v) vertex_begin_cone_[v + 1] += vertex_begin_cone_[v];
        vertex_cone_.resize(3 * triangles_.size());
        std::vector<std::uint32_t> fill(vertex_begin_cone_.begin(), vertex_begin_cone_.end() - 1);
        for (std::uint32_t t = 0; t < triangles_.size(); ++t)
            for (std::uint32_t v : triangles_[t]) vertex_cone_[fill[v]++] = t;
        // Each cell's tetrahedron: a walk from the previous cell's (neighbouring cells are near), else a scan.
        cone_table_.resize(std::size_t(cells));
        std::uint32_t t = 0;
        for (int cell = 0; cell < cells; ++cell) {
            const Vec3<S> d = cell_direction(cell);
            auto low = [&](std::uint32_t i, int& e) {
                const CentralCone& k = cones_[i];
                const S s0 = k.side[0].dot(d), s1 = k.side[1].dot(d), s2 = k.side[2].dot(d);
                e = s0 <= s1 ? (s0 <= s2 ? 0 : 2) : (s1 <= s2 ? 1 : 2);
                return std::min(s0, std::min(s1, s2));
            };
            int e = 0;
            std::size_t steps = 0;
            while (low(t, e) < S(0) && steps++ < cones_.size()) t = cones_[t].next[std::size_t(e)];
            if (low(t, e) < S(0))
                for (std::uint32_t i = 0; i < cones_.size(); ++i)
                    if (low(i, e) > low(t, e)) t = i;
            cone_table_[std::size_t(cell)] = t;
        }
    }

    /// The direction table's cell of d (see build_start_table); −1 when d is zero, subnormal or not finite.
    [[nodiscard]] CDKIT_ALWAYS_INLINE static int direction_cell(const Vec3<S>& d) noexcept {
        S m;
        return direction_cell(d, m);
    }
    /// The same, with m = |d|∞ (the largest absolute component), for a table of `res` × `res` cells per face.
    [[nodiscard]] CDKIT_ALWAYS_INLINE static int direction_cell(const Vec3<S>& d, S& m, int res = table_res) noexcept {
        const S x = d[0], y = d[1], z = d[2];
        const S ax = std::abs(x), ay = std::abs(y), az = std::abs(z);
        int face;
        S u, v;
        if (ax >= ay && ax >= az) { face = x < S(0); m = ax; u = y; v = z; }
        else if (ay >= az) { face = 2 + (y < S(0)); m = ay; u = z; v = x; }
        else { face = 4 + (z < S(0)); m = az; u = x; v = y; }
        const S half = S(res) / S(2);
        const S k = half / m;
        // |u|, |v| ≤ m, so fi, fj lie in [0, table_res] up to rounding; anything else (NaN or infinite
        // components, a zero or subnormal direction) is not tabulated.
        const S fi = u * k + half, fj = v * k + half;
        if (!(fi > S(-1) && fi < S(res + 1) && fj > S(-1) && fj < S(res + 1))) return -1;
        const int i = std::clamp(int(fi), 0, res - 1);
        const int j = std::clamp(int(fj), 0, res - 1);
        return (face * res + i) * res + j;
    }
    /// The cell's centre direction (the one tabulated for it).
    [[nodiscard]] static Vec3<S> cell_direction(int cell, int res = table_res) noexcept {
        const int face = cell / (res * res), i = cell / res % res, j = cell % res;
        const int axis = face / 2;
        Vec3<S> d;
        d[axis] = face % 2 ? S(-1) : S(1);
        d[(axis + 1) % 3] = S(2 * i + 1) / S(res) - S(1);
        d[(axis + 2) % 3] = S(2 * j + 1) / S(res) - S(1);
        return d;
    }
    /// The table's start vertex for direction d; uint32(-1) when d is zero or not finite.
    [[nodiscard]] CDKIT_ALWAYS_INLINE std::uint32_t table_start(const Vec3<S>& d) const noexcept {
        S m;
        const int cell = direction_cell(d, m, support_res_);
        return cell < 0 ? std::uint32_t(-1) : start_table_[std::size_t(cell)] & ~certified_bit;
    }
    /// Climbs to the best neighbour of the current vertex until none is better; each step strictly
    /// increases d·x, so it stops after at most |V| steps.
    [[nodiscard]] std::uint32_t climb(const Vec3<S>& d, std::uint32_t best, S best_dot) const noexcept {
        for (;;) {
            const std::uint32_t from = best;
            scan_neighbours(d, from, best, best_dot);
            if (best == from) return best;
        }
    }

#if defined(__SSE2__)
    static constexpr bool has_rings = std::is_same_v<S, double>;
#else
    static constexpr bool has_rings = false;
#endif
    /// The scan of vertex v's neighbours: for each neighbour n in adjacency order, d·n > best_dot makes n the
    /// best (best, best_dot updated). With rings (build_rings) two neighbours per SSE2 operation, the scalar
    /// updates only for a pair that beats the current best; the products are summed in the order of Eigen's
    /// 3-vector dot product, (d₀x₀ + d₁x₁) + d₂x₂, so the outcome is the scalar loop's, bit for bit.
    CDKIT_ALWAYS_INLINE void scan_neighbours(const Vec3<S>& d, std::uint32_t v, std::uint32_t& best,
                                             S& best_dot) const noexcept {
#if defined(__SSE2__)
        if constexpr (has_rings) {
            const double* const base = rings_.data() + 6 * std::size_t(ring_begin_[v]);
            const std::uint32_t pairs = ring_begin_[v + 1] - ring_begin_[v];
            const __m128d dx = _mm_set1_pd(d[0]), dy = _mm_set1_pd(d[1]), dz = _mm_set1_pd(d[2]);
            __m128d bound = _mm_set1_pd(best_dot);
            for (std::uint32_t i = 0; i < pairs; ++i) {
                const double* p = base + 6 * std::size_t(i);
                const __m128d xy = _mm_add_pd(_mm_mul_pd(dx, _mm_loadu_pd(p)), _mm_mul_pd(dy, _mm_loadu_pd(p + 2)));
                const __m128d t = _mm_add_pd(xy, _mm_mul_pd(dz, _mm_loadu_pd(p + 4)));
                if (_mm_movemask_pd(_mm_cmpgt_pd(t, bound)) == 0) continue;
                alignas(16) double tt[2];
                _mm_store_pd(tt, t);
                const std::uint32_t e = offsets_[v] + 2 * i;
                if (tt[0] > best_dot) { best_dot = tt[0]; best = neighbours_[e]; }
                // (The second lane of an odd count's last pair repeats the first: never greater.)
                if (tt[1] > best_dot) { best_dot = tt[1]; best = neighbours_[e + 1]; }
                bound = _mm_set1_pd(best_dot);
            }
            return;
        }
#endif
        for (std::uint32_t e = offsets_[v]; e < offsets_[v + 1]; ++e) {
            const S t = d.dot(vertices_[neighbours_[e]]);
            if (t > best_dot) { best_dot = t; best = neighbours_[e]; }
        }
    }
    /// Each vertex's neighbours' coordinates, two at a time as [x₀ x₁ y₀ y₁ z₀ z₁] (an odd count repeats the
    /// last neighbour), for scan_neighbours: the hint scan and the climb need no index loads and do two
    /// neighbours per operation. 24 bytes per adjacency entry (about 6× the vertices' own bytes).
    void build_rings() {
        if constexpr (has_rings) {
            ring_begin_.assign(1, 0);
            rings_.clear();
            for (std::uint32_t v = 0; v + 1 < offsets_.size(); ++v) {
                const std::uint32_t b = offsets_[v], n = offsets_[v + 1] - b;
                for (std::uint32_t k = 0; k < n; k += 2) {
                    const Vec3<S>& x0 = vertices_[neighbours_[b + k]];
                    const Vec3<S>& x1 = vertices_[neighbours_[b + std::min(k + 1, n - 1)]];
                    for (int c = 0; c < 3; ++c) {
                        rings_.push_back(x0[c]);
                        rings_.push_back(x1[c]);
                    }
                }
                ring_begin_.push_back(std::uint32_t(rings_.size() / 6));
            }
        }
    }

    [[nodiscard]] std::uint32_t brute_force_index(const Vec3<S>& d) const noexcept {
        std::uint32_t best = 0;
        S best_dot = d.dot(vertices_[0]);
        for (std::uint32_t i = 1; i < vertices_.size(); ++i) {
            S v = d.dot(vertices_[i]);
            if (v > best_dot) { best_dot = v; best = i; }
        }
        return best;
    }
    std::vector<Vec3<S>> vertices_;
    std::uint32_t vertex_count_ = 0;  ///< vertices_.size(), kept for the inlined hint test
    std::vector<std::array<std::uint32_t, 3>> triangles_;
    std::vector<std::uint32_t> offsets_, neighbours_;
    std::vector<double> rings_;             ///< see build_rings (empty without SSE2 or for S ≠ double)
    std::vector<std::uint32_t> ring_begin_;  ///< vertex v's ring: pairs ring_begin_[v] .. ring_begin_[v + 1]
    std::array<std::uint32_t, 6> seeds_{};
    std::vector<std::uint32_t> start_table_;  ///< see build_start_table (empty for brute-force hulls)
    int support_res_ = table_res;  ///< cells per cube-face side of start_table_ (table_res … 4·table_res)
    S certified_low_ = S(1), certified_high_ = S(0);  ///< range of |d|∞ for certified cells (empty: none)
    /// The tetrahedron joining the centre to a hull triangle (see build_cones).
    struct CentralCone {
        Vec3<S> normal = Vec3<S>::Zero();  ///< the triangle's outward unit normal; its plane is normal·x = offset
        S offset = S(0);
        std::array<Vec3<S>, 3> side{};    ///< inward unit normals of the planes through the centre and edge e
        std::array<S, 3> side_offset{};    ///< (edge e joins the triangle's corners e and e + 1)
        std::array<std::uint32_t, 3> next{};  ///< the triangle across edge e
    };
    std::vector<CentralCone> cones_;           ///< empty: no containment test (see build_cones)
    std::vector<std::uint32_t> cone_table_;    ///< a cell's centre direction lies in this tetrahedron's cone
    std::vector<std::uint32_t> vertex_begin_cone_{0}, vertex_cone_;  ///< the tetrahedra at each vertex (CSR)
    S containment_error_ = S(0);
    Vec3<S> center_ = Vec3<S>::Zero();
    // Boundary topology in CSR form (see the accessors).
    std::vector<std::uint32_t> face_begin_, face_loop_, face_edge_;
    std::vector<Vec3<S>> face_normals_;
    std::vector<S> face_offsets_;
    std::vector<PolyhedronEdge<S>> edges_;
    std::vector<std::uint32_t> vertex_begin_, vertex_edge_;
    std::vector<Vec3<S>> vertex_edge_dir_;
    S radius_ = S(0);
    S bounding_radius_ = S(0), inner_radius_ = S(0);
    bool topology_ok_ = false;
};

}  // namespace cdkit
