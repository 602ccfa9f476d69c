#pragma once
/// \file Narrow-phase dispatch of World: one function that takes two posed Shapes and runs the test that
/// matches their kinds, returning a plain contact struct.
///
///   convex – convex : GJK boolean test (warm-started from the caller's per-pair GjkCache; van den Bergen,
///                     JGT 1999), then EPA for depth, normal and witness points (van den Bergen, GDC 2001);
///   mesh – mesh     : collide() on the two OBB trees (first intersecting triangle pair as the witness);
///   convex – mesh   : descent of the mesh's OBB tree with the convex shape's box carried into the mesh
///                     frame, then GJK of the shape against each triangle of the overlapping leaves.
///
/// Contacts that involve a mesh are surface contacts (a triangle touches or crosses the other shape): a
/// convex shape lying wholly inside a closed mesh is *not* reported, and no penetration depth is given
/// (has_depth is false). Use a convex representation where volume matters (suggest_representation.hpp).
/// All functions are const on their inputs, noexcept apart from allocation, and thread-safe; the only
/// mutable state is the caller-owned cache.

#include "cdkit/bvh/traverse.hpp"
#include "cdkit/ccd/convex_toi.hpp"
#include "cdkit/ccd/mesh_ccd.hpp"
#include "cdkit/narrowphase/epa.hpp"
#include "cdkit/narrowphase/gjk.hpp"
#include "cdkit/query.hpp"
#include "cdkit/world/shape.hpp"

#include <optional>

namespace cdkit {

/// Which narrow phase produced a contact.
enum class PairMethod { convex_convex, convex_mesh, mesh_mesh };

/// A contact between objects a < b, world frame.
template <class S = double> struct WorldContact {
    ObjectId a = 0, b = 0;
    PairMethod method = PairMethod::convex_convex;
    /// Convex–convex: true, and depth/normal/points come from EPA. With a mesh: false, depth 0, normal zero,
    /// point_a == point_b a witness point where the surfaces touch.
    bool has_depth = false;
    S depth = S(0);                          ///< penetration depth ≥ 0 (0: touching)
    Vec3<S> normal = Vec3<S>::Zero();        ///< unit, from a towards b: moving b by depth·normal separates them
    Vec3<S> point_a = Vec3<S>::Zero();       ///< deepest point of a (on b's side)
    Vec3<S> point_b = Vec3<S>::Zero();       ///< deepest point of b
    int gjk_iterations = 0;                  ///< of the warm-started boolean test (convex–convex)
    /// When in the step the contact begins: 1 for a contact at the poses of step() (a discrete test); below 1
    /// for a pair with a CCD object (World::set_ccd), the fraction of the motion since the previous step at which
    /// they first touch — depth 0 then, and normal and points those of the touching poses.
    S toi = S(1);
    friend bool operator<(const WorldContact& x, const WorldContact& y) noexcept {
        return ObjectPair{x.a, x.b} < ObjectPair{y.a, y.b};
    }
};

namespace detail {

/// The convex shape `c` (at `pose_c`) against mesh `m` (at `pose_m`): first touching triangle, or nothing.
template <class S, class Convex>
std::optional<WorldContact<S>> convex_vs_mesh(const Convex& c, const Aabb<S>& c_bounds, const Transform<S>& pose_c,
                                              const WorldMeshModel<S>& m, const Transform<S>& pose_m) noexcept {
    const Transform<S> c_in_m = pose_m.inverse() * pose_c;
    // The shape's local box as an OBB in the mesh frame; BVH nodes are tested against it directly.
    Obb<S> probe;
    probe.axes = c_in_m.R;
    probe.center = c_in_m * c_bounds.center;
    probe.half = c_bounds.half;
    const auto rel = Obb<S>::relative(Transform<S>{});
    const auto& nodes = m.bvh().nodes();
    const auto& order = m.bvh().triangle_order();
    const auto& mesh = m.mesh();
    if (nodes.empty()) return std::nullopt;
    SmallStack<std::uint32_t, 64> stack;
    stack.push(0);
    while (!stack.empty()) {
        const auto& node = nodes[stack.pop()];
        if (!overlap(node.bv, probe, rel)) continue;
        if (!node.is_leaf()) {
            stack.push(node.first);
            stack.push(node.first + 1);
            continue;
        }
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
            const auto t = mesh.triangle(order[i]);
            const ConvexTriangle<S> tri(t[0], t[1], t[2]);  // vertices were validated with the mesh
            const GjkResult<S> g = gjk_intersect(tri, Transform<S>{}, c, c_in_m);
            if (!g.colliding) continue;
            const PenetrationResult<S> p = penetration(tri, Transform<S>{}, c, c_in_m);
            WorldContact<S> w;
            w.method = PairMethod::convex_mesh;
            w.point_a = w.point_b = pose_m * Vec3<S>((p.point_a + p.point_b) / S(2));
            w.gjk_iterations = g.iterations;
            return w;
        }
    }
    return std::nullopt;
}

}  // namespace detail

/// Narrow phase for one pair: shape `a` of object `id_a` at `pose_a` against `b`. Returns a contact when the
/// shapes touch or overlap. `cache` (optional, one per pair, caller-owned) warm-starts GJK for convex pairs.
/// Poses must be rigid (World checks them on entry). Const and thread-safe.
template <class S>
[[nodiscard]] std::optional<WorldContact<S>> collide_shapes(ObjectId id_a, const Shape<S>& a, const Transform<S>& pose_a,
                                                            ObjectId id_b, const Shape<S>& b, const Transform<S>& pose_b,
                                                            GjkCache<S>* cache = nullptr) {
    if (id_b < id_a) return collide_shapes(id_b, b, pose_b, id_a, a, pose_a, cache);
    const Transform<S> pa = a.placed(pose_a), pb = b.placed(pose_b);
    std::optional<WorldContact<S>> out;
    if (a.is_convex() && b.is_convex()) {
        out = a.visit_convex([&](const auto& ca) {
            return b.visit_convex([&](const auto& cb) -> std::optional<WorldContact<S>> {
                const GjkResult<S> g = gjk_intersect(ca, pa, cb, pb, cache);
                if (!g.colliding) return std::nullopt;
                const PenetrationResult<S> p = penetration(ca, pa, cb, pb);
                WorldContact<S> w;
                w.method = PairMethod::convex_convex;
                w.has_depth = true;
                w.depth = p.depth;
                w.normal = p.normal;
                w.point_a = p.point_a;
                w.point_b = p.point_b;
                w.gjk_iterations = g.iterations;
                return w;
            });
        });
    } else if (!a.is_convex() && !b.is_convex()) {
        const CollisionResult<S> r = collide(a.mesh_model(), pa, b.mesh_model(), pb);
        if (r.colliding && !r.contacts.empty()) {
            WorldContact<S> w;
            w.method = PairMethod::mesh_mesh;
            w.point_a = w.point_b = r.contacts.front().point;
            out = w;
        }
    } else {
        const Shape<S>& convex = a.is_convex() ? a : b;
        const Shape<S>& mesh = a.is_convex() ? b : a;
        const Transform<S>& pc = a.is_convex() ? pa : pb;
        const Transform<S>& pm = a.is_convex() ? pb : pa;
        out = convex.visit_convex([&](const auto& c) {
            return detail::convex_vs_mesh(c, convex.local_bounds(), pc, mesh.mesh_model(), pm);
        });
    }
    if (out) {
        out->a = id_a;
        out->b = id_b;
    }
    return out;
}

/// The first contact of two objects while each moves from its pose at `start_*` to the one at `end_*`: convex
/// pairs by conservative advancement (convex_toi), mesh pairs by mesh_ccd; a convex shape against a mesh has no
/// continuous test yet and is tested at the end poses (toi 1). Ids ordered as in collide_shapes.
template <class S>
[[nodiscard]] std::optional<WorldContact<S>> continuous_collide_shapes(ObjectId id_a, const Shape<S>& a,
                                                                       const Transform<S>& start_a,
                                                                       const Transform<S>& end_a, ObjectId id_b,
                                                                       const Shape<S>& b, const Transform<S>& start_b,
                                                                       const Transform<S>& end_b,
                                                                       GjkCache<S>* cache = nullptr) {
    static_assert(std::is_same_v<S, double>, "continuous collision runs in double");
    if (id_b < id_a) return continuous_collide_shapes(id_b, b, start_b, end_b, id_a, a, start_a, end_a, cache);
    const Transform<S> sa = a.placed(start_a), ea = a.placed(end_a), sb = b.placed(start_b), eb = b.placed(end_b);
    if (a.is_convex() && b.is_convex()) {
        return a.visit_convex([&](const auto& ca) {
            return b.visit_convex([&](const auto& cb) -> std::optional<WorldContact<S>> {
                const ToiResult r = convex_toi(ca, sa, ea, cb, sb, eb);
                if (!r.colliding) return std::nullopt;
                WorldContact<S> w;
                w.a = id_a, w.b = id_b;
                w.method = PairMethod::convex_convex;
                w.has_depth = true;  // touching at toi: depth 0
                w.normal = r.normal;
                w.point_a = r.point_a;
                w.point_b = r.point_b;
                w.gjk_iterations = r.iterations;
                w.toi = r.toi;
                return w;
            });
        });
    }
    if (!a.is_convex() && !b.is_convex()) {
        const DeformableCcdResult r = mesh_ccd(a.mesh_model(), sa, ea, b.mesh_model(), sb, eb);
        if (!r.colliding) return std::nullopt;
        WorldContact<S> w;
        w.a = id_a, w.b = id_b;
        w.method = PairMethod::mesh_mesh;
        w.point_a = w.point_b = r.contacts.front().ccd.point;
        w.toi = r.toi;
        return w;
    }
    return collide_shapes(id_a, a, end_a, id_b, b, end_b, cache);
}

}  // namespace cdkit
