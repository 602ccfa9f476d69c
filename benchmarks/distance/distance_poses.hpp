#pragma once
// Pose helpers shared by cdkit_bench_distance and cdkit_distance_expansion_cost, so that both query the
// same P2 poses: the mesh scaled into [-1, 1]³ about its box centre, and uniformly random rotations (from a
// normalised Gaussian quaternion, bench_util.hpp) drawn from the benchmark's seeded generator.
#include "../bench_util.hpp"  // random_rotation
#include "cdkit/core/math.hpp"
#include "cdkit/core/mesh.hpp"

#include <random>

namespace cdbench {

inline cdkit::TriangleMesh<double> unit_scaled(cdkit::TriangleMesh<double> m) {
    cdkit::Vec3<double> lo = m.vertices[0], hi = m.vertices[0];
    for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    for (auto& v : m.vertices) v = (v - (lo + hi) / 2) * (2 / (hi - lo).maxCoeff());
    return m;
}

}  // namespace cdbench
