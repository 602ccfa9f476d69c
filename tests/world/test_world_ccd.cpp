// World::set_ccd: a fast object's motion between two steps is tested as a whole (convex pairs and convex–mesh pairs by
// conservative advancement, meshes by mesh_ccd or, turning, mesh_toi), including arcs that leave the end poses' boxes.

#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <cdkit/world/world.hpp>

namespace {
using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;
}  // namespace

TEST_CASE("World CCD: a fast sphere does not pass through a thin box", "[world][ccd]") {
    for (bool ccd : {false, true}) {
        cdkit::World<double> w;
        (void)w.add(cdkit::Shape<double>::box(V(1, 1, 0.001)), T());
        const auto bullet = w.add(cdkit::Shape<double>::sphere(0.01), T::translation(V(0.3, 0.2, 1)));
        w.set_ccd(bullet, ccd);
        CHECK(w.ccd(bullet) == ccd);
        CHECK(w.step().contacts.empty());
        w.set_pose(bullet, T::translation(V(0.3, 0.2, -1)));
        const auto r = w.step();
        if (!ccd) {
            CHECK(r.contacts.empty());  // tunnels: clear of the box at both poses
            continue;
        }
        REQUIRE(r.contacts.size() == 1);
        // The sphere's bottom (z = 1 − 0.01) meets the top face (z = 0.001) after 0.989 of 2 units.
        CHECK(r.contacts[0].toi <= 0.989 / 2);
        CHECK(r.contacts[0].toi >= 0.989 / 2 - 1e-6);
        CHECK(std::abs(r.contacts[0].normal.z()) > 0.999);
        // The next step starts where this one ended: resting below the box, no contact.
        CHECK(w.step().contacts.empty());
    }
}

TEST_CASE("World CCD: a turning rod hits what neither end pose touches", "[world][ccd]") {
    cdkit::World<double> w;
    // A capsule of half length 1 (along its z axis) turns by 170° about x in one step; a small sphere at (0, 0.9, 0)
    // is clear of the rod at both ends (whose boxes reach y = ±0.22) and lies inside the tips' circle.
    const auto rod = w.add(cdkit::Shape<double>::capsule(0.05, 1.0), T());
    (void)w.add(cdkit::Shape<double>::sphere(0.05), T::translation(V(0, 0.9, 0)));
    w.set_ccd(rod, true);
    CHECK(w.step().contacts.empty());
    const double turn = 170 * M_PI / 180;
    w.set_pose(rod, T(Eigen::AngleAxisd(turn, V::UnitX()).toRotationMatrix(), V::Zero()));
    const auto r = w.step();
    REQUIRE(r.contacts.size() == 1);
    CHECK(r.contacts[0].toi > 0);
    CHECK(r.contacts[0].toi < 1);
    // The same turn without CCD sees nothing.
    cdkit::World<double> plain;
    const auto rod2 = plain.add(cdkit::Shape<double>::capsule(0.05, 1.0), T());
    (void)plain.add(cdkit::Shape<double>::sphere(0.05), T::translation(V(0, 0.9, 0)));
    (void)plain.step();
    plain.set_pose(rod2, T(Eigen::AngleAxisd(turn, V::UnitX()).toRotationMatrix(), V::Zero()));
    CHECK(plain.step().contacts.empty());
}

TEST_CASE("World CCD: meshes, discrete pairs untouched, bad ids", "[world][ccd]") {
    cdkit::World<double> w;
    const auto a = w.add(cdkit::Shape<double>::mesh(cdkit::test::uv_sphere<double>(0.1, 6, 8)), T::translation(V(-3, 0, 0)));
    (void)w.add(cdkit::Shape<double>::mesh(cdkit::test::grid_box<double>(V(0.5, 0.5, 0.002), 2)), T());
    const auto c = w.add(cdkit::Shape<double>::sphere(0.1), T::translation(V(5, 5, 5)));
    const auto d = w.add(cdkit::Shape<double>::sphere(0.1), T::translation(V(5.15, 5, 5)));  // overlaps c: discrete
    w.set_ccd(a, true);
    auto r = w.step();
    REQUIRE(r.contacts.size() == 1);
    CHECK(r.contacts[0].a == c);
    CHECK(r.contacts[0].b == d);
    CHECK(r.contacts[0].toi == 1);
    w.set_pose(a, T(Eigen::AngleAxisd(1.0, V::UnitY()).toRotationMatrix(), V(3, 0, 0)));  // through the thin plate
    r = w.step();
    REQUIRE(r.contacts.size() == 2);
    CHECK(r.contacts[0].toi < 1);
    CHECK(r.contacts[0].method == cdkit::PairMethod::mesh_mesh);
    CHECK_THROWS_AS(w.set_ccd(99, true), cdkit::Error);
}

TEST_CASE("World CCD: convex shapes against meshes, and turning meshes", "[world][ccd]") {
    for (bool ccd : {false, true}) {
        // A small fast box through a thin mesh plate: mesh_convex_toi catches it; without CCD it tunnels.
        cdkit::World<double> w;
        const auto plate = w.add(cdkit::Shape<double>::mesh(cdkit::test::grid_box<double>(V(1, 1, 0.001), 2)), T());
        const auto bullet = w.add(cdkit::Shape<double>::box(V(0.01, 0.01, 0.01)), T::translation(V(0.3, 0.2, 1)));
        w.set_ccd(bullet, ccd);
        CHECK(w.step().contacts.empty());
        w.set_pose(bullet, T::translation(V(0.3, 0.2, -1)));
        const auto r = w.step();
        if (!ccd) {
            CHECK(r.contacts.empty());
            continue;
        }
        REQUIRE(r.contacts.size() == 1);
        CHECK(r.contacts[0].a == plate);
        CHECK(r.contacts[0].method == cdkit::PairMethod::convex_mesh);
        // The box's bottom (z = 1 − 0.01) meets the plate's top (z = 0.001) after 0.989 of 2 units.
        CHECK(r.contacts[0].toi <= 0.989 / 2);
        CHECK(r.contacts[0].toi >= 0.989 / 2 - 1e-6);
    }
    // A mesh bar turning 170° past a sphere that neither end pose touches: the bar's broad box covers its arcs and
    // mesh_convex_toi follows them (the same for a mesh ball, where mesh_toi does).
    for (bool mesh_ball : {false, true}) {
        cdkit::World<double> w;
        const auto bar = w.add(cdkit::Shape<double>::mesh(cdkit::test::grid_box<double>(V(0.02, 0.02, 1.0), 2)), T());
        const auto ball = mesh_ball ? w.add(cdkit::Shape<double>::mesh(cdkit::test::uv_sphere<double>(0.05, 8, 12)),
                                            T::translation(V(0, 0.9, 0)))
                                    : w.add(cdkit::Shape<double>::sphere(0.05), T::translation(V(0, 0.9, 0)));
        w.set_ccd(bar, true);
        CHECK(w.step().contacts.empty());
        w.set_pose(bar, T(Eigen::AngleAxisd(170 * M_PI / 180, V::UnitX()).toRotationMatrix(), V::Zero()));
        const auto r = w.step();
        REQUIRE(r.contacts.size() == 1);
        CHECK(r.contacts[0].b == ball);
        CHECK(r.contacts[0].toi > 0.3);
        CHECK(r.contacts[0].toi < 0.6);
    }
}
