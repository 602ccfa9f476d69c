#pragma once
/// \file Bvh<BV>: a bounding volume hierarchy over a triangle mesh, stored as one flat, index-linked node
/// array. The tree holds indices into the mesh, never a copy of its geometry.

#include "cdkit/core/mesh.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace cdkit {

/// One node. Inner node: `count == 0`, children at `first` and `first + 1`. Leaf: `count > 0` triangles,
/// `Bvh::triangle_order()[first .. first + count)`.
template <class BV> struct BvhNode {
    BV bv;
    std::uint32_t first = 0;
    std::uint32_t count = 0;
    [[nodiscard]] bool is_leaf() const noexcept { return count != 0; }
};

/// How a top-down build splits a node's triangles.
enum class SplitStrategy {
    median,  ///< object median of the centroids along the BV's longest axis (balanced: depth ⌈log2 n⌉)
    mean,    ///< the centroids' mean along that axis, as FCL and RAPID do (falls back to median if one side is empty)
    /// Binned surface area heuristic (16 bins per axis, all three axes; MacDonald, Booth, "Heuristics for ray
    /// tracing using space subdivision", 1990; binning after Wald, "On fast construction of SAH-based BVHs",
    /// 2007): minimises area(L)·n_L + area(R)·n_R of the halves' triangle bounding boxes. Meant for Aabb and
    /// Kdop trees; any BV accepts it. Falls back to the median when all centroids share a bin.
    sah,
    /// The centroids' principal axis, then the split position along it that minimises vol(L) + vol(R) of the
    /// halves' boxes in the principal frame (a full sweep over the sorted centroids). Meant for Obb trees.
    pca_volume,
};

struct BuildOptions {
    /// Binned SAH by default: on the bunny and the whole dragon ladder (11k … 871k) it made every BV's
    /// queries faster than the median split (docs/bvh.md, "Build strategies"), for 1.1–2.5× the build time.
    SplitStrategy split = SplitStrategy::sah;
    /// Leaves hold at most this many triangles (≥ 1). Above 1, every cut falls on a multiple of it, so all
    /// leaves but one are full: ⌈n / max_leaf_triangles⌉ leaves whatever the split.
    std::uint32_t max_leaf_triangles = 1;
    /// Build meshes of at least `parallel_min_triangles` on several threads when cdkit has TBB
    /// (CDKIT_HAS_TBB); the tree is the same either way, only its node layout differs. Below 2^16
    /// triangles, starting threads costs more than the build.
    bool parallel = true;
    std::size_t parallel_min_triangles = std::size_t(1) << 16;
};

/// Statistics of a built tree.
struct BvhStats {
    std::size_t nodes = 0;
    std::size_t leaves = 0;
    std::size_t depth = 0;          ///< number of levels (a single leaf: 1)
    std::size_t memory_bytes = 0;   ///< nodes + triangle order
};

template <class BV> class Bvh {
public:
    using Scalar = typename BV::Scalar;
    using Node = BvhNode<BV>;

    Bvh() = default;
    Bvh(std::vector<Node> nodes, std::vector<Index> order, std::size_t depth)
        : nodes_(std::move(nodes)), order_(std::move(order)), depth_(depth) {}

    [[nodiscard]] const std::vector<Node>& nodes() const noexcept { return nodes_; }
    [[nodiscard]] const std::vector<Index>& triangle_order() const noexcept { return order_; }
    [[nodiscard]] const Node& root() const noexcept { return nodes_.front(); }
    [[nodiscard]] bool empty() const noexcept { return nodes_.empty(); }
    [[nodiscard]] std::size_t depth() const noexcept { return depth_; }
    [[nodiscard]] std::size_t memory_bytes() const noexcept {
        return nodes_.size() * sizeof(Node) + order_.size() * sizeof(Index);
    }
    [[nodiscard]] BvhStats stats() const noexcept {
        BvhStats s;
        s.nodes = nodes_.size();
        for (const Node& n : nodes_) s.leaves += n.is_leaf();
        s.depth = depth_;
        s.memory_bytes = memory_bytes();
        return s;
    }

    /// Replaces node i's bounding volume, leaving the topology as it is. For refit (bvh/refit.hpp): the
    /// caller keeps the containment invariant (validate() checks it).
    void set_volume(std::size_t i, const BV& bv) noexcept { nodes_[i].bv = bv; }

    /// Checks the tree's invariants against its mesh and throws cdkit::Error naming the first broken one:
    /// child indices in range, every triangle in exactly one leaf, and every vertex of a leaf's triangles
    /// inside the BV of the leaf and of each of its ancestors. O(n · depth): for tests and debugging.
    /// The mesh may be in double under float BVs (see build_bvh); vertices are then tested rounded to float.
    template <class M> void validate(const TriangleMesh<M>& mesh) const;

private:
    std::vector<Node> nodes_;
    std::vector<Index> order_;
    std::size_t depth_ = 0;
};

template <class BV> template <class M> void Bvh<BV>::validate(const TriangleMesh<M>& mesh) const {
    const std::string src = mesh.source;
    if (nodes_.empty()) throw Error(src, "bvh", "tree is empty");
    if (order_.size() != mesh.triangles.size()) throw Error(src, "bvh", "triangle count differs from the mesh's");
    std::vector<std::uint8_t> seen(mesh.triangles.size(), 0);
    struct Item { std::uint32_t node, parent; };
    std::vector<Item> stack{{0u, UINT32_MAX}};
    std::vector<std::uint32_t> parent_of(nodes_.size(), UINT32_MAX);
    while (!stack.empty()) {
        auto [i, p] = stack.back();
        stack.pop_back();
        if (i >= nodes_.size()) throw Error(src, "bvh node " + std::to_string(p), "child index out of range");
        parent_of[i] = p;
        const Node& n = nodes_[i];
        if (!n.bv.is_valid()) throw Error(src, "bvh node " + std::to_string(i), "bounding volume is invalid");
        if (n.is_leaf()) {
            if (std::size_t(n.first) + n.count > order_.size())
                throw Error(src, "bvh node " + std::to_string(i), "leaf range out of range");
            for (std::uint32_t k = n.first; k < n.first + n.count; ++k) {
                const Index t = order_[k];
                if (t >= mesh.triangles.size() || seen[t]++)
                    throw Error(src, "bvh node " + std::to_string(i), "triangle referenced twice or out of range");
                // The leaf and all its ancestors must contain the triangle's vertices.
                for (std::uint32_t a = i; a != UINT32_MAX; a = parent_of[a])
                    for (Index v : mesh.triangles[t])
                        if (!nodes_[a].bv.contains(mesh.vertices[v].template cast<Scalar>()))
                            throw Error(src, "bvh node " + std::to_string(a),
                                        "does not contain vertex " + std::to_string(v) + " of triangle " +
                                            std::to_string(t));
            }
        } else {
            if (n.first + 1 >= nodes_.size() || n.first <= i)
                throw Error(src, "bvh node " + std::to_string(i), "child index out of range");
            stack.push_back({n.first, i});
            stack.push_back({n.first + 1, i});
        }
    }
}

}  // namespace cdkit
