#pragma once
/// \file Small fixed-size linear algebra on top of Eigen and the rigid Transform every query takes.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cdkit/core/status.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace cdkit {

template <class S> using Vec3 = Eigen::Matrix<S, 3, 1>;
template <class S> using Mat3 = Eigen::Matrix<S, 3, 3>;

/// A rigid motion x ↦ R·x + t. `R` must be a rotation (orthonormal, det +1); `is_valid()` checks it.
/// Poses in cdkit map an object's model frame into the world frame.
template <class S> struct Transform {
    using Scalar = S;
    Mat3<S> R = Mat3<S>::Identity();
    Vec3<S> t = Vec3<S>::Zero();

    Transform() = default;
    Transform(const Mat3<S>& rotation, const Vec3<S>& translation) : R(rotation), t(translation) {}
    /// From an Eigen isometry (its linear part is taken as the rotation).
    explicit Transform(const Eigen::Transform<S, 3, Eigen::Isometry>& iso) : R(iso.linear()), t(iso.translation()) {}

    [[nodiscard]] static Transform identity() { return {}; }
    [[nodiscard]] static Transform translation(const Vec3<S>& v) { return {Mat3<S>::Identity(), v}; }

    [[nodiscard]] Vec3<S> operator*(const Vec3<S>& p) const { return R * p + t; }
    /// Composition: (a * b)(x) = a(b(x)).
    [[nodiscard]] Transform operator*(const Transform& b) const { return {R * b.R, R * b.t + t}; }
    [[nodiscard]] Transform inverse() const {
        Mat3<S> rt = R.transpose();
        return {rt, -(rt * t)};
    }
    template <class T> [[nodiscard]] Transform<T> cast() const {
        return {R.template cast<T>(), t.template cast<T>()};
    }
    [[nodiscard]] Eigen::Transform<S, 3, Eigen::Isometry> to_isometry() const {
        Eigen::Transform<S, 3, Eigen::Isometry> iso = Eigen::Transform<S, 3, Eigen::Isometry>::Identity();
        iso.linear() = R;
        iso.translation() = t;
        return iso;
    }

    /// True when all entries are finite and R is orthonormal with det +1 within `tol` (default: a few
    /// hundred ulps of S, enough for rotations composed from a handful of products).
    /// Written for the queries' entry (pose_is_usable; a sixth of a far query's time went here): RᵀR's six
    /// distinct entries (the columns' dot products) and the determinant as a triple product. No finiteness pass
    /// over R: a NaN or infinity in R makes the determinant NaN or infinite, and its comparison fails.
    [[nodiscard]] bool is_valid(S tol = S(512) * std::numeric_limits<S>::epsilon()) const {
        const auto c0 = R.col(0), c1 = R.col(1), c2 = R.col(2);
        const S e = std::max({std::abs(c0.dot(c0) - S(1)), std::abs(c1.dot(c1) - S(1)), std::abs(c2.dot(c2) - S(1)),
                              std::abs(c0.dot(c1)), std::abs(c0.dot(c2)), std::abs(c1.dot(c2))});
        return e <= tol && std::abs(c0.dot(c1.cross(c2)) - S(1)) <= tol && t.allFinite();
    }
};


/// The gate the queries apply: finite, and orthonormal with det +1 to within sqrt(eps) — loose enough for
/// rotations accumulated over a long simulation without re-orthonormalising, tight enough to refuse
/// scales, shears, reflections and garbage.
template <class S> [[nodiscard]] bool pose_is_usable(const Transform<S>& pose) noexcept {
    return pose.is_valid(std::sqrt(std::numeric_limits<S>::epsilon()));
}

}  // namespace cdkit
