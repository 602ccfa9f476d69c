// Issue 37, independent oracles: World::step() on scenes of polytopes (boxes and hulls) judged by the exact polytope
// referee (tests/oracles/exact_polytope.hpp, CGAL's exact quadratic program on exactly posed vertices) over every
// pair — not by collide_shapes, which test_world.cpp compares against. Every broad phase; objects jostled between
// frames and some pairs placed at gaps of 1e-9 … 1e-3 and overlaps of that size by GJK, so the boolean is decided
// near contact. Also the speculative margin: pairs within it come back with colliding false and their distance.
#include <catch2/catch.hpp>

#include "cdkit/narrowphase/gjk.hpp"
#include "cdkit/world/world.hpp"
#include "mesh_factory.hpp"
#include "oracles/exact_polytope.hpp"
#include "test_common.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace cdkit;
using cdkit::test::exact::exact_polytope_pair;

namespace {

using V = Vec3<double>;

std::vector<V> box_vertices(const V& h) {
    std::vector<V> c;
    for (int i = 0; i < 8; ++i) c.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
    return c;
}

}  // namespace

TEST_CASE("World contacts on boxes and hulls equal the exact referee over every pair", "[world][exact]") {
    const BroadPhaseKind kinds[] = {BroadPhaseKind::dynamic_aabb_tree, BroadPhaseKind::sweep_and_prune,
                                    BroadPhaseKind::uniform_grid, BroadPhaseKind::brute_force,
                                    BroadPhaseKind::sorted_cell_grid};
    int judged = 0, colliding = 0, wrong = 0, near_pairs = 0, margin_wrong = 0;
    for (const BroadPhaseKind kind : kinds) {
        std::mt19937_64 rng(91 + int(kind));
        const double margin = 1e-2;
        World<double> world(WorldOptions{.broad_phase = kind, .contact_margin = margin});
        const int n = test::scaled(40, 16);
        std::uniform_real_distribution<double> sz(0.2, 0.6), pos(0, 3.5);
        std::normal_distribution<double> g;
        std::vector<std::vector<V>> vertices;
        std::vector<Shape<double>> shapes;
        std::vector<ObjectId> ids;
        for (int i = 0; i < n; ++i) {
            if (i % 2 == 0) {
                vertices.push_back(box_vertices(V(sz(rng), sz(rng), sz(rng))));
                shapes.push_back(Shape<double>::box((vertices.back()[7])));
            } else {
                std::vector<V> cloud;
                for (int k = 0; k < 25; ++k) cloud.push_back(V(g(rng), 0.5 * g(rng), g(rng)) * 0.3);
                vertices.push_back(cloud);
                shapes.push_back(Shape<double>::convex_hull(cloud));
            }
            ids.push_back(world.add(shapes.back(), Transform<double>(test::random_rotation(rng), V(pos(rng), pos(rng), pos(rng)))));
        }
        for (int f = 0; f < test::scaled(4, 2); ++f) {
            for (ObjectId id : ids) {
                Transform<double> p = world.pose(id);
                p.t += 0.05 * V(g(rng), g(rng), g(rng));
                world.set_pose(id, p);
            }
            // Some pairs (0,1), (2,3), ... brought to a gap or an overlap of 10^-9 … 10^-3 along GJK's normal.
            for (int i = 0; i + 1 < n; i += 4) {
                const Transform<double> pa = world.pose(ids[i]);
                Transform<double> pb = world.pose(ids[i + 1]);
                const auto& sa = shapes[i];
                const auto& sb = shapes[i + 1];
                pb.t = pa.t + 1.5 * V(g(rng), g(rng), g(rng)).normalized();
                const auto d = sa.visit_convex([&](const auto& ca) {
                    return sb.visit_convex([&](const auto& cb) { return gjk_distance(ca, pa, cb, pb); });
                });
                if (d.status != GjkStatus::separated) continue;
                const double gap = (f + i) % 2 ? std::pow(10.0, -9 + int(rng() % 7)) : -std::pow(10.0, -9 + int(rng() % 7));
                pb.t += (gap - d.distance) * d.normal;
                world.set_pose(ids[i + 1], pb);
            }
            const auto r = world.step();
            std::vector<std::pair<ObjectId, ObjectId>> got_colliding, got_near;
            for (const auto& c : r.contacts) (c.colliding ? got_colliding : got_near).emplace_back(c.a, c.b);
            std::vector<std::pair<ObjectId, ObjectId>> ref_colliding;
            for (int i = 0; i < n; ++i)
                for (int j = i + 1; j < n; ++j) {
                    const auto e = exact_polytope_pair(vertices[i], world.pose(ids[i]), vertices[j], world.pose(ids[j]), false);
                    ++judged;
                    const ObjectId a = std::min(ids[i], ids[j]), b = std::max(ids[i], ids[j]);
                    if (e.intersect) ref_colliding.emplace_back(a, b);
                    // A pair within the margin but apart: reported, not colliding, with its distance.
                    if (!e.intersect && e.distance <= margin * (1 - 1e-9)) {
                        ++near_pairs;
                        const auto it = std::find_if(r.contacts.begin(), r.contacts.end(),
                                                     [&](const auto& c) { return c.a == a && c.b == b; });
                        margin_wrong += it == r.contacts.end() || it->colliding ||
                                        std::abs(it->distance - e.distance) > 1e-9 * (1 + e.distance);
                    }
                }
            std::sort(got_colliding.begin(), got_colliding.end());
            std::sort(ref_colliding.begin(), ref_colliding.end());
            colliding += int(ref_colliding.size());
            wrong += got_colliding != ref_colliding;
            CHECK(got_colliding == ref_colliding);
        }
    }
    INFO(judged << " pairs judged, " << colliding << " colliding, " << near_pairs << " within the margin");
    CHECK(wrong == 0);
    CHECK(margin_wrong == 0);
    CHECK(colliding > 20);
    CHECK(near_pairs > 10);
}
