#pragma once
// Small helpers the stand-alone benchmarks share: a uniformly random rotation and the median of samples.
#include <cdkit/core/math.hpp>

#include <algorithm>
#include <random>
#include <vector>

namespace cdbench {

/// A uniformly random rotation (a normalised Gaussian quaternion).
inline cdkit::Mat3<double> random_rotation(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    return q.normalized().toRotationMatrix();
}

/// The upper median of `v` (0 for no samples).
inline double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace cdbench
