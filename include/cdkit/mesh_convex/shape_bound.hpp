#pragma once
/// \file The convex shape's bound in the mesh's frame, and the test of a BVH node against it, for every BV type.
///
/// A mesh–convex query descends one tree: the shape has none. Its bound under the relative pose is built once per
/// query, in the mesh's model frame (where the nodes are), and each node is tested against it:
///   - every shape: its local box (six support queries, so any support-mapped shape works) as an oriented box in
///     the mesh frame; OBB and AABB nodes run the 15-axis separating-axis test against it (Gottschalk, Lin,
///     Manocha, "OBBTree", SIGGRAPH 1996), distance queries its lower bound (bv/bv_distance.hpp);
///   - spheres and capsules, which are a point or a segment grown by a ball: that swept sphere itself, exact, so a
///     sphere is tested by its centre's distance to the node and a capsule against an RSS node by the rectangle's
///     distance to its segment (Larsen, Gottschalk, Lin, Manocha, "Fast proximity queries with swept sphere
///     volumes", 1999);
///   - k-DOP nodes: the shape's own k-DOP in the mesh frame (K support queries; Klosowski et al., TVCG 1998), so
///     the test is K/2 slab comparisons without re-alignment;
///   - sphere nodes: the centre's distance to the swept sphere or to the box;
///   - round shapes (anything but a box, sphere or capsule): a node that passes the box test must also pass the
///     centre gap (ShapeBound::centre_gap, one support query), which rejects the nodes that only meet the box's
///     empty corners; RSS distance bounds take the larger of the two.
/// All bounds are padded by `slack`, which covers the rounding of the pose and the touching tolerance of the
/// triangle tests (GJK counts pairs within 256ε of the coordinates' magnitude as touching), so a node is never
/// culled while one of its triangles would be reported: the tree query answers what testing every triangle does.

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/bv_distance.hpp"
#include "cdkit/bv/detail/obb_sibling_test.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/rss.hpp"
#include "cdkit/bv/sphere.hpp"
#include "cdkit/narrowphase/convex_shapes.hpp"
#include "cdkit/narrowphase/support.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace cdkit {
namespace detail {

template <class C> inline constexpr bool is_sphere_v = std::is_same_v<C, cdkit::Sphere<typename C::Scalar>>;
template <class C> inline constexpr bool is_capsule_v = std::is_same_v<C, cdkit::Capsule<typename C::Scalar>>;
template <class C> inline constexpr bool is_box_v = std::is_same_v<C, cdkit::Box<typename C::Scalar>>;

/// The shape (local frame) placed in the mesh frame by `pose`, bounded. S: the mesh's scalar.
template <class S> struct ShapeBound {
    Transform<S> pose;                        ///< shape frame → mesh frame
    Vec3<S> local_center, local_half;         ///< the shape's local box (padded by slack)
    Obb<S> box;                               ///< that box in the mesh frame
    bool swept = false;                       ///< sphere or capsule: exactly the segment [seg0, seg1] grown by radius
    bool box_is_shape = false;                ///< a Box: the local box is the shape itself (no centre gap needed)
    Vec3<S> seg0 = Vec3<S>::Zero(), seg1 = Vec3<S>::Zero();
    S radius = S(0);
    S slack = S(0);                           ///< rounding / touching padding, mesh-frame length
    bool finite = false;                      ///< the support map answered finite points
    Vec3<S> center = Vec3<S>::Zero();         ///< the shape's interior point (center()) in the mesh frame
    const void* shape = nullptr;              ///< the shape, for support() (type erased: one indirect call)
    Vec3<S> (*local_support)(const void*, const Vec3<S>&) noexcept = nullptr;
    /// The placed shape's support point along the mesh-frame direction d.
    [[nodiscard]] Vec3<S> support(const Vec3<S>& d) const noexcept {
        return pose * local_support(shape, Vec3<S>(pose.R.transpose() * d));
    }
    /// A lower bound on the distance between the shape and a convex set K, from q, the point of K nearest the
    /// shape's centre: K lies beyond the plane through q orthogonal to u = (q − centre)/|q − centre| (q is K's
    /// nearest point), the shape below u·support(u). Cheap (one support query) and tight for round shapes, where
    /// a box bound leaves the corners. 0 (no information) when q is the centre.
    [[nodiscard]] S centre_gap(const Vec3<S>& q) const noexcept {
        const Vec3<S> w = q - center;
        const S len = w.norm();
        if (!(len > S(0))) return S(0);
        const Vec3<S> u = w / len;
        return u.dot(q) - u.dot(support(u)) - slack;
    }
};

/// Builds the bound of `shape` under `pose` (shape → mesh frame). `finite` false when a support point is not
/// finite (NaN or infinite sizes): the query then refuses the input.
template <SupportMapped C, class S>
[[nodiscard]] ShapeBound<S> make_shape_bound(const C& shape, const Transform<S>& pose) noexcept {
    ShapeBound<S> b;
    b.pose = pose;
    const auto [lo, hi] = support_box(shape);
    b.finite = lo.allFinite() && hi.allFinite() && (hi.array() >= lo.array()).all();
    if (!b.finite) return b;
    const Vec3<S> c = (lo + hi) * S(0.5);
    const Vec3<S> h = (hi - lo) * S(0.5);
    b.shape = &shape;
    b.local_support = [](const void* p, const Vec3<S>& d) noexcept {
        return Vec3<S>(static_cast<const C*>(p)->support(d));
    };
    b.center = pose * Vec3<S>(shape.center());
    const S eps = std::numeric_limits<S>::epsilon();
    // Magnitudes of everything the triangle tests compute with near this shape: its placement and its size.
    const S magnitude = pose.t.cwiseAbs().maxCoeff() + c.cwiseAbs().maxCoeff() + h.cwiseAbs().maxCoeff();
    b.slack = S(1024) * eps * magnitude + std::numeric_limits<S>::min();
    b.local_center = c;
    b.local_half = h + Vec3<S>::Constant(b.slack);
    b.box.axes = pose.R;
    b.box.center = pose * c;
    b.box.half = b.local_half;
    b.box_is_shape = is_box_v<C>;
    if constexpr (is_sphere_v<C>) {
        b.swept = true;
        b.seg0 = b.seg1 = pose.t;
        b.radius = shape.radius;
    } else if constexpr (is_capsule_v<C>) {
        b.swept = true;
        const Vec3<S> axis = pose.R.col(2) * shape.half_length;
        b.seg0 = pose.t - axis;
        b.seg1 = pose.t + axis;
        b.radius = shape.radius;
    }
    return b;
}

/// Squared distance of p to the box (centre c, axes columns of R, half extents h).
template <class S>
[[nodiscard]] inline S point_box_dist2(const Vec3<S>& p, const Mat3<S>& R, const Vec3<S>& c, const Vec3<S>& h) noexcept {
    const Vec3<S> q = R.transpose() * (p - c);
    const Vec3<S> e = (q.cwiseAbs() - h).cwiseMax(S(0));
    return e.squaredNorm();
}

/// Squared distance of p to the segment [a, b].
template <class S> [[nodiscard]] inline S point_segment_dist2(const Vec3<S>& p, const Vec3<S>& a, const Vec3<S>& b) noexcept {
    const Vec3<S> d = b - a;
    const S dd = d.squaredNorm();
    S t = dd > S(0) ? (p - a).dot(d) / dd : S(0);
    t = std::clamp(t, S(0), S(1));
    return (p - (a + d * t)).squaredNorm();
}

template <class S> [[nodiscard]] inline Obb<S> identity_obb(const Vec3<S>& c, const Vec3<S>& h) noexcept {
    Obb<S> o;
    o.center = c;
    o.half = h;
    return o;
}

/// The test of one node of a `BV` tree (over a mesh of scalar M) against the shape's bound: `overlaps(bv)`
/// (false only when no point of the shape is in the node's volume, up to the bound's padding) and
/// `lower_bound(bv, cutoff)` (at most the distance of any triangle in the node to the shape; may stop early once
/// it reaches `cutoff`). Specialised per BV type below; others fail to compile here.
template <class BV, class M> struct NodeTester {
    static_assert(sizeof(BV) == 0,
                  "mesh-convex queries support MeshModel trees of Aabb, Obb, Rss, Kdop<K> and BoundingSphere: "
                  "this bounding volume has no NodeTester (mesh_convex/shape_bound.hpp)");
};

/// Separating-axis test of an oriented box (axes A, centre c, half extents a) against the probe box `p` (both in
/// the mesh frame), in A's frame: one 3×3 product per node (the library's overlap() under a relative transform
/// takes two). A's face axes are first tried against the probe's circumscribed ball (`p_radius`), which needs only
/// the centre offset: most culled nodes stop there.
template <class S>
[[nodiscard]] inline bool obb_probe_disjoint(const Mat3<S>& A, const Vec3<S>& c, const Vec3<S>& a, const Obb<S>& p,
                                             S p_radius) noexcept {
    const Vec3<S> T = A.transpose() * (p.center - c);
    if (std::abs(T[0]) > a[0] + p_radius || std::abs(T[1]) > a[1] + p_radius || std::abs(T[2]) > a[2] + p_radius)
        return true;
    const Mat3<S> Rb = A.transpose() * p.axes;
    return boxes_disjoint(a, p.half, Rb, abs_with_slack(Rb), T, S(0));
}

template <class T, class M> struct NodeTester<Obb<T>, M> {
    const ShapeBound<M>& b;
    typename Obb<M>::Relative rel = Obb<M>::relative(Transform<M>{});
    M probe_radius;
    template <class C> NodeTester(const ShapeBound<M>& bound, const C&) noexcept
        : b(bound), probe_radius(bound.box.half.norm() * (M(1) + M(8) * std::numeric_limits<M>::epsilon())) {}
    static Obb<M> widen(const Obb<T>& n) noexcept {
        if constexpr (std::is_same_v<T, M>) return n;
        else {
            Obb<M> o;
            o.axes = n.axes.template cast<M>();
            o.center = n.center.template cast<M>();
            o.half = n.half.template cast<M>();
            return o;
        }
    }
    [[nodiscard]] bool overlaps(const Obb<T>& n) const noexcept {
        if constexpr (std::is_same_v<T, M>) return overlaps_same(n);  // no copy of the node
        else return overlaps_same(widen(n));
    }
    [[nodiscard]] bool overlaps_same(const Obb<M>& node) const noexcept {
        if (b.swept && b.seg0 == b.seg1) {
            const M r = b.radius + b.slack;
            return point_box_dist2(b.seg0, node.axes, node.center, node.half) <= r * r;
        }
        if (obb_probe_disjoint(node.axes, node.center, node.half, b.box, probe_radius)) return false;
        return b.swept || b.box_is_shape || !corner_only(node);
    }
    /// Whether the descent tests both children of a node at once (children_overlap): for every bound but a
    /// sphere's, whose test (a point's distance to the box) has nothing to share between two lanes (testing both
    /// children eagerly was slower on it in a first A/B of the mesh–convex benchmark).
    [[nodiscard]] bool tests_siblings() const noexcept { return !(b.swept && b.seg0 == b.seg1); }
    /// Both children of a node at once, in two SIMD lanes (bv/detail/obb_sibling_test.hpp), with the deeper-
    /// overlapping one to enter first; each child's answer is overlaps()' up to the rounding of the lanes' products
    /// (both within the slacks: no node with a touching triangle is culled).
    [[nodiscard]] CDKIT_ALWAYS_INLINE SiblingOverlap children_overlap(const Obb<T>& c0, const Obb<T>& c1) const noexcept {
        if (b.swept && b.seg0 == b.seg1) {  // a sphere: its centre's distance to each box
            SiblingOverlap s;
            s.overlap[0] = overlaps(c0), s.overlap[1] = overlaps(c1);
            return s;
        }
        SiblingOverlap s = children_overlap_probe<M>(c0, c1, b.box, probe_radius);
        if (!(b.swept || b.box_is_shape)) {
            if (s.overlap[0] && corner_only(widen(c0))) s.overlap[0] = false, s.second_first = false;
            if (s.overlap[1] && corner_only(widen(c1))) s.overlap[1] = false, s.second_first = false;
        }
        return s;
    }
    /// Round shapes (hulls, ellipsoids, cylinders, cones) leave their box's corners empty: the centre gap to the
    /// node's point nearest the shape's centre rejects the nodes that only meet a corner. Out of line: the box,
    /// sphere and capsule never take it, and their node test is the hot loop.
    CDKIT_NOINLINE bool corner_only(const Obb<M>& node) const noexcept {
        const Vec3<M> q = node.axes.transpose() * (b.center - node.center);
        const Vec3<M> nearest = node.center + node.axes * q.cwiseMax(-node.half).cwiseMin(node.half);
        return b.centre_gap(nearest) > M(0);
    }
    [[nodiscard]] M lower_bound(const Obb<T>& n, M cutoff) const noexcept {
        const Obb<M> node = widen(n);
        if (b.swept && b.seg0 == b.seg1)
            return std::sqrt(point_box_dist2(b.seg0, node.axes, node.center, node.half)) - b.radius - b.slack;
        return distance_lower_bound(node, b.box, rel, cutoff);
    }
};

template <class T, class M> struct NodeTester<Aabb<T>, M> {
    const ShapeBound<M>& b;
    Aabb<M> local;                     ///< the shape's local box
    typename Aabb<M>::Relative rel;    ///< shape frame → mesh frame
    template <class C> NodeTester(const ShapeBound<M>& bound, const C&) noexcept
        : b(bound), local{bound.local_center, bound.local_half}, rel(Aabb<M>::relative(bound.pose)) {}
    static Aabb<M> widen(const Aabb<T>& n) noexcept { return {n.center.template cast<M>(), n.half.template cast<M>()}; }
    [[nodiscard]] bool overlaps(const Aabb<T>& n) const noexcept {
        const Aabb<M> node = widen(n);
        if (b.swept && b.seg0 == b.seg1) {
            const M r = b.radius + b.slack;
            return (((b.seg0 - node.center).cwiseAbs() - node.half).cwiseMax(M(0))).squaredNorm() <= r * r;
        }
        return overlap(node, local, rel);
    }
    [[nodiscard]] M lower_bound(const Aabb<T>& n, M cutoff) const noexcept {
        const Aabb<M> node = widen(n);
        if (b.swept && b.seg0 == b.seg1)
            return std::sqrt((((b.seg0 - node.center).cwiseAbs() - node.half).cwiseMax(M(0))).squaredNorm()) -
                   b.radius - b.slack;
        return distance_lower_bound(node, local, rel, cutoff);
    }
};

template <class T, class M> struct NodeTester<Rss<T>, M> {
    const ShapeBound<M>& b;
    Rss<M> probe;  ///< swept shapes: the segment grown by the radius, as a degenerate RSS in the mesh frame
    typename Obb<M>::Relative rel = Obb<M>::relative(Transform<M>{});
    template <class C> NodeTester(const ShapeBound<M>& bound, const C&) noexcept : b(bound) {
        if (!b.swept) return;
        const Vec3<M> d = b.seg1 - b.seg0;
        const M len = d.norm();
        const Vec3<M> u = len > M(0) ? Vec3<M>(d / len) : Vec3<M>::UnitX();
        const Vec3<M> v = u.unitOrthogonal();
        probe.axes.col(0) = u;
        probe.axes.col(1) = v;
        probe.axes.col(2) = u.cross(v);
        probe.center = (b.seg0 + b.seg1) * M(0.5);
        probe.half = typename Rss<M>::Vec2(len * M(0.5), M(0));
        probe.radius = b.radius + b.slack;
    }
    static Rss<M> widen(const Rss<T>& n) noexcept {
        if constexpr (std::is_same_v<T, M>) return n;
        else {
            Rss<M> o;
            o.axes = n.axes.template cast<M>();
            o.center = n.center.template cast<M>();
            o.half = n.half.template cast<M>();
            o.radius = M(n.radius);
            return o;
        }
    }
    /// The box around an RSS: the rectangle grown by the radius on every side.
    static Obb<M> box_of(const Rss<M>& r) noexcept {
        Obb<M> o;
        o.axes = r.axes;
        o.center = r.center;
        o.half = Vec3<M>(r.half[0] + r.radius, r.half[1] + r.radius, r.radius);
        return o;
    }
    /// The rectangle alone, as a flat box (the RSS is it grown by the radius).
    static Obb<M> rectangle_of(const Rss<M>& r) noexcept {
        Obb<M> o;
        o.axes = r.axes;
        o.center = r.center;
        o.half = Vec3<M>(r.half[0], r.half[1], M(0));
        return o;
    }
    [[nodiscard]] bool overlaps(const Rss<T>& n) const noexcept {
        const Rss<M> node = widen(n);
        if (b.swept) return !(distance_lower_bound_same_frame(node, probe, M(0)) > M(0));
        return overlap(box_of(node), b.box, rel);
    }
    /// Generic shapes: dist(rectangle ⊕ ball, box) = max(dist(rectangle, box) − radius, 0), so the box bound of the
    /// flat rectangle minus the radius (tighter than the box around the whole RSS, whose corners are square).
    /// Also the centre gap (ShapeBound::centre_gap) to the RSS's point nearest the shape's centre: the rectangle's
    /// nearest point moved towards the centre by the radius. The larger of the two bounds is kept.
    [[nodiscard]] M lower_bound(const Rss<T>& n, M cutoff) const noexcept {
        const Rss<M> node = widen(n);
        if (b.swept) return distance_lower_bound_same_frame(node, probe, M(0), cutoff);
        const M box = distance_lower_bound(rectangle_of(node), b.box, rel, cutoff + node.radius) - node.radius;
        if (box >= cutoff || b.box_is_shape) return box;  // a box's own bound is exact: the gap adds only cost
        const Vec3<M> d = b.center - node.center;
        const M x = std::clamp(d.dot(node.axes.col(0)), -node.half[0], node.half[0]);
        const M y = std::clamp(d.dot(node.axes.col(1)), -node.half[1], node.half[1]);
        const Vec3<M> q = node.center + node.axes.col(0) * x + node.axes.col(1) * y;
        const M len = (b.center - q).norm();
        if (!(len > node.radius)) return box;  // the centre is inside the RSS
        const Vec3<M> on_rss = q + (b.center - q) * (node.radius / len);
        return std::max(box, b.centre_gap(on_rss) * (M(1) - M(64) * std::numeric_limits<M>::epsilon()));
    }
};

template <class T, int K, class M> struct NodeTester<Kdop<T, K>, M> {
    static constexpr int N = K / 2;
    const ShapeBound<M>& b;
    std::array<M, K> h;  ///< the shape's own K-DOP in the mesh frame (support values, padded)
    template <class C> NodeTester(const ShapeBound<M>& bound, const C& shape) noexcept : b(bound) {
        for (int j = 0; j < N; ++j) {
            const auto& d = Kdop<T, K>::directions[j];
            const Vec3<M> dw{M(d[0]), M(d[1]), M(d[2])};
            const M pad = b.slack * M(std::abs(d[0]) + std::abs(d[1]) + std::abs(d[2]));
            const Vec3<M> up = b.pose * Vec3<M>(shape.support(Vec3<M>(b.pose.R.transpose() * dw)));
            const Vec3<M> down = b.pose * Vec3<M>(shape.support(Vec3<M>(-(b.pose.R.transpose() * dw))));
            h[j] = kdop_project(d, up) + pad;
            h[N + j] = -kdop_project(d, down) + pad;
        }
    }
    [[nodiscard]] bool overlaps(const Kdop<T, K>& n) const noexcept {
        for (int j = 0; j < N; ++j)
            if (h[j] < -M(n.h[N + j]) || -h[N + j] > M(n.h[j])) return false;
        return true;
    }
    /// The largest slab gap over the K/2 directions, each divided by its direction's length (a projection onto a
    /// unit direction is 1-Lipschitz, so any one gap bounds the distance from below).
    [[nodiscard]] M lower_bound(const Kdop<T, K>& n, M) const noexcept {
        M best = 0;
        for (int j = 0; j < N; ++j) {
            const auto& d = Kdop<T, K>::directions[j];
            const M gap = std::max(-M(n.h[N + j]) - h[j], -h[N + j] - M(n.h[j]));
            if (gap > M(0)) best = std::max(best, gap / std::sqrt(M(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])));
        }
        return best * (M(1) - M(16) * std::numeric_limits<M>::epsilon());
    }
};

template <class T, class M> struct NodeTester<BoundingSphere<T>, M> {
    const ShapeBound<M>& b;
    template <class C> NodeTester(const ShapeBound<M>& bound, const C&) noexcept : b(bound) {}
    /// Distance of the ball's centre to the shape's bound, minus the bound's radius and slack.
    [[nodiscard]] M centre_distance(const Vec3<M>& c) const noexcept {
        if (b.swept) return std::sqrt(point_segment_dist2(c, b.seg0, b.seg1)) - b.radius - b.slack;
        return std::sqrt(point_box_dist2(c, b.box.axes, b.box.center, b.box.half));
    }
    [[nodiscard]] bool overlaps(const BoundingSphere<T>& n) const noexcept {
        return centre_distance(n.center.template cast<M>()) <= M(n.radius);
    }
    [[nodiscard]] M lower_bound(const BoundingSphere<T>& n, M) const noexcept {
        return (centre_distance(n.center.template cast<M>()) - M(n.radius)) *
               (M(1) - M(16) * std::numeric_limits<M>::epsilon());
    }
};

}  // namespace detail
}  // namespace cdkit
