#pragma once
/// \file Reference volume of the intersection of two closed meshes, vol(A ∩ B), by integration along lines.
///
/// The estimate the penetration volume of inner sphere trees is measured against. Lines parallel to the x
/// axis cross both meshes; along each line the inside of a mesh is a union of intervals found exactly from
/// its crossings (InsideTest::line_crossings: exact predicates decide which triangles a line crosses and with
/// which orientation), so the length of A ∩ B on the line is exact up to the rounding of the crossings'
/// x values. Only the two remaining dimensions are sampled: one line per cell of an n × n grid over the (y, z)
/// overlap of the meshes' bounding boxes, at a uniformly random point of its cell (stratified, "jittered"
/// sampling). Each pass is an unbiased estimate; the result is the mean of independent passes and its
/// standard error is their spread over √passes. A line that grazes an edge or a vertex (probability zero,
/// but possible on meshes with coordinates on a lattice) is redrawn in its cell.
///
/// Why not plain Monte Carlo in 3D: with uniform samples in the boxes' overlap the relative standard error
/// falls as 1/√N and is large when the meshes fill little of the box (2M samples left 1.9% on the dragon,
/// as large as the 2% target being judged). Integrating one dimension exactly and stratifying the other two
/// removes most of that variance (Monte Carlo integration with stratification and dimension reduction:
/// Press & Farrar, "Recursive stratified sampling for multidimensional Monte Carlo integration", Computers in
/// Physics 4(2), 1990; the line-integral form is the ray-casting volume estimate of solid modelling).
///
/// Both functions are const and thread-safe (independent calls on shared InsideTest objects are fine).

#include "cdkit/core/error.hpp"
#include "cdkit/core/math.hpp"
#include "cdkit/ist/closed_mesh.hpp"
#include "cdkit/ist/inside_test.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace cdkit {

struct IntersectionVolumeOptions {
    int grid = 256;            ///< lines per side of the (y, z) grid of one pass, in [1, 16384]
    int passes = 4;            ///< independent jittered passes (≥ 2 gives a standard error), in [1, 1024]
    std::uint64_t seed = 1;    ///< seed of the jitter: the same seed gives the same bits
};

struct IntersectionVolume {
    double volume = 0;          ///< mean of the passes' estimates of vol(A ∩ B)
    double standard_error = 0;  ///< of the mean, from the spread of the passes (0 with one pass)
    long lines = 0;             ///< lines cast (passes · grid², redraws not counted)
    long redrawn = 0;           ///< lines that grazed an edge or vertex and were drawn again
};

namespace detail {

/// Intervals of the line where the winding number is non-zero, from its crossings (t, sign), sorted in
/// ascending order and disjoint. The winding number at x is the sum of the signs of the crossings with t > x.
inline void inside_intervals(std::vector<std::pair<double, int>>& crossings,
                             std::vector<std::pair<double, double>>& out) {
    out.clear();
    std::sort(crossings.begin(), crossings.end(), [](const auto& p, const auto& q) { return p.first > q.first; });
    int w = 0;
    double upper = 0;
    for (const auto& [t, s] : crossings) {   // from +∞ downwards
        const int next = w + s;
        if (w == 0 && next != 0) upper = t;                     // entering the solid (going down)
        if (w != 0 && next == 0 && t < upper) out.emplace_back(t, upper);
        w = next;
    }
    std::reverse(out.begin(), out.end());
}

/// Total length of the intersection of two sorted lists of disjoint intervals.
[[nodiscard]] inline double overlap_length(const std::vector<std::pair<double, double>>& a,
                                           const std::vector<std::pair<double, double>>& b) noexcept {
    double len = 0;
    std::size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        const double lo = std::max(a[i].first, b[j].first), hi = std::min(a[i].second, b[j].second);
        if (hi > lo) len += hi - lo;
        (a[i].second < b[j].second ? i : j) += 1;
    }
    return len;
}

inline void bounding_box(const TriangleMesh<double>& m, Vec3<double>& lo, Vec3<double>& hi) {
    lo = Vec3<double>::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Triangle& t : m.triangles)
        for (Index v : t) lo = lo.cwiseMin(m.vertices[v]), hi = hi.cwiseMax(m.vertices[v]);
}

}  // namespace detail

/// vol(A ∩ B) of two closed meshes given in one frame, as InsideTest objects (see the file comment). The
/// meshes' closedness is the caller's concern (check_closed_mesh()); the other overload checks it.
/// Throws cdkit::Error for options out of range, for non-finite vertex coordinates, or when a line keeps
/// grazing edges after 64 redraws.
[[nodiscard]] inline IntersectionVolume mesh_intersection_volume(const InsideTest& a, const InsideTest& b,
                                                                 const IntersectionVolumeOptions& options = {}) {
    if (options.grid < 1 || options.grid > 16384 || options.passes < 1 || options.passes > 1024)
        throw Error("mesh_intersection_volume", "options",
                    "grid must be in [1, 16384] and passes in [1, 1024]; got grid " + std::to_string(options.grid) +
                        ", passes " + std::to_string(options.passes));
    IntersectionVolume out;
    if (a.mesh().triangles.empty() || b.mesh().triangles.empty()) return out;
    Vec3<double> alo, ahi, blo, bhi;
    detail::bounding_box(a.mesh(), alo, ahi);
    detail::bounding_box(b.mesh(), blo, bhi);
    const std::string non_finite = "non-finite vertex coordinates (NaN or Inf)";
    if (!(alo.allFinite() && ahi.allFinite())) throw Error(a.mesh().source, "vertices", non_finite);
    if (!(blo.allFinite() && bhi.allFinite())) throw Error(b.mesh().source, "vertices", non_finite);
    const double y0 = std::max(alo.y(), blo.y()), y1 = std::min(ahi.y(), bhi.y());
    const double z0 = std::max(alo.z(), blo.z()), z1 = std::min(ahi.z(), bhi.z());
    if (!(y1 > y0) || !(z1 > z0) || !(std::min(ahi.x(), bhi.x()) > std::max(alo.x(), blo.x()))) return out;

    const int n = options.grid;
    const double dy = (y1 - y0) / n, dz = (z1 - z0) / n;
    std::mt19937_64 rng(options.seed);
    std::uniform_real_distribution<double> u01(0, 1);
    std::vector<std::pair<double, int>> ca, cb;
    std::vector<std::pair<double, double>> ia, ib;
    std::vector<double> pass_volume;
    for (int p = 0; p < options.passes; ++p) {
        double sum = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                for (int attempt = 0;; ++attempt) {
                    if (attempt == 64)
                        throw Error(a.mesh().source + " / " + b.mesh().source, "lines",
                                    "every line drawn in a (y, z) cell grazes an edge or a vertex");
                    const double y = y0 + (i + u01(rng)) * dy, z = z0 + (j + u01(rng)) * dz;
                    if (a.line_crossings(y, z, ca) && b.line_crossings(y, z, cb)) break;
                    ++out.redrawn;
                }
                if (ca.empty() || cb.empty()) continue;
                detail::inside_intervals(ca, ia);
                detail::inside_intervals(cb, ib);
                sum += detail::overlap_length(ia, ib);
            }
        pass_volume.push_back(sum * dy * dz);
    }
    out.lines = long(options.passes) * n * n;
    double mean = 0;
    for (double v : pass_volume) mean += v;
    mean /= double(pass_volume.size());
    out.volume = mean;
    if (pass_volume.size() > 1) {
        double ss = 0;
        for (double v : pass_volume) ss += (v - mean) * (v - mean);
        out.standard_error = std::sqrt(ss / double(pass_volume.size() - 1) / double(pass_volume.size()));
    }
    return out;
}

/// vol(A ∩ B) for meshes `a` at `pose_a` and `b` at `pose_b`. Both must be closed, manifold and consistently
/// oriented (check_closed_mesh(); throws cdkit::Error naming the mesh otherwise), and the poses rigid motions
/// (Transform::is_valid()). The integration runs in A's frame: B's vertices are moved there. For many poses
/// of the same meshes, build the InsideTest of A once and call the other overload.
[[nodiscard]] inline IntersectionVolume mesh_intersection_volume(const TriangleMesh<double>& a,
                                                                 const Transform<double>& pose_a,
                                                                 const TriangleMesh<double>& b,
                                                                 const Transform<double>& pose_b,
                                                                 const IntersectionVolumeOptions& options = {}) {
    (void)check_closed_mesh(a);
    (void)check_closed_mesh(b);
    if (!pose_a.is_valid() || !pose_b.is_valid())
        throw Error(a.source + " / " + b.source, "pose", "a pose is not a rigid motion (NaN/Inf, scale, shear or reflection)");
    const Transform<double> b_to_a = pose_a.inverse() * pose_b;
    TriangleMesh<double> moved = b;
    for (auto& v : moved.vertices) v = b_to_a * v;
    return mesh_intersection_volume(InsideTest(a), InsideTest(std::move(moved)), options);
}

}  // namespace cdkit
