#pragma once
/// \file The long-double retry shared by GJK's near-contact refinement (`refine_near_contact`) and EPA's
/// (`refine_penetration`): the shapes seen in `wider_t`, the frame with A's origin, the settings carried over with
/// the narrow type's touching tolerance, and when a double distance is refined.

#include <cdkit/narrowphase/gjk/types.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace cdkit {
namespace detail {

/// A shape seen in the wider type of `refine_near_contact`: the directions are rounded to the shape's own type,
/// its support points widened exactly. For a primitive the points are the shape's own (a rounded direction picks a
/// point optimal for a direction within an ulp's angle); a wrapper's (Transformed, Inflated) carry its own double
/// rounding.
template <SupportMapped A> struct WidenedShape {
    using Narrow = typename A::Scalar;
    using Scalar = wider_t<Narrow>;
    const A* shape;
    [[nodiscard]] Vec3<Scalar> support(const Vec3<Scalar>& d) const noexcept {
        return Vec3<Narrow>(shape->support(d.template cast<Narrow>())).template cast<Scalar>();
    }
    [[nodiscard]] Vec3<Scalar> center() const noexcept { return Vec3<Narrow>(shape->center()).template cast<Scalar>(); }
    [[nodiscard]] Scalar margin() const noexcept
        requires HasMargin<A>
    {
        return Scalar(shape->margin());
    }
    [[nodiscard]] Vec3<Scalar> core_support(const Vec3<Scalar>& d) const noexcept
        requires HasMargin<A>
    {
        return Vec3<Narrow>(shape->core_support(d.template cast<Narrow>())).template cast<Scalar>();
    }
};

/// `s` in its scalar's wider type: `s.widened()` where the shape has it, else a `WidenedShape` view.
template <SupportMapped A> [[nodiscard]] auto widened_shape(const A& s) noexcept {
    if constexpr (HasWidened<A>) {
        return s.widened();
    } else {
        return WidenedShape<A>{&s};
    }
}

/// The poses of a double query's retry in `wider_t` (`refine_near_contact`, EPA's `refine_penetration`): world axes
/// with the origin moved to A's, so that B's offset t_b − t_a is exact or nearly in the wider type and the rounding
/// stays ε_W of the relative coordinates, however far from the world's origin the shapes are.
template <class S> struct WideningFrame {
    using W = wider_t<S>;
    Vec3<W> origin;          ///< A's position: add it to the retry's world points
    Transform<W> pose_a;     ///< A's rotation, at the origin
    Transform<W> pose_b;     ///< B's rotation, at t_b − t_a
    WideningFrame(const Transform<S>& a, const Transform<S>& b)
        : origin(a.t.template cast<W>()),
          pose_a(a.R.template cast<W>(), Vec3<W>::Zero()),
          pose_b(b.R.template cast<W>(), Vec3<W>(b.t.template cast<W>() - origin)) {}
};

/// S's touching tolerance factor (tf·ε_S) in units of the wider type's ε: a retry does not call a pair separated
/// below the threshold the S query applies.
template <class S> [[nodiscard]] inline wider_t<S> widened_touch_factor(S touch_factor) noexcept {
    using W = wider_t<S>;
    return W(touch_factor) * W(std::numeric_limits<S>::epsilon()) / std::numeric_limits<W>::epsilon();
}

/// True when a separated distance query in double should be refined in long double (`refine_near_contact`).
/// `magnitude`: of the coordinates the loop worked with in A's frame, |t_rel|₁ + size (size = the largest |w|);
/// they carry rounding of about ε·magnitude (the relative pose, B's points mapped into A's frame). Measured
/// (docs/convex.md), the double answer is off by up to ~24ε·magnitude/distance where a core is curved (the loop
/// stops at its convergence floor: 1e-8 relative at a distance of 1e-7 between shapes 0.4 apart) and ~ε·magnitude/
/// distance on two polytope cores (it ends on the closest simplex; only the final rounding): refine where 32 and 2
/// times that exceed the tolerance. The distance, not the cores' |v|: a margin (capsule, sphere) leaves |v|'s
/// absolute rounding on a distance that is much smaller. Also refined: a loop that stopped short of its tolerance
/// (`tolerance_met` false: gap above 4× the tolerance at a repeated point, no progress or the rounding floor of
/// v·w, which is ε·size², not ε·magnitude, where D is long and thin: a needle pair came out 5e-9 relative too far).
template <SupportMapped A, SupportMapped B>
[[nodiscard]] inline bool near_contact_needs_refinement(const GjkSettings<typename A::Scalar>& settings,
                                                        const GjkResult<typename A::Scalar>& r,
                                                        typename A::Scalar magnitude, bool tolerance_met) noexcept {
    using S = typename A::Scalar;
    constexpr S floor = HasPolytopeCore<A> && HasPolytopeCore<B> ? S(2) : S(32);
    return settings.refine_near_contact && r.status == GjkStatus::separated &&
           (!tolerance_met ||
            floor * std::numeric_limits<S>::epsilon() * magnitude > settings.rel_tolerance * r.distance);
}

/// Whether queries in S have a near-contact refinement: double, where long double is wider (x87 or quad).
template <class S>
inline constexpr bool refines_near_contact =
    std::is_same_v<S, double> && std::numeric_limits<long double>::digits > std::numeric_limits<double>::digits;

/// `settings` in the wider type of a retry (`refine_near_contact`, EPA's `refine_penetration`): the same iteration cap
/// and relative tolerance, the touching tolerance of S (`widened_touch_factor`), every other field at its default.
template <class S>
[[nodiscard]] inline GjkSettings<wider_t<S>> widened_settings(const GjkSettings<S>& settings) noexcept {
    using W = wider_t<S>;
    GjkSettings<W> ws;
    ws.max_iterations = settings.max_iterations;
    ws.rel_tolerance = W(settings.rel_tolerance);
    ws.touch_factor = widened_touch_factor(settings.touch_factor);
    return ws;
}

}  // namespace detail
}  // namespace cdkit
