#pragma once
/// \file penetration_depth(): depth and normal of two intersecting triangle meshes, with or without inner sphere
/// trees.
///
/// The depth along a direction is directional_depth()'s (the translation of B along it that undoes every crossing of
/// the surfaces: always a translation that separates them, so never below the true translational penetration depth
/// along that line). What this file adds is the choice of direction; the shortest of the candidates wins:
///   - with inner sphere trees (Weller, Zachmann, "Inner sphere trees for proximity and penetration queries", RSS
///     2009): the direction of the penalty force on B, Σ over overlapping inner-sphere pairs of lens volume × centre
///     direction (penalty_force.hpp). It is continuous in the pose (each pair's volume vanishes as it separates), and
///     comes with the penetration volume;
///   - from the surfaces alone: the normal of the intersection curve, Σ over crossing triangle pairs of the segment's
///     length × (n_A − n_B), n the triangles' unit normals. For closed meshes oriented outwards it points the way B
///     leaves A (on a face crossing a face it is the faces' normal). Open meshes need consistent orientation for it;
///     otherwise pass a direction;
///   - when the curve's normal vanishes (its terms cancel), the line from the crossing's centre to B's centre.
/// refine_steps > 0 then searches globally (32 directions spread over the sphere: directional depth has local minima)
/// and locally around the best (a pattern search: four tilts by an angle that starts at 0.5 rad; a tilt that shortens
/// the depth becomes the new centre, and when none does the angle halves, refine_steps times). The minimum over all
/// directions is the translational penetration depth, and every step can only come closer to it from above. A
/// direction whose fixed-point frontier passes the best depth so far is abandoned. Const and thread-safe.

#include "cdkit/ist/inner_sphere_tree.hpp"
#include "cdkit/ist/penalty_force.hpp"
#include "cdkit/mesh_depth/directional_depth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace cdkit {

namespace detail {

/// The direction of the intersection curve (A's frame): Σ |segment|·(n_A − n_B) over the pairs that cross now, or the
/// centre line when it vanishes. False when nothing crosses. Adds collide()'s counters to `stats`.
template <class BV, class M>
[[nodiscard]] bool surface_direction(const DepthSearch<BV, M>& search, const MeshModel<BV, M>& a, const MeshModel<BV, M>& b,
                                     const Transform<double>& rel, Vec3<double>& d, DepthDirection& source,
                                     TraversalStats& stats) {
    const CollisionResult<M>& c = search.crossing();
    stats.bv_tests += c.stats.bv_tests;
    stats.leaf_pairs += c.stats.leaf_pairs;
    stats.primitive_tests += c.stats.primitive_tests;
    if (!c.colliding || c.contacts.empty()) return false;
    const auto unit_normal = [](const TriangleMesh<M>& m, Index t, const Mat3<double>& R) {
        const Triangle& tri = m.triangles[t];
        const Vec3<double> v0 = m.vertices[tri[0]].template cast<double>(), v1 = m.vertices[tri[1]].template cast<double>(),
                           v2 = m.vertices[tri[2]].template cast<double>();
        const Vec3<double> n = R * (v1 - v0).cross(v2 - v0);
        return n.norm() > 0 ? Vec3<double>(n.normalized()) : Vec3<double>::Zero();
    };
    Vec3<double> sum = Vec3<double>::Zero(), centre = Vec3<double>::Zero();
    for (const Contact<M>& k : c.contacts) {
        const double w = (k.segment[1] - k.segment[0]).template cast<double>().norm();
        sum += w * (unit_normal(a.mesh(), k.triangle_a, Mat3<double>::Identity()) - unit_normal(b.mesh(), k.triangle_b, rel.R));
        centre += k.point.template cast<double>();
    }
    centre /= double(c.contacts.size());
    const double scale = std::max(1.0, double(c.contacts.size()));
    if (sum.norm() > 1e-9 * scale) {
        d = sum.normalized();
        source = DepthDirection::surface_normal;
        return true;
    }
    Vec3<double> mid = Vec3<double>::Zero();
    for (const auto& v : b.mesh().vertices) mid += v.template cast<double>();
    mid = rel * Vec3<double>(mid / double(std::max<std::size_t>(1, b.mesh().vertices.size())));
    d = mid - centre;
    if (!(d.norm() > 0)) d = Vec3<double>::UnitZ();
    d.normalize();
    source = DepthDirection::centre_line;
    return true;
}

/// Candidate directions (A's frame) in order, then the refinement; writes the shortest answer into `out`.
template <class BV, class M>
void shortest_depth(DepthSearch<BV, M>& search, const Transform<double>& pa,
                    const std::vector<std::pair<Vec3<double>, DepthDirection>>& candidates, const MeshDepthRequest& request,
                    MeshDepthResult& out) {
    DirectionDepth best;
    Vec3<double> best_d = Vec3<double>::Zero();
    DepthDirection best_source = DepthDirection::none;
    double cap = std::numeric_limits<double>::infinity();
    const auto consider = [&](const Vec3<double>& d, DepthDirection source) {
        const DirectionDepth r = search.along(d, request.max_passes, cap, out.stats);
        if (!r.colliding || r.passed_cap || !r.complete || !(r.depth < cap)) {
            if (best_source == DepthDirection::none && r.colliding) best = r, best_d = d, best_source = source;
            return;
        }
        best = r, best_d = d, best_source = source, cap = r.depth;
    };
    for (const auto& [d, source] : candidates) {
        consider(d, source);
        if (best_source == DepthDirection::none) return;  // the surfaces do not cross (same for every direction)
    }
    // Directional depth has local minima (a limb that must clear another): before the local search, a coarse global
    // one over 32 directions spread over the sphere (Fibonacci lattice), each abandoned once it passes the best.
    // They go in the order of their lower bound (the crossing pairs' intervals alone), the most promising first, and
    // a direction whose bound already passes the best depth is not searched at all.
    if (request.refine_steps > 0) {
        constexpr int coarse = 32;
        const double golden = 3.14159265358979323846 * (3 - std::sqrt(5.0));
        std::vector<std::pair<double, Vec3<double>>> spread;
        for (int i = 0; i < coarse; ++i) {
            const double z = 1 - (2 * i + 1) / double(coarse), r = std::sqrt(std::max(0.0, 1 - z * z));
            const Vec3<double> d(r * std::cos(golden * i), r * std::sin(golden * i), z);
            spread.emplace_back(search.first_frontier(d, out.stats), d);
        }
        std::sort(spread.begin(), spread.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        for (const auto& [bound, d] : spread)
            if (bound < cap) consider(d, DepthDirection::refined);
    }
    // Pattern search on the sphere: four tilts of the best direction; a tilt that shortens the depth becomes the
    // centre and the same angle is tried again (at most 4 moves per angle), otherwise the angle halves.
    double angle = 0.5;
    for (int step = 0; step < request.refine_steps; ++step, angle *= 0.5)
        for (int move = 0; move < 4; ++move) {
            const Vec3<double> centre = best_d, u = centre.unitOrthogonal(), v = centre.cross(u);
            for (const Vec3<double>& axis : {u, v, Vec3<double>(-u), Vec3<double>(-v)})
                consider(Vec3<double>(std::cos(angle) * centre + std::sin(angle) * axis).normalized(), DepthDirection::refined);
            if (best_d == centre) break;
        }
    store_direction(best, best_d, pa, best_source, out);
}

/// Both overloads of penetration_depth(): the candidates (the trees' force direction when given, then the surface
/// normal) and the shortest answer.
template <class BV, class M>
[[nodiscard]] MeshDepthResult penetration_depth(const MeshModel<BV, M>& a, const InnerSphereTree* ist_a,
                                                const Transform<M>& pose_a, const MeshModel<BV, M>& b,
                                                const InnerSphereTree* ist_b, const Transform<M>& pose_b,
                                                const MeshDepthRequest& request) {
    if (request.direction) return directional_depth(a, pose_a, b, pose_b, *request.direction, request);
    MeshDepthResult out;
    Transform<double> pa, rel;
    out.status = depth_setup(pose_a, pose_b, pa, rel);
    if (out.status != QueryStatus::ok) return out;
    std::vector<std::pair<Vec3<double>, DepthDirection>> candidates;
    if (ist_a && ist_b) {
        const Transform<double> pb = pa * rel;
        const PenetrationVolumeResult v = penetration_volume(*ist_a, pa, *ist_b, pb);
        out.volume = v.volume;
        const PenaltyWrench w = penalty_wrench(v, *ist_a, pa, *ist_b, pb, 1.0, pa.t, pb.t);
        if (w.on_b.force.norm() > 0) {
            out.force_direction = w.on_b.force.normalized();
            candidates.emplace_back(pa.R.transpose() * out.force_direction, DepthDirection::ist_force);
        }
    }
    DepthSearch<BV, M> search(a, b, rel);
    Vec3<double> d;
    DepthDirection source = DepthDirection::none;
    if (!surface_direction(search, a, b, rel, d, source, out.stats.traversal)) return out;
    candidates.emplace_back(d, source);
    shortest_depth(search, pa, candidates, request, out);
    return out;
}

}  // namespace detail

/// Depth and normal of meshes `a` (at `pose_a`) and `b` (at `pose_b`) from their surfaces (see the file comment);
/// with request.direction set, the depth along that direction only. Not colliding (depth 0) when no triangles cross.
/// Status invalid_pose / invalid_input as directional_depth(). Const and thread-safe.
template <class BV, class M>
[[nodiscard]] MeshDepthResult penetration_depth(const MeshModel<BV, M>& a, const std::type_identity_t<Transform<M>>& pose_a,
                                                const MeshModel<BV, M>& b, const std::type_identity_t<Transform<M>>& pose_b,
                                                const MeshDepthRequest& request = {}) {
    return detail::penetration_depth(a, nullptr, pose_a, b, nullptr, pose_b, request);
}

/// As above, with each mesh's inner sphere tree (built from the same mesh, in the same model frame): the penalty
/// force direction is the first candidate, and the result also carries the penetration volume and that direction.
/// Where no inner spheres overlap (a shallow contact between the packings' surface gaps) the surfaces alone decide.
/// The volume is reported even when no surfaces cross (one mesh wholly inside the other: colliding false, no depth).
template <class BV, class M>
[[nodiscard]] MeshDepthResult penetration_depth(const MeshModel<BV, M>& a, const InnerSphereTree& ist_a,
                                                const std::type_identity_t<Transform<M>>& pose_a,
                                                const MeshModel<BV, M>& b, const InnerSphereTree& ist_b,
                                                const std::type_identity_t<Transform<M>>& pose_b,
                                                const MeshDepthRequest& request = {}) {
    return detail::penetration_depth(a, &ist_a, pose_a, b, &ist_b, pose_b, request);
}

}  // namespace cdkit
