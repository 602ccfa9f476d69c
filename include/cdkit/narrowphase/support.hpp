#pragma once
/// \file Convex shapes described by their support mapping, and the wrappers that compose them.
///
/// A convex set C is represented by its support function s_C(d) = argmax_{x in C} d·x (any maximiser).
/// Everything the convex narrow phase (GJK, EPA) needs is that map plus one interior point, so shapes are
/// plain value types satisfying `SupportMapped`, composed by the non-virtual wrappers below
/// (van den Bergen, "Collision Detection in Interactive 3D Environments", 2003, ch. 4).
///
/// Shapes that are a "core" set grown by a ball (sphere = point + r, capsule = segment + r, `Inflated`)
/// also expose `margin()` and `core_support(d)`; GJK then works on the cores and subtracts the margins,
/// which makes spheres and capsules exact instead of asymptotically converging.

#include <cdkit/core/math.hpp>

#include <cmath>
#include <concepts>

namespace cdkit {

/// A convex shape given by its support map in its own (local) frame.
/// `support(d)` returns a point of the shape maximising d·x (d need not be unit, may be zero: then any
/// point of the shape); `center()` returns a point in the shape's interior (or relative interior for flat
/// shapes), used to seed GJK and EPA. Both must be const, noexcept in spirit and thread-safe.
template <class T>
concept SupportMapped = requires(const T& s, const Vec3<typename T::Scalar>& d) {
    typename T::Scalar;
    { s.support(d) } -> std::convertible_to<Vec3<typename T::Scalar>>;
    { s.center() } -> std::convertible_to<Vec3<typename T::Scalar>>;
};

/// A support-mapped shape that is a convex core grown by a ball of radius `margin()`:
/// support(d) = core_support(d) + margin()·d/|d|.
template <class T>
concept HasMargin = SupportMapped<T> && requires(const T& s, const Vec3<typename T::Scalar>& d) {
    { s.margin() } -> std::convertible_to<typename T::Scalar>;
    { s.core_support(d) } -> std::convertible_to<Vec3<typename T::Scalar>>;
};

namespace detail {
/// d/|d|, or zero when d is zero (a zero direction then adds nothing to an inflated support point).
template <class S> [[nodiscard]] inline Vec3<S> safe_normalized(const Vec3<S>& d) noexcept {
    S n = d.norm();
    return n > S(0) ? Vec3<S>(d / n) : Vec3<S>::Zero();
}

/// The core support of a shape (its full support when it has no margin) and its margin.
template <SupportMapped T> [[nodiscard]] inline Vec3<typename T::Scalar> core_support(
    const T& s, const Vec3<typename T::Scalar>& d) noexcept {
    if constexpr (HasMargin<T>) return s.core_support(d);
    else return s.support(d);
}
template <SupportMapped T> [[nodiscard]] inline typename T::Scalar margin_of(const T& s) noexcept {
    if constexpr (HasMargin<T>) return s.margin();
    else { (void)s; return typename T::Scalar(0); }
}
}  // namespace detail

/// A shape placed by a rigid pose: support in the outer frame is pose·s(Rᵀd). Non-owning view: the
/// wrapped shape must outlive it.
template <SupportMapped Shape> struct Transformed {
    using Scalar = typename Shape::Scalar;
    const Shape& shape;
    Transform<Scalar> pose;

    [[nodiscard]] Vec3<Scalar> support(const Vec3<Scalar>& d) const noexcept {
        return pose * Vec3<Scalar>(shape.support(pose.R.transpose() * d));
    }
    [[nodiscard]] Vec3<Scalar> center() const noexcept { return pose * Vec3<Scalar>(shape.center()); }
    [[nodiscard]] Scalar margin() const noexcept { return detail::margin_of(shape); }
    [[nodiscard]] Vec3<Scalar> core_support(const Vec3<Scalar>& d) const noexcept {
        return pose * Vec3<Scalar>(detail::core_support(shape, Vec3<Scalar>(pose.R.transpose() * d)));
    }
};

/// A shape grown by a ball of radius `radius` ≥ 0 (Minkowski sum with a ball: rounded corners).
/// Non-owning view.
template <SupportMapped Shape> struct Inflated {
    using Scalar = typename Shape::Scalar;
    const Shape& shape;
    Scalar radius;

    [[nodiscard]] Vec3<Scalar> support(const Vec3<Scalar>& d) const noexcept {
        return Vec3<Scalar>(shape.support(d)) + radius * detail::safe_normalized(d);
    }
    [[nodiscard]] Vec3<Scalar> center() const noexcept { return shape.center(); }
    [[nodiscard]] Scalar margin() const noexcept { return detail::margin_of(shape) + radius; }
    [[nodiscard]] Vec3<Scalar> core_support(const Vec3<Scalar>& d) const noexcept {
        return detail::core_support(shape, d);
    }
};

/// The Minkowski difference A − B = {a − b}: support(d) = s_A(d) − s_B(−d). A and B intersect iff it
/// contains the origin, and their distance is its distance to the origin. Non-owning view.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
struct MinkowskiDifference {
    using Scalar = typename A::Scalar;
    const A& a;
    const B& b;

    [[nodiscard]] Vec3<Scalar> support(const Vec3<Scalar>& d) const noexcept {
        return Vec3<Scalar>(a.support(d)) - Vec3<Scalar>(b.support(Vec3<Scalar>(-d)));
    }
    [[nodiscard]] Vec3<Scalar> center() const noexcept {
        return Vec3<Scalar>(a.center()) - Vec3<Scalar>(b.center());
    }
};

}  // namespace cdkit
