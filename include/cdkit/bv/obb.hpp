#pragma once
/// \file Oriented bounding box fitted by principal component analysis of the triangles (continuous, area
/// weighted covariance: Gottschalk, Lin, Manocha, "OBBTree", SIGGRAPH 1996) — a single triangle in its own
/// plane instead (triangle_frame) — overlap by the 15-axis separating-axis test.

#include "cdkit/bv/detail/separating_axis.hpp"
#include "cdkit/bv/fit.hpp"
#include "cdkit/bv/triangle_moments.hpp"

#include <Eigen/Eigenvalues>

#include <limits>
#include <optional>

namespace cdkit {

template <class S> struct Obb {
    using Scalar = S;
    template <class T> using rebind = Obb<T>;  ///< the same BV in another scalar type
    static constexpr const char* name = "OBB";

    Mat3<S> axes = Mat3<S>::Identity();  ///< columns: the box's unit axes, a right-handed rotation
    Vec3<S> center = Vec3<S>::Zero();
    Vec3<S> half = Vec3<S>::Constant(S(-1));  ///< half extents along the axes; negative = empty

    [[nodiscard]] static Obb empty() noexcept { return {}; }
    [[nodiscard]] bool is_empty() const noexcept { return (half.array() < S(0)).any(); }
    [[nodiscard]] bool is_valid() const noexcept {
        return axes.allFinite() && center.allFinite() && half.allFinite() && (half.array() >= S(0)).all();
    }
    [[nodiscard]] S volume() const noexcept { return is_empty() ? S(0) : S(8) * half.prod(); }
    [[nodiscard]] S surface_area() const noexcept {
        return is_empty() ? S(0) : S(8) * (half.x() * half.y() + half.y() * half.z() + half.z() * half.x());
    }
    [[nodiscard]] S size() const noexcept { return half.x() + half.y() + half.z(); }
    [[nodiscard]] Vec3<S> split_axis() const noexcept {
        int k;
        half.maxCoeff(&k);
        return axes.col(k);
    }
    [[nodiscard]] bool contains(const Vec3<S>& p, S tol = S(0)) const noexcept {
        return ((axes.transpose() * (p - center)).cwiseAbs().array() <= half.array() + tol).all();
    }

    /// PCA frame of the triangles (area-weighted second moments; vertex moments when all have zero area),
    /// then the tight box in that frame, padded conservatively.
    [[nodiscard]] static Obb fit(const TriangleMesh<S>& mesh, TriangleRange tris) noexcept {
        if (tris.empty()) return empty();
        if (tris.size() == 1)
            if (const auto frame = triangle_frame(mesh, tris[0])) return fit_in_frame(mesh, tris, *frame);
        return fit_in_frame(mesh, tris, principal_frame(local_covariance(mesh, tris)));
    }

    /// The frame of the smallest box around one triangle: its normal, and in its plane the smallest-area
    /// enclosing rectangle, which has a side along one of the edges (Freeman, Shapira, "Determining the
    /// minimum-area encasing rectangle for an arbitrary closed curve", CACM 1975) — flat, and tighter and
    /// cheaper than the triangle's PCA frame (no eigen decomposition: half of a tree's nodes are such leaves).
    /// Empty for a zero-area triangle.
    [[nodiscard]] static std::optional<Mat3<S>> triangle_frame(const TriangleMesh<S>& mesh, Index t) noexcept {
        using V = Eigen::Matrix<double, 3, 1>;
        const auto& tri = mesh.triangles[t];
        const V p[3] = {mesh.vertices[tri[0]].template cast<double>(), mesh.vertices[tri[1]].template cast<double>(),
                        mesh.vertices[tri[2]].template cast<double>()};
        // Eigen's normalized() leaves a zero vector as it is: test the lengths, not the results.
        const V c = (p[1] - p[0]).cross(p[2] - p[0]);
        if (!(c.squaredNorm() > 0) || !c.allFinite()) return std::nullopt;
        const V n = c / c.norm();
        double best = std::numeric_limits<double>::infinity();
        V best_u = V::Zero();
        for (int i = 0; i < 3; ++i) {
            const V e = p[(i + 1) % 3] - p[i];
            if (!(e.squaredNorm() > 0)) continue;
            const V u = e / e.norm();
            const V v = n.cross(u);
            double lo_u = 0, hi_u = 0, lo_v = 0, hi_v = 0;  // relative to p[i]
            for (const V& q : p) {
                const double a = (q - p[i]).dot(u), b = (q - p[i]).dot(v);
                lo_u = std::min(lo_u, a), hi_u = std::max(hi_u, a), lo_v = std::min(lo_v, b), hi_v = std::max(hi_v, b);
            }
            const double area = (hi_u - lo_u) * (hi_v - lo_v);
            if (area < best) best = area, best_u = u;
        }
        if (!(best < std::numeric_limits<double>::infinity())) return std::nullopt;
        Mat3<S> axes;  // u × (n × u) = n: right-handed
        axes.col(0) = best_u.template cast<S>();
        axes.col(1) = n.cross(best_u).template cast<S>();
        axes.col(2) = n.template cast<S>();
        return axes;
    }

    /// The same fit from moments precomputed about a common origin (triangle_moments(): a build sums ten
    /// numbers per triangle instead of recomputing outer products at every level). Where those moments
    /// cancel — a node tiny against its distance from the origin — or all areas are zero, it falls back
    /// to node-local moments, so the frame is as accurate as fit()'s.
    [[nodiscard]] static Obb fit(const TriangleMesh<S>& mesh, TriangleRange tris, const MeshMoments& moments) noexcept {
        if (tris.empty()) return empty();
        if (tris.size() == 1)
            if (const auto frame = triangle_frame(mesh, tris[0])) return fit_in_frame(mesh, tris, *frame);
        double area = 0, first[3] = {0, 0, 0}, second[6] = {0, 0, 0, 0, 0, 0};
        for (Index t : tris) {
            const TriangleMoments& m = moments.triangles[t];
            area += m.area;
            for (int k = 0; k < 3; ++k) first[k] += m.first[k];
            for (int k = 0; k < 6; ++k) second[k] += m.second[k];
        }
        if (area > 0) {
            const Eigen::Matrix<double, 3, 1> mean(first[0] / area, first[1] / area, first[2] / area);
            Eigen::Matrix<double, 3, 3> cov;
            int k = 0;
            for (int a = 0; a < 3; ++a)
                for (int b = a; b < 3; ++b, ++k) cov(a, b) = cov(b, a) = second[k] / area - mean[a] * mean[b];
            // E[x xᵀ] − mean meanᵀ keeps about 16 − log10(|mean|² / trace) digits: accept it while that is
            // at least 10; nearer the cancellation, node-local moments are cheap (such nodes are small).
            if (cov.trace() > 1e-6 * mean.squaredNorm()) return fit_in_frame(mesh, tris, principal_frame(cov));
        }
        return fit(mesh, tris);
    }

    /// Covariance of the triangles (area weighted; of the vertices when every area is zero), in double
    /// about one of their vertices so that far-away meshes do not cancel catastrophically.
    [[nodiscard]] static Eigen::Matrix<double, 3, 3> local_covariance(const TriangleMesh<S>& mesh, TriangleRange tris) noexcept {
        using D = double;
        Eigen::Matrix<D, 3, 3> second = Eigen::Matrix<D, 3, 3>::Zero();
        Eigen::Matrix<D, 3, 1> first = Eigen::Matrix<D, 3, 1>::Zero();
        D area_sum = 0;
        const Eigen::Matrix<D, 3, 1> origin = mesh.vertices[mesh.triangles[tris[0]][0]].template cast<D>();
        for (Index t : tris) {
            const auto& tri = mesh.triangles[t];
            const Eigen::Matrix<D, 3, 1> p = mesh.vertices[tri[0]].template cast<D>() - origin;
            const Eigen::Matrix<D, 3, 1> q = mesh.vertices[tri[1]].template cast<D>() - origin;
            const Eigen::Matrix<D, 3, 1> r = mesh.vertices[tri[2]].template cast<D>() - origin;
            const D area = 0.5 * (q - p).cross(r - p).norm();
            const Eigen::Matrix<D, 3, 1> m = (p + q + r) / 3.0;
            // ∫ x xᵀ over the triangle / area = (9 m mᵀ + p pᵀ + q qᵀ + r rᵀ) / 12.
            second += (area / 12.0) * (9.0 * m * m.transpose() + p * p.transpose() + q * q.transpose() +
                                        r * r.transpose());
            first += area * m;
            area_sum += area;
        }
        Eigen::Matrix<D, 3, 3> cov;
        if (area_sum > 0) {
            const Eigen::Matrix<D, 3, 1> mean = first / area_sum;
            cov = second / area_sum - mean * mean.transpose();
        } else {  // all triangles degenerate: plain vertex covariance
            Eigen::Matrix<D, 3, 1> mean = Eigen::Matrix<D, 3, 1>::Zero();
            std::size_t n = 0;
            for (Index t : tris)
                for (Index v : mesh.triangles[t]) mean += mesh.vertices[v].template cast<D>() - origin, ++n;
            mean /= D(n);
            cov.setZero();
            for (Index t : tris)
                for (Index v : mesh.triangles[t]) {
                    const Eigen::Matrix<D, 3, 1> d = mesh.vertices[v].template cast<D>() - origin - mean;
                    cov += d * d.transpose();
                }
        }
        return cov;
    }

    /// The eigenvectors of a covariance as a right-handed rotation, largest variance first (identity when
    /// the decomposition fails).
    [[nodiscard]] static Mat3<S> principal_frame(const Eigen::Matrix<double, 3, 3>& cov) noexcept {
        using D = double;
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix<D, 3, 3>> eig;
        eig.computeDirect(cov);
        Eigen::Matrix<D, 3, 3> frame = eig.eigenvectors();
        if (!frame.allFinite()) frame.setIdentity();
        // Re-orthonormalise and make it right-handed.
        Eigen::Matrix<D, 3, 1> u = frame.col(2).normalized();
        Eigen::Matrix<D, 3, 1> v = (frame.col(1) - frame.col(1).dot(u) * u).normalized();
        if (!u.allFinite() || !v.allFinite()) {
            u = Eigen::Matrix<D, 3, 1>::UnitX();
            v = Eigen::Matrix<D, 3, 1>::UnitY();
        }
        Mat3<S> axes;
        axes.col(0) = u.template cast<S>();
        axes.col(1) = v.template cast<S>();
        axes.col(2) = u.cross(v).template cast<S>();
        return axes;
    }

    /// The tight box with the given axes (columns, orthonormal) around the triangles' vertices.
    [[nodiscard]] static Obb fit_in_frame(const TriangleMesh<S>& mesh, TriangleRange tris, const Mat3<S>& axes) noexcept {
        Vec3<S> lo = Vec3<S>::Constant(std::numeric_limits<S>::infinity());
        Vec3<S> hi = -lo;
        S magnitude = 0;
        const Mat3<S> at = axes.transpose();
        for (Index t : tris)
            for (Index v : mesh.triangles[t]) {
                const Vec3<S> p = at * mesh.vertices[v];
                lo = lo.cwiseMin(p);
                hi = hi.cwiseMax(p);
                magnitude = std::max(magnitude, mesh.vertices[v].cwiseAbs().maxCoeff());
            }
        Obb box;
        box.axes = axes;
        if (tris.empty()) return box;
        // Projections onto slightly non-orthonormal rounded axes: pad by the magnitude, not the extent.
        const S pad = S(4) * detail::fit_padding(magnitude);
        box.half = (hi - lo) * S(0.5) + Vec3<S>::Constant(pad);
        box.center = axes * ((lo + hi) * S(0.5));
        return box;
    }

    struct Relative {
        Mat3<S> R;
        Vec3<S> t;
        S slack;
    };
    [[nodiscard]] static Relative relative(const Transform<S>& b_to_a) noexcept {
        return {b_to_a.R, b_to_a.t, detail::translation_slack(b_to_a.t)};
    }
};

/// Overlap of box `a` (in A's frame) with box `b` (in B's frame), `rel` taking B's frame to A's.
template <class S>
[[nodiscard]] inline bool overlap(const Obb<S>& a, const Obb<S>& b, const typename Obb<S>::Relative& rel) noexcept {
    const Mat3<S> at = a.axes.transpose();
    const Mat3<S> Rb = at * (rel.R * b.axes);
    const Vec3<S> T = at * (rel.R * b.center + rel.t - a.center);
    return !detail::boxes_disjoint(a.half, b.half, Rb, detail::abs_with_slack(Rb), T, rel.slack);
}

}  // namespace cdkit
