// mesh_intersection_volume(): the line-integral reference of vol(A ∩ B) against volumes known in closed form
// (boxes: exact along x, a convex polygon's area across), the divergence theorem (A ∩ A, B inside A), zero
// for disjoint meshes, and plain Monte Carlo on the bunny; its standard error must be honest and small.
#include "ist_test_util.hpp"

#include "cdkit/ist/closed_mesh.hpp"
#include "cdkit/ist/intersection_volume.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <thread>

using namespace cdkit;

namespace {

/// A closed box of half extents h: 8 vertices, 12 outward-facing triangles.
TriangleMesh<double> closed_box(const Vec3<double>& h) {
    TriangleMesh<double> m;
    for (int k = 0; k < 8; ++k)
        m.vertices.emplace_back((k & 1 ? 1 : -1) * h.x(), (k & 2 ? 1 : -1) * h.y(), (k & 4 ? 1 : -1) * h.z());
    m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    m.source = "closed_box";
    return m;
}

using Poly = std::vector<Eigen::Vector2d>;

/// Convex polygon (counter-clockwise) clipped by the half plane left of a → b (Sutherland–Hodgman).
Poly clip(const Poly& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    Poly out;
    auto side = [&](const Eigen::Vector2d& q) { return (b - a).x() * (q - a).y() - (b - a).y() * (q - a).x(); };
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Eigen::Vector2d& c = p[i];
        const Eigen::Vector2d& d = p[(i + 1) % p.size()];
        const double sc = side(c), sd = side(d);
        if (sc >= 0) out.push_back(c);
        if ((sc >= 0) != (sd >= 0)) out.push_back(c + (d - c) * (sc / (sc - sd)));
    }
    return out;
}

double area(const Poly& p) {
    double a2 = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const auto& c = p[i];
        const auto& d = p[(i + 1) % p.size()];
        a2 += c.x() * d.y() - c.y() * d.x();
    }
    return a2 / 2;
}

Mat3<double> rotation_about_x(double angle) {
    return Eigen::AngleAxisd(angle, Vec3<double>::UnitX()).toRotationMatrix();
}

}  // namespace

TEST_CASE("intersection volume: axis-aligned boxes are exact", "[ist][intersection_volume]") {
    const auto a = closed_box({1, 1, 1}), b = closed_box({0.7, 0.5, 0.9});
    // B's x range [0.1, 1.5], y [-0.2, 0.8], z [-1.3, 0.5]: the overlap is 0.9 · 1.0 · 1.5.
    const auto r = mesh_intersection_volume(a, Transform<double>{}, b,
                                            Transform<double>::translation({0.8, 0.3, -0.4}), {.grid = 16, .passes = 3});
    CHECK(r.volume == Approx(1.35).epsilon(1e-12));
    CHECK(r.standard_error < 1e-12);
    CHECK(r.lines == 3 * 16 * 16);
}

TEST_CASE("intersection volume: a box turned about x (x overlap times a polygon's area)", "[ist][intersection_volume]") {
    const auto a = closed_box({1, 1, 1}), b = closed_box({0.7, 0.5, 0.9});
    for (double angle : {0.3, 0.7854, 1.2}) {
        const Mat3<double> R = rotation_about_x(angle);
        const Vec3<double> t(0.8, 0.3, -0.4);
        // Across x the overlap is the unit square ∩ B's turned rectangle; along x always [0.1, 1].
        Poly square = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}, rect;
        for (Eigen::Vector2d c : {Eigen::Vector2d(-0.5, -0.9), Eigen::Vector2d(0.5, -0.9), Eigen::Vector2d(0.5, 0.9),
                                  Eigen::Vector2d(-0.5, 0.9)})
            rect.push_back(R.block<2, 2>(1, 1) * c + t.tail<2>());
        Poly cut = square;
        for (std::size_t i = 0; i < rect.size(); ++i) cut = clip(cut, rect[i], rect[(i + 1) % rect.size()]);
        const double exact = 0.9 * area(cut);
        const auto r = mesh_intersection_volume(a, Transform<double>{}, b, Transform<double>(R, t),
                                                {.grid = test::scaled(128, 64), .passes = 8});
        INFO("angle " << angle << ": " << r.volume << " ± " << r.standard_error << " against " << exact);
        CHECK(std::abs(r.volume - exact) < 5 * r.standard_error + 1e-9);
        CHECK(r.standard_error < 2e-3 * exact);
        CHECK(std::abs(r.volume - exact) < 5e-3 * exact);
    }
}

TEST_CASE("intersection volume: A ∩ A and a mesh inside another give the mesh's volume", "[ist][intersection_volume]") {
    const auto bunny = test::unit_bunny();
    const double v = signed_mesh_volume(bunny);
    const IntersectionVolumeOptions o{.grid = test::scaled(256, 64), .passes = 4};
    const auto self = mesh_intersection_volume(bunny, Transform<double>{}, bunny, Transform<double>{}, o);
    INFO(self.volume << " ± " << self.standard_error << " against " << v);
    CHECK(std::abs(self.volume - v) < 5 * self.standard_error + 1e-12);
    CHECK(std::abs(self.volume - v) < 1e-3 * v);

    const auto sphere = test::uv_sphere(0.1, 24, 32), big = test::uv_sphere(1.0, 24, 32);
    const double vs = signed_mesh_volume(sphere);
    // The small sphere lies inside the big one: the intersection is the small sphere.
    const auto inner = mesh_intersection_volume(big, Transform<double>{}, sphere,
                                                Transform<double>::translation({0.2, -0.3, 0.1}), o);
    CHECK(std::abs(inner.volume - vs) < 5 * inner.standard_error + 1e-15);
    CHECK(std::abs(inner.volume - vs) < 1e-3 * vs);
}

TEST_CASE("intersection volume: disjoint meshes give zero", "[ist][intersection_volume]") {
    const auto bunny = test::unit_bunny();
    // Far apart: no bounding-box overlap, no line cast.
    const auto far = mesh_intersection_volume(bunny, Transform<double>{}, bunny, Transform<double>::translation({5, 0, 0}));
    CHECK(far.volume == 0);
    CHECK(far.lines == 0);
    // Boxes overlapping, solids not: lines are cast and find nothing.
    const auto a = closed_box({1, 1, 1});
    const Mat3<double> R = Eigen::AngleAxisd(0.7854, Vec3<double>(0, 0, 1)).toRotationMatrix();
    const auto near = mesh_intersection_volume(a, Transform<double>{}, a, Transform<double>(R, {2.2, 2.2, 0}), {.grid = 64});
    CHECK(near.lines > 0);
    CHECK(near.volume == 0);
}

TEST_CASE("intersection volume agrees with Monte Carlo on overlapping bunnies", "[ist][intersection_volume]") {
    const auto bunny = test::unit_bunny();
    const InsideTest inside(bunny);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u01(0, 1);
    const long samples = test::scaled(400000, 40000);
    for (int k = 0; k < 3; ++k) {
        const Mat3<double> R = test::random_rotation(rng);
        const Vec3<double> t(0.3 * u01(rng), 0.3 * u01(rng), 0.3 * u01(rng));
        const Transform<double> pose(R, t);
        const auto r = mesh_intersection_volume(bunny, Transform<double>{}, bunny, pose, {.grid = test::scaled(128, 64), .passes = 4, .seed = 3});
        // Monte Carlo in the bounding box of A (which holds A ∩ B).
        Vec3<double> lo = bunny.vertices[0], hi = lo;
        for (const auto& v : bunny.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
        const Transform<double> inv = pose.inverse();
        long hits = 0;
        for (long s = 0; s < samples; ++s) {
            const Vec3<double> p = lo + Vec3<double>(u01(rng), u01(rng), u01(rng)).cwiseProduct(hi - lo);
            hits += inside.inside(p) && inside.inside(inv * p);
        }
        const double box = (hi - lo).prod(), f = double(hits) / double(samples);
        const double mc = f * box, mc_sigma = std::sqrt(f * (1 - f) / double(samples)) * box;
        INFO("pose " << k << ": lines " << r.volume << " ± " << r.standard_error << ", Monte Carlo " << mc << " ± " << mc_sigma);
        REQUIRE(hits > 100);
        CHECK(std::abs(r.volume - mc) < 4.5 * std::hypot(mc_sigma, r.standard_error));
        CHECK(r.standard_error < 0.25 * mc_sigma);  // far tighter than the Monte Carlo it replaces
    }
}

TEST_CASE("intersection volume: same seed, same bits, from several threads", "[ist][intersection_volume]") {
    const auto bunny = test::unit_bunny();
    const InsideTest a(bunny);
    TriangleMesh<double> moved = bunny;
    const Transform<double> pose(rotation_about_x(0.4), {0.2, 0.1, 0});
    for (auto& v : moved.vertices) v = pose * v;
    const InsideTest b(moved);
    const IntersectionVolumeOptions o{.grid = 64, .passes = 2, .seed = 9};
    const auto ref = mesh_intersection_volume(a, b, o);
    std::vector<IntersectionVolume> got(4);
    std::vector<std::thread> threads;
    for (auto& g : got) threads.emplace_back([&a, &b, &o, &g] { g = mesh_intersection_volume(a, b, o); });
    for (auto& t : threads) t.join();
    for (const auto& g : got) {
        CHECK(g.volume == ref.volume);
        CHECK(g.standard_error == ref.standard_error);
    }
    const auto other_seed = mesh_intersection_volume(a, b, {.grid = 64, .passes = 2, .seed = 10});
    CHECK(other_seed.volume != ref.volume);
}

TEST_CASE("intersection volume: bad input is refused with the mesh's name", "[ist][intersection_volume][errors]") {
    const auto box = closed_box({1, 1, 1});
    auto open = box;
    open.triangles.pop_back();
    open.source = "open_box.obj";
    try {
        (void)mesh_intersection_volume(box, Transform<double>{}, open, Transform<double>{});
        FAIL("an open mesh was accepted");
    } catch (const Error& e) {
        CHECK_THAT(e.what(), Catch::Contains("open_box.obj") && Catch::Contains("boundary"));
    }
    Transform<double> nan_pose;
    nan_pose.t.x() = std::nan("");
    CHECK_THROWS_AS(mesh_intersection_volume(box, Transform<double>{}, box, nan_pose), Error);
    Transform<double> scaled_pose;
    scaled_pose.R *= 2;
    CHECK_THROWS_AS(mesh_intersection_volume(box, Transform<double>{}, box, scaled_pose), Error);
    const InsideTest in(box);
    CHECK_THROWS_AS(mesh_intersection_volume(in, in, {.grid = 0}), Error);
    CHECK_THROWS_AS(mesh_intersection_volume(in, in, {.passes = 0}), Error);
    // The InsideTest overload does not check closedness, but never answers for non-finite coordinates.
    auto broken = box;
    broken.vertices[3].y() = std::numeric_limits<double>::infinity();
    broken.source = "broken_box.obj";
    try {
        (void)mesh_intersection_volume(in, InsideTest(broken));
        FAIL("a non-finite vertex was accepted");
    } catch (const Error& e) {
        CHECK_THAT(e.what(), Catch::Contains("broken_box.obj") && Catch::Contains("non-finite"));
    }
    // An empty mesh has no volume to share.
    CHECK(mesh_intersection_volume(in, InsideTest{}, {}).volume == 0);
}
