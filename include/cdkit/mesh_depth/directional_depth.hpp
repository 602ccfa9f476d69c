#pragma once
/// \file directional_depth(): how far B must move along a given direction until its surface no longer crosses A's.
///
/// Each triangle pair (P of A, Q of B) crosses for one closed interval of translations t·n
/// (detail/translation_interval.hpp); the surfaces cross at t iff some pair's interval holds t. The answer is the
/// first t ≥ 0 outside every interval that holds 0 or is reached from 0 without a gap: a fixed point. The pairs that
/// cross now (collide() in ContactMode::all, computed once for all directions) hold 0; the largest end of their
/// intervals is the first frontier f. Each further pass finds the largest end of an interval that begins by f and
/// moves f there, until no interval reaches past f. A pass is a branch and bound over both trees: a node pair is
/// bounded by the interval of its two boxes (A's nodes boxed in A's frame, B's carried there), pruned when that
/// begins after f or ends before the best end so far, the pair reaching further searched first. The direction search
/// of penetration_depth.hpp stops a direction as soon as its frontier passes the shortest translation found along
/// another.
///
/// This is the directional penetration depth of the two surfaces, measured along the line from where B is (the
/// definition of, e.g., Kim, Lin, Manocha, "Fast penetration depth estimation using rasterization hardware and
/// hierarchical refinement", 2002, restricted to translations along n; the minimum over all n is the translational
/// penetration depth of Dobkin et al. 1993). For two closed meshes it is the depth of their volumes, unless B moved
/// along n comes to lie wholly inside A (then the surfaces no longer cross: the query reports that gap, as collide()
/// would). For open meshes it is the translation that undoes every crossing of the sheets.
/// Const and thread-safe.

#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/ccd/detail/swept_node_box.hpp"
#include "cdkit/mesh_depth/detail/translation_interval.hpp"
#include "cdkit/mesh_depth/result.hpp"
#include "cdkit/query.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace cdkit {

namespace detail {

/// The depth along one direction (in A's frame) and the pair that ends it.
struct DirectionDepth {
    bool colliding = false;
    bool complete = true;
    bool passed_cap = false;  ///< the frontier passed the cap: this direction is no better than one already found
    double depth = 0;
    Index triangle_a = 0, triangle_b = 0;
    Vec3<double> point_a = Vec3<double>::Zero(), point_b = Vec3<double>::Zero();  // A's frame
};

/// Per-thread storage of one depth query's node boxes and posed vertices, kept between queries: an entry is valid
/// for the query whose generation it carries, so a new query costs no clearing (allocating and zeroing a box per
/// node of two 5k-triangle trees took longer than the search itself).
struct DepthScratch {
    std::vector<BroadBox<double>> box_a, box_b;
    std::vector<Vec3<double>> vertex_b;
    std::vector<std::uint32_t> stamp_a, stamp_b, stamp_v;
    std::uint32_t generation = 0;

    /// Starts a query over trees of these sizes; entries of earlier queries become stale.
    void begin(std::size_t nodes_a, std::size_t nodes_b, std::size_t vertices_b) {
        if (++generation == 0) {  // wrapped: clear the stamps once
            for (auto* v : {&stamp_a, &stamp_b, &stamp_v}) std::fill(v->begin(), v->end(), 0u);
            generation = 1;
        }
        if (box_a.size() < nodes_a) box_a.resize(nodes_a), stamp_a.resize(nodes_a, 0);
        if (box_b.size() < nodes_b) box_b.resize(nodes_b), stamp_b.resize(nodes_b, 0);
        if (vertex_b.size() < vertices_b) vertex_b.resize(vertices_b), stamp_v.resize(vertices_b, 0);
    }
    static DepthScratch& of_this_thread() {
        thread_local DepthScratch scratch;
        return scratch;
    }
};

/// Both trees with B carried into A's frame, the triangle pairs that cross now (collide(), ContactMode::all), and the
/// node boxes and B's posed vertices, computed on first use and shared by every direction (in the thread's
/// DepthScratch: one DepthSearch per thread at a time).
template <class BV, class M> class DepthSearch {
public:
    DepthSearch(const MeshModel<BV, M>& a, const MeshModel<BV, M>& b, const Transform<double>& b_to_a)
        : a_(a), b_(b), rel_(b_to_a), scratch_(DepthScratch::of_this_thread()) {
        crossing_ = collide(a, Transform<M>{}, b, b_to_a.template cast<M>(), CollisionRequest{ContactMode::all});
        scratch_.begin(a.bvh().nodes().size(), b.bvh().nodes().size(), b.mesh().vertices.size());
        generation_ = scratch_.generation;
    }

    /// The pairs that cross at B's present pose, in A's frame.
    [[nodiscard]] const CollisionResult<M>& crossing() const noexcept { return crossing_; }

    /// The depth along unit `d` (A's frame). Stops with passed_cap once the frontier exceeds `cap`.
    /// The pairs that cross now hold t = 0: the largest end of their intervals is the first frontier f. Then each
    /// pass (extend()) moves f to the largest end of an interval that begins by f, until none reaches past it.
    DirectionDepth along(const Vec3<double>& d, int max_passes, double cap, MeshDepthStats& stats) {
        DirectionDepth out;
        out.colliding = crossing_.colliding && !crossing_.contacts.empty();
        if (!out.colliding) return out;
        ++stats.directions;
        const Contact<M>& first = crossing_.contacts.front();
        out.triangle_a = first.triangle_a;
        out.triangle_b = first.triangle_b;
        out.point_a = out.point_b = first.point.template cast<double>();
        double f = first_frontier(d, stats, &out);
        for (int pass = 0; f > 0 && f <= cap; ++pass) {
            if (pass == max_passes) {
                out.complete = false;
                break;
            }
            ++stats.passes;
            double best = f;
            if (!extend(d, f, cap, best, out, stats.traversal)) break;
            f = best;
        }
        out.passed_cap = f > cap;
        out.depth = f;
        return out;
    }

    /// The largest end of the intervals of the pairs that cross now: a lower bound of the depth along unit `d`
    /// (cheap: no tree descent). With `out`, the pair that gives it.
    double first_frontier(const Vec3<double>& d, MeshDepthStats& stats, DirectionDepth* out = nullptr) {
        double f = 0;
        DirectionDepth scratch;
        for (const Contact<M>& c : crossing_.contacts) {
            ++stats.traversal.primitive_tests;
            const TranslationInterval r = triangle_translation_interval(triangle_a(c.triangle_a), triangle_b(c.triangle_b), d);
            if (!r.empty() && r.hi > f) keep(r, c.triangle_a, c.triangle_b, f, out ? *out : scratch);
        }
        return f;
    }

private:
    struct Pending {
        std::uint32_t a, b;
        double hi;
    };

    static void keep(const TranslationInterval& r, Index a, Index b, double& f, DirectionDepth& out) noexcept {
        f = r.hi;
        out.triangle_a = a;
        out.triangle_b = b;
        out.point_a = r.at_hi_a;
        out.point_b = r.at_hi_b;
    }

    const BroadBox<double>& box_a(std::uint32_t i) {
        if (scratch_.stamp_a[i] != generation_)
            scratch_.box_a[i] = world_box(a_.bvh().nodes()[i].bv, Transform<double>{}), scratch_.stamp_a[i] = generation_;
        return scratch_.box_a[i];
    }
    const BroadBox<double>& box_b(std::uint32_t i) {
        if (scratch_.stamp_b[i] != generation_)
            scratch_.box_b[i] = world_box(b_.bvh().nodes()[i].bv, rel_), scratch_.stamp_b[i] = generation_;
        return scratch_.box_b[i];
    }
    const Vec3<double>& vertex_b(Index v) {
        if (scratch_.stamp_v[v] != generation_)
            scratch_.vertex_b[v] = rel_.R * b_.mesh().vertices[v].template cast<double>() + rel_.t,
            scratch_.stamp_v[v] = generation_;
        return scratch_.vertex_b[v];
    }
    std::array<Vec3<double>, 3> triangle_a(Index t) const {
        const auto& m = a_.mesh();
        const Triangle& tri = m.triangles[t];
        return {m.vertices[tri[0]].template cast<double>(), m.vertices[tri[1]].template cast<double>(),
                m.vertices[tri[2]].template cast<double>()};
    }
    std::array<Vec3<double>, 3> triangle_b(Index t) {
        const Triangle& tri = b_.mesh().triangles[t];
        return {vertex_b(tri[0]), vertex_b(tri[1]), vertex_b(tri[2])};
    }

    /// One pass: the largest end of a triangle-pair interval that begins by f and ends after it, into `best` (which
    /// starts at f). A branch and bound over both trees: a node pair is pruned when its boxes' interval begins after f
    /// or ends by `best`; the child pair that reaches further goes first. False when no interval reaches past f.
    /// Returns early once `best` passes `cap` (the direction is lost).
    bool extend(const Vec3<double>& d, double f, double cap, double& best, DirectionDepth& out, TraversalStats& st) {
        const auto& na = a_.bvh().nodes();
        const auto& nb = b_.bvh().nodes();
        const auto& order_a = a_.bvh().triangle_order();
        const auto& order_b = b_.bvh().triangle_order();
        const auto interval = [&](std::uint32_t ia, std::uint32_t ib) {
            ++st.bv_tests;
            return box_translation_interval(box_a(ia), box_b(ib), d);
        };
        const auto worth = [&](const TranslationInterval& r) { return !r.empty() && r.lo <= f && r.hi > best; };
        bool found = false;
        stack_.clear();
        if (const TranslationInterval r = interval(0, 0); worth(r)) stack_.push_back({0, 0, r.hi});
        while (!stack_.empty()) {
            const Pending p = stack_.back();
            stack_.pop_back();
            if (!(p.hi > best)) continue;
            const BvhNode<BV>& x = na[p.a];
            const BvhNode<BV>& y = nb[p.b];
            if (x.is_leaf() && y.is_leaf()) {
                ++st.leaf_pairs;
                for (std::uint32_t i = x.first; i < x.first + x.count; ++i) {
                    const std::array<Vec3<double>, 3> P = triangle_a(order_a[i]);
                    for (std::uint32_t j = y.first; j < y.first + y.count; ++j) {
                        ++st.primitive_tests;
                        const TranslationInterval r = triangle_translation_interval(P, triangle_b(order_b[j]), d);
                        if (!worth(r)) continue;
                        keep(r, order_a[i], order_b[j], best, out);
                        found = true;
                        if (best > cap) return true;
                    }
                }
                continue;
            }
            // Split the larger volume (or the one that is not a leaf); the child pair reaching further goes first.
            const bool split_a = y.is_leaf() || (!x.is_leaf() && x.bv.size() >= y.bv.size());
            const std::uint32_t a0 = split_a ? x.first : p.a, a1 = split_a ? x.first + 1 : p.a;
            const std::uint32_t b0 = split_a ? p.b : y.first, b1 = split_a ? p.b : y.first + 1;
            const TranslationInterval r0 = interval(a0, b0), r1 = interval(a1, b1);
            const bool w0 = worth(r0), w1 = worth(r1);
            if (w0 && w1 && r0.hi > r1.hi) {
                stack_.push_back({a1, b1, r1.hi});
                stack_.push_back({a0, b0, r0.hi});
            } else {
                if (w0) stack_.push_back({a0, b0, r0.hi});
                if (w1) stack_.push_back({a1, b1, r1.hi});
            }
        }
        return found;
    }

    const MeshModel<BV, M>& a_;
    const MeshModel<BV, M>& b_;
    Transform<double> rel_;
    CollisionResult<M> crossing_;
    DepthScratch& scratch_;
    std::uint32_t generation_ = 0;
    std::vector<Pending> stack_;
};

/// Pose check and B's pose in A's frame, in double.
template <class M>
[[nodiscard]] QueryStatus depth_setup(const Transform<M>& pose_a, const Transform<M>& pose_b, Transform<double>& pa,
                                      Transform<double>& b_to_a) noexcept {
    if (!pose_is_usable(pose_a) || !pose_is_usable(pose_b)) return QueryStatus::invalid_pose;
    pa = pose_a.template cast<double>();
    b_to_a = pa.inverse() * pose_b.template cast<double>();
    return QueryStatus::ok;
}

/// Copies a direction's answer into the result (points and normal into the world frame).
inline void store_direction(const DirectionDepth& r, const Vec3<double>& d, const Transform<double>& pa,
                            DepthDirection source, MeshDepthResult& out) noexcept {
    out.colliding = r.colliding;
    out.complete = r.complete;
    out.depth = r.colliding ? r.depth : 0;
    out.normal = r.colliding ? Vec3<double>(pa.R * d) : Vec3<double>::Zero();
    out.direction = r.colliding ? source : DepthDirection::none;
    out.triangle_a = r.triangle_a;
    out.triangle_b = r.triangle_b;
    out.point_a = r.colliding ? Vec3<double>(pa * r.point_a) : Vec3<double>::Zero();
    out.point_b = r.colliding ? Vec3<double>(pa * r.point_b) : Vec3<double>::Zero();
}

}  // namespace detail

/// The translation of B (`b` at `pose_b`) along `direction` (world frame, from A towards B; any non-zero length) that
/// undoes every crossing of its triangles with A's (`a` at `pose_a`); see the file comment. Any BV of the tree family,
/// any scalar (computed in double). Status invalid_pose for a pose that is not a rigid motion, invalid_input for a
/// zero or non-finite direction. Const and thread-safe.
template <class BV, class M>
[[nodiscard]] MeshDepthResult directional_depth(const MeshModel<BV, M>& a, const std::type_identity_t<Transform<M>>& pose_a,
                                                const MeshModel<BV, M>& b, const std::type_identity_t<Transform<M>>& pose_b,
                                                const Vec3<double>& direction, const MeshDepthRequest& request = {}) {
    MeshDepthResult out;
    Transform<double> pa, rel;
    out.status = detail::depth_setup(pose_a, pose_b, pa, rel);
    if (out.status != QueryStatus::ok) return out;
    const double len = direction.norm();
    if (!(len > 0) || !std::isfinite(len)) {
        out.status = QueryStatus::invalid_input;
        return out;
    }
    const Vec3<double> d = pa.R.transpose() * (direction / len);
    detail::DepthSearch<BV, M> search(a, b, rel);
    const detail::DirectionDepth r =
        search.along(d, request.max_passes, std::numeric_limits<double>::infinity(), out.stats);
    detail::store_direction(r, d, pa, DepthDirection::given, out);
    return out;
}

}  // namespace cdkit
