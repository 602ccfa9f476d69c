#pragma once
/// \file Distance from a point to a triangle mesh, on an Aabb tree: the sphere packer's distance field.
///
/// The closest point on a triangle follows Ericson, "Real-Time Collision Detection" (2005), sec. 5.1.5
/// (Voronoi regions of the vertices, edges and face, decided by barycentric sign tests). The tree search is
/// best-first branch and bound: a node is skipped when its box is farther than the best triangle so far.
/// Callers with a good guess (a neighbour's closest triangle) can seed the bound with it, and callers that
/// only compare the distance with a threshold can stop at the first triangle below it.
/// Const and thread-safe.

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bvh/build.hpp"
#include "cdkit/bvh/traverse.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cdkit {

/// The point of triangle (a, b, c) closest to p.
[[nodiscard]] inline Vec3<double> closest_point_on_triangle(const Vec3<double>& p, const Vec3<double>& a,
                                                            const Vec3<double>& b, const Vec3<double>& c) noexcept {
    const Vec3<double> ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3<double> bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
    const Vec3<double> cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double den = va + vb + vc;
    if (!(den > 0)) {  // zero-area triangle that slipped past the region tests: take the best edge
        Vec3<double> best = a;
        for (const auto& [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
            const Vec3<double> e = v - u;
            const double ee = e.squaredNorm();
            const double s = ee > 0 ? std::clamp((p - u).dot(e) / ee, 0.0, 1.0) : 0.0;
            const Vec3<double> q = u + e * s;
            if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
        }
        return best;
    }
    return a + ab * (vb / den) + ac * (vc / den);
}

/// Result of PointMeshDistance::query().
struct PointMeshClosest {
    double distance = std::numeric_limits<double>::infinity();
    Vec3<double> point = Vec3<double>::Zero();  ///< closest point on the mesh
    Index triangle = 0;
};

/// A mesh with an Aabb tree, answering closest-point queries. Keeps its own copy of the mesh.
class PointMeshDistance {
public:
    PointMeshDistance() = default;
    /// `mesh` must be valid (validate()).
    explicit PointMeshDistance(TriangleMesh<double> mesh)
        : mesh_(std::move(mesh)), bvh_(build_bvh<Aabb<double>>(mesh_, options())) {}

    [[nodiscard]] const TriangleMesh<double>& mesh() const noexcept { return mesh_; }

    /// Closest point of the mesh to p, searching only closer than `max_distance` (returns distance +inf
    /// when nothing is that close).
    [[nodiscard]] PointMeshClosest query(const Vec3<double>& p,
                                         double max_distance = std::numeric_limits<double>::infinity()) const noexcept {
        PointMeshQuery q;
        q.max_distance = max_distance;
        return query(p, q);
    }

    /// `hint` value meaning none.
    static constexpr Index no_hint = ~Index(0);
    /// Options of the accelerated query(), for callers that ask about many nearby points or need less than
    /// the exact distance.
    struct PointMeshQuery {
        double max_distance = std::numeric_limits<double>::infinity();  ///< search only closer than this
        /// A triangle measured first (e.g. a neighbouring point's closest one): a close one prunes the tree
        /// from the root. The result is the same minimum over the same triangle distances with or without it.
        Index hint = no_hint;
        /// ≥ 0: the caller only needs to know whether the distance exceeds stop_at; the search returns at the
        /// first triangle found at distance ≤ stop_at, with that (not necessarily least) distance. Distances
        /// above stop_at come out exact.
        double stop_at = -1;
        /// > 0: only ⌊distance / quantum⌋ is needed; subtrees that cannot lower it are skipped, so the
        /// returned distance may exceed the least one but has the same ⌊· / quantum⌋ (a relative margin of
        /// 1e-9 on the cut keeps rounding on the safe side).
        double quantum = 0;
    };
    /// Closest point with the options above; with the defaults it is query(p, max_distance).
    [[nodiscard]] PointMeshClosest query(const Vec3<double>& p, const PointMeshQuery& opt) const noexcept {
        PointMeshClosest out;
        if (bvh_.empty()) return out;
        constexpr double inf = std::numeric_limits<double>::infinity();
        double best2 = opt.max_distance < inf ? opt.max_distance * opt.max_distance : inf;
        double cut2 = best2;  // subtrees at squared distance ≥ cut2 cannot matter
        const double stop2 = opt.stop_at >= 0 ? opt.stop_at * opt.stop_at : -1.0;
        bool found = false;
        auto improve = [&](const Vec3<double>& q, double d2, Index tri) {
            best2 = d2, out.point = q, out.triangle = tri, found = true;
            if (opt.quantum > 0) {
                const double floor_d = std::floor(std::sqrt(d2) / opt.quantum) * opt.quantum * (1 + 1e-9);
                cut2 = std::min(best2, floor_d * floor_d);
            } else {
                cut2 = best2;
            }
        };
        if (opt.hint < mesh_.triangles.size()) {
            const Triangle& t = mesh_.triangles[opt.hint];
            const Vec3<double> q = closest_point_on_triangle(p, mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]]);
            const double d2 = (q - p).squaredNorm();
            if (d2 < best2) improve(q, d2, opt.hint);
        }
        const auto& nodes = bvh_.nodes();
        const auto& order = bvh_.triangle_order();
        struct Item { std::uint32_t node; double d2; };
        detail::SmallStack<Item, 128> stack;
        if (!(found && best2 <= stop2)) stack.push({0, box_dist2(nodes[0].bv, p)});
        while (!stack.empty()) {
            const Item it = stack.pop();
            if (it.d2 >= cut2) continue;
            const auto& n = nodes[it.node];
            if (n.is_leaf()) {
                for (std::uint32_t k = n.first; k < n.first + n.count; ++k) {
                    const Triangle& t = mesh_.triangles[order[k]];
                    const Vec3<double> q =
                        closest_point_on_triangle(p, mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]]);
                    const double d2 = (q - p).squaredNorm();
                    if (d2 < best2) improve(q, d2, order[k]);
                }
                if (found && best2 <= stop2) break;
                continue;
            }
            Item c0{n.first, box_dist2(nodes[n.first].bv, p)}, c1{n.first + 1, box_dist2(nodes[n.first + 1].bv, p)};
            if (c1.d2 < c0.d2) std::swap(c0, c1);
            if (c1.d2 < cut2) stack.push(c1);
            if (c0.d2 < cut2) stack.push(c0);
        }
        if (found) out.distance = std::sqrt(best2);
        return out;
    }
    /// Distance only.
    [[nodiscard]] double distance(const Vec3<double>& p) const noexcept { return query(p).distance; }

private:
    static BuildOptions options() {
        BuildOptions o;
        o.split = SplitStrategy::sah;  // point queries prune best on small boxes
        o.max_leaf_triangles = 2;
        return o;
    }
    static double box_dist2(const Aabb<double>& b, const Vec3<double>& p) noexcept {
        return ((p - b.center).cwiseAbs() - b.half).cwiseMax(0.0).squaredNorm();
    }
    TriangleMesh<double> mesh_;
    Bvh<Aabb<double>> bvh_;
};

}  // namespace cdkit
