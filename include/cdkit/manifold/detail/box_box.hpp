#pragma once
/// \file Box–box contacts by the separating-axis test: the 15 axes of two boxes (their 3 + 3 face normals and the 9
/// cross products of their edge directions; Gottschalk, Lin, Manocha, "OBBTree", SIGGRAPH 1996) decide overlap, and
/// the axis of least penetration is the contact normal (for two convex polytopes the smallest overlap over these
/// axes is the penetration depth). A face axis gives the face-clipping manifold of clip.hpp; an edge axis one point,
/// the closest points of the two supporting edges. The choice prefers a face axis unless an edge axis is clearly
/// shallower (by 5 %), as box2d and ODE do, so a resting box does not flip between face and edge contacts. No GJK or
/// EPA: about the cost of the node test of an OBB tree plus a clip.

#include "cdkit/manifold/detail/clip.hpp"
#include "cdkit/manifold/result.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace cdkit::detail {

/// What the axis test decided: the boxes are apart along some axis (GJK then measures the distance, which the axes
/// only bound from below), `m` is filled, or a face clip kept no point (rounding at a touching pair: EPA decides).
enum class BoxBoxOutcome { separated, done, use_epa };

/// Fills `m` (colliding, normal, points) when the boxes overlap or touch by the 15-axis test.
template <class S>
BoxBoxOutcome box_box_manifold(const Box<S>& a, const Transform<S>& pose_a, const Box<S>& b, const Transform<S>& pose_b, S margin,
                      ContactManifold<S>& m) noexcept {
    const Mat3<S> R = pose_a.R.transpose() * pose_b.R;  // B's axes in A's frame
    const Vec3<S> t = pose_a.R.transpose() * (pose_b.t - pose_a.t);
    Mat3<S> absR;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) absR(i, j) = std::abs(R(i, j));
    const Vec3<S>& ha = a.half;
    const Vec3<S>& hb = b.half;
    const S scale = std::max(ha.maxCoeff(), hb.maxCoeff());
    // Best (largest) separation over face axes and over edge axes; axes in A's frame.
    S face_sep = -std::numeric_limits<S>::infinity(), edge_sep = -std::numeric_limits<S>::infinity();
    Vec3<S> face_axis = Vec3<S>::UnitZ(), edge_axis = Vec3<S>::UnitZ();
    int edge_i = 0, edge_j = 0;
    const auto face = [&](const Vec3<S>& axis, S ra, S rb) {
        const S s = std::abs(t.dot(axis)) - ra - rb;
        if (s > face_sep) face_sep = s, face_axis = axis;
        return s <= S(0);
    };
    for (int i = 0; i < 3; ++i)
        if (!face(Vec3<S>::Unit(i), ha[i], hb.dot(absR.row(i)))) return BoxBoxOutcome::separated;
    for (int j = 0; j < 3; ++j)
        if (!face(Vec3<S>(R.col(j)), ha.dot(absR.col(j)), hb[j])) return BoxBoxOutcome::separated;
    // Edge axes e_i × (R e_j); near-parallel edges give no axis (their face axes already cover them).
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const Vec3<S> axis = Vec3<S>::Unit(i).cross(Vec3<S>(R.col(j)));
            const S len = axis.norm();
            if (!(len > S(1e-6))) continue;
            const Vec3<S> u = axis / len;
            S ra = S(0), rb = S(0);
            for (int k = 0; k < 3; ++k) {
                ra += ha[k] * std::abs(u[k]);
                rb += hb[k] * std::abs(u.dot(Vec3<S>(R.col(k))));
            }
            const S s = std::abs(t.dot(u)) - ra - rb;
            if (s > S(0)) return BoxBoxOutcome::separated;
            if (s > edge_sep) edge_sep = s, edge_axis = u, edge_i = i, edge_j = j;
        }
    m.colliding = true;
    // A face axis unless an edge axis is clearly shallower.
    const bool use_edge = edge_sep > S(0.95) * face_sep + S(1e-12) * scale;
    Vec3<S> n_local = use_edge ? edge_axis : face_axis;
    if (t.dot(n_local) < S(0)) n_local = -n_local;  // from A towards B
    const Vec3<S> n = pose_a.R * n_local;
    if (!use_edge) {
        // The two boxes' faces along ±n: any face of a box is within 55° of the direction it supports best.
        const FeatureTolerance<S> any_face(std::numbers::pi / 2);
        const ContactFeature<S> fa = supporting_feature(a, pose_a, n, any_face);
        const ContactFeature<S> fb = supporting_feature(b, pose_b, Vec3<S>(-n), any_face);
        return clip_features(fa, fb, n, margin, m) ? BoxBoxOutcome::done : BoxBoxOutcome::use_epa;
    }
    // Edge against edge: one point, the closest points of the two supporting edges (A's along e_i, B's along R e_j),
    // in A's frame.
    Vec3<S> ca = Vec3<S>::Zero(), cb = t;
    for (int k = 0; k < 3; ++k) {
        if (k != edge_i) ca[k] = n_local[k] >= S(0) ? ha[k] : -ha[k];
        if (k != edge_j) {
            const Vec3<S> bk(R.col(k));
            cb -= (bk.dot(n_local) >= S(0) ? hb[k] : -hb[k]) * bk;
        }
    }
    const Vec3<S> da = Vec3<S>::Unit(edge_i), db(R.col(edge_j));
    // Closest points of the lines ca + s·da and cb + u·db, clamped to the edges.
    const Vec3<S> r = ca - cb;
    const S c = da.dot(db), d1 = da.dot(r), d2 = db.dot(r);
    const S den = S(1) - c * c;
    S s = den > S(1e-12) ? (c * d2 - d1) / den : S(0);
    s = std::clamp(s, -ha[edge_i], ha[edge_i]);
    S u = std::clamp(S(c * s + d2), -hb[edge_j], hb[edge_j]);
    s = std::clamp(S(c * u - d1), -ha[edge_i], ha[edge_i]);
    const Vec3<S> pa_local = ca + s * da, pb_local = cb + u * db;
    m.normal = n;
    m.count = 1;
    ManifoldPoint<S>& p = m.points[0];
    p.point_a = pose_a * pa_local;
    p.point_b = pose_a * pb_local;
    p.depth = (p.point_a - p.point_b).dot(n);
    p.id = contact_id(64 + std::uint64_t(edge_i), 64 + std::uint64_t(edge_j), 0xFFFFFFFEull);
    return BoxBoxOutcome::done;
}

}  // namespace cdkit::detail
