// Time of impact of a mesh and a convex shape (ccd/mesh_convex_toi.hpp). A sphere on a straight path is judged by
// the closed form of a swept sphere against every triangle (face plane, edge cylinders, vertex balls: quadratics,
// no GJK, no tree); turning shapes by the discrete mesh–convex collide() at 2,001 instants (a consistency check: the
// advancement must never report a time after the first sampled contact).

#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <cdkit/bv/aabb.hpp>
#include <cdkit/bv/obb.hpp>
#include <cdkit/bv/rss.hpp>
#include <cdkit/ccd/mesh_convex_toi.hpp>
#include <cdkit/ccd/mesh_toi.hpp>
#include <cdkit/ccd/mesh_ccd.hpp>
#include <cdkit/query.hpp>
#include <cdkit/io/load_mesh.hpp>
#include <cdkit/mesh_convex/collide.hpp>

#include <cmath>
#include <limits>
#include <random>

namespace {

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;
constexpr double none = std::numeric_limits<double>::infinity();

/// Smallest root in [0, 1] of a·t² + 2b·t + c = 0 with the motion entering (c > 0 start outside), or none.
double first_root(double a, double b, double c) {
    if (c <= 0) return 0;
    if (a <= 0) return none;
    const double disc = b * b - a * c;
    if (disc < 0) return none;
    const double t = (-b - std::sqrt(disc)) / a;
    return t >= 0 && t <= 1 ? t : none;
}

/// First t in [0, 1] at which the ball of radius r centred at c0 + t·v touches triangle (p0, p1, p2).
double swept_sphere_triangle(const V& c0, const V& v, double r, const V& p0, const V& p1, const V& p2) {
    double best = none;
    // Vertices: |c0 + t v − p| = r.
    for (const V& p : {p0, p1, p2}) {
        const V m = c0 - p;
        best = std::min(best, first_root(v.squaredNorm(), m.dot(v), m.squaredNorm() - r * r));
    }
    // Edges: distance to the edge's line = r, the foot within the edge.
    const V pts[3] = {p0, p1, p2};
    for (int k = 0; k < 3; ++k) {
        const V a = pts[k], e = pts[(k + 1) % 3] - a;
        const double ee = e.squaredNorm();
        const V m = c0 - a;
        const V mp = m - e * (m.dot(e) / ee), vp = v - e * (v.dot(e) / ee);  // components orthogonal to the edge
        const double t = first_root(vp.squaredNorm(), mp.dot(vp), mp.squaredNorm() - r * r);
        if (t == none) continue;
        const double s = (m + t * v).dot(e) / ee;
        if (s >= 0 && s <= 1) best = std::min(best, t);
    }
    // Face: signed plane distance = ±r, the foot inside the triangle.
    const V n = (p1 - p0).cross(p2 - p0).normalized();
    const double d0 = n.dot(c0 - p0), dv = n.dot(v);
    for (double side : {r, -r}) {
        if (dv == 0) continue;
        const double t = (side - d0) / dv;
        if (!(t >= 0 && t <= 1)) continue;
        const V x = c0 + t * v - side * n;  // the touching point in the plane
        const V e0 = (p1 - p0).cross(x - p0), e1 = (p2 - p1).cross(x - p1), e2 = (p0 - p2).cross(x - p2);
        if (e0.dot(n) >= 0 && e1.dot(n) >= 0 && e2.dot(n) >= 0) best = std::min(best, t);
    }
    return best;
}

}  // namespace

TEMPLATE_TEST_CASE("mesh–convex time of impact: a moving sphere against the bunny, by the swept-sphere closed form",
                   "[ccd][mesh_convex]", cdkit::Aabb<double>, cdkit::Obb<double>, cdkit::Rss<double>) {
    using namespace cdkit;
    const TriangleMesh<double> bunny = test::unit_scaled(load_mesh(CDKIT_DATA_DIR "/bunny.obj"));
    const MeshModel<TestType> model(bunny);
    std::mt19937_64 rng(34);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0, 1);
    int hits = 0, misses = 0, missed = 0, false_hit = 0, late = 0, early = 0;
    const ToiRequest request;
    for (int i = 0; i < test::scaled(300, 60); ++i) {
        const double r = 0.005 + 0.05 * u(rng);
        const V start = V(g(rng), g(rng), g(rng)).normalized() * 1.5;
        const V end = V(0.3 * g(rng), 0.3 * g(rng), 0.3 * g(rng)) - start * (0.2 * u(rng));  // through or past it
        const T mesh_pose(test::random_rotation(rng), V(0.1 * g(rng), 0.1 * g(rng), 0.1 * g(rng)));
        // The exact answer in the mesh frame: the centre moves linearly there too.
        const V c0 = mesh_pose.R.transpose() * (start - mesh_pose.t), v = mesh_pose.R.transpose() * (end - start);
        double truth = none;
        for (const Triangle& t : bunny.triangles)
            truth = std::min(truth, swept_sphere_triangle(c0, v, r, bunny.vertices[t[0]], bunny.vertices[t[1]],
                                                          bunny.vertices[t[2]]));
        const ToiResult toi = mesh_convex_toi(model, mesh_pose, mesh_pose, Sphere<double>(r), T(Mat3<double>::Identity(), start),
                                              T(Mat3<double>::Identity(), end), request);
        REQUIRE(toi.status == QueryStatus::ok);
        REQUIRE_FALSE(toi.capped);
        if (truth == none) {
            ++misses;
            false_hit += toi.colliding;  // sampled paths: a graze within 1e-6 would be needed for a hit
            continue;
        }
        ++hits;
        if (!toi.colliding) {
            ++missed;
            continue;
        }
        late += toi.toi > truth + 1e-12;
        // Within the tolerance in distance: the path covers |end − start| per unit of t.
        early += (truth - toi.toi) * (end - start).norm() > 2 * request.tolerance / 1e-3;
    }
    INFO(hits << " paths hit the bunny, " << misses << " miss it");
    CHECK(hits > 10);
    CHECK(misses > 10);
    CHECK(missed == 0);
    CHECK(late == 0);
    CHECK(false_hit == 0);
    CHECK(early == 0);
}

TEST_CASE("mesh–convex time of impact: turning boxes and a turning mesh, never after a sampled contact",
          "[ccd][mesh_convex]") {
    using namespace cdkit;
    const TriangleMesh<double> bunny = test::unit_scaled(load_mesh(CDKIT_DATA_DIR "/bunny.obj"));
    const MeshModel<Obb<double>> model(bunny);
    std::mt19937_64 rng(35);
    std::normal_distribution<double> g;
    int sampled_contacts = 0, after_sample = 0, contacts = 0;
    for (int i = 0; i < test::scaled(40, 10); ++i) {
        const Box<double> box(V(0.02, 0.1, 0.01));
        const T s0(test::random_rotation(rng), V(g(rng), g(rng), g(rng)).normalized() * 1.2);
        const T s1(test::random_rotation(rng), V(0.2 * g(rng), 0.2 * g(rng), 0.2 * g(rng)));
        const T m0(test::random_rotation(rng), V::Zero()), m1(test::random_rotation(rng), V::Zero());
        const ToiResult toi = mesh_convex_toi(model, m0, m1, box, s0, s1);
        REQUIRE(toi.status == QueryStatus::ok);
        contacts += toi.colliding;
        // The same motions (detail::PoseMotion) sampled at 2,001 instants by the discrete mesh–convex collide().
        const detail::PoseMotion mm(m0, m1), ms(s0, s1);
        for (int k = 0; k <= 2000; ++k) {
            const double t = k / 2000.0;
            if (collide(model, mm.at(t), box, ms.at(t)).colliding) {
                ++sampled_contacts;
                after_sample += !toi.colliding || toi.toi > t;
                break;
            }
        }
    }
    INFO(contacts << " contacts, " << sampled_contacts << " seen by sampling");
    CHECK(sampled_contacts > 3);
    CHECK(after_sample == 0);
}

TEST_CASE("mesh–convex time of impact: bad input", "[ccd][mesh_convex]") {
    using namespace cdkit;
    const MeshModel<Obb<double>> model(test::uv_sphere(1.0, 8, 12));
    const Sphere<double> ball(0.1);
    T bad;
    bad.R *= 2;
    CHECK(mesh_convex_toi(model, bad, T{}, ball, T{}, T{}).status == QueryStatus::invalid_pose);
    ToiRequest zero;
    zero.tolerance = 0;
    CHECK(mesh_convex_toi(model, T{}, T{}, ball, T{}, T{}, zero).status == QueryStatus::invalid_input);
    T nan_pose;
    nan_pose.t.x() = std::nan("");
    CHECK(mesh_convex_toi(model, T{}, T{}, ball, nan_pose, T{}).status == QueryStatus::invalid_pose);
}

TEST_CASE("mesh–mesh time of impact under rotation: never after a sampled contact, and arcs that linear CCD misses",
          "[ccd][mesh_convex]") {
    using namespace cdkit;
    // A long thin bar turning half a revolution about its centre past a small sphere that neither end pose touches:
    // its tip sweeps an arc through the sphere, while the straight-line paths of mesh_ccd cut the chord inside it.
    const TriangleMesh<double> bar_mesh = test::grid_box(V(1.0, 0.02, 0.02), 2);
    const TriangleMesh<double> ball_mesh = test::uv_sphere(0.05, 8, 12);
    const MeshModel<Obb<double>> bar(bar_mesh), ball(ball_mesh);
    const T bar0{}, bar1(Eigen::AngleAxisd(3.0, V::UnitZ()).toRotationMatrix(), V::Zero());
    const T ball_pose(Mat3<double>::Identity(), V(0, 0.95, 0));
    const ToiResult toi = mesh_toi(bar, bar0, bar1, ball, ball_pose, ball_pose);
    REQUIRE(toi.status == QueryStatus::ok);
    CHECK(toi.colliding);
    // The bar's side (half width 0.02) meets the ball (radius 0.05, centre 0.95 from the axis) when its angle is
    // π/2 − asin(0.07/0.95) ≈ 1.497 of the 3.0 radians turned: t ≈ 0.499 (the ball is a 96-triangle polyhedron
    // inside the sphere, so a little later; never as late as the bar's upright position at t = π/6).
    CHECK(toi.toi > 0.45);
    CHECK(toi.toi < (M_PI / 2) / 3.0);
    CHECK_FALSE(collide(bar, bar0, ball, ball_pose).colliding);
    CHECK_FALSE(collide(bar, bar1, ball, ball_pose).colliding);
    CHECK_FALSE(mesh_ccd(bar, bar0, bar1, ball, ball_pose, ball_pose).colliding);  // the chords miss it

    // Random turning meshes: never after the first of 2,001 sampled contacts of the discrete collide().
    std::mt19937_64 rng(36);
    std::normal_distribution<double> g;
    const TriangleMesh<double> soup = test::random_soup(60, 0.4, 5);
    const MeshModel<Obb<double>> a(soup), b(ball_mesh);
    int sampled = 0, after = 0;
    for (int i = 0; i < test::scaled(30, 10); ++i) {
        const T a0(test::random_rotation(rng), V::Zero()), a1(test::random_rotation(rng), V(0.1 * g(rng), 0, 0));
        const T b0(Mat3<double>::Identity(), V(g(rng), g(rng), g(rng)).normalized() * 0.8);
        const T b1(test::random_rotation(rng), V(0.2 * g(rng), 0.2 * g(rng), 0.2 * g(rng)));
        const ToiResult r = mesh_toi(a, a0, a1, b, b0, b1);
        REQUIRE(r.status == QueryStatus::ok);
        const detail::PoseMotion ma(a0, a1), mb(b0, b1);
        for (int k = 0; k <= 2000; ++k) {
            const double t = k / 2000.0;
            if (collide(a, ma.at(t), b, mb.at(t)).colliding) {
                ++sampled;
                after += !r.colliding || r.toi > t;
                break;
            }
        }
    }
    CHECK(sampled > 3);
    CHECK(after == 0);
}
