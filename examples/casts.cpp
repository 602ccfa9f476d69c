// Casts: what a motion planner or a character controller asks before it moves anything.
//  1. A shape cast: a capsule (a gripper finger) slid along +x at a box. Both only translate, so convex_toi runs a
//     GJK ray cast; the closed form says when the capsule's side meets the box's face.
//  2. The same slide while the finger turns a quarter turn: conservative advancement, never later than the slide.
//  3. A ray at the bunny through its tree (closest hit: triangle, distance, normal), then a 64 × 64 sensor sweep.
//  4. A ball dropped through the bunny's box: mesh_convex_toi, the time it first touches the surface.
// Usage: casts [MESH]   (exits non-zero when an answer disagrees with its check)
#include <cdkit/bv/obb.hpp>
#include <cdkit/ccd/convex_toi.hpp>
#include <cdkit/ccd/mesh_convex_toi.hpp>
#include <cdkit/ccd/ray_cast.hpp>
#include <cdkit/io/load_mesh.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

int main(int argc, char** argv) try {
    int failures = 0;
    auto check = [&](bool ok, const char* what) {
        if (!ok) {
            std::printf("  CHECK FAILED: %s\n", what);
            ++failures;
        }
    };

    // 1. Capsule of radius 0.1 (axis z, half length 0.3) from x = −3 to x = 3; unit box at the origin. The side
    //    touches the face x = −0.5 when the axis is at x = −0.6: t = 2.4 / 6 = 0.4.
    const cdkit::Capsule<double> finger(0.1, 0.3);
    const cdkit::Box<double> box(V(0.5, 0.5, 0.5));
    const T start = T::translation(V(-3, 0, 0)), end = T::translation(V(3, 0, 0)), still;
    const cdkit::ToiResult slide = cdkit::convex_toi(finger, start, end, box, still, still);
    std::printf("shape cast: contact %d at t = %.9f (closed form 0.4), %d iterations, normal (%.3f %.3f %.3f)\n",
                slide.colliding, slide.toi, slide.iterations, slide.normal.x(), slide.normal.y(), slide.normal.z());
    check(slide.colliding && slide.toi <= 0.4 && slide.toi >= 0.4 - 1e-6, "the cast's time is the closed form's");

    // 2. The finger also turns a quarter turn about y (its axis tips towards x): it reaches further, so sooner.
    const T turned(cdkit::Mat3<double>(Eigen::AngleAxisd(M_PI / 2, V::UnitY())), end.t);
    const cdkit::ToiResult turn = cdkit::convex_toi(finger, start, turned, box, still, still);
    const cdkit::detail::PoseMotion motion(start, turned);
    const auto at_contact = cdkit::gjk_distance(finger, motion.at(turn.toi), box, still);
    std::printf("turning cast: contact %d at t = %.9f, %d iterations, distance there %.2g\n", turn.colliding, turn.toi,
                turn.iterations, at_contact.distance);
    check(turn.colliding && turn.toi < slide.toi && at_contact.distance <= 1e-6, "the turning finger touches sooner");

    // 3. Rays at the bunny (scaled as it comes), its tree built once.
    const cdkit::TriangleMesh<double> mesh = cdkit::load_mesh(argc > 1 ? argv[1] : CDKIT_DEFAULT_MESH);
    const cdkit::MeshModel<cdkit::Obb<double>> bunny(mesh);
    V lo = mesh.vertices[0], hi = lo;
    for (const V& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const V centre = 0.5 * (lo + hi), size = hi - lo;
    cdkit::Ray down;
    down.origin = V(centre.x(), hi.y() + size.y(), centre.z());
    down.direction = V(0, -1, 0);
    const cdkit::RayCastResult hit = cdkit::ray_cast(bunny, still, down);
    if (hit.hit) {
        const cdkit::RayHit& h = hit.hits[0];
        std::printf("ray: hits triangle %u at distance %.4f, normal (%.3f %.3f %.3f), %llu box tests\n",
                    unsigned(h.triangle), h.t, h.normal.x(), h.normal.y(), h.normal.z(),
                    static_cast<unsigned long long>(hit.bv_tests));
    }
    check(hit.hit && hit.hits[0].point.y() <= hi.y() + 1e-9 && hit.hits[0].point.y() >= lo.y() - 1e-9,
          "a ray down through the box's centre meets the bunny inside its box");
    std::vector<cdkit::Ray> sweep;
    for (int i = 0; i < 64; ++i)
        for (int j = 0; j < 64; ++j) {
            cdkit::Ray r;
            r.origin = V(lo.x() + size.x() * (i + 0.5) / 64, lo.y() + size.y() * (j + 0.5) / 64, hi.z() + size.z());
            r.direction = V(0, 0, -1);
            sweep.push_back(r);
        }
    const std::vector<cdkit::RayCastResult> image = cdkit::ray_cast_many(bunny, still, sweep);
    int hits = 0;
    for (const auto& r : image) hits += r.hit;
    std::printf("sensor sweep: %d of %zu rays hit\n", hits, image.size());
    check(hits > 0 && hits < int(image.size()), "the sweep sees the bunny's silhouette, not all or nothing");

    // 4. A ball of a tenth of the bunny's height dropped from above its box to below it, through the centre.
    const double radius = 0.1 * size.y();
    const cdkit::Sphere<double> ball(radius);
    const T above = T::translation(V(centre.x(), hi.y() + 2 * radius, centre.z()));
    const T below = T::translation(V(centre.x(), lo.y() - 2 * radius, centre.z()));
    const cdkit::ToiResult drop = cdkit::mesh_convex_toi(bunny, still, still, ball, above, below);
    std::printf("ball drop: touches at t = %.6f (%d iterations)\n", drop.toi, drop.iterations);
    check(drop.colliding && drop.toi > 0 && drop.toi < 1, "the ball lands on the bunny during the drop");
    // It lands no lower than the ray through its centre first meets the surface, less the ball's radius.
    const double centre_y = above.t.y() + drop.toi * (below.t.y() - above.t.y());
    check(centre_y >= hit.hits[0].point.y() - 1e-9, "the ball touches before its centre reaches the ray's hit");

    std::printf(failures ? "%d check(s) failed\n" : "all checks passed\n", failures);
    return failures ? 1 : 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "casts: %s\n", e.what());
    return 2;
}
