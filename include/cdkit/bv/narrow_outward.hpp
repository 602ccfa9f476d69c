#pragma once
/// \file Float bounding volumes over double meshes: each BV is fitted in double, then rounded outward to
/// float, so it still contains the double triangles exactly (conservative culling) while nodes take half the
/// bytes. The float BV is further padded like a float fit (detail::fit_padding at float precision), which
/// covers the query's own float rounding: the relative transform rounded to float, and float arithmetic in
/// the overlap and distance tests, exactly as for a float tree over a float mesh.

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/sphere.hpp"

#include <cmath>
#include <limits>
#include <type_traits>

namespace cdkit {

namespace detail {
/// The largest float <= x, and the smallest float >= x (x finite, within float's range).
[[nodiscard]] inline float float_down(double x) noexcept {
    const float f = static_cast<float>(x);
    return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
[[nodiscard]] inline float float_up(double x) noexcept {
    const float f = static_cast<float>(x);
    return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}
}  // namespace detail

/// An Aabb<float> holding `b`.
[[nodiscard]] inline Aabb<float> narrow_outward(const Aabb<double>& b) noexcept {
    if (b.is_empty()) return Aabb<float>::empty();
    const Vec3<double> lo = b.min(), hi = b.max();
    const double magnitude = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
    const float pad = detail::fit_padding(detail::float_up(magnitude));
    Vec3<float> flo, fhi;
    for (int k = 0; k < 3; ++k) flo[k] = detail::float_down(lo[k]) - pad, fhi[k] = detail::float_up(hi[k]) + pad;
    return Aabb<float>::from_min_max(flo, fhi);
}

/// An Obb<float> holding `b`: its axes rounded to float, extents re-measured on those axes from b's corners.
[[nodiscard]] inline Obb<float> narrow_outward(const Obb<double>& b) noexcept {
    if (b.is_empty()) return Obb<float>::empty();
    Obb<float> out;
    out.axes = b.axes.cast<float>();
    const Mat3<double> axes = out.axes.cast<double>();  // exactly the float axes
    Vec3<double> lo = Vec3<double>::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    double magnitude = 0;
    for (int c = 0; c < 8; ++c) {
        const Vec3<double> s((c & 1) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, (c & 4) ? 1.0 : -1.0);
        const Vec3<double> corner = b.center + b.axes * s.cwiseProduct(b.half);
        const Vec3<double> p = axes.transpose() * corner;
        lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
        magnitude = std::max(magnitude, corner.cwiseAbs().maxCoeff());
    }
    out.center = (axes * ((lo + hi) * 0.5)).cast<float>();
    // Extents measured from the rounded centre's own projections: exact containment on the float axes,
    // however the rounding moved the centre and however far from orthonormal the rounded axes are.
    const Vec3<double> c = axes.transpose() * out.center.cast<double>();
    const float pad = 4 * detail::fit_padding(detail::float_up(magnitude));
    for (int k = 0; k < 3; ++k) out.half[k] = detail::float_up(std::max(hi[k] - c[k], c[k] - lo[k])) + pad;
    return out;
}

/// A Kdop<float, K> holding `b`: every support value rounded up.
template <int K> [[nodiscard]] Kdop<float, K> narrow_outward(const Kdop<double, K>& b) noexcept {
    if (b.is_empty()) return Kdop<float, K>::empty();
    double magnitude = 0;
    for (double v : b.h) magnitude = std::max(magnitude, std::abs(v));
    const float pad = 3 * detail::fit_padding(detail::float_up(magnitude));
    Kdop<float, K> out;
    for (int k = 0; k < K; ++k) out.h[k] = detail::float_up(b.h[k]) + pad;
    return out;
}

/// A BoundingSphere<float> holding `b`: the rounded centre's shift added to the radius.
[[nodiscard]] inline BoundingSphere<float> narrow_outward(const BoundingSphere<double>& b) noexcept {
    if (b.is_empty()) return BoundingSphere<float>::empty();
    BoundingSphere<float> out;
    out.center = b.center.cast<float>();
    const double moved = (out.center.cast<double>() - b.center).norm() * (1 + 1e-6);
    const double magnitude = b.center.cwiseAbs().maxCoeff() + b.radius;
    out.radius = detail::float_up(b.radius + moved) + 4 * detail::fit_padding(detail::float_up(magnitude));
    return out;
}

namespace detail {
/// BV stored in BV::Scalar over a mesh of scalar M: the same scalar, or float BVs over a double mesh.
template <class BV, class M>
inline constexpr bool bv_fits_mesh_v =
    std::is_same_v<typename BV::Scalar, M> || (std::is_same_v<typename BV::Scalar, float> && std::is_same_v<M, double>);

/// BV::fit for a mesh of scalar M: directly, or fitted in M and rounded outward.
template <class BV, class M> [[nodiscard]] BV fit_over(const TriangleMesh<M>& mesh, TriangleRange tris) {
    static_assert(bv_fits_mesh_v<BV, M>, "a BV is stored in the mesh's scalar type, or in float over a double mesh");
    if constexpr (std::is_same_v<typename BV::Scalar, M>) return BV::fit(mesh, tris);
    else return narrow_outward(BV::template rebind<M>::fit(mesh, tris));
}
}  // namespace detail

}  // namespace cdkit
