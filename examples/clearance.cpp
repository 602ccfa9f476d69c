// Clearance monitoring, as a motion planner or a safety layer does it: a moving part (an OBB tree, built for fast
// collide()) near a fixed environment (an RSS tree, built for fast distance()). The two trees mix: collide() and
// distance() take models of different bounding volumes. DistanceRequest::max_distance bounds the distance query to
// the safety zone: a part farther away costs a few node tests and answers +inf, a part inside the zone gets its
// exact distance and the closest points.
// Usage: clearance [mesh file]   (default: data/bunny.obj, used for both the part and the environment)
#include <cdkit/cdkit.hpp>

#include <cmath>
#include <cstdio>
#include <memory>

int main(int argc, char** argv) try {
    const char* path = argc > 1 ? argv[1] : CDKIT_DEFAULT_MESH;
    auto mesh = std::make_shared<const cdkit::TriangleMesh<double>>(cdkit::load_mesh(path));
    const cdkit::MeshModel<cdkit::Obb<double>> part(mesh);
    const cdkit::MeshModel<cdkit::Rss<double>> environment(mesh);

    // The zone of interest: 5 % of the mesh's size.
    cdkit::Vec3<double> lo = mesh->vertices.front(), hi = lo;
    for (const auto& v : mesh->vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double size = (hi - lo).maxCoeff();
    cdkit::DistanceRequest<double> zone;
    zone.max_distance = 0.05 * size;

    // The part slides past the environment along x, from far away through contact.
    const cdkit::Transform<double> at_origin;
    int far = 0, near = 0, touching = 0;
    for (int step = 0; step <= 10; ++step) {
        const double x = size * (1.5 - 0.1 * step);
        const cdkit::Transform<double> pose(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                                            Eigen::Vector3d(x, 0.0, 0.0));
        const auto hit = cdkit::collide(part, pose, environment, at_origin);
        const auto gap = cdkit::distance(part, pose, environment, at_origin, zone);
        if (hit.status != cdkit::QueryStatus::ok || gap.status != cdkit::QueryStatus::ok) return 1;
        if (hit.colliding) {
            ++touching;
            std::printf("x = %6.3f: colliding (triangles %u and %u)\n", x, hit.contacts[0].triangle_a,
                        hit.contacts[0].triangle_b);
        } else if (std::isinf(gap.distance)) {
            ++far;
            std::printf("x = %6.3f: clear, beyond the %.4f zone (%llu node tests)\n", x, zone.max_distance,
                        static_cast<unsigned long long>(gap.stats.bv_tests));
        } else {
            ++near;
            std::printf("x = %6.3f: inside the zone, %.5f apart (closest points on triangles %u and %u)\n", x,
                        gap.distance, gap.triangle_a, gap.triangle_b);
        }
        // The bounded query agrees with the unbounded one wherever it answers.
        const auto exact = cdkit::distance(part, pose, environment, at_origin);
        if (!std::isinf(gap.distance) && gap.distance != exact.distance) return 1;
        if (std::isinf(gap.distance) && !(exact.distance > zone.max_distance)) return 1;
    }
    std::printf("%d steps clear, %d inside the zone, %d colliding\n", far, near, touching);
    return far > 0 && touching > 0 ? 0 : 1;  // the sweep must pass from clear to colliding
} catch (const cdkit::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
}
