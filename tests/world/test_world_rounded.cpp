// Rounded shapes in the World (Shape::rounded): contacts against closed forms (a rounded box on the ground, two
// rounded boxes edge to edge, a rounded box over a mesh floor, speculative contacts), against the same shape built
// round (a point rounded into a ball, a segment into a capsule), continuous collision of a rounded bullet, and bad
// input.
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <cdkit/world/world.hpp>

#include <cmath>
#include <random>

using namespace cdkit;

namespace {
using V = Vec3<double>;
using T = Transform<double>;

/// A square floor of two triangles at z = 0, 10 wide.
TriangleMesh<double> floor_mesh() {
    TriangleMesh<double> m;
    m.source = "<floor>";
    m.vertices = {V(-5, -5, 0), V(5, -5, 0), V(5, 5, 0), V(-5, 5, 0)};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

std::optional<WorldContact<double>> contact(const Shape<double>& a, const T& pa, const Shape<double>& b, const T& pb,
                                            double margin = 0) {
    ManifoldRequest r;
    r.margin = margin;
    return collide_shapes(ObjectId(0), a, pa, ObjectId(1), b, pb, static_cast<ManifoldCache<double>*>(nullptr), r);
}
}  // namespace

TEST_CASE("rounded box on the ground: depth, normal and four points in closed form", "[world][rounded]") {
    const Shape<double> ground = Shape<double>::box(V(5, 5, 1));  // top face at z = 0 when placed at z = -1
    const V h(0.4, 0.3, 0.2);
    const double r = 0.05;
    const Shape<double> rounded_box = Shape<double>::box(h).rounded(r);
    CHECK(rounded_box.rounding() == r);
    for (const double z : {0.2 + 0.05 - 0.01, 0.2 + 0.01, 0.2 - 0.03}) {  // core apart by 0.04, 0.01; core overlapping
        const auto c = contact(ground, T::translation(V(0, 0, -1)), rounded_box, T::translation(V(0.1, -0.2, z)));
        INFO("z = " << z);
        REQUIRE(c);
        CHECK(c->colliding);
        CHECK(c->depth == Approx(h.z() + r - z).margin(1e-12));
        CHECK(c->normal.isApprox(V(0, 0, 1), 1e-12));
        REQUIRE(c->point_count == 4);
        for (int i = 0; i < 4; ++i) {
            CHECK(c->points[i].depth == Approx(h.z() + r - z).margin(1e-12));
            CHECK(c->points[i].point_b.z() == Approx(z - h.z() - r).margin(1e-12));  // the rounded box's bottom
            CHECK(c->points[i].point_a.z() == Approx(0).margin(1e-12));              // the ground's top
        }
    }
    // Apart: nothing, or with a margin a speculative contact of distance gap − r.
    const T above = T::translation(V(0, 0, 0.2 + 0.05 + 0.02));
    CHECK_FALSE(contact(ground, T::translation(V(0, 0, -1)), rounded_box, above));
    const auto s = contact(ground, T::translation(V(0, 0, -1)), rounded_box, above, 0.03);
    REQUIRE(s);
    CHECK_FALSE(s->colliding);
    CHECK(s->distance == Approx(0.02).margin(1e-12));
    CHECK_FALSE(contact(ground, T::translation(V(0, 0, -1)), rounded_box, above, 0.015));
}

TEST_CASE("two rounded boxes: the roundings add up", "[world][rounded]") {
    // Unit cubes turned 45° about z, edge to edge along x: the cores' distance is gap; rounded by 0.1 and 0.2 they
    // overlap by 0.3 − gap.
    const T turn(Eigen::AngleAxisd(M_PI / 4, V::UnitZ()).toRotationMatrix(), V::Zero());
    const double half_diag = std::sqrt(2.0) * 0.5;
    const Shape<double> a = Shape<double>::box(V(0.5, 0.5, 0.5)).rounded(0.1);
    const Shape<double> b = Shape<double>::box(V(0.5, 0.5, 0.5)).rounded(0.15).rounded(0.05);  // roundings add up
    CHECK(b.rounding() == Approx(0.2));
    for (const double gap : {0.25, 0.1}) {
        const T pb(turn.R, V(2 * half_diag + gap, 0, 0));
        const auto c = contact(a, turn, b, pb);
        REQUIRE(c);
        CHECK(c->depth == Approx(0.3 - gap).margin(1e-9));
        CHECK(c->normal.isApprox(V(1, 0, 0), 1e-9));
    }
    // Cores overlapping by 0.05 along x: their overlap is a square prism whose diagonal along x is 0.05, pushed apart
    // most cheaply across a face, by 0.05/√2; the rounded shapes by that plus 0.3 (depths of Minkowski sums add).
    const auto deep = contact(a, turn, b, T(turn.R, V(2 * half_diag - 0.05, 0, 0)));
    REQUIRE(deep);
    CHECK(deep->depth == Approx(0.3 + 0.05 / std::sqrt(2.0)).margin(1e-9));
    CHECK(std::abs(deep->normal.x()) == Approx(1 / std::sqrt(2.0)).margin(1e-9));
    CHECK_FALSE(contact(a, turn, b, T(turn.R, V(2 * half_diag + 0.31, 0, 0))));
}

TEST_CASE("a point rounded into a ball and a segment into a capsule give the round shapes' contacts", "[world][rounded]") {
    std::mt19937_64 rng(8);
    std::normal_distribution<double> g;
    std::vector<V> cloud;
    for (int i = 0; i < 30; ++i) cloud.push_back(V(g(rng), g(rng), g(rng)) * 0.4);
    const Shape<double> others[] = {Shape<double>::box(V(0.5, 0.3, 0.4)), Shape<double>::convex_hull(cloud),
                                    Shape<double>::cylinder(0.3, 0.5), Shape<double>::mesh(test::uv_sphere(0.6, 12, 24))};
    const std::pair<Shape<double>, Shape<double>> same[] = {
        {Shape<double>::sphere(0).rounded(0.35), Shape<double>::sphere(0.35)},
        {Shape<double>::capsule(0, 0.4).rounded(0.2), Shape<double>::capsule(0.2, 0.4)},
        {Shape<double>::sphere(0.1).rounded(0.25), Shape<double>::sphere(0.35)},
    };
    int compared = 0, hits = 0;
    for (int i = 0; i < test::scaled(300, 60); ++i) {
        const T po(test::random_rotation(rng), V::Zero());
        const T ps(test::random_rotation(rng), V(g(rng), g(rng), g(rng)).normalized() * (0.5 + 0.6 * std::abs(g(rng))));
        for (const auto& o : others)
            for (const auto& [rounded, round] : same) {
                const auto x = contact(o, po, rounded, ps, 0.05), y = contact(o, po, round, ps, 0.05);
                REQUIRE(bool(x) == bool(y));
                ++compared;
                if (!x) continue;
                INFO("other " << to_string(o.kind()) << ", " << to_string(round.kind()));
                CHECK(x->colliding == y->colliding);
                hits += x->colliding;
                // Apart, the two are GJK distances of the same cores: equal. Overlapping cores go to EPA: the rounded
                // shape's on the core (a point or a segment: exact against polytopes) plus the radius, the round
                // shape's on the core with its margin, which stops within EPA's tolerance on the curved sum (a
                // sampled minimum over directions found the rounded answer the closer one in 5 of 6 such cases).
                CHECK(x->distance == Approx(y->distance).margin(1e-9));
                CHECK(x->depth == Approx(y->depth).margin(2e-3));
                if (x->colliding && x->depth > 1e-2) CHECK((x->normal - y->normal).norm() < 5e-2);
            }
    }
    CHECK(hits > compared / 10);
    CHECK(hits < compared * 9 / 10);
}

TEST_CASE("a rounded box over a mesh floor; speculative within the margin", "[world][rounded]") {
    const Shape<double> floor = Shape<double>::mesh(floor_mesh());
    const Shape<double> box = Shape<double>::box(V(0.3, 0.3, 0.1)).rounded(0.05);
    for (const double z : {0.14, 0.12, 0.08}) {  // core 0.04 and 0.02 above the floor, then through it
        World<double> w;
        (void)w.add(floor, T());
        (void)w.add(box, T::translation(V(0.5, 0.5, z)));
        const auto r = w.step();
        INFO("z = " << z);
        REQUIRE(r.contacts.size() == 1);
        const auto& c = r.contacts[0];
        CHECK(c.colliding);
        CHECK(c.method == PairMethod::convex_mesh);
        CHECK(c.depth == Approx(0.15 - z).margin(1e-9));
        CHECK(c.normal.isApprox(V(0, 0, 1), 1e-9));  // from the floor (a) to the box (b)
        CHECK(c.point_b.z() == Approx(z - 0.15).margin(1e-9));  // the rounded box's lowest point
    }
    World<double> w(WorldOptions{.contact_margin = 0.05});
    (void)w.add(floor, T());
    (void)w.add(box, T::translation(V(0.5, 0.5, 0.18)));  // rounded surface 0.03 above the floor
    const auto r = w.step();
    REQUIRE(r.contacts.size() == 1);
    CHECK_FALSE(r.contacts[0].colliding);
    CHECK(r.contacts[0].distance == Approx(0.03).margin(1e-9));
}

TEST_CASE("rounded curved cores tangent to a mesh floor give a contact of depth r", "[world][rounded]") {
    // The core's lowest point lies on the floor up to rounding: the core's mesh–convex boolean and its distance may
    // disagree here (two GJK tolerances), and either way the rounded shape overlaps the floor by r.
    const Shape<double> floor = Shape<double>::mesh(floor_mesh());
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g;
    std::vector<V> cloud;
    for (int i = 0; i < 30; ++i) cloud.push_back(V(g(rng), g(rng), g(rng)) * 0.3);
    const Shape<double> cores[] = {Shape<double>::cylinder(0.3, 0.2), Shape<double>::cone(0.3, 0.3),
                                   Shape<double>::ellipsoid(V(0.4, 0.2, 0.3)), Shape<double>::convex_hull(cloud)};
    const double r = 0.05;
    int checked = 0;
    for (int i = 0; i < test::scaled(200, 50); ++i)
        for (const auto& core : cores) {
            const Mat3<double> R = test::random_rotation(rng);
            const double lowest = core.visit_convex([&](const auto& c) {
                return (R * c.support(R.transpose() * V(0, 0, -1))).z();
            });
            const T pose(R, V(0.3 * g(rng), 0.3 * g(rng), -lowest));
            const auto c = contact(floor, T(), core.rounded(r), pose);
            INFO(to_string(core.kind()) << " pose " << i);
            REQUIRE(c);
            CHECK(c->colliding);
            CHECK(c->depth == Approx(r).margin(1e-6));
            CHECK(c->normal.isApprox(V(0, 0, 1), 1e-4));  // from the floor (a) to the shape (b)
            // The direction the distance-0 branch takes (boolean apart, distance 0: not met on these poses).
            core.visit_convex([&](const auto& cc) {
                const Index t = distance(floor.mesh_model(), T(), cc, pose).triangle;
                const V u = detail::core_to_triangle_direction(cc, pose, floor.mesh_model(), T(), t);
                INFO("direction " << u.transpose());
                CHECK(u.isApprox(V(0, 0, -1), 1e-4));
            });
            ++checked;
        }
    CHECK(checked == 4 * test::scaled(200, 50));
}

TEST_CASE("World CCD: a rounded bullet hits where the round one does", "[world][rounded][ccd]") {
    for (const bool mesh_wall : {false, true}) {
        double toi[2] = {0, 0};
        for (int k = 0; k < 2; ++k) {
            World<double> w;
            if (mesh_wall) (void)w.add(Shape<double>::mesh(floor_mesh()), T());
            else (void)w.add(Shape<double>::box(V(1, 1, 0.001)), T());
            const Shape<double> bullet = k == 0 ? Shape<double>::sphere(0).rounded(0.01) : Shape<double>::sphere(0.01);
            const auto id = w.add(bullet, T::translation(V(0.3, 0.2, 1)));
            w.set_ccd(id, true);
            REQUIRE(w.step().contacts.empty());
            w.set_pose(id, T::translation(V(0.3, 0.2, -1)));
            const auto r = w.step();
            REQUIRE(r.contacts.size() == 1);
            toi[k] = r.contacts[0].toi;
        }
        INFO((mesh_wall ? "mesh floor" : "thin box"));
        const double expected = (1 - 0.01 - (mesh_wall ? 0.0 : 0.001)) / 2;
        CHECK(toi[0] <= expected);
        CHECK(toi[0] >= expected - 1e-6);
        CHECK(toi[0] == Approx(toi[1]).margin(1e-6));
    }
}

TEST_CASE("rounded shapes: bad input is a clear error", "[world][rounded]") {
    const Shape<double> box = Shape<double>::box(V(1, 1, 1));
    CHECK_THROWS_AS(box.rounded(-0.1), Error);
    CHECK_THROWS_AS(box.rounded(std::nan("")), Error);
    CHECK_THROWS_AS(box.rounded(std::numeric_limits<double>::infinity()), Error);
    CHECK_THROWS_AS(Shape<double>::mesh(test::uv_sphere(0.5, 6, 12)).rounded(0.1), Error);
    CHECK_THROWS_AS(Shape<double>::compound({box}).rounded(0.1), Error);
    CHECK_NOTHROW(box.rounded(0));
    // The broad phase sees the rounded extent.
    const BroadBox<double> b = box.rounded(0.25).world_box(T());
    CHECK(b.hi.x() == Approx(1.25));
    CHECK(b.lo.z() == Approx(-1.25));
}
