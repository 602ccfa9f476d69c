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

/// n points at uniformly random directions and radii in [r/2, r] (P3's point clouds; the draws' order is part of
/// the seeded corpora: bench_convex.cpp's counter and bench_exact_counter.cpp replay it call for call).
inline std::vector<cdkit::Vec3<double>> random_cloud(std::mt19937_64& rng, int n, double r) {
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0.5, 1.0);
    std::vector<cdkit::Vec3<double>> p;
    for (int i = 0; i < n; ++i) p.push_back(cdkit::Vec3<double>(g(rng), g(rng), g(rng)).normalized() * r * u(rng));
    return p;
}

/// The upper median of `v` (0 for no samples).
inline double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace cdbench
