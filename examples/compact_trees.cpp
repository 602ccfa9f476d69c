// Compact trees for big meshes: the same bunny under three trees of falling size — Obb<double>, float Obbs over
// the double mesh with four triangles per leaf, and the restricted boxtree (8-byte nodes, smaller than the mesh) — with their bytes against
// the mesh's, the same contact pairs and separation distance from all three, and a refit of the boxtree after
// the mesh deforms.
// Usage: compact_trees [mesh file]   (default: data/bunny.obj)
#include <cdkit/cdkit.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <utility>
#include <vector>

namespace {
template <class Result> std::vector<std::pair<cdkit::Index, cdkit::Index>> pairs_of(const Result& r) {
    std::vector<std::pair<cdkit::Index, cdkit::Index>> p;
    for (const auto& c : r.contacts) p.emplace_back(c.triangle_a, c.triangle_b);
    std::sort(p.begin(), p.end());
    return p;
}
}  // namespace

int main(int argc, char** argv) try {
    using namespace cdkit;
    const char* path = argc > 1 ? argv[1] : CDKIT_DEFAULT_MESH;
    const auto mesh = std::make_shared<const TriangleMesh<double>>(load_mesh(path));

    // One mesh, shared by the three models (no copies): only the trees differ.
    const MeshModel<Obb<double>> obb(mesh);
    BuildOptions four;
    four.max_leaf_triangles = 4;                                // fewer nodes: under 2x the mesh's bytes
    const MeshModel<Obb<float>, double> obb_float(mesh, four);  // float boxes, rounded outwards: still exact
    RestrictedBoxtree<double> boxtree(mesh);              // one plane per node, leaves of one triangle

    const double mesh_bytes = double(mesh->memory_bytes());
    std::printf("%s: %zu triangles, mesh %.0f KiB\n", path, mesh->num_triangles(), mesh_bytes / 1024);
    std::printf("  Obb<double> tree         %7.1f B/triangle  %.2fx the mesh\n",
                double(obb.memory_bytes()) / double(mesh->num_triangles()), double(obb.memory_bytes()) / mesh_bytes);
    std::printf("  Obb<float>/double, 4/leaf %5.1f B/triangle  %.2fx the mesh\n",
                double(obb_float.memory_bytes()) / double(mesh->num_triangles()), double(obb_float.memory_bytes()) / mesh_bytes);
    std::printf("  restricted boxtree       %7.1f B/triangle  %.2fx the mesh\n",
                double(boxtree.memory_bytes()) / double(mesh->num_triangles()), double(boxtree.memory_bytes()) / mesh_bytes);

    // Two copies, the second turned and shifted by a tenth of the mesh's size: every tree finds the same pairs.
    Vec3<double> lo = mesh->vertices[0], hi = lo;
    for (const auto& v : mesh->vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double size = (hi - lo).maxCoeff();
    const Transform<double> pose_a;
    const Transform<double> pose_b(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                                   Eigen::Vector3d(0.1 * size, 0.0, 0.0));
    const CollisionRequest all{ContactMode::all};
    const auto p_obb = pairs_of(collide(obb, pose_a, obb, pose_b, all));
    const auto p_float = pairs_of(collide(obb_float, pose_a, obb_float, pose_b, all));
    const auto p_box = pairs_of(collide(boxtree, pose_a, boxtree, pose_b, all));
    std::printf("contact pairs: Obb<double> %zu, Obb<float> %zu, boxtree %zu\n", p_obb.size(), p_float.size(), p_box.size());
    if (p_obb.empty() || p_obb != p_float || p_obb != p_box) {
        std::fprintf(stderr, "error: the trees disagree\n");
        return 1;
    }

    // Pulled apart: every tree answers the same separation distance (exact: the minimum over triangle pairs).
    const Transform<double> pose_c(pose_b.R, Eigen::Vector3d(1.2 * size, 0.0, 0.0));
    const double d_obb = distance(obb, pose_a, obb, pose_c).distance;
    const double d_float = distance(obb_float, pose_a, obb_float, pose_c).distance;
    const double d_box = distance(boxtree, pose_a, boxtree, pose_c).distance;
    std::printf("separation distance: Obb<double> %.9g, Obb<float> %.9g, boxtree %.9g\n", d_obb, d_float, d_box);
    if (!(d_obb > 0) || d_obb != d_float || d_obb != d_box) {
        std::fprintf(stderr, "error: the distances disagree\n");
        return 1;
    }

    // The mesh bends (same triangles, moved vertices): refit the boxtree in O(n) instead of rebuilding it.
    auto bent = std::make_shared<TriangleMesh<double>>(*mesh);
    for (auto& v : bent->vertices) v.y() += 0.05 * size * std::sin(6.0 * (v.x() - lo.x()) / size);
    boxtree.refit(bent);
    const RestrictedBoxtree<double> rebuilt(bent);
    const auto p_refit = pairs_of(collide(boxtree, pose_a, boxtree, pose_b, all));
    const auto p_rebuilt = pairs_of(collide(rebuilt, pose_a, rebuilt, pose_b, all));
    std::printf("after bending: refitted boxtree %zu pairs, rebuilt boxtree %zu pairs\n", p_refit.size(), p_rebuilt.size());
    return p_refit == p_rebuilt ? 0 : 1;
} catch (const cdkit::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
}
