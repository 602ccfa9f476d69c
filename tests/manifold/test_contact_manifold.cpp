// Contact manifolds of convex pairs: the points a resting pair needs (four corners of a box on a box, two ends of an
// edge, the rim of a cylinder's base), each on both surfaces with its own depth, ids that persist, speculative points
// within a margin, bad input, threads. Surfaces are checked by each shape's own geometry (plane distances, radii),
// not by the GJK that produced the normal. The face-on-face points against the exact intersection polygon: in
// test_manifold_faces_cgal.cpp; the World's use of manifolds: tests/world/test_world_manifold.cpp.
#include "cdkit/manifold/contact_manifold.hpp"
#include "cdkit/narrowphase/convex_polyhedron.hpp"
#include "cdkit/narrowphase/convex_shapes.hpp"

#include <catch2/catch.hpp>

#include <map>
#include <numbers>
#include <random>
#include <set>
#include <thread>

using namespace cdkit;
using V = Vec3<double>;
using T = Transform<double>;

namespace {

T rot(double angle, const V& axis, const V& t) { return {Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(), t}; }

/// Distance of world point p to the surface of a box at pose (negative inside): the largest face-plane distance.
double box_surface_distance(const Box<double>& b, const T& pose, const V& p) {
    const V l = pose.R.transpose() * (p - pose.t);
    return (l.cwiseAbs() - b.half).maxCoeff();
}

const Box<double> ground(V(10, 10, 0.5));
const T ground_pose = T::translation(V(0, 0, -0.5));  // top face: z = 0

}  // namespace

TEST_CASE("a box flat on the ground touches at its four corners, each at its depth", "[manifold]") {
    const Box<double> box(V(0.5, 0.3, 0.2));
    for (double yaw : {0.0, 0.4, 1.2, 2.9}) {
        const T pose = rot(yaw, V::UnitZ(), V(0.3, -0.2, 0.2 - 0.01));
        const ContactManifold<double> m = contact_manifold(ground, ground_pose, box, pose);
        REQUIRE(m.status == QueryStatus::ok);
        REQUIRE(m.colliding);
        REQUIRE(m.count == 4);
        CHECK((m.normal - V::UnitZ()).norm() < 1e-12);
        std::vector<std::uint64_t> ids;
        for (int i = 0; i < 4; ++i) {
            const ManifoldPoint<double>& p = m.points[i];
            CHECK(p.depth == Approx(0.01).margin(1e-12));
            CHECK(std::abs(box_surface_distance(box, pose, p.point_b)) < 1e-12);  // a corner of the box
            const V l = pose.R.transpose() * (p.point_b - pose.t);
            CHECK(std::abs(std::abs(l.x()) - 0.5) < 1e-12);
            CHECK(std::abs(std::abs(l.y()) - 0.3) < 1e-12);
            CHECK(std::abs(p.point_a.z()) < 1e-12);  // on the ground's top face
            CHECK(((p.point_a - p.point_b).dot(m.normal) - p.depth) == Approx(0).margin(1e-12));
            ids.push_back(p.id);
        }
        std::sort(ids.begin(), ids.end());
        CHECK(std::adjacent_find(ids.begin(), ids.end()) == ids.end());
    }
}

TEST_CASE("a tilted box touches along its lowest edge, a box on a corner at one point", "[manifold]") {
    const Box<double> box(V(0.5, 0.5, 0.5));
    // Tilted about x by 0.03 rad (below the feature angle): the face is the feature, two of its corners dip in.
    const double tilt = 0.03;
    T pose = rot(tilt, V::UnitX(), V::Zero());
    const double lowest = -(pose.R * V(0.5, 0.5, -0.5)).z();  // the lowest corner's depth below the centre
    pose.t = V(0, 0, std::max(lowest, -(pose.R * V(0.5, -0.5, -0.5)).z()) - 0.004);
    ContactManifold<double> m = contact_manifold(ground, ground_pose, box, pose);
    REQUIRE(m.count == 2);
    for (int i = 0; i < 2; ++i) {
        CHECK(std::abs(box_surface_distance(box, pose, m.points[i].point_b)) < 1e-12);
        CHECK(m.points[i].depth == Approx(-m.points[i].point_b.z()).margin(1e-12));
        CHECK(m.points[i].depth == Approx(0.004).margin(1e-9));
    }
    // The same tilt with a margin: the lifted corners come back as speculative points (negative depth).
    ManifoldRequest speculative;
    speculative.margin = 0.05;
    m = contact_manifold(ground, ground_pose, box, pose, speculative);
    REQUIRE(m.count == 4);
    int lifted = 0;
    for (int i = 0; i < 4; ++i) {
        CHECK(m.points[i].depth == Approx(-m.points[i].point_b.z()).margin(1e-12));
        lifted += m.points[i].depth < 0;
    }
    CHECK(lifted == 2);
    // On a corner (turned about two axes by more than the feature angle): one point, the corner.
    pose = rot(0.6, V(1, 1, 0), V::Zero());
    V low = V::Zero();
    for (double x : {-0.5, 0.5})
        for (double y : {-0.5, 0.5})
            for (double z : {-0.5, 0.5}) {
                const V c = pose.R * V(x, y, z);
                if (c.z() < low.z()) low = c;
            }
    pose.t = V(0, 0, -low.z() - 0.002);
    m = contact_manifold(ground, ground_pose, box, pose);
    REQUIRE(m.count == 1);
    CHECK((m.points[0].point_b - (pose.R * (pose.R.transpose() * low) + pose.t)).norm() < 1e-6);
    CHECK(m.points[0].depth == Approx(0.002).margin(1e-9));
}

TEST_CASE("curved shapes: a sphere at one point, a lying capsule at its ends, a cylinder on its base at its rim",
          "[manifold]") {
    const ContactManifold<double> s = contact_manifold(ground, ground_pose, Sphere<double>(0.3), T::translation(V(1, 2, 0.29)));
    REQUIRE(s.count == 1);
    CHECK(s.points[0].depth == Approx(0.01).margin(1e-9));
    CHECK((s.points[0].point_b - V(1, 2, -0.01)).norm() < 1e-9);

    const Capsule<double> cap(0.2, 0.6);
    const T lying = rot(std::numbers::pi / 2, V::UnitY(), V(0, 0, 0.19));
    const ContactManifold<double> c = contact_manifold(ground, ground_pose, cap, lying);
    REQUIRE(c.count == 2);
    for (int i = 0; i < 2; ++i) {
        CHECK(std::abs(std::abs(c.points[i].point_b.x()) - 0.6) < 1e-9);  // the segment's ends, on the surface
        CHECK(c.points[i].depth == Approx(0.01).margin(1e-9));
    }

    const Cylinder<double> cyl(0.4, 0.5);
    const T standing = rot(0.3, V::UnitZ(), V(0.5, 0, 0.49));
    const ContactManifold<double> y = contact_manifold(ground, ground_pose, cyl, standing);
    REQUIRE(y.count == 4);
    for (int i = 0; i < 4; ++i) {
        const V l = standing.R.transpose() * (y.points[i].point_b - standing.t);
        CHECK(l.head<2>().norm() == Approx(0.4).margin(1e-12));  // on the rim
        CHECK(y.points[i].depth == Approx(0.01).margin(1e-12));
    }
}

namespace {

/// Hexagonal prism, axis z, circumradius r, half height h, first corner at angle `phase`.
std::vector<V> hexagonal_prism(double r, double h, double phase) {
    std::vector<V> prism;
    for (int k = 0; k < 6; ++k) {
        const double a = phase + k * std::numbers::pi / 3;
        prism.emplace_back(r * std::cos(a), r * std::sin(a), -h);
        prism.emplace_back(r * std::cos(a), r * std::sin(a), h);
    }
    return prism;
}

/// Area of the convex polygon through the points (any order), in the plane z = const.
double convex_area_xy(std::vector<V> p) {
    V c = V::Zero();
    for (const V& q : p) c += q / double(p.size());
    std::sort(p.begin(), p.end(), [&](const V& a, const V& b) {
        return std::atan2(a.y() - c.y(), a.x() - c.x()) < std::atan2(b.y() - c.y(), b.x() - c.x());
    });
    double area = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const V& a = p[i];
        const V& b = p[(i + 1) % p.size()];
        area += a.x() * b.y() - a.y() * b.x();
    }
    return std::abs(area) / 2;
}

}  // namespace

TEST_CASE("a hull's face on a box, and a hull's edge lying on a box's face", "[manifold]") {
    const ConvexPolyhedron<double> hull(hexagonal_prism(0.5, 0.25, 0));
    const T pose = rot(0.2, V::UnitZ(), V(0, 0, 0.24));
    const ContactManifold<double> m = contact_manifold(ground, ground_pose, hull, pose);
    REQUIRE(m.count == 4);  // six corners reduced to four
    std::vector<V> points;
    for (int i = 0; i < 4; ++i) {
        CHECK(m.points[i].depth == Approx(0.01).margin(1e-12));
        points.push_back(m.points[i].point_b);
    }
    // The four span at least half the hexagon (area 3√3/2 r² = 0.6495 for r = 0.5); the best four corners span 2/3.
    CHECK(convex_area_xy(points) > 0.5 * 0.6495);
    // A prism on its side, a long edge on top (z = 0.5, along y), under a thin box: two points, the edge's ends.
    const ConvexPolyhedron<double> side_hull(hexagonal_prism(0.5, 0.25, std::numbers::pi / 2));
    const T side = rot(std::numbers::pi / 2, V::UnitX(), V::Zero());
    const ContactManifold<double> e =
        contact_manifold(side_hull, side, Box<double>(V(0.1, 1, 0.1)), T::translation(V(0, 0, 0.5 + 0.1 - 0.005)));
    REQUIRE(e.count == 2);
    for (int i = 0; i < 2; ++i) {
        CHECK(e.points[i].depth == Approx(0.005).margin(1e-9));
        CHECK(std::abs(e.points[i].point_a.y()) == Approx(0.25).margin(1e-9));
    }
}

TEST_CASE("manifold ids persist through a cache while the points move a little", "[manifold]") {
    const Box<double> box(V(0.5, 0.5, 0.5));
    ManifoldCache<double> cache;
    T pose = rot(0.01, V::UnitZ(), V(0, 0, 0.49));
    const ContactManifold<double> first = contact_manifold(ground, ground_pose, box, pose, {}, &cache);
    REQUIRE(first.count == 4);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> small(-1e-3, 1e-3);
    for (int step = 0; step < 50; ++step) {
        pose = rot(0.01 + small(rng), V(small(rng), small(rng), 1), V(small(rng), small(rng), 0.49 + small(rng)));
        const ContactManifold<double> m = contact_manifold(ground, ground_pose, box, pose, {}, &cache);
        REQUIRE(m.count >= 2);
        for (int i = 0; i < m.count; ++i) {
            // The point that lies where first's point j lay has first's id.
            int nearest = 0;
            for (int j = 1; j < first.count; ++j)
                if ((first.points[j].point_b - m.points[i].point_b).norm() <
                    (first.points[nearest].point_b - m.points[i].point_b).norm())
                    nearest = j;
            CHECK(m.points[i].id == first.points[nearest].id);
        }
    }
}

TEST_CASE("speculative contacts within the margin, nothing beyond it", "[manifold]") {
    const Box<double> box(V(0.5, 0.5, 0.5));
    const T apart = T::translation(V(0, 0, 0.5 + 0.01));
    CHECK(contact_manifold(ground, ground_pose, box, apart).count == 0);
    ManifoldRequest r;
    r.margin = 0.005;
    CHECK(contact_manifold(ground, ground_pose, box, apart, r).count == 0);
    r.margin = 0.02;
    const ContactManifold<double> m = contact_manifold(ground, ground_pose, box, apart, r);
    CHECK_FALSE(m.colliding);
    CHECK(m.distance == Approx(0.01).margin(1e-9));
    REQUIRE(m.count == 4);
    for (int i = 0; i < 4; ++i) CHECK(m.points[i].depth == Approx(-0.01).margin(1e-9));
}

TEST_CASE("manifold bad input: a negative or NaN margin, a wide feature angle, a non-rigid pose", "[manifold][robustness]") {
    const Box<double> box(V(0.5, 0.5, 0.5));
    const T pose = T::translation(V(0, 0, 0.49));
    ManifoldRequest r;
    r.margin = -1;
    CHECK(contact_manifold(ground, ground_pose, box, pose, r).status == QueryStatus::invalid_input);
    r.margin = std::numeric_limits<double>::quiet_NaN();
    CHECK(contact_manifold(ground, ground_pose, box, pose, r).status == QueryStatus::invalid_input);
    r = {};
    r.feature_angle = 1.0;
    CHECK(contact_manifold(ground, ground_pose, box, pose, r).status == QueryStatus::invalid_input);
    T bad = pose;
    bad.R(0, 0) = 2;
    const ContactManifold<double> m = contact_manifold(ground, ground_pose, box, bad);
    CHECK(m.status == QueryStatus::invalid_pose);
    CHECK(m.count == 0);
}

TEST_CASE("random convex pairs: every manifold point lies on both shapes' surfaces", "[manifold]") {
    // Boxes against hexagonal prisms (both checked by plane distances) in random poses near contact.
    const ConvexPolyhedron<double> hull(hexagonal_prism(0.4, 0.3, 0));
    const auto hull_distance = [&](const T& pose, const V& p) {
        const V l = pose.R.transpose() * (p - pose.t);
        double d = -1e9;
        for (std::size_t f = 0; f < hull.face_count(); ++f)
            d = std::max(d, hull.face_normal(std::uint32_t(f)).dot(l) - hull.face_offset(std::uint32_t(f)));
        return d;
    };
    const Box<double> box(V(0.5, 0.2, 0.3));
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    int manifolds = 0, multi = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const T pa = rot(3 * u(rng), V(u(rng), u(rng), u(rng) + 1e-3), V::Zero());
        // Snap half of the poses to face-parallel ones, where manifolds have several points.
        T pb = trial % 2 ? rot(3 * u(rng), V(u(rng), u(rng), u(rng) + 1e-3), V::Zero()) : T(pa.R, V::Zero());
        const V dir = V(u(rng), u(rng), u(rng)).normalized();
        pb.t = dir * 0.55;  // near contact: from overlapping to apart
        const ContactManifold<double> m = contact_manifold(box, pa, hull, pb);
        if (m.count == 0) continue;
        ++manifolds;
        multi += m.count > 1;
        for (int i = 0; i < m.count; ++i) {
            const ManifoldPoint<double>& p = m.points[i];
            INFO("trial " << trial << " point " << i << " depth " << p.depth);
            // Each point lies on one surface and inside (or on) the other, as deep as its depth says.
            CHECK(box_surface_distance(box, pa, p.point_a) < 1e-9);
            CHECK(hull_distance(pb, p.point_b) < 1e-9);
            CHECK(((p.point_a - p.point_b).dot(m.normal) - p.depth) == Approx(0).margin(1e-9));
            CHECK(p.depth >= -1e-9);
            CHECK(p.depth <= 0.6);
        }
        CHECK(std::abs(m.normal.norm() - 1) < 1e-9);
    }
    CHECK(manifolds > 100);
    CHECK(multi > 50);
}

TEST_CASE("contact_manifold is const and thread-safe", "[manifold][threads]") {
    const Box<double> box(V(0.5, 0.4, 0.3));
    std::vector<T> poses;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 200; ++i) poses.push_back(rot(0.1 * u(rng), V(u(rng), u(rng), 1), V(u(rng), u(rng), 0.28)));
    std::vector<ContactManifold<double>> reference;
    for (const T& p : poses) reference.push_back(contact_manifold(ground, ground_pose, box, p));
    std::vector<int> mismatches(4, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (std::size_t i = 0; i < poses.size(); ++i) {
                const ContactManifold<double> m = contact_manifold(ground, ground_pose, box, poses[i]);
                if (m.count != reference[i].count) ++mismatches[t];
                for (int k = 0; k < std::min(m.count, reference[i].count); ++k)
                    if (m.points[k].point_b != reference[i].points[k].point_b) ++mismatches[t];
            }
        });
    for (auto& th : threads) th.join();
    CHECK(mismatches == std::vector<int>(4, 0));
}

TEST_CASE("two boxes by the axis test agree with the same boxes as hulls through GJK and EPA", "[manifold]") {
    // Box–box manifolds skip GJK/EPA (detail/box_box.hpp); the same boxes given as 8-corner hulls take the general
    // path. Random sizes and orientations, placed by bisection to touching and then pushed 0–5 % of the size in.
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(0, 1);
    const auto corners = [](const V& h) {
        std::vector<V> c;
        for (double x : {-1.0, 1.0})
            for (double y : {-1.0, 1.0})
                for (double z : {-1.0, 1.0}) c.emplace_back(x * h.x(), y * h.y(), z * h.z());
        return c;
    };
    int face_contacts = 0, edge_contacts = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const V ha(0.1 + u(rng), 0.1 + u(rng), 0.1 + u(rng)), hb(0.1 + u(rng), 0.1 + u(rng), 0.1 + u(rng));
        const Box<double> a(ha), b(hb);
        const ConvexPolyhedron<double> hull_a(corners(ha)), hull_b(corners(hb));
        const T pa = rot(6 * u(rng), V(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5), V::Zero());
        // Half the pairs share an orientation up to a turn about one axis (face contacts), half are random.
        const T pb0 = trial % 2 ? rot(6 * u(rng), V(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5), V::Zero())
                                : T(pa.R * rot(u(rng), V::UnitZ(), V::Zero()).R, V::Zero());
        const V dir = V(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
        double lo = 0, hi = 5;
        for (int i = 0; i < 60; ++i) {
            const double mid = (lo + hi) / 2;
            (gjk_intersect(hull_a, pa, hull_b, T(pb0.R, mid * dir)).colliding ? lo : hi) = mid;
        }
        const double size = std::max(ha.maxCoeff(), hb.maxCoeff());
        const T pb(pb0.R, (lo - 0.05 * size * u(rng)) * dir);
        const ContactManifold<double> axis = contact_manifold(a, pa, b, pb);
        const ContactManifold<double> general = contact_manifold(hull_a, pa, hull_b, pb);
        INFO("trial " << trial);
        REQUIRE(axis.colliding == general.colliding);
        if (!axis.colliding) continue;
        const double depth = penetration(hull_a, pa, hull_b, pb).depth;  // EPA's, on the hulls
        CHECK(axis.max_depth() >= depth - 1e-9 * size);          // the chosen axis overlaps at least the minimum
        CHECK(axis.max_depth() <= depth / 0.95 + 1e-9 * size);   // a face axis is kept within 5 % of an edge's
        CHECK(axis.normal.dot(general.normal) > 0.5);
        (axis.count > 1 ? face_contacts : edge_contacts) += 1;
        for (int i = 0; i < axis.count; ++i) {
            const ManifoldPoint<double>& p = axis.points[i];
            CHECK(box_surface_distance(a, pa, p.point_a) < 1e-9 * size);
            CHECK(box_surface_distance(b, pb, p.point_b) < 1e-9 * size);
            CHECK(std::abs((p.point_a - p.point_b).dot(axis.normal) - p.depth) < 1e-9 * size);
            CHECK(p.depth >= -1e-9 * size);
        }
    }
    CHECK(face_contacts > 50);
    CHECK(edge_contacts > 20);
}
