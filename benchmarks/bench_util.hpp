#pragma once
// Small helpers the stand-alone benchmarks share: a uniformly random rotation, random clouds, quantiles and the
// median of samples, and warm best-of-3 timing.
#include <cdkit/core/math.hpp>

#include <algorithm>
#include <chrono>
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

/// The q-quantile of `v` as the sample at rank ⌊q·n⌋ (0 for no samples; q = 0.5 is the upper median).
inline double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size())))];
}

/// Seconds of the fastest of 3 timed runs of `f`, after one untimed run (so the query is measured warm).
template <class F> double warm_best_seconds(F&& f) {
    f();
    double best = 1e300;
    for (int i = 0; i < 3; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
}

/// The upper median of `v` (0 for no samples).
inline double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace cdbench
