// World: contacts against an all-pairs narrow phase for every broad phase, parallel == sequential, interest
// matrix filters, convex–mesh semantics, bad input, and the representation suggestion on generated meshes.
#include <catch2/catch.hpp>

#include "cdkit/io/load_mesh.hpp"
#include "cdkit/world/suggest_representation.hpp"
#include "cdkit/world/world.hpp"
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <thread>
#include <vector>

using namespace cdkit;
using T = Transform<double>;
using V = Vec3<double>;

namespace {

/// A closed, outward-oriented box mesh with half extents h.
TriangleMesh<double> box_mesh(const V& h) {
    TriangleMesh<double> m;
    m.source = "<box_mesh>";
    for (int i = 0; i < 8; ++i) m.vertices.push_back(V(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z()));
    const Index q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : q) {
        m.triangles.push_back({f[0], f[1], f[2]});
        m.triangles.push_back({f[0], f[2], f[3]});
    }
    return m;
}

/// A closed prism over a regular n-gon (convex, neither a box nor a ball).
TriangleMesh<double> prism_mesh(int n, double r, double h) {
    TriangleMesh<double> m;
    m.source = "<prism>";
    for (int i = 0; i < n; ++i) {
        const double a = 2 * 3.14159265358979323846 * i / n;
        m.vertices.push_back(V(r * std::cos(a), r * std::sin(a), -h));
        m.vertices.push_back(V(r * std::cos(a), r * std::sin(a), h));
    }
    const Index bottom = Index(m.vertices.size());
    m.vertices.push_back(V(0, 0, -h));
    m.vertices.push_back(V(0, 0, h));
    for (int i = 0; i < n; ++i) {
        const Index b0 = Index(2 * i), t0 = b0 + 1, b1 = Index(2 * ((i + 1) % n)), t1 = b1 + 1;
        m.triangles.push_back({b0, b1, t1});
        m.triangles.push_back({b0, t1, t0});
        m.triangles.push_back({bottom, b1, b0});
        m.triangles.push_back({Index(bottom + 1), t0, t1});
    }
    return m;
}

T random_pose(std::mt19937_64& rng, double world) {
    std::uniform_real_distribution<double> u(0, world);
    return T(test::random_rotation(rng), V(u(rng), u(rng), u(rng)));
}

/// A mixed scene: spheres, boxes, capsules, shared hulls, and a few meshes.
std::vector<Shape<double>> mixed_shapes(std::mt19937_64& rng, int n, bool with_meshes) {
    std::uniform_real_distribution<double> sz(0.2, 0.8);
    std::vector<V> cloud;
    std::normal_distribution<double> g;
    for (int i = 0; i < 30; ++i) cloud.push_back(V(g(rng), g(rng), g(rng)) * 0.4);
    const Shape<double> hull = Shape<double>::convex_hull(cloud);
    const Shape<double> ball_mesh = Shape<double>::mesh(test::uv_sphere(0.6, 8, 16));
    const Shape<double> soup = Shape<double>::mesh(test::random_soup(60, 0.3, 9));
    std::vector<Shape<double>> shapes;
    for (int i = 0; i < n; ++i) {
        switch (with_meshes ? i % 6 : i % 4) {
            case 0: shapes.push_back(Shape<double>::sphere(sz(rng))); break;
            case 1: shapes.push_back(Shape<double>::box(V(sz(rng), sz(rng), sz(rng)))); break;
            case 2: shapes.push_back(Shape<double>::capsule(sz(rng) / 2, sz(rng))); break;
            case 3: shapes.push_back(hull.with_offset(T::translation(V(0.1, 0, 0)))); break;
            case 4: shapes.push_back(ball_mesh); break;
            default: shapes.push_back(soup); break;
        }
    }
    return shapes;
}

struct Key {
    ObjectId a, b;
    friend bool operator==(const Key&, const Key&) = default;
};

/// The oracle: every live pair through collide_shapes, no broad phase, no cache, optional filter.
template <class Filter>
std::vector<WorldContact<double>> all_pairs(const World<double>& w, const std::vector<ObjectId>& ids, Filter&& keep) {
    std::vector<WorldContact<double>> out;
    for (std::size_t i = 0; i < ids.size(); ++i)
        for (std::size_t j = i + 1; j < ids.size(); ++j) {
            const ObjectId a = std::min(ids[i], ids[j]), b = std::max(ids[i], ids[j]);
            if (!keep(a, b)) continue;
            if (auto c = collide_shapes(a, w.shape(a), w.pose(a), b, w.shape(b), w.pose(b))) out.push_back(*c);
        }
    std::sort(out.begin(), out.end());
    return out;
}

void check_same(const std::vector<WorldContact<double>>& got, const std::vector<WorldContact<double>>& ref) {
    REQUIRE(got.size() == ref.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        REQUIRE(got[i].a == ref[i].a);
        REQUIRE(got[i].b == ref[i].b);
        CHECK(got[i].method == ref[i].method);
        CHECK(got[i].has_depth == ref[i].has_depth);
        CHECK(std::abs(got[i].depth - ref[i].depth) <= 1e-9 * (1 + ref[i].depth));
    }
}

}  // namespace

TEST_CASE("World contacts equal an all-pairs narrow phase for every broad phase", "[world]") {
    const BroadPhaseKind kinds[] = {BroadPhaseKind::dynamic_aabb_tree, BroadPhaseKind::sweep_and_prune,
                                    BroadPhaseKind::uniform_grid, BroadPhaseKind::brute_force,
                                    BroadPhaseKind::sorted_cell_grid};
    for (const BroadPhaseKind kind : kinds) {
        std::mt19937_64 rng(42);
        World<double> world(WorldOptions{kind});
        const int n = 120;
        const double extent = 7.0;
        std::vector<ObjectId> ids;
        for (auto& s : mixed_shapes(rng, n, true)) ids.push_back(world.add(s, random_pose(rng, extent)));
        std::size_t total = 0, mesh_contacts = 0, convex_contacts = 0, frames = 0;
        std::normal_distribution<double> step(0, 0.05);
        const int nframes = test::scaled(8, 3);
        for (int f = 0; f < nframes; ++f) {
            for (ObjectId id : ids) {
                T p = world.pose(id);
                p.t += V(step(rng), step(rng), step(rng));
                world.set_pose(id, p);
            }
            if (f == 1) {  // remove and re-add (id reuse) between frames
                world.remove(ids[5]);
                const ObjectId again = world.add(Shape<double>::sphere(0.5), random_pose(rng, extent));
                CHECK(again == ids[5]);
            }
            const auto r = world.step();
            const auto ref = all_pairs(world, ids, [](ObjectId, ObjectId) { return true; });
            check_same(r.contacts, ref);
            CHECK(r.stats.tested_pairs == r.stats.broad_pairs);
            CHECK(r.stats.broad_pairs >= r.contacts.size());
            total += ref.size();
            for (const auto& c : ref) (c.method == PairMethod::convex_convex ? convex_contacts : mesh_contacts) += 1;
            ++frames;
        }
        // Hit rate: both kinds of narrow phase produced contacts, far from all pairs.
        CHECK(convex_contacts > frames * 5);
        CHECK(mesh_contacts > frames * 2);
        CHECK(total < frames * std::size_t(n) * n / 8);
    }
}

TEST_CASE("World: the parallel narrow phase gives the sequential contacts", "[world]") {
    std::mt19937_64 rng(7);
    World<double> seq, par(WorldOptions{BroadPhaseKind::dynamic_aabb_tree, true, 1});
    const auto shapes = mixed_shapes(rng, 300, true);
    std::vector<ObjectId> ids;
    for (const auto& s : shapes) {
        const T pose = random_pose(rng, 9.0);
        ids.push_back(seq.add(s, pose));
        REQUIRE(par.add(s, pose) == ids.back());
    }
    std::normal_distribution<double> step(0, 0.05);
    std::size_t total = 0;
    for (int f = 0; f < test::scaled(5, 2); ++f) {
        for (ObjectId id : ids) {
            T p = seq.pose(id);
            p.t += V(step(rng), step(rng), step(rng));
            seq.set_pose(id, p);
            par.set_pose(id, p);
        }
        const auto a = seq.step(), b = par.step();
#if defined(CDKIT_HAS_TBB)
        CHECK(b.stats.ran_parallel);
#endif
        CHECK_FALSE(a.stats.ran_parallel);
        REQUIRE(a.contacts.size() == b.contacts.size());
        for (std::size_t i = 0; i < a.contacts.size(); ++i) {  // bit for bit
            CHECK(a.contacts[i].a == b.contacts[i].a);
            CHECK(a.contacts[i].b == b.contacts[i].b);
            CHECK(a.contacts[i].depth == b.contacts[i].depth);
            CHECK(a.contacts[i].normal == b.contacts[i].normal);
            CHECK(a.contacts[i].point_a == b.contacts[i].point_a);
            CHECK(a.contacts[i].gjk_iterations == b.contacts[i].gjk_iterations);
        }
        CHECK(a.stats.gjk_iterations == b.stats.gjk_iterations);
        total += a.contacts.size();
    }
    CHECK(total > 50);
}

TEST_CASE("World respects the interest matrix's groups and pair overrides", "[world]") {
    std::mt19937_64 rng(3);
    World<double> world;
    std::vector<ObjectId> ids;
    for (auto& s : mixed_shapes(rng, 150, false)) ids.push_back(world.add(s, random_pose(rng, 6.0)));
    for (ObjectId id : ids)
        if (id % 3 == 0) world.set_group(id, 1);
    world.set_groups_tested(1, 1, false);  // group 1 never against group 1
    // Re-enable one group-1 pair and disable one group-0 pair that do collide (found from the oracle).
    const auto unfiltered = all_pairs(world, ids, [](ObjectId, ObjectId) { return true; });
    ObjectPair on{}, off{};
    bool have_on = false, have_off = false;
    for (const auto& c : unfiltered) {
        if (!have_on && c.a % 3 == 0 && c.b % 3 == 0) on = {c.a, c.b}, have_on = true;
        if (!have_off && c.a % 3 != 0 && c.b % 3 != 0) off = {c.a, c.b}, have_off = true;
    }
    REQUIRE(have_on);
    REQUIRE(have_off);
    world.set_pair_tested(on.a, on.b, true);
    world.set_pair_tested(off.a, off.b, false);
    auto keep = [&](ObjectId a, ObjectId b) {
        if (ObjectPair{a, b} == on) return true;
        if (ObjectPair{a, b} == off) return false;
        return !(a % 3 == 0 && b % 3 == 0);
    };
    for (int f = 0; f < 2; ++f) {
        const auto r = world.step();
        const auto ref = all_pairs(world, ids, keep);
        check_same(r.contacts, ref);
        CHECK(r.stats.tested_pairs < r.stats.broad_pairs);  // the filter removed pairs before the narrow phase
        CHECK(std::find_if(r.contacts.begin(), r.contacts.end(), [&](const auto& c) {
                  return c.a == on.a && c.b == on.b;
              }) != r.contacts.end());
        CHECK(ref.size() < unfiltered.size());
    }
}

TEST_CASE("World: convex–convex contacts carry EPA depth; convex–mesh contacts the deepest facet's", "[world]") {
    World<double> world;
    const ObjectId a = world.add(Shape<double>::sphere(1.0), T{});
    const ObjectId b = world.add(Shape<double>::box(V(0.5, 0.5, 0.5)), T::translation(V(1.3, 0, 0)));
    auto r = world.step();
    REQUIRE(r.contacts.size() == 1);
    CHECK(r.contacts[0].has_depth);
    CHECK(r.contacts[0].depth == Approx(0.2).margin(1e-9));
    CHECK(r.contacts[0].normal.x() == Approx(1.0).margin(1e-9));  // from a (sphere) towards b (box)
    world.set_pose(b, T::translation(V(1.6, 0, 0)));
    CHECK(world.step().contacts.empty());
    world.remove(b);

    // A small ball against a unit-sphere mesh: contact only where it reaches the surface.
    const ObjectId m = world.add(Shape<double>::mesh(test::uv_sphere(1.0, 24, 48)), T::translation(V(10, 0, 0)));
    const ObjectId s = world.add(Shape<double>::sphere(0.2), T::translation(V(10, 0, 0)));
    world.remove(a);
    for (double d : {0.5, 0.9, 1.0, 1.1, 1.3}) {
        world.set_pose(s, T::translation(V(10, 0, d)));
        r = world.step();
        const bool expected = d > 0.75 && d < 1.25;
        INFO("distance " << d);
        CHECK((r.contacts.size() == 1) == expected);
        if (!r.contacts.empty()) {
            CHECK(r.contacts[0].method == PairMethod::convex_mesh);
            // The depth against the deepest touching facet: 0.2 − |d − 1| up to the facets' sag (1 − cos(π/24)).
            CHECK(r.contacts[0].has_depth);
            CHECK(std::abs(r.contacts[0].depth - (0.2 - std::abs(d - 1))) < 0.01);
            if (d != 1.0) CHECK(r.contacts[0].normal.z() * (d - 1) > 0);  // the ball leaves the facet on its own side
            CHECK((r.contacts[0].point_a - r.contacts[0].point_b - r.contacts[0].depth * r.contacts[0].normal).norm() < 1e-9);
            CHECK(std::abs(r.contacts[0].point_a.z() - 1.0) < 0.3);
            CHECK(r.contacts[0].a == std::min(m, s));
        }
    }
}

TEST_CASE("World: mesh–mesh contacts carry the depth of the volumes along the curve's normal", "[world]") {
    World<double> world;
    const ObjectId a = world.add(Shape<double>::mesh(test::grid_box<double>(V(0.5, 0.5, 0.5), 2)), T{});
    const ObjectId b = world.add(Shape<double>::mesh(test::grid_box<double>(V(0.4, 0.4, 0.4), 2)), T::translation(V(0.7, 0, 0)));
    auto r = world.step();
    REQUIRE(r.contacts.size() == 1);
    const auto& c = r.contacts[0];
    CHECK(c.method == PairMethod::mesh_mesh);
    CHECK(c.a == a);
    CHECK(c.b == b);
    CHECK(c.has_depth);
    CHECK(c.depth == Approx(0.2).margin(1e-9));
    CHECK(c.normal.isApprox(V(1, 0, 0), 1e-9));
    CHECK((c.point_a - c.point_b - c.depth * c.normal).norm() < 1e-9);
    // Nested without a crossing surface: no contact, as collide() says (docs/world.md).
    world.set_pose(b, T::translation(V(0.05, 0, 0)));
    CHECK(world.step().contacts.empty());
    // WorldOptions::mesh_depth off: the same pair, a witness point only.
    WorldOptions o;
    o.mesh_depth = false;
    World<double> plain(o);
    plain.add(Shape<double>::mesh(test::grid_box<double>(V(0.5, 0.5, 0.5), 2)), T{});
    plain.add(Shape<double>::mesh(test::grid_box<double>(V(0.4, 0.4, 0.4), 2)), T::translation(V(0.7, 0, 0)));
    plain.add(Shape<double>::sphere(0.2), T::translation(V(0.0, 0.0, 0.6)));
    r = plain.step();
    REQUIRE(r.contacts.size() == 2);
    for (const auto& k : r.contacts) {
        CHECK_FALSE(k.has_depth);
        CHECK(k.depth == 0);
        CHECK(k.point_a == k.point_b);
    }
}

TEST_CASE("World rejects bad poses, ids and shapes with cdkit::Error", "[world]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    World<double> world;
    const ObjectId a = world.add(Shape<double>::sphere(1), T{});
    T bad = T::translation(V(nan, 0, 0));
    T scaled(Mat3<double>::Identity() * 2.0, V::Zero());
    CHECK_THROWS_AS(world.add(Shape<double>::sphere(1), bad), cdkit::Error);
    CHECK_THROWS_AS(world.add(Shape<double>::sphere(1), scaled), cdkit::Error);
    CHECK_THROWS_AS(world.set_pose(a, bad), cdkit::Error);
    CHECK_THROWS_AS(world.set_pose(99, T{}), cdkit::Error);
    CHECK_THROWS_AS(world.set_group(a, 64), cdkit::Error);
    CHECK_THROWS_AS(Shape<double>::sphere(-1), cdkit::Error);
    CHECK_THROWS_AS(Shape<double>::sphere(nan), cdkit::Error);
    CHECK_THROWS_AS(Shape<double>::convex_hull(std::vector<V>{V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)}), cdkit::Error);
    CHECK_THROWS_AS(Shape<double>::convex_hull(Shape<double>::Hull{}), cdkit::Error);
    CHECK_THROWS_AS(Shape<double>::mesh(Shape<double>::Mesh{}), cdkit::Error);
    CHECK_THROWS_AS(Shape<double>::mesh(TriangleMesh<double>{}), cdkit::Error);
    CHECK_THROWS_AS(Shape<double>::sphere(1).with_offset(scaled), cdkit::Error);
    CHECK(world.pose(a).t == V::Zero());  // failed calls changed nothing
    world.remove(a);
    CHECK_THROWS_AS(world.remove(a), cdkit::Error);
    CHECK_THROWS_AS(world.pose(a), cdkit::Error);
    CHECK(world.size() == 0);
    CHECK(world.step().contacts.empty());
}

TEST_CASE("suggest_representation picks box, sphere, hull and mesh on generated meshes", "[world]") {
    std::mt19937_64 rng(5);
    {
        // A rotated, shifted box: found in its own frame.
        TriangleMesh<double> m = box_mesh(V(0.5, 1.0, 2.0));
        const T place(test::random_rotation(rng), V(3, -1, 2));
        for (auto& v : m.vertices) v = place * v;
        const auto s = suggest_representation(m);
        INFO(s.reason);
        CHECK(s.kind == ShapeKind::box);
        CHECK(s.closed);
        CHECK(s.convex);
        V h = s.half_extents;
        std::sort(h.data(), h.data() + 3);
        CHECK(h.isApprox(V(0.5, 1.0, 2.0), 1e-9));
        // The built shape covers the mesh: every vertex is inside its box (in the suggested frame).
        const Shape<double> shape = make_shape(m, s);
        CHECK(shape.kind() == ShapeKind::box);
        for (const auto& v : m.vertices) {
            const V q = shape.offset().inverse() * v;
            CHECK((q.cwiseAbs().array() <= s.half_extents.array() + 1e-9).all());
        }
    }
    {
        TriangleMesh<double> m = test::uv_sphere(0.7, 16, 32);
        for (auto& v : m.vertices) v += V(1, 2, 3);
        const auto s = suggest_representation(m);
        INFO(s.reason);
        CHECK(s.kind == ShapeKind::sphere);
        CHECK(s.radius == Approx(0.7).epsilon(1e-9));
        CHECK(s.offset.t.isApprox(V(1, 2, 3), 1e-9));
        CHECK(make_shape(m, s).kind() == ShapeKind::sphere);
    }
    {
        const auto s = suggest_representation(prism_mesh(6, 1.0, 0.3));
        INFO(s.reason);
        CHECK(s.kind == ShapeKind::convex_hull);
        CHECK(s.convex);
        CHECK(make_shape(prism_mesh(6, 1.0, 0.3), s).kind() == ShapeKind::convex_hull);
    }
    {
        const auto bunny = load_mesh(test::data_path("bunny.obj"));
        const auto s = suggest_representation(bunny);
        INFO(s.reason);
        CHECK(s.closed);
        CHECK_FALSE(s.convex);
        CHECK(s.kind == ShapeKind::mesh);
        CHECK(s.volume < s.hull_volume);
    }
    {
        const auto teapot = load_mesh(test::data_path("teapot.obj"));
        const auto s = suggest_representation(teapot);
        CHECK_FALSE(s.closed);
        CHECK(s.kind == ShapeKind::mesh);
        const auto soup = suggest_representation(test::random_soup(50, 0.2, 3));
        CHECK(soup.kind == ShapeKind::mesh);
    }
    CHECK_THROWS_AS(suggest_representation(TriangleMesh<double>{}), cdkit::Error);
}

TEST_CASE("collide_shapes is const and thread-safe", "[world]") {
    std::mt19937_64 rng(13);
    const auto shapes = mixed_shapes(rng, 60, true);
    std::vector<T> poses;
    for (std::size_t i = 0; i < shapes.size(); ++i) poses.push_back(random_pose(rng, 3.0));
    auto run = [&] {
        std::vector<int> hits;
        for (std::size_t i = 0; i < shapes.size(); ++i)
            for (std::size_t j = i + 1; j < shapes.size(); ++j)
                hits.push_back(collide_shapes(ObjectId(i), shapes[i], poses[i], ObjectId(j), shapes[j], poses[j]) ? 1 : 0);
        return hits;
    };
    const auto ref = run();
    std::vector<std::vector<int>> got(3);
    std::vector<std::thread> th;
    for (int t = 0; t < 3; ++t) th.emplace_back([&, t] { got[std::size_t(t)] = run(); });
    for (auto& x : th) x.join();
    for (const auto& g : got) CHECK(g == ref);
    CHECK(std::count(ref.begin(), ref.end(), 1) > 20);
}
