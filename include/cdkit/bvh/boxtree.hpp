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
/// The node format is in bvh/boxtree_node.hpp, the build in bvh/detail/boxtree_builder.hpp, the collision
/// descent (node concept, overlap and distance tests) in bvh/boxtree_descent.hpp: collide() and distance()
/// (query.hpp, distance.hpp) descend it as they descend every other tree.

#include "cdkit/bv/fit.hpp"
#include "cdkit/bvh/boxtree_node.hpp"
#include "cdkit/bvh/detail/boxtree_builder.hpp"
#include "cdkit/core/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#if defined(CDKIT_HAS_TBB)
#include <tbb/parallel_for.h>
#endif

namespace cdkit {

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

    std::shared_ptr<const TriangleMesh<S>> mesh_;
    BoxtreeOptions options_;
    std::vector<Node> nodes_;
    FloatBox root_box_{};
    Vec3<S> centre_ = Vec3<S>::Zero();
    std::size_t depth_ = 0;
};

template <class S> void RestrictedBoxtree<S>::build() {
    using Builder = detail::BoxtreeBuilder<S>;
    const TriangleMesh<S>& mesh = *mesh_;
    const std::size_t n = mesh.triangles.size();
    // A box has six faces, and a face once moved onto the tight box gains nothing more: at most five
    // one-child nodes ever precede a node, whatever the options say.
    const std::size_t per_triangle = 2 * (std::min<std::size_t>(options_.max_extra_restrictions, 5) + 1);
    if (n > std::size_t(Node::max_index) / per_triangle)
        throw Error(mesh.source, "", "restricted boxtree: " + std::to_string(n) +
                                         " triangles exceed the 27-bit node index (with these options)");
    centre_ = detail::boxtree_centre(mesh);
    Builder builder(mesh, centre_, options_);
    typename Builder::Work root = builder.root();
    root_box_ = root.parent = detail::boxtree_root_box(mesh, root.tight);

    // The top levels breadth first, then the subtrees below them (in parallel with TBB), each into its own
    // vector, spliced in order: the layout does not depend on the threads.
    constexpr std::uint32_t kTopLevels = 4;
    nodes_.assign(1, Node{});
    depth_ = 0;
    std::vector<typename Builder::Work> level{root}, pending;
    std::array<typename Builder::Work, 2> below;
    while (!level.empty()) {
        std::vector<typename Builder::Work> next;
        for (const auto& w : level) {
            if (w.level > kTopLevels) {
                pending.push_back(w);
                continue;
            }
            const std::size_t k = builder.expand(nodes_, w, below, depth_);
            next.insert(next.end(), below.begin(), below.begin() + std::ptrdiff_t(k));
        }
        level.swap(next);
    }
    std::vector<std::vector<Node>> parts(pending.size());
    std::vector<std::size_t> part_depth(pending.size(), 0);
    const auto grow = [&](std::size_t i) {
        typename Builder::Work w = pending[i];
        w.node = 0;
        parts[i].reserve(3 * std::size_t(w.end - w.begin));
        parts[i].assign(1, Node{});
        part_depth[i] = builder.grow(parts[i], w);
    };
#if defined(CDKIT_HAS_TBB)
    if (n >= 20000) tbb::parallel_for(std::size_t(0), pending.size(), grow);
    else
#endif
        for (std::size_t i = 0; i < pending.size(); ++i) grow(i);
    // Local index 0 is the pending slot; local index k > 0 goes to offset + k − 1.
    for (std::size_t i = 0; i < pending.size(); ++i) {
        const std::uint32_t offset = std::uint32_t(nodes_.size());
        const auto moved = [&](Node x) {
            if (!x.is_leaf()) x.set_link(x.kind(), x.index() + offset - 1);
            return x;
        };
        nodes_[pending[i].node] = moved(parts[i][0]);
        for (std::size_t k = 1; k < parts[i].size(); ++k) nodes_.push_back(moved(parts[i][k]));
        depth_ = std::max(depth_, part_depth[i]);
        std::vector<Node>().swap(parts[i]);
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

    const Vec3<S> centre = detail::boxtree_centre(mesh);
    const std::vector<detail::BoxtreeTriBox> tri = detail::boxtree_triangle_boxes(mesh, centre);
    // Each node's triangles' box, bottom-up: children follow their parent in the array.
    std::vector<detail::BoxtreeTriBox> tight(nodes_.size());
    for (std::size_t i = nodes_.size(); i-- > 0;) {
        const Node& n = nodes_[i];
        if (n.kind() == Node::Kind::leaf) tight[i] = tri[n.index()];
        else if (n.kind() == Node::Kind::one_child) tight[i] = tight[n.index()];
        else tight[i] = tight[n.index()], tight[i].add(tight[n.index() + 1]);
    }
    const FloatBox root = detail::boxtree_root_box(mesh, tight[0]);
    // Top-down: each restricted face moves to its node's padded tight box, clipped to the parent's implied box
    // (the build's rule, so the same mesh gives the same planes).
    std::vector<Node> nodes = nodes_;
    std::vector<FloatBox> parent_box(nodes.size());
    parent_box[0] = root;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        Node& n = nodes[i];
        if (i != 0 && n.axis() != Node::no_axis) {
            const FloatBox t = detail::boxtree_clipped(detail::boxtree_padded<S>(tight[i]), parent_box[i]);
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
