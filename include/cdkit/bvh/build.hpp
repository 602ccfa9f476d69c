#pragma once
/// \file Top-down BVH construction: fit a BV to a node's triangles, split them by their centroids along the
/// BV's longest axis, recurse. Median splits give a balanced tree (depth ⌈log2(n / leaf size)⌉ + 1).

#include "cdkit/bv/fit.hpp"
#include "cdkit/bv/narrow_outward.hpp"
#include "cdkit/bv/triangle_moments.hpp"
#include "cdkit/bvh/bvh.hpp"
#include "cdkit/bvh/detail/morton_order.hpp"
#include "cdkit/core/detail/parallel_loop.hpp"
#include "cdkit/core/error.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(CDKIT_HAS_TBB)
#include <tbb/parallel_for.h>
#endif

namespace cdkit {

namespace detail {
/// BVs whose fit can use per-mesh precomputed triangle moments (Obb).
template <class BV>
concept FitsFromMoments = requires(const TriangleMesh<typename BV::Scalar>& m, TriangleRange r, const MeshMoments& mm) {
    { BV::fit(m, r, mm) } -> std::same_as<BV>;
};

/// Moves the k-th smallest of [first, last) by (key, index) to first + k (the median by default), the
/// smaller keys before it: nth_element on cached keys, which spares re-reading centroids at every
/// comparison. Ties broken by index so that builds are deterministic whatever the standard library does.
template <class S, class Key>
void median_partition(Index* first, Index* last, Key key, std::vector<std::pair<S, Index>>& scratch,
                      std::size_t k = std::size_t(-1)) {
    const std::size_t n = std::size_t(last - first);
    if (k == std::size_t(-1)) k = n / 2;
    scratch.resize(n);
    for (std::size_t i = 0; i < n; ++i) scratch[i] = {key(first[i]), first[i]};
    std::nth_element(scratch.begin(), scratch.begin() + std::ptrdiff_t(k), scratch.end());
    for (std::size_t i = 0; i < n; ++i) first[i] = scratch[i].second;
}

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
template <class S> struct BinBox {
    Vec3<S> lo = Vec3<S>::Constant(std::numeric_limits<S>::infinity());
    Vec3<S> hi = Vec3<S>::Constant(-std::numeric_limits<S>::infinity());
    void add(const Vec3<S>& p) noexcept { lo = lo.cwiseMin(p), hi = hi.cwiseMax(p); }
    void add(const BinBox& b) noexcept { lo = lo.cwiseMin(b.lo), hi = hi.cwiseMax(b.hi); }
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

/// What SAH binning reads of a triangle, in one record computed once per build: one random access per
/// triangle and node instead of a centroid plus three vertices through the index (that indirection was 44%
/// of an Obb build on 871k triangles).
template <class S> struct TriangleBounds {
    BinBox<S> box;
    Vec3<S> centroid;
};

template <class S> [[nodiscard]] std::vector<TriangleBounds<S>> triangle_bounds(const TriangleMesh<S>& mesh,
                                                                                const std::vector<Vec3<S>>& centroid,
                                                                                bool parallel) {
    std::vector<TriangleBounds<S>> out(mesh.triangles.size());
    for_each_index(out.size(), [&](std::size_t i) {
        for (Index v : mesh.triangles[i]) out[i].box.add(mesh.vertices[v]);
        out[i].centroid = centroid[i];
    }, parallel);
    return out;
}

/// Binned SAH split of [first, last) (Wald, "On fast construction of SAH-based bounding volume hierarchies",
/// 2007): centroids binned along each axis in one pass, the cost area·count of both sides swept over the bin
/// boundaries. Partitions in place and returns the cut, or nullptr when no bin boundary separates the
/// centroids (then the caller splits at the median).
template <class S>
[[nodiscard]] Index* sah_split(const std::vector<TriangleBounds<S>>& tri, Index* first, Index* last, int& axis_used) {
    constexpr int kMaxBins = 16;
    // Most nodes are small: n bins resolve n centroids as well as 16 do, and the sweep below costs per bin.
    const int B = int(std::min<std::ptrdiff_t>(kMaxBins, last - first));
    BinBox<S> cb;
    for (Index* p = first; p != last; ++p) cb.add(tri[*p].centroid);
    bool binned[3];
    S scale[3];
    for (int axis = 0; axis < 3; ++axis) {
        // An extent so small that B / extent overflows (subnormal centroid spread) is left unbinned: an
        // infinite scale would turn (c − lo)·scale into NaN for c = lo.
        scale[axis] = cb.hi[axis] > cb.lo[axis] ? S(B) / (cb.hi[axis] - cb.lo[axis]) : S(0);
        binned[axis] = scale[axis] > S(0) && scale[axis] <= std::numeric_limits<S>::max();
    }
    auto bin_of = [&](const Vec3<S>& c, int axis) {
        const int b = int((c[axis] - cb.lo[axis]) * scale[axis]);
        return std::clamp(b, 0, B - 1);
    };
    std::array<std::array<BinBox<S>, kMaxBins>, 3> box;
    std::array<std::array<std::size_t, kMaxBins>, 3> count{};
    for (Index* p = first; p != last; ++p) {
        const Vec3<S>& c = tri[*p].centroid;
        const BinBox<S>& tb = tri[*p].box;
        for (int axis = 0; axis < 3; ++axis) {
            if (!binned[axis]) continue;
            const int b = bin_of(c, axis);
            ++count[axis][b];
            box[axis][b].add(tb);
        }
    }
    double best = std::numeric_limits<double>::infinity();
    int best_axis = -1, best_bin = 0;
    for (int axis = 0; axis < 3; ++axis) {
        if (!binned[axis]) continue;
        // Sweep: right-to-left suffix areas, then left-to-right.
        std::array<double, kMaxBins> right_cost{};
        BinBox<S> acc;
        std::size_t n = 0;
        for (int b = B - 1; b > 0; --b) {
            acc.add(box[axis][b]), n += count[axis][b];
            right_cost[b] = acc.area() * double(n);
        }
        acc = BinBox<S>();
        n = 0;
        for (int b = 0; b < B - 1; ++b) {
            acc.add(box[axis][b]), n += count[axis][b];
            const std::size_t right_n = std::size_t(last - first) - n;
            if (n == 0 || right_n == 0) continue;
            const double cost = acc.area() * double(n) + right_cost[b + 1];
            if (cost < best) best = cost, best_axis = axis, best_bin = b;
        }
    }
    if (best_axis < 0) return nullptr;
    axis_used = best_axis;
    return std::partition(first, last, [&](Index t) { return bin_of(tri[t].centroid, best_axis) <= best_bin; });
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
    BinBox<S> acc;
    for (std::size_t i = n; i-- > 1;) {
        for (Index v : mesh.triangles[first[i]]) acc.add(Vec3<S>(ft * mesh.vertices[v]));
        suffix[i] = acc.volume();
    }
    acc = BinBox<S>();
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

namespace detail {

/// One top-down build: the shared read-only inputs and the triangle order, which each subtree permutes only
/// within its own range (so disjoint subtrees may be built by different threads).
template <class BV> class TopDownBuilder {
public:
    using S = typename BV::Scalar;
    using Node = BvhNode<BV>;
    /// A node still to be built: its slot in the node array, its range of the triangle order, its level.
    struct Pending {
        std::uint32_t node, begin, end, level;
    };

    /// Works on a Morton-ordered copy of `mesh` (detail/morton_order.hpp); take_order() maps back.
    TopDownBuilder(const TriangleMesh<S>& mesh, const BuildOptions& options)
        : local_(morton_ordered(mesh, parallel_precompute(mesh, options))), mesh_(local_.mesh), options_(options),
          leaf_max_(std::max<std::uint32_t>(1, options.max_leaf_triangles)), order_(mesh.triangles.size()),
          centroid_(mesh.triangles.size()) {
        // Per-triangle precomputation: in parallel blocks (same numbers) when the build is parallel.
        const bool parallel = parallel_precompute(mesh, options);
        std::iota(order_.begin(), order_.end(), Index(0));
        for_each_index(centroid_.size(), [&](std::size_t i) {
            const Triangle& t = mesh_.triangles[i];
            centroid_[i] = (mesh_.vertices[t[0]] + mesh_.vertices[t[1]] + mesh_.vertices[t[2]]) / S(3);
        }, parallel);
        if constexpr (FitsFromMoments<BV>) moments_ = triangle_moments(mesh_, parallel);
        if (options.split == SplitStrategy::sah) tri_bounds_ = triangle_bounds(mesh_, centroid_, parallel);
    }
    [[nodiscard]] static bool parallel_precompute(const TriangleMesh<S>& mesh, const BuildOptions& options) noexcept {
        return options.parallel && mesh.triangles.size() >= options.parallel_min_triangles;
    }

    /// Fits `w`'s BV into `node` (unless `fitted`: it is there already) and makes it a leaf when it holds
    /// few enough triangles. Otherwise, when `split`, partitions its range and returns the cut; else 0.
    std::uint32_t fit_node(Node& node, const Pending& w, bool fitted, bool split,
                           std::vector<std::pair<S, Index>>& scratch) const {
        const TriangleRange range(order_.data() + w.begin, w.end - w.begin);
        if (!fitted) {
            if constexpr (FitsFromMoments<BV>) node.bv = BV::fit(mesh_, range, moments_);
            else node.bv = BV::fit(mesh_, range);
        }
        if (is_leaf(w)) {
            node.first = w.begin;
            node.count = w.end - w.begin;
            return 0;
        }
        return split ? split_range(node.bv, w.begin, w.end, scratch) : 0;
    }

    [[nodiscard]] bool is_leaf(const Pending& w) const noexcept { return w.end - w.begin <= leaf_max_; }

    /// Nodes of the subtree over m triangles: every cut falls on a multiple of the leaf size (align_cut), so
    /// it has exactly ⌈m / leaf⌉ leaves. Known sizes let subtrees built in parallel write straight into the
    /// final array.
    [[nodiscard]] std::uint32_t node_count(std::uint32_t m) const noexcept { return 2 * ((m + leaf_max_ - 1) / leaf_max_) - 1; }

    /// Makes `parent` an inner node over the two adjacent slots `children`, `children` + 1; returns their ranges.
    static std::array<Pending, 2> add_children(Node* nodes, const Pending& parent, std::uint32_t children, std::uint32_t cut) {
        nodes[parent.node].first = children;
        nodes[parent.node].count = 0;
        return {Pending{children, parent.begin, cut, parent.level + 1}, Pending{children + 1, cut, parent.end, parent.level + 1}};
    }

    /// Builds the subtree of `root` into `nodes`: root's slot holds its BV already when `root_fitted`; its
    /// node_count() − 1 descendants take the slots from `next` on, depth first, children of a node adjacent.
    /// Returns the depth reached.
    std::size_t grow(Node* nodes, std::uint32_t next, const Pending& root, bool root_fitted) const {
        const std::uint32_t end = next + node_count(root.end - root.begin) - 1;
        std::vector<std::pair<S, Index>> scratch;
        std::vector<Pending> stack{root};
        std::size_t depth = 0;
        while (!stack.empty()) {
            const Pending w = stack.back();
            stack.pop_back();
            depth = std::max<std::size_t>(depth, w.level);
            const std::uint32_t cut = fit_node(nodes[w.node], w, root_fitted && w.node == root.node, true, scratch);
            if (is_leaf(w)) continue;
            CDKIT_ASSERT(next + 2 <= end, "BVH build: a subtree outgrew its node_count()");
            const auto [left, right] = add_children(nodes, w, next, cut);
            next += 2;
            // Right first so the left subtree is built (and laid out) next: depth-first order in memory.
            stack.push_back(right);
            stack.push_back(left);
        }
        return depth;
    }

    /// The finished triangle order, in the input mesh's indices (leaves the builder without it).
    [[nodiscard]] std::vector<Index> take_order() {
        for (Index& t : order_) t = local_.original[t];
        return std::move(order_);
    }

private:
    /// Partitions [begin, end) of the order by the chosen strategy; returns the cut (begin < cut < end).
    std::uint32_t split_range(const BV& bv, std::uint32_t begin, std::uint32_t end,
                              std::vector<std::pair<S, Index>>& scratch) const {
        Index* first = order_.data() + begin;
        Index* last = order_.data() + end;
        Vec3<S> axis = split_direction(bv, centroid_, first, last);
        auto key = [&](Index t) { return centroid_[t].dot(axis); };
        Index* mid = first + (end - begin) / 2;
        Index* cut = nullptr;
        int sah_axis = -1;
        if (options_.split == SplitStrategy::sah) cut = sah_split(tri_bounds_, first, last, sah_axis);
        else if (options_.split == SplitStrategy::pca_volume) cut = pca_volume_split(mesh_, centroid_, first, last);
        if (cut != nullptr && cut != first && cut != last) {
            mid = cut;
            if (sah_axis >= 0) axis = Vec3<S>::Unit(sah_axis);
        } else if (options_.split == SplitStrategy::mean) {
            S mean = 0;
            for (Index* p = first; p != last; ++p) mean += key(*p);
            mean /= S(last - first);
            Index* mean_cut = std::partition(first, last, [&](Index t) { return key(t) < mean; });
            if (mean_cut != first && mean_cut != last) mid = mean_cut;
            else median_partition(first, last, key, scratch);
        } else {
            median_partition(first, last, key, scratch);
        }
        if (leaf_max_ > 1) mid = align_cut(first, mid, last, key, scratch,
                                              options_.split == SplitStrategy::pca_volume && mid == cut);
        return std::uint32_t(mid - order_.data());
    }

    /// With several triangles per leaf, moves the cut to the nearest multiple of the leaf size (at most half
    /// a leaf's triangles cross it, taken nearest the cut along the split axis), so that a subtree of k
    /// leaves' triangles splits into whole leaves: unbalanced SAH or median cuts otherwise leave many leaves
    /// part-full (Obb<float> trees with 4-triangle leaves were 2.1× the mesh's bytes on dragon_48k).
    /// `sorted`: [first, last) is sorted along the axis (the PCA sweep), so moving the cut is enough.
    template <class Key>
    Index* align_cut(Index* first, Index* mid, Index* last, Key key, std::vector<std::pair<S, Index>>& scratch,
                     bool sorted) const {
        const std::size_t n = std::size_t(last - first), left = std::size_t(mid - first);
        std::size_t aligned = (left + leaf_max_ / 2) / leaf_max_ * leaf_max_;
        if (aligned == 0) aligned = leaf_max_;
        if (aligned >= n) aligned -= leaf_max_;  // n > leaf_max_: an inner node
        if (aligned == left || aligned == 0) return mid;
        if (!sorted) median_partition(first, last, key, scratch, aligned);
        return first + aligned;
    }

    MortonOrderedMesh<S> local_;
    const TriangleMesh<S>& mesh_;  ///< local_.mesh
    BuildOptions options_;
    std::uint32_t leaf_max_;
    // mutable: subtrees permute disjoint ranges of it; nothing else changes after construction.
    mutable std::vector<Index> order_;
    std::vector<Vec3<S>> centroid_;
    std::vector<TriangleBounds<S>> tri_bounds_;  ///< SAH only
    MeshMoments moments_;
};

}  // namespace detail

/// Builds a Bvh<BV> over `mesh`, which must be valid (validate() it first; MeshModel does). O(n log n) for
/// median, mean and sah splits (O(n · depth)); O(n log² n) for pca_volume (a sort per node).
/// With TBB (CDKIT_HAS_TBB) and options.parallel, meshes of at least options.parallel_min_triangles are built by
/// splitting the top levels first (level by level, each level's nodes in parallel) and then growing the subtrees
/// below them in parallel: the same tree as the sequential build (same nodes, BVs and triangle order), laid out
/// with the top levels breadth first and then each subtree depth first.
///
/// A mesh in double with a float BV (Obb<float> over TriangleMesh<double>, say) gets the double tree's
/// structure with every BV rounded outward to float (bv/narrow_outward.hpp): half the node bytes, still
/// exact in the conservative direction.
namespace detail {
template <class BV> [[nodiscard]] Bvh<BV> build_same_scalar(const TriangleMesh<typename BV::Scalar>& mesh,
                                                           const BuildOptions& options);
}  // namespace detail

template <class BV, class M = typename BV::Scalar>
[[nodiscard]] Bvh<BV> build_bvh(const TriangleMesh<M>& mesh, const BuildOptions& options = {}) {
    static_assert(detail::bv_fits_mesh_v<BV, M>, "a BV is stored in the mesh's scalar type, or in float over a double mesh");
    if constexpr (!std::is_same_v<typename BV::Scalar, M>) {
        const auto wide = build_bvh<typename BV::template rebind<M>>(mesh, options);
        std::vector<BvhNode<BV>> nodes(wide.nodes().size());
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            nodes[i].bv = narrow_outward(wide.nodes()[i].bv);
            nodes[i].first = wide.nodes()[i].first;
            nodes[i].count = wide.nodes()[i].count;
        }
        return Bvh<BV>(std::move(nodes), wide.triangle_order(), wide.depth());
    } else {
        return detail::build_same_scalar<BV>(mesh, options);
    }
}

namespace detail {
template <class BV> [[nodiscard]] Bvh<BV> build_same_scalar(const TriangleMesh<typename BV::Scalar>& mesh,
                                                           const BuildOptions& options) {
    using Node = BvhNode<BV>;
    using Pending = typename detail::TopDownBuilder<BV>::Pending;
    const std::size_t n = mesh.triangles.size();
    if (n == 0) return {};
    detail::TopDownBuilder<BV> builder(mesh, options);
    [[maybe_unused]] const std::uint32_t leaf_max = std::max<std::uint32_t>(1, options.max_leaf_triangles);
    std::vector<Node> nodes(builder.node_count(std::uint32_t(n)));
    const Pending root{0, 0, std::uint32_t(n), 1};
#if defined(CDKIT_HAS_TBB)
    if (options.parallel && n >= std::max<std::size_t>(options.parallel_min_triangles, 2 * leaf_max)) {
        // The top levels breadth first, the nodes of each level fitted and split in parallel (their ranges
        // are disjoint), down to 16 subtrees (enough to balance a few cores); then those in parallel, each
        // into its own slots of the array. Each top level reads every triangle: done one node at a time,
        // they were the serial part of the build.
        constexpr std::uint32_t kTopLevels = 5;
        std::vector<Pending> level{root}, pending;
        std::uint32_t next = 1;
        std::size_t depth = 1;
        while (!level.empty()) {
            std::vector<std::uint32_t> cut(level.size());
            tbb::parallel_for(std::size_t(0), level.size(), [&](std::size_t i) {
                std::vector<std::pair<typename BV::Scalar, Index>> scratch;
                cut[i] = builder.fit_node(nodes[level[i].node], level[i], false, level[i].level < kTopLevels, scratch);
            });
            std::vector<Pending> below;
            for (std::size_t i = 0; i < level.size(); ++i) {
                const Pending& w = level[i];
                depth = std::max<std::size_t>(depth, w.level);
                if (builder.is_leaf(w)) continue;
                if (w.level == kTopLevels) {
                    pending.push_back(w);
                    continue;
                }
                const auto children = builder.add_children(nodes.data(), w, next, cut[i]);
                next += 2;
                below.insert(below.end(), children.begin(), children.end());
            }
            level.swap(below);
        }
        std::vector<std::uint32_t> first_slot(pending.size());
        for (std::size_t i = 0; i < pending.size(); ++i) {
            first_slot[i] = next;
            next += builder.node_count(pending[i].end - pending[i].begin) - 1;
        }
        CDKIT_ASSERT(next == nodes.size(), "BVH build: node slots do not add up");
        std::vector<std::size_t> part_depth(pending.size());
        tbb::parallel_for(std::size_t(0), pending.size(), [&](std::size_t i) {
            part_depth[i] = builder.grow(nodes.data(), first_slot[i], pending[i], true);
        });
        for (std::size_t d : part_depth) depth = std::max(depth, d);
        return Bvh<BV>(std::move(nodes), builder.take_order(), depth);
    }
#endif
    const std::size_t depth = builder.grow(nodes.data(), 1, root, false);
    return Bvh<BV>(std::move(nodes), builder.take_order(), depth);
}
}  // namespace detail

}  // namespace cdkit
