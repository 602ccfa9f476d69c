// Compound shapes in the World: convex children at fixed offsets in one rigid object, one contact per touching
// child pair. The reference is every child tested on its own (collide_shapes on the child with its offset), so the
// tree over the children is checked for what it must not miss; plus known contacts, errors and CCD.
#include "cdkit/world/world.hpp"

#include <catch2/catch.hpp>

#include <numbers>
#include <random>
#include <set>

using namespace cdkit;

namespace {

using V = Vec3<double>;
using T = Transform<double>;

/// An L of two boxes: a 2 x 0.5 x 0.5 bar along x and a 0.5 x 0.5 x 1.5 post 0.01 above its right end.
Shape<double> l_shape() {
    return Shape<double>::compound({Shape<double>::box(V(1, 0.25, 0.25)),
                                    Shape<double>::box(V(0.25, 0.25, 0.75)).with_offset(T::translation(V(0.75, 0, 1.01)))});
}

}  // namespace

TEST_CASE("compound: an L on the ground touches through both boxes, a ball through one", "[world][compound]") {
    World<double> world;
    world.add(Shape<double>::box(V(10, 10, 0.5)), T::translation(V(0, 0, -0.5)));
    // The L standing: only the bar touches the ground.
    const ObjectId l = world.add(l_shape(), T::translation(V(0, 0, 0.24)));
    CHECK(world.shape(l).kind() == ShapeKind::compound);
    WorldStepResult<double> r = world.step();
    REQUIRE(r.contacts.size() == 1);
    CHECK(r.contacts[0].child_a == WorldContact<double>::no_child);
    CHECK(r.contacts[0].child_b == 0);  // the bar
    CHECK(r.contacts[0].point_count == 4);
    CHECK(r.contacts[0].depth == Approx(0.01).margin(1e-9));
    // A ball against the post's side only.
    const ObjectId ball = world.add(Shape<double>::sphere(0.3), T::translation(V(0.75 + 0.25 + 0.29, 0, 1.2)));
    r = world.step();
    REQUIRE(r.contacts.size() == 2);
    const WorldContact<double>& c = r.contacts[1];
    CHECK(c.a == l);
    CHECK(c.b == ball);
    CHECK(c.child_a == 1);
    CHECK(c.child_b == WorldContact<double>::no_child);
    CHECK(c.depth == Approx(0.01).margin(1e-9));
    // Turned over onto its side, both the bar and the post lie on the ground: one contact each.
    world.set_pose(l, T(Eigen::AngleAxisd(std::numbers::pi / 2, V::UnitX()).toRotationMatrix(), V(0, 0, 0.24)));
    world.set_pose(ball, T::translation(V(5, 5, 5)));
    r = world.step();
    std::set<std::uint32_t> children;
    for (const WorldContact<double>& k : r.contacts) children.insert(k.child_b);
    CHECK(children == std::set<std::uint32_t>{0, 1});
}

TEST_CASE("compound: the tree over many children finds every child contact testing each child finds",
          "[world][compound]") {
    // A 6 x 6 x 3 lattice of small boxes and balls (108 children), against random spheres, boxes and another compound.
    std::vector<Shape<double>> kids;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            for (int k = 0; k < 3; ++k) {
                const T at = T::translation(V(0.5 * i, 0.5 * j, 0.5 * k));
                kids.push_back(((i + j + k) % 2 ? Shape<double>::box(V(0.2, 0.15, 0.2)) : Shape<double>::sphere(0.2)).with_offset(at));
            }
    const Shape<double> lattice = Shape<double>::compound(kids);
    const Shape<double> pair = l_shape();
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-0.5, 3);
    std::uniform_real_distribution<double> angle(-3, 3);
    int contacts = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const T pose_lattice(Eigen::AngleAxisd(0.3, V(1, 2, 3).normalized()).toRotationMatrix(), V(0.1, 0.2, 0.3));
        const T pose_other(Eigen::AngleAxisd(angle(rng), V(1, 1, 0).normalized()).toRotationMatrix(), V(u(rng), u(rng), u(rng)));
        const Shape<double> other = trial % 3 == 0 ? Shape<double>::sphere(0.4) : trial % 3 == 1 ? Shape<double>::box(V(0.5, 0.1, 0.3)) : pair;
        std::vector<WorldContact<double>> got;
        collide_shapes_all(ObjectId(0), lattice, pose_lattice, ObjectId(1), other, pose_other,
                           static_cast<PairCache<double>*>(nullptr), ManifoldRequest{}, got);
        // Reference: every child (and every child of the other compound) on its own.
        std::set<std::pair<std::uint32_t, std::uint32_t>> expected, found;
        for (std::uint32_t i = 0; i < kids.size(); ++i) {
            if (!other.is_compound()) {
                if (collide_shapes(ObjectId(0), kids[i], pose_lattice, ObjectId(1), other, pose_other))
                    expected.insert({i, WorldContact<double>::no_child});
                continue;
            }
            const auto& theirs = other.compound_shape().children();
            for (std::uint32_t j = 0; j < theirs.size(); ++j)
                if (collide_shapes(ObjectId(0), kids[i], pose_lattice, ObjectId(1), theirs[j], pose_other))
                    expected.insert({i, j});
        }
        for (const WorldContact<double>& c : got) found.insert({c.child_a, c.child_b});
        CHECK(found == expected);
        contacts += int(got.size());
    }
    CHECK(contacts > 100);
}

TEST_CASE("compound against a mesh and another compound, and collide_shapes' deepest child", "[world][compound]") {
    World<double> world;
    TriangleMesh<double> ground;
    ground.vertices = {V(-5, -5, 0), V(5, -5, 0), V(5, 5, 0), V(-5, 5, 0)};
    ground.triangles = {{0, 1, 2}, {0, 2, 3}};
    ground.source = "ground quad";
    world.add(Shape<double>::mesh(ground), T{});
    const ObjectId l = world.add(l_shape(), T::translation(V(0, 0, 0.24)));
    const ObjectId m = world.add(l_shape(), T::translation(V(0, 0.49, 0.24)));  // side by side, touching along y
    const WorldStepResult<double> r = world.step();
    int mesh_contacts = 0, compound_pairs = 0;
    for (const WorldContact<double>& c : r.contacts) {
        if (c.method == PairMethod::convex_mesh) ++mesh_contacts;
        if (c.a == l && c.b == m) {
            ++compound_pairs;
            CHECK(c.child_a == c.child_b);  // bar on bar, post on post
        }
    }
    CHECK(mesh_contacts == 2);
    CHECK(compound_pairs == 2);
    const auto deepest = collide_shapes(ObjectId(0), l_shape(), T::translation(V(0, 0, 0.24)), ObjectId(1),
                                        Shape<double>::sphere(0.5), T::translation(V(0.75, 0, 2.4)));
    REQUIRE(deepest);
    CHECK(deepest->child_a == 1);
    CHECK(deepest->depth == Approx(0.1).margin(1e-9));
}

TEST_CASE("compound: a fast one is caught by CCD, bad compounds are rejected", "[world][compound][robustness]") {
    World<double> world;
    world.add(Shape<double>::box(V(0.05, 5, 5)), T{});  // a thin wall at x = 0
    const ObjectId l = world.add(l_shape(), T::translation(V(-5, 0, 0)));
    world.set_ccd(l, true);
    (void)world.step();
    world.set_pose(l, T::translation(V(5, 0, 0)));  // through the wall in one step
    const WorldStepResult<double> r = world.step();
    REQUIRE(r.contacts.size() == 1);
    CHECK(r.contacts[0].toi < 1);
    CHECK(r.contacts[0].child_b != WorldContact<double>::no_child);
    CHECK_THROWS_AS(Shape<double>::compound({}), Error);
    TriangleMesh<double> tri;
    tri.vertices = {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)};
    tri.triangles = {{0, 1, 2}};
    CHECK_THROWS_AS(Shape<double>::compound({Shape<double>::mesh(tri)}), Error);
    CHECK_THROWS_AS(Shape<double>::compound({l_shape()}), Error);
    CHECK_THROWS_AS(Shape<double>::sphere(std::numeric_limits<double>::quiet_NaN()), Error);
}
