// The convex narrow phase on one pair over a short coherent motion: the bunny's convex hull (a ConvexPolyhedron
// from its vertices, by Qhull) and a second hull approach, touch and pass through each other, one frame at a time.
// Each frame asks every method the docs describe and prints what it answers:
//   gjk_distance with a per-pair GjkCache (warm start), closest_features with its cache (V-Clip-style walk),
//   gjk_intersect, separating_plane_intersect with its cache (the lecture's perceptron plane), and, where the
//   shapes overlap, penetration: EPA's depth as a bracket [depth_lower, depth], its normal and witness points.
// Then a capsule against the hull (a margin shape: GJK runs on its segment core).
// Usage: convex_pair [mesh]   (default: the bundled bunny; exits non-zero when two methods disagree)
#include <cdkit/io/load_mesh.hpp>
#include <cdkit/narrowphase/closest_features.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/epa.hpp>
#include <cdkit/narrowphase/gjk.hpp>
#include <cdkit/narrowphase/separating_plane.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

using cdkit::to_string;

int main(int argc, char** argv) try {
    const char* path = argc > 1 ? argv[1] : CDKIT_DEFAULT_MESH;
    cdkit::TriangleMesh<double> mesh = cdkit::load_mesh(path);
    // The hull of the mesh's vertices, scaled to unit size about its centre (throws cdkit::Error on fewer than
    // four points, NaN or a flat set).
    V lo = mesh.vertices[0], hi = lo;
    for (const V& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const V centre = (lo + hi) / 2;
    const double scale = 1.0 / (hi - lo).maxCoeff();
    std::vector<V> points;
    for (const V& v : mesh.vertices) points.push_back((v - centre) * scale);
    const cdkit::ConvexPolyhedron<double> hull(points);
    std::printf("%s: %zu vertices -> convex hull of %zu vertices\n", path, mesh.vertices.size(), hull.vertices().size());

    // B: the same hull, turning, moved from x = 1.6 through the origin's neighbourhood and back out.
    cdkit::GjkCache<double> gjk_cache;
    cdkit::ClosestFeatureCache<double> feature_cache;
    cdkit::SeparatingPlaneCache<double> plane_cache;
    int disagreements = 0;
    const T pose_a;
    T last_apart;                         // the last separated frame's pose of B ...
    V last_normal = V::Zero();            // ... its normal (A towards B) ...
    double last_distance = 0;             // ... and distance
    std::printf("%5s %8s %-12s %12s %12s %-6s %-6s %s\n", "frame", "x", "gjk", "distance", "features", "bool",
                "plane", "penetration [lower, depth] normal");
    for (int f = 0; f <= 40; ++f) {
        const double x = 1.6 - 0.05 * f;
        const T pose_b(Eigen::AngleAxisd(0.03 * f, V(0.3, 1.0, 0.2).normalized()).toRotationMatrix(), V(x, 0.1, 0.05));
        const cdkit::GjkResult<double> d = cdkit::gjk_distance(hull, pose_a, hull, pose_b, &gjk_cache);
        const cdkit::ClosestFeatureResult<double> c = cdkit::closest_features(hull, pose_a, hull, pose_b, &feature_cache);
        const cdkit::GjkResult<double> hit = cdkit::gjk_intersect(hull, pose_a, hull, pose_b);
        const cdkit::SeparatingPlaneResult<double> plane =
            cdkit::separating_plane_intersect(hull, pose_a, hull, pose_b, &plane_cache);
        if (d.status == cdkit::GjkStatus::separated) last_apart = pose_b, last_normal = d.normal, last_distance = d.distance;
        std::printf("%5d %8.3f %-12s %12.9f %12.9f %-6s %-6s", f, x, to_string(d.status), d.distance, c.distance,
                    hit.colliding ? "hit" : "apart", plane.colliding ? "hit" : "apart");
        // The methods agree: the same distance (to 1e-9 of the size) when apart, the same boolean otherwise.
        if (d.status == cdkit::GjkStatus::separated && std::abs(d.distance - c.distance) > 1e-9) ++disagreements;
        if (hit.colliding != d.colliding || plane.colliding != hit.colliding) ++disagreements;
        if (hit.colliding) {
            const cdkit::PenetrationResult<double> p = cdkit::penetration(hull, pose_a, hull, pose_b);
            std::printf(" %-12s [%.6f, %.6f] (%.3f %.3f %.3f)", to_string(p.status), p.depth_lower, p.depth, p.normal.x(),
                        p.normal.y(), p.normal.z());
            // Moving B by depth along the normal separates the pair (up to the tolerance): depth is an upper bound.
            const T moved(pose_b.R, V(pose_b.t + (p.depth + 1e-9) * p.normal));
            if (p.depth_lower > p.depth || cdkit::gjk_intersect(hull, pose_a, hull, moved).colliding) ++disagreements;
        }
        std::printf("\n");
    }

    // Touching: the last separated frame with B moved back along the normal by its distance. The answers are
    // within the touching tolerance (256ε·size): touching, or a gap or overlap of that order, never a false "apart"
    // by more than it.
    const T touch(last_apart.R, V(last_apart.t - last_distance * last_normal));
    const cdkit::GjkResult<double> dt = cdkit::gjk_distance(hull, pose_a, hull, touch);
    const cdkit::GjkResult<double> ht = cdkit::gjk_intersect(hull, pose_a, hull, touch);
    const cdkit::PenetrationResult<double> pt = cdkit::penetration(hull, pose_a, hull, touch);
    std::printf("moved into contact: distance query %s (%.3g), boolean %s, penetration %s (depth %.3g)\n",
                to_string(dt.status), dt.distance, to_string(ht.status), to_string(pt.status), pt.depth);
    if (!(dt.distance <= 1e-12) || !(pt.depth <= 1e-12)) ++disagreements;

    // A capsule (radius 0.1, half length 0.4, axis z) beside the hull: the distance is exact on the core segment.
    const cdkit::Capsule<double> capsule(0.1, 0.4);
    const T pose_c(Eigen::Matrix3d::Identity(), V(0.9, 0.0, 0.0));
    const cdkit::GjkResult<double> dc = cdkit::gjk_distance(hull, pose_a, capsule, pose_c);
    std::printf("capsule: %s, distance %.9f, closest points (%.4f %.4f %.4f) and (%.4f %.4f %.4f)\n", to_string(dc.status),
                dc.distance, dc.point_a.x(), dc.point_a.y(), dc.point_a.z(), dc.point_b.x(), dc.point_b.y(),
                dc.point_b.z());
    if (dc.status == cdkit::GjkStatus::separated && std::abs((dc.point_a - dc.point_b).norm() - dc.distance) > 1e-9)
        ++disagreements;

    std::printf("%d disagreements\n", disagreements);
    return disagreements == 0 ? 0 : 1;
} catch (const std::exception& e) {
    std::fprintf(stderr, "convex_pair: %s\n", e.what());
    return 1;
}
