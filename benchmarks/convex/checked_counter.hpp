#pragma once
// The checked counter of P3 (issue 37, "Evidence a stranger can check"): seeded random pairs of two qhull hulls
// (200 and 50 points), an ellipsoid, a cylinder and two cones at random poses, six classes in turn (hull–hull,
// hull–ellipsoid, ellipsoid–cylinder, cylinder–hull, cone–cylinder, cone–cone). Each case's cold boolean and
// distance query are judged by oracles that share no code with cdkit's GJK: hull–hull by CGAL's exact polytope
// distance (tests/oracles/exact_polytope.hpp), every curved class by the MPFR referee
// (tests/oracles/curved_referee.hpp), with the band and the judges of tests/narrowphase/convex_hard_cases.hpp.
// Wrong: a boolean contradicting the judge where the exact or certified gap exceeds 1e-10 of the size, or a
// distance off the exact value / the certified interval by more than 1e-9 relative where the distance exceeds
// 1e-6 of the size. Undecided (exactly touching hulls; curved pairs the referee cannot certify) are counted per
// class and printed, never dropped. Besides, as a consistency check only (cdkit judged by cdkit), the answers
// against cdkit's own GJK in long double, as the counter did before the referee. Run by cdkit_bench_convex after
// its timings and alone by cdkit_bench_convex_exact.

namespace cdbench {

/// Runs the first `cases` cases of the seeded corpus (seed 7; case i is the same case in every run built by the same
/// compiler), prints per class the judged, undecided and wrong counts, and returns 0 when no answer is wrong (nor
/// inconsistent with the long-double GJK), 1 otherwise. `csv`: when not null, a file that gets the provenance
/// lines (argc, argv) and one row per class.
int run_checked_counter(long cases, const char* csv = nullptr, int argc = 0, char** argv = nullptr);

}  // namespace cdbench
