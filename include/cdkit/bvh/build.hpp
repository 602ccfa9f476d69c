#pragma once
/// \file Top-down BVH construction: fit a BV to a node's triangles, split them by their centroids along the
/// BV's longest axis, recurse. Median splits give a balanced tree (depth ⌈log2(n / leaf size)⌉ + 1).

#include "cdkit/bvh/bvh.hpp"

#include <algorithm>
#include <numeric>

namespace cdkit {

/// Builds a Bvh<BV> over `mesh`, which must be valid (validate() it first; MeshModel does). O(n log n).
template <class BV> [[nodiscard]] Bvh<BV> build_bvh(const TriangleMesh<typename BV::Scalar>& mesh,
                                                    const BuildOptions& options = {}) {
    using S = typename BV::Scalar;
    using Node = BvhNode<BV>;
    const std::size_t n = mesh.triangles.size();
    const std::uint32_t leaf_max = std::max<std::uint32_t>(1, options.max_leaf_triangles);
    std::vector<Index> order(n);
    std::iota(order.begin(), order.end(), Index(0));
    std::vector<Vec3<S>> centroid(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Triangle& t = mesh.triangles[i];
        centroid[i] = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / S(3);
    }
    std::vector<Node> nodes;
    if (n == 0) return {};
    nodes.reserve(2 * ((n + leaf_max - 1) / leaf_max));
    nodes.emplace_back();
    struct Work { std::uint32_t node, begin, end, level; };
    std::vector<Work> stack{{0, 0, std::uint32_t(n), 1}};
    std::size_t depth = 0;
    while (!stack.empty()) {
        const Work w = stack.back();
        stack.pop_back();
        depth = std::max<std::size_t>(depth, w.level);
        const TriangleRange range(order.data() + w.begin, w.end - w.begin);
        nodes[w.node].bv = BV::fit(mesh, range);
        if (w.end - w.begin <= leaf_max) {
            nodes[w.node].first = w.begin;
            nodes[w.node].count = w.end - w.begin;
            continue;
        }
        const Vec3<S> axis = nodes[w.node].bv.split_axis();
        auto key = [&](Index t) { return centroid[t].dot(axis); };
        // Ties broken by index so that builds are deterministic whatever the standard library does.
        auto less = [&](Index a, Index b) {
            const S ka = key(a), kb = key(b);
            return ka < kb || (ka == kb && a < b);
        };
        Index* first = order.data() + w.begin;
        Index* last = order.data() + w.end;
        Index* mid = first + (w.end - w.begin) / 2;
        if (options.split == SplitStrategy::mean) {
            S mean = 0;
            for (Index* p = first; p != last; ++p) mean += key(*p);
            mean /= S(last - first);
            Index* cut = std::partition(first, last, [&](Index t) { return key(t) < mean; });
            if (cut != first && cut != last) mid = cut;
            else std::nth_element(first, mid, last, less);
        } else {
            std::nth_element(first, mid, last, less);
        }
        const std::uint32_t split = std::uint32_t(mid - order.data());
        const std::uint32_t children = std::uint32_t(nodes.size());
        nodes[w.node].first = children;
        nodes[w.node].count = 0;
        nodes.emplace_back();
        nodes.emplace_back();
        // Right first so the left subtree is built (and laid out) next: depth-first order in memory.
        stack.push_back({children + 1, split, w.end, w.level + 1});
        stack.push_back({children, w.begin, split, w.level + 1});
    }
    return Bvh<BV>(std::move(nodes), std::move(order), depth);
}

}  // namespace cdkit
