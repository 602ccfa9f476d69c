// Robot links against an environment mesh: a capsule, a box and a convex hull sweep down onto the bunny, and at
// each step the mesh–convex queries answer: collide() (do they touch, and where), distance() (how far, between
// which points, to which triangle) and penetration() (per touching triangle, how deep and along which normal).
// Usage: mesh_convex [mesh]   (default: the bundled bunny; exits non-zero when the answers contradict each other)
#include <cdkit/io/load_mesh.hpp>
#include <cdkit/mesh_convex.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

/// Lowers `shape` from above the mesh onto it and prints what the three queries say at each height.
template <class Shape> int sweep(const char* name, const cdkit::MeshModel<cdkit::Obb<double>>& mesh, const Shape& shape) {
    std::printf("\n%s\n%8s %9s %10s %9s %11s %9s\n", name, "height", "colliding", "distance", "triangle", "contacts",
                "depth");
    const T mesh_pose;  // the mesh at the origin; the shape tilted and lowered along -y
    const cdkit::Mat3<double> tilt = Eigen::AngleAxisd(0.4, V(1, 0, 1).normalized()).toRotationMatrix();
    int contradictions = 0;
    for (double h = 1.0; h >= 0.2; h -= 0.1) {
        const T pose(tilt, V(-0.3, h, 0.1));
        const cdkit::MeshConvexResult<double> hit = cdkit::collide(mesh, mesh_pose, shape, pose);
        const cdkit::MeshConvexDistanceResult<double> d = cdkit::distance(mesh, mesh_pose, shape, pose);
        const cdkit::MeshConvexPenetrationResult<double> p =
            cdkit::penetration(mesh, mesh_pose, shape, pose, cdkit::MeshConvexRequest{cdkit::ContactMode::all});
        std::printf("%8.2f %9s %10.5f %9u %11zu %9.5f\n", h, hit.colliding ? "yes" : "no", d.distance, d.triangle,
                    p.contacts.size(), p.colliding ? p.deepest.depth : 0.0);
        // The three must agree on whether the shape touches the mesh (up to GJK's touching tolerance).
        if (hit.colliding != p.colliding || (hit.colliding && d.distance > 1e-9) || (!hit.colliding && d.distance == 0))
            ++contradictions;
    }
    return contradictions;
}

int main(int argc, char** argv) try {
    cdkit::TriangleMesh<double> mesh = cdkit::load_mesh(argc > 1 ? argv[1] : CDKIT_DEFAULT_MESH);
    // Into [-1, 1]³ about the box centre, as the benchmarks do.
    V lo = mesh.vertices[0], hi = lo;
    for (const V& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    for (V& v : mesh.vertices) v = (v - 0.5 * (lo + hi)) * (2.0 / (hi - lo).maxCoeff());
    const cdkit::MeshModel<cdkit::Obb<double>> model(std::move(mesh));  // validates and builds the tree once
    std::printf("%zu triangles\n", model.mesh().triangles.size());

    std::vector<V> pts;  // a rounded link: 64 points on an ellipsoid, hulled by Qhull
    for (int i = 0; i < 64; ++i) {
        const double z = 1 - (2 * i + 1) / 64.0, r = std::sqrt(1 - z * z), a = 2.39996 * i;
        pts.push_back(V(0.15 * r * std::cos(a), 0.08 * r * std::sin(a), 0.1 * z));
    }
    int bad = 0;
    bad += sweep("capsule r 0.05, length 0.3", model, cdkit::Capsule<double>(0.05, 0.15));
    bad += sweep("box 0.2 x 0.12 x 0.3", model, cdkit::Box<double>(V(0.1, 0.06, 0.15)));
    bad += sweep("convex hull of 64 points", model, cdkit::ConvexPolyhedron<double>(pts));

    // Bad input answers with a status, never with a crash or a silent "no".
    cdkit::Sphere<double> broken(0.1);
    broken.radius = std::nan("");
    const auto r = cdkit::collide(model, T(), broken, T());
    std::printf("\nNaN radius: status %s\n", cdkit::to_string(r.status));
    if (r.status != cdkit::QueryStatus::invalid_input) ++bad;
    return bad == 0 ? 0 : 1;
} catch (const cdkit::Error& e) {
    std::fprintf(stderr, "mesh_convex: %s\n", e.what());
    return 1;
}
