#pragma once
/// \file The point of least norm in the convex hull of a few 3D vectors. For a maximin of smooth functions
/// (the packing's clearance: the least distance to the surface and the placed spheres) it is the direction
/// of steepest ascent of the nearly active ones, and zero at a local maximum (V. F. Demyanov, V. N.
/// Malozemov, "Introduction to Minimax", Wiley 1974, ch. 2).

#include "cdkit/core/math.hpp"

#include <limits>
#include <vector>

namespace cdkit::detail {

/// The point of least norm in the convex hull of v (a handful of vectors in 3D), by trying the hull's
/// vertices, edges and triangles: the answer z is the candidate of least norm with z·v_i ≥ |z|² for every i
/// (no vector points below it); when no candidate passes, the origin lies inside the hull and z = 0.
[[nodiscard]] inline Vec3<double> min_norm_in_hull(const std::vector<Vec3<double>>& v) {
    const std::size_t n = v.size();
    Vec3<double> best = Vec3<double>::Zero();
    double best2 = std::numeric_limits<double>::infinity();
    auto consider = [&](const Vec3<double>& z) {
        const double z2 = z.squaredNorm();
        if (z2 >= best2) return;
        const double slack = 1e-12 + 1e-9 * z2;
        for (const Vec3<double>& w : v)
            if (z.dot(w) < z2 - slack) return;
        best = z, best2 = z2;
    };
    for (std::size_t i = 0; i < n; ++i) {
        consider(v[i]);
        for (std::size_t j = i + 1; j < n; ++j) {
            const Vec3<double> e = v[j] - v[i];
            const double ee = e.squaredNorm();
            if (ee > 0) {
                const double t = -v[i].dot(e) / ee;
                if (t > 0 && t < 1) consider(v[i] + t * e);
            }
            for (std::size_t k = j + 1; k < n; ++k) {
                // Origin projected onto the plane of the triangle, in barycentric coordinates.
                const Vec3<double> e1 = v[j] - v[i], e2 = v[k] - v[i];
                const double a11 = e1.dot(e1), a12 = e1.dot(e2), a22 = e2.dot(e2);
                const double b1 = -v[i].dot(e1), b2 = -v[i].dot(e2);
                const double det = a11 * a22 - a12 * a12;
                if (!(det > 1e-14 * a11 * a22)) continue;
                const double s = (b1 * a22 - b2 * a12) / det, t = (a11 * b2 - a12 * b1) / det;
                if (s > 0 && t > 0 && s + t < 1) consider(v[i] + s * e1 + t * e2);
            }
        }
    }
    return best2 < std::numeric_limits<double>::infinity() ? best : Vec3<double>::Zero();
}

}  // namespace cdkit::detail
