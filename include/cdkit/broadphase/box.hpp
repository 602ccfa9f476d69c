#pragma once
/// \file The box every broad phase works on: world-space min/max corners, closed intervals (boxes that share
/// a face, an edge or a corner overlap), plus object ids, pairs and the input check shared by all methods.

#include "cdkit/bv/aabb.hpp"
#include "cdkit/core/error.hpp"
#include "cdkit/core/math.hpp"

#include <cmath>
#include <cstdint>
#include <string>

namespace cdkit {

/// Stable handle of an object in a broad phase. Ids are dense small integers; a removed id may be handed out
/// again by a later insert (so per-pair data keyed by ids must be dropped on removal, see InterestMatrix).
using ObjectId = std::uint32_t;

/// World-space axis-aligned box as min/max corners. A point (lo == hi) is a valid box.
template <class S = double> struct BroadBox {
    using Scalar = S;
    Vec3<S> lo = Vec3<S>::Zero();
    Vec3<S> hi = Vec3<S>::Zero();

    /// From cdkit's centre/half-extent box. The corners are computed as centre -/+ half.
    [[nodiscard]] static BroadBox from_aabb(const Aabb<S>& b) noexcept { return {b.min(), b.max()}; }
    /// From a centre and half extents (same rounding as from_aabb).
    [[nodiscard]] static BroadBox from_center_half(const Vec3<S>& c, const Vec3<S>& h) noexcept {
        return {c - h, c + h};
    }
    /// Finite coordinates and lo <= hi on every axis.
    [[nodiscard]] bool is_valid() const noexcept {
        return lo.allFinite() && hi.allFinite() && (lo.array() <= hi.array()).all();
    }
};

/// Closed-interval overlap: touching boxes overlap.
template <class S> [[nodiscard]] inline bool overlap(const BroadBox<S>& a, const BroadBox<S>& b) noexcept {
    return a.lo.x() <= b.hi.x() && b.lo.x() <= a.hi.x() && a.lo.y() <= b.hi.y() && b.lo.y() <= a.hi.y() &&
           a.lo.z() <= b.hi.z() && b.lo.z() <= a.hi.z();
}

/// An unordered pair of objects, stored with a < b.
struct ObjectPair {
    ObjectId a = 0;
    ObjectId b = 0;
    [[nodiscard]] static ObjectPair make(ObjectId x, ObjectId y) noexcept { return x < y ? ObjectPair{x, y} : ObjectPair{y, x}; }
    [[nodiscard]] std::uint64_t key() const noexcept { return (std::uint64_t(a) << 32) | b; }
    friend bool operator==(const ObjectPair&, const ObjectPair&) = default;
    friend bool operator<(const ObjectPair& p, const ObjectPair& q) noexcept { return p.key() < q.key(); }
};

namespace detail {
/// The error for a box that failed check_box (kept out of line: check_box runs on every move).
template <class S> [[noreturn]] void throw_bad_box(const BroadBox<S>& b, const char* op) {
    if (!b.lo.allFinite() || !b.hi.allFinite())
        throw Error("<broadphase>", std::string(op) + " box", "NaN or infinite coordinate");
    throw Error("<broadphase>", std::string(op) + " box", "min > max");
}
/// Bad boxes come from the application, so they raise cdkit::Error where they enter (insert / move).
/// One branch for the common valid box (every move of every frame comes through here): x - x == 0 exactly
/// when x is finite.
template <class S> inline void check_box(const BroadBox<S>& b, const char* op) {
    bool ok = true;
    for (int a = 0; a < 3; ++a) {
        ok &= b.lo[a] - b.lo[a] == S(0);
        ok &= b.hi[a] - b.hi[a] == S(0);
        ok &= b.lo[a] <= b.hi[a];
    }
    if (!ok) [[unlikely]]
        throw_bad_box(b, op);
}
}  // namespace detail

}  // namespace cdkit
