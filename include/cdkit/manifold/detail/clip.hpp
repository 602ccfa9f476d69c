#pragma once
/// \file Clipping of an incident feature against a reference face, and the reduction of a contact polygon to four
/// points. The incident face (or edge, or vertex) is cut by the planes through the reference face's edges that
/// stand perpendicular to it (Sutherland, Hodgman, "Reentrant polygon clipping", CACM 1974), so what remains
/// lies over the reference face; each remaining point's height over the reference plane is its separation. The
/// reduction keeps the deepest point and then the points that span the largest area (the choice of box2d and
/// Bullet's persistent manifolds): a solver supports the body over the whole contact patch with four points.

#include "cdkit/manifold/detail/feature.hpp"
#include "cdkit/manifold/result.hpp"

#include <algorithm>
#include <array>
#include <cstdint>

namespace cdkit::detail {

/// A point of a clipped polygon with the key of the features that made it.
template <class S> struct ClipVertex {
    Vec3<S> p;
    std::uint32_t key;
};

/// A polygon under clipping: the incident feature's vertices and, for each plane, at most one new vertex per edge.
template <class S> struct ClipPolygon {
    static constexpr int capacity = 2 * ContactFeature<S>::capacity + 2;
    std::array<ClipVertex<S>, capacity> v;
    int n = 0;
    void push(const Vec3<S>& p, std::uint32_t key) noexcept {
        if (n < capacity) v[n++] = {p, key};
    }
};

/// Keeps the part of `in` with m·p ≤ offset; `plane` numbers the plane for the new vertices' keys.
template <class S>
void clip_by_plane(const ClipPolygon<S>& in, ClipPolygon<S>& out, const Vec3<S>& m, S offset, std::uint32_t plane) noexcept {
    out.n = 0;
    if (in.n == 0) return;
    const auto crossing = [&](const ClipVertex<S>& a, S da, const ClipVertex<S>& b, S db) {
        const S t = da / (da - db);
        const std::uint32_t key = ((plane + 1) << 20) ^ (a.key << 10) ^ b.key;
        out.push(a.p + t * (b.p - a.p), key | 0x80000000u);
    };
    if (in.n == 1) {
        if (m.dot(in.v[0].p) <= offset) out.push(in.v[0].p, in.v[0].key);
        return;
    }
    if (in.n == 2) {  // a segment stays a segment
        const S d0 = m.dot(in.v[0].p) - offset, d1 = m.dot(in.v[1].p) - offset;
        if (d0 <= 0) out.push(in.v[0].p, in.v[0].key);
        if ((d0 < 0) != (d1 < 0) && d0 != d1) crossing(in.v[0], d0, in.v[1], d1);
        if (d1 <= 0) out.push(in.v[1].p, in.v[1].key);
        if (out.n == 3) out.n = 2;  // an end on the plane and a crossing at it: the same point
        return;
    }
    const ClipVertex<S>* prev = &in.v[in.n - 1];
    S dp = m.dot(prev->p) - offset;
    for (int i = 0; i < in.n; ++i) {
        const ClipVertex<S>& cur = in.v[i];
        const S dc = m.dot(cur.p) - offset;
        if (dc <= 0) {
            if (dp > 0) crossing(*prev, dp, cur, dc);
            out.push(cur.p, cur.key);
        } else if (dp <= 0 && dp != dc) {
            crossing(*prev, dp, cur, dc);
        }
        prev = &cur;
        dp = dc;
    }
}

/// Clips `incident` to the prism over the reference face `ref` (a polygon, counter-clockwise about its outward
/// normal). The result is in `out`.
template <class S>
void clip_to_face(const ContactFeature<S>& ref, const ContactFeature<S>& incident, ClipPolygon<S>& out) noexcept {
    ClipPolygon<S> tmp;
    ClipPolygon<S>* src = &out;
    ClipPolygon<S>* dst = &tmp;
    src->n = 0;
    for (int i = 0; i < incident.count; ++i) src->push(incident.points[i], incident.keys[i]);
    for (int k = 0; k < ref.count && src->n > 0; ++k) {
        const Vec3<S>& a = ref.points[k];
        const Vec3<S>& b = ref.points[(k + 1) % ref.count];
        const Vec3<S> m = (b - a).cross(ref.normal);  // outward side of edge a → b
        clip_by_plane(*src, *dst, m, m.dot(a), std::uint32_t(k));
        std::swap(src, dst);
    }
    if (src != &out) out = *src;
}

/// Clips the incident segment to the slab over the reference segment [a, b].
template <class S>
void clip_to_segment(const ContactFeature<S>& ref, const ContactFeature<S>& incident, ClipPolygon<S>& out) noexcept {
    ClipPolygon<S> in, tmp;
    for (int i = 0; i < incident.count; ++i) in.push(incident.points[i], incident.keys[i]);
    const Vec3<S> u = ref.points[1] - ref.points[0];
    clip_by_plane(in, tmp, u, u.dot(ref.points[1]), 0);
    clip_by_plane(tmp, out, Vec3<S>(-u), -u.dot(ref.points[0]), 1);
}

/// A candidate contact: its point on the incident feature and its partner on the reference, its separation along
/// the normal, its key.
template <class S> struct CandidatePoint {
    Vec3<S> p, on_ref;
    S separation;
    std::uint32_t key;
};

/// Indices of at most four of `c` (n > 4 of them): the deepest, the one farthest from it, the one that makes the
/// largest triangle with those, and the one that adds the most area outside that triangle (areas in the plane
/// ⟂ normal).
template <class S>
int reduce_to_four(const CandidatePoint<S>* c, int n, const Vec3<S>& normal, std::array<int, 4>& keep) noexcept {
    int i0 = 0;
    for (int i = 1; i < n; ++i)
        if (c[i].separation < c[i0].separation) i0 = i;
    int i1 = -1;
    S far = S(-1);
    for (int i = 0; i < n; ++i) {
        const S d = (c[i].p - c[i0].p).squaredNorm();
        if (i != i0 && d > far) far = d, i1 = i;
    }
    keep = {i0, i1, -1, -1};
    if (i1 < 0 || !(far > S(0))) return 1;
    const auto area = [&](int a, int b, int q) { return normal.dot((c[b].p - c[a].p).cross(c[q].p - c[a].p)); };
    int i2 = -1;
    S best = S(0);
    for (int i = 0; i < n; ++i) {
        const S a = std::abs(area(i0, i1, i));
        if (a > best) best = a, i2 = i;
    }
    if (i2 < 0) return 2;
    if (area(i0, i1, i2) < 0) std::swap(i1, i2);  // counter-clockwise about the normal
    keep = {i0, i1, i2, -1};
    int i3 = -1;
    best = S(0);
    for (int i = 0; i < n; ++i) {
        // The area the point adds: the largest triangle it makes with an edge it lies outside of.
        const S a = -std::min({area(i0, i1, i), area(i1, i2, i), area(i2, i0, i)});
        if (a > best) best = a, i3 = i;
    }
    if (i3 < 0) return 3;
    keep[3] = i3;
    return 4;
}

/// One 64-bit id from the features that made a point (splitmix64's finaliser over a running combination).
[[nodiscard]] inline std::uint64_t contact_id(std::uint64_t ref, std::uint64_t incident, std::uint64_t key) noexcept {
    std::uint64_t x = ref * 0x9E3779B97F4A7C15ull ^ (incident + 0x632BE59BD9B4E019ull) * 0xC2B2AE3D27D4EB4Full ^ key;
    x ^= x >> 30, x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 27, x *= 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

/// The manifold's points from the two features (world frame) along the normal n (A → B); false when clipping
/// leaves none within the margin (the caller then keeps the single point).
template <class S>
bool clip_features(const ContactFeature<S>& fa, const ContactFeature<S>& fb, const Vec3<S>& n, S margin,
                   ContactManifold<S>& m) noexcept {
    bool ref_is_a;
    if (fa.count >= 3 && fb.count >= 3) ref_is_a = fa.normal.dot(n) >= -fb.normal.dot(n) - S(1e-3);  // ties: A
    else if (fa.count >= 3 || fb.count >= 3) ref_is_a = fa.count >= 3;
    else ref_is_a = true;  // two edges
    const ContactFeature<S>& ref = ref_is_a ? fa : fb;
    const ContactFeature<S>& inc = ref_is_a ? fb : fa;
    const Vec3<S> up = ref.count >= 3 ? ref.normal : Vec3<S>(ref_is_a ? n : Vec3<S>(-n));  // out of the reference

    ClipPolygon<S> clipped;
    if (ref.count >= 3) clip_to_face(ref, inc, clipped);
    else clip_to_segment(ref, inc, clipped);
    m.stats.clipped_points = clipped.n;

    std::array<CandidatePoint<S>, ClipPolygon<S>::capacity> cand;
    int nc = 0;
    // The partner on the reference: the projection on the face's plane, or the nearest point of the reference edge.
    const auto on_ref = [&](const Vec3<S>& p) -> Vec3<S> {
        if (ref.count >= 3) return p - up.dot(p - ref.points[0]) * up;
        const Vec3<S> e = ref.points[1] - ref.points[0];
        const S len2 = e.squaredNorm();
        const S t = len2 > S(0) ? std::clamp(S(e.dot(p - ref.points[0]) / len2), S(0), S(1)) : S(0);
        return ref.points[0] + t * e;
    };
    for (int i = 0; i < clipped.n; ++i) {
        const Vec3<S> r = on_ref(clipped.v[i].p);
        const S s = up.dot(clipped.v[i].p - r);
        if (s <= margin) cand[nc++] = {clipped.v[i].p, r, s, clipped.v[i].key};
    }
    if (nc == 0) return false;
    std::array<int, 4> keep{0, 1, 2, 3};
    const int count = nc > 4 ? reduce_to_four(cand.data(), nc, up, keep) : nc;
    const Vec3<S> normal = ref_is_a ? up : Vec3<S>(-up);
    m.normal = normal;
    m.count = 0;
    for (int k = 0; k < count; ++k) {
        const CandidatePoint<S>& c = cand[keep[k]];
        ManifoldPoint<S>& p = m.points[m.count++];
        p.point_a = ref_is_a ? c.on_ref : c.p;
        p.point_b = ref_is_a ? c.p : c.on_ref;
        p.depth = -c.separation;
        p.id = contact_id((std::uint64_t(ref.index) << 1) | (ref_is_a ? 0u : 1u), inc.index, c.key);
    }
    return true;
}

}  // namespace cdkit::detail
