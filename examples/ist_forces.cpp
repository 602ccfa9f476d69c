// Inner sphere trees: penalty force and torque between two bunnies along a path.
//
// Packs the mesh with inner spheres, builds the tree, then slides a second copy through the first one and
// prints, per step, the penetration volume of the inner spheres, its estimate of the meshes' intersection
// volume (`calibrated`: the cell spheres' lenses) next to a reference of it (mesh_intersection_volume, exact
// along lines), the number of overlapping sphere pairs and the penalty force and torque on the moving copy
// (stiffness 1: force = volume-weighted push along the sphere centre lines).
//
// Usage: ist_forces [mesh] [spheres]   (default: the bundled bunny, 2000 spheres)
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/ist/inner_sphere_tree.hpp"
#include "cdkit/ist/intersection_volume.hpp"
#include "cdkit/ist/ist_query.hpp"
#include "cdkit/ist/penalty_force.hpp"

#include <cstdio>
#include <cstdlib>
#include <exception>

#ifndef CDKIT_DEFAULT_MESH
#define CDKIT_DEFAULT_MESH "data/bunny.obj"
#endif

int main(int argc, char** argv) {
    try {
        cdkit::TriangleMesh<double> mesh = cdkit::load_mesh(argc > 1 ? argv[1] : CDKIT_DEFAULT_MESH);
        // Work in units of the mesh's size: scale into [-1, 1]^3 around the bounding-box centre.
        Eigen::Vector3d lo = mesh.vertices[0], hi = lo;
        for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
        for (auto& v : mesh.vertices) v = (v - (lo + hi) / 2) * (2 / (hi - lo).maxCoeff());

        cdkit::PackingOptions packing;
        packing.max_spheres = argc > 2 ? std::size_t(std::atol(argv[2])) : 2000;
        const cdkit::InnerSphereTree tree = cdkit::build_inner_sphere_tree(mesh, packing);
        std::printf("%zu inner spheres cover %.1f%% of the volume %.4f; tree of %zu nodes, depth %zu\n",
                    tree.spheres().size(), 100 * tree.coverage(), tree.mesh_volume(), tree.nodes().size(),
                    tree.stats().depth);

        const cdkit::Transform<double> pose_a;  // the fixed copy, at the origin
        const cdkit::InsideTest inside_a(mesh);
        std::printf("%6s %9s %9s %9s %6s %31s %31s\n", "x", "spheres", "estimate", "meshes", "pairs", "force on B",
                    "torque on B");
        const int steps = 16;
        for (int i = 0; i <= steps; ++i) {
            // B comes in along -x from just outside contact, turning slowly about y.
            const double s = double(i) / steps;
            const cdkit::Transform<double> pose_b(
                Eigen::AngleAxisd(0.5 * s, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                Eigen::Vector3d(1.8 - 0.7 * s, 0.1, 0.0));
            const auto volume = cdkit::penetration_volume(tree, pose_a, tree, pose_b);
            const auto w = cdkit::penalty_wrench(volume, tree, pose_a, tree, pose_b, 1.0, pose_a.t, pose_b.t);
            cdkit::TriangleMesh<double> moved = mesh;
            for (auto& v : moved.vertices) v = pose_b * v;
            const auto reference = cdkit::mesh_intersection_volume(inside_a, cdkit::InsideTest(std::move(moved)),
                                                                   {.grid = 96, .passes = 2});
            std::printf("%6.3f %9.5f %9.5f %9.5f %6zu  (%8.5f %8.5f %8.5f)  (%8.5f %8.5f %8.5f)\n", pose_b.t.x(),
                        volume.volume, volume.calibrated, reference.volume, volume.pairs.size(), w.on_b.force.x(), w.on_b.force.y(), w.on_b.force.z(), w.on_b.torque.x(),
                        w.on_b.torque.y(), w.on_b.torque.z());
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ist_forces: %s\n", e.what());
        return 1;
    }
}
