#pragma once
/// \file Narrow-phase dispatch of World: one function that takes two posed Shapes and runs the test that
/// matches their kinds, returning a plain contact struct.
///
///   convex – convex : the contact manifold (manifold/contact_manifold.hpp): GJK boolean test (warm-started from
///                     the caller's per-pair GjkCache; van den Bergen, JGT 1999), EPA for depth and normal (van
///                     den Bergen, GDC 2001), then up to four points from the touching faces or edges;
///   mesh – mesh     : penetration_depth() of mesh_depth/penetration_depth.hpp on the two OBB trees: the crossing
///                     triangle pairs, the intersection curve's normal, and the translation of b along it that undoes
///                     every crossing (depth), with the triangle pair that separates last as the points;
///   convex – mesh   : penetration(mesh, pose, shape, pose) of mesh_convex/penetration.hpp: descent of the mesh's OBB
///                     tree against the shape's bound, the exact sphere / capsule test or GJK per triangle, then EPA
///                     between the shape and each touching triangle; the deepest triangle gives depth and normal.
///   compound – any  : each child near the other shape (the compound's tree) against it, one contact per touching
///                     child pair (collide_shapes_all; collide_shapes keeps the deepest).
///
/// Contacts that involve a mesh are surface contacts (a triangle touches or crosses the other shape): a
/// convex shape lying wholly inside a closed mesh is *not* reported. Their depth says how far to push apart: for
/// two meshes the depth of the volumes along the normal (the surfaces uncross), for a convex shape against a mesh
/// the depth against the deepest touching triangle (docs/contacts.md, "Mesh penetration depth").
/// With a contact margin (ManifoldRequest::margin > 0) pairs apart by at most the margin are reported too, as
/// speculative contacts: `colliding` false, `distance` their separation, points with negative depth (meshes: their
/// closest points).
/// All functions are const on their inputs, noexcept apart from allocation, and thread-safe; the only
/// mutable state is the caller-owned cache.

#include "cdkit/bvh/traverse.hpp"
#include "cdkit/ccd/convex_toi.hpp"
#include "cdkit/ccd/mesh_ccd.hpp"
#include "cdkit/ccd/mesh_convex_toi.hpp"
#include "cdkit/ccd/mesh_toi.hpp"
#include "cdkit/distance.hpp"
#include "cdkit/manifold/contact_manifold.hpp"
#include "cdkit/mesh_convex/penetration.hpp"
#include "cdkit/mesh_depth/penetration_depth.hpp"
#include "cdkit/mesh_convex/collide.hpp"
#include "cdkit/mesh_convex/distance.hpp"
#include "cdkit/narrowphase/epa.hpp"
#include "cdkit/narrowphase/gjk.hpp"
#include "cdkit/query.hpp"
#include "cdkit/world/shape.hpp"

#include <optional>
#include <tuple>
#include <vector>

namespace cdkit {

/// Which narrow phase produced a contact.
enum class PairMethod { convex_convex, convex_mesh, mesh_mesh };

/// A contact between objects a < b, world frame.
template <class S = double> struct WorldContact {
    ObjectId a = 0, b = 0;
    PairMethod method = PairMethod::convex_convex;
    /// Touching or overlapping; false for a speculative contact (apart by `distance` ≤ the World's contact margin).
    bool colliding = true;
    S distance = S(0);  ///< separation of a speculative contact; 0 when colliding
    /// True for every contact at the present poses: convex–convex from the contact manifold, mesh–mesh from
    /// penetration_depth(), convex–mesh from the deepest touching triangle's EPA. False for speculative contacts
    /// (their closest points and the direction between them), and for mesh contacts with ManifoldRequest::mesh_depth
    /// off (WorldOptions::mesh_depth: point_a == point_b a witness, normal zero). CCD contacts: depth 0 at toi.
    bool has_depth = false;
    S depth = S(0);                          ///< penetration depth ≥ 0 of the deepest point (0: touching)
    Vec3<S> normal = Vec3<S>::Zero();        ///< unit, from a towards b: moving b by depth·normal separates them
    Vec3<S> point_a = Vec3<S>::Zero();       ///< deepest point of a (on b's side)
    Vec3<S> point_b = Vec3<S>::Zero();       ///< deepest point of b
    /// The manifold: up to four points sharing `normal`, each with its depth and a feature id that stays the same
    /// from step to step while the same features touch (convex pairs; a face on a face gives up to four). Mesh
    /// contacts and CCD contacts carry their one witness here.
    int point_count = 0;
    std::array<ManifoldPoint<S>, 4> points{};
    int gjk_iterations = 0;                  ///< of the warm-started boolean test (convex–convex)
    /// When in the step the contact begins: 1 for a contact at the poses of step() (a discrete test); below 1
    /// for a pair with a CCD object (World::set_ccd), the fraction of the motion since the previous step at which
    /// they first touch — depth 0 then, and normal and points those of the touching poses.
    S toi = S(1);
    /// For a compound object, which of its children touches (an index into its children); no_child otherwise.
    static constexpr std::uint32_t no_child = std::uint32_t(-1);
    std::uint32_t child_a = no_child, child_b = no_child;
    friend bool operator<(const WorldContact& x, const WorldContact& y) noexcept {
        return std::tie(x.a, x.b, x.child_a, x.child_b) < std::tie(y.a, y.b, y.child_a, y.child_b);
    }
};

/// What World keeps for a pair between steps: its ManifoldCache and, for a compound object, one per touching child
/// pair (found by a linear search: a compound touches through a few children at a time).
template <class S = double> struct PairCache {
    ManifoldCache<S> manifold;
    std::vector<std::pair<std::uint64_t, ManifoldCache<S>>> children;
    [[nodiscard]] ManifoldCache<S>& child(std::uint32_t child_a, std::uint32_t child_b) {
        const std::uint64_t key = (std::uint64_t(child_a) << 32) | child_b;
        for (auto& [k, c] : children)
            if (k == key) return c;
        return children.emplace_back(key, ManifoldCache<S>{}).second;
    }
};

namespace detail {

/// The convex shape `c` (at `pose_c`) against mesh `m` (at `pose_m`): the deepest touching triangle (the public
/// mesh–convex penetration()), or without `with_depth` the first one (collide(): a witness point only), or nothing.
/// `convex_first` says which of the two is the World's `a`.
template <class S, class Convex>
std::optional<WorldContact<S>> convex_vs_mesh(const Convex& c, const Transform<S>& pose_c, const WorldMeshModel<S>& m,
                                              const Transform<S>& pose_m, bool convex_first, bool with_depth) noexcept {
    if (!with_depth) {
        const MeshConvexResult<S> r = cdkit::collide(m, pose_m, c, pose_c, MeshConvexRequest{ContactMode::first});
        if (!r.colliding || r.contacts.empty()) return std::nullopt;
        WorldContact<S> w;
        w.method = PairMethod::convex_mesh;
        w.point_a = w.point_b = r.contacts.front().point;
        return w;
    }
    const MeshConvexPenetrationResult<S> r = cdkit::penetration(m, pose_m, c, pose_c, MeshConvexRequest{ContactMode::first});
    if (!r.colliding) return std::nullopt;
    WorldContact<S> w;
    w.method = PairMethod::convex_mesh;
    w.has_depth = true;
    w.depth = r.deepest.depth;
    // penetration()'s normal runs from the triangle towards the shape: the World's runs from a to b.
    w.normal = convex_first ? Vec3<S>(-r.deepest.normal) : r.deepest.normal;
    w.point_a = convex_first ? r.deepest.point_shape : r.deepest.point_mesh;
    w.point_b = convex_first ? r.deepest.point_mesh : r.deepest.point_shape;
    return w;
}

/// Mesh a against mesh b: penetration_depth() (mesh_depth/) in the World's terms, or without `with_depth` collide()'s
/// first crossing pair as a witness, or nothing.
template <class S>
std::optional<WorldContact<S>> mesh_vs_mesh(const WorldMeshModel<S>& a, const Transform<S>& pa, const WorldMeshModel<S>& b,
                                            const Transform<S>& pb, bool with_depth) {
    if (!with_depth) {
        const CollisionResult<S> r = collide(a, pa, b, pb);
        if (!r.colliding || r.contacts.empty()) return std::nullopt;
        WorldContact<S> w;
        w.method = PairMethod::mesh_mesh;
        w.point_a = w.point_b = r.contacts.front().point;
        return w;
    }
    const MeshDepthResult d = penetration_depth(a, pa, b, pb);
    if (!d.colliding) return std::nullopt;
    WorldContact<S> w;
    w.method = PairMethod::mesh_mesh;
    w.has_depth = true;
    w.depth = S(d.depth);
    w.normal = d.normal.template cast<S>();
    w.point_a = d.point_a.template cast<S>();
    w.point_b = d.point_b.template cast<S>();
    return w;
}

/// A speculative contact from closest points (a on the first shape, b on the second) apart by `d`.
template <class S> WorldContact<S> speculative_contact(PairMethod method, const Vec3<S>& a, const Vec3<S>& b, S d) {
    WorldContact<S> w;
    w.method = method;
    w.colliding = false;
    w.distance = d;
    w.point_a = a;
    w.point_b = b;
    w.normal = safe_normalized(Vec3<S>(b - a));
    return w;
}

/// A contact of one point (meshes, CCD): the witness pair becomes the manifold's point.
template <class S> WorldContact<S> with_witness(WorldContact<S> w) {
    if (w.point_count == 0) {
        w.point_count = 1;
        w.points[0] = {w.point_a, w.point_b, w.colliding ? w.depth : -w.distance, 0};
    }
    return w;
}

/// A convex pair's contact from the manifold of their cores (shapes without rounding: the shapes themselves).
template <class S> WorldContact<S> manifold_contact(const ContactManifold<S>& m) {
    WorldContact<S> w;
    w.method = PairMethod::convex_convex;
    w.colliding = m.colliding;
    w.distance = m.distance;
    w.has_depth = true;
    w.normal = m.normal;
    w.point_count = m.count;
    w.points = m.points;
    w.gjk_iterations = m.stats.gjk_iterations;
    return w;
}

/// The deepest of the contact's points fills depth, point_a and point_b.
template <class S> void take_deepest_point(WorldContact<S>& w) {
    int deepest = 0;
    for (int i = 1; i < w.point_count; ++i)
        if (w.points[i].depth > w.points[deepest].depth) deepest = i;
    w.depth = std::max(w.points[deepest].depth, S(0));
    w.point_a = w.points[deepest].point_a;
    w.point_b = w.points[deepest].point_b;
}

/// A contact of the cores of two rounded shapes (radii ra, rb; found within margin + ra + rb) made the rounded
/// shapes' contact: every depth grows by ra + rb, a's points move by ra along the normal and b's back by rb; points
/// apart by more than the margin are dropped. Nothing when none is left.
template <class S> std::optional<WorldContact<S>> rounded_contact(WorldContact<S> w, S ra, S rb, S margin) {
    const S r = ra + rb;
    int kept = 0;
    for (int i = 0; i < w.point_count; ++i) {
        ManifoldPoint<S> p = w.points[i];
        p.depth += r;
        if (p.depth < -margin) continue;
        p.point_a += ra * w.normal;
        p.point_b -= rb * w.normal;
        w.points[kept++] = p;
    }
    if (kept == 0) return std::nullopt;
    w.point_count = kept;
    w.colliding = w.colliding || w.distance <= r;
    w.distance = w.colliding ? S(0) : w.distance - r;
    take_deepest_point(w);
    return w;
}

/// Unit direction from a convex core to a mesh triangle it touches (distance 0): EPA's separating direction
/// between the two, or the triangle's normal turned away from the core's centre where EPA gives none.
template <class S, class Convex>
Vec3<S> core_to_triangle_direction(const Convex& c, const Transform<S>& pose_c, const WorldMeshModel<S>& m,
                                   const Transform<S>& pose_m, Index t) {
    const auto& tri = m.mesh().triangles[t];
    const Vec3<S>&v0 = m.mesh().vertices[tri[0]], &v1 = m.mesh().vertices[tri[1]], &v2 = m.mesh().vertices[tri[2]];
    const PenetrationResult<S> p = cdkit::penetration(ConvexTriangle<S>(v0, v1, v2), pose_m, c, pose_c);
    // penetration()'s normal runs from the triangle (a) towards the core (b).
    if (p.normal.allFinite() && p.normal.norm() > S(0.5)) return -p.normal;
    Vec3<S> n = pose_m.R * (v1 - v0).cross(v2 - v0);
    if (n.dot(pose_c.t - pose_m * v0) > S(0)) n = -n;
    return safe_normalized(n);
}

/// A distance query for a speculative contact: only pairs within `margin` matter, so the tree walk prunes
/// everything farther (a pair beyond it costs a few node bounds, not a full distance query).
template <class S> [[nodiscard]] DistanceRequest<S> within_request(S margin) noexcept {
    DistanceRequest<S> r;
    r.max_distance = margin;
    return r;
}

/// A rounded convex shape (core `c`, radius `r` > 0) against a mesh: the core's mesh–convex contact (its depth and
/// point grown by r) where the core touches the mesh, else the core's distance to the mesh against r (a contact of
/// depth r − d, or a speculative one within the margin), along the closest points' direction.
template <class S, class Convex>
std::optional<WorldContact<S>> rounded_convex_vs_mesh(const Convex& c, S r, const Transform<S>& pose_c,
                                                      const WorldMeshModel<S>& m, const Transform<S>& pose_m,
                                                      bool convex_first, bool with_depth, S margin) {
    if (auto w = convex_vs_mesh(c, pose_c, m, pose_m, convex_first, with_depth)) {
        if (w->has_depth) {
            w->depth += r;
            // The normal runs from a to b; the shape's point moves by r towards the mesh.
            (convex_first ? w->point_a : w->point_b) += (convex_first ? r : -r) * w->normal;
        }
        return w;
    }
    const MeshConvexDistanceResult<S> d = distance(m, pose_m, c, pose_c, within_request(r + margin));
    if (!(d.distance <= r + margin)) return std::nullopt;
    // The core touches the mesh by the distance query although the boolean said apart (their tolerances differ
    // within ~1e-9 of touching): the rounded shape overlaps by r, along the closest triangle's separating direction.
    const Vec3<S> u = d.distance > S(0) ? Vec3<S>((d.point_mesh - d.point_shape) / d.distance)
                                        : core_to_triangle_direction(c, pose_c, m, pose_m, d.triangle);
    const Vec3<S> on_shape = d.point_shape + r * u;
    WorldContact<S> w;
    w.method = PairMethod::convex_mesh;
    w.colliding = d.distance <= r;
    w.distance = w.colliding ? S(0) : d.distance - r;
    w.has_depth = w.colliding;
    w.depth = w.colliding ? r - d.distance : S(0);
    w.normal = convex_first ? u : Vec3<S>(-u);
    w.point_a = convex_first ? on_shape : d.point_mesh;
    w.point_b = convex_first ? d.point_mesh : on_shape;
    return w;
}

template <class S>
std::optional<WorldContact<S>> deepest_child_contact(ObjectId id_a, const Shape<S>& a, const Transform<S>& pose_a,
                                                     ObjectId id_b, const Shape<S>& b, const Transform<S>& pose_b,
                                                     const ManifoldRequest& request);

}  // namespace detail

/// Narrow phase for one pair: shape `a` of object `id_a` at `pose_a` against `b`. Returns a contact when the
/// shapes touch or overlap, or lie within `request.margin` (a speculative contact). `request` also chooses the
/// single-point contact over the manifold for convex pairs (`single_point`) and the feature angle. `cache`
/// (optional, one per pair, caller-owned) warm-starts GJK and keeps the manifold ids of convex pairs. Poses must be rigid (World checks
/// them on entry). Const and thread-safe.
template <class S>
[[nodiscard]] std::optional<WorldContact<S>> collide_shapes(ObjectId id_a, const Shape<S>& a, const Transform<S>& pose_a,
                                                            ObjectId id_b, const Shape<S>& b, const Transform<S>& pose_b,
                                                            ManifoldCache<S>* cache = nullptr,
                                                            const ManifoldRequest& request = {}) {
    if (id_b < id_a) return collide_shapes(id_b, b, pose_b, id_a, a, pose_a, cache, request);
    if (a.is_compound() || b.is_compound()) return detail::deepest_child_contact(id_a, a, pose_a, id_b, b, pose_b, request);
    const Transform<S> pa = a.placed(pose_a), pb = b.placed(pose_b);
    const S margin = S(request.margin);
    std::optional<WorldContact<S>> out;
    if (a.is_convex() && b.is_convex()) {
        // Rounded shapes: the cores' manifold within the margin plus both roundings, then grown (rounded_contact).
        const S ra = a.rounding(), rb = b.rounding();
        ManifoldRequest core_request = request;
        core_request.margin = request.margin + double(ra + rb);
        out = a.visit_convex([&](const auto& ca) {
            return b.visit_convex([&](const auto& cb) -> std::optional<WorldContact<S>> {
                const ContactManifold<S> m = contact_manifold(ca, pa, cb, pb, core_request, cache);
                if (m.count == 0) return std::nullopt;
                WorldContact<S> w = detail::manifold_contact(m);
                if (ra + rb > S(0)) return detail::rounded_contact(w, ra, rb, margin);
                detail::take_deepest_point(w);
                return w;
            });
        });
    } else if (!a.is_convex() && !b.is_convex()) {
        out = detail::mesh_vs_mesh(a.mesh_model(), pa, b.mesh_model(), pb, request.mesh_depth);
        if (!out && margin > S(0)) {
            const DistanceResult<S> d = distance(a.mesh_model(), pa, b.mesh_model(), pb, detail::within_request(margin));
            if (d.distance <= margin)
                out = detail::speculative_contact(PairMethod::mesh_mesh, d.point_a, d.point_b, d.distance);
        }
    } else {
        const bool convex_first = a.is_convex();
        const Shape<S>& convex = convex_first ? a : b;
        const Shape<S>& mesh = convex_first ? b : a;
        const Transform<S>& pc = convex_first ? pa : pb;
        const Transform<S>& pm = convex_first ? pb : pa;
        out = convex.visit_convex([&](const auto& c) -> std::optional<WorldContact<S>> {
            if (convex.rounding() > S(0))
                return detail::rounded_convex_vs_mesh(c, convex.rounding(), pc, mesh.mesh_model(), pm, convex_first,
                                                      request.mesh_depth, margin);
            if (auto w = detail::convex_vs_mesh(c, pc, mesh.mesh_model(), pm, convex_first, request.mesh_depth)) return w;
            if (!(margin > S(0))) return std::nullopt;
            const MeshConvexDistanceResult<S> d = distance(mesh.mesh_model(), pm, c, pc, detail::within_request(margin));
            if (!(d.distance <= margin)) return std::nullopt;
            return convex_first
                       ? detail::speculative_contact(PairMethod::convex_mesh, d.point_shape, d.point_mesh, d.distance)
                       : detail::speculative_contact(PairMethod::convex_mesh, d.point_mesh, d.point_shape, d.distance);
        });
    }
    if (out) {
        out->a = id_a;
        out->b = id_b;
        out = detail::with_witness(*out);
    }
    return out;
}

/// Narrow phase for one pair, every contact: as collide_shapes, and for a compound object one contact per touching
/// child pair (the children near the other shape found by the compound's tree, under the other's box carried into
/// the compound's frame and grown by the margin), each with `child_a` / `child_b` set and its own cache in `cache`.
/// Appends to `out`. Const on the shapes and thread-safe; `cache` (optional, one per pair) is the caller's.
template <class S>
void collide_shapes_all(ObjectId id_a, const Shape<S>& a, const Transform<S>& pose_a, ObjectId id_b, const Shape<S>& b,
                        const Transform<S>& pose_b, PairCache<S>* cache, const ManifoldRequest& request,
                        std::vector<WorldContact<S>>& out) {
    if (id_b < id_a) return collide_shapes_all(id_b, b, pose_b, id_a, a, pose_a, cache, request, out);
    if (!a.is_compound() && !b.is_compound()) {
        if (auto c = collide_shapes(id_a, a, pose_a, id_b, b, pose_b, cache ? &cache->manifold : nullptr, request))
            out.push_back(*c);
        return;
    }
    constexpr std::uint32_t none = WorldContact<S>::no_child;
    const S margin = S(request.margin);
    // The frames the children's offsets hang from.
    const Transform<S> fa = a.is_compound() ? a.placed(pose_a) : pose_a, fb = b.is_compound() ? b.placed(pose_b) : pose_b;
    const auto near = [&](const Shape<S>& compound, const Transform<S>& frame, const Shape<S>& other,
                          const Transform<S>& other_pose, auto&& f) {
        BroadBox<S> box = other.world_box(frame.inverse() * other_pose);
        box.lo.array() -= margin;
        box.hi.array() += margin;
        compound.compound_shape().for_each_child_overlapping(box, f);
    };
    const auto test = [&](const Shape<S>& x, std::uint32_t cx, const Transform<S>& px, const Shape<S>& y, std::uint32_t cy,
                          const Transform<S>& py) {
        ManifoldCache<S>* c = cache ? &cache->child(cx, cy) : nullptr;
        if (auto w = collide_shapes(id_a, x, px, id_b, y, py, c, request)) {
            w->child_a = cx;
            w->child_b = cy;
            out.push_back(*w);
        }
    };
    if (!b.is_compound()) {
        const auto& kids = a.compound_shape().children();
        near(a, fa, b, pose_b, [&](std::uint32_t i) { test(kids[i], i, fa, b, none, pose_b); });
    } else if (!a.is_compound()) {
        const auto& kids = b.compound_shape().children();
        near(b, fb, a, pose_a, [&](std::uint32_t j) { test(a, none, pose_a, kids[j], j, fb); });
    } else {
        const auto& ka = a.compound_shape().children();
        const auto& kb = b.compound_shape().children();
        near(a, fa, b, fb, [&](std::uint32_t i) {
            near(b, fb, ka[i], fa, [&](std::uint32_t j) { test(ka[i], i, fa, kb[j], j, fb); });
        });
    }
}

namespace detail {

/// collide_shapes for a compound: the deepest of its child contacts (a colliding one before a speculative one).
template <class S>
std::optional<WorldContact<S>> deepest_child_contact(ObjectId id_a, const Shape<S>& a, const Transform<S>& pose_a,
                                                     ObjectId id_b, const Shape<S>& b, const Transform<S>& pose_b,
                                                     const ManifoldRequest& request) {
    std::vector<WorldContact<S>> all;
    collide_shapes_all(id_a, a, pose_a, id_b, b, pose_b, static_cast<PairCache<S>*>(nullptr), request, all);
    std::optional<WorldContact<S>> best;
    for (const WorldContact<S>& c : all)
        if (!best || std::tuple(c.colliding, c.depth, -c.distance) > std::tuple(best->colliding, best->depth, -best->distance))
            best = c;
    return best;
}

}  // namespace detail

/// The first contact of two objects while each moves from its pose at `start_*` to the one at `end_*` (constant
/// linear and angular velocity): convex pairs by conservative advancement (convex_toi), a convex shape and a mesh
/// by mesh_convex_toi, two meshes by mesh_ccd when neither turns (their vertices then move on lines, which
/// mesh_ccd follows exactly) and by mesh_toi when one does. Ids ordered as in collide_shapes.
template <class S>
[[nodiscard]] std::optional<WorldContact<S>> continuous_collide_shapes(ObjectId id_a, const Shape<S>& a,
                                                                       const Transform<S>& start_a,
                                                                       const Transform<S>& end_a, ObjectId id_b,
                                                                       const Shape<S>& b, const Transform<S>& start_b,
                                                                       const Transform<S>& end_b,
                                                                       GjkCache<S>* cache = nullptr) {
    static_assert(std::is_same_v<S, double>, "continuous collision runs in double");
    if (id_b < id_a) return continuous_collide_shapes(id_b, b, start_b, end_b, id_a, a, start_a, end_a, cache);
    if (a.is_compound() || b.is_compound()) {  // the earliest contact over the child pairs (every pair: CCD is rare)
        std::optional<WorldContact<S>> first;
        const auto consider = [&](std::optional<WorldContact<S>> c, std::uint32_t ca, std::uint32_t cb) {
            if (!c || (first && first->toi <= c->toi)) return;
            c->child_a = ca;
            c->child_b = cb;
            first = c;
        };
        constexpr std::uint32_t none = WorldContact<S>::no_child;
        const std::uint32_t na = a.is_compound() ? std::uint32_t(a.compound_shape().children().size()) : 1;
        const std::uint32_t nb = b.is_compound() ? std::uint32_t(b.compound_shape().children().size()) : 1;
        for (std::uint32_t i = 0; i < na; ++i)
            for (std::uint32_t j = 0; j < nb; ++j) {
                const Shape<S>& x = a.is_compound() ? a.compound_shape().children()[i] : a;
                const Shape<S>& y = b.is_compound() ? b.compound_shape().children()[j] : b;
                consider(continuous_collide_shapes(id_a, x, a.is_compound() ? a.placed(start_a) : start_a,
                                                   a.is_compound() ? a.placed(end_a) : end_a, id_b, y,
                                                   b.is_compound() ? b.placed(start_b) : start_b,
                                                   b.is_compound() ? b.placed(end_b) : end_b, cache),
                         a.is_compound() ? i : none, b.is_compound() ? j : none);
            }
        return first;
    }
    const Transform<S> sa = a.placed(start_a), ea = a.placed(end_a), sb = b.placed(start_b), eb = b.placed(end_b);
    if (a.is_convex() && b.is_convex()) {
        return a.visit_convex([&](const auto& ca) {
            return b.visit_convex([&](const auto& cb) -> std::optional<WorldContact<S>> {
                // Rounded shapes: the cores' time of impact at the sum of the roundings, the points moved out by them.
                const ToiResult r = convex_toi(ca, sa, ea, cb, sb, eb, ToiRequest{.separation = double(a.rounding() + b.rounding())});
                if (!r.colliding) return std::nullopt;
                WorldContact<S> w;
                w.a = id_a, w.b = id_b;
                w.method = PairMethod::convex_convex;
                w.has_depth = true;  // touching at toi: depth 0
                w.normal = r.normal;
                w.point_a = r.point_a + a.rounding() * r.normal;
                w.point_b = r.point_b - b.rounding() * r.normal;
                w.gjk_iterations = r.iterations;
                w.toi = r.toi;
                return detail::with_witness(w);
            });
        });
    }
    WorldContact<S> w;
    w.a = id_a, w.b = id_b;
    if (!a.is_convex() && !b.is_convex()) {
        w.method = PairMethod::mesh_mesh;
        if (sa.R == ea.R && sb.R == eb.R) {  // translations: every vertex on a line, mesh_ccd is exact
            const DeformableCcdResult r = mesh_ccd(a.mesh_model(), sa, ea, b.mesh_model(), sb, eb);
            if (!r.colliding) return std::nullopt;
            w.point_a = w.point_b = r.contacts.front().ccd.point;
            w.toi = r.toi;
            return detail::with_witness(w);
        }
        const ToiResult r = mesh_toi(a.mesh_model(), sa, ea, b.mesh_model(), sb, eb);  // vertices on arcs
        if (!r.colliding) return std::nullopt;
        w.point_a = w.point_b = (r.point_a + r.point_b) / 2;
        w.toi = r.toi;
        return detail::with_witness(w);
    }
    // A convex shape and a mesh: the advancement on their distance (the mesh as the first object).
    const bool mesh_first = !a.is_convex();
    const Shape<S>& mesh = mesh_first ? a : b;
    const Shape<S>& convex = mesh_first ? b : a;
    const ToiRequest toi_request{.separation = double(convex.rounding())};  // a rounded shape's core, as above
    const ToiResult r = convex.visit_convex([&](const auto& c) {
        return mesh_first ? mesh_convex_toi(mesh.mesh_model(), sa, ea, c, sb, eb, toi_request)
                          : mesh_convex_toi(mesh.mesh_model(), sb, eb, c, sa, ea, toi_request);
    });
    if (!r.colliding) return std::nullopt;
    w.method = PairMethod::convex_mesh;
    // The witness: on the mesh, the closest point (r.point_a); a rounded core's point moved out towards it.
    w.point_a = w.point_b = convex.rounding() > S(0) ? r.point_a : Vec3<S>((r.point_a + r.point_b) / 2);
    w.toi = r.toi;
    return detail::with_witness(w);
}

}  // namespace cdkit
