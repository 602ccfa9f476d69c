#pragma once
/// \file Primitive convex shapes for the convex narrow phase, each given by its support map (see
/// support.hpp). All live in their own local frame, centred at the origin, symmetric axis along z; place
/// them with a pose in the query. Constructors validate (finite, non-negative sizes) and raise
/// `cdkit::Error`; support queries are const, noexcept and thread-safe.

#include <cdkit/core/error.hpp>
#include <cdkit/core/math.hpp>
#include <cdkit/narrowphase/support.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace cdkit {

namespace detail {
template <class S> inline void check_size(S v, const char* shape, const char* what, bool positive = false) {
    if (!std::isfinite(v) || v < S(0) || (positive && v == S(0)))
        throw Error(std::string("<") + shape + ">", what,
                    positive ? "must be finite and > 0" : "must be finite and >= 0");
}
template <class S> inline void check_point(const Vec3<S>& p, const char* shape, const char* what) {
    if (!p.allFinite()) throw Error(std::string("<") + shape + ">", what, "must be finite");
}
/// Checks the (value, name) pairs of a shape's sizes: all finite and ≥ 0.
template <class S, class... Rest> inline void check_sizes(const char* shape, S v, const char* what, Rest... rest) {
    check_size(v, shape, what);
    if constexpr (sizeof...(Rest) > 0) check_sizes(shape, rest...);
}
/// h with the sign of v (h ≥ 0): the extreme coordinate of a symmetric extent along v. Branch-free (a sign
/// bit copy): the former compare-and-branch (v < 0 ? −h : h) mispredicted on GJK's varying directions and
/// was the largest single cost of a box support query in the profile. A zero direction still picks a
/// definite point (+0 gives +h, −0 gives −h; both are maximisers).
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE S signed_extent(S h, S v) noexcept { return std::copysign(h, v); }
/// sqrt(x² + y²); std::hypot (a libm call, ~25 % of a cylinder support query) only where the squares
/// would underflow or overflow.
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE S planar_norm(S x, S y) noexcept {
    const S q = x * x + y * y;
    if (q >= std::numeric_limits<S>::min() && q <= std::numeric_limits<S>::max()) return std::sqrt(q);
    return std::hypot(x, y);
}
/// Support of the disc of radius r at height z (normal z) along d: its rim point towards (d_x, d_y), or the
/// centre when d is axial (cylinder caps, the cone's base).
template <class S> [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> disc_support(const Vec3<S>& d, S r, S z) noexcept {
    const S rho = planar_norm(d.x(), d.y());
    if (!(rho > S(0))) return {S(0), S(0), z};
    return {r * d.x() / rho, r * d.y() / rho, z};
}
/// Selects a shape constructor that skips the size checks: for `widened()`, whose sizes are a checked shape's.
struct unchecked_t {};
}  // namespace detail

/// A ball of radius `radius` around the origin: a point core with margin `radius`.
template <class S = double> struct Sphere {
    using Scalar = S;
    static constexpr bool centered_at_origin = true;  ///< center() is the origin (saves GJK a transform)
    static constexpr bool polytope_core = true;       ///< HasPolytopeCore: exact core support
    S radius;
    explicit Sphere(S r) : radius(r) { detail::check_size(r, "sphere", "radius"); }
    [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> support(const Vec3<S>& d) const noexcept {
        return radius * detail::safe_normalized(d);
    }
    [[nodiscard]] Vec3<S> center() const noexcept { return Vec3<S>::Zero(); }
    [[nodiscard]] S margin() const noexcept { return radius; }
    [[nodiscard]] Vec3<S> core_support(const Vec3<S>&) const noexcept { return Vec3<S>::Zero(); }
    /// Balls about the centre (HasBoundingBalls): the sphere itself.
    [[nodiscard]] S bounding_radius() const noexcept { return radius; }
    [[nodiscard]] S inner_radius() const noexcept { return radius; }
};

/// An axis-aligned box [-h, h] (h = half extents) in its local frame.
template <class S = double> struct Box {
    using Scalar = S;
    static constexpr bool centered_at_origin = true;  ///< center() is the origin (saves GJK a transform)
    static constexpr bool polytope_core = true;       ///< HasPolytopeCore: exact core support
    Vec3<S> half;
    explicit Box(const Vec3<S>& half_extents) : half(half_extents) {
        detail::check_sizes("box", half[0], "half extent", half[1], "half extent", half[2], "half extent");
    }
    [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> support(const Vec3<S>& d) const noexcept {
        return {detail::signed_extent(half.x(), d.x()), detail::signed_extent(half.y(), d.y()),
                detail::signed_extent(half.z(), d.z())};
    }
    [[nodiscard]] Vec3<S> center() const noexcept { return Vec3<S>::Zero(); }
    /// Balls about the centre (HasBoundingBalls): through the corners, and touching the nearest faces.
    [[nodiscard]] S bounding_radius() const noexcept {
        return detail::round_up(std::sqrt(half[0] * half[0] + half[1] * half[1] + half[2] * half[2]));
    }
    [[nodiscard]] S inner_radius() const noexcept { return std::min({half[0], half[1], half[2]}); }
    /// p at least `slack` inside every face (HasContainmentTest). Non-short-circuit: GJK's points vary.
    [[nodiscard]] CDKIT_ALWAYS_INLINE bool contains_strictly(const Vec3<S>& p, S slack) const noexcept {
        return (std::abs(p[0]) < half[0] - slack) & (std::abs(p[1]) < half[1] - slack) &
               (std::abs(p[2]) < half[2] - slack);
    }
    /// The outward face normal ±e_i whose face plane p lies farthest outside of, |p_i| − h_i largest
    /// (HasCandidateAxes). Branch-free: which face wins varies from query to query.
    [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> candidate_axis(const Vec3<S>& p) const noexcept {
        const S ex = std::abs(p[0]) - half[0], ey = std::abs(p[1]) - half[1], ez = std::abs(p[2]) - half[2];
        const bool x = (ex >= ey) & (ex >= ez);
        const bool y = !x & (ey >= ez);
        const bool z = !x & !y;
        return {S(x) * std::copysign(S(1), p[0]), S(y) * std::copysign(S(1), p[1]), S(z) * std::copysign(S(1), p[2])};
    }
    /// The direction e_k of the edges nearest to p (HasCandidateEdges): k the axis p lies least outside of (for p
    /// beyond two faces, the edge between them).
    [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> candidate_edge(const Vec3<S>& p) const noexcept {
        const S ex = std::abs(p[0]) - half[0], ey = std::abs(p[1]) - half[1], ez = std::abs(p[2]) - half[2];
        const bool x = (ex <= ey) & (ex <= ez);
        const bool y = !x & (ey <= ez);
        const bool z = !x & !y;
        return {S(x), S(y), S(z)};
    }
};

/// A capsule: the segment z ∈ [-half_length, half_length] grown by `radius`.
template <class S = double> struct Capsule {
    using Scalar = S;
    static constexpr bool centered_at_origin = true;  ///< center() is the origin (saves GJK a transform)
    static constexpr bool polytope_core = true;       ///< HasPolytopeCore: exact core support
    S radius, half_length;
    Capsule(S r, S half_len) : radius(r), half_length(half_len) {
        detail::check_sizes("capsule", r, "radius", half_len, "half length");
    }
    [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> core_support(const Vec3<S>& d) const noexcept {
        return {S(0), S(0), detail::signed_extent(half_length, d.z())};
    }
    [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> support(const Vec3<S>& d) const noexcept {
        return core_support(d) + radius * detail::safe_normalized(d);
    }
    [[nodiscard]] Vec3<S> center() const noexcept { return Vec3<S>::Zero(); }
    [[nodiscard]] S margin() const noexcept { return radius; }
    /// Balls about the centre (HasBoundingBalls): through the tips, and the ball of the centre's cross-section.
    [[nodiscard]] S bounding_radius() const noexcept { return detail::round_up(S(half_length + radius)); }
    [[nodiscard]] S inner_radius() const noexcept { return radius; }
};

/// A solid cylinder of radius `radius`, z ∈ [-half_height, half_height].
template <class S = double> struct Cylinder {
    using Scalar = S;
    static constexpr bool centered_at_origin = true;  ///< center() is the origin (saves GJK a transform)
    S radius, half_height;
    Cylinder(S r, S half_h) : radius(r), half_height(half_h) {
        detail::check_sizes("cylinder", r, "radius", half_h, "half height");
    }
    Cylinder(S r, S half_h, detail::unchecked_t) noexcept : radius(r), half_height(half_h) {}
    [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> support(const Vec3<S>& d) const noexcept {
        return detail::disc_support(d, radius, detail::signed_extent(half_height, d.z()));
    }
    /// The same cylinder in the wider type (HasWidened).
    [[nodiscard]] Cylinder<wider_t<S>> widened() const noexcept {
        return {wider_t<S>(radius), wider_t<S>(half_height), detail::unchecked_t{}};
    }
    [[nodiscard]] Vec3<S> center() const noexcept { return Vec3<S>::Zero(); }
    /// Balls about the centre (HasBoundingBalls): through the rims, and touching the side or the caps.
    [[nodiscard]] S bounding_radius() const noexcept {
        return detail::round_up(std::sqrt(radius * radius + half_height * half_height));
    }
    [[nodiscard]] S inner_radius() const noexcept { return std::min(radius, half_height); }
    /// p at least `slack` inside the caps and the side (HasContainmentTest): the shrunk cylinder's test.
    [[nodiscard]] CDKIT_ALWAYS_INLINE bool contains_strictly(const Vec3<S>& p, S slack) const noexcept {
        const S r = radius - slack;
        return (std::abs(p[2]) < half_height - slack) & (r > S(0)) & (p[0] * p[0] + p[1] * p[1] < r * r);
    }
};

/// A solid cone: base disc of radius `radius` at z = -half_height, apex at z = +half_height.
template <class S = double> struct Cone {
    using Scalar = S;
    S radius, half_height;
    Cone(S r, S half_h) : radius(r), half_height(half_h) {
        detail::check_sizes("cone", r, "radius", half_h, "half height");
    }
    Cone(S r, S half_h, detail::unchecked_t) noexcept : radius(r), half_height(half_h) {}
    [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> support(const Vec3<S>& d) const noexcept {
        // The apex wins when d lies inside the cone of normals at the apex: d_z·|side| > r·|d| with the
        // side generator length |side| = sqrt(r² + (2h)²). Squared (d_z > 0) that is 2h·d_z > r·ρ with
        // ρ = |(d_x, d_y)|, the rim's own norm: one sqrt for the whole query instead of three.
        const S rho = detail::planar_norm(d.x(), d.y());
        if (d.z() > S(0) && (S(2) * half_height * d.z() > radius * rho || !(rho > S(0))))
            return {S(0), S(0), half_height};
        if (!(rho > S(0))) return {S(0), S(0), -half_height};
        return {radius * d.x() / rho, radius * d.y() / rho, -half_height};
    }
    /// The same cone in the wider type (HasWidened).
    [[nodiscard]] Cone<wider_t<S>> widened() const noexcept {
        return {wider_t<S>(radius), wider_t<S>(half_height), detail::unchecked_t{}};
    }
    /// The centroid, a quarter of the height above the base.
    [[nodiscard]] Vec3<S> center() const noexcept { return {S(0), S(0), center_z()}; }
    /// Its height (it lies on the axis: GJK places it with one column of the rotation).
    [[nodiscard]] S center_z() const noexcept { return -half_height / S(2); }
    /// Balls about the centroid (HasBoundingBalls): through the apex (1.5 h away) or the rim, whichever is
    /// farther; inside, touching the base (h/2 away) or within the side (1.5 r h / √(4h² + r²) is the distance
    /// from the centroid to the generator line through (r, −h) and (0, h)).
    [[nodiscard]] S bounding_radius() const noexcept {
        const S h = half_height;
        return detail::round_up(std::max(S(1.5) * h, S(std::sqrt(radius * radius + h * h / S(4)))));
    }
    [[nodiscard]] S inner_radius() const noexcept {
        const S h = half_height, r = radius;
        // √(4h² + r²) ≤ 2h + r: a division instead of a sqrt and a division, at most 30 % below the exact ball.
        const S side = S(1.5) * r * h / (S(2) * h + r);
        return detail::round_down(std::min(h / S(2), side == side ? side : S(0)));
    }
    /// p at least `slack` inside the base, below the apex and inside the side (HasContainmentTest). The side's
    /// distance is (r(h − z) − 2hρ)/√(4h² + r²), ρ = |(p_x, p_y)|; √(4h² + r²) ≤ 2h + r keeps it conservative, and
    /// comparing squares (both sides ≥ 0) saves the sqrt.
    [[nodiscard]] CDKIT_ALWAYS_INLINE bool contains_strictly(const Vec3<S>& p, S slack) const noexcept {
        const S h = half_height, r = radius;
        const S q = r * (h - p[2]) - slack * (S(2) * h + r);  // 2h times the largest ρ allowed at height z
        const S two_h = S(2) * h;
        return (std::abs(p[2]) < h - slack) & (q > S(0)) & (two_h * two_h * (p[0] * p[0] + p[1] * p[1]) < q * q);
    }
    /// The outward normal of the face p lies farthest outside of (HasCandidateAxes): the base, −e_z, or the side
    /// at p's azimuth, (2h·u, r) with u = p's direction in the base plane (e_x on the axis). The side's signed
    /// distance is (2hρ + r(z − h))/√(4h² + r²); √(4h² + r²) ≤ 2h + r stands in for the root in the comparison
    /// (it only picks the face). Branch-free: which face wins varies from query to query.
    [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> candidate_axis(const Vec3<S>& p) const noexcept {
        const S h = half_height, r = radius;
        const S rho = detail::planar_norm(p[0], p[1]);
        const bool axial = !(rho > S(0));
        const S ux = axial ? S(1) : p[0] / rho, uy = axial ? S(0) : p[1] / rho;
        const bool base = (-p[2] - h) * (S(2) * h + r) > S(2) * h * rho + r * (p[2] - h);
        const S side = base ? S(0) : S(2) * h;
        return {side * ux, side * uy, base ? S(-1) : r};
    }
};

/// A solid axis-aligned ellipsoid with semi-axes `radii`.
template <class S = double> struct Ellipsoid {
    using Scalar = S;
    static constexpr bool centered_at_origin = true;  ///< center() is the origin (saves GJK a transform)
    Vec3<S> radii;
    explicit Ellipsoid(const Vec3<S>& r) : radii(r) {
        detail::check_sizes("ellipsoid", r[0], "radius", r[1], "radius", r[2], "radius");
    }
    Ellipsoid(const Vec3<S>& r, detail::unchecked_t) noexcept : radii(r) {}
    [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> support(const Vec3<S>& d) const noexcept {
        // argmax d·x on x = D u, |u| = 1 is D (D d)/|D d| with D = diag(radii).
        // Per component (Eigen's packet norm reloaded d, just written by GJK, through a stalled 16-byte load).
        const S x = radii.x() * d.x(), y = radii.y() * d.y(), z = radii.z() * d.z();
        const S n = std::sqrt(x * x + y * y + z * z);
        if (!(n > S(0))) return {S(0), S(0), radii.z()};
        const S inv = S(1) / n;  // one division instead of three
        return {radii.x() * x * inv, radii.y() * y * inv, radii.z() * z * inv};
    }
    [[nodiscard]] Vec3<S> center() const noexcept { return Vec3<S>::Zero(); }
    /// The same ellipsoid in the wider type (HasWidened).
    [[nodiscard]] Ellipsoid<wider_t<S>> widened() const noexcept {
        return {radii.template cast<wider_t<S>>(), detail::unchecked_t{}};
    }
    /// Balls about the centre (HasBoundingBalls): of the largest and of the smallest semi-axis.
    [[nodiscard]] S bounding_radius() const noexcept { return std::max({radii[0], radii[1], radii[2]}); }
    [[nodiscard]] S inner_radius() const noexcept { return std::min({radii[0], radii[1], radii[2]}); }
};

/// A triangle (flat convex set) with vertices a, b, c in the local frame.
template <class S = double> struct ConvexTriangle {
    using Scalar = S;
    static constexpr bool polytope_core = true;  ///< HasPolytopeCore: its support is an exact vertex
    Vec3<S> a, b, c;
    ConvexTriangle(const Vec3<S>& a_, const Vec3<S>& b_, const Vec3<S>& c_) : a(a_), b(b_), c(c_) {
        detail::check_point(a, "triangle", "vertex a");
        detail::check_point(b, "triangle", "vertex b");
        detail::check_point(c, "triangle", "vertex c");
    }
    [[nodiscard]] CDKIT_ALWAYS_INLINE Vec3<S> support(const Vec3<S>& d) const noexcept {
        S da = d.dot(a), db = d.dot(b), dc = d.dot(c);
        if (da >= db && da >= dc) return a;
        return db >= dc ? b : c;
    }
    [[nodiscard]] Vec3<S> center() const noexcept { return (a + b + c) / S(3); }
    /// Balls about center() (HasBoundingBalls): through the farthest vertex; flat, so no inner ball (the
    /// centre itself is a point of the triangle, up to its rounding, which the caller's slack covers).
    [[nodiscard]] S bounding_radius() const noexcept {
        const Vec3<S> m = center();
        const S r2 = std::max({(a - m).squaredNorm(), (b - m).squaredNorm(), (c - m).squaredNorm()});
        return detail::round_up(std::sqrt(r2));
    }
    [[nodiscard]] S inner_radius() const noexcept { return S(0); }
};

}  // namespace cdkit
