// GJK against exact references: closed forms for sphere/capsule/box pairs, brute-force polytope distance
// in long double; touching configurations, scale ratios, warm start, concurrency.
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include "mesh_factory.hpp"
#include "narrowphase/convex_reference.hpp"
#include "test_common.hpp"

#include <thread>

using namespace cdkit;
using cdkit::test::L;
using cdkit::test::VL;

namespace {

Transform<double> random_pose(std::mt19937_64& rng, double spread) {
    std::uniform_real_distribution<double> u(-spread, spread);
    return {test::random_rotation(rng), Vec3<double>(u(rng), u(rng), u(rng))};
}

/// Whether a separated boolean result's points are A's and B's extreme points along its normal (within 1e-12),
/// B's beyond A's: the certificate of a separating-plane exit.
template <class A, class B>
bool plane_points_certified(const A& a, const Transform<double>& pa, const B& b, const Transform<double>& pb,
                            const GjkResult<double>& r) {
    const Vec3<double> n = r.normal;  // A towards B
    const double ha = n.dot(pa * Vec3<double>(a.support(pa.R.transpose() * n)));
    const double hb = n.dot(pb * Vec3<double>(b.support(pb.R.transpose() * Vec3<double>(-n))));
    return std::abs(n.dot(r.point_a) - ha) <= 1e-12 && std::abs(n.dot(r.point_b) - hb) <= 1e-12 &&
           n.dot(r.point_b) > n.dot(r.point_a);
}

std::vector<Vec3<double>> random_points(std::mt19937_64& rng, int n, double r) {
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0.2, 1.0);
    std::vector<Vec3<double>> pts;
    for (int i = 0; i < n; ++i) {
        Vec3<double> p(g(rng), g(rng), g(rng));
        pts.push_back(p.normalized() * r * u(rng));
    }
    return pts;
}

std::vector<Vec3<double>> box_corners(const Vec3<double>& h) {
    std::vector<Vec3<double>> c;
    for (int i = 0; i < 8; ++i)
        c.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
    return c;
}

}  // namespace

TEST_CASE("GJK statuses have distinct names", "[gjk]") {
    using cdkit::GjkStatus;
    const std::string names[] = {to_string(GjkStatus::separated), to_string(GjkStatus::touching),
                                 to_string(GjkStatus::intersecting), to_string(GjkStatus::max_iterations),
                                 to_string(GjkStatus::degenerate)};
    CHECK(names[0] == "separated");
    CHECK(names[4] == "degenerate");
    for (int i = 0; i < 5; ++i)
        for (int j = i + 1; j < 5; ++j) CHECK(names[i] != names[j]);
}

TEST_CASE("convex shapes reject bad input", "[gjk][shapes]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(Sphere<double>(-1.0), Error);
    CHECK_THROWS_AS(Sphere<double>(nan), Error);
    CHECK_THROWS_AS(Box<double>(Vec3<double>(1, -1, 1)), Error);
    CHECK_THROWS_AS(Capsule<double>(1.0, nan), Error);
    CHECK_THROWS_AS(Cylinder<double>(-0.1, 1.0), Error);
    CHECK_THROWS_AS(Cone<double>(1.0, -1.0), Error);
    CHECK_THROWS_AS(Ellipsoid<double>(Vec3<double>(1, 1, nan)), Error);
    CHECK_THROWS_AS(ConvexTriangle<double>(Vec3<double>(nan, 0, 0), Vec3<double>::Zero(), Vec3<double>::Zero()),
                    Error);
    CHECK_NOTHROW(Sphere<double>(0.0));
}

TEST_CASE("convex hull rejects empty, few, flat and NaN point sets", "[gjk][convex_hull]") {
    using P = std::vector<Vec3<double>>;
    CHECK_THROWS_AS(ConvexPolyhedron<double>(P{}), Error);
    CHECK_THROWS_AS(ConvexPolyhedron<double>(P{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), Error);
    CHECK_THROWS_AS(ConvexPolyhedron<double>(P{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.2, 0}}), Error);
    CHECK_THROWS_AS(ConvexPolyhedron<double>(P{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}), Error);
    CHECK_THROWS_AS(ConvexPolyhedron<double>(P{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, std::nan("")}}), Error);
    ConvexPolyhedron<double> cube(box_corners({1, 2, 3}));
    CHECK(cube.vertices().size() == 8);
    CHECK(cube.triangles().size() == 12);
}

TEST_CASE("convex hull contains its points; hill climbing equals brute force", "[gjk][convex_hull]") {
    std::mt19937_64 rng(42);
    for (int n : {20, 200, 1000}) {
        auto pts = random_points(rng, n, 1.0);
        ConvexPolyhedron<double> hull(pts);
        auto ref = test::ref_polytope(hull, Transform<double>{});
        int outside = 0;
        for (const auto& p : pts) {
            for (const auto& t : ref.tri) {
                VL n3 = (ref.v[t[1]] - ref.v[t[0]]).cross(ref.v[t[2]] - ref.v[t[0]]);
                if (n3.normalized().dot(p.cast<L>() - ref.v[t[0]]) > 1e-12L) { ++outside; break; }
            }
        }
        CHECK(outside == 0);
        std::normal_distribution<double> g;
        for (int i = 0; i < 500; ++i) {
            Vec3<double> d(g(rng), g(rng), g(rng));
            double best = -1e300;
            for (const auto& v : hull.vertices()) best = std::max(best, d.dot(v));
            REQUIRE(d.dot(hull.support(d)) == best);
        }
        // Hinted hill climbing: any start vertex (a chained previous answer, a random one, one out of range)
        // reaches the same maximum, and the hint is left on a maximising vertex.
        std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(hull.vertices().size()) + 5);
        std::uint32_t chained = std::uint32_t(-1);
        int wrong = 0;
        for (int i = 0; i < 500; ++i) {
            Vec3<double> d(g(rng), g(rng), g(rng));
            double best = -1e300;
            for (const auto& v : hull.vertices()) best = std::max(best, d.dot(v));
            std::uint32_t random_hint = pick(rng);
            if (d.dot(hull.support(d, chained)) != best) ++wrong;
            if (d.dot(hull.support(d, random_hint)) != best) ++wrong;
            if (chained >= hull.vertices().size() || random_hint >= hull.vertices().size()) ++wrong;
            if (d.dot(hull.vertices()[chained]) != best) ++wrong;
        }
        CHECK(wrong == 0);
    }
}

TEST_CASE("hinted support from every vertex equals brute force, ties and odd degrees included", "[gjk][convex_hull]") {
    // The hint's scan goes over each vertex's neighbour ring two at a time (SSE2, double); an odd ring repeats
    // its last neighbour. Every vertex as the hint, directions that tie (axis and diagonal directions on a box
    // and an octahedron-like hull) and random ones, and a coherent sequence: the answer is a maximiser each time.
    std::mt19937_64 rng(2026);
    std::normal_distribution<double> g;
    std::vector<std::vector<Vec3<double>>> clouds;
    clouds.push_back(
        {{-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {-1, 1, 1}, {1, 1, 1}});
    clouds.push_back({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0.5, 0.5, 0.6}});
    clouds.push_back(random_points(rng, 60, 1.0));
    clouds.push_back(random_points(rng, 400, 1.0));
    std::vector<Vec3<double>> dirs;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z)
                if (x || y || z) dirs.emplace_back(x, y, z);
    for (int i = 0; i < 40; ++i) dirs.emplace_back(g(rng), g(rng), g(rng));
    for (const auto& pts : clouds) {
        ConvexPolyhedron<double> hull(pts);
        const auto n = std::uint32_t(hull.vertices().size());
        int wrong = 0;
        for (const auto& d : dirs) {
            double best = -1e300;
            for (const auto& v : hull.vertices()) best = std::max(best, d.dot(v));
            for (std::uint32_t h = 0; h < n; ++h) {
                std::uint32_t hint = h;
                wrong += d.dot(hull.support(d, hint)) != best;
                wrong += hint >= n || d.dot(hull.vertices()[hint]) != best;
            }
        }
        // Coherent: a direction turning by 0.5° per step, the hint chained.
        const Vec3<double> axis = Vec3<double>(0.3, 0.8, -0.5).normalized();
        const Mat3<double> turn = Eigen::AngleAxisd(0.5 * 3.14159265358979 / 180, axis).toRotationMatrix();
        Vec3<double> d(0.2, -0.7, 0.4);
        std::uint32_t hint = std::uint32_t(-1);
        for (int i = 0; i < 2000; ++i) {
            d = turn * d;
            double best = -1e300;
            for (const auto& v : hull.vertices()) best = std::max(best, d.dot(v));
            wrong += d.dot(hull.support(d, hint)) != best;
        }
        CHECK(wrong == 0);
    }
    // The scalar scan (no rings) in long double gives the same maxima.
    std::vector<Vec3<long double>> pl;
    for (const auto& p : clouds[3]) pl.push_back(p.cast<long double>());
    ConvexPolyhedron<long double> hl(pl);
    int wrong = 0;
    for (const auto& dd : dirs) {
        const Vec3<long double> d = dd.cast<long double>();
        long double best = -1e300L;
        for (const auto& v : hl.vertices()) best = std::max(best, d.dot(v));
        std::uint32_t hint = 0;
        wrong += d.dot(hl.support(d, hint)) != best;
    }
    CHECK(wrong == 0);
}

TEST_CASE("cylinder and cone support maps for tiny and huge directions", "[gjk][shapes]") {
    // planar_norm replaces std::hypot by sqrt(x² + y²) except where the squares under- or overflow.
    Cylinder<double> cyl(0.5, 0.4);
    Cone<double> cone(0.6, 0.7);
    for (double m : {1e-170, 1e-300, 1.0, 1e200, 1e300}) {
        const Vec3<double> d(m, -m, 0.0);
        const Vec3<double> rim(0.5 / std::sqrt(2.0), -0.5 / std::sqrt(2.0), 0.4);
        const Vec3<double> p = cyl.support(d);
        CHECK(p.head<2>().isApprox(rim.head<2>(), 1e-12));
        const Vec3<double> q = cone.support(d);
        CHECK(q.head<2>().isApprox(Vec3<double>(0.6 / std::sqrt(2.0), -0.6 / std::sqrt(2.0), 0).head<2>(), 1e-12));
        CHECK(q.z() == -0.7);
    }
    CHECK(cyl.support(Vec3<double>(0, 0, -1)) == Vec3<double>(0, 0, -0.4));
    CHECK(cone.support(Vec3<double>(0, 0, 1e-300)) == Vec3<double>(0, 0, 0.7));
}

TEST_CASE("support maps are maximal over sampled support points", "[gjk][shapes]") {
    std::mt19937_64 rng(7);
    Sphere<double> sphere(0.7);
    Box<double> box({0.3, 0.5, 0.9});
    Capsule<double> capsule(0.2, 0.8);
    Cylinder<double> cylinder(0.5, 0.4);
    Cone<double> cone(0.6, 0.7);
    Ellipsoid<double> ell({0.2, 0.9, 0.5});
    ConvexTriangle<double> tri({0, 0, 0}, {1, 0.2, 0}, {0.3, 1, 0.5});
    std::normal_distribution<double> g;
    auto check = [&](const auto& s) {
        int bad = 0;
        std::vector<Vec3<double>> dirs;
        for (int i = 0; i < 200; ++i) dirs.emplace_back(g(rng), g(rng), g(rng));
        dirs.emplace_back(0, 0, 0);
        dirs.emplace_back(0, 0, 1);
        dirs.emplace_back(0, 0, -1);
        for (const auto& d : dirs) {
            Vec3<double> p = s.support(d);
            if (!p.allFinite()) ++bad;
            for (const auto& e : dirs)
                if (d.dot(Vec3<double>(s.support(e))) > d.dot(p) + 1e-12) ++bad;
        }
        CHECK(bad == 0);
    };
    check(sphere); check(box); check(capsule); check(cylinder); check(cone); check(ell); check(tri);
    check(Inflated<Box<double>>{box, 0.1});
    check(Transformed<Cone<double>>{cone, random_pose(rng, 1.0)});
    check(MinkowskiDifference<Cylinder<double>, Ellipsoid<double>>{cylinder, ell});
    // Cone apex and base rim lie on the cone.
    CHECK(cone.support({0, 0, 1}).z() == Approx(0.7));
    CHECK(cone.support({1, 0, 0}).isApprox(Vec3<double>(0.6, 0, -0.7)));
}

TEMPLATE_TEST_CASE("GJK sphere-sphere and sphere-capsule match closed forms", "[gjk]", float, double) {
    using S = TestType;
    std::mt19937_64 rng(11);
    const S tol = std::is_same_v<S, double> ? S(1e-12) : S(2e-5);
    int hits = 0, n = test::scaled(2000, 50);
    for (int i = 0; i < n; ++i) {
        std::uniform_real_distribution<double> ur(0.01, 1.0);
        Sphere<S> a(S(ur(rng))), b(S(ur(rng)));
        Capsule<S> c(S(ur(rng)), S(ur(rng)));
        Transform<S> pa = random_pose(rng, 1.5).template cast<S>(), pb = random_pose(rng, 1.5).template cast<S>();
        auto r = gjk_distance(a, pa, b, pb);
        L ref = (pa.t.template cast<L>() - pb.t.template cast<L>()).norm() - L(a.radius) - L(b.radius);
        if (ref > 0) {
            REQUIRE(r.status == GjkStatus::separated);
            CHECK(std::abs(L(r.distance) - ref) <= L(tol) * std::max<L>(1, ref));
            CHECK((r.point_b - r.point_a).norm() == Approx(r.distance).margin(10 * tol));
        } else {
            ++hits;
            CHECK(r.colliding);
        }
        CHECK(gjk_intersect(a, pa, b, pb).colliding == (ref <= 0));
        // Sphere against capsule: the capsule axis is the segment ±half_length·z in its frame.
        auto rc = gjk_distance(a, pa, c, pb);
        VL p = pa.t.template cast<L>();
        VL e0 = (pb * Vec3<S>(0, 0, -c.half_length)).template cast<L>();
        VL e1 = (pb * Vec3<S>(0, 0, c.half_length)).template cast<L>();
        L refc = (test::closest_on_segment(p, e0, e1) - p).norm() - L(a.radius) - L(c.radius);
        if (refc > 0) CHECK(std::abs(L(rc.distance) - refc) <= L(tol) * 10 * std::max<L>(1, refc));
        else CHECK(rc.colliding);
    }
    CHECK(hits > n / 10);
    CHECK(hits < n * 9 / 10);
}

TEST_CASE("GJK sphere-box matches closed form across scale ratios up to 1e6", "[gjk]") {
    std::mt19937_64 rng(5);
    int hits = 0, total = 0;
    for (double scale : {1e-3, 1.0, 1e3, 1e6}) {
        for (int i = 0; i < test::scaled(500, 20); ++i) {
            std::uniform_real_distribution<double> u(0.1, 1.0);
            Box<double> box(Vec3<double>(u(rng), u(rng), u(rng)) * scale);
            Sphere<double> sphere(u(rng));
            Transform<double> pb = random_pose(rng, 0.1);
            pb.t *= scale;
            Transform<double> ps = random_pose(rng, 1.6 * scale);
            auto r = gjk_distance(sphere, ps, box, pb);
            VL c = (pb.inverse() * ps.t).cast<L>();
            L ref = test::point_box_distance(c, box.half.cast<L>()) - L(sphere.radius);
            ++total;
            if (ref > 1e-9L * scale) {
                REQUIRE(r.status == GjkStatus::separated);
                CHECK(std::abs(L(r.distance) - ref) <= 1e-9L * std::max<L>(ref, L(1e-6) * scale));
            } else if (ref < -1e-9L * scale) {
                ++hits;
                CHECK(r.colliding);
            }
        }
    }
    CHECK(hits > total / 20);
    CHECK(hits < total * 19 / 20);
}

TEST_CASE("GJK polytope distance matches brute force in long double", "[gjk]") {
    std::mt19937_64 rng(2024);
    int n = test::scaled(300, 20), hits = 0, separated = 0;
    for (int i = 0; i < n; ++i) {
        std::uniform_int_distribution<int> un(8, 40);
        ConvexPolyhedron<double> a(random_points(rng, un(rng), 1.0));
        ConvexPolyhedron<double> b(i % 3 == 0 ? box_corners({0.4, 0.7, 0.2}) : random_points(rng, un(rng), 0.6));
        Transform<double> pa = random_pose(rng, 0.3), pb = random_pose(rng, 1.5);
        auto ra = test::ref_polytope(a, pa), rb = test::ref_polytope(b, pb);
        bool ref_hit = test::ref_intersect(ra, rb);
        auto r = gjk_distance(a, pa, b, pb);
        auto rbool = gjk_intersect(a, pa, b, pb);
        if (ref_hit) {
            ++hits;
            CHECK(r.colliding);
            CHECK(rbool.colliding);
        } else {
            ++separated;
            L ref = test::ref_distance(ra, rb);
            if (ref > 1e-12L) {
                REQUIRE(r.status == GjkStatus::separated);
                CHECK(std::abs(L(r.distance) - ref) <= 1e-9L * std::max<L>(ref, 1e-3L));
                CHECK(!rbool.colliding);
                // Witness points lie on the shapes: their distance is the distance.
                CHECK(std::abs((r.point_a - r.point_b).norm() - r.distance) <= 1e-9 * std::max(1.0, r.distance));
            }
        }
    }
    CHECK(hits > n / 10);
    CHECK(separated > n / 10);
}

TEST_CASE("GJK distance between curved shapes near contact is within 1e-9 of a certified interval", "[gjk]") {
    // On curved shapes the support points cluster and the triangle step meets sliver triangles, whose
    // rounded normal once put |v| below the distance (up to 7e-7 relative on close cones). The reference is
    // long-double GJK clamped into a certified interval: lower bounds from the gap between the supporting
    // planes along the reference's and the answer's normals, upper bound from the reference's witness points
    // (long-double GJK has the same sliver floor, 2000× smaller, and was seen 9e-9 below a certified bound).
    // The first 600 cone/cylinder–ellipsoid pairs of seed 2026 passed even with the needle-triangle error (see
    // the needle test below); pairs 1024, 4720 and 5698 of the 6000 were 1.1–1.2e-9 off. Since the
    // normal is built at the triangle's largest angle 120k such pairs stay ≤ 2.3e-10; the bound keeps a margin.
    std::mt19937_64 rng(2026);
    std::uniform_real_distribution<double> u(0.5, 1.0);
    GjkSettings<L> tight;
    tight.rel_tolerance = 1e-16L;
    int tried = 0, placed = 0, checked = 0, below_lower = 0, off = 0, ref_not_apart = 0, not_apart = 0;
    double worst = 0;
    auto gap = [](const auto& a, const Transform<L>& pa, const auto& b, const Transform<L>& pb, VL n) {
        n.normalize();
        const Transformed<std::decay_t<decltype(a)>> ta{a, pa};
        const Transformed<std::decay_t<decltype(b)>> tb{b, pb};
        return n.dot(tb.support(VL(-n))) - n.dot(ta.support(n));
    };
    auto run = [&](const auto& a, const auto& al, const auto& b, const auto& bl, int k) {
        ++tried;
        Transform<double> pa(test::random_rotation(rng), Vec3<double>::Zero());
        std::normal_distribution<double> g;
        Transform<double> pb(test::random_rotation(rng), Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 0.4);
        auto d0 = gjk_distance(al, pa.cast<L>(), bl, pb.cast<L>(), nullptr, tight);
        if (d0.status != GjkStatus::separated) return;  // (never: the drawn poses are apart, checked below)
        ++placed;
        pb.t += (std::pow(10.0, -3 - (k % 3)) - double(d0.distance)) * d0.normal.template cast<double>();
        const Transform<L> pal = pa.cast<L>(), pbl = pb.cast<L>();
        auto ref = gjk_distance(al, pal, bl, pbl, nullptr, tight);
        auto d = gjk_distance(a, pa, b, pb);
        // Placed 1e-3 … 1e-5 apart (1e-2 … 1e-4 of the size): both must say so; every placed pair is checked.
        ref_not_apart += ref.status != GjkStatus::separated;
        not_apart += d.status != GjkStatus::separated;
        if (ref.status != GjkStatus::separated || d.status != GjkStatus::separated) return;
        const L lower = std::max(gap(al, pal, bl, pbl, ref.normal), gap(al, pal, bl, pbl, d.normal.template cast<L>()));
        const L upper = std::max(lower, (ref.point_b - ref.point_a).norm());
        const L ref_c = std::clamp(ref.distance, lower, upper);
        ++checked;
        if (L(d.distance) < lower * (1 - 1e-9L)) ++below_lower;
        const double err = double(std::abs(L(d.distance) - ref_c) / ref_c);
        worst = std::max(worst, err);
        if (err > 1e-9) ++off;
    };
    for (int k = 0; k < test::scaled(6000, 600); ++k) {
        const double r1 = 0.1 * u(rng), h1 = 0.1 * u(rng), r2 = 0.1 * u(rng), h2 = 0.1 * u(rng);
        if (k % 2 == 0) run(Cone<double>(r1, h1), Cone<L>(r1, h1), Cone<double>(r2, h2), Cone<L>(r2, h2), k / 2);
        else run(Cylinder<double>(r1, h1), Cylinder<L>(r1, h1), Ellipsoid<double>({r2, h2, r1}),
                 Ellipsoid<L>(VL(r2, h2, r1)), k / 2);
    }
    // The other curved pairs (cylinder–cylinder, cone–cylinder and capsule–cone were also off before, up to
    // 4.7e-9).
    for (int k = 0; k < test::scaled(2500, 250); ++k) {
        const double r1 = 0.1 * u(rng), h1 = 0.1 * u(rng), r2 = 0.1 * u(rng), h2 = 0.1 * u(rng);
        switch (k % 5) {
            case 0:
                run(Cylinder<double>(r1, h1), Cylinder<L>(r1, h1), Cylinder<double>(r2, h2), Cylinder<L>(r2, h2),
                    k / 5);
                break;
            case 1:
                run(Ellipsoid<double>({r1, h1, r2}), Ellipsoid<L>(VL(r1, h1, r2)), Ellipsoid<double>({r2, h2, r1}),
                    Ellipsoid<L>(VL(r2, h2, r1)), k / 5);
                break;
            case 2:
                run(Capsule<double>(r1, h1), Capsule<L>(r1, h1), Cone<double>(r2, h2), Cone<L>(r2, h2), k / 5);
                break;
            case 3:
                run(Cone<double>(r1, h1), Cone<L>(r1, h1), Cylinder<double>(r2, h2), Cylinder<L>(r2, h2), k / 5);
                break;
            default:
                run(Capsule<double>(r1, h1), Capsule<L>(r1, h1), Ellipsoid<double>({r2, h2, r1}),
                    Ellipsoid<L>(VL(r2, h2, r1)), k / 5);
                break;
        }
    }
    INFO("worst relative error " << worst << " over " << checked << " pairs, " << placed << " placed of " << tried);
    CHECK(ref_not_apart == 0);
    CHECK(not_apart == 0);
    CHECK(checked == placed);
    CHECK(placed == tried);  // centres 0.4 apart, bounding radii ≤ 0.1·√2: every drawn pose is apart
    CHECK(below_lower == 0);
    CHECK(off == 0);
    CHECK(worst < 5e-10);
}

TEST_CASE("GJK triangle step on needles: the normal is built at the largest angle", "[gjk]") {
    // Near contact on curved shapes GJK's triangles become needles: two support points ~1e-8 apart, the third
    // ~0.2 away. ab × ac taken at the far vertex (angle ~5e-8) tilted the plane by ε/5e-8, putting |v| up to
    // 1e-4 relative off at distance 1e-5; the edges at the largest angle give ~ε·lever/distance. Reference:
    // the squared plane distance of the same (rounded) points in __float128 (products of doubles exact).
    using Q = __float128;
    std::mt19937_64 rng(77);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double worst = 0, worst_point = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const double dist = trial % 2 ? 1e-5 : 1e-3, h = 5e-9 * (1 + u(rng) * 0.5);
        const Mat3<double> R = test::random_rotation(rng);
        // Foot (0, 0, dist) inside the needle a, b, c.
        const Vec3<double> p[3] = {R * Vec3<double>(-0.15 + 0.01 * u(rng), 0.3 * h * u(rng), dist),
                                   R * Vec3<double>(0.05, -h, dist), R * Vec3<double>(0.05 + 1e-9 * u(rng), h, dist)};
        for (int rot = 0; rot < 3; ++rot) {  // the far vertex first, second and third
            GjkSimplex<double> s;
            s.size = 3;
            for (int i = 0; i < 3; ++i) s.v[std::size_t(i)].w = p[(i + rot) % 3];
            detail::SimplexSelection<double> sel;
            detail::SimplexSolver<double>::select(s, sel);
            REQUIRE(sel.size == 3);
            Q e1[3], e2[3];
            for (int k = 0; k < 3; ++k) { e1[k] = Q(p[1][k]) - Q(p[0][k]); e2[k] = Q(p[2][k]) - Q(p[0][k]); }
            const Q n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                            e1[0] * e2[1] - e1[1] * e2[0]};
            const Q np = n[0] * Q(p[0][0]) + n[1] * Q(p[0][1]) + n[2] * Q(p[0][2]);
            const Q ref2 = np * np / (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            const double rel = std::abs(double((Q(sel.v.squaredNorm()) - ref2) / ref2)) / 2;  // on |v|
            worst = std::max(worst, rel);
            // Witness points are Σ λ_i (a_i, b_i) over the final simplex, whose weights gjk_finish refines with
            // sliver_weights: they must put Σ λ_i w_i on the foot of the origin (in __float128:
            // n·p0 n / |n|²), or the points slide along the needle while |v| is right (Ericson's weights:
            // 3.7e-3 off with the far vertex first, 1e-11 otherwise).
            detail::SimplexSolver<double>::apply(s, sel);
            detail::SimplexSolver<double>::sliver_weights(s, sel.v);
            const Q nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
            Q err2 = 0;
            for (int k = 0; k < 3; ++k) {
                Q x = -np * n[k] / nn;
                for (int j = 0; j < 3; ++j) x += Q(s.lambda[std::size_t(j)]) * Q(s.v[std::size_t(j)].w[k]);
                err2 += x * x;
            }
            worst_point = std::max(worst_point, std::sqrt(double(err2)));
        }
    }
    INFO("worst relative error of |v| " << worst << ", worst distance of Σλw from the foot " << worst_point);
    CHECK(worst < 1e-10);
    CHECK(worst_point < 1e-13);  // the points are ~0.2 from the origin: a few ε of that
}

TEST_CASE("GJK touching configurations: boxes face to face, edge to edge", "[gjk][touching]") {
    Box<double> box({0.5, 0.5, 0.5});
    ConvexPolyhedron<double> hull(box_corners({0.5, 0.5, 0.5}));
    for (double s : {1e-3, 1.0, 1e4}) {
        Box<double> b2({0.5 * s, 0.5 * s, 0.5 * s});
        Transform<double> pa = Transform<double>::translation({0, 0, 0});
        Transform<double> pb = Transform<double>::translation({0.5 + 0.5 * s, 0.2, -0.1});
        auto r = gjk_distance(box, pa, b2, pb);
        CHECK(r.colliding);
        CHECK(r.distance == 0.0);
        CHECK(gjk_intersect(box, pa, b2, pb).colliding);
        pb.t.x() += 1e-3;
        r = gjk_distance(box, pa, b2, pb);
        CHECK(r.status == GjkStatus::separated);
        CHECK(r.distance == Approx(1e-3).epsilon(1e-9));
        CHECK(r.normal.isApprox(Vec3<double>(1, 0, 0), 1e-9));
    }
    // Hull against box, face to face exactly.
    auto r = gjk_distance(hull, Transform<double>{}, box, Transform<double>::translation({0, 1.0, 0}));
    CHECK(r.colliding);
    CHECK(r.distance == 0.0);
    // Sphere resting on a box face.
    Sphere<double> sphere(0.25);
    r = gjk_distance(sphere, Transform<double>::translation({0.1, 0.2, 0.75}), box, Transform<double>{});
    CHECK(r.status == GjkStatus::touching);
}

TEST_CASE("GJK shapes of all kinds: boolean agrees with distance, hit rate", "[gjk]") {
    std::mt19937_64 rng(99);
    Cylinder<double> cyl(0.4, 0.6);
    Cone<double> cone(0.5, 0.5);
    Ellipsoid<double> ell({0.3, 0.6, 0.2});
    Capsule<double> cap(0.2, 0.5);
    ConvexPolyhedron<double> hull(random_points(rng, 300, 0.7));
    int hits = 0, n = test::scaled(1000, 50), bad = 0;
    auto run = [&](const auto& a, const auto& b) {
        Transform<double> pa = random_pose(rng, 0.5), pb = random_pose(rng, 1.0);
        auto d = gjk_distance(a, pa, b, pb);
        auto i = gjk_intersect(a, pa, b, pb);
        if (d.status == GjkStatus::max_iterations || d.status == GjkStatus::degenerate) ++bad;
        if (d.colliding) ++hits;
        if (d.status == GjkStatus::separated && d.distance > 1e-9) {
            // Lower bound check: witnesses are on the shapes, so nothing can be closer than their gap
            // measured along the normal; and the boolean must agree.
            if (i.colliding) ++bad;
            double gap = (d.point_b - d.point_a).dot(d.normal);
            if (std::abs(gap - d.distance) > 1e-9) ++bad;
            // The support planes along ±normal certify the distance.
            Vec3<double> nA = pa.R.transpose() * d.normal, nB = pb.R.transpose() * (-d.normal);
            double hA = d.normal.dot(pa * Vec3<double>(a.support(nA)));
            double hB = d.normal.dot(pb * Vec3<double>(b.support(nB)));
            if (std::abs((hB - hA) - d.distance) > 1e-7) ++bad;
        } else if (d.colliding && !i.colliding) {
            ++bad;
        }
    };
    for (int k = 0; k < n; ++k) {
        run(cyl, cone); run(ell, cap); run(hull, cyl); run(cone, ell); run(cap, hull);
    }
    CHECK(bad == 0);
    CHECK(hits > n / 2);
    CHECK(hits < 4 * n);
}

TEST_CASE("GJK warm start gives the same answer with no more iterations", "[gjk][warm_start]") {
    std::mt19937_64 rng(3);
    ConvexPolyhedron<double> a(random_points(rng, 500, 1.0)), b(random_points(rng, 500, 1.0));
    GjkCache<double> cache;
    long cold_it = 0, warm_it = 0;
    Transform<double> pb = Transform<double>::translation({2.5, 0.3, 0.1});
    for (int step = 0; step < 200; ++step) {
        Transform<double> pa(Eigen::AngleAxisd(0.01 * step, Vec3<double>(0, 0, 1)).toRotationMatrix(),
                             Vec3<double>(0.002 * step, 0, 0));
        auto cold = gjk_distance(a, pa, b, pb);
        auto warm = gjk_distance(a, pa, b, pb, &cache);
        cold_it += cold.iterations;
        warm_it += warm.iterations;
        REQUIRE(cold.status == warm.status);
        CHECK(warm.distance == Approx(cold.distance).epsilon(1e-12));
    }
    CHECK(warm_it <= cold_it);
}

TEST_CASE("GJK warm start from stored support points: exact near contact, guarded against other shapes",
          "[gjk][warm_start]") {
    std::mt19937_64 rng(17);
    ConvexPolyhedron<double> a(random_points(rng, 20, 1.0)), b(random_points(rng, 200, 0.8)),
        other(random_points(rng, 60, 0.5));
    Cylinder<double> cyl(0.4, 0.5);
    Capsule<double> cap(0.2, 0.4);
    const int frames = test::scaled(600, 60);
    // Coherent paths through near contact and overlap: B moved along the normal to a scheduled gap. Warm
    // and cold distances agree to 1e-9 relative, plus `abs_tol`: on a cylinder's rim GJK (cold or warm) stops
    // on its no-progress floor after ~30 iterations, up to ~2e-10 absolute from the other start's answer.
    auto path = [&](const auto& sa, const auto& sb, double abs_tol, long& checked, long& hits, long& bad) {
        GjkCache<double> dcache, bcache;
        Transform<double> pa, pb;
        for (int f = 0; f < frames; ++f) {
            pa.R = Eigen::AngleAxisd(0.009 * f, Vec3<double>(1, 2, 3).normalized()).toRotationMatrix();
            pb.R = Eigen::AngleAxisd(0.012 * f, Vec3<double>(-1, 2, 0.5).normalized()).toRotationMatrix();
            pb.t = 3.0 * Vec3<double>(std::cos(0.005 * f), std::sin(0.005 * f), 0.1);
            const double gap = (f % 3 == 2) ? -1e-3 : std::pow(10.0, -2.0 - 3.0 * (0.5 + 0.5 * std::sin(0.05 * f)));
            const auto d0 = gjk_distance(sa, pa, sb, pb);
            if (d0.status != GjkStatus::separated) continue;
            pb.t += (gap - d0.distance) * d0.normal;
            const auto cold = gjk_distance(sa, pa, sb, pb);
            const auto warm = gjk_distance(sa, pa, sb, pb, &dcache);
            const auto wb = gjk_intersect(sa, pa, sb, pb, &bcache);
            ++checked;
            hits += cold.colliding;
            const bool wrong_bool = warm.colliding != cold.colliding || wb.colliding != cold.colliding;
            const bool wrong_dist = !cold.colliding &&
                                    std::abs(warm.distance - cold.distance) > 1e-9 * cold.distance + abs_tol;
            bad += wrong_bool || wrong_dist;
        }
    };
    long checked = 0, hits = 0, bad = 0;
    path(a, b, 1e-14, checked, hits, bad);
    path(a, cyl, 1e-9, checked, hits, bad);
    path(cap, b, 1e-14, checked, hits, bad);
    CHECK(bad == 0);
    CHECK(hits > checked / 5);
    CHECK(hits < checked / 2);
    // One cache used for two different shape pairs in turn: the stored points of one must never be taken
    // for the other (answers equal the cold ones).
    GjkCache<double> shared;
    int wrong = 0;
    for (int i = 0; i < test::scaled(400, 40); ++i) {
        const Transform<double> p = random_pose(rng, 1.2);
        const ConvexPolyhedron<double>& bb = (i % 2) ? b : other;
        const auto cold = gjk_distance(a, Transform<double>{}, bb, p);
        const auto warm = gjk_distance(a, Transform<double>{}, bb, p, &shared);
        if (cold.colliding != warm.colliding) ++wrong;
        else if (!cold.colliding && std::abs(cold.distance - warm.distance) > 1e-9 * cold.distance + 1e-14) ++wrong;
        if (gjk_intersect(a, Transform<double>{}, bb, p, &shared).colliding != cold.colliding) ++wrong;
    }
    CHECK(wrong == 0);
}

TEST_CASE("GJK boolean early exit returns the extreme points of a separating plane", "[gjk]") {
    std::mt19937_64 rng(29);
    ConvexPolyhedron<double> hull(random_points(rng, 100, 0.5));
    Capsule<double> cap(0.1, 0.3);
    GjkSettings<double> planes_only;  // the bounding-ball exit has its own test (test_gjk_bounding_balls.cpp)
    planes_only.bounding_ball_test = false;
    int separated = 0, bad = 0;
    for (int i = 0; i < test::scaled(500, 50); ++i) {
        const Transform<double> pa = random_pose(rng, 0.2), pb = random_pose(rng, 1.5);
        const auto r = gjk_intersect(hull, pa, cap, pb, nullptr, planes_only);
        if (r.status != GjkStatus::separated) continue;
        ++separated;
        if (!plane_points_certified(hull, pa, cap, pb, r)) ++bad;
    }
    CHECK(bad == 0);
    CHECK(separated > test::scaled(500, 50) / 10);
}

TEST_CASE("GJK warm boolean's cached-direction exit: the cold answer, with a certified world-frame plane",
          "[gjk][warm_start][boolean]") {
    // A warm boolean first tests the cache's last separating direction in world axes (gjk_query's
    // warm_direction_separates). Along coherent paths of a hull and a capsule (margins, on either side) and of
    // two hulls, through separation and overlap: every answer is the cold one, and every exit there (iterations
    // 0, separated) reports the extreme points of both shapes along its normal, B's beyond A's, and a distance
    // that is a lower bound.
    std::mt19937_64 rng(31);
    const ConvexPolyhedron<double> hull(random_points(rng, 100, 0.5)), other(random_points(rng, 60, 0.4));
    const Capsule<double> cap(0.1, 0.3);
    int exits = 0, bad = 0, wrong = 0, frames = 0;
    auto path = [&](const auto& a, const auto& b) {
        GjkCache<double> cache;
        const Mat3<double> spin_a = Eigen::AngleAxisd(0.02, Vec3<double>(1, 2, 3).normalized()).toRotationMatrix();
        const Mat3<double> spin_b = Eigen::AngleAxisd(0.03, Vec3<double>(-2, 1, 1).normalized()).toRotationMatrix();
        Transform<double> pa(test::random_rotation(rng), Vec3<double>(5, -3, 2));  // away from the origin
        Transform<double> pb(test::random_rotation(rng), pa.t + Vec3<double>(1.6, 0.0, 0.0));
        for (int f = 0; f < test::scaled(400, 80); ++f, ++frames) {
            pa.R = spin_a * pa.R;
            pb.R = spin_b * pb.R;
            pb.t = pa.t + Vec3<double>(0.9 + 0.7 * std::cos(0.05 * f), 0.2 * std::sin(0.03 * f), 0.0);
            const auto r = gjk_intersect(a, pa, b, pb, &cache);
            wrong += r.colliding != gjk_intersect(a, pa, b, pb).colliding;
            if (r.status != GjkStatus::separated || r.iterations != 0) continue;
            ++exits;
            if (!plane_points_certified(a, pa, b, pb, r)) ++bad;
            if (!(r.distance > 0 && r.distance <= gjk_distance(a, pa, b, pb).distance * (1 + 1e-12))) ++bad;
        }
    };
    path(hull, cap);
    path(cap, hull);
    path(hull, other);
    CHECK(wrong == 0);
    CHECK(bad == 0);
    CHECK(exits > frames / 4);
}

TEST_CASE("GJK cold boolean with and without momentum agrees with long double near contact", "[gjk][boolean]") {
    // The cold boolean path (world-frame first support pair, Nesterov momentum in the first iterations) must
    // give the long-double answer whatever the search directions: pairs of every shape kind are placed at
    // gaps ±1e-2 … ±1e-6 of their size along the reference normal. Separated answers must be certified: the
    // returned distance is a lower bound, and the supporting planes along the returned normal are that far
    // apart, through the returned points.
    std::mt19937_64 rng(515);
    std::uniform_real_distribution<double> u(0.5, 1.0);
    GjkSettings<L> tight;
    tight.rel_tolerance = 1e-16L;
    tight.momentum_iterations = 0;
    GjkSettings<double> momentum, plain, always;
    plain.momentum_iterations = 0;
    always.momentum_iterations = 1000;
    // Support-plane exits only (their points are checked on the shapes); the ball exit is tested apart.
    momentum.bounding_ball_test = plain.bounding_ball_test = always.bounding_ball_test = false;
    const GjkSettings<double> settings[3] = {momentum, plain, always};
    int checked = 0, wrong = 0, uncertified = 0;
    long iterations[3] = {0, 0, 0}, curved_close[2] = {0, 0};
    auto run = [&](const auto& a, const auto& al, const auto& b, const auto& bl, int k, bool curved) {
        Transform<double> pa(test::random_rotation(rng), Vec3<double>::Zero());
        std::normal_distribution<double> g;
        Transform<double> pb(test::random_rotation(rng), Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 0.4);
        const auto d0 = gjk_distance(al, pa.cast<L>(), bl, pb.cast<L>(), nullptr, tight);
        if (d0.status != GjkStatus::separated) return;
        const double target = (k % 2 ? -0.1 : 0.1) * std::pow(10.0, -2 * (1 + (k / 2) % 3));
        pb.t += (target - double(d0.distance)) * d0.normal.template cast<double>();
        const auto ref = gjk_distance(al, pa.cast<L>(), bl, pb.cast<L>(), nullptr, tight);
        const bool ref_hit = ref.colliding;
        if (!ref_hit && !(ref.distance > 1e-8L)) return;  // too close to call in double
        if (ref_hit != (target < 0)) return;
        ++checked;
        for (int m = 0; m < 3; ++m) {
            const auto r = gjk_intersect(a, pa, b, pb, nullptr, settings[m]);
            iterations[m] += r.iterations;
            if (curved && !ref_hit && m < 2) curved_close[m] += r.iterations;
            if (r.colliding != ref_hit) { ++wrong; continue; }
            if (r.status != GjkStatus::separated) continue;
            const Vec3<double> n = r.normal;
            const double ha = n.dot(pa * Vec3<double>(a.support(pa.R.transpose() * n)));
            const double hb = n.dot(pb * Vec3<double>(b.support(pb.R.transpose() * Vec3<double>(-n))));
            const double tol = 1e-12;
            if (!(r.distance > 0) || L(r.distance) > ref.distance * (1 + 1e-9L) + L(tol) ||
                std::abs(n.norm() - 1) > 1e-12 || hb - ha < r.distance - tol ||
                std::abs(n.dot(r.point_a) - ha) > tol || std::abs(n.dot(r.point_b) - hb) > tol)
                ++uncertified;
        }
    };
    const int n = test::scaled(60, 12);
    for (int k = 0; k < n; ++k) {
        const double r1 = 0.1 * u(rng), h1 = 0.1 * u(rng), r2 = 0.1 * u(rng), h2 = 0.1 * u(rng);
        run(Ellipsoid<double>({r1, h1, r2}), Ellipsoid<L>(VL(r1, h1, r2)), Ellipsoid<double>({h2, r2, r1}),
            Ellipsoid<L>(VL(h2, r2, r1)), k, true);
        run(Box<double>({r1, h1, r2}), Box<L>(VL(r1, h1, r2)), Box<double>({h2, r2, h1}), Box<L>(VL(h2, r2, h1)), k,
            false);
        run(Capsule<double>(r1 / 2, h1), Capsule<L>(r1 / 2, h1), Capsule<double>(r2 / 2, h2), Capsule<L>(r2 / 2, h2),
            k, false);
        run(Cylinder<double>(r1, h1), Cylinder<L>(r1, h1), Cone<double>(r2, h2), Cone<L>(r2, h2), k, true);
        const auto pts = random_points(rng, 60, 0.1);
        std::vector<VL> ptsl;
        for (const auto& p : pts) ptsl.push_back(p.cast<L>());
        run(ConvexPolyhedron<double>(pts), ConvexPolyhedron<L>(ptsl), Cylinder<double>(r2, h2), Cylinder<L>(r2, h2),
            k, false);
    }
    INFO("iterations: default " << iterations[0] << ", plain " << iterations[1] << ", always momentum "
                                << iterations[2] << "; curved separated pairs: default " << curved_close[0]
                                << ", plain " << curved_close[1]);
    CHECK(checked >= n * 5 * 8 / 10);
    CHECK(wrong == 0);
    CHECK(uncertified == 0);
    // Momentum exists to shorten the search on curved shapes near contact (deterministic counts, seeded).
    CHECK(curved_close[0] < curved_close[1]);
}

TEST_CASE("GJK queries are thread-safe on shared shapes", "[gjk][concurrency]") {
    std::mt19937_64 rng(8);
    ConvexPolyhedron<double> a(random_points(rng, 400, 1.0));
    Ellipsoid<double> e({0.5, 0.3, 0.8});
    std::vector<Transform<double>> poses;
    for (int i = 0; i < 400; ++i) poses.push_back(random_pose(rng, 1.5));
    std::vector<double> serial;
    for (const auto& p : poses) serial.push_back(gjk_distance(a, Transform<double>{}, e, p).distance);
    std::vector<int> mismatches(4, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            GjkCache<double> cache;  // per thread, per pair
            for (std::size_t i = 0; i < poses.size(); ++i) {
                auto r = gjk_distance(a, Transform<double>{}, e, poses[i]);
                if (r.distance != serial[i]) ++mismatches[std::size_t(t)];
                auto w = gjk_distance(a, Transform<double>{}, e, poses[i], &cache);
                if (std::abs(w.distance - serial[i]) > 1e-9) ++mismatches[std::size_t(t)];
            }
        });
    for (auto& th : threads) th.join();
    for (int m : mismatches) CHECK(m == 0);
}
