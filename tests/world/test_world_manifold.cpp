// The World's contacts with manifolds: four points for a box on the ground by default, one with manifolds off,
// speculative contacts within the contact margin, the convex kinds added with manifolds (cylinder, cone, ellipsoid,
// triangle), a negative margin rejected. (The manifold query itself: tests/manifold/.)
#include "cdkit/world/world.hpp"

#include <catch2/catch.hpp>

#include <map>
#include <set>

using namespace cdkit;

namespace {

using V = Vec3<double>;
using T = Transform<double>;

T rotated(double angle, const V& axis, const V& t) {
    return {Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(), t};
}

const T ground_pose = T::translation(V(0, 0, -0.5));  // a ground box's top face at z = 0

}  // namespace

TEST_CASE("World: manifolds by default, one point when off, speculative contacts within the margin", "[manifold][world]") {
    for (bool manifolds : {true, false}) {
        World<double> world(WorldOptions{.manifolds = manifolds});
        world.add(Shape<double>::box(V(5, 5, 0.5)), ground_pose);
        world.add(Shape<double>::box(V(0.5, 0.5, 0.5)), rotated(0.3, V::UnitZ(), V(0, 0, 0.49)));
        const WorldStepResult<double> r = world.step();
        REQUIRE(r.contacts.size() == 1);
        CHECK(r.contacts[0].point_count == (manifolds ? 4 : 1));
        CHECK(r.contacts[0].depth == Approx(0.01).margin(1e-9));
    }
    World<double> world(WorldOptions{.contact_margin = 0.05});
    world.add(Shape<double>::box(V(5, 5, 0.5)), ground_pose);
    const ObjectId b = world.add(Shape<double>::box(V(0.5, 0.5, 0.5)), T::translation(V(0, 0, 0.53)));
    const ObjectId s = world.add(Shape<double>::sphere(0.2), T::translation(V(3, 0, 0.3)));
    WorldStepResult<double> r = world.step();
    REQUIRE(r.contacts.size() == 1);  // the box 3 cm up; the sphere 10 cm up is beyond the margin
    CHECK_FALSE(r.contacts[0].colliding);
    CHECK(r.contacts[0].distance == Approx(0.03).margin(1e-9));
    CHECK(r.contacts[0].point_count == 4);
    world.set_pose(s, T::translation(V(3, 0, 0.22)));
    world.set_pose(b, T::translation(V(0, 0, 0.49)));
    r = world.step();
    REQUIRE(r.contacts.size() == 2);
    CHECK(r.contacts[0].colliding);
    CHECK_FALSE(r.contacts[1].colliding);
    CHECK(r.contacts[1].point_count == 1);
    CHECK(r.contacts[1].points[0].depth == Approx(-0.02).margin(1e-9));
}

TEST_CASE("World: cylinders, cones, ellipsoids and triangles resting on the ground, and against each other",
          "[manifold][world]") {
    World<double> world;
    world.add(Shape<double>::box(V(20, 20, 0.5)), ground_pose);
    const ObjectId cyl = world.add(Shape<double>::cylinder(0.4, 0.5), T::translation(V(0, 0, 0.49)));
    const ObjectId cone = world.add(Shape<double>::cone(0.4, 0.5), T::translation(V(3, 0, 0.49)));
    const ObjectId ell = world.add(Shape<double>::ellipsoid(V(0.3, 0.4, 0.5)), T::translation(V(6, 0, 0.49)));
    const ObjectId tri = world.add(Shape<double>::triangle(V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)), T::translation(V(9, 0, -0.01)));
    CHECK(world.shape(cyl).kind() == ShapeKind::cylinder);
    CHECK(std::string(to_string(world.shape(tri).kind())) == "triangle");
    WorldStepResult<double> r = world.step();
    REQUIRE(r.contacts.size() == 4);
    const std::map<ObjectId, int> expected_points{{cyl, 4}, {cone, 4}, {ell, 1}, {tri, 3}};
    for (const WorldContact<double>& c : r.contacts) {
        INFO("object " << c.b << " (" << to_string(world.shape(c.b).kind()) << ")");
        CHECK(c.a == 0);
        CHECK(c.point_count == expected_points.at(c.b));
        CHECK(c.depth == Approx(0.01).margin(1e-9));
        CHECK((c.normal - V::UnitZ()).norm() < 1e-6);
    }
    // A cone lying on a cylinder's side and an ellipsoid touching the cone: pairs among the new kinds.
    world.set_pose(cone, T::translation(V(0, 0, 1.49)));  // cone's base on the cylinder's top cap
    world.set_pose(ell, T::translation(V(0.69, 0, 0.6)));  // the ellipsoid (x radius 0.3) into the cylinder (r 0.4)
    r = world.step();
    std::set<std::pair<ObjectId, ObjectId>> pairs;
    for (const WorldContact<double>& c : r.contacts) pairs.insert({c.a, c.b});
    CHECK(pairs.count({cyl, cone}) == 1);
    CHECK(pairs.count({cyl, ell}) == 1);
    for (const WorldContact<double>& c : r.contacts)
        if (c.a == cyl && c.b == cone) CHECK(c.point_count == 4);  // disc on disc
}

TEST_CASE("World: a negative or NaN contact margin is rejected", "[manifold][world][robustness]") {
    CHECK_THROWS_AS(World<double>(WorldOptions{.contact_margin = -0.1}), Error);
    CHECK_THROWS_AS(World<double>(WorldOptions{.contact_margin = std::numeric_limits<double>::quiet_NaN()}), Error);
}
