#pragma once
/// \file The status family: how every cdkit result says whether it holds an answer.
///
/// Every result struct has a `status` field and a `bool colliding` field (rays: `hit`). The status is one of
/// two enums that spell shared meanings the same way:
/// - `QueryStatus` for queries whose answer is a set or a number computed after an input check (mesh collide
///   and distance, inner sphere trees, continuous collision, ray casts): `ok`, or why nothing was computed.
/// - `GjkStatus` for the convex queries (GJK, EPA's input, closest features, separating planes): the
///   geometric class of the answer (`separated` / `touching` / `intersecting`) or why it is only a bound.
/// `colliding` is always the one boolean a caller needs: for convex results it is `is_colliding(status)`.

namespace cdkit {

/// Outcome of a query's input check. Queries refuse poses that are not rigid motions (NaN/Inf, scale,
/// shear, reflection) instead of returning an answer that looks valid but is not: the BV tests assume a
/// rotation, and NaN would make every test false ("no collision").
enum class QueryStatus {
    ok,
    invalid_pose,   ///< a pose failed pose_is_usable(); the result holds no answer
    invalid_input,  ///< an input point, size or setting was NaN, infinite or out of range; no answer
};

/// Outcome of a convex query.
enum class GjkStatus {
    separated,       ///< distance > 0 (beyond the touching tolerance)
    touching,        ///< distance within the touching tolerance of 0: contact, no proven overlap volume
    intersecting,    ///< the shapes overlap (origin strictly inside the Minkowski difference / margins overlap)
    max_iterations,  ///< iteration cap reached; the result holds the best bound found
    degenerate,      ///< numerical trouble (non-finite support point); the result holds the best bound found
};

/// The convex answer as a boolean: touching counts as colliding (conservative for collision detection).
[[nodiscard]] constexpr bool is_colliding(GjkStatus s) noexcept {
    return s == GjkStatus::touching || s == GjkStatus::intersecting;
}

/// Names, for messages and reports ("ok", "invalid_pose", "separated", ...).
[[nodiscard]] constexpr const char* to_string(QueryStatus s) noexcept {
    switch (s) {
        case QueryStatus::ok: return "ok";
        case QueryStatus::invalid_pose: return "invalid_pose";
        case QueryStatus::invalid_input: return "invalid_input";
    }
    return "?";
}
[[nodiscard]] constexpr const char* to_string(GjkStatus s) noexcept {
    switch (s) {
        case GjkStatus::separated: return "separated";
        case GjkStatus::touching: return "touching";
        case GjkStatus::intersecting: return "intersecting";
        case GjkStatus::max_iterations: return "max_iterations";
        case GjkStatus::degenerate: return "degenerate";
    }
    return "?";
}

}  // namespace cdkit
