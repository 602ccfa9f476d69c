#pragma once
/// \file Axis-aligned bounding box. In a BVH query the other tree's boxes arrive rotated, so the overlap test
/// is the box–box separating-axis test with the relative rotation fixed for the whole query: |R| is computed
/// once per query, and each test costs one rotated centre plus comparisons. No mesh is re-fitted per query.

#include "cdkit/bv/detail/separating_axis.hpp"
#include "cdkit/bv/fit.hpp"

namespace cdkit {

template <class S> struct Aabb {
    using Scalar = S;
    template <class T> using rebind = Aabb<T>;  ///< the same BV in another scalar type
    static constexpr const char* name = "AABB";

    Vec3<S> center = Vec3<S>::Zero();
    Vec3<S> half = Vec3<S>::Constant(S(-1));  ///< half extents; negative = empty

    [[nodiscard]] static Aabb empty() noexcept { return {}; }
    [[nodiscard]] static Aabb from_min_max(const Vec3<S>& lo, const Vec3<S>& hi) noexcept {
        return {(lo + hi) * S(0.5), (hi - lo) * S(0.5)};
    }
    [[nodiscard]] bool is_empty() const noexcept { return (half.array() < S(0)).any(); }
    [[nodiscard]] bool is_valid() const noexcept {
        return center.allFinite() && half.allFinite() && (half.array() >= S(0)).all();
    }
    [[nodiscard]] Vec3<S> min() const noexcept { return center - half; }
    [[nodiscard]] Vec3<S> max() const noexcept { return center + half; }
    [[nodiscard]] S volume() const noexcept { return is_empty() ? S(0) : S(8) * half.prod(); }
    [[nodiscard]] S surface_area() const noexcept {
        return is_empty() ? S(0) : S(8) * (half.x() * half.y() + half.y() * half.z() + half.z() * half.x());
    }
    /// Used by the traversal to decide which tree to descend: the larger box.
    [[nodiscard]] S size() const noexcept { return half.x() + half.y() + half.z(); }
    /// The direction a top-down build splits along: the longest axis.
    [[nodiscard]] Vec3<S> split_axis() const noexcept {
        int k;
        half.maxCoeff(&k);
        return Vec3<S>::Unit(k);
    }
    [[nodiscard]] bool contains(const Vec3<S>& p, S tol = S(0)) const noexcept {
        return ((p - center).cwiseAbs().array() <= half.array() + tol).all();
    }
    /// Smallest box holding both.
    [[nodiscard]] static Aabb merge(const Aabb& a, const Aabb& b) noexcept {
        if (a.is_empty()) return b;
        if (b.is_empty()) return a;
        return from_min_max(a.min().cwiseMin(b.min()), a.max().cwiseMax(b.max()));
    }

    /// Fits the triangles' vertices, padded conservatively (see detail::fit_padding).
    [[nodiscard]] static Aabb fit(const TriangleMesh<S>& mesh, TriangleRange tris) noexcept {
        Vec3<S> lo = Vec3<S>::Constant(std::numeric_limits<S>::infinity());
        Vec3<S> hi = -lo;
        for (Index t : tris)
            for (Index v : mesh.triangles[t]) {
                lo = lo.cwiseMin(mesh.vertices[v]);
                hi = hi.cwiseMax(mesh.vertices[v]);
            }
        if (tris.empty()) return empty();
        const S pad = detail::fit_padding(std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()));
        return from_min_max(lo.array() - pad, hi.array() + pad);
    }

    /// Per-query data: the rotation and translation taking the second tree's frame into the first's.
    struct Relative {
        Mat3<S> R;
        Mat3<S> absR;
        Vec3<S> t;
        S slack;
    };
    [[nodiscard]] static Relative relative(const Transform<S>& b_to_a) noexcept {
        return {b_to_a.R, detail::abs_with_slack(b_to_a.R), b_to_a.t, detail::translation_slack(b_to_a.t)};
    }
};

/// Overlap of box `a` (in A's frame) with box `b` (in B's frame), `rel` taking B's frame to A's.
template <class S>
[[nodiscard]] inline bool overlap(const Aabb<S>& a, const Aabb<S>& b, const typename Aabb<S>::Relative& rel) noexcept {
    const Vec3<S> T = rel.R * b.center + rel.t - a.center;
    return !detail::boxes_disjoint(a.half, b.half, rel.R, rel.absR, T, rel.slack);
}

}  // namespace cdkit
