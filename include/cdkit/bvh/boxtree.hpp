#pragma once
/// \file RestrictedBoxtree<S>: the restricted boxtree of Zachmann, "Minimal hierarchical collision
/// detection", VRST 2002. Every node's box is implied: the root stores the mesh's bounding box, and each other
/// node moves exactly one face of its parent's box inwards (one axis, one side, one float plane). A node is
/// 8 bytes (the plane, and 32 bits packing axis, side, kind and a child or triangle index); leaves hold one
/// triangle. The tree stores no copy of the geometry.
///
/// Planes are stored in float, in the tree's local frame (the model frame shifted to the centre of the mesh's
/// bounding box, so float resolution follows the object's size, not its distance from the origin), rounded
/// outwards: the implied box of every node contains its triangles' vertices, padded like the other BV fits
/// (detail::fit_padding) so that queries stay conservative against the rounded transformed vertices.
///
/// A node whose triangles' box differs from its parent's on several faces gets (optionally) a chain of
/// one-child nodes, each restricting one more face, before the node that splits (BoxtreeOptions).
/// The collision query is in bvh/boxtree_collide.hpp.

#include "cdkit/bv/fit.hpp"
#include "cdkit/core/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

namespace cdkit {

/// One node of a restricted boxtree: 8 bytes. Its box is its parent's box with the face (axis, side) moved
/// to `plane` (for the root, and for `axis() == no_axis`, the parent's box unchanged).
struct BoxtreeNode {
    enum class Kind : std::uint32_t {
        leaf = 0,          ///< index() is a triangle of the mesh
        one_child = 1,     ///< a further restriction of the same triangles: the child is at index()
        two_children = 2,  ///< children at index() and index() + 1
    };
    static constexpr std::uint32_t no_axis = 3;
    static constexpr std::uint32_t index_bits = 27;
    static constexpr std::uint32_t max_index = (std::uint32_t(1) << index_bits) - 1;

    float plane = 0;          ///< the moved face's coordinate, in the tree's local frame
    std::uint32_t bits = no_axis;  ///< axis (2 bits) | upper side (1) | kind (2) | index (27)

    [[nodiscard]] std::uint32_t axis() const noexcept { return bits & 3u; }
    /// True: the node's box max along axis() is `plane`; false: its min.
    [[nodiscard]] bool upper() const noexcept { return (bits >> 2) & 1u; }
    [[nodiscard]] Kind kind() const noexcept { return Kind((bits >> 3) & 3u); }
    [[nodiscard]] bool is_leaf() const noexcept { return kind() == Kind::leaf; }
    [[nodiscard]] std::uint32_t index() const noexcept { return bits >> 5; }

    void set_restriction(std::uint32_t axis, bool upper_side, float value) noexcept {
        plane = value;
        bits = (bits & ~7u) | (axis & 3u) | (std::uint32_t(upper_side) << 2);
    }
    void set_link(Kind k, std::uint32_t index) noexcept {
        bits = (bits & 7u) | (std::uint32_t(k) << 3) | (index << 5);
    }
};
static_assert(sizeof(BoxtreeNode) == 8, "a restricted boxtree node is one float and one packed 32-bit word");

/// An axis-aligned box as six floats: lo x, y, z, then hi x, y, z. The implied boxes of a boxtree.
using FloatBox = std::array<float, 6>;

/// How a boxtree build splits a node's triangles.
enum class BoxtreeSplit {
    median,       ///< object median of the centroids along the longest axis of the node's tight box (balanced)
    /// Binned surface area heuristic on the boxes the children will actually have: for 16 centroid bins on
    /// each axis, each side's tight box, the implied box that its one-face restriction (and one-child nodes)
    /// leaves of the parent's box, and cost area(implied L)·n_L + area(implied R)·n_R. Not balanced.
    implied_sah,
};

/// Build parameters. One-child nodes cost 8 bytes each and tighten the boxes where a single face is not
/// enough. The defaults keep the tree under the bytes of a double mesh (the bunny: 0.92×, 22.2 B per
/// triangle); `max_extra_restrictions = 0` gives the plain binary tree, 2n − 1 nodes (16 B per triangle,
/// under a float mesh's bytes too).
struct BoxtreeOptions {
    BoxtreeSplit split = BoxtreeSplit::implied_sah;
    /// At most this many one-child nodes before each node (0: a plain binary tree of 2n − 1 nodes).
    std::uint32_t max_extra_restrictions = 1;
    /// A one-child node is added only when its face cuts off at least this fraction of the box's surface area.
    float min_extra_gain = 0.25f;
};

/// Statistics of a built boxtree.
struct BoxtreeStats {
    std::size_t nodes = 0;
    std::size_t leaves = 0;
    std::size_t one_child_nodes = 0;
    std::size_t depth = 0;         ///< number of levels on the longest root-to-leaf path (one-child nodes count)
    std::size_t memory_bytes = 0;  ///< nodes + root box + centre
};

namespace detail {
/// The float nearest to x on the side that keeps a box conservative (±infinity beyond float's range, which
/// the build then rejects; the range is checked first because an out-of-range conversion is undefined).
[[nodiscard]] inline float boxtree_round_down(double x) noexcept {
    constexpr double top = double(std::numeric_limits<float>::max());
    if (x < -top) return -std::numeric_limits<float>::infinity();
    if (x > top) return std::numeric_limits<float>::max();
    float f = static_cast<float>(x);
    if (double(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}
[[nodiscard]] inline float boxtree_round_up(double x) noexcept {
    constexpr double top = double(std::numeric_limits<float>::max());
    if (x > top) return std::numeric_limits<float>::infinity();
    if (x < -top) return -std::numeric_limits<float>::max();
    float f = static_cast<float>(x);
    if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}
/// The box of `parent` with `node`'s restriction applied.
[[nodiscard]] inline FloatBox restrict_box(FloatBox box, const BoxtreeNode& node) noexcept {
    const std::uint32_t k = node.axis();
    if (k != BoxtreeNode::no_axis) box[node.upper() ? k + 3 : k] = node.plane;
    return box;
}
}  // namespace detail

/// A triangle mesh (shared, never copied by queries) with its restricted boxtree. Immutable once built:
/// queries on it are const and thread-safe.
template <class S = double> class RestrictedBoxtree {
public:
    using Scalar = S;
    using Node = BoxtreeNode;

    /// Validates the mesh and builds the tree. Throws cdkit::Error naming mesh->source on bad data (see
    /// cdkit::validate), when the mesh's extent around its centre does not fit float planes (beyond ~1e38),
    /// or when it has more triangles than the 27-bit node index can address.
    explicit RestrictedBoxtree(std::shared_ptr<const TriangleMesh<S>> mesh, const BoxtreeOptions& options = {})
        : mesh_(checked(std::move(mesh))), options_(options) {
        build();
    }
    explicit RestrictedBoxtree(TriangleMesh<S> mesh, const BoxtreeOptions& options = {})
        : RestrictedBoxtree(std::make_shared<const TriangleMesh<S>>(std::move(mesh)), options) {}

    [[nodiscard]] const TriangleMesh<S>& mesh() const noexcept { return *mesh_; }
    [[nodiscard]] const std::shared_ptr<const TriangleMesh<S>>& mesh_ptr() const noexcept { return mesh_; }
    [[nodiscard]] const std::vector<Node>& nodes() const noexcept { return nodes_; }
    /// The local frame's origin in the model frame: local = model − centre().
    [[nodiscard]] const Vec3<S>& centre() const noexcept { return centre_; }
    /// The root's box, in the local frame.
    [[nodiscard]] const FloatBox& root_box() const noexcept { return root_box_; }
    [[nodiscard]] std::size_t depth() const noexcept { return depth_; }
    /// Bytes of the tree alone (the mesh is the caller's and shared): nodes, root box and centre.
    [[nodiscard]] std::size_t memory_bytes() const noexcept {
        return nodes_.size() * sizeof(Node) + sizeof(root_box_) + sizeof(centre_);
    }
    [[nodiscard]] BoxtreeStats stats() const noexcept {
        BoxtreeStats s;
        s.nodes = nodes_.size();
        for (const Node& n : nodes_) {
            s.leaves += n.is_leaf();
            s.one_child_nodes += n.kind() == Node::Kind::one_child;
        }
        s.depth = depth_;
        s.memory_bytes = memory_bytes();
        return s;
    }

    /// Calls `visit(triangle, box)` for every leaf with its implied box (local frame).
    template <class Visit> void for_each_leaf(Visit&& visit) const {
        struct Item { std::uint32_t node; FloatBox box; };
        std::vector<Item> stack{{0u, root_box_}};
        while (!stack.empty()) {
            const Item it = stack.back();
            stack.pop_back();
            const Node& n = nodes_[it.node];
            const FloatBox box = detail::restrict_box(it.box, n);
            if (n.kind() == Node::Kind::leaf) visit(n.index(), box);
            else if (n.kind() == Node::Kind::one_child) stack.push_back({n.index(), box});
            else stack.push_back({n.index() + 1, box}), stack.push_back({n.index(), box});
        }
    }

    /// Checks the invariants and throws cdkit::Error naming the first broken one: indices in range,
    /// children after their parent, every triangle in exactly one leaf, and every vertex of a leaf's
    /// triangle inside the leaf's implied box (exactly, in long double). O(n).
    void validate() const;

    /// Deformation: takes `moved`, the same mesh with moved vertices (same vertex count, same triangles in the
    /// same order), and refits the tree to it in O(n). The topology (each node's triangles, axis and side)
    /// stays and every plane is recomputed from its node's triangles exactly as the build computes it, so a
    /// refit onto the mesh the tree was built on gives the built tree again, node for node; after a
    /// deformation the boxes are tight on the chosen faces but the split no longer follows the shape.
    /// Throws cdkit::Error naming moved->source when the topology differs, a vertex is not finite or the
    /// extent no longer fits float planes; the tree is unchanged then. Not thread-safe against queries on it.
    void refit(std::shared_ptr<const TriangleMesh<S>> moved);

private:
    static std::shared_ptr<const TriangleMesh<S>> checked(std::shared_ptr<const TriangleMesh<S>> m) {
        if (!m) throw Error("<mesh>", "", "null mesh");
        cdkit::validate(*m);
        return m;
    }
    void build();

    /// A triangle's vertices' box in the local frame (double) and the magnitude its padding covers: the
    /// model coordinates (queries transform those) and the local ones (the box tests work in those).
    struct TriBox {
        std::array<double, 6> box = {HUGE_VAL, HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        double magnitude = 0;
        void add(const TriBox& o) noexcept {
            for (int k = 0; k < 3; ++k) box[k] = std::min(box[k], o.box[k]), box[k + 3] = std::max(box[k + 3], o.box[k + 3]);
            magnitude = std::max(magnitude, o.magnitude);
        }
    };
    /// The centre of the mesh's bounding box: the local frame's origin.
    [[nodiscard]] static Vec3<S> box_centre(const TriangleMesh<S>& mesh) noexcept {
        Vec3<S> lo = Vec3<S>::Constant(std::numeric_limits<S>::infinity()), hi = -lo;
        for (const Triangle& t : mesh.triangles)
            for (Index v : t) lo = lo.cwiseMin(mesh.vertices[v]), hi = hi.cwiseMax(mesh.vertices[v]);
        return lo * S(0.5) + hi * S(0.5);
    }
    /// Every triangle's TriBox in the local frame around `centre`; the centroids (local) too when asked.
    [[nodiscard]] static std::vector<TriBox> triangle_boxes(const TriangleMesh<S>& mesh, const Vec3<S>& centre,
                                                            std::vector<Vec3<double>>* centroids = nullptr) {
        const std::size_t n = mesh.triangles.size();
        std::vector<TriBox> tri(n);
        if (centroids) centroids->assign(n, Vec3<double>::Zero());
        const Vec3<double> c = centre.template cast<double>();
        for (std::size_t i = 0; i < n; ++i)
            for (Index v : mesh.triangles[i]) {
                const Vec3<double> p = mesh.vertices[v].template cast<double>();
                const Vec3<double> l = p - c;
                if (centroids) (*centroids)[i] += l / 3.0;
                TriBox& tb = tri[i];
                for (int k = 0; k < 3; ++k) tb.box[k] = std::min(tb.box[k], l[k]), tb.box[k + 3] = std::max(tb.box[k + 3], l[k]);
                tb.magnitude = std::max({tb.magnitude, p.cwiseAbs().maxCoeff(), l.cwiseAbs().maxCoeff()});
            }
        return tri;
    }
    /// A TriBox padded (fit_padding's rule in S, plus the local coordinates' own rounding) and rounded
    /// outwards to float.
    [[nodiscard]] static FloatBox padded(const TriBox& b) noexcept {
        const double eps = double(std::numeric_limits<S>::epsilon());
        const double pad = double(detail::fit_padding(S(b.magnitude))) + 4 * eps * b.magnitude;
        FloatBox f;
        for (int k = 0; k < 3; ++k)
            f[k] = detail::boxtree_round_down(b.box[k] - pad), f[k + 3] = detail::boxtree_round_up(b.box[k + 3] + pad);
        return f;
    }
    /// The root box from the whole mesh's TriBox; throws when it does not fit float planes.
    [[nodiscard]] static FloatBox root_box_of(const TriangleMesh<S>& mesh, const TriBox& all) {
        const FloatBox f = padded(all);
        for (float x : f)
            if (!std::isfinite(x)) throw Error(mesh.source, "", "restricted boxtree: the mesh's extent does not fit float planes");
        return f;
    }
    /// `tight` clipped to `parent` on every face: both hold the triangles, so their intersection does too,
    /// and a child's box never grows past its parent's.
    [[nodiscard]] static FloatBox clipped(FloatBox tight, const FloatBox& parent) noexcept {
        for (int k = 0; k < 3; ++k) tight[k] = std::max(tight[k], parent[k]), tight[k + 3] = std::min(tight[k + 3], parent[k + 3]);
        return tight;
    }

    std::shared_ptr<const TriangleMesh<S>> mesh_;
    BoxtreeOptions options_;
    std::vector<Node> nodes_;
    FloatBox root_box_{};
    Vec3<S> centre_ = Vec3<S>::Zero();
    std::size_t depth_ = 0;
};

template <class S> void RestrictedBoxtree<S>::build() {
    const TriangleMesh<S>& mesh = *mesh_;
    const std::size_t n = mesh.triangles.size();
    // A box has six faces, and a face once moved onto the tight box gains nothing more: at most five
    // one-child nodes ever precede a node, whatever the options say.
    const std::size_t per_triangle = 2 * (std::min<std::size_t>(options_.max_extra_restrictions, 5) + 1);
    if (n > std::size_t(Node::max_index) / per_triangle)
        throw Error(mesh.source, "", "restricted boxtree: " + std::to_string(n) +
                                         " triangles exceed the 27-bit node index (with these options)");
    centre_ = box_centre(mesh);
    std::vector<Vec3<double>> centroid;
    const std::vector<TriBox> tri = triangle_boxes(mesh, centre_, &centroid);
    // The padded box of triangles [first, last), rounded outwards to float.
    auto fit = [&](const Index* first, const Index* last) {
        TriBox b;
        for (const Index* p = first; p != last; ++p) b.add(tri[*p]);
        return padded(b);
    };

    std::vector<Index> order(n);
    std::iota(order.begin(), order.end(), Index(0));
    {
        TriBox all;
        for (const TriBox& t : tri) all.add(t);
        root_box_ = root_box_of(mesh, all);
    }

    nodes_.clear();
    nodes_.reserve(2 * n);
    nodes_.emplace_back();  // the root: no restriction of its own
    struct Work { std::uint32_t node, begin, end, level; FloatBox parent; };
    std::vector<Work> stack{{0, 0, std::uint32_t(n), 1, root_box_}};
    depth_ = 0;
    // The face of `box` whose move to `tight` cuts off the largest fraction of the box's surface area (a
    // proxy for the chance that another box overlaps it).
    struct Cut { std::uint32_t axis = Node::no_axis; bool upper = false; double value = 0; double gain = 0; };
    auto best_cut = [](const auto& box, const auto& tight) {
        Cut best;
        const double e[3] = {double(box[3]) - double(box[0]), double(box[4]) - double(box[1]), double(box[5]) - double(box[2])};
        const double area = e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
        for (std::uint32_t k = 0; k < 3; ++k) {
            if (!(e[k] > 0)) continue;
            // Fraction of the surface area cut off (of the extent when the box is flat).
            const double w = area > 0 ? (e[(k + 1) % 3] + e[(k + 2) % 3]) / area : 1 / e[k];
            const double g_lo = (double(tight[k]) - double(box[k])) * w;
            const double g_hi = (double(box[k + 3]) - double(tight[k + 3])) * w;
            if (g_lo > best.gain) best = {k, false, double(tight[k]), g_lo};
            if (g_hi > best.gain) best = {k, true, double(tight[k + 3]), g_hi};
        }
        return best;
    };
    // The split heuristic's estimate of a child's implied box: the parent's box after the cuts the build
    // would make (in double, without the padding: a cost, not a bound).
    const double min_gain = double(options_.min_extra_gain);
    auto implied_area = [&](const FloatBox& parent, const std::array<double, 6>& tight) {
        std::array<double, 6> box;
        for (int k = 0; k < 6; ++k) box[k] = double(parent[k]);
        for (std::uint32_t c = 0; c <= options_.max_extra_restrictions; ++c) {
            const Cut cut = best_cut(box, tight);
            if (cut.axis == Node::no_axis || (c > 0 && !(cut.gain >= min_gain))) break;
            box[cut.upper ? cut.axis + 3 : cut.axis] = cut.value;
        }
        const double x = box[3] - box[0], y = box[4] - box[1], z = box[5] - box[2];
        return x * y + y * z + z * x;
    };
    // Binned SAH over implied boxes: partitions [first, last) and returns the cut, or nullptr when no bin
    // split separates the centroids.
    auto sah_split = [&](Index* first, Index* last, const FloatBox& box) -> Index* {
        constexpr int B = 16;
        using Box6d = std::array<double, 6>;
        const Box6d none = {HUGE_VAL, HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        auto add = [](Box6d& a, const Box6d& b) {
            for (int k = 0; k < 3; ++k) a[k] = std::min(a[k], b[k]), a[k + 3] = std::max(a[k + 3], b[k + 3]);
        };
        Vec3<double> clo = Vec3<double>::Constant(HUGE_VAL), chi = -clo;
        for (Index* p = first; p != last; ++p) clo = clo.cwiseMin(centroid[*p]), chi = chi.cwiseMax(centroid[*p]);
        double best = HUGE_VAL;
        int best_axis = -1, best_bin = 0;
        auto bin_of = [&](Index t, int axis) {
            const double w = chi[axis] - clo[axis];
            return std::clamp(int(double(B) * (centroid[t][axis] - clo[axis]) / w), 0, B - 1);
        };
        for (int axis = 0; axis < 3; ++axis) {
            if (!(chi[axis] > clo[axis])) continue;
            std::array<Box6d, B> bins;
            bins.fill(none);
            std::array<std::size_t, B> count{};
            for (Index* p = first; p != last; ++p) {
                const int b = bin_of(*p, axis);
                ++count[b];
                add(bins[b], tri[*p].box);
            }
            std::array<double, B> right_cost{};
            Box6d acc = none;
            std::size_t n_acc = 0;
            for (int b = B - 1; b > 0; --b) {
                add(acc, bins[b]), n_acc += count[b];
                right_cost[b] = n_acc ? implied_area(box, acc) * double(n_acc) : 0;
            }
            acc = none;
            n_acc = 0;
            for (int b = 0; b < B - 1; ++b) {
                add(acc, bins[b]), n_acc += count[b];
                const std::size_t right_n = std::size_t(last - first) - n_acc;
                if (n_acc == 0 || right_n == 0) continue;
                const double cost = implied_area(box, acc) * double(n_acc) + right_cost[b + 1];
                if (cost < best) best = cost, best_axis = axis, best_bin = b;
            }
        }
        if (best_axis < 0) return nullptr;
        return std::partition(first, last, [&](Index t) { return bin_of(t, best_axis) <= best_bin; });
    };
    while (!stack.empty()) {
        const Work w = stack.back();
        stack.pop_back();
        Index* first = order.data() + w.begin;
        Index* last = order.data() + w.end;
        const FloatBox tight = clipped(fit(first, last), w.parent);
        std::uint32_t cur = w.node, level = w.level;
        FloatBox box = w.parent;
        if (cur != 0) {  // the root's box is the fit itself
            const Cut cut = best_cut(box, tight);
            nodes_[cur].set_restriction(cut.axis, cut.upper, float(cut.value));
            box = detail::restrict_box(box, nodes_[cur]);
            for (std::uint32_t e = 0; e < options_.max_extra_restrictions; ++e) {
                const Cut more = best_cut(box, tight);
                if (!(more.gain >= double(options_.min_extra_gain)) || more.axis == Node::no_axis) break;
                const std::uint32_t next = std::uint32_t(nodes_.size());
                nodes_.emplace_back();
                nodes_[cur].set_link(Node::Kind::one_child, next);
                cur = next;
                ++level;
                nodes_[cur].set_restriction(more.axis, more.upper, float(more.value));
                box = detail::restrict_box(box, nodes_[cur]);
            }
        }
        depth_ = std::max<std::size_t>(depth_, level);
        if (w.end - w.begin == 1) {
            nodes_[cur].set_link(Node::Kind::leaf, *first);
            continue;
        }
        Index* mid = options_.split == BoxtreeSplit::implied_sah ? sah_split(first, last, box) : nullptr;
        if (mid == nullptr || mid == first || mid == last) {
            // Median split of the centroids along the tight box's longest axis; ties by index (deterministic).
            int axis = 0;
            for (int k = 1; k < 3; ++k)
                if (double(tight[k + 3]) - tight[k] > double(tight[axis + 3]) - tight[axis]) axis = k;
            mid = first + (last - first) / 2;
            std::nth_element(first, mid, last, [&](Index a, Index b) {
                const double ka = centroid[a][axis], kb = centroid[b][axis];
                return ka < kb || (ka == kb && a < b);
            });
        }
        const std::uint32_t children = std::uint32_t(nodes_.size());
        nodes_.emplace_back();
        nodes_.emplace_back();
        nodes_[cur].set_link(Node::Kind::two_children, children);
        const std::uint32_t split = std::uint32_t(mid - order.data());
        stack.push_back({children + 1, split, w.end, level + 1, box});
        stack.push_back({children, w.begin, split, level + 1, box});
    }
}

template <class S> void RestrictedBoxtree<S>::refit(std::shared_ptr<const TriangleMesh<S>> moved) {
    if (!moved) throw Error("<mesh>", "", "refit: null mesh");
    const TriangleMesh<S>& mesh = *moved;
    if (mesh.vertices.size() != mesh_->vertices.size())
        throw Error(mesh.source, "", "refit: vertex count " + std::to_string(mesh.vertices.size()) +
                                         " differs from the tree's " + std::to_string(mesh_->vertices.size()));
    if (mesh.triangles.size() != mesh_->triangles.size())
        throw Error(mesh.source, "", "refit: triangle count differs from the tree's");
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
        if (mesh.triangles[i] != mesh_->triangles[i])
            throw Error(mesh.source, "triangle " + std::to_string(i), "refit: differs from the tree's (topology changed)");
    cdkit::validate(mesh);

    const Vec3<S> centre = box_centre(mesh);
    const std::vector<TriBox> tri = triangle_boxes(mesh, centre);
    // Each node's triangles' box, bottom-up: children follow their parent in the array.
    std::vector<TriBox> tight(nodes_.size());
    for (std::size_t i = nodes_.size(); i-- > 0;) {
        const Node& n = nodes_[i];
        if (n.kind() == Node::Kind::leaf) tight[i] = tri[n.index()];
        else if (n.kind() == Node::Kind::one_child) tight[i] = tight[n.index()];
        else tight[i] = tight[n.index()], tight[i].add(tight[n.index() + 1]);
    }
    const FloatBox root = root_box_of(mesh, tight[0]);
    // Top-down: each restricted face moves to its node's padded tight box, clipped to the parent's implied box
    // (the build's rule, so the same mesh gives the same planes).
    std::vector<Node> nodes = nodes_;
    std::vector<FloatBox> parent_box(nodes.size());
    parent_box[0] = root;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        Node& n = nodes[i];
        if (i != 0 && n.axis() != Node::no_axis) {
            const FloatBox t = clipped(padded(tight[i]), parent_box[i]);
            const std::uint32_t k = n.axis();
            n.set_restriction(k, n.upper(), n.upper() ? t[k + 3] : t[k]);
        }
        const FloatBox box = detail::restrict_box(parent_box[i], n);
        if (n.kind() == Node::Kind::one_child) parent_box[n.index()] = box;
        else if (n.kind() == Node::Kind::two_children) parent_box[n.index()] = parent_box[n.index() + 1] = box;
    }
    nodes_ = std::move(nodes);
    root_box_ = root;
    centre_ = centre;
    mesh_ = std::move(moved);
}

template <class S> void RestrictedBoxtree<S>::validate() const {
    const TriangleMesh<S>& mesh = *mesh_;
    const std::string& src = mesh.source;
    if (nodes_.empty()) throw Error(src, "restricted boxtree", "tree is empty");
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const Node& nd = nodes_[i];
        if (nd.axis() != Node::no_axis && !std::isfinite(nd.plane))
            throw Error(src, "boxtree node " + std::to_string(i), "plane is not finite");
        if (nd.kind() == Node::Kind::leaf) {
            if (nd.index() >= mesh.triangles.size())
                throw Error(src, "boxtree node " + std::to_string(i), "triangle index out of range");
        } else if (nd.index() <= i || std::size_t(nd.index()) + (nd.kind() == Node::Kind::two_children) >= nodes_.size() ||
                   nd.kind() == Node::Kind(3)) {
            throw Error(src, "boxtree node " + std::to_string(i), "child index out of range");
        }
    }
    std::vector<std::uint8_t> seen(mesh.triangles.size(), 0);
    std::size_t leaves = 0;
    for_each_leaf([&](std::uint32_t t, const FloatBox& box) {
        if (seen[t]++) throw Error(src, "triangle " + std::to_string(t), "in more than one boxtree leaf");
        ++leaves;
        for (Index v : mesh.triangles[t])
            for (int k = 0; k < 3; ++k) {
                const long double local = (long double)mesh.vertices[v][k] - (long double)centre_[k];
                if (local < (long double)box[k] || local > (long double)box[k + 3])
                    throw Error(src, "triangle " + std::to_string(t),
                                "vertex " + std::to_string(v) + " lies outside its boxtree leaf's box");
            }
    });
    if (leaves != mesh.triangles.size()) throw Error(src, "restricted boxtree", "a triangle is in no leaf");
}

}  // namespace cdkit
