#pragma once
/// \file The top-down build of a restricted boxtree (Zachmann, "Minimal hierarchical collision detection",
/// VRST 2002): each node moves the face of its parent's box that cuts off the most surface area onto its
/// triangles' padded box (then, optionally, a chain of one-child nodes moves more faces), and splits its
/// triangles by a binned SAH whose cost uses the boxes the children will actually imply, or by the median.
///
/// Layout for speed, not for the answer: the triangles are read in Morton order (bvh/detail/morton_order.hpp,
/// so a node's records sit together in memory), one pass over a node's triangles bins all three axes, and
/// the pass that partitions a node also measures each child's box and centroid bounds, which the child needs
/// (three passes a node where there were six). The tree is the same as the former one-pass-per-question
/// build's, up to ties of the median split (broken by position in Morton order, deterministic).
#include "cdkit/bv/fit.hpp"
#include "cdkit/bvh/boxtree_node.hpp"
#include "cdkit/bvh/detail/morton_order.hpp"
#include "cdkit/core/detail/parallel_loop.hpp"
#include "cdkit/core/error.hpp"
#include "cdkit/core/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace cdkit::detail {

/// The box (double, a boxtree's local frame) of some triangles' vertices, and the magnitude the padding must
/// cover: of the model coordinates (queries transform those) and of the local ones (the box tests use those).
struct BoxtreeTriBox {
    std::array<double, 6> box = {HUGE_VAL, HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    double magnitude = 0;
    void add(const BoxtreeTriBox& o) noexcept {
        for (int k = 0; k < 3; ++k) box[k] = std::min(box[k], o.box[k]), box[k + 3] = std::max(box[k + 3], o.box[k + 3]);
        magnitude = std::max(magnitude, o.magnitude);
    }
};

/// The centre of the mesh's bounding box: a boxtree's local frame's origin.
template <class S> [[nodiscard]] Vec3<S> boxtree_centre(const TriangleMesh<S>& mesh) noexcept {
    Vec3<S> lo = Vec3<S>::Constant(std::numeric_limits<S>::infinity()), hi = -lo;
    for (const Triangle& t : mesh.triangles)
        for (Index v : t) lo = lo.cwiseMin(mesh.vertices[v]), hi = hi.cwiseMax(mesh.vertices[v]);
    return lo * S(0.5) + hi * S(0.5);
}

/// Every triangle's box in the local frame around `centre`; the centroids (local) too when asked. In
/// parallel blocks for large meshes (same numbers).
template <class S>
[[nodiscard]] std::vector<BoxtreeTriBox> boxtree_triangle_boxes(const TriangleMesh<S>& mesh, const Vec3<S>& centre,
                                                                std::vector<Vec3<double>>* centroids = nullptr) {
    const std::size_t n = mesh.triangles.size();
    std::vector<BoxtreeTriBox> tri(n);
    if (centroids) centroids->assign(n, Vec3<double>::Zero());
    const Vec3<double> c = centre.template cast<double>();
    for_each_index(n, [&](std::size_t i) {
        for (Index v : mesh.triangles[i]) {
            const Vec3<double> p = mesh.vertices[v].template cast<double>();
            const Vec3<double> l = p - c;
            if (centroids) (*centroids)[i] += l / 3.0;
            BoxtreeTriBox& tb = tri[i];
            for (int k = 0; k < 3; ++k) tb.box[k] = std::min(tb.box[k], l[k]), tb.box[k + 3] = std::max(tb.box[k + 3], l[k]);
            tb.magnitude = std::max({tb.magnitude, p.cwiseAbs().maxCoeff(), l.cwiseAbs().maxCoeff()});
        }
    });
    return tri;
}

/// A box padded (fit_padding's rule in S, plus the local coordinates' own rounding) and rounded outwards
/// to float.
template <class S> [[nodiscard]] FloatBox boxtree_padded(const BoxtreeTriBox& b) noexcept {
    const double eps = double(std::numeric_limits<S>::epsilon());
    const double pad = double(fit_padding(S(b.magnitude))) + 4 * eps * b.magnitude;
    FloatBox f;
    for (int k = 0; k < 3; ++k)
        f[k] = boxtree_round_down(b.box[k] - pad), f[k + 3] = boxtree_round_up(b.box[k + 3] + pad);
    return f;
}

/// The root box from the whole mesh's box; throws when it does not fit float planes.
template <class S> [[nodiscard]] FloatBox boxtree_root_box(const TriangleMesh<S>& mesh, const BoxtreeTriBox& all) {
    const FloatBox f = boxtree_padded<S>(all);
    for (float x : f)
        if (!std::isfinite(x)) throw Error(mesh.source, "", "restricted boxtree: the mesh's extent does not fit float planes");
    return f;
}

/// `tight` clipped to `parent` on every face: both hold the triangles, so their intersection does too, and
/// a child's box never grows past its parent's.
[[nodiscard]] inline FloatBox boxtree_clipped(FloatBox tight, const FloatBox& parent) noexcept {
    for (int k = 0; k < 3; ++k) tight[k] = std::max(tight[k], parent[k]), tight[k + 3] = std::min(tight[k + 3], parent[k + 3]);
    return tight;
}

/// Builds boxtree nodes over a mesh (already validated). Subtrees of disjoint ranges may grow on several
/// threads at once, each into its own node vector.
template <class S> class BoxtreeBuilder {
public:
    using Node = BoxtreeNode;
    /// A node to build: its slot, its triangles (positions [begin, end) of the order), their box and
    /// centroid bounds, its level (the root's is 1) and the box its parent implies.
    struct Work {
        std::uint32_t node, begin, end, level;
        BoxtreeTriBox tight;
        Vec3<double> clo, chi;
        FloatBox parent;
    };

    BoxtreeBuilder(const TriangleMesh<S>& mesh, const Vec3<S>& centre, const BoxtreeOptions& options)
        : sorted_(morton_ordered(mesh)), options_(options) {
        tri_ = boxtree_triangle_boxes(sorted_.mesh, centre, &centroid_);
        order_.resize(tri_.size());
        for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = Index(i);
    }

    /// The root's work (slot 0, every triangle). Its `parent` is left for the caller to set to the root box,
    /// which is made from `tight` (the root restricts nothing).
    [[nodiscard]] Work root() const noexcept { return measured(0, std::uint32_t(order_.size()), 1, {}); }

    /// Writes w's node into nodes[w.node] (which exists): its restriction, a chain of one-child nodes
    /// appended after it, and a leaf or two children slots appended; returns how many children works it
    /// wrote to `below` (0 or 2).
    std::size_t expand(std::vector<Node>& nodes, const Work& w, std::array<Work, 2>& below, std::size_t& depth) {
        Index* first = order_.data() + w.begin;
        Index* last = order_.data() + w.end;
        const FloatBox tight = boxtree_clipped(boxtree_padded<S>(w.tight), w.parent);
        std::uint32_t cur = w.node, level = w.level;
        FloatBox box = w.parent;
        if (w.level != 1) {  // the root (level 1) restricts nothing: its box is the fit itself
            const Cut cut = best_cut(box, tight);
            nodes[cur].set_restriction(cut.axis, cut.upper, float(cut.value));
            box = restrict_box(box, nodes[cur]);
            for (std::uint32_t e = 0; e < options_.max_extra_restrictions; ++e) {
                const Cut more = best_cut(box, tight);
                if (!(more.gain >= double(options_.min_extra_gain)) || more.axis == Node::no_axis) break;
                const std::uint32_t next = std::uint32_t(nodes.size());
                nodes.emplace_back();
                nodes[cur].set_link(Node::Kind::one_child, next);
                cur = next;
                ++level;
                nodes[cur].set_restriction(more.axis, more.upper, float(more.value));
                box = restrict_box(box, nodes[cur]);
            }
        }
        depth = std::max<std::size_t>(depth, level);
        if (w.end - w.begin == 1) {
            nodes[cur].set_link(Node::Kind::leaf, sorted_.original[*first]);
            return 0;
        }
        Index* mid = options_.split == BoxtreeSplit::implied_sah ? sah_split(first, last, box, w.clo, w.chi) : nullptr;
        if (mid == nullptr || mid == first || mid == last) {
            // Median split of the centroids along the tight box's longest axis; ties by position (deterministic).
            int axis = 0;
            for (int k = 1; k < 3; ++k)
                if (double(tight[k + 3]) - tight[k] > double(tight[axis + 3]) - tight[axis]) axis = k;
            mid = first + (last - first) / 2;
            std::nth_element(first, mid, last, [&](Index a, Index b) {
                const double ka = centroid_[a][axis], kb = centroid_[b][axis];
                return ka < kb || (ka == kb && a < b);
            });
        }
        const std::uint32_t children = std::uint32_t(nodes.size());
        nodes.emplace_back();
        nodes.emplace_back();
        nodes[cur].set_link(Node::Kind::two_children, children);
        const std::uint32_t split = std::uint32_t(mid - order_.data());
        below[0] = measured(w.begin, split, level + 1, box);
        below[0].node = children;
        below[1] = measured(split, w.end, level + 1, box);
        below[1].node = children + 1;
        return 2;
    }

    /// Builds w's whole subtree into `nodes`, depth first; returns its deepest level.
    std::size_t grow(std::vector<Node>& nodes, const Work& root) {
        std::size_t depth = 0;
        std::vector<Work> stack{root};
        std::array<Work, 2> below;
        while (!stack.empty()) {
            const Work w = stack.back();
            stack.pop_back();
            if (expand(nodes, w, below, depth) == 2) stack.push_back(below[1]), stack.push_back(below[0]);
        }
        return depth;
    }

private:
    using Box6d = std::array<double, 6>;

    /// Work for positions [begin, end): one pass for the triangles' box and centroid bounds.
    [[nodiscard]] Work measured(std::uint32_t begin, std::uint32_t end, std::uint32_t level, const FloatBox& parent) const noexcept {
        Work w{0, begin, end, level, {}, Vec3<double>::Constant(HUGE_VAL), Vec3<double>::Constant(-HUGE_VAL), parent};
        for (std::uint32_t i = begin; i < end; ++i) {
            const Index t = order_[i];
            w.tight.add(tri_[t]);
            w.clo = w.clo.cwiseMin(centroid_[t]), w.chi = w.chi.cwiseMax(centroid_[t]);
        }
        return w;
    }

    /// Per face axis, the fraction of `box`'s surface area that moving the face by one unit cuts off (of the
    /// extent when the box is flat); 0 for an axis of zero extent, which no cut can take.
    struct CutWeights { double w[3]; };
    template <class A> [[nodiscard]] static CutWeights cut_weights(const A& box) noexcept {
        CutWeights c{};
        const double e[3] = {double(box[3]) - double(box[0]), double(box[4]) - double(box[1]), double(box[5]) - double(box[2])};
        const double area = e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
        for (int k = 0; k < 3; ++k)
            c.w[k] = !(e[k] > 0) ? 0.0 : area > 0 ? (e[(k + 1) % 3] + e[(k + 2) % 3]) / area : 1 / e[k];
        return c;
    }
    /// The face of `box` whose move to `tight` cuts off the largest fraction of the box's surface area (a
    /// proxy for the chance that another box overlaps it); `cw` = cut_weights(box).
    struct Cut { std::uint32_t axis = Node::no_axis; bool upper = false; double value = 0; double gain = 0; };
    template <class A, class B>
    [[nodiscard]] static Cut best_cut(const A& box, const B& tight, const CutWeights& cw) noexcept {
        Cut best;
        for (std::uint32_t k = 0; k < 3; ++k) {
            if (cw.w[k] == 0) continue;
            const double g_lo = (double(tight[k]) - double(box[k])) * cw.w[k];
            const double g_hi = (double(box[k + 3]) - double(tight[k + 3])) * cw.w[k];
            if (g_lo > best.gain) best = {k, false, double(tight[k]), g_lo};
            if (g_hi > best.gain) best = {k, true, double(tight[k + 3]), g_hi};
        }
        return best;
    }
    template <class A, class B> [[nodiscard]] static Cut best_cut(const A& box, const B& tight) noexcept {
        return best_cut(box, tight, cut_weights(box));
    }

    /// The split heuristic's estimate of a child's implied box: the parent's box after the cuts the build
    /// would make (in double, without the padding: a cost, not a bound); returns its surface area (halved).
    /// `cw` = cut_weights(parent), the same for every candidate of a node.
    [[nodiscard]] double implied_area(const FloatBox& parent, const CutWeights& cw, const Box6d& tight) const noexcept {
        Box6d box;
        for (int k = 0; k < 6; ++k) box[k] = double(parent[k]);
        for (std::uint32_t c = 0; c <= options_.max_extra_restrictions; ++c) {
            const Cut cut = c == 0 ? best_cut(box, tight, cw) : best_cut(box, tight);
            if (cut.axis == Node::no_axis || (c > 0 && !(cut.gain >= double(options_.min_extra_gain)))) break;
            box[cut.upper ? cut.axis + 3 : cut.axis] = cut.value;
        }
        const double x = box[3] - box[0], y = box[4] - box[1], z = box[5] - box[2];
        return x * y + y * z + z * x;
    }

    /// Binned SAH over implied boxes, 16 bins on each axis filled in one pass: partitions [first, last) and
    /// returns the cut, or nullptr when no bin split separates the centroids.
    [[nodiscard]] Index* sah_split(Index* first, Index* last, const FloatBox& box, const Vec3<double>& clo,
                                   const Vec3<double>& chi) const {
        constexpr int B = 16;
        const Box6d none = {HUGE_VAL, HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        auto add = [](Box6d& a, const Box6d& b) {
            for (int k = 0; k < 3; ++k) a[k] = std::min(a[k], b[k]), a[k + 3] = std::max(a[k + 3], b[k + 3]);
        };
        const auto bin_of = [&](Index t, int axis) {
            return std::clamp(int(double(B) * (centroid_[t][axis] - clo[axis]) / (chi[axis] - clo[axis])), 0, B - 1);
        };
        std::array<std::array<Box6d, B>, 3> bins;
        std::array<std::array<std::size_t, B>, 3> count{};
        for (auto& axis_bins : bins) axis_bins.fill(none);
        bool live[3];
        for (int axis = 0; axis < 3; ++axis) live[axis] = chi[axis] > clo[axis];
        for (Index* p = first; p != last; ++p)
            for (int axis = 0; axis < 3; ++axis) {
                if (!live[axis]) continue;
                const int b = bin_of(*p, axis);
                ++count[axis][b];
                add(bins[axis][b], tri_[*p].box);
            }
        const CutWeights cw = cut_weights(box);
        double best = HUGE_VAL;
        int best_axis = -1, best_bin = 0;
        for (int axis = 0; axis < 3; ++axis) {
            if (!live[axis]) continue;
            std::array<double, B> right_cost{};
            Box6d acc = none;
            std::size_t n_acc = 0;
            // An empty bin leaves both sides as they were: its costs are its neighbour's, and a cut after
            // it splits like the cut before it (the first of equal costs wins), so it is skipped. Most
            // nodes are small and fill few of the 16 bins.
            for (int b = B - 1; b > 0; --b) {
                if (count[axis][b] == 0) {
                    right_cost[b] = b + 1 < B ? right_cost[b + 1] : 0;
                    continue;
                }
                add(acc, bins[axis][b]), n_acc += count[axis][b];
                right_cost[b] = implied_area(box, cw, acc) * double(n_acc);
            }
            acc = none;
            n_acc = 0;
            for (int b = 0; b < B - 1; ++b) {
                if (count[axis][b] == 0) continue;
                add(acc, bins[axis][b]), n_acc += count[axis][b];
                const std::size_t right_n = std::size_t(last - first) - n_acc;
                if (right_n == 0) continue;
                const double cost = implied_area(box, cw, acc) * double(n_acc) + right_cost[b + 1];
                if (cost < best) best = cost, best_axis = axis, best_bin = b;
            }
        }
        if (best_axis < 0) return nullptr;
        return std::partition(first, last, [&](Index t) { return bin_of(t, best_axis) <= best_bin; });
    }

    MortonOrderedMesh<S> sorted_;
    BoxtreeOptions options_;
    std::vector<BoxtreeTriBox> tri_;       ///< by position in Morton order
    std::vector<Vec3<double>> centroid_;   ///< local frame, by position in Morton order
    std::vector<Index> order_;             ///< positions, partitioned node by node
};

}  // namespace cdkit::detail
