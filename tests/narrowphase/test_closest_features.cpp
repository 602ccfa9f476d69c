// Closest-feature tracking against GJK and the long-double brute-force reference: random polytopes at
// random and near-touching poses (cold and warm-started along coherent paths), boxes with parallel faces,
// penetration, degenerate hulls, bad input and concurrency.
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/closest_features.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include "mesh_factory.hpp"
#include "narrowphase/convex_reference.hpp"
#include "test_common.hpp"

#include <thread>

using namespace cdkit;
using cdkit::test::L;

namespace {

std::vector<Vec3<double>> random_points(std::mt19937_64& rng, int n, double r) {
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0.2, 1.0);
    std::vector<Vec3<double>> pts;
    for (int i = 0; i < n; ++i) pts.push_back(Vec3<double>(g(rng), g(rng), g(rng)).normalized() * r * u(rng));
    return pts;
}

std::vector<Vec3<double>> box_corners(const Vec3<double>& h) {
    std::vector<Vec3<double>> c;
    for (int i = 0; i < 8; ++i)
        c.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
    return c;
}

Mat3<double> small_rotation(std::mt19937_64& rng, double angle) {
    std::normal_distribution<double> g;
    Vec3<double> axis(g(rng), g(rng), g(rng));
    return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

/// Moves pose_b along the GJK normal so that the distance becomes `gap` (negative: overlap by about -gap).
void set_gap(const ConvexPolyhedron<double>& a, const Transform<double>& pa, const ConvexPolyhedron<double>& b,
             Transform<double>& pb, double gap) {
    for (int k = 0; k < 3; ++k) {
        auto d = gjk_distance(a, pa, b, pb);
        if (d.status != GjkStatus::separated || d.normal.squaredNorm() == 0) return;
        pb.t += (gap - d.distance) * d.normal;
        if (gap <= 0) return;
    }
}

struct Checker {
    long cases = 0, separated = 0, colliding = 0, bad_distance = 0, bad_boolean = 0, bad_gjk = 0, used_gjk = 0;
    double worst_rel = 0;
    long iterations = 0;
    /// Compares the result with the brute-force reference (distance ≤ 1e-9 relative, booleans outside a
    /// 1e-9 band) and with GJK.
    void check(const ConvexPolyhedron<double>& a, const Transform<double>& pa, const ConvexPolyhedron<double>& b,
               const Transform<double>& pb, const ClosestFeatureResult<double>& r, bool with_reference = true) {
        ++cases;
        iterations += r.iterations;
        used_gjk += r.used_gjk;
        auto g = gjk_distance(a, pa, b, pb);
        if (r.colliding) ++colliding; else ++separated;
        if (r.colliding != g.colliding && std::max(r.distance, g.distance) > 1e-9) ++bad_gjk;
        if (!r.colliding && !g.colliding && std::abs(r.distance - g.distance) > 1e-9 * g.distance + 1e-14)
            ++bad_gjk;
        if (!with_reference) return;
        auto A = test::ref_polytope(a, pa), B = test::ref_polytope(b, pb);
        const bool hit = test::ref_intersect(A, B);
        if (hit) {
            if (!r.colliding) {
                // Allowed only within the touching band: the reference's boundary cases.
                ++bad_boolean;
            }
            return;
        }
        const L ref = test::ref_distance(A, B);
        if (ref > 1e-9L && r.colliding) ++bad_boolean;
        if (!r.colliding) {
            const double rel = double(std::abs(L(r.distance) - ref) / std::max(ref, L(1e-12)));
            worst_rel = std::max(worst_rel, rel);
            if (rel > 1e-9) ++bad_distance;
            // The witness points are on the shapes and |pb − pa| is the distance.
            if (std::abs((r.point_b - r.point_a).norm() - r.distance) > 1e-12) ++bad_distance;
        }
    }
};

}  // namespace

TEST_CASE("closest features: hull topology is consistent", "[closest_features]") {
    ConvexPolyhedron<double> cube(box_corners({1, 2, 3}));
    REQUIRE(cube.has_topology());
    CHECK(cube.face_count() == 6);
    CHECK(cube.edges().size() == 12);
    CHECK(cube.triangles().size() == 12);
    for (std::uint32_t f = 0; f < 6; ++f) CHECK(cube.face_vertices(f).size() == 4);
    // Points on the faces and edges of a cube (a 5×5×5 grid) leave only the corners: every vertex a corner.
    std::vector<Vec3<double>> grid;
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j)
            for (int k = 0; k <= 4; ++k) grid.emplace_back(i, j, k);
    ConvexPolyhedron<double> gridded(grid);
    CHECK(gridded.has_topology());
    CHECK(gridded.vertices().size() == 8);
    CHECK(gridded.face_count() == 6);
    std::mt19937_64 rng(3);
    for (int n : {4, 10, 200, 1000}) {
        ConvexPolyhedron<double> hull(random_points(rng, n, 1.0));
        REQUIRE(hull.has_topology());
        CHECK(hull.vertices().size() + hull.face_count() == hull.edges().size() + 2);
        // Faces are outward: every vertex lies on or below every face plane.
        int bad = 0;
        for (std::uint32_t f = 0; f < hull.face_count(); ++f)
            for (const auto& v : hull.vertices())
                if (hull.face_normal(f).dot(v) - hull.face_offset(f) > 1e-12) ++bad;
        CHECK(bad == 0);
        // The edge side directions point into their faces.
        for (const auto& e : hull.edges()) {
            CHECK(e.side_left.dot(hull.face_normal(e.face_left)) == Approx(0).margin(1e-12));
            CHECK(e.side_right.dot(hull.face_normal(e.face_right)) == Approx(0).margin(1e-12));
        }
    }
}

TEST_CASE("closest features: cold queries equal GJK and the brute-force reference", "[closest_features]") {
    std::mt19937_64 rng(101);
    Checker ck;
    const int n = test::scaled(150, 30);
    const double gaps[] = {0.5, 0.1, 1e-3, 1e-5, -1e-2, -0.2};
    for (int i = 0; i < n; ++i) {
        ConvexPolyhedron<double> a(random_points(rng, 4 + int(rng() % 40), 1.0));
        ConvexPolyhedron<double> b(random_points(rng, 4 + int(rng() % 40), 0.7));
        Transform<double> pa(test::random_rotation(rng), Vec3<double>::Zero());
        std::normal_distribution<double> g;
        Transform<double> pb(test::random_rotation(rng), Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 3.0);
        set_gap(a, pa, b, pb, gaps[i % 6]);
        ck.check(a, pa, b, pb, closest_features(a, pa, b, pb));
    }
    CHECK(ck.bad_distance == 0);
    CHECK(ck.bad_boolean == 0);
    CHECK(ck.bad_gjk == 0);
    CHECK(ck.worst_rel <= 1e-9);
    // Hit rate: both answers occur.
    CHECK(ck.colliding >= n / 6);
    CHECK(ck.separated >= n / 2);
    // The walk itself answers nearly always (GJK only on cycles / step cap).
    CHECK(ck.used_gjk <= n / 10);
}

TEST_CASE("closest features: warm-started along coherent paths", "[closest_features][warm_start]") {
    std::mt19937_64 rng(202);
    Checker ck;
    const int paths = test::scaled(12, 3), frames = 120;
    long walk_steps = 0, warm_frames = 0;
    for (int p = 0; p < paths; ++p) {
        ConvexPolyhedron<double> a(random_points(rng, 20, 1.0));
        ConvexPolyhedron<double> b(random_points(rng, p % 2 ? 200 : 30, 0.8));
        Transform<double> pa(test::random_rotation(rng), Vec3<double>::Zero());
        Transform<double> pb(test::random_rotation(rng), Vec3<double>(2.5, 0, 0));
        const Mat3<double> spin_a = small_rotation(rng, 0.01), spin_b = small_rotation(rng, 0.013);
        const Mat3<double> orbit = Eigen::AngleAxisd(0.004, Vec3<double>::UnitZ()).toRotationMatrix();
        ClosestFeatureCache<double> cache;
        for (int f = 0; f < frames; ++f) {
            pa.R = spin_a * pa.R;
            pb.R = spin_b * pb.R;
            pb.t = orbit * pb.t;
            // Gap oscillating through near-touching (and, on odd paths, slightly into contact).
            const double gap = (p % 2 ? 0.02 : 0.05) * std::cos(0.05 * f) + (p % 2 ? 0.01 : 0.051);
            set_gap(a, pa, b, pb, gap);
            auto r = closest_features(a, pa, b, pb, &cache);
            if (f > 0) { walk_steps += r.iterations; ++warm_frames; }
            ck.check(a, pa, b, pb, r, f % 10 == 0);
        }
    }
    CHECK(ck.bad_distance == 0);
    CHECK(ck.bad_boolean == 0);
    CHECK(ck.bad_gjk == 0);
    CHECK(ck.colliding > 0);
    CHECK(ck.separated > ck.cases / 2);
    // Coherence: a warm frame needs few steps on average (cold walks on these hulls take ~5–15).
    CHECK(double(walk_steps) / double(warm_frames) < 3.0);
}

TEST_CASE("closest features: boxes with parallel faces, cube face to face", "[closest_features][parallel]") {
    ConvexPolyhedron<double> cube(box_corners({0.5, 0.5, 0.5}));
    ConvexPolyhedron<double> slab(box_corners({2.0, 0.3, 0.1}));
    const Transform<double> id;
    ClosestFeatureCache<double> cache;
    int checked = 0;
    for (double gap : {1.0, 0.1, 1e-3, 1e-6, 1e-9}) {
        for (double slide : {0.0, 0.3, 0.99, 1.2}) {
            // Face to face, partly overlapping in projection (slide < 1), then edge to edge past the corner.
            Transform<double> pb(Mat3<double>::Identity(), Vec3<double>(1.0 + gap, slide, 0.0));
            auto r = closest_features(cube, id, cube, pb, &cache);
            const double expect = slide < 1.0 ? gap : std::hypot(gap, slide - 1.0);
            REQUIRE(r.status == GjkStatus::separated);
            CHECK(r.distance == Approx(expect).epsilon(1e-9).margin(1e-15));
            CHECK(std::abs((r.point_b - r.point_a).norm() - r.distance) < 1e-12);
            ++checked;
            auto c = closest_features(cube, id, cube, pb);  // cold
            CHECK(c.distance == Approx(expect).epsilon(1e-9).margin(1e-15));
        }
        // A thin slab lying on the cube's top face, rotated about the face normal (parallel faces, crossing
        // edges), and tilted a little about x (an edge parallel to the face).
        for (double yaw : {0.0, 0.3, 1.0}) {
            Transform<double> pb(Eigen::AngleAxisd(yaw, Vec3<double>::UnitZ()).toRotationMatrix(),
                                 Vec3<double>(0.1, 0.0, 0.6 + gap));
            auto r = closest_features(cube, id, slab, pb, &cache);
            REQUIRE(r.status == GjkStatus::separated);
            CHECK(r.distance == Approx(gap).epsilon(1e-9).margin(1e-15));
            Transform<double> tilt(Eigen::AngleAxisd(0.2, Vec3<double>::UnitX()).toRotationMatrix(),
                                   Vec3<double>(0.0, 0.0, 0.5 + gap));
            tilt.t.z() += 0.3 * std::sin(0.2) + 0.1 * std::cos(0.2);  // lowest slab edge at height 0.5 + gap
            auto t = closest_features(cube, id, slab, tilt, &cache);
            REQUIRE(t.status == GjkStatus::separated);
            CHECK(t.distance == Approx(gap).epsilon(1e-9).margin(1e-15));
            checked += 2;
        }
    }
    CHECK(checked == 5 * 4 + 5 * 3 * 2);
    // Exactly touching faces and overlapping cubes are colliding.
    Transform<double> touch(Mat3<double>::Identity(), Vec3<double>(1.0, 0.2, 0.1));
    CHECK(closest_features(cube, id, cube, touch).colliding);
    Transform<double> overlap(Mat3<double>::Identity(), Vec3<double>(0.9, 0.2, 0.1));
    CHECK(closest_features(cube, id, cube, overlap).colliding);
    CHECK(closest_features(cube, id, cube, overlap, &cache).colliding);
}

TEST_CASE("closest features: penetrating cases report intersecting", "[closest_features][penetration]") {
    std::mt19937_64 rng(303);
    int colliding = 0, n = test::scaled(100, 20);
    for (int i = 0; i < n; ++i) {
        ConvexPolyhedron<double> a(random_points(rng, 30, 1.0));
        ConvexPolyhedron<double> b(random_points(rng, 30, 0.5));
        Transform<double> pa(test::random_rotation(rng), Vec3<double>::Zero());
        // Deep (centres together) and shallow overlaps, cold and from a cache of a separated frame.
        std::normal_distribution<double> g;
        Vec3<double> dir = Vec3<double>(g(rng), g(rng), g(rng)).normalized();
        Transform<double> far(test::random_rotation(rng), 3.0 * dir);
        Transform<double> near = far;
        set_gap(a, pa, b, near, -0.05);
        Transform<double> deep(far.R, 0.01 * dir);
        ClosestFeatureCache<double> cache;
        auto r0 = closest_features(a, pa, b, far, &cache);
        CHECK(r0.status == GjkStatus::separated);
        for (const auto& pb : {near, deep}) {
            ClosestFeatureCache<double> c2 = cache;
            auto warm = closest_features(a, pa, b, pb, &c2);
            auto cold = closest_features(a, pa, b, pb);
            CHECK(warm.colliding);
            CHECK(cold.colliding);
            CHECK(warm.distance == 0);
            colliding += warm.colliding + cold.colliding;
        }
    }
    CHECK(colliding == 4 * n);
}

TEST_CASE("closest features: degenerate hulls, stale caches and bad poses", "[closest_features][robustness]") {
    std::mt19937_64 rng(404);
    // Slivers: points in a slab 1e-7 thick, a needle, and a near-regular tetrahedron.
    std::vector<Vec3<double>> slab, needle;
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 40; ++i) slab.emplace_back(u(rng), u(rng), 1e-7 * u(rng));
    for (int i = 0; i < 40; ++i) needle.emplace_back(u(rng), 1e-6 * u(rng), 1e-6 * u(rng));
    ConvexPolyhedron<double> s(slab), nd(needle);
    ConvexPolyhedron<double> tet(std::vector<Vec3<double>>{{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}});
    CHECK(s.has_topology());  // the walk itself runs on the slivers (no blanket GJK fallback)
    CHECK(nd.has_topology());
    Checker ck;
    const int n = test::scaled(60, 12);
    for (int i = 0; i < n; ++i) {
        const ConvexPolyhedron<double>* shapes[] = {&s, &nd, &tet};
        const auto& a = *shapes[i % 3];
        const auto& b = *shapes[(i / 3) % 3];
        Transform<double> pa(test::random_rotation(rng), Vec3<double>::Zero());
        std::normal_distribution<double> g;
        Transform<double> pb(test::random_rotation(rng), Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 4.0);
        set_gap(a, pa, b, pb, i % 2 ? 1e-4 : 0.3);
        ClosestFeatureCache<double> cache;
        ck.check(a, pa, b, pb, closest_features(a, pa, b, pb, &cache));
        pb.t += 1e-3 * pb.t.normalized();
        ck.check(a, pa, b, pb, closest_features(a, pa, b, pb, &cache));
    }
    CHECK(ck.bad_distance == 0);
    CHECK(ck.bad_boolean == 0);
    CHECK(ck.bad_gjk == 0);
    CHECK(ck.separated >= n);

    // A cache from another pair (indices out of range or meaningless) still gives the right answer.
    ConvexPolyhedron<double> big(random_points(rng, 300, 1.0));
    Transform<double> pa, pb(Mat3<double>::Identity(), Vec3<double>(3, 0, 0));
    ClosestFeatureCache<double> stale;
    (void)closest_features(big, pa, big, pb, &stale);
    stale.a.index += 100000;
    auto r = closest_features(tet, pa, tet, pb, &stale);
    auto g = gjk_distance(tet, pa, tet, pb);
    CHECK(r.distance == Approx(g.distance).epsilon(1e-9));
    stale.a = {FeatureType::face, 1};
    stale.b = {FeatureType::edge, 2};
    r = closest_features(tet, pa, tet, pb, &stale);
    CHECK(r.distance == Approx(g.distance).epsilon(1e-9));

    // Non-finite poses: a documented status, no hang.
    Transform<double> bad(Mat3<double>::Identity(), Vec3<double>(std::nan(""), 0, 0));
    auto d = closest_features(tet, pa, tet, bad, &stale);
    CHECK(d.status == GjkStatus::degenerate);
    CHECK(std::isnan(d.distance));
}

TEST_CASE("closest features: const queries are thread-safe with separate caches", "[closest_features][concurrency]") {
    std::mt19937_64 rng(505);
    ConvexPolyhedron<double> a(random_points(rng, 20, 1.0)), b(random_points(rng, 200, 0.8));
    const int frames = test::scaled(400, 40);
    std::vector<Transform<double>> pa(static_cast<std::size_t>(frames)), pb(static_cast<std::size_t>(frames));
    Transform<double> A(test::random_rotation(rng), Vec3<double>::Zero()), B(test::random_rotation(rng), {2.0, 0, 0});
    const Mat3<double> sa = small_rotation(rng, 0.02), sb = small_rotation(rng, 0.03);
    for (int f = 0; f < frames; ++f) {
        A.R = sa * A.R;
        B.R = sb * B.R;
        B.t = Eigen::AngleAxisd(0.01, Vec3<double>::UnitZ()).toRotationMatrix() * B.t;
        pa[std::size_t(f)] = A;
        pb[std::size_t(f)] = B;
    }
    auto run = [&](std::vector<double>& out) {
        ClosestFeatureCache<double> cache;
        for (int f = 0; f < frames; ++f)
            out.push_back(closest_features(a, pa[std::size_t(f)], b, pb[std::size_t(f)], &cache).distance);
    };
    std::vector<double> serial;
    run(serial);
    std::vector<std::vector<double>> results(4);
    std::vector<std::thread> threads;
    for (auto& res : results) threads.emplace_back(run, std::ref(res));
    for (auto& t : threads) t.join();
    for (const auto& res : results) CHECK(res == serial);
    int positive = 0;
    for (double d : serial) positive += d > 0;
    CHECK(positive > 0);
}

TEST_CASE("closest features in float agree with the double computation", "[closest_features][float]") {
    std::mt19937_64 rng(606);
    const int n = test::scaled(200, 40);
    int bad = 0, separated = 0, colliding = 0;
    const double gaps[] = {0.5, 0.05, 5e-3, -0.05};
    for (int i = 0; i < n; ++i) {
        std::vector<Vec3<float>> pf, qf;
        std::vector<Vec3<double>> pd, qd;
        for (const auto& x : random_points(rng, 30, 1.0)) {
            pf.push_back(x.cast<float>());
            pd.push_back(pf.back().cast<double>());
        }
        for (const auto& x : random_points(rng, 30, 0.7)) {
            qf.push_back(x.cast<float>());
            qd.push_back(qf.back().cast<double>());
        }
        ConvexPolyhedron<float> a(pf), b(qf);
        ConvexPolyhedron<double> ad(pd), bd(qd);
        Transform<double> pa(test::random_rotation(rng), Vec3<double>::Zero());
        std::normal_distribution<double> g;
        Transform<double> pb(test::random_rotation(rng), Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 3.0);
        set_gap(ad, pa, bd, pb, gaps[i % 4]);
        const Transform<float> paf = pa.cast<float>(), pbf = pb.cast<float>();
        ClosestFeatureCache<float> cache;
        (void)closest_features(a, paf, b, pbf, &cache);
        Transform<float> moved = pbf;
        moved.t += 1e-3f * moved.t.normalized();
        auto r = closest_features(a, paf, b, moved, &cache);
        auto ref = gjk_distance(ad, paf.cast<double>(), bd, moved.cast<double>());
        if (ref.colliding) {
            ++colliding;
            bad += !r.colliding;
        } else {
            ++separated;
            if (ref.distance > 1e-3)
                bad += r.colliding || std::abs(r.distance - ref.distance) > 1e-3 * ref.distance + 1e-5;
        }
    }
    CHECK(bad == 0);
    CHECK(colliding >= n / 8);
    CHECK(separated >= n / 2);
}

TEST_CASE("closest features: scales 1e-6 to 1e6, nested and coincident hulls", "[closest_features][robustness]") {
    std::mt19937_64 rng(707);
    for (double s : {1e-6, 1.0, 1e6}) {
        ConvexPolyhedron<double> a(random_points(rng, 100, s)), b(random_points(rng, 50, 0.1 * s));
        const Transform<double> id;
        CHECK(closest_features(a, id, a, id).colliding);  // coincident
        CHECK(closest_features(a, id, b, id).status == GjkStatus::intersecting);  // b inside a: no boundary contact
        CHECK(closest_features(b, id, a, id).status == GjkStatus::intersecting);
        // A coherent pass from separated through deep overlap and out again, against GJK.
        ClosestFeatureCache<double> cache;
        int bad = 0, hits = 0;
        for (int f = -100; f <= 100; ++f) {
            Transform<double> p(Eigen::AngleAxisd(0.02 * f, Vec3<double>(1, 1, 0).normalized()).toRotationMatrix(),
                                Vec3<double>(0.02 * std::abs(f) * s, 0.002 * f * s, 0));
            auto r = closest_features(a, id, b, p, &cache);
            auto g = gjk_distance(a, id, b, p);
            hits += r.colliding;
            if (r.colliding != g.colliding || std::abs(r.distance - g.distance) > 1e-9 * g.distance + 1e-13 * s)
                ++bad;
        }
        CHECK(bad == 0);
        CHECK(hits > 20);
        CHECK(hits < 180);
    }
}
