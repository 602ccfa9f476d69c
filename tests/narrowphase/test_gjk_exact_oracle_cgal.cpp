// Issue 37, independent oracles: cdkit's convex queries on polytope pairs (boxes, triangles, hulls) judged by an
// exact referee that shares no code with them (tests/oracles/exact_polytope.hpp: CGAL's exact quadratic program
// for the distance and exact LPs for the depth, on exactly posed vertices). First the referee itself on answers
// known in closed form; then the hard-case corpus (convex_hard_cases.hpp, the same generator as
// test_gjk_hard_cases.cpp and cdkit_bench_convex_hard) with every polytope case judged exactly — one wrong boolean
// fails; then test_gjk.cpp's random polytope pairs and the hull's strict containment test, judged exactly. The
// corpus's curved cases go to the curved referee (tests/oracles/curved_referee.hpp, MPFR), which is itself checked
// here against the exact answer on every polytope case (it judges hulls by their support function too).
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include "convex_hard_cases.hpp"
#include "mesh_factory.hpp"
#include "oracles/curved_referee.hpp"
#include "oracles/exact_polytope.hpp"
#include "test_common.hpp"

#include <cmath>
#include <random>

using namespace cdkit;
using cdkit::test::exact::exact_direction_separates;
using cdkit::test::exact::exact_polytope_pair;

namespace {

constexpr int hard_exact_cases = 20000;  // CI size; cdkit_bench_convex_hard runs the same judge at 1M

std::vector<Vec3<double>> cube(double h) {
    std::vector<Vec3<double>> c;
    for (int i = 0; i < 8; ++i) c.emplace_back(i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h);
    return c;
}

Transform<double> at(double x, double y = 0, double z = 0) {
    return Transform<double>(Mat3<double>::Identity(), Vec3<double>(x, y, z));
}

std::vector<Vec3<double>> cloud(std::mt19937_64& rng, int n, double r) {
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0.2, 1.0);
    std::vector<Vec3<double>> pts;
    for (int i = 0; i < n; ++i) pts.push_back(Vec3<double>(g(rng), g(rng), g(rng)).normalized() * r * u(rng));
    return pts;
}

}  // namespace

TEST_CASE("exact polytope oracle: answers known in closed form", "[gjk][exact]") {
    const auto box = cube(1);
    // Apart by 2^-40, touching face to face, overlapping by 2^-40 (the L∞ depth of axis-aligned boxes is exact).
    auto r = exact_polytope_pair(box, at(0), box, at(2 + 0x1p-40, 0.5, 0.25), true);
    CHECK_FALSE(r.intersect);
    CHECK(r.squared_distance == 0x1p-80);
    r = exact_polytope_pair(box, at(0), box, at(2, 0.5, 0.25), true);
    CHECK(r.intersect);
    CHECK(r.depth_known);
    CHECK(r.touching);
    CHECK(r.depth_inf == 0);
    r = exact_polytope_pair(box, at(0), box, at(2 - 0x1p-40, 0.5, 0.25), true);
    CHECK(r.intersect);
    CHECK_FALSE(r.touching);
    CHECK(r.depth_inf == 0x1p-40);
    // One ulp apart a million units from the origin (ulp(1e6 + 1) = 2^-33), where long double would still resolve it
    // but a double difference of the world coordinates would not be needed: the poses are applied exactly.
    const double x = 1e6 + 1, next = std::nextafter(x, 2e6);
    r = exact_polytope_pair(box, at(1e6), box, at(next + 1), true);
    CHECK_FALSE(r.intersect);
    CHECK(r.distance == next - x);
    // A rotated cube: a vertex of B touching A's face exactly. R rotates (1, 1, 1)/√3-ish corners; its rounded
    // entries make B's vertex coordinates non-doubles, so only an exact pose can place B touching: B's corner
    // (−1, −1, −1) at the rotation's image lands at R·(−1, −1, −1) + t; t is chosen so the lowest vertex's x is
    // exactly 1 along A's face x = 1 — not representable in general, so check the side instead: B strictly beyond.
    const Mat3<double> R = Eigen::AngleAxisd(0.7, Vec3<double>(1, 2, 3).normalized()).toRotationMatrix();
    r = exact_polytope_pair(box, at(0), box, Transform<double>(R, Vec3<double>(4, 0, 0)), true);
    CHECK_FALSE(r.intersect);
    CHECK(r.distance > 0.2);
    // Flat shapes: coplanar triangles that overlap touch (no volume; a weakly separating plane); crossing ones
    // overlap with depth; a point on a triangle touches; a segment through a box overlaps.
    const std::vector<Vec3<double>> t1{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, t2{{0.2, 0.2, 0}, {2, 0.2, 0}, {0.2, 2, 0}};
    const std::vector<Vec3<double>> t3{{0.2, 0.2, -1}, {0.2, 0.2, 1}, {0.3, 0.25, 0}};
    r = exact_polytope_pair(t1, at(0), t2, at(0), true);
    CHECK(r.intersect);
    CHECK(r.touching);
    r = exact_polytope_pair(t1, at(0), t3, at(0), true);
    CHECK(r.intersect);
    CHECK_FALSE(r.touching);
    CHECK(r.depth_inf > 0);
    const std::vector<Vec3<double>> point{{0.25, 0.25, 0}};
    r = exact_polytope_pair(t1, at(0), point, at(0), true);
    CHECK(r.touching);
    r = exact_polytope_pair(t1, at(0), point, at(0, 0, 0x1p-60), false);
    CHECK_FALSE(r.intersect);
    CHECK(r.squared_distance == 0x1p-120);
    const std::vector<Vec3<double>> segment{{-3, 0.5, 0.5}, {3, 0.5, 0.5}};
    r = exact_polytope_pair(box, at(0), segment, at(0), true);
    CHECK(r.intersect);
    CHECK_FALSE(r.touching);
    // Separating directions, exactly.
    CHECK(exact_direction_separates(box, at(0), box, at(2 + 0x1p-40), Vec3<double>(1, 0, 0)));
    CHECK(exact_direction_separates(box, at(0), box, at(2), Vec3<double>(1, 0, 0)));  // touching: a weak plane
    CHECK_FALSE(exact_direction_separates(box, at(0), box, at(2 - 0x1p-40), Vec3<double>(1, 0, 0)));
    CHECK_FALSE(exact_direction_separates(box, at(0), box, at(2 + 0x1p-40), Vec3<double>(1, 1e-9, 0)));
}

TEST_CASE("hard convex cases: every polytope case judged by the exact oracle", "[gjk][hard][exact]") {
    using namespace cdkit::test::hard;
    const long cases = cdkit::test::scaled(hard_exact_cases, 2000);
    ExactOracle oracle;
    oracle.pair = &exact_polytope_pair;
    oracle.curved = &cdkit::test::curved::curved_referee;
    oracle.curved_depth = &cdkit::test::curved::depth_exceeds;
    const auto per_pair = run_hard_cases(cases, 1, oracle);
    Counts all;
    for (const Counts& c : per_pair) all.add(c);
    const ExactCounts& e = all.exact;
    const CurvedCounts& v = all.curved;
    INFO(e.judged << " judged exactly, " << v.judged << " curved (" << v.undecided << " undecided, " << v.wrong
                  << " wrong), " << e.touching << " touching, " << e.in_band << " in band, " << e.wrong
                  << " wrong of " << e.answers << " answers; worst distance error " << e.worst_distance_error
                  << "; the curved referee against the exact answer: " << e.referee_checked << " checked, "
                  << e.referee_undecided << " undecided, " << e.referee_contradicted << " refuted\n"
                  << e.first_wrong << v.first_wrong);
    // 6 of the 20 class pairs are polytope pairs (box-box, hull-hull, hull-box, tri-tri, tri-box, hull-tri), judged
    // exactly; the other 14 go to the curved referee (test_gjk_curved_referee.cpp asserts its own counts).
    CHECK(e.judged + v.judged == cases);
    CHECK(e.not_judged == 0);
    CHECK(e.judged == 6 * (cases / 20) + std::min<long>(cases % 20, 1));
    CHECK(e.wrong == 0);
    CHECK(v.wrong == 0);
    CHECK(all.failures() == 0);
    // The curved referee, judged in turn on the polytope cases: no certificate the exact answer refutes, and it
    // decides the cases that are not exactly touching (those, and flat pairs with no interior, stay undecided).
    CHECK(e.referee_checked == e.judged);
    CHECK(e.referee_contradicted == 0);
    CHECK(e.referee_undecided <= e.touching + e.judged / 20);
    // The corpus is hard for the judge too: apart, overlapping and exactly touching cases all occur, and answers
    // near contact (in the band) occur.
    CHECK(e.separated > e.judged / 5);
    CHECK(e.overlapping > e.judged / 5);
    CHECK(e.touching > 0);
    CHECK(e.answers >= 6 * e.judged);
    // Disagreements exist only within the band, and within 1e-10 of the size (docs/convex.md's promise).
    CHECK(e.disagree_by_gap[3] + e.disagree_by_gap[4] == 0);
    // Distances: where the exact distance exceeds 1e-6 of the size (the long-double count's domain) every
    // separation distance is within 1e-9 of it, relative; closer ones are binned (rounding of |t| dominates there).
    CHECK(e.distances > e.separated);
    CHECK(e.distances_far > e.distances / 3);
    CHECK(e.distance_error_far[3] + e.distance_error_far[4] + e.distance_error_far[5] == 0);
    // EPA's bracket against the exact L∞ depth's bounds (δ ≤ depth_inf ≤ √3·δ): seed 1 at 20,000 cases has 2 of
    // 2,257 brackets whose lower end exceeds depth_inf by 1e-12 … 1.5e-10 of the size (a needle box against a segment,
    // a degenerate exit on a 5e3-long segment): counted, and bounded here so that more would be seen.
    CHECK(e.epa_checked > e.overlapping / 2);
    CHECK(e.epa_contradicted <= e.epa_checked / 500);
    // The row "hard cases seed 1 (CI size)" of results/exact_convex_judge.csv, quoted in docs/robustness.md (§1b).
    // The corpus places its near-contact pairs with long-double GJK, so a change to GJK may move these counts:
    // rerun `cdkit_bench_convex_hard 20000 1` and update the file and these numbers together.
    if (cases == hard_exact_cases) {
        CHECK(e.judged == 6000);
        CHECK(e.not_judged == 0);  // was 14000 before the curved referee
        CHECK(v.judged == 14000);
        CHECK(v.undecided == 0);
        CHECK(v.disagree_band <= 7292);
        CHECK(v.disagree_undecided == 0);
        CHECK(v.distances_far >= 6870);
        CHECK(v.worst_distance_error_far < 1e-10);  // 9.9e-11
        CHECK(e.referee_undecided <= 467);  // the exactly touching pairs (563 before de84222)
        CHECK(e.touching == 467);
        CHECK(e.in_band == 1474);
        CHECK(e.disagree_band <= 4535);
        CHECK(e.distances_far >= 4128);
        CHECK(e.worst_distance_error_far < 1e-10);  // 7.4e-11
        CHECK(e.epa_contradicted <= 2);
    }
}

TEST_CASE("GJK polytope boolean and distance against the exact oracle", "[gjk][exact]") {
    // test_gjk.cpp's random hull / box pairs (long-double brute force there), judged exactly here: every boolean,
    // every distance within 1e-9 relative (1e-12 absolute at contact).
    std::mt19937_64 rng(2024);
    const int n = cdkit::test::scaled(300, 30);
    int hits = 0, apart = 0;
    for (int i = 0; i < n; ++i) {
        std::uniform_int_distribution<int> un(8, 40);
        const auto pa_pts = cloud(rng, un(rng), 1.0);
        const auto pb_pts = i % 3 == 0 ? cube(0.4) : cloud(rng, un(rng), 0.6);
        const ConvexPolyhedron<double> a(pa_pts), b(pb_pts);
        std::uniform_real_distribution<double> u(-1.5, 1.5);
        const Transform<double> pa(cdkit::test::random_rotation(rng), Vec3<double>(u(rng), u(rng), u(rng)) * 0.2);
        const Transform<double> pb(cdkit::test::random_rotation(rng), Vec3<double>(u(rng), u(rng), u(rng)));
        const auto x = exact_polytope_pair(a.vertices(), pa, b.vertices(), pb, true);
        REQUIRE_FALSE(x.touching);  // random poses: exact contact has probability 0
        const auto d = gjk_distance(a, pa, b, pb);
        const auto bo = gjk_intersect(a, pa, b, pb);
        INFO("case " << i << ": exact distance " << x.distance << ", depth_inf " << x.depth_inf);
        CHECK(d.colliding == x.intersect);
        CHECK(bo.colliding == x.intersect);
        if (x.intersect) {
            ++hits;
        } else {
            ++apart;
            CHECK(d.status == GjkStatus::separated);
            CHECK(std::abs(d.distance - x.distance) <= 1e-9 * x.distance + 1e-12);
            if (bo.status == GjkStatus::separated)  // the early exit's plane separates, exactly
                CHECK(exact_direction_separates(a.vertices(), pa, b.vertices(), pb, bo.normal));
        }
    }
    CHECK(hits > n / 10);
    CHECK(apart > n / 10);
}

TEST_CASE("hull strict containment is conservative in exact arithmetic", "[gjk][containment][exact]") {
    // ConvexPolyhedron::contains_strictly(p, slack) (the walk through centre–triangle tetrahedra) accepts p only
    // with a ball of radius slack around it inside the hull: at slack 0 exactly inside (the point {p} overlaps the
    // hull with depth, not touching); at slack s its exact L∞ depth is ≥ s (δ ≤ depth_inf). Round and thin hulls,
    // points near the boundary.
    std::mt19937_64 rng(703);
    std::uniform_real_distribution<double> radial(0.5, 1.0), u(0.0, 1.0);
    std::vector<Vec3<double>> round, thin;
    for (int i = 0; i < 200; ++i) {
        const Vec3<double> q = cdkit::test::random_unit(rng) * 0.1 * radial(rng);
        round.push_back(q);
        thin.push_back(Vec3<double>(q[0], q[1], 1e-2 * q[2]));
    }
    const Transform<double> id = at(0);
    for (const auto* pts : {&round, &thin}) {
        const ConvexPolyhedron<double> hull(*pts);
        for (double slack : {0.0, 1e-12, 1e-5}) {
            int accepted = 0, rejected_inside = 0;
            const int points = cdkit::test::scaled(150, 40);
            for (int i = 0; i < points; ++i) {
                const Vec3<double> q = hull.support(cdkit::test::random_unit(rng));
                const double f = i % 2 ? 1 - 1e-3 * u(rng) : u(rng);
                const Vec3<double> p = f * q + 0.01 * hull.bounding_radius() * cdkit::test::random_unit(rng);
                const bool in = hull.contains_strictly(p, slack);
                const auto x = exact_polytope_pair(hull.vertices(), id, {p}, id, true);
                if (in) {
                    ++accepted;
                    INFO((pts == &round ? "round" : "thin") << " hull, slack " << slack << ", point " << p.transpose());
                    CHECK(x.intersect);
                    CHECK_FALSE(x.touching);
                    CHECK(x.depth_inf >= slack);
                } else {
                    rejected_inside += x.intersect && !x.touching && x.depth_inf > 1e-3;
                }
            }
            INFO((pts == &round ? "round" : "thin") << " hull, slack " << slack << ": accepted " << accepted
                                                    << ", rejected though 1e-3 deep " << rejected_inside);
            CHECK(accepted > points / 10);  // not useless: it accepts a share of the points, thin hull included
        }
    }
}
