// The curved-shape referee (tests/oracles/curved_referee.hpp, issue 37 "independent oracles"), first on pairs whose
// distance has a closed form, then as the judge of the hard-case corpus's curved pairs (convex_hard_cases.hpp, the
// generator of test_gjk_hard_cases.cpp and cdkit_bench_convex_hard): no boolean may contradict a certificate
// beyond the band, every distance is judged against the certified interval, and the referee must decide nearly
// every case (so a regression that leaves it undecided fails here instead of passing by judging nothing).
#include <catch2/catch.hpp>

#include "convex_hard_cases.hpp"
#include "oracles/curved_referee.hpp"
#include "test_common.hpp"

#include <cstdio>

using namespace cdkit;
using namespace cdkit::test::curved;

namespace {

Transform<double> at(double x, double y, double z) { return {Mat3<double>::Identity(), Vec3<double>(x, y, z)}; }

/// The referee certifies separation with an interval holding `exact` (and not wider than 1e-15 of it).
void check_apart(const ShapeSpec& a, const Transform<double>& pa, const ShapeSpec& b, const Transform<double>& pb,
                 double exact) {
    const CurvedAnswer r = curved_referee(a, pa, b, pb, Vec3<double>::Zero());
    INFO("exact " << exact << ", lower " << r.lower << ", upper " << r.upper << ", rounds " << r.iterations);
    REQUIRE(r.verdict == Verdict::separated);
    CHECK(r.lower > 0);
    CHECK(r.lower <= exact);
    CHECK(r.upper >= exact);
    CHECK(r.upper - r.lower <= 1e-15 * exact);
}

/// The referee certifies an overlap, its depth bound no deeper than `depth`.
void check_overlap(const ShapeSpec& a, const Transform<double>& pa, const ShapeSpec& b, const Transform<double>& pb,
                   double depth) {
    const CurvedAnswer r = curved_referee(a, pa, b, pb, Vec3<double>::Zero());
    INFO("depth " << depth << ", bound " << r.depth_lower << ", rounds " << r.iterations);
    REQUIRE(r.verdict == Verdict::intersecting);
    CHECK(r.depth_lower > 0);
    CHECK(r.depth_lower <= depth);
}

}  // namespace

TEST_CASE("curved referee: closed-form distances and overlaps", "[gjk][curved][oracle]") {
    const ShapeSpec ball{ShapeKind::sphere, 1.0}, small{ShapeKind::sphere, 0.5};
    // Centres 1.5 + g apart: the difference t − 1.5 is exact in double (Sterbenz), so is the distance.
    for (double g : {1.0, 1e-3, 1e-9, 1e-13}) {
        const double t = 1.5 + g;
        check_apart(ball, at(0, 0, 0), small, at(t, 0, 0), t - 1.5);
        check_apart(ball, at(0, 0, 0), small, at(-t, 0, 0), t - 1.5);
        check_overlap(ball, at(0, 0, 0), small, at(1.5 - g, 0, 0), 1.5 - (1.5 - g));
    }
    // Parallel capsules along z, radii 0.2 and 0.3, their axes x apart: distance x − 0.5 wherever they face.
    const ShapeSpec cap_a{ShapeKind::capsule, 0.2, 1.0}, cap_b{ShapeKind::capsule, 0.3, 0.4};
    for (double g : {0.25, 1e-6, 1e-12}) {
        const double x = 0.5 + g;
        check_apart(cap_a, at(0, 0, 0), cap_b, at(x, 0, 0.3), x - 0.5);
        check_overlap(cap_a, at(0, 0, 0), cap_b, at(0.5 - g, 0, 0.3), 0.5 - (0.5 - g));
    }
    // A box and a ball: across a face (distance t − 1.5) and off a corner (|corner − centre| − r, in long double).
    const ShapeSpec box{ShapeKind::box, 1, 1, 1};
    for (double g : {0.5, 1e-10}) {
        const double t = 1.5 + g;
        check_apart(box, at(0, 0, 0), small, at(t, 0.3, -0.2), t - 1.5);
        check_overlap(box, at(0, 0, 0), small, at(1.5 - g, 0.3, -0.2), 1.5 - (1.5 - g));
    }
    {
        const double c = 1.5;
        const long double exact = std::sqrt(3.0L) * 0.5L - 0.5L;
        check_apart(box, at(0, 0, 0), small, at(c, c, c), double(exact));
    }
    // A cone's apex (z = +h) under a box's face; a cylinder's cap on it; an ellipsoid's pole on it; two rounded boxes
    // face to face; a hull (a tetrahedron) and a ball.
    const ShapeSpec cone{ShapeKind::cone, 0.5, 0.75}, cyl{ShapeKind::cylinder, 0.3, 0.5},
        ell{ShapeKind::ellipsoid, 0.3, 0.2, 0.125}, rbox{ShapeKind::rounded_box, 0.5, 0.25, 0.25, 0.25};
    for (double g : {0.125, 1e-11}) {
        check_apart(cone, at(0, 0, 0), box, at(0.2, -0.1, 1.75 + g), (1.75 + g) - 1.75);
        check_apart(cyl, at(0, 0, 0), box, at(0.4, -0.3, 1.5 + g), (1.5 + g) - 1.5);
        check_apart(ell, at(0, 0, 0), box, at(0.1, 0.1, 1.125 + g), (1.125 + g) - 1.125);
        check_apart(rbox, at(0, 0, 0), rbox, at(1.5 + g, 0.125, 0), (1.5 + g) - 1.5);
        check_overlap(cone, at(0, 0, 0), box, at(0.2, -0.1, 1.75 - g), 1.75 - (1.75 - g));
        check_overlap(rbox, at(0, 0, 0), rbox, at(1.5 - g, 0.125, 0), 1.5 - (1.5 - g));
    }
    const std::vector<Vec3<double>> tet = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const ShapeSpec hull{ShapeKind::hull, 0, 0, 0, 0, &tet};
    check_apart(hull, at(0, 0, 0), small, at(0.25, 0.25, -0.5 - 1e-9), (0.5 + 1e-9) - 0.5);
    // Coincident and nested shapes: deep overlaps (the origin of B − A at a centre of symmetry, where the search's
    // simplex passes through it and must be completed).
    check_overlap(cap_a, at(0.3, 0.2, 0.1), cap_a, at(0.3, 0.2, 0.1), 0.2);
    check_overlap(ell, at(0, 0, 0), ell, at(0, 0, 0), 0.125);
    check_overlap(box, at(0, 0, 0), small, at(0, 0, 0), 1.5);
    // Two equal cones at one pose: B − A is symmetric about the origin and its rim-to-rim support points are
    // coplanar through it, which left 1.4 % of such pairs (random rotations, no hint) undecided before the search
    // fell back to six points just off the origin (4 of the 1M hard cases: results/exact_convex_judge.csv).
    {
        std::mt19937_64 rng(7);
        std::normal_distribution<double> gauss;
        int undecided = 0;
        for (int i = 0; i < 300; ++i) {
            const ShapeSpec c{ShapeKind::cone, 0.097949, 0.050251};
            Eigen::Quaterniond q(gauss(rng), gauss(rng), gauss(rng), gauss(rng));
            q.normalize();
            const Transform<double> p(q.toRotationMatrix(), Vec3<double>(gauss(rng), gauss(rng), gauss(rng)));
            undecided += curved_referee(c, p, c, p, Vec3<double>::Zero()).verdict != Verdict::intersecting;
        }
        CHECK(undecided == 0);
    }
    // Rigid motion: the same ball pair under a rotation keeps its distance (to the rotation's rounding).
    {
        const Mat3<double> rot = Eigen::AngleAxisd(0.7, Vec3<double>(1, 2, 3).normalized()).toRotationMatrix();
        const Vec3<double> c(0.3, -0.2, 0.9);
        const Transform<double> pa(rot, c), pb(rot, c + rot * Vec3<double>(1.5 + 1e-6, 0, 0));
        const CurvedAnswer r = curved_referee(ball, pa, small, pb, Vec3<double>::Zero());
        REQUIRE(r.verdict == Verdict::separated);
        CHECK(std::abs(r.lower - 1e-6) <= 1e-15);
    }
    // The depth test: balls overlapping by 1e-3 hold a ball of radius 1e-4 in B − A, not one of radius 1e-3.
    CHECK(depth_exceeds(ball, at(0, 0, 0), small, at(1.5 - 1e-3, 0, 0), 1e-4) == 1);
    CHECK(depth_exceeds(ball, at(0, 0, 0), small, at(1.5 - 1e-3, 0, 0), 1e-3) == -1);
    // The support points lie on the shapes: a ball's along the direction, a box's at a corner.
    const Vec3<double> p = support_point(small, at(1, 2, 3), Vec3<double>(0, 0, -2));
    CHECK(p.isApprox(Vec3<double>(1, 2, 2.5)));
    CHECK(support_point(box, at(0, 0, 0), Vec3<double>(1, -1, 1)).isApprox(Vec3<double>(1, -1, 1)));
}

TEST_CASE("hard convex cases: curved pairs judged by the referee", "[gjk][hard][curved][oracle]") {
    using namespace cdkit::test::hard;
    const long cases = cdkit::test::scaled(10000, 300);
    ExactOracle oracle;
    oracle.curved = &curved_referee;
    oracle.curved_depth = &depth_exceeds;
    const auto per_pair = run_hard_cases(cases, 1, oracle);
    Counts all;
    for (const Counts& c : per_pair) all.add(c);
    const CurvedCounts& v = all.curved;
    std::string histogram;
    for (std::size_t k = 0; k < v.distance_error.size(); ++k)
        histogram += std::string(" ") + error_bin_names[k] + " " + std::to_string(v.distance_error[k]);
    std::string far;
    for (std::size_t k = 0; k < v.distance_error_far.size(); ++k)
        far += std::string(" ") + error_bin_names[k] + " " + std::to_string(v.distance_error_far[k]);
    std::printf("curved referee on %ld hard cases: judged %ld (apart %ld, overlapping %ld), undecided %ld, wrong "
                "booleans %ld of %ld answers, disagreements in band %ld, undecided against the band %ld; distances "
                "off the certified interval (%ld):%s; worst %.3g; far (%ld):%s, worst %.3g\n",
                all.cases, v.judged, v.separated, v.overlapping, v.undecided, v.wrong, v.answers, v.disagree_band,
                v.disagree_undecided, v.distances, histogram.c_str(), v.worst_distance_error, v.distances_far,
                far.c_str(), v.worst_distance_error_far);
    INFO(v.first_wrong << v.first_undecided);
    // The corpus's 14 curved class pairs of 20, every one given to the referee.
    long curved_cases = 0;
    for (std::size_t p = 0; p < per_pair.size(); ++p) curved_cases += per_pair[p].curved.judged > 0 ? per_pair[p].cases : 0;
    CHECK(v.judged == curved_cases);
    CHECK(curved_cases >= cases * 14 / 20);
    // Not one boolean contradicts a certificate beyond the band (1e-10 of the size, docs/convex.md "Certified
    // separation").
    CHECK(v.wrong == 0);
    // The referee decides: both verdicts occur often, undecided cases are rare (seed 1: see docs/robustness.md).
    CHECK(v.separated > v.judged / 4);
    CHECK(v.overlapping > v.judged / 4);
    CHECK(v.undecided * 100 <= v.judged);
    CHECK(v.distances > v.judged / 4);
    // Far apart (certified distance > 1e-6 of the size) every distance lies within 1e-9 of its certified interval:
    // docs/convex.md's bound for separated curved pairs ("within 1e-9 of a certified interval").
    CHECK(v.distances_far > v.distances / 3);
    CHECK(v.worst_distance_error_far <= 1e-9);
    // The certificates are tight: no interval wider than 1e-15 of its distance (or of 1e-9 of the size).
    CHECK(v.widest_interval <= 1e-15);
}
