#pragma once
/// \file A convex polyhedron built as the convex hull of a point set, with a support map.
///
/// The hull is computed once at construction by Qhull (Barber, Dobkin, Huhdanpaa, "The Quickhull
/// algorithm for convex hulls", ACM TOMS 1996) in src/convex/convex_hull.cpp, linked privately.
/// Support queries scan all vertices for small hulls and otherwise climb the vertex adjacency graph
/// (a linear function has no local maximum on a convex polytope's graph that is not global; van den
/// Bergen 2003, §4.3.4 "hill climbing").

#include <cdkit/core/error.hpp>
#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/support.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace cdkit {

namespace detail {
/// Output of the hull builder: hull vertices (subset of the input, in double), outward-oriented triangles
/// indexing them, and the input index each hull vertex came from.
struct HullData {
    std::vector<Vec3<double>> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::uint32_t> source_index;
};
/// Builds the 3-D convex hull of `points`. Raises cdkit::Error for fewer than 4 points, non-finite
/// coordinates, or a flat (coplanar/collinear/coincident) set.
HullData convex_hull(const std::vector<Vec3<double>>& points);
}  // namespace detail

/// A solid convex polyhedron: the convex hull of the given points, in their frame.
template <class S = double> class ConvexPolyhedron {
public:
    using Scalar = S;
    /// Hulls with at most this many vertices are searched by brute force; larger ones by hill climbing.
    static constexpr std::size_t brute_force_limit = 48;

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
        // Adjacency in CSR form, from the triangle edges (each undirected edge once per direction).
        std::vector<std::vector<std::uint32_t>> adj(vertices_.size());
        for (const auto& t : triangles_)
            for (int k = 0; k < 3; ++k) adj[t[k]].push_back(t[(k + 1) % 3]);  // every edge appears in both
        offsets_.assign(1, 0);                                                 // directions over the faces
        for (auto& a : adj) {
            neighbours_.insert(neighbours_.end(), a.begin(), a.end());
            offsets_.push_back(std::uint32_t(neighbours_.size()));
        }
        // Hill-climbing seeds: the extreme vertices along ±x, ±y, ±z.
        for (int axis = 0; axis < 3; ++axis)
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                Vec3<S> d = Vec3<S>::Zero();
                d[axis] = S(sgn);
                seeds_[std::size_t(2 * axis + (sgn + 1) / 2)] = brute_force_index(d);
            }
    }

    /// The vertex maximising d·x. Const, noexcept, thread-safe (no cached state).
    [[nodiscard]] Vec3<S> support(const Vec3<S>& d) const noexcept { return vertices_[support_index(d)]; }
    /// Index into vertices() of a vertex maximising d·x.
    [[nodiscard]] std::uint32_t support_index(const Vec3<S>& d) const noexcept {
        if (vertices_.size() <= brute_force_limit) return brute_force_index(d);
        std::uint32_t best = seeds_[0];
        S best_dot = d.dot(vertices_[best]);
        for (std::size_t k = 1; k < 6; ++k) {
            S v = d.dot(vertices_[seeds_[k]]);
            if (v > best_dot) { best_dot = v; best = seeds_[k]; }
        }
        // Climb; each step strictly increases d·x, so it stops after at most |V| steps.
        for (bool moved = true; moved;) {
            moved = false;
            for (std::uint32_t e = offsets_[best]; e < offsets_[best + 1]; ++e) {
                S v = d.dot(vertices_[neighbours_[e]]);
                if (v > best_dot) { best_dot = v; best = neighbours_[e]; moved = true; }
            }
        }
        return best;
    }
    /// The vertex average (an interior point).
    [[nodiscard]] Vec3<S> center() const noexcept { return center_; }
    [[nodiscard]] const std::vector<Vec3<S>>& vertices() const noexcept { return vertices_; }
    /// Outward-oriented (counter-clockwise seen from outside) hull triangles indexing vertices().
    [[nodiscard]] const std::vector<std::array<std::uint32_t, 3>>& triangles() const noexcept {
        return triangles_;
    }

private:
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
    Vec3<S> center_ = Vec3<S>::Zero();
};

}  // namespace cdkit
