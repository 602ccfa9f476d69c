// Ray casts against convex shapes (ccd/convex_ray_cast.hpp) judged by closed forms: the ray–sphere quadratic,
// the slab test for boxes, and a hull's faces one by one (the first face plane the ray enters through where it
// stays inside every other face's half-space). Independent of GJK: no support maps in the oracles.

#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <cdkit/ccd/convex_ray_cast.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>

#include <cmath>
#include <limits>
#include <optional>
#include <random>

namespace {

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;
constexpr double inf = std::numeric_limits<double>::infinity();

V unit(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    const double x = g(rng), y = g(rng), z = g(rng);
    return V(x, y, z).normalized();
}

/// Entry time of the ray o + t·d into the ball |x − c| ≤ r, t ≥ 0 (0 when o is inside), or none.
std::optional<double> sphere_entry(const V& o, const V& d, const V& c, double r) {
    const V m = o - c;
    const double a = d.squaredNorm(), b = m.dot(d), k = m.squaredNorm() - r * r;
    if (k <= 0) return 0.0;
    const double disc = b * b - a * k;
    if (b >= 0 || disc < 0) return std::nullopt;
    return (-b - std::sqrt(disc)) / a;
}

/// Entry time into the box |x_local| ≤ h placed by `pose` (slab test in the box frame), or none.
std::optional<double> box_entry(const V& o, const V& d, const T& pose, const V& h) {
    const V lo = pose.R.transpose() * (o - pose.t), ld = pose.R.transpose() * d;
    double t0 = 0, t1 = inf;
    for (int k = 0; k < 3; ++k) {
        if (ld[k] == 0) {
            if (std::abs(lo[k]) > h[k]) return std::nullopt;
            continue;
        }
        double a = (-h[k] - lo[k]) / ld[k], b = (h[k] - lo[k]) / ld[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    if (t0 > t1) return std::nullopt;
    return t0;
}

}  // namespace

TEST_CASE("convex ray cast: spheres, boxes and hulls against closed forms", "[ccd][ray]") {
    using namespace cdkit;
    std::mt19937_64 rng(515);
    std::uniform_real_distribution<double> u(0.2, 2.0);
    const double tol = 1e-9;
    int hits = 0, misses = 0, late = 0, early_by_more = 0, wrong_hit = 0, bad_normal = 0;
    for (int i = 0; i < test::scaled(3000, 300); ++i) {
        const T pose(test::random_rotation(rng), unit(rng) * u(rng));
        // Rays from a distance of 3–6 aimed near the shape: about half of them hit.
        const V target = pose.t + unit(rng) * u(rng);
        Ray ray;
        ray.origin = pose.t + unit(rng) * (3 + 3 * std::uniform_real_distribution<double>(0, 1)(rng));
        ray.direction = (target - ray.origin) * u(rng);
        std::optional<double> truth;
        RayCastResult r;
        V c_point;  // a point the normal must face away from (the shape's centre)
        switch (i % 2) {
            case 0: {
                const double radius = u(rng);
                truth = sphere_entry(ray.origin, ray.direction, pose.t, radius);
                r = ray_cast(Sphere<double>(radius), pose, ray);
                c_point = pose.t;
                break;
            }
            default: {
                const V half(u(rng), u(rng), 0.1 * u(rng));
                truth = box_entry(ray.origin, ray.direction, pose, half);
                r = ray_cast(Box<double>(half), pose, ray);
                c_point = pose.t;
                break;
            }
        }
        REQUIRE(r.status == QueryStatus::ok);
        const double speed = ray.direction.norm();
        if (!truth) {
            // A miss by more than the tolerance must be a miss; a graze within it may hit.
            ++misses;
            if (r.hit) wrong_hit += 1;
            continue;
        }
        ++hits;
        if (!r.hit) {
            ++late;  // a missed hit
            continue;
        }
        const double t = r.hits[0].t;
        late += t > *truth + 1e-12 * (1 + *truth);
        // Earlier than the exact entry only by what the tolerance allows along the ray (grazing rays more).
        const V n = r.hits[0].normal;
        const double cos_in = std::abs(n.dot(ray.direction)) / speed;
        early_by_more += (*truth - t) * speed > 2 * tol / std::max(cos_in, 1e-3) + 1e-12;
        bad_normal += !(std::abs(n.norm() - 1) < 1e-9 && n.dot(r.hits[0].point - c_point) > 0);
    }
    INFO(hits << " hits, " << misses << " misses");
    CHECK(hits > 50);
    CHECK(misses > 50);
    CHECK(late == 0);
    CHECK(early_by_more == 0);
    CHECK(bad_normal == 0);
    // Rays that miss by more than 1e-9 were drawn at random: a hit on one would be a false positive. Grazes within
    // the tolerance are too rare in this draw to matter, so none is allowed.
    CHECK(wrong_hit == 0);
}

TEST_CASE("convex ray cast: a hull by its face planes, starts inside, thin shapes, bounds, bad input", "[ccd][ray]") {
    using namespace cdkit;
    std::mt19937_64 rng(99);
    // A hull of random points: the exact entry is the largest entering face-plane time, if no exiting plane comes
    // earlier (Cyrus–Beck clipping over the hull's face planes, not its support map).
    std::vector<V> pts;
    for (int i = 0; i < 40; ++i) pts.push_back(unit(rng));
    const ConvexPolyhedron<double> hull(pts);
    int checked = 0, late = 0, wrong = 0;
    for (int i = 0; i < test::scaled(500, 100); ++i) {
        const T pose(test::random_rotation(rng), unit(rng));
        Ray ray;
        ray.origin = pose.t + unit(rng) * 4;
        ray.direction = pose.t + 0.8 * unit(rng) - ray.origin;
        double t0 = 0, t1 = inf;
        for (std::size_t f = 0; f < hull.face_count(); ++f) {
            const V n = pose.R * hull.face_normal(std::uint32_t(f));
            const V p = pose * V(hull.face_normal(std::uint32_t(f)) * hull.face_offset(std::uint32_t(f)));
            const double num = n.dot(p - ray.origin), den = n.dot(ray.direction);
            if (den == 0) {
                if (num < 0) t0 = inf;
                continue;
            }
            const double t = num / den;
            if (den < 0) t0 = std::max(t0, t);
            else t1 = std::min(t1, t);
        }
        const bool truth = t0 <= t1;
        const RayCastResult r = ray_cast(hull, pose, ray);
        ++checked;
        wrong += r.hit != truth && std::abs(t0 - t1) > 1e-6;  // grazes of an edge within rounding: undecided
        if (truth && r.hit) late += r.hits[0].t > t0 + 1e-9;
    }
    CHECK(checked > 0);
    CHECK(wrong == 0);
    CHECK(late == 0);

    // A ray starting inside hits at t_min.
    const Box<double> box(V(1, 1, 1));
    Ray inside;
    inside.origin = V(0.2, 0.1, 0);
    inside.direction = V(1, 0, 0);
    const RayCastResult in = ray_cast(box, T{}, inside);
    REQUIRE(in.hit);
    CHECK(in.hits[0].t == 0);
    // A plate 1e-9 thick, hit face-on from far away: never passed through.
    const Box<double> plate(V(1, 1, 5e-10));
    Ray down;
    down.origin = V(0.3, -0.2, 1e6);
    down.direction = V(0, 0, -2e6);
    const RayCastResult p = ray_cast(plate, T{}, down);
    REQUIRE(p.hit);
    CHECK(p.hits[0].t <= (1e6 - 5e-10) / 2e6);
    CHECK(p.hits[0].t > 0.4999999);
    CHECK(p.hits[0].normal.z() == Approx(1.0));
    // t_max before the shape: a miss; t_min past it: a miss.
    Ray shortened = down;
    shortened.t_max = 0.49;
    CHECK_FALSE(ray_cast(plate, T{}, shortened).hit);
    Ray late_start = down;
    late_start.t_min = 0.6;
    CHECK_FALSE(ray_cast(plate, T{}, late_start).hit);
    // Bad input: a clear status, no hit.
    Ray nan_ray = down;
    nan_ray.direction.x() = std::nan("");
    CHECK(ray_cast(plate, T{}, nan_ray).status == QueryStatus::invalid_input);
    Ray zero = down;
    zero.direction.setZero();
    CHECK(ray_cast(plate, T{}, zero).status == QueryStatus::invalid_input);
    T scaled;
    scaled.R *= 2;
    CHECK(ray_cast(plate, scaled, down).status == QueryStatus::invalid_pose);
    ConvexRayRequest bad;
    bad.tolerance = -1;
    CHECK(ray_cast(plate, T{}, down, bad).status == QueryStatus::invalid_input);
}

TEST_CASE("convex ray cast: a ray passing within half the tolerance of a shape hits it, one beyond it misses",
          "[ccd][ray]") {
    // The cast first clips the ray to the shape's bounding ball; for a sphere that ball is the shape itself, so the
    // ball must be grown by the tolerance or grazing rays would be missed. Between half the tolerance and the
    // tolerance either answer is allowed (the cast steps past a support plane while it is over tolerance / 2 away).
    const cdkit::Sphere<double> ball(1.0);
    const T pose = T::translation(V(5, -2, 3));
    cdkit::ConvexRayRequest request;
    request.tolerance = 1e-6;
    for (const double gap : {0.0, 0.4e-6, 0.9e-6, 1.5e-6, 3e-6}) {
        cdkit::Ray ray;
        ray.origin = pose.t + V(-10, 1 + gap, 0);
        ray.direction = V(2, 0, 0);
        const cdkit::RayCastResult r = cdkit::ray_cast(ball, pose, ray, request);
        CAPTURE(gap);
        REQUIRE(r.status == cdkit::QueryStatus::ok);
        if (gap < 0.5 * request.tolerance) CHECK(r.hit);
        if (gap > request.tolerance) CHECK_FALSE(r.hit);
        if (r.hit) {
            CHECK(r.hits[0].t <= 5.0);  // never after the tangent point, at x = pose.x: t = 10 / 2
            CHECK(std::abs(r.hits[0].point.y() - pose.t.y()) <= 1 + gap + 1e-12);
        }
    }
}
