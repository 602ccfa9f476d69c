// Issue 5's robustness count: the seeded hard convex pairs of tests/narrowphase/convex_hard_cases.hpp (degenerate
// shapes, size ratios to 1e6, touching / near / nested / coincident placements) through every convex query,
// against long-double GJK; per class pair the failures (see the header) and what is counted besides. Then the
// independent judge (issue 37): every case of two polytopes (boxes, triangles, hulls) judged again by the exact
// oracle (tests/oracles/exact_polytope_cgal.cpp: CGAL's exact QP and LPs on the exactly posed vertices) — wrong
// booleans, undecided (exactly touching) and in-band cases, the distance-error histogram, EPA brackets against the
// exact L∞ depth; cases with a curved shape are counted as not judged exactly. Non-zero exit on any failure or
// exactly wrong boolean. Usage: cdkit_bench_convex_hard [cases=1000000] [seed=1] [exact|noexact]
#include "narrowphase/convex_hard_cases.hpp"
#include "oracles/exact_polytope.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>

using namespace cdkit::test::hard;

int main(int argc, char** argv) {
    const long cases = argc > 1 ? std::atol(argv[1]) : 1000000;
    const unsigned long seed = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 1;
    const auto t0 = std::chrono::steady_clock::now();
    const bool exact_judge = !(argc > 3 && std::strcmp(argv[3], "noexact") == 0);
    ExactOracle oracle;
    if (exact_judge) oracle.pair = &cdkit::test::exact::exact_polytope_pair;
    const auto per_pair = run_hard_cases(cases, seed, oracle);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Counts all;
    std::printf("Hard convex cases (issue 5): %ld seeded cases (seed %lu), %zu class pairs, degenerate shapes, size "
                "ratios to 1e6, touching / near / nested / coincident placements; reference long-double GJK\n",
                cases, seed, per_pair.size());
    std::printf("%-10s %8s %8s %9s | %9s %6s %7s %7s %6s | %8s %8s | %6s %6s %6s %6s\n", "pair", "cases", "decisive",
                "colliding", "nonfinite", "status", "wrongB", "wrongD", "depth", "dist.chk", "dist.out", "EPA",
                "maxit", "degen", "loose");
    for (std::size_t p = 0; p < per_pair.size(); ++p) {
        const Counts& c = per_pair[p];
        std::printf("%-10s %8ld %8ld %9ld | %9ld %6ld %7ld %7ld %6ld | %8ld %8ld | %6ld %6ld %6ld %6ld\n", pair_names[p],
                    c.cases, c.decisive, c.colliding, c.nonfinite, c.bad_status, c.wrong_boolean,
                    c.wrong_distance_status, c.bad_depth, c.distance_checked, c.distance_outliers, c.epa_runs,
                    c.epa_status[3], c.epa_status[4], [&] { long n = 0; for (long x : c.epa_loose) n += x; return n; }());
        all.add(c);
    }
    std::printf("%s", all.first_failures.c_str());
    std::printf("%s", all.first_outliers.c_str());
    std::printf("placements:");
    for (int k = 0; k < placements; ++k) std::printf(" %s %ld", placement_names[k], all.by_placement[std::size_t(k)]);
    std::printf(" (%ld fell back to a random pose: no long-double normal to place along)\n", all.placed_random);
    std::printf("EPA statuses: separated %ld, touching %ld, intersecting %ld, max_iterations %ld, degenerate %ld\n",
                all.epa_status[0], all.epa_status[1], all.epa_status[2], all.epa_status[3], all.epa_status[4]);
    std::printf("EPA separated or touching where h(n) > 1e-9 size, by placement:");
    for (int k = 0; k < placements; ++k) std::printf(" %s %ld", placement_names[k], all.epa_wrong_status[std::size_t(k)]);
    std::printf("\nEPA bracket (depth - depth_lower) / depth > 1e-3, by placement:");
    for (int k = 0; k < placements; ++k) std::printf(" %s %ld", placement_names[k], all.epa_loose[std::size_t(k)]);
    std::printf("\nEPA bracket (depth - depth_lower) / depth, %ld overlaps with h(n) > 1e-9 size (h(n): D's support "
                "along the normal, long double); %ld shallower, %ld of them off h(n) by > 1e-12 size:\n",
                all.epa_checked, all.epa_shallow, all.epa_shallow_off);
    for (std::size_t k = 0; k < all.epa_gap.size(); ++k) {
        const auto& g = all.epa_gap[k];
        std::printf("  %-14s <= 1e-9 %7ld, <= 1e-6 %7ld, <= 1e-3 %7ld, > 1e-3 %7ld; depth off h(n): %ld\n",
                    cdkit::to_string(cdkit::GjkStatus(k)), g[0], g[1], g[2], g[3], g[4]);
    }
    std::printf("hard cases: %ld cases, %ld decisive, failures %ld (non-finite %ld, bad status %ld, wrong boolean %ld, "
                "wrong distance status %ld, bad depth %ld); distances off the certified interval by > 1e-9: %ld of "
                "%ld; slowest case %.0f us; %.1f s\n",
                all.cases, all.decisive, all.failures(), all.nonfinite, all.bad_status, all.wrong_boolean,
                all.wrong_distance_status, all.bad_depth, all.distance_outliers, all.distance_checked,
                all.slowest_us, secs);
    if (exact_judge) {
        const ExactCounts& e = all.exact;
        std::printf("\nExact judge (CGAL Polytope_distance_d and LPs over Gmpzf, exactly posed vertices): per polytope "
                    "pair, wrong booleans / answers, undecided (exactly touching), in band (0 < exact gap or L∞ depth "
                    "<= %.0e size)\n", band_rel);
        std::printf("%-10s %8s %8s %8s %8s %8s %8s %8s %9s\n", "pair", "judged", "apart", "overlap", "touching",
                    "in.band", "answers", "wrongB", "dist.chk");
        for (std::size_t p = 0; p < per_pair.size(); ++p) {
            const ExactCounts& x = per_pair[p].exact;
            if (x.judged == 0) continue;
            std::printf("%-10s %8ld %8ld %8ld %8ld %8ld %8ld %8ld %9ld\n", pair_names[p], x.judged, x.separated,
                        x.overlapping, x.touching, x.in_band, x.answers, x.wrong, x.distances);
        }
        std::printf("%s", e.first_wrong.c_str());
        std::printf("disagreements with the exact answer by |exact gap| / size:");
        for (std::size_t k = 0; k < e.disagree_by_gap.size(); ++k)
            std::printf(" %s %ld", gap_bin_names[k], e.disagree_by_gap[k]);
        std::printf(" (%ld of them inside the band, not failures)\n", e.disagree_band);
        std::printf("separation distances, |d - exact| / max(exact, 1e-9 size), %ld answers:", e.distances);
        for (std::size_t k = 0; k < e.distance_error.size(); ++k)
            std::printf(" %s %ld", error_bin_names[k], e.distance_error[k]);
        std::printf("; worst %.3g\n", e.worst_distance_error);
        std::printf("  of them exact distance > 1e-6 size, |d - exact| / exact, %ld answers:", e.distances_far);
        for (std::size_t k = 0; k < e.distance_error_far.size(); ++k)
            std::printf(" %s %ld", error_bin_names[k], e.distance_error_far[k]);
        std::printf("; worst %.3g\n", e.worst_distance_error_far);
        std::printf("EPA brackets [depth_lower, depth] contradicting the exact L-inf depth bounds: %ld of %ld\n",
                    e.epa_contradicted, e.epa_checked);
        std::printf("exact judge: %ld cases, judged exactly %ld, wrong booleans %ld (of %ld answers), undecided "
                    "(exactly touching) %ld, in band %ld, not judged (curved) %ld\n",
                    all.cases, e.judged, e.wrong, e.answers, e.touching, e.in_band, e.not_judged);
    }
    return all.failures() == 0 && all.exact.wrong == 0 ? 0 : 1;
}
