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

#include "cdkit/core/inlining.hpp"
#include "cdkit/core/math.hpp"

#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <type_traits>

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

/// A shape whose support query can start from a caller-kept hint (a vertex index of a polyhedron) that it
/// updates to the answer: `support(d, hint)`. GJK keeps one hint per shape during a query and, with a
/// `GjkCache`, across frames; the answer never depends on the hint, only the work does.
template <class T>
concept HintedSupport = SupportMapped<T> && requires(const T& s, const Vec3<typename T::Scalar>& d, std::uint32_t& h) {
    { s.support(d, h) } -> std::convertible_to<Vec3<typename T::Scalar>>;
};

/// A shape that knows two balls about its `center()`, margins included: one that contains it
/// (`bounding_radius()`) and one that it contains (`inner_radius()`; 0 when it has no interior, `center()`
/// being a point of the shape). Both are rounded outwards (the outer one up, the inner one down), so they stay
/// conservative. The cold boolean GJK decides a pair whose outer balls are disjoint, or whose inner balls
/// overlap, before any support query (`GjkSettings::bounding_ball_test`).
template <class T>
concept HasBoundingBalls = SupportMapped<T> && requires(const T& s) {
    { s.bounding_radius() } -> std::convertible_to<typename T::Scalar>;
    { s.inner_radius() } -> std::convertible_to<typename T::Scalar>;
};

/// A shape with a cheap conservative point-containment test in its local frame: `contains_strictly(p, slack)`
/// true only when the ball of radius `slack` about p lies inside the shape (margins included), up to roundings
/// far below `slack`; it may answer false for such points (a thin shape, a point near an edge). The cold boolean
/// GJK uses it as an overlap certificate that needs no tetrahedron: a support point of one shape strictly
/// inside the other proves that the two overlap.
template <class T>
concept HasContainmentTest = SupportMapped<T> &&
                             requires(const T& s, const Vec3<typename T::Scalar>& p, typename T::Scalar slack) {
                                 { s.contains_strictly(p, slack) } -> std::convertible_to<bool>;
                             };
/// The answer of a shape's point location (HasPointLocation): `inside` as contains_strictly's; otherwise `axis`,
/// when non-zero, an outward face normal whose plane p lies beyond (so p is outside where the faces are flat; a
/// candidate separating axis, see HasCandidateAxes: a wrong one only costs a support pair).
template <class S> struct PointLocation {
    bool inside = false;
    Vec3<S> axis = Vec3<S>::Zero();
};

/// A shape whose containment test walks (a hull): `locate(p, slack, hint)` with a support vertex near p as the
/// hint (GJK's), answering a PointLocation. The cold boolean GJK runs it once, with its slack (not a cheap pass
/// without the slack first), and tries the axis it returns as a candidate separating axis.
template <class T>
concept HasPointLocation =
    HasContainmentTest<T> &&
    requires(const T& s, const Vec3<typename T::Scalar>& p, typename T::Scalar slack, std::uint32_t hint) {
        { s.locate(p, slack, hint) } -> std::same_as<PointLocation<typename T::Scalar>>;
    };

/// A shape that can name a likely separating direction towards a point p (local frame): `candidate_axis(p)`, an
/// outward normal (non-zero) of the face whose plane p lies farthest outside of (a cone's side counts as a face at
/// p's azimuth). When p is the other shape's point nearest to this one, that normal is the separating axis of a
/// vertex–face contact (the separating axis theorem: Gottschalk, Lin, Manocha, "OBBTree", SIGGRAPH 1996). The cold
/// boolean GJK tries it with its plane test before its loop; any direction is safe, a wrong one only costs a
/// support pair.
template <class T>
concept HasCandidateAxes = SupportMapped<T> && requires(const T& s, const Vec3<typename T::Scalar>& p) {
    { s.candidate_axis(p) } -> std::convertible_to<Vec3<typename T::Scalar>>;
};

/// A shape with candidate axes that also names `candidate_edge(p)`, the unit direction of its edge nearest p: for
/// two such shapes the cross product of their nearest edges is the axis of an edge–edge contact, tried after the
/// face normals (boxes; the cone has none — with its rim tangents the extra support pair cost its overlapping
/// pairs more than it decided).
template <class T>
concept HasCandidateEdges = HasCandidateAxes<T> && requires(const T& s, const Vec3<typename T::Scalar>& p) {
    { s.candidate_edge(p) } -> std::convertible_to<Vec3<typename T::Scalar>>;
};

/// A wider floating type (float → double, double → long double), for GJK's rare refinement steps.
template <class S> using wider_t =
    std::conditional_t<std::is_same_v<S, float>, double, std::conditional_t<std::is_same_v<S, double>, long double, S>>;

/// A shape whose core (the set GJK runs on: the shape itself, or the point or segment under its margin) is a
/// polytope that the support map answers with exact vertices: `static constexpr bool polytope_core = true`. GJK
/// then ends on the closest simplex itself, off only by the final rounding (a few ε of the coordinates), while on
/// a curved core it stops at its convergence floor; the near-contact refinement (`GjkSettings::
/// refine_near_contact`) starts 16× closer for pairs of these.
template <class T>
concept HasPolytopeCore = SupportMapped<T> && requires { requires T::polytope_core; };

/// A shape that can be rebuilt in the wider floating type: `widened()`, the same set with Scalar
/// `wider_t<Scalar>`. GJK's near-contact refinement (`GjkSettings::refine_near_contact`) then queries it there;
/// shapes without it have their support points widened, which is exact for vertices but leaves a curved
/// surface's points rounded to the narrow type.
template <class T>
concept HasWidened = SupportMapped<T> && requires(const T& s) {
    { s.widened() } -> SupportMapped;
};

namespace detail {
/// x rounded outwards by a few ulps: a radius computed with a handful of rounded operations (a sqrt, a sum)
/// is within 4ε relative of the true value, so these give a certain upper / lower bound.
template <class S> [[nodiscard]] inline S round_up(S x) noexcept {
    return x * (S(1) + S(8) * std::numeric_limits<S>::epsilon());
}
template <class S> [[nodiscard]] inline S round_down(S x) noexcept {
    return x * (S(1) - S(8) * std::numeric_limits<S>::epsilon());
}

/// R·v, R^T·v and R·p + t written out per component. Eigen's generic 3×3 product is not always inlined at
/// -O2 (the profile of issue 5 showed `generic_product_impl::evalTo` as an out-of-line call taking ~10 % of a
/// one-iteration GJK query); these are, and a support query on a placed shape needs two of them.
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> rotate(const Mat3<S>& R, const Vec3<S>& v) noexcept {
    return Vec3<S>(R(0, 0) * v[0] + R(0, 1) * v[1] + R(0, 2) * v[2], R(1, 0) * v[0] + R(1, 1) * v[1] + R(1, 2) * v[2],
                   R(2, 0) * v[0] + R(2, 1) * v[1] + R(2, 2) * v[2]);
}
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> rotate_back(const Mat3<S>& R, const Vec3<S>& v) noexcept {
    return Vec3<S>(R(0, 0) * v[0] + R(1, 0) * v[1] + R(2, 0) * v[2], R(0, 1) * v[0] + R(1, 1) * v[1] + R(2, 1) * v[2],
                   R(0, 2) * v[0] + R(1, 2) * v[1] + R(2, 2) * v[2]);
}
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> place(const Transform<S>& pose, const Vec3<S>& p) noexcept {
    const Mat3<S>& R = pose.R;
    return Vec3<S>(R(0, 0) * p[0] + R(0, 1) * p[1] + R(0, 2) * p[2] + pose.t[0],
                   R(1, 0) * p[0] + R(1, 1) * p[1] + R(1, 2) * p[2] + pose.t[1],
                   R(2, 0) * p[0] + R(2, 1) * p[1] + R(2, 2) * p[2] + pose.t[2]);
}
/// a − b per component (Eigen's expression for it was an out-of-line call in the GJK profile).
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> minus(const Vec3<S>& a, const Vec3<S>& b) noexcept {
    return Vec3<S>(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}
/// Dot product, squared norm, negation, a + s·b and cross product per component. Eigen 3.4 evaluates the first
/// two components of a 3-vector dot product or negation as one 16-byte packet: on a vector GJK has just
/// written component by component (a support point, a rotated direction) that load cannot be served from
/// the two pending 8-byte stores, and the store-forwarding stalls were the largest cost of a GJK iteration
/// in the profile (box pairs: ~45 ns per iteration before).
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE S dot3(const Vec3<S>& a, const Vec3<S>& b) noexcept {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE S norm2(const Vec3<S>& a) noexcept {
    return a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
}
/// |a|₁, the magnitude that rounding slacks and error bounds scale with.
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE S norm1(const Vec3<S>& a) noexcept {
    return std::abs(a[0]) + std::abs(a[1]) + std::abs(a[2]);
}
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> neg(const Vec3<S>& a) noexcept {
    return Vec3<S>(-a[0], -a[1], -a[2]);
}
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> plus_scaled(const Vec3<S>& a, S s, const Vec3<S>& b) noexcept {
    return Vec3<S>(a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]);
}
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> cross3(const Vec3<S>& a, const Vec3<S>& b) noexcept {
    return Vec3<S>(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
}
/// All three components finite (x·0 is 0 for finite x and NaN for ±inf or NaN; no overflow), one branch.
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE bool all_finite(const Vec3<S>& v) noexcept {
    return v[0] * S(0) + v[1] * S(0) + v[2] * S(0) == S(0);
}
/// pose_a⁻¹·pose_b (B's frame into A's) without temporaries: R = R_aᵀR_b, t = R_aᵀ(t_b − t_a).
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE Transform<S> relative_pose(const Transform<S>& pose_a,
                                                                   const Transform<S>& pose_b) noexcept {
    Transform<S> r;
    for (int j = 0; j < 3; ++j) {
        const Vec3<S> c = rotate_back(pose_a.R, Vec3<S>(pose_b.R.col(j)));
        r.R.col(j) = c;
    }
    r.t = rotate_back(pose_a.R, Vec3<S>(pose_b.t - pose_a.t));
    return r;
}

/// d/|d|, or zero when d is zero (a zero direction then adds nothing to an inflated support point).
template <class S> [[nodiscard]] inline Vec3<S> safe_normalized(const Vec3<S>& d) noexcept {
    S n = d.norm();
    return n > S(0) ? Vec3<S>(d / n) : Vec3<S>::Zero();
}

/// The core support of a shape (its full support when it has no margin) and its margin.
template <SupportMapped T> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<typename T::Scalar> core_support(
    const T& s, const Vec3<typename T::Scalar>& d) noexcept {
    if constexpr (HasMargin<T>) return s.core_support(d);
    else return s.support(d);
}
/// Core support (as `core_support`) through the shape's hinted query where it has one and `hint` is given.
template <SupportMapped T> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<typename T::Scalar> core_support_hinted(
    const T& s, const Vec3<typename T::Scalar>& d, std::uint32_t* hint) noexcept {
    if constexpr (HintedSupport<T> && !HasMargin<T>) {
        if (hint) return s.support(d, *hint);
    }
    (void)hint;
    return core_support(s, d);
}
/// Full support through the shape's hinted query where it has one (`hint` non-null), else `support(d)`.
template <SupportMapped T> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<typename T::Scalar> support_hinted(
    const T& s, const Vec3<typename T::Scalar>& d, std::uint32_t* hint) noexcept {
    if constexpr (HintedSupport<T>) {
        if (hint) return s.support(d, *hint);
    }
    (void)hint;
    return s.support(d);
}
/// The shape's interior point in the world frame: the pose's translation for shapes whose `center()` is the
/// origin (a `static constexpr bool centered_at_origin`), one rotation column for one on the z axis
/// (`center_z()`), without the products by zero that IEEE arithmetic cannot fold away.
template <SupportMapped T> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<typename T::Scalar> world_center(
    const T& s, const Transform<typename T::Scalar>& pose) noexcept {
    if constexpr (requires { requires T::centered_at_origin; }) {
        (void)s;
        return pose.t;
    } else if constexpr (requires { { s.center_z() } -> std::convertible_to<typename T::Scalar>; }) {
        const typename T::Scalar z = s.center_z();  // on the local z axis (a cone's centroid)
        return Vec3<typename T::Scalar>(pose.t[0] + pose.R(0, 2) * z, pose.t[1] + pose.R(1, 2) * z,
                                        pose.t[2] + pose.R(2, 2) * z);
    } else {
        return place(pose, Vec3<typename T::Scalar>(s.center()));
    }
}
template <SupportMapped T> [[nodiscard]] inline typename T::Scalar margin_of(const T& s) noexcept {
    if constexpr (HasMargin<T>) return s.margin();
    else { (void)s; return typename T::Scalar(0); }
}
/// A point of the shape's core moved out by its margin along the unit direction n: p + margin·n; p itself for
/// a margin-free shape (no product by a zero margin, which IEEE arithmetic cannot fold away).
template <SupportMapped T> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<typename T::Scalar> pushed_out(
    const T& s, const Vec3<typename T::Scalar>& p, const Vec3<typename T::Scalar>& n) noexcept {
    if constexpr (HasMargin<T>) return Vec3<typename T::Scalar>(p + s.margin() * n);
    else { (void)s; (void)n; return p; }
}
/// The shape's bounding box in its own frame from six support calls (exact for a support-mapped shape: each side
/// touches the shape). `lo` ≤ `hi` unless a size is NaN or infinite; callers that take input check finiteness.
template <class S> struct SupportBox {
    Vec3<S> lo, hi;
};
template <SupportMapped T> [[nodiscard]] SupportBox<typename T::Scalar> support_box(const T& s) noexcept {
    using S = typename T::Scalar;
    SupportBox<S> b;
    for (int i = 0; i < 3; ++i) {
        b.hi[i] = Vec3<S>(s.support(Vec3<S>::Unit(i)))[i];
        b.lo[i] = Vec3<S>(s.support(Vec3<S>(-Vec3<S>::Unit(i))))[i];
    }
    return b;
}
}  // namespace detail

/// A shape placed by a rigid pose: support in the outer frame is pose·s(Rᵀd). Non-owning view: the
/// wrapped shape must outlive it.
template <SupportMapped Shape> struct Transformed {
    using Scalar = typename Shape::Scalar;
    const Shape& shape;
    Transform<Scalar> pose;

    [[nodiscard]] Vec3<Scalar> support(const Vec3<Scalar>& d) const noexcept {
        return detail::place(pose, Vec3<Scalar>(shape.support(detail::rotate_back(pose.R, d))));
    }
    [[nodiscard]] Vec3<Scalar> center() const noexcept { return detail::place(pose, Vec3<Scalar>(shape.center())); }
    [[nodiscard]] Scalar margin() const noexcept { return detail::margin_of(shape); }
    [[nodiscard]] Vec3<Scalar> core_support(const Vec3<Scalar>& d) const noexcept {
        return detail::place(pose, Vec3<Scalar>(detail::core_support(shape, detail::rotate_back(pose.R, d))));
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
    /// Balls about center() (see HasBoundingBalls), where the wrapped shape has them.
    [[nodiscard]] Scalar bounding_radius() const noexcept
        requires HasBoundingBalls<Shape>
    {
        return detail::round_up(Scalar(shape.bounding_radius() + radius));
    }
    [[nodiscard]] Scalar inner_radius() const noexcept
        requires HasBoundingBalls<Shape>
    {
        return detail::round_down(Scalar(shape.inner_radius() + radius));
    }
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
