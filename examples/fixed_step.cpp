// The fixed-time-step loop of a simulation (the lecture's accumulator): frames take whatever time they
// take to render; physics advances in steps of exactly dt, collide then integrate, as many steps as the
// elapsed time allows. Boxes and balls fall onto a ground box; a bunny mesh (representation suggested by
// suggest_representation) sits on the ground as a sensor that reports what touches it.
// Usage: fixed_step   (no arguments; prints contact counts, exits 0 when every body came to rest on the ground)
#include <cdkit/io/load_mesh.hpp>
#include <cdkit/world/suggest_representation.hpp>
#include <cdkit/world/world.hpp>

#include <cstdio>
#include <random>
#include <vector>

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

int main() try {
    cdkit::World<double> world(cdkit::WorldOptions{cdkit::BroadPhaseKind::dynamic_aabb_tree, true});
    const double ground_top = 0.0;
    const cdkit::ObjectId ground = world.add(cdkit::Shape<double>::box(V(60, 60, 0.5)), T::translation(V(0, 0, ground_top - 0.5)));
    world.set_group(ground, 1);

    // The bunny: a closed, non-convex mesh, so the helper keeps its BVH. It only senses (group 2).
    cdkit::TriangleMesh<double> bunny = cdkit::load_mesh(CDKIT_DATA_DIR "/bunny.obj");
    V lo = bunny.vertices[0], hi = lo;
    for (const auto& v : bunny.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    for (auto& v : bunny.vertices) v = (v - V((lo.x() + hi.x()) / 2, (lo.y() + hi.y()) / 2, lo.z())) * (3.0 / (hi - lo).maxCoeff());
    const auto advice = cdkit::suggest_representation(bunny);
    std::printf("bunny: %zu triangles, %s, %s -> %s (%s)\n", advice.triangles, advice.closed ? "closed" : "open",
                advice.convex ? "convex" : "not convex", cdkit::to_string(advice.kind), advice.reason.c_str());
    const cdkit::ObjectId sensor = world.add(cdkit::make_shape(bunny, advice), T::translation(V(8, 8, ground_top)));
    world.set_group(sensor, 2);
    world.set_groups_tested(1, 2, false);  // the bunny stands on the ground: not a contact we need

    // Falling bodies: translation only (no rotation), velocity v.
    struct Body { cdkit::ObjectId id; V v; };
    std::vector<Body> bodies;
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2), size(0.3, 0.6);
    for (int i = 0; i < 120; ++i) {  // a 5 x 6 x 4 lattice, spaced so that nothing starts overlapping
        const V p(1.6 * (i % 5) - 3.2 + jitter(rng), 1.6 * (i / 5 % 6) - 4 + jitter(rng), 2 + 1.6 * (i / 30) + jitter(rng));
        auto shape = i % 2 ? cdkit::Shape<double>::sphere(size(rng)) : cdkit::Shape<double>::box(V(size(rng), size(rng), size(rng)));
        bodies.push_back({world.add(shape, T::translation(p)), V::Zero()});
    }
    // A few balls dropped onto the bunny's back, for the sensor.
    for (int i = 0; i < 4; ++i) bodies.push_back({world.add(cdkit::Shape<double>::sphere(0.3), T::translation(V(8 + 0.2 * i, 8, 6 + i))), V::Zero()});
    std::vector<int> index_of(world.size() + 8, -1);
    for (std::size_t i = 0; i < bodies.size(); ++i) index_of[bodies[i].id] = int(i);

    const double dt = 1.0 / 120.0, g = 9.81;
    double accumulator = 0, t = 0;
    std::size_t steps = 0, contacts_total = 0, sensor_hits = 0, last_contacts = 0;
    for (int frame = 0; frame < 240; ++frame) {
        const double frame_time = frame % 3 == 0 ? 1.0 / 40 : 1.0 / 75;  // an uneven renderer
        accumulator += frame_time;
        while (accumulator >= dt) {
            // collide
            const auto result = world.step();
            contacts_total += result.contacts.size();
            last_contacts = result.contacts.size();
            // respond: push bodies apart along the EPA normal, remove the approaching velocity
            for (const auto& c : result.contacts) {
                if (c.a == sensor || c.b == sensor) { ++sensor_hits; continue; }
                if (!c.has_depth) continue;
                const int ia = index_of[c.a], ib = index_of[c.b];
                const double share = (ia >= 0 && ib >= 0) ? 0.5 : 1.0;
                for (const auto& [i, sign] : {std::pair{ia, -1.0}, std::pair{ib, 1.0}}) {
                    if (i < 0) continue;
                    Body& body = bodies[std::size_t(i)];
                    T pose = world.pose(body.id);
                    pose.t += sign * share * c.depth * c.normal;
                    world.set_pose(body.id, pose);
                    const double vn = body.v.dot(sign * c.normal);
                    if (vn < 0) body.v -= vn * sign * c.normal;
                }
            }
            // integrate (semi-implicit Euler)
            for (auto& body : bodies) {
                body.v.z() -= g * dt;
                T pose = world.pose(body.id);
                pose.t += body.v * dt;
                world.set_pose(body.id, pose);
            }
            accumulator -= dt;
            t += dt;
            ++steps;
        }
        // render: here, a line of text now and then (a renderer would interpolate with accumulator / dt)
        if (frame % 40 == 0)
            std::printf("frame %3d  t = %.2f s  steps %4zu  contacts last step %zu\n", frame, t, steps, last_contacts);
    }
    // Every body must rest on the ground (not sunk through it) and have come (nearly) to rest.
    std::size_t resting = 0, sunk = 0;
    for (const auto& body : bodies) {
        const auto box = world.shape(body.id).world_box(world.pose(body.id));
        if (box.lo.z() < ground_top - 0.1) ++sunk;
        if (std::abs(body.v.z()) < 0.5) ++resting;
    }
    std::printf("%zu steps of %.4f s, %zu contacts in all, %zu sensor contacts with the bunny, %zu/%zu bodies at rest, %zu sunk\n",
                steps, dt, contacts_total, sensor_hits, resting, bodies.size(), sunk);
    return sunk == 0 && sensor_hits > 0 && contacts_total > 0 ? 0 : 1;
} catch (const cdkit::Error& e) {
    std::fprintf(stderr, "fixed_step: %s\n", e.what());
    return 1;
}
