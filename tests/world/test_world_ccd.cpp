// World::set_ccd: a fast object's motion between two steps is tested as a whole (convex pairs by conservative
// advancement, mesh pairs by mesh_ccd), including motions that turn, whose arcs leave the boxes of the end poses.

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
