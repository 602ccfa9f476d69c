#pragma once
// Reference penetration depth of two meshes by sampling translations: for each of many directions u, the smallest
// t ≥ 0 at which B moved by t·u no longer crosses A (march from 0 in steps, then bisect the last step), and the
// minimum over the directions. It only asks a boolean collide() at translated poses, which the caller supplies
// (FCL's in the tests, so the reference shares no code with cdkit's depth query). Resolution: the step (a gap
// shorter than one step can be stepped over) and the direction sampling (the minimum over all directions is at most
// this one's).
#include "cdkit/core/math.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace cdkit::test {

/// Directions spread evenly over the sphere (Fibonacci lattice).
inline std::vector<Vec3<double>> sphere_directions(int n) {
    std::vector<Vec3<double>> out;
    const double golden = 3.14159265358979323846 * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1 - (2 * i + 1) / double(n), r = std::sqrt(std::max(0.0, 1 - z * z));
        out.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
    }
    return out;
}

/// First t in [0, cap] at which !crossing(t·u), to within `tolerance` (bisection); +inf when none up to cap.
/// `crossing(v)`: do the surfaces cross with B moved by v?
template <class Crossing>
double first_gap_along(Crossing&& crossing, const Vec3<double>& u, double step, double cap, double tolerance) {
    if (!crossing(Vec3<double>::Zero())) return 0;
    double lo = 0;
    for (double t = step;; t += step) {
        if (lo > cap) return std::numeric_limits<double>::infinity();
        if (!crossing(t * u)) {
            double hi = t;
            while (hi - lo > tolerance) {
                const double mid = 0.5 * (lo + hi);
                (crossing(mid * u) ? lo : hi) = mid;
            }
            return hi;
        }
        lo = t;
    }
}

struct SampledDepth {
    double depth = std::numeric_limits<double>::infinity();
    Vec3<double> direction = Vec3<double>::Zero();
};

/// The smallest first gap over `directions` (and over `extra` directions tried first, e.g. a query's own normal).
template <class Crossing>
SampledDepth sampled_min_translation(Crossing&& crossing, const std::vector<Vec3<double>>& directions, double step,
                                     double tolerance) {
    SampledDepth best;
    for (const Vec3<double>& u : directions) {
        const double t = first_gap_along(crossing, u, step, best.depth, tolerance);
        if (t < best.depth) best = {t, u};
    }
    return best;
}

}  // namespace cdkit::test
