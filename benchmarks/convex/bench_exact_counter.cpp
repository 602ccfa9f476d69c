// The checked counter of cdkit_bench_convex alone (checked_counter.hpp: the same seeded hull / ellipsoid /
// cylinder / cone pairs, case i the counter's case i), without P3's timings: hull–hull judged by the exact oracle
// (CGAL), every curved class by the MPFR referee, undecided cases counted per class; non-zero exit on a wrong
// answer. Usage: cdkit_bench_convex_exact [cases=1000000] [--csv FILE] (FILE: provenance, one row per class).
#include "checked_counter.hpp"

#include <cstdlib>
#include <cstring>

int main(int argc, char** argv) {
    long cases = 1000000;
    const char* csv = nullptr;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--csv") == 0 && i + 1 < argc) csv = argv[++i];
        else cases = std::atol(argv[i]);
    }
    return cdbench::run_checked_counter(cases, csv, argc, argv);
}
