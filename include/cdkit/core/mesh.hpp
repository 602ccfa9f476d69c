#pragma once
/// \file TriangleMesh: an indexed triangle soup, its validation and its statistics.

#include "cdkit/core/error.hpp"
#include "cdkit/core/math.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

namespace cdkit {

using Index = std::uint32_t;
using Triangle = std::array<Index, 3>;

/// Vertices plus triangles as index triples. No orientation, closedness or manifoldness is required
/// (polygon soups are first-class); `compute_stats` tells what a mesh is. `source` names where the mesh
/// came from (a file path, or "<mesh>"), and every Error raised about this mesh names it.
template <class S = double> struct TriangleMesh {
    using Scalar = S;
    std::vector<Vec3<S>> vertices;
    std::vector<Triangle> triangles;
    std::string source = "<mesh>";

    [[nodiscard]] std::size_t num_vertices() const noexcept { return vertices.size(); }
    [[nodiscard]] std::size_t num_triangles() const noexcept { return triangles.size(); }
    [[nodiscard]] bool empty() const noexcept { return triangles.empty(); }
    [[nodiscard]] std::array<Vec3<S>, 3> triangle(std::size_t i) const noexcept {
        const Triangle& t = triangles[i];
        return {vertices[t[0]], vertices[t[1]], vertices[t[2]]};
    }
    /// Bytes of the vertex and index arrays (what "the mesh's memory" means in size ratios).
    [[nodiscard]] std::size_t memory_bytes() const noexcept {
        return vertices.size() * sizeof(Vec3<S>) + triangles.size() * sizeof(Triangle);
    }
    template <class T> [[nodiscard]] TriangleMesh<T> cast() const {
        TriangleMesh<T> m;
        m.vertices.reserve(vertices.size());
        for (const auto& v : vertices) m.vertices.push_back(v.template cast<T>());
        m.triangles = triangles;
        m.source = source;
        return m;
    }
};

/// Throws cdkit::Error (naming mesh.source and the first offending element) when the mesh has no
/// triangles, a non-finite vertex coordinate, or an index out of range. Degenerate triangles are allowed:
/// they are legal polygon soup, and every query handles them.
template <class S> void validate(const TriangleMesh<S>& mesh) {
    if (mesh.triangles.empty()) throw Error(mesh.source, "", "mesh has no triangles");
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
        if (!mesh.vertices[i].allFinite())
            throw Error(mesh.source, "vertex " + std::to_string(i), "coordinate is NaN or infinite");
    const std::size_t n = mesh.vertices.size();
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
        for (Index v : mesh.triangles[i])
            if (v >= n)
                throw Error(mesh.source, "triangle " + std::to_string(i),
                            "vertex index " + std::to_string(v) + " out of range (" + std::to_string(n) +
                                " vertices)");
}

/// What a mesh is: counts and the defects that matter to the queries.
struct MeshStats {
    std::size_t vertices = 0;
    std::size_t triangles = 0;
    std::size_t degenerate_triangles = 0;  ///< a repeated vertex index, or edge vectors whose cross product evaluates to zero
    std::size_t duplicate_triangles = 0;   ///< same vertex set as an earlier triangle (any order)
    std::size_t edges = 0;                 ///< distinct undirected edges
    std::size_t boundary_edges = 0;        ///< used by exactly one triangle
    std::size_t non_manifold_edges = 0;    ///< used by three or more triangles
    std::size_t inconsistent_edges = 0;    ///< two triangles traverse the edge in the same direction
    bool closed = false;                   ///< every edge used by exactly two triangles
    bool consistently_oriented = false;    ///< closed and no inconsistent edge
};

/// Computes MeshStats in O(n log n). The mesh must be valid (see validate()).
template <class S> [[nodiscard]] MeshStats compute_stats(const TriangleMesh<S>& mesh) {
    MeshStats st;
    st.vertices = mesh.vertices.size();
    st.triangles = mesh.triangles.size();
    std::vector<Triangle> sorted;
    sorted.reserve(mesh.triangles.size());
    // Directed edges (from, to); undirected grouping via (min, max).
    std::vector<std::tuple<Index, Index, std::int8_t>> edges;
    edges.reserve(mesh.triangles.size() * 3);
    for (const Triangle& t : mesh.triangles) {
        const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
        const Vec3<S>& a = mesh.vertices[t[0]];
        const Vec3<S>& b = mesh.vertices[t[1]];
        const Vec3<S>& c = mesh.vertices[t[2]];
        if (repeated || (b - a).cross(c - a).squaredNorm() == S(0)) ++st.degenerate_triangles;
        Triangle s = t;
        std::sort(s.begin(), s.end());
        sorted.push_back(s);
        if (repeated) continue;  // edges of a collapsed triangle do not bound anything
        for (int k = 0; k < 3; ++k) {
            Index u = t[k], v = t[(k + 1) % 3];
            edges.emplace_back(std::min(u, v), std::max(u, v), std::int8_t(u < v ? 1 : -1));
        }
    }
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 1; i < sorted.size(); ++i)
        if (sorted[i] == sorted[i - 1]) ++st.duplicate_triangles;
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        int forward = 0, backward = 0;
        while (j < edges.size() && std::get<0>(edges[j]) == std::get<0>(edges[i]) &&
               std::get<1>(edges[j]) == std::get<1>(edges[i])) {
            (std::get<2>(edges[j]) > 0 ? forward : backward)++;
            ++j;
        }
        ++st.edges;
        const int uses = forward + backward;
        if (uses == 1) ++st.boundary_edges;
        else if (uses > 2) ++st.non_manifold_edges;
        else if (forward != 1) ++st.inconsistent_edges;
        i = j;
    }
    st.closed = st.edges > 0 && st.boundary_edges == 0 && st.non_manifold_edges == 0;
    st.consistently_oriented = st.closed && st.inconsistent_edges == 0;
    return st;
}

/// Joins vertices with bit-identical coordinates and remaps the triangles (assimp's importers split
/// vertices per face for some formats). Keeps the first occurrence's order.
template <class S> void join_identical_vertices(TriangleMesh<S>& mesh) {
    struct Hash {
        std::size_t operator()(const std::array<S, 3>& p) const noexcept {
            std::size_t h = 1469598103934665603ull;
            for (S x : p) {
                if (x == S(0)) x = S(0);  // +0 and -0 are the same point
                h = (h ^ std::hash<S>{}(x)) * 1099511628211ull;
            }
            return h;
        }
    };
    std::unordered_map<std::array<S, 3>, Index, Hash> first;
    first.reserve(mesh.vertices.size());
    std::vector<Index> remap(mesh.vertices.size());
    std::vector<Vec3<S>> joined;
    joined.reserve(mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        const Vec3<S>& v = mesh.vertices[i];
        std::array<S, 3> key{v.x() == S(0) ? S(0) : v.x(), v.y() == S(0) ? S(0) : v.y(),
                             v.z() == S(0) ? S(0) : v.z()};
        auto [it, inserted] = first.emplace(key, Index(joined.size()));
        if (inserted) joined.push_back(v);
        remap[i] = it->second;
    }
    for (Triangle& t : mesh.triangles)
        for (Index& v : t) v = remap[v];
    mesh.vertices = std::move(joined);
}

}  // namespace cdkit
