#pragma once
// cdkit_bench_ist --out-of-sample: the calibrated penetration volume's error where the depth calibration's
// strength α was not derived (see out_of_sample.cpp).
#include <string>
#include <vector>

namespace cdbench {

struct OutOfSampleOptions {
    std::vector<std::string> meshes;           // closed meshes (each scaled into [-1, 1]^3)
    std::vector<std::size_t> counts;           // sphere counts
    std::vector<double> depths{0.01, 0.05, 0.2};  // |δ|, fractions of the bounding box's diagonal
    int poses = 8;                             // P2 directions per mesh (each evaluated at every δ)
    int line_grid = 256;                       // reference: lines per side, 8 jittered passes
    std::string csv;                           // results file (provenance first), empty: none
};

/// Runs the comparison, prints its tables; returns the process exit code.
int run_out_of_sample(const OutOfSampleOptions& options, int argc, char** argv);

}  // namespace cdbench
