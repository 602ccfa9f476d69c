// The checked counter (checked_counter.hpp): the seeded corpus, the independent judges per class, the consistency
// check against cdkit's long-double GJK, the report.
#include "checked_counter.hpp"

#include "../bench_util.hpp"
#include "../provenance.hpp"
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include "narrowphase/convex_hard_cases.hpp"  // the exact and curved judges, their band and bins
#include "narrowphase/convex_reference.hpp"   // certified_interval (the consistency check)
#include "oracles/curved_referee.hpp"
#include "oracles/exact_polytope.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <type_traits>
#include <vector>

namespace cdbench {
namespace {

using namespace cdkit;
using cdkit::test::hard::Answer;
using cdkit::test::hard::CurvedCounts;
using cdkit::test::hard::ExactCounts;
using cdkit::test::hard::ExactOracle;
using cdkit::test::hard::JudgedCounts;
using LD = long double;

constexpr int classes = 6;
constexpr const char* class_names[classes] = {"hull-hull", "hull-ell", "ell-cyl", "cyl-hull", "cone-cyl", "cone-cone"};

struct ClassCounts {
    long cases = 0;
    ExactCounts exact;    ///< hull–hull: CGAL's exact answer
    CurvedCounts curved;  ///< the curved classes: the MPFR referee's certificates
    long wrong_distances = 0;
    int described = 0;  ///< wrong cases printed (the first dozen)
    // Consistency with cdkit's own GJK in long double (not evidence: cdkit judged by cdkit).
    long ld_hits = 0, ld_bool = 0, ld_dist_checked = 0, ld_dist = 0, ld_dist_plain = 0;
    long by_balls = 0, by_containment = 0;  ///< booleans decided by the bounding-ball / containment pre-tests
};

/// Distances off the judge's by more than 1e-9 relative where the judge's distance exceeds 1e-6 of the size (the
/// relative-error domain; below it a distance is judged by the histogram only, as in the hard cases).
long far_distance_failures(const JudgedCounts& j) {
    return j.distance_error_far[3] + j.distance_error_far[4] + j.distance_error_far[5];
}

template <class S> constexpr bool is_hull = std::is_same_v<S, ConvexPolyhedron<double>>;

/// One case of class `k`: cdkit's cold boolean and distance judged by the class's oracle, then compared with the
/// long-double GJK (consistency).
template <class A, class AL, class B, class BL>
void check(const A& a, const AL& al, const B& b, const BL& bl, const Transform<double>& pa,
           const Transform<double>& pb, long i, int k, const ExactOracle& oracle, ClassCounts& c) {
    ++c.cases;
    const auto d = gjk_distance(a, pa, b, pb);
    const auto bo = gjk_intersect(a, pa, b, pb);
    c.by_balls += bo.iterations == 0;
    // the containment certificate (GjkSettings::containment_test): a support point inside the other shape, no simplex
    c.by_containment += bo.status == GjkStatus::intersecting && bo.iterations >= 1 && bo.simplex.size == 0;
    const double size = a.bounding_radius() + b.bounding_radius();
    const std::vector<Answer> answers = {{"cold boolean", bo.colliding, false, bo.status, 0.0},
                                         {"distance", d.colliding, true, d.status, d.distance}};
    JudgedCounts& judged = is_hull<A> && is_hull<B> ? static_cast<JudgedCounts&>(c.exact) : c.curved;
    const long wrong_before = judged.wrong, far_wrong_before = far_distance_failures(judged);
    if constexpr (is_hull<A> && is_hull<B>) {
        // The exact judge alone: the referee's own check against CGAL belongs to the hard cases (its polytope cases).
        ExactOracle exact_only = oracle;
        exact_only.curved = nullptr;
        cdkit::test::hard::judge_exactly(exact_only, a, pa, b, pb, size, cdkit::test::hard::random_pose, answers,
                                         nullptr, c.exact);
    } else {
        // cdkit's normal only seeds the referee's search: its certificates are checked on their own.
        cdkit::test::hard::judge_curved(oracle, a, pa, b, pb, size, cdkit::test::hard::random_pose, answers,
                                        d.normal, c.curved);
    }
    const long far_wrong = far_distance_failures(judged) - far_wrong_before;
    c.wrong_distances += far_wrong;
    if ((judged.wrong > wrong_before || far_wrong > 0) && ++c.described <= 12)
        std::printf("  wrong answer: case %ld (%s): booleans cold %d, distance query %d; distance %.17g, status %s\n",
                    i, class_names[k], int(bo.colliding), int(d.colliding), d.distance, to_string(d.status));

    // Consistency check against cdkit's own long-double GJK (distance relative error ≤ 1e-9 where the distance is
    // ≥ 1e-7; booleans compared where |distance| > 1e-9·0.1).
    GjkSettings<LD> tight;
    tight.rel_tolerance = 1e-16L;
    const auto ref = gjk_distance(al, pa.cast<LD>(), bl, pb.cast<LD>(), nullptr, tight);
    c.ld_hits += ref.colliding;
    if (!ref.colliding && ref.distance > 1e-9L * 0.1L) {
        if (bo.colliding || d.colliding) ++c.ld_bool;
        if (ref.distance > 1e-7L) {
            ++c.ld_dist_checked;
            if (std::abs(LD(d.distance) - ref.distance) > 1e-9L * ref.distance) ++c.ld_dist_plain;
            // the long-double distance clamped into its certified interval (long double too)
            const auto [lower, upper] =
                cdkit::test::certified_interval(al, pa.cast<LD>(), bl, pb.cast<LD>(), ref, d.normal);
            const LD ref_c = std::clamp(ref.distance, lower, upper);
            if (std::abs(LD(d.distance) - ref_c) > 1e-9L * ref_c && ++c.ld_dist <= 5)
                std::printf("  consistency: case %ld (%s): distance %.17g vs long-double %.17Lg (certified-clamped "
                            "%.17Lg), %d it, status %d\n",
                            i, class_names[k], d.distance, ref.distance, ref_c, d.iterations, int(d.status));
        }
    } else if (ref.colliding && !(bo.colliding && d.colliding)) {
        ++c.ld_bool;
    }
}

template <class T> std::vector<T> castv(const std::vector<Vec3<double>>& p) {
    std::vector<T> o;
    for (const auto& x : p) o.push_back(x.template cast<typename T::Scalar>());
    return o;
}

}  // namespace

int run_checked_counter(long cases, const char* csv_path, int argc, char** argv) {
    // The corpus: these draws, in this order, are the counter's since before the judges (bench_util.hpp).
    std::mt19937_64 r2(7);
    const auto p1 = random_cloud(r2, 200, 0.1);
    const auto p2 = random_cloud(r2, 50, 0.1);
    const ConvexPolyhedron<double> h1(p1), h2(p2);
    const ConvexPolyhedron<LD> h1l(castv<Vec3<LD>>(p1)), h2l(castv<Vec3<LD>>(p2));
    const Ellipsoid<double> e(Vec3<double>(0.1, 0.05, 0.08));
    const Ellipsoid<LD> el(Vec3<LD>(0.1L, 0.05L, 0.08L));
    const Cylinder<double> cy(0.05, 0.1);
    const Cylinder<LD> cyl_l(0.05L, 0.1L);
    const Cone<double> co(0.06, 0.09);  // cone–cylinder: the cold boolean's containment test in every round
    const Cone<LD> co_l(0.06L, 0.09L);
    const Cone<double> co2(0.08, 0.05);  // cone–cone: the cones' candidate axes (base, side at an azimuth)
    const Cone<LD> co2_l(0.08L, 0.05L);
    ExactOracle oracle;
    oracle.pair = &cdkit::test::exact::exact_polytope_pair;
    oracle.curved = &cdkit::test::curved::curved_referee;
    oracle.curved_depth = &cdkit::test::curved::depth_exceeds;
    std::array<ClassCounts, classes> per;
    std::uniform_real_distribution<double> t(-0.3, 0.3);
    const auto t0 = std::chrono::steady_clock::now();
    for (long i = 0; i < cases; ++i) {
        // (The three t(r2) draws' order is the compiler's, as it has always been: the corpus is per compiler.)
        const Transform<double> pa(random_rotation(r2), Vec3<double>::Zero());
        const Transform<double> pb(random_rotation(r2), Vec3<double>(t(r2), t(r2), t(r2)));
        const int k = int(i % classes);
        switch (k) {
            case 0: check(h1, h1l, h2, h2l, pa, pb, i, k, oracle, per[0]); break;
            case 1: check(h1, h1l, e, el, pa, pb, i, k, oracle, per[1]); break;
            case 2: check(e, el, cy, cyl_l, pa, pb, i, k, oracle, per[2]); break;
            case 3: check(cy, cyl_l, h2, h2l, pa, pb, i, k, oracle, per[3]); break;
            case 4: check(co, co_l, cy, cyl_l, pa, pb, i, k, oracle, per[4]); break;
            default: check(co2, co2_l, co, co_l, pa, pb, i, k, oracle, per[5]); break;
        }
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    std::printf("\nChecked counter: %ld seeded cases, judged independently of cdkit's GJK: hull-hull by CGAL's exact "
                "polytope distance (undecided: exactly touching), the curved classes by the MPFR referee "
                "(undecided: no certificate). Wrong: a boolean contradicting the judge beyond %.0e of the size, or a "
                "distance off the judge's by > 1e-9 relative where it exceeds 1e-6 of the size\n",
                cases, cdkit::test::hard::band_rel);
    std::printf("%-10s %8s %-7s %8s %8s %9s %8s %7s %7s %7s %8s %8s %7s %10s\n", "class", "cases", "judge", "apart",
                "overlap", "undecided", "answers", "wrongB", "band", "undec.", "dist.chk", "dist.far", "wrongD",
                "worst.far");
    long judged = 0, undecided = 0, answers = 0, wrong = 0, wrong_d = 0, far = 0;
    long ld_bool = 0, ld_dist = 0, ld_dist_plain = 0, ld_checked = 0, hits = 0, by_balls = 0, by_containment = 0;
    for (int k = 0; k < classes; ++k) {
        const ClassCounts& c = per[std::size_t(k)];
        const bool exact = k == 0;
        const JudgedCounts& j = exact ? static_cast<const JudgedCounts&>(c.exact) : c.curved;
        const long undec = exact ? c.exact.touching : c.curved.undecided;
        const long undec_band = exact ? 0 : c.curved.disagree_undecided;
        std::printf("%-10s %8ld %-7s %8ld %8ld %9ld %8ld %7ld %7ld %7ld %8ld %8ld %7ld %10.3g\n", class_names[k],
                    c.cases, exact ? "exact" : "referee", j.separated, j.overlapping, undec, j.answers, j.wrong,
                    j.disagree_band, undec_band, j.distances, j.distances_far, c.wrong_distances,
                    j.worst_distance_error_far);
        judged += j.judged, undecided += undec, answers += j.answers, wrong += j.wrong;
        wrong_d += c.wrong_distances, far += j.distances_far;
        ld_bool += c.ld_bool, ld_dist += c.ld_dist, ld_dist_plain += c.ld_dist_plain, ld_checked += c.ld_dist_checked;
        hits += c.ld_hits, by_balls += c.by_balls, by_containment += c.by_containment;
    }
    for (const ClassCounts& c : per) std::printf("%s%s%s", c.exact.first_wrong.c_str(), c.curved.first_wrong.c_str(),
                                                 c.curved.first_undecided.c_str());
    std::printf("checked counter: %ld cases, judged %ld, undecided %ld, wrong booleans %ld (of %ld answers), wrong "
                "distances %ld (of %ld far answers)  (%.1f s)\n",
                cases, judged, undecided, wrong, answers, wrong_d, far, secs);
    std::printf("consistency check (cdkit's own GJK in long double, not evidence): %ld colliding, booleans "
                "inconsistent %ld, distance checks %ld with rel. error > 1e-9: %ld against the certified-clamped "
                "long-double distance (%ld against the plain one); booleans decided by the bounding balls: %ld, by "
                "containment: %ld\n",
                hits, ld_bool, ld_checked, ld_dist, ld_dist_plain, by_balls, by_containment);

    if (csv_path != nullptr) {
        if (std::FILE* f = std::fopen(csv_path, "w")) {
            write_provenance(f, argc, argv);
            std::fprintf(f, "# wall: %.0f s\n", secs);
            std::fprintf(f, "class,cases,judge,apart,overlapping,undecided,answers,wrong_booleans,"
                            "disagreements_in_band,disagreements_undecided,distance_answers,far_answers,"
                            "wrong_distances,worst_far_err,ld_booleans_inconsistent,ld_distances_inconsistent\n");
            for (int k = 0; k < classes; ++k) {
                const ClassCounts& c = per[std::size_t(k)];
                const bool exact = k == 0;
                const JudgedCounts& j = exact ? static_cast<const JudgedCounts&>(c.exact) : c.curved;
                std::fprintf(f, "%s,%ld,%s,%ld,%ld,%ld,%ld,%ld,%ld,%ld,%ld,%ld,%ld,%.1e,%ld,%ld\n", class_names[k],
                             c.cases, exact ? "exact" : "referee", j.separated, j.overlapping,
                             exact ? c.exact.touching : c.curved.undecided, j.answers, j.wrong, j.disagree_band,
                             exact ? 0L : c.curved.disagree_undecided, j.distances, j.distances_far,
                             c.wrong_distances, j.worst_distance_error_far, c.ld_bool, c.ld_dist);
            }
            double worst = 0;
            long apart = 0, overlapping = 0, band = 0, undec_band = 0, distances = 0;
            for (int k = 0; k < classes; ++k) {
                const ClassCounts& c = per[std::size_t(k)];
                const JudgedCounts& j = k == 0 ? static_cast<const JudgedCounts&>(c.exact) : c.curved;
                worst = std::max(worst, j.worst_distance_error_far);
                apart += j.separated, overlapping += j.overlapping, band += j.disagree_band;
                undec_band += k == 0 ? 0 : c.curved.disagree_undecided;
                distances += j.distances;
            }
            std::fprintf(f, "all,%ld,both,%ld,%ld,%ld,%ld,%ld,%ld,%ld,%ld,%ld,%ld,%.1e,%ld,%ld\n", cases, apart,
                         overlapping, undecided, answers, wrong, band, undec_band, distances, far, wrong_d, worst,
                         ld_bool, ld_dist);
            std::fclose(f);
        } else {
            std::fprintf(stderr, "cannot write %s\n", csv_path);
            return 2;
        }
    }
    return wrong == 0 && wrong_d == 0 && ld_bool == 0 && ld_dist == 0 ? 0 : 1;
}

}  // namespace cdbench
