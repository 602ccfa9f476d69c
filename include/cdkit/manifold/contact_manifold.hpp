#pragma once
/// \file Contact manifolds of convex pairs: up to four contact points sharing one normal, so that a box resting on
/// a box is held at its corners instead of rocking on one point.
///
/// The method (the one of box2d and Jolt, in 3-D): GJK decides the pair (warm-started from the caller's cache; with a
/// margin the same search also measures a pair apart by at most the margin, gjk_distance_within),
/// EPA, started from GJK's final simplex, gives the penetration normal n (van den Bergen, GDC 2001); then each shape's supporting feature along the
/// normal (A's along n, B's along −n: face, edge or vertex, feature.hpp) is found, the better aligned face becomes
/// the reference, and the other feature is clipped to the prism over it (detail/clip.hpp, Sutherland–Hodgman). Every
/// clipped point whose height over the reference plane is at most the margin is a contact point, its depth that
/// height negated, its partner its projection on the reference face; more than four are reduced to the deepest
/// and those spanning the largest area. Two edges (a capsule lying along a box edge, two parallel capsules) clip
/// one to the slab of the other. A vertex feature on either side (a sphere, a corner) gives EPA's single point.
/// Two overlapping boxes skip GJK and EPA: the separating-axis test gives the normal and depth (detail/box_box.hpp).
///
/// Ids hash the reference feature, the incident feature and the clipping plane or vertex that made a point:
/// they stay equal while the same features touch, which is what a solver needs to warm-start its impulses.
/// Const, noexcept, thread-safe; the only mutable state is the caller's GJK cache.

#include "cdkit/manifold/detail/box_box.hpp"
#include "cdkit/manifold/detail/clip.hpp"
#include "cdkit/manifold/result.hpp"
#include "cdkit/narrowphase/epa.hpp"
#include "cdkit/narrowphase/gjk.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <type_traits>

namespace cdkit {

namespace detail {

/// Gives each point of `m` last frame's id where it has one: the same id, else the nearest old point within
/// `reach` (A's frame) not taken yet. Then stores `m` as the new last frame.
template <class S>
void carry_ids(ContactManifold<S>& m, const Transform<S>& pose_a, ManifoldCache<S>& cache) noexcept {
    std::array<Vec3<S>, 4> local{};
    S diameter = S(0);
    for (int i = 0; i < m.count; ++i) {
        local[i] = pose_a.R.transpose() * (m.points[i].point_a - pose_a.t);
        for (int j = 0; j < i; ++j) diameter = std::max(diameter, S((local[i] - local[j]).squaredNorm()));
    }
    const S reach2 = diameter / S(100);  // (a tenth of the patch)²
    std::array<bool, 4> taken{};
    std::array<bool, 4> matched{};
    for (int i = 0; i < m.count; ++i)
        for (int j = 0; j < cache.count; ++j)
            if (!taken[j] && cache.ids[j] == m.points[i].id) taken[j] = matched[i] = true;
    for (int i = 0; i < m.count; ++i) {
        if (matched[i]) continue;
        int best = -1;
        S best_d = reach2;
        for (int j = 0; j < cache.count; ++j) {
            const S d = (cache.local_a[j] - local[i]).squaredNorm();
            if (!taken[j] && d <= best_d) best_d = d, best = j;
        }
        if (best >= 0) {
            taken[best] = matched[i] = true;
            m.points[i].id = cache.ids[best];
        }
    }
    for (int i = 0; i < m.count; ++i) {
        m.stats.kept_ids += matched[i];
        // An id already given to an earlier point (two clipped points from the same features): make it unique.
        for (int j = 0; j < i; ++j)
            if (m.points[j].id == m.points[i].id) m.points[i].id = contact_id(m.points[i].id, std::uint64_t(i), 0);
    }
    cache.count = m.count;
    for (int i = 0; i < m.count; ++i) cache.local_a[i] = local[i], cache.ids[i] = m.points[i].id;
}

}  // namespace detail

/// The contact manifold of shape `a` at `pose_a` and shape `b` at `pose_b` (any support-mapped shapes; faces, edges
/// and the flat parts of curved shapes give several points, see the file comment). `cache` (optional, caller-owned,
/// one per pair) warm-starts GJK and keeps the points' ids from frame to frame (ManifoldCache). A pose that is not a finite rigid motion gives `QueryStatus::invalid_pose`, a
/// negative or non-finite margin or a feature angle outside [0, π/4] `invalid_input`, and an empty manifold.
template <SupportMapped A, SupportMapped B>
    requires std::same_as<typename A::Scalar, typename B::Scalar>
[[nodiscard]] ContactManifold<typename A::Scalar> contact_manifold(const A& a, const Transform<typename A::Scalar>& pose_a,
                                                                   const B& b, const Transform<typename A::Scalar>& pose_b,
                                                                   const ManifoldRequest& request = {},
                                                                   ManifoldCache<typename A::Scalar>* cache = nullptr) noexcept {
    using S = typename A::Scalar;
    ContactManifold<S> m;
    if (!pose_is_usable(pose_a) || !pose_is_usable(pose_b)) {
        m.status = QueryStatus::invalid_pose;
        return m;
    }
    if (!(request.margin >= 0) || !std::isfinite(request.margin) || !(request.feature_angle >= 0) ||
        !(request.feature_angle <= std::numbers::pi / 4)) {
        m.status = QueryStatus::invalid_input;
        return m;
    }
    if constexpr (std::is_same_v<A, Box<S>> && std::is_same_v<B, Box<S>>) {  // two boxes: the axis test, no GJK/EPA
        if (!request.single_point) {
            const detail::BoxBoxOutcome o = detail::box_box_manifold(a, pose_a, b, pose_b, S(request.margin), m);
            if (o == detail::BoxBoxOutcome::done) {
                if (cache) detail::carry_ids(m, pose_a, *cache);
                return m;
            }
            m = ContactManifold<S>{};  // apart (GJK measures how far) or a touching clip that kept nothing (EPA)
        }
    }
    GjkCache<S>* gjk_cache = cache ? &cache->gjk : nullptr;
    // With a margin one search says both whether the pair collides and, when it is apart by at most the margin, how
    // far (gjk_distance_within: the boolean's plane exit beyond the margin, else on to the distance from the same
    // simplex); a boolean followed by a distance query paid for GJK twice on those pairs.
    const bool speculative = request.margin > 0;
    const GjkResult<S> g = speculative ? gjk_distance_within(a, pose_a, b, pose_b, S(request.margin), gjk_cache)
                                       : gjk_intersect(a, pose_a, b, pose_b, gjk_cache);
    m.stats.gjk_iterations = g.iterations;
    ManifoldPoint<S> deepest;
    Vec3<S> n;
    if (g.colliding) {
        // EPA from GJK's final tetrahedron where GJK ended on one, so the pair pays for GJK once.
        const PenetrationResult<S> p = penetration(a, pose_a, b, pose_b, g);
        m.stats.gjk_iterations += p.gjk_iterations;
        m.stats.epa_iterations = p.epa_iterations;
        m.colliding = true;
        n = p.normal;
        deepest = {p.point_a, p.point_b, p.status == GjkStatus::intersecting ? p.depth : S(0), 0};
    } else {
        m.distance = g.distance;  // beyond the margin: a lower bound
        if (!speculative || g.distance > S(request.margin)) {
            if (cache) cache->count = 0;
            return m;
        }
        n = g.normal;
        deepest = {g.point_a, g.point_b, -g.distance, 0};
    }
    if (!n.allFinite() || !(n.squaredNorm() > S(0.5))) {  // touching at a point EPA gave no direction for
        n = detail::safe_normalized(Vec3<S>(pose_b * Vec3<S>(b.center()) - pose_a * Vec3<S>(a.center())));
        if (!(n.squaredNorm() > S(0.5))) n = Vec3<S>(S(0), S(0), S(1));
    }
    if (request.single_point) {  // EPA's witness pair alone: no features (one point per pair, one fixed id)
        m.normal = n;
        m.count = 1;
        deepest.id = detail::contact_id(0, 0, 0xFFFFFFFFull);
        m.points[0] = deepest;
        if (cache) detail::carry_ids(m, pose_a, *cache);
        return m;
    }
    const detail::FeatureTolerance<S> tol(request.feature_angle);
    const detail::ContactFeature<S> fa = detail::supporting_feature(a, pose_a, n, tol);
    const detail::ContactFeature<S> fb = detail::supporting_feature(b, pose_b, Vec3<S>(-n), tol);
    if (fa.count == 1 || fb.count == 1 || !detail::clip_features(fa, fb, n, S(request.margin), m)) {
        m.normal = n;
        m.count = 1;
        deepest.id = detail::contact_id(std::uint64_t(fa.index) << 1, fb.index, 0xFFFFFFFFull);
        m.points[0] = deepest;
    }
    if (cache) detail::carry_ids(m, pose_a, *cache);
    return m;
}

}  // namespace cdkit
