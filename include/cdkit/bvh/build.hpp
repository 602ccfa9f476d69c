#pragma once
/// \file Top-down BVH construction: fit a BV to a node's triangles, split them by their centroids along the
/// BV's longest axis, recurse. Median splits give a balanced tree (depth ⌈log2(n / leaf size)⌉ + 1).

#include "cdkit/bv/fit.hpp"
#include "cdkit/bvh/bvh.hpp"

#include <algorithm>
#include <numeric>
#include <array>

#include <Eigen/Eigenvalues>
#include <limits>

namespace cdkit {

namespace detail {
/// The BV's split_axis() when it has one; otherwise (a sphere has no preferred direction) the axis along
/// which the node's triangle centroids spread widest.
template <class BV, class S>
[[nodiscard]] Vec3<S> split_direction(const BV& bv, const std::vector<Vec3<S>>& centroid, const Index* first,
                                      const Index* last) noexcept {
    if constexpr (requires { bv.split_axis(); }) {
        return bv.split_axis();
    } else {
        Vec3<S> lo = Vec3<S>::Constant(std::numeric_limits<S>::infinity()), hi = -lo;
        for (const Index* p = first; p != last; ++p) lo = lo.cwiseMin(centroid[*p]), hi = hi.cwiseMax(centroid[*p]);
        int k;
        (hi - lo).maxCoeff(&k);
        return Vec3<S>::Unit(k);
    }
}

/// Bounds of a set of points, for the split heuristics (not a BV: no padding).
template <class S> struct Box {
    Vec3<S> lo = Vec3<S>::Constant(std::numeric_limits<S>::infinity());
    Vec3<S> hi = Vec3<S>::Constant(-std::numeric_limits<S>::infinity());
    void add(const Vec3<S>& p) noexcept { lo = lo.cwiseMin(p), hi = hi.cwiseMax(p); }
    void add(const Box& b) noexcept { lo = lo.cwiseMin(b.lo), hi = hi.cwiseMax(b.hi); }
    [[nodiscard]] double area() const noexcept {
        if (!(hi.x() >= lo.x())) return 0;
        const Vec3<double> e = (hi - lo).template cast<double>();
        return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
    }
    [[nodiscard]] double volume() const noexcept {
        if (!(hi.x() >= lo.x())) return 0;
        const Vec3<double> e = (hi - lo).template cast<double>();
        return e.x() * e.y() * e.z();
    }
};

/// Binned SAH split of [first, last): partitions in place and returns the cut, or nullptr when no bin split
/// separates the centroids (then the caller splits at the median).
template <class S>
[[nodiscard]] Index* sah_split(const TriangleMesh<S>& mesh, const std::vector<Vec3<S>>& centroid, Index* first,
                               Index* last) {
    constexpr int B = 16;
    Box<S> cb;
    for (Index* p = first; p != last; ++p) cb.add(centroid[*p]);
    double best = std::numeric_limits<double>::infinity();
    int best_axis = -1, best_bin = 0;
    auto bin_of = [&](Index t, int axis) {
        const S w = cb.hi[axis] - cb.lo[axis];
        const int b = int(S(B) * (centroid[t][axis] - cb.lo[axis]) / w);
        return std::clamp(b, 0, B - 1);
    };
    for (int axis = 0; axis < 3; ++axis) {
        if (!(cb.hi[axis] > cb.lo[axis])) continue;
        std::array<Box<S>, B> box;
        std::array<std::size_t, B> count{};
        for (Index* p = first; p != last; ++p) {
            const int b = bin_of(*p, axis);
            ++count[b];
            for (Index v : mesh.triangles[*p]) box[b].add(mesh.vertices[v]);
        }
        // Sweep: right-to-left suffix areas, then left-to-right.
        std::array<double, B> right_cost{};
        Box<S> acc;
        std::size_t n = 0;
        for (int b = B - 1; b > 0; --b) {
            acc.add(box[b]), n += count[b];
            right_cost[b] = acc.area() * double(n);
        }
        acc = Box<S>();
        n = 0;
        for (int b = 0; b < B - 1; ++b) {
            acc.add(box[b]), n += count[b];
            const std::size_t right_n = std::size_t(last - first) - n;
            if (n == 0 || right_n == 0) continue;
            const double cost = acc.area() * double(n) + right_cost[b + 1];
            if (cost < best) best = cost, best_axis = axis, best_bin = b;
        }
    }
    if (best_axis < 0) return nullptr;
    return std::partition(first, last, [&](Index t) { return bin_of(t, best_axis) <= best_bin; });
}

/// PCA + volume-minimising sweep over [first, last): sorts along the centroids' principal axis and returns
/// the cut minimising vol(L) + vol(R) of the halves' boxes in the principal frame.
template <class S>
[[nodiscard]] Index* pca_volume_split(const TriangleMesh<S>& mesh, const std::vector<Vec3<S>>& centroid,
                                      Index* first, Index* last) {
    const std::size_t n = std::size_t(last - first);
    Eigen::Matrix<double, 3, 1> mean = Eigen::Matrix<double, 3, 1>::Zero();
    for (Index* p = first; p != last; ++p) mean += centroid[*p].template cast<double>();
    mean /= double(n);
    Eigen::Matrix<double, 3, 3> cov = Eigen::Matrix<double, 3, 3>::Zero();
    for (Index* p = first; p != last; ++p) {
        const Eigen::Matrix<double, 3, 1> d = centroid[*p].template cast<double>() - mean;
        cov += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 3, 3>> eig;
    eig.computeDirect(cov);
    Eigen::Matrix<double, 3, 3> frame = eig.eigenvectors();
    if (!frame.allFinite()) frame.setIdentity();
    const Vec3<S> axis = frame.col(2).template cast<S>();
    const Mat3<S> ft = frame.transpose().template cast<S>();
    auto key = [&](Index t) { return centroid[t].dot(axis); };
    std::sort(first, last, [&](Index a, Index b) {
        const S ka = key(a), kb = key(b);
        return ka < kb || (ka == kb && a < b);
    });
    std::vector<double> suffix(n + 1, 0.0);
    Box<S> acc;
    for (std::size_t i = n; i-- > 1;) {
        for (Index v : mesh.triangles[first[i]]) acc.add(Vec3<S>(ft * mesh.vertices[v]));
        suffix[i] = acc.volume();
    }
    acc = Box<S>();
    double best = std::numeric_limits<double>::infinity();
    std::size_t cut = n / 2;
    for (std::size_t i = 0; i + 1 < n; ++i) {
        for (Index v : mesh.triangles[first[i]]) acc.add(Vec3<S>(ft * mesh.vertices[v]));
        const double cost = acc.volume() + suffix[i + 1];
        // Ties (flat or collapsed input: every cost 0) go to the more balanced cut.
        const auto imbalance = [&](std::size_t c) { return c > n / 2 ? c - n / 2 : n / 2 - c; };
        if (cost < best || (cost == best && imbalance(i + 1) < imbalance(cut))) best = cost, cut = i + 1;
    }
    return first + cut;
}
}  // namespace detail

/// Builds a Bvh<BV> over `mesh`, which must be valid (validate() it first; MeshModel does). O(n log n) for
/// median, mean and sah splits (O(n · depth)); O(n log² n) for pca_volume (a sort per node).
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
        const Vec3<S> axis = detail::split_direction(nodes[w.node].bv, centroid, order.data() + w.begin,
                                                     order.data() + w.end);
        auto key = [&](Index t) { return centroid[t].dot(axis); };
        // Ties broken by index so that builds are deterministic whatever the standard library does.
        auto less = [&](Index a, Index b) {
            const S ka = key(a), kb = key(b);
            return ka < kb || (ka == kb && a < b);
        };
        Index* first = order.data() + w.begin;
        Index* last = order.data() + w.end;
        Index* mid = first + (w.end - w.begin) / 2;
        Index* cut = nullptr;
        if (options.split == SplitStrategy::sah) cut = detail::sah_split(mesh, centroid, first, last);
        else if (options.split == SplitStrategy::pca_volume) cut = detail::pca_volume_split(mesh, centroid, first, last);
        if (cut != nullptr && cut != first && cut != last) {
            mid = cut;
        } else if (options.split == SplitStrategy::mean) {
            S mean = 0;
            for (Index* p = first; p != last; ++p) mean += key(*p);
            mean /= S(last - first);
            Index* mean_cut = std::partition(first, last, [&](Index t) { return key(t) < mean; });
            if (mean_cut != first && mean_cut != last) mid = mean_cut;
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
