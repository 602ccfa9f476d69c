#pragma once
/// \file Bounding sphere, for sphere trees (Hubbard, "Approximating polyhedra with spheres for time-critical
/// collision detection", ACM TOG 1996). The fit takes the smaller of Ritter's sphere (Ritter, "An efficient
/// bounding sphere", Graphics Gems 1990) and the minimum enclosing ball by Welzl's randomised algorithm in
/// its move-to-front form (Welzl, "Smallest enclosing disks (balls and ellipsoids)", 1991; Gärtner,
/// "Fast and robust smallest enclosing balls", ESA 1999), whose recursion depth is bounded by 4.
/// Whatever centre is chosen, the radius is then recomputed as the largest distance to a vertex, so the
/// ball contains its vertices even when the small linear solves of Welzl's algorithm round badly.
/// The overlap test under a rigid motion moves one centre: it is rotation invariant.

#include "cdkit/bv/fit.hpp"

#include <algorithm>
#include <array>
#include <random>
#include <vector>

namespace cdkit {

namespace detail {
using Vec3d = Eigen::Matrix<double, 3, 1>;
struct Ball {
    Vec3d c = Vec3d::Zero();
    double r2 = -1;  ///< squared radius; negative = empty
    [[nodiscard]] bool holds(const Vec3d& p) const noexcept { return (p - c).squaredNorm() <= r2 * (1 + 1e-12) + 1e-300; }
};

/// The smallest ball with all `n` (≤ 4) points on its boundary (the circumscribed ball of their affine
/// hull); for affinely dependent points, a ball holding them all (never smaller than needed, which is what
/// matters: the radius is recomputed afterwards).
[[nodiscard]] inline Ball ball_through(const Vec3d* p, int n) noexcept {
    Ball b;
    if (n == 0) return b;
    auto farthest_pair = [&] {
        Ball f{p[0], 0};
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j)
                if ((p[i] - p[j]).squaredNorm() / 4 > f.r2) f = {(p[i] + p[j]) / 2, (p[i] - p[j]).squaredNorm() / 4};
        for (int i = 0; i < n; ++i) f.r2 = std::max(f.r2, (p[i] - f.c).squaredNorm());
        return f;
    };
    if (n == 1) return {p[0], 0};
    if (n == 2) return {(p[0] + p[1]) / 2, (p[0] - p[1]).squaredNorm() / 4};
    const Vec3d a = p[1] - p[0], c = p[2] - p[0];
    const Vec3d axc = a.cross(c);
    const double d3 = 2 * axc.squaredNorm();
    if (n == 3) {
        if (!(d3 > 1e-24 * a.squaredNorm() * c.squaredNorm())) return farthest_pair();
        const Vec3d o = (a.squaredNorm() * c.cross(axc) + c.squaredNorm() * axc.cross(a)) / d3;
        return {p[0] + o, o.squaredNorm()};
    }
    const Vec3d e = p[3] - p[0];
    Eigen::Matrix<double, 3, 3> M;
    M.row(0) = 2 * a;
    M.row(1) = 2 * c;
    M.row(2) = 2 * e;
    const double det = M.determinant();
    if (!(std::abs(det) > 1e-12 * 8 * a.norm() * c.norm() * e.norm())) return farthest_pair();
    const Vec3d o = M.inverse() * Vec3d(a.squaredNorm(), c.squaredNorm(), e.squaredNorm());
    return {p[0] + o, o.squaredNorm()};
}

/// Welzl's move-to-front recursion over pts[0, end) with the support set `support` (size s ≤ 4).
inline Ball welzl_mtf(std::vector<Vec3d>& pts, std::size_t end, std::array<Vec3d, 4>& support, int s) {
    Ball b = ball_through(support.data(), s);
    if (s == 4) return b;
    for (std::size_t i = 0; i < end; ++i) {
        if (b.r2 >= 0 && b.holds(pts[i])) continue;
        support[s] = pts[i];
        b = welzl_mtf(pts, i, support, s + 1);
        // Move the point to the front: points that were on the boundary tend to stay there.
        std::rotate(pts.begin(), pts.begin() + std::ptrdiff_t(i), pts.begin() + std::ptrdiff_t(i) + 1);
    }
    return b;
}
}  // namespace detail

/// A ball: centre and radius.
template <class S> struct BoundingSphere {
    using Scalar = S;
    template <class T> using rebind = BoundingSphere<T>;  ///< the same BV in another scalar type
    static constexpr const char* name = "SPHERE";

    Vec3<S> center = Vec3<S>::Zero();
    S radius = S(-1);  ///< negative = empty

    [[nodiscard]] static BoundingSphere empty() noexcept { return {}; }
    [[nodiscard]] bool is_empty() const noexcept { return !(radius >= S(0)); }
    [[nodiscard]] bool is_valid() const noexcept { return center.allFinite() && std::isfinite(radius) && radius >= S(0); }
    [[nodiscard]] S volume() const noexcept {
        return is_empty() ? S(0) : S(4.18879020478639098462) * radius * radius * radius;  // 4π/3 r³
    }
    [[nodiscard]] S surface_area() const noexcept { return is_empty() ? S(0) : S(12.5663706143591729539) * radius * radius; }
    /// Used by the traversal to decide which tree to descend.
    [[nodiscard]] S size() const noexcept { return radius; }
    // No split_axis(): a ball has no preferred direction, so build_bvh splits along the widest extent of the
    // node's triangle centroids instead.
    [[nodiscard]] bool contains(const Vec3<S>& p, S tol = S(0)) const noexcept {
        return (p - center).norm() <= radius + tol;
    }
    /// The smallest ball holding both balls, its radius rounded up so that it holds them in floating point.
    [[nodiscard]] static BoundingSphere merge(const BoundingSphere& a, const BoundingSphere& b) noexcept {
        if (a.is_empty()) return b;
        if (b.is_empty()) return a;
        const Vec3<S> d = b.center - a.center;
        const S dist = d.norm();
        if (dist + b.radius <= a.radius) return a;
        if (dist + a.radius <= b.radius) return b;
        const S r = (dist + a.radius + b.radius) * S(0.5);
        BoundingSphere m;
        m.center = dist > S(0) ? Vec3<S>(a.center + d * ((r - a.radius) / dist)) : a.center;
        const S need = std::max((m.center - a.center).norm() + a.radius, (m.center - b.center).norm() + b.radius);
        m.radius = need * (S(1) + S(8) * std::numeric_limits<S>::epsilon()) + std::numeric_limits<S>::min();
        return m;
    }

    /// The smaller of Ritter's sphere and Welzl's minimum ball of the vertices, padded conservatively.
    [[nodiscard]] static BoundingSphere fit(const TriangleMesh<S>& mesh, TriangleRange tris) {
        if (tris.empty()) return empty();
        std::vector<detail::Vec3d> pts;
        pts.reserve(3 * tris.size());
        for (Index t : tris)
            for (Index v : mesh.triangles[t]) pts.push_back(mesh.vertices[v].template cast<double>());
        // Ritter: a far pair, then grow through one pass.
        auto farthest = [&](const detail::Vec3d& from) {
            std::size_t best = 0;
            double d = -1;
            for (std::size_t i = 0; i < pts.size(); ++i)
                if ((pts[i] - from).squaredNorm() > d) d = (pts[i] - from).squaredNorm(), best = i;
            return pts[best];
        };
        const detail::Vec3d p1 = farthest(pts[0]), p2 = farthest(p1);
        detail::Vec3d c = (p1 + p2) / 2;
        double r = (p2 - p1).norm() / 2;
        for (const auto& p : pts) {
            const double d = (p - c).norm();
            if (d > r) {
                const double nr = (r + d) / 2;
                c += (p - c) * ((nr - r) / d);
                r = nr;
            }
        }
        BoundingSphere best = around(mesh, tris, c.template cast<S>());
        // Welzl on a deterministic shuffle (own Fisher–Yates: std::shuffle's algorithm is unspecified).
        std::mt19937 rng(12345);
        for (std::size_t i = pts.size(); i > 1; --i) std::swap(pts[i - 1], pts[rng() % i]);
        std::array<detail::Vec3d, 4> support;
        const detail::Ball w = detail::welzl_mtf(pts, pts.size(), support, 0);
        if (w.c.allFinite()) {
            const BoundingSphere s = around(mesh, tris, w.c.template cast<S>());
            if (s.radius < best.radius) best = s;
        }
        return best;
    }

    /// The ball with the given centre holding all the triangles' vertices (the radius is the largest
    /// distance as contains() computes it, plus padding for the transformed vertices' rounding).
    [[nodiscard]] static BoundingSphere around(const TriangleMesh<S>& mesh, TriangleRange tris, const Vec3<S>& center) noexcept {
        BoundingSphere s;
        s.center = center;
        S r = 0, magnitude = center.cwiseAbs().maxCoeff();
        for (Index t : tris)
            for (Index v : mesh.triangles[t]) {
                r = std::max(r, (mesh.vertices[v] - center).norm());
                magnitude = std::max(magnitude, mesh.vertices[v].cwiseAbs().maxCoeff());
            }
        s.radius = r + S(4) * detail::fit_padding(magnitude);
        return s;
    }

    /// Per-query data: the rigid motion and the slack for its rounding.
    struct Relative {
        Mat3<S> R;
        Vec3<S> t;
        S t_slack;
    };
    [[nodiscard]] static Relative relative(const Transform<S>& b_to_a) noexcept {
        return {b_to_a.R, b_to_a.t, S(32) * std::numeric_limits<S>::epsilon() * b_to_a.t.cwiseAbs().maxCoeff()};
    }
};

/// Overlap of ball `a` (in A's frame) with ball `b` (in B's frame), `rel` taking B's frame to A's.
/// Conservative: the distance of the centres is compared with the radii plus the rounding of R·c + t.
template <class S>
[[nodiscard]] inline bool overlap(const BoundingSphere<S>& a, const BoundingSphere<S>& b, const typename BoundingSphere<S>::Relative& rel) noexcept {
    const Vec3<S> d = rel.R * b.center + rel.t - a.center;
    const S reach = a.radius + b.radius;
    const S slack = rel.t_slack + S(32) * std::numeric_limits<S>::epsilon() *
                                      (reach + a.center.cwiseAbs().maxCoeff() + b.center.cwiseAbs().maxCoeff());
    const S r = reach + slack;
    return d.squaredNorm() <= r * r;
}

}  // namespace cdkit

// Node layout: centre and radius (a Bvh node adds 8 bytes).
static_assert(sizeof(cdkit::BoundingSphere<double>) == 32 && sizeof(cdkit::BoundingSphere<float>) == 16);
