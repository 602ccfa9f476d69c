// How deep do two meshes cross? Two bunnies are pushed into each other step by step; at each step
// penetration_depth() answers with the translation of B that undoes every crossing of their surfaces: its length
// (depth), its direction (normal), and where the last triangle pair separates. Printed three ways: the surfaces'
// own normal (the default), with a search of the sphere of directions (refine_steps), and with both meshes' inner
// sphere trees (their penalty force direction competes; the penetration volume comes along).
// Usage: mesh_depth [mesh]   (default: the bundled bunny; exits non-zero when an answer contradicts another)
#include <cdkit/io/load_mesh.hpp>
#include <cdkit/mesh_depth/penetration_depth.hpp>

#include <cstdio>

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

int main(int argc, char** argv) try {
    cdkit::TriangleMesh<double> mesh = cdkit::load_mesh(argc > 1 ? argv[1] : CDKIT_DEFAULT_MESH);
    // Into [-1, 1]^3, so that the printed depths read as fractions of the object's size.
    V lo = mesh.vertices[0], hi = lo;
    for (const V& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    for (V& v : mesh.vertices) v = (v - (lo + hi) / 2) * (2 / (hi - lo).maxCoeff());
    const cdkit::MeshModel<cdkit::Obb<double>> model(mesh);
    cdkit::PackingOptions packing;
    packing.max_spheres = 2000;
    const cdkit::InnerSphereTree ist = cdkit::build_inner_sphere_tree(mesh, packing);

    const T pa;
    const cdkit::Mat3<double> turn = Eigen::AngleAxisd(2.0, V(0.3, 1, 0.2).normalized()).toRotationMatrix();
    cdkit::MeshDepthRequest refine;
    refine.refine_steps = 2;
    int contradictions = 0;
    std::printf("%7s %9s %9s %9s %9s %22s\n", "offset", "surface", "refined", "with IST", "volume", "normal (surface)");
    for (double x = 1.6; x >= 0.9; x -= 0.1) {
        const T pb(turn, V(x, 0.1, 0.0));
        const cdkit::MeshDepthResult s = cdkit::penetration_depth(model, pa, model, pb);
        const cdkit::MeshDepthResult r = cdkit::penetration_depth(model, pa, model, pb, refine);
        const cdkit::MeshDepthResult v = cdkit::penetration_depth(model, ist, pa, model, ist, pb);
        std::printf("%7.2f %9.4f %9.4f %9.4f %9.5f   (%6.3f %6.3f %6.3f)\n", x, s.depth, r.depth, v.depth, v.volume,
                    s.normal.x(), s.normal.y(), s.normal.z());
        // The three agree on whether the surfaces cross; more candidates can only shorten the default's translation;
        // the last pair to separate touches after it (its points are depth·normal apart).
        contradictions += s.colliding != r.colliding || s.colliding != v.colliding;
        contradictions += r.depth > s.depth + 1e-12 || v.depth > s.depth + 1e-12;
        if (s.colliding) contradictions += (s.point_a - s.point_b - s.depth * s.normal).norm() > 1e-9;
    }
    std::printf("\n%s\n", contradictions == 0 ? "all answers consistent" : "CONTRADICTIONS");
    return contradictions == 0 ? 0 : 1;
} catch (const std::exception& e) {
    std::fprintf(stderr, "mesh_depth: %s\n", e.what());
    return 1;
}
