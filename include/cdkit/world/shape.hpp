#pragma once
/// \file The representation an object of a World carries: the cheapest one that answers its queries
/// (sphere, box, capsule, cylinder, cone, ellipsoid, triangle, convex hull, or a mesh with its BVH), chosen by the user (or suggested by
/// suggest_representation.hpp), optionally placed in the object's frame by a fixed offset.
///
/// Shapes are immutable values; hulls and mesh models are held by shared_ptr so many objects can share
/// one (a hundred crates share one hull). All members are const and thread-safe.

#include "cdkit/bv/obb.hpp"
#include "cdkit/broadphase/box.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/core/error.hpp"
#include "cdkit/narrowphase/convex_polyhedron.hpp"
#include "cdkit/narrowphase/convex_shapes.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <variant>

namespace cdkit {

/// Which representation a Shape holds.
/// (The order is the one of Shape's variant; later kinds were added at the end.)
enum class ShapeKind { sphere, box, capsule, convex_hull, mesh, cylinder, cone, ellipsoid, triangle, compound };

/// Name of a kind, for messages and reports.
[[nodiscard]] inline const char* to_string(ShapeKind k) noexcept {
    switch (k) {
        case ShapeKind::sphere: return "sphere";
        case ShapeKind::box: return "box";
        case ShapeKind::capsule: return "capsule";
        case ShapeKind::convex_hull: return "convex_hull";
        case ShapeKind::mesh: return "mesh";
        case ShapeKind::cylinder: return "cylinder";
        case ShapeKind::cone: return "cone";
        case ShapeKind::ellipsoid: return "ellipsoid";
        case ShapeKind::triangle: return "triangle";
        case ShapeKind::compound: return "compound";
    }
    return "?";
}

template <class S> class CompoundShape;

/// The BVH type World uses for meshes (OBB trees: tight for rigid meshes, see docs/bvh.md).
template <class S> using WorldMeshModel = MeshModel<Obb<S>>;

/// A collision representation in its local frame. Convex kinds go to GJK/EPA, meshes to the BVH queries.
template <class S = double> class Shape {
public:
    using Scalar = S;
    using Hull = std::shared_ptr<const ConvexPolyhedron<S>>;
    using Mesh = std::shared_ptr<const WorldMeshModel<S>>;
    using Compound = std::shared_ptr<const CompoundShape<S>>;

    /// Ball of radius r ≥ 0 centred at the origin (throws cdkit::Error for a negative or non-finite r).
    [[nodiscard]] static Shape sphere(S radius) { return Shape(Sphere<S>(radius)); }
    /// Box with the given half extents (≥ 0, finite), centred at the origin, axis-aligned in its frame.
    [[nodiscard]] static Shape box(const Vec3<S>& half_extents) { return Shape(Box<S>(half_extents)); }
    /// Capsule: segment from (0,0,−half_length) to (0,0,+half_length) grown by radius.
    [[nodiscard]] static Shape capsule(S radius, S half_length) { return Shape(Capsule<S>(radius, half_length)); }
    /// Cylinder of radius r around the z axis, z ∈ [−half_height, half_height].
    [[nodiscard]] static Shape cylinder(S radius, S half_height) { return Shape(Cylinder<S>(radius, half_height)); }
    /// Cone: base disc of radius r at z = −half_height, apex at z = +half_height.
    [[nodiscard]] static Shape cone(S radius, S half_height) { return Shape(Cone<S>(radius, half_height)); }
    /// Axis-aligned ellipsoid with the given semi-axes (≥ 0, finite).
    [[nodiscard]] static Shape ellipsoid(const Vec3<S>& radii) { return Shape(Ellipsoid<S>(radii)); }
    /// A flat triangle (finite vertices; a degenerate one is a segment or a point, still convex).
    [[nodiscard]] static Shape triangle(const Vec3<S>& a, const Vec3<S>& b, const Vec3<S>& c) {
        return Shape(ConvexTriangle<S>(a, b, c));
    }
    /// Convex hull of points (Qhull; throws cdkit::Error for < 4 points, NaN, or a flat set).
    [[nodiscard]] static Shape convex_hull(const std::vector<Vec3<S>>& points) {
        return convex_hull(std::make_shared<const ConvexPolyhedron<S>>(points));
    }
    /// A shared, already built hull (throws cdkit::Error for nullptr).
    [[nodiscard]] static Shape convex_hull(Hull hull) {
        if (!hull) throw Error("<world>", "convex hull shape", "null hull");
        return Shape(std::move(hull));
    }
    /// A shared mesh model (triangle soup or closed mesh with its BVH; throws cdkit::Error for nullptr).
    [[nodiscard]] static Shape mesh(Mesh model) {
        if (!model) throw Error("<world>", "mesh shape", "null mesh model");
        return Shape(std::move(model));
    }
    /// Builds the BVH of a mesh (validates it: cdkit::Error naming mesh.source on bad data).
    [[nodiscard]] static Shape mesh(TriangleMesh<S> m) {
        return mesh(std::make_shared<const WorldMeshModel<S>>(std::move(m)));
    }

    /// Several convex shapes moving as one rigid object (the usual model of a concave object: a convex
    /// decomposition), each placed in the object's frame by its own offset (`with_offset`). Throws cdkit::Error for
    /// no children, a mesh child or a compound child. A small tree over the children's boxes finds the ones near
    /// the other shape; World reports one contact per touching child pair (WorldContact::child_a / child_b).
    [[nodiscard]] static Shape compound(std::vector<Shape> children);

    /// The same shape placed by a fixed rigid `offset` in the object's frame (object pose · offset places
    /// it in the world). Throws cdkit::Error when the offset is not a rigid motion.
    [[nodiscard]] Shape with_offset(const Transform<S>& offset) const {
        if (!pose_is_usable(offset)) throw Error("<world>", "shape offset", "not a finite rigid motion");
        Shape s = *this;
        s.offset_ = offset;
        s.has_offset_ = true;
        return s;
    }

    /// The same convex shape with its surface pushed out by `radius` (the Minkowski sum with a ball of that radius:
    /// a rounded box, a rounded hull; rounding a sphere or capsule grows its radius). Roundings add up. A pair's
    /// contacts are those of the cores within the sum of the two roundings, so no new shape type is made (GJK's margin
    /// idea: van den Bergen, "Collision Detection in Interactive 3D Environments", 2003, §4.3.6). Throws cdkit::Error
    /// for a mesh or compound, or a negative or non-finite radius.
    [[nodiscard]] Shape rounded(S radius) const {
        if (!is_convex())
            throw Error("<world>", "rounded shape", std::string("a ") + to_string(kind()) + " (only convex shapes can be rounded)");
        if (!(radius >= S(0)) || !std::isfinite(radius))
            throw Error("<world>", "rounded shape", "the radius must be finite and >= 0");
        Shape s = *this;
        s.rounding_ += radius;
        s.local_ = Aabb<S>{local_.center, Vec3<S>(local_.half.array() + radius)};
        return s;
    }
    /// The rounding radius (0 unless `rounded`).
    [[nodiscard]] S rounding() const noexcept { return rounding_; }

    [[nodiscard]] ShapeKind kind() const noexcept { return ShapeKind(value_.index()); }
    [[nodiscard]] bool is_convex() const noexcept { return kind() != ShapeKind::mesh && kind() != ShapeKind::compound; }
    [[nodiscard]] bool is_compound() const noexcept { return kind() == ShapeKind::compound; }
    [[nodiscard]] const Transform<S>& offset() const noexcept { return offset_; }
    [[nodiscard]] bool has_offset() const noexcept { return has_offset_; }
    /// The pose of the shape's own frame for an object at `pose`.
    [[nodiscard]] Transform<S> placed(const Transform<S>& pose) const { return has_offset_ ? pose * offset_ : pose; }

    /// Calls f(support_mapped_shape) for a convex kind (precondition: is_convex()).
    template <class F> decltype(auto) visit_convex(F&& f) const {
        switch (kind()) {
            case ShapeKind::sphere: return f(std::get<0>(value_));
            case ShapeKind::box: return f(std::get<1>(value_));
            case ShapeKind::capsule: return f(std::get<2>(value_));
            case ShapeKind::cylinder: return f(std::get<5>(value_));
            case ShapeKind::cone: return f(std::get<6>(value_));
            case ShapeKind::ellipsoid: return f(std::get<7>(value_));
            case ShapeKind::triangle: return f(std::get<8>(value_));
            default: return f(*std::get<3>(value_));
        }
    }
    /// The mesh model (precondition: kind() == ShapeKind::mesh).
    [[nodiscard]] const WorldMeshModel<S>& mesh_model() const noexcept { return *std::get<4>(value_); }
    /// The compound's children and tree (precondition: kind() == ShapeKind::compound).
    [[nodiscard]] const CompoundShape<S>& compound_shape() const noexcept { return *std::get<9>(value_); }

    /// Local box (centre, half extents) of the shape in its own frame.
    [[nodiscard]] const Aabb<S>& local_bounds() const noexcept { return local_; }
    /// World-space box for an object at `pose`: the local box carried by the pose (|R|·half), conservative.
    [[nodiscard]] BroadBox<S> world_box(const Transform<S>& pose) const noexcept {
        const Transform<S> p = has_offset_ ? pose * offset_ : pose;
        const Vec3<S> c = p.R * local_.center + p.t;
        const Vec3<S> h = p.R.cwiseAbs() * local_.half;
        return BroadBox<S>::from_center_half(c, h);
    }

private:
    using Value = std::variant<Sphere<S>, Box<S>, Capsule<S>, Hull, Mesh, Cylinder<S>, Cone<S>, Ellipsoid<S>,
                               ConvexTriangle<S>, Compound>;
    explicit Shape(Value v) : value_(std::move(v)) { local_ = compute_local(); }

    Aabb<S> compute_local() const {
        switch (kind()) {
            case ShapeKind::sphere: {
                const S r = std::get<0>(value_).radius;
                return Aabb<S>::from_min_max(Vec3<S>::Constant(-r), Vec3<S>::Constant(r));
            }
            case ShapeKind::box: {
                const Vec3<S> h = std::get<1>(value_).half;
                return Aabb<S>::from_min_max(-h, h);
            }
            case ShapeKind::capsule: {
                const auto& c = std::get<2>(value_);
                const Vec3<S> h(c.radius, c.radius, c.radius + c.half_length);
                return Aabb<S>::from_min_max(-h, h);
            }
            case ShapeKind::cylinder: {
                const auto& c = std::get<5>(value_);
                const Vec3<S> h(c.radius, c.radius, c.half_height);
                return Aabb<S>::from_min_max(-h, h);
            }
            case ShapeKind::cone: {
                const auto& c = std::get<6>(value_);
                const Vec3<S> h(c.radius, c.radius, c.half_height);
                return Aabb<S>::from_min_max(-h, h);
            }
            case ShapeKind::ellipsoid: {
                const Vec3<S> r = std::get<7>(value_).radii;
                return Aabb<S>::from_min_max(-r, r);
            }
            case ShapeKind::triangle: {
                const auto& t = std::get<8>(value_);
                return bounds_of({t.a, t.b, t.c});
            }
            case ShapeKind::compound: return std::get<9>(value_)->bounds();
            case ShapeKind::convex_hull: return bounds_of(std::get<3>(value_)->vertices());
            case ShapeKind::mesh: return bounds_of(std::get<4>(value_)->mesh().vertices);
        }
        return {};
    }
    static Aabb<S> bounds_of(const std::vector<Vec3<S>>& v) {
        Vec3<S> lo = v.front(), hi = v.front();
        for (const auto& p : v) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
        return Aabb<S>::from_min_max(lo, hi);
    }

    Value value_;
    Aabb<S> local_;  ///< grown by the rounding
    Transform<S> offset_{};
    bool has_offset_ = false;
    S rounding_ = S(0);
};

/// The children of a compound Shape and a small bounding-box tree over them (median splits of the children's boxes,
/// at most two children per leaf), all in the compound's frame. Immutable; const members are thread-safe.
template <class S> class CompoundShape {
public:
    explicit CompoundShape(std::vector<Shape<S>> children) : children_(std::move(children)) {
        if (children_.empty()) throw Error("<world>", "compound shape", "no children");
        boxes_.reserve(children_.size());
        for (std::size_t i = 0; i < children_.size(); ++i) {
            if (!children_[i].is_convex())
                throw Error("<world>", "compound shape child " + std::to_string(i),
                            std::string("a ") + to_string(children_[i].kind()) + " (children must be convex)");
            boxes_.push_back(children_[i].world_box(Transform<S>{}));
        }
        order_.resize(children_.size());
        for (std::uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
        build(0, std::uint32_t(order_.size()));
        bounds_ = Aabb<S>::from_min_max(nodes_.front().box.lo, nodes_.front().box.hi);
    }
    [[nodiscard]] const std::vector<Shape<S>>& children() const noexcept { return children_; }
    /// The box of all children (compound frame).
    [[nodiscard]] const Aabb<S>& bounds() const noexcept { return bounds_; }
    /// Calls f(i) for every child whose box overlaps `query` (compound frame; touching counts).
    template <class F> void for_each_child_overlapping(const BroadBox<S>& query, F&& f) const {
        std::uint32_t stack[64];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& n = nodes_[stack[--top]];
            if (!overlap(n.box, query)) continue;
            if (n.count > 0) {
                for (std::uint32_t k = n.first; k < n.first + n.count; ++k)
                    if (overlap(boxes_[order_[k]], query)) f(order_[k]);
            } else {
                stack[top++] = n.left;
                stack[top++] = n.right;
            }
        }
    }

private:
    struct Node {
        BroadBox<S> box;
        std::uint32_t first = 0, count = 0;  ///< a leaf: the children order_[first, first + count)
        std::uint32_t left = 0, right = 0;   ///< an inner node (count 0): its two nodes
    };
    /// Builds the node over order_[begin, end) and returns its index (the root is node 0). Depth ≤ log2(n) + 1.
    std::uint32_t build(std::uint32_t begin, std::uint32_t end) {
        BroadBox<S> box = boxes_[order_[begin]];
        for (std::uint32_t k = begin; k < end; ++k) {
            box.lo = box.lo.cwiseMin(boxes_[order_[k]].lo);
            box.hi = box.hi.cwiseMax(boxes_[order_[k]].hi);
        }
        const std::uint32_t index = std::uint32_t(nodes_.size());
        nodes_.push_back({box, begin, end - begin, 0, 0});
        if (end - begin <= 2) return index;
        int axis = 0;
        (box.hi - box.lo).maxCoeff(&axis);
        const std::uint32_t mid = begin + (end - begin) / 2;
        const auto centre = [&](std::uint32_t c) { return boxes_[c].lo[axis] + boxes_[c].hi[axis]; };
        std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                         [&](std::uint32_t x, std::uint32_t y) { return centre(x) < centre(y); });
        const std::uint32_t left = build(begin, mid), right = build(mid, end);
        nodes_[index].count = 0;
        nodes_[index].left = left;
        nodes_[index].right = right;
        return index;
    }

    std::vector<Shape<S>> children_;
    std::vector<BroadBox<S>> boxes_;
    std::vector<std::uint32_t> order_;
    std::vector<Node> nodes_;
    Aabb<S> bounds_;
};

template <class S> Shape<S> Shape<S>::compound(std::vector<Shape<S>> children) {
    return Shape(std::make_shared<const CompoundShape<S>>(std::move(children)));
}

}  // namespace cdkit
