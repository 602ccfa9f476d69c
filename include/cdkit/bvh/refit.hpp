#pragma once
/// \file Refit for deformable meshes: after the vertices move (same triangles), every node's volume is
/// recomputed bottom-up, leaves from their triangles and inner nodes from their two children, in O(n) — the
/// tree's topology stays, so its quality degrades as the deformation grows (van den Bergen, "Efficient
/// collision detection of complex deformable models using AABB trees", JGT 1997). The per-BV rule:
///
/// - Aabb, Kdop: the union of the children, as tight as a fresh fit of the same triangles.
/// - BoundingSphere: the ball holding both children's balls, looser than a fresh fit of the triangles (the
///   children's balls bulge past the vertices).
/// - Obb: each node keeps its axes (from the original PCA) and gets new extents from its triangles' vertices
///   in that frame — inner nodes too, in O(n log n): a box around the children's boxes, in axes turned
///   against theirs, bulges at every level (measured: 4.6× the built tree's summed surface area on a sphere
///   and 11.5× on the bunny with no deformation at all). With unmoved vertices a double tree gets its built
///   boxes back; after a deformation the axes no longer follow the shape: looser than a fresh fit.
/// - Rss: the same rule (kept axes, rectangle and radius re-fitted from the node's vertices,
///   Rss::fit_in_frame), for the same reason: merging two swept rectangles in turned axes bulges per level.
///
/// `degradation()` measures what the refit costs: Σ node surface area / the surface area of a fresh fit of the
/// whole mesh, relative to the same ratio of the tree that was built (scale invariant); `should_rebuild`
/// compares it with a threshold. Surface area, not volume: it is what a query's chance to visit a node grows
/// with (the SAH's argument), and it stays positive for the flat single-triangle leaves, whose volume is ~0
/// at build time, so that any refit that tilts them against their kept Obb axes would multiply a volume sum.

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/rss.hpp"
#include "cdkit/bvh/build.hpp"

#include <string>

namespace cdkit {

namespace detail {
/// An inner node's volume from its children.
template <class BV> [[nodiscard]] BV refit_inner(const BV&, const BV& left, const BV& right) noexcept {
    return BV::merge(left, right);
}

template <class S> [[nodiscard]] Aabb<S> refit_inner(const Aabb<S>&, const Aabb<S>& l, const Aabb<S>& r) noexcept {
    const Vec3<S> lo = l.min().cwiseMin(r.min()), hi = l.max().cwiseMax(r.max());
    Aabb<S> m = Aabb<S>::from_min_max(lo, hi);
    // Centre and half extent round: widen by a few ulps so the parent holds the children exactly, and the
    // rounding cannot accumulate up the tree.
    m.half.array() += S(4) * std::numeric_limits<S>::epsilon() * std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
    return m;
}

/// BV types whose inner nodes are refitted from their triangles rather than from their children.
template <class BV> inline constexpr bool refits_from_triangles_v = false;
template <class S> inline constexpr bool refits_from_triangles_v<Obb<S>> = true;
template <class S> inline constexpr bool refits_from_triangles_v<Rss<S>> = true;

template <class BV, class M> [[nodiscard]] BV refit_leaf(const BV&, const TriangleMesh<M>& mesh, TriangleRange tris) {
    return fit_over<BV>(mesh, tris);
}
template <class S, class M> [[nodiscard]] Obb<S> refit_leaf(const Obb<S>& old, const TriangleMesh<M>& mesh, TriangleRange tris) {
    if constexpr (std::is_same_v<S, M>) return Obb<S>::fit_in_frame(mesh, tris, old.axes);
    else return narrow_outward(Obb<M>::fit_in_frame(mesh, tris, old.axes.template cast<M>()));
}

template <class S, class M> [[nodiscard]] Rss<S> refit_leaf(const Rss<S>& old, const TriangleMesh<M>& mesh, TriangleRange tris) {
    if constexpr (std::is_same_v<S, M>) return Rss<S>::fit_in_frame(mesh, tris, old.axes);
    else return narrow_outward(Rss<M>::fit_in_frame(mesh, tris, old.axes.template cast<M>()));
}

/// The size measure of degradation(): surface_area(), or volume() for a BV type without one.
template <class BV> [[nodiscard]] double degradation_measure(const BV& bv) noexcept {
    if constexpr (requires { bv.surface_area(); }) return double(bv.surface_area());
    else return double(bv.volume());
}
}  // namespace detail

/// Σ volume() over all nodes (for Kdop its volume proxy).
template <class BV> [[nodiscard]] double total_volume(const Bvh<BV>& bvh) noexcept {
    double v = 0;
    for (const auto& n : bvh.nodes()) v += double(n.bv.volume());
    return v;
}

/// Σ surface_area() over all nodes (for Kdop the area of its box proxy; volume() for a BV without an area).
template <class BV> [[nodiscard]] double total_surface_area(const Bvh<BV>& bvh) noexcept {
    double a = 0;
    for (const auto& n : bvh.nodes()) a += detail::degradation_measure(n.bv);
    return a;
}

/// Σ node surface area / the surface area of a fresh fit of the whole mesh (the root a rebuild would get): how
/// much the tree's volumes overlap and overhang. Scale invariant, so uniform growth of the mesh does not
/// change it; O(n) plus one fit of all triangles.
template <class BV, class M> [[nodiscard]] double surface_ratio(const Bvh<BV>& bvh, const TriangleMesh<M>& mesh) {
    if (bvh.empty()) return 0;
    const auto& order = bvh.triangle_order();
    const double root = detail::degradation_measure(detail::fit_over<BV>(mesh, TriangleRange(order.data(), order.size())));
    return root > 0 ? total_surface_area(bvh) / root : 1.0;
}

/// Refits `bvh` to `mesh`, the mesh it was built on with moved vertices (same triangles, in the same order),
/// in O(n). Throws cdkit::Error when the triangle count differs or a vertex is not finite. The triangles
/// themselves are not compared here (MeshModel::refit does); a mesh with other triangles gives a valid but
/// meaningless tree.
template <class BV, class M> void refit(Bvh<BV>& bvh, const TriangleMesh<M>& mesh) {
    if (mesh.triangles.size() != bvh.triangle_order().size())
        throw Error(mesh.source, "", "refit: triangle count " + std::to_string(mesh.triangles.size()) +
                                         " differs from the tree's " + std::to_string(bvh.triangle_order().size()));
    validate(mesh);
    const auto& nodes = bvh.nodes();
    const auto& order = bvh.triangle_order();
    // Children always follow their parent in the array (build_bvh lays the tree out that way, validate()
    // checks it), so one backward sweep sees both children before the parent.
    if constexpr (detail::refits_from_triangles_v<BV>) {
        // A node's triangles are contiguous in triangle_order: the span of its children's.
        std::vector<std::pair<std::uint32_t, std::uint32_t>> span(nodes.size());
        for (std::size_t i = nodes.size(); i-- > 0;) {
            const auto& n = nodes[i];
            span[i] = n.is_leaf() ? std::pair{n.first, n.first + n.count}
                                  : std::pair{span[n.first].first, span[n.first + 1].second};
            const TriangleRange tris(order.data() + span[i].first, span[i].second - span[i].first);
            bvh.set_volume(i, detail::refit_leaf(n.bv, mesh, tris));
        }
    } else {
        for (std::size_t i = nodes.size(); i-- > 0;) {
            const auto& n = nodes[i];
            if (n.is_leaf())
                bvh.set_volume(i, detail::refit_leaf(n.bv, mesh, TriangleRange(order.data() + n.first, n.count)));
            else
                bvh.set_volume(i, detail::refit_inner(n.bv, nodes[n.first].bv, nodes[n.first + 1].bv));
        }
    }
}

}  // namespace cdkit
