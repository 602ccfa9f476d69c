#pragma once
/// \file Refit for deformable meshes: after the vertices move (same triangles), every node's volume is
/// recomputed bottom-up, leaves from their triangles and inner nodes from their two children, in O(n) — the
/// tree's topology stays, so its quality degrades as the deformation grows (van den Bergen, "Efficient
/// collision detection of complex deformable models using AABB trees", JGT 1997). The per-BV rule:
///
/// - Aabb, Kdop: the union of the children, as tight as a fresh fit of the same triangles.
/// - BoundingSphere: the ball holding both children's balls, looser than a fresh fit of the triangles (the
///   children's balls bulge past the vertices).
/// - Obb: each node keeps its axes (from the original PCA) and gets new extents: leaves from their
///   triangles' vertices, inner nodes from their children's boxes. The axes no longer follow the deformed
///   shape: looser than a fresh fit.
///
/// `degradation()` measures what the refit costs: Σ node volume / the volume of a fresh fit of the whole mesh,
/// relative to the same ratio of the tree that was built (scale invariant); `should_rebuild` compares it with a threshold.

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bvh/build.hpp"

#include <string>

namespace cdkit {

namespace detail {
/// An inner node's volume from its children (and its own old volume, whose frame an Obb keeps).
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

template <class S> [[nodiscard]] Obb<S> refit_inner(const Obb<S>& old, const Obb<S>& l, const Obb<S>& r) noexcept {
    const Mat3<S> at = old.axes.transpose();
    Vec3<S> lo = Vec3<S>::Constant(std::numeric_limits<S>::infinity()), hi = -lo;
    S magnitude = 0;
    for (const Obb<S>* c : {&l, &r}) {
        const Mat3<S> rc = at * c->axes;
        const Vec3<S> p = at * c->center;
        const Vec3<S> reach = abs_with_slack(rc) * c->half;
        lo = lo.cwiseMin(p - reach);
        hi = hi.cwiseMax(p + reach);
        magnitude = std::max(magnitude, c->center.cwiseAbs().maxCoeff() + c->half.sum());
    }
    Obb<S> m;
    m.axes = old.axes;
    m.half = (hi - lo) * S(0.5) + Vec3<S>::Constant(S(4) * fit_padding(magnitude));
    m.center = old.axes * ((lo + hi) * S(0.5));
    return m;
}

template <class BV, class M> [[nodiscard]] BV refit_leaf(const BV&, const TriangleMesh<M>& mesh, TriangleRange tris) {
    return fit_over<BV>(mesh, tris);
}
template <class S, class M> [[nodiscard]] Obb<S> refit_leaf(const Obb<S>& old, const TriangleMesh<M>& mesh, TriangleRange tris) {
    if constexpr (std::is_same_v<S, M>) return Obb<S>::fit_in_frame(mesh, tris, old.axes);
    else return narrow_outward(Obb<M>::fit_in_frame(mesh, tris, old.axes.template cast<M>()));
}
}  // namespace detail

/// Σ volume() over all nodes (for Kdop its volume proxy).
template <class BV> [[nodiscard]] double total_volume(const Bvh<BV>& bvh) noexcept {
    double v = 0;
    for (const auto& n : bvh.nodes()) v += double(n.bv.volume());
    return v;
}

/// Σ node volume / the volume of a fresh fit of the whole mesh (the root a rebuild would get): how much the
/// tree's volumes overlap and overhang. Scale invariant, so uniform growth of the mesh does not change it;
/// O(n) plus one fit of all triangles.
template <class BV, class M> [[nodiscard]] double volume_ratio(const Bvh<BV>& bvh, const TriangleMesh<M>& mesh) {
    if (bvh.empty()) return 0;
    const auto& order = bvh.triangle_order();
    const double root = double(detail::fit_over<BV>(mesh, TriangleRange(order.data(), order.size())).volume());
    return root > 0 ? total_volume(bvh) / root : 1.0;
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
    for (std::size_t i = nodes.size(); i-- > 0;) {
        const auto& n = nodes[i];
        if (n.is_leaf())
            bvh.set_volume(i, detail::refit_leaf(n.bv, mesh, TriangleRange(order.data() + n.first, n.count)));
        else
            bvh.set_volume(i, detail::refit_inner(n.bv, nodes[n.first].bv, nodes[n.first + 1].bv));
    }
}

}  // namespace cdkit
