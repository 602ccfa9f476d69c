#pragma once
/// \file Area-weighted first and second moments of triangles, precomputed once per mesh so that a top-down
/// build fits each node's PCA frame (Gottschalk, Lin, Manocha, "OBBTree", SIGGRAPH 1996) from sums of ten
/// numbers per triangle instead of re-deriving outer products from the vertices at every level.

#include "cdkit/core/detail/parallel_loop.hpp"
#include "cdkit/core/mesh.hpp"

#include <vector>

namespace cdkit {

/// One triangle's moments about a common origin o: area, area·(centroid − o), and the upper triangle
/// (xx, xy, xz, yy, yz, zz) of ∫(x − o)(x − o)ᵀ dA = area/12 · (9 m mᵀ + p pᵀ + q qᵀ + r rᵀ).
struct TriangleMoments {
    double area = 0;
    double first[3] = {0, 0, 0};
    double second[6] = {0, 0, 0, 0, 0, 0};
};

/// The moments of every triangle of `mesh` about `origin`, and that origin: what a build needs to sum
/// node moments. Moments far from the origin relative to the node's size cancel in the covariance;
/// Obb::fit detects that and falls back to node-local moments.
struct MeshMoments {
    Eigen::Matrix<double, 3, 1> origin = Eigen::Matrix<double, 3, 1>::Zero();
    std::vector<TriangleMoments> triangles;
};

/// Triangles in parallel blocks when `parallel` (and TBB is on): the same numbers either way.
template <class S> [[nodiscard]] MeshMoments triangle_moments(const TriangleMesh<S>& mesh, bool parallel = true) {
    using D3 = Eigen::Matrix<double, 3, 1>;
    MeshMoments out;
    if (mesh.vertices.empty()) return out;
    D3 lo = mesh.vertices[0].template cast<double>(), hi = lo;
    for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v.template cast<double>()), hi = hi.cwiseMax(v.template cast<double>());
    out.origin = (lo + hi) / 2;
    out.triangles.resize(mesh.triangles.size());
    detail::for_each_index(mesh.triangles.size(), [&](std::size_t i) {
        const auto& t = mesh.triangles[i];
        const D3 p = mesh.vertices[t[0]].template cast<double>() - out.origin;
        const D3 q = mesh.vertices[t[1]].template cast<double>() - out.origin;
        const D3 r = mesh.vertices[t[2]].template cast<double>() - out.origin;
        const double area = 0.5 * (q - p).cross(r - p).norm();
        const D3 m = (p + q + r) / 3.0;
        TriangleMoments& tm = out.triangles[i];
        tm.area = area;
        for (int k = 0; k < 3; ++k) tm.first[k] = area * m[k];
        const double w = area / 12.0;
        int s = 0;
        for (int a = 0; a < 3; ++a)
            for (int b = a; b < 3; ++b)
                tm.second[s++] = w * (9.0 * m[a] * m[b] + p[a] * p[b] + q[a] * q[b] + r[a] * r[b]);
    }, parallel);
    return out;
}

}  // namespace cdkit
