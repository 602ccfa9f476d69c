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
#include <utility>
#include <vector>

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
        build_topology(h.faces);
        build_balls();
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
    [[nodiscard]] std::uint32_t support_index(const Vec3<S>& d, std::uint32_t hint) const noexcept {
        std::uint32_t best = std::uint32_t(-1);
        S best_dot = S(0);
        if (hint < vertices_.size()) {
            // A coherent caller's hint is usually the answer: one scan of its neighbours proves it (a local
            // maximum is the global one) without the table lookup, whose division and load would sit on the
            // query's critical path.
            best = hint;
            best_dot = d.dot(vertices_[hint]);
            for (std::uint32_t e = offsets_[hint]; e < offsets_[hint + 1]; ++e) {
                const S v = d.dot(vertices_[neighbours_[e]]);
                if (v > best_dot) { best_dot = v; best = neighbours_[e]; }
            }
            // (Not when the products overflowed to −∞ around the hint: a tie there proves nothing.)
            if (best == hint && best_dot >= -std::numeric_limits<S>::max()) return hint;
        }
        if (vertices_.size() <= brute_force_limit) return brute_force_index(d);
        const std::uint32_t start = table_start(d);
        if (start != std::uint32_t(-1)) {
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
    void build_start_table() {
        if (vertices_.size() <= brute_force_limit) return;
        start_table_.resize(std::size_t(6 * table_res * table_res));
        for (int face = 0; face < 6; ++face)
            for (int i = 0; i < table_res; ++i)
                for (int j = 0; j < table_res; ++j) {
                    const int axis = face / 2;
                    Vec3<S> d;
                    d[axis] = face % 2 ? S(-1) : S(1);
                    d[(axis + 1) % 3] = S(2 * i + 1) / S(table_res) - S(1);
                    d[(axis + 2) % 3] = S(2 * j + 1) / S(table_res) - S(1);
                    start_table_[std::size_t((face * table_res + i) * table_res + j)] = brute_force_index(d);
                }
    }
    /// The table's start vertex for direction d; uint32(-1) when d is zero or not finite.
    [[nodiscard]] CDKIT_ALWAYS_INLINE std::uint32_t table_start(const Vec3<S>& d) const noexcept {
        const S x = d[0], y = d[1], z = d[2];
        const S ax = std::abs(x), ay = std::abs(y), az = std::abs(z);
        int face;
        S m, u, v;
        if (ax >= ay && ax >= az) { face = x < S(0); m = ax; u = y; v = z; }
        else if (ay >= az) { face = 2 + (y < S(0)); m = ay; u = z; v = x; }
        else { face = 4 + (z < S(0)); m = az; u = x; v = y; }
        constexpr S half = S(table_res) / S(2);
        const S k = half / m;
        // |u|, |v| ≤ m, so fi, fj lie in [0, table_res] up to rounding; anything else (NaN or infinite
        // components, a zero or subnormal direction) falls back to the seeds.
        const S fi = u * k + half, fj = v * k + half;
        if (!(fi > S(-1) && fi < S(table_res + 1) && fj > S(-1) && fj < S(table_res + 1))) return std::uint32_t(-1);
        const int i = std::clamp(int(fi), 0, table_res - 1);
        const int j = std::clamp(int(fj), 0, table_res - 1);
        return start_table_[std::size_t((face * table_res + i) * table_res + j)];
    }
    /// Climbs to the best neighbour of the current vertex until none is better; each step strictly
    /// increases d·x, so it stops after at most |V| steps.
    [[nodiscard]] std::uint32_t climb(const Vec3<S>& d, std::uint32_t best, S best_dot) const noexcept {
        for (;;) {
            const std::uint32_t from = best;
            for (std::uint32_t e = offsets_[from]; e < offsets_[from + 1]; ++e) {
                const S v = d.dot(vertices_[neighbours_[e]]);
                if (v > best_dot) { best_dot = v; best = neighbours_[e]; }
            }
            if (best == from) return best;
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
    std::vector<std::array<std::uint32_t, 3>> triangles_;
    std::vector<std::uint32_t> offsets_, neighbours_;
    std::array<std::uint32_t, 6> seeds_{};
    std::vector<std::uint32_t> start_table_;  ///< see build_start_table (empty for brute-force hulls)
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
