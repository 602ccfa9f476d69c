#pragma once
/// \file The input gate of inner sphere trees: a mesh must bound a volume. check_closed_mesh() accepts a
/// closed, edge-manifold, consistently oriented mesh with a non-negligible volume and returns that volume
/// (the sum of signed tetrahedra from the origin, i.e. the divergence theorem on the triangle fan).

#include "cdkit/core/mesh.hpp"

#include <cmath>
#include <string>

namespace cdkit {

/// Signed volume enclosed by `mesh`: Σ a·(b×c)/6 over its triangles. Positive for outward-facing
/// (counter-clockwise seen from outside) closed meshes, negative for inward-facing ones; meaningless for
/// open meshes. Accumulated relative to the bounding-box centre to limit cancellation far from the origin.
[[nodiscard]] inline double signed_mesh_volume(const TriangleMesh<double>& mesh) noexcept {
    if (mesh.vertices.empty()) return 0;
    Vec3<double> lo = mesh.vertices[0], hi = mesh.vertices[0];
    for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const Vec3<double> o = (lo + hi) / 2;
    double six_v = 0;
    for (const Triangle& t : mesh.triangles)
        six_v += (mesh.vertices[t[0]] - o).dot((mesh.vertices[t[1]] - o).cross(mesh.vertices[t[2]] - o));
    return six_v / 6;
}

/// Checks that `mesh` can be filled with inner spheres and returns its enclosed volume (> 0).
/// Throws cdkit::Error naming mesh.source when the mesh is invalid (see validate()), is open (boundary
/// edges), has non-manifold edges (used by three or more triangles) or inconsistently oriented edges (the
/// message gives the count of each kind), or when its volume is below 1e-9 of its bounding box's (flat or
/// zero-volume meshes). An inward-facing but otherwise consistent mesh is accepted: its |volume| is used.
inline double check_closed_mesh(const TriangleMesh<double>& mesh) {
    validate(mesh);
    const MeshStats st = compute_stats(mesh);
    if (st.boundary_edges || st.non_manifold_edges || st.inconsistent_edges) {
        std::string why = "inner sphere trees need a closed, manifold, consistently oriented mesh; found " +
                          std::to_string(st.boundary_edges) + " boundary (open) edges, " +
                          std::to_string(st.non_manifold_edges) + " non-manifold edges, " +
                          std::to_string(st.inconsistent_edges) + " inconsistently oriented edges (of " +
                          std::to_string(st.edges) + ")";
        throw Error(mesh.source, "edges", why);
    }
    Vec3<double> lo = mesh.vertices[0], hi = mesh.vertices[0];
    for (const Triangle& t : mesh.triangles)
        for (Index v : t) lo = lo.cwiseMin(mesh.vertices[v]), hi = hi.cwiseMax(mesh.vertices[v]);
    const Vec3<double> ext = hi - lo;
    const double box = ext.x() * ext.y() * ext.z();
    const double volume = std::abs(signed_mesh_volume(mesh));
    if (!(box > 0) || !(volume > 1e-9 * box) || !std::isfinite(volume))
        throw Error(mesh.source, "volume",
                    "mesh encloses no volume (" + std::to_string(volume) + " against a bounding box of " +
                        std::to_string(box) + "): flat, degenerate or too tiny to fill with spheres");
    return volume;
}

}  // namespace cdkit
