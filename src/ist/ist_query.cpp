// Inner sphere tree queries: penetration volume (exact and time-critical), distance, combined.
#include "cdkit/ist/ist_query.hpp"

#include "cdkit/bvh/traverse.hpp"

#include <algorithm>
#include <cmath>
#include <queue>

namespace cdkit {
namespace {

using Vec3d = Vec3<double>;
constexpr double kPi = 3.14159265358979323846;

double ball_volume(double r) noexcept { return 4.0 / 3.0 * kPi * r * r * r; }

struct Frame {
    Mat3<double> R;
    Vec3d t;
    [[nodiscard]] Vec3d operator()(const Vec3d& p) const noexcept { return R * p + t; }
};

}  // namespace

PenetrationVolumeResult penetration_volume(const InnerSphereTree& a, const Transform<double>& pose_a,
                                           const InnerSphereTree& b, const Transform<double>& pose_b,
                                           const IstRequest& request) {
    PenetrationVolumeResult out;
    if (!pose_is_usable(pose_a) || !pose_is_usable(pose_b)) {
        out.status = QueryStatus::invalid_pose;
        return out;
    }
    if (a.empty() || b.empty()) return out;
    const Transform<double> rel = pose_a.inverse() * pose_b;
    const Frame to_a{rel.R, rel.t};
    const auto& na = a.nodes();
    const auto& nb = b.nodes();
    const auto& wa = a.cell_weights();
    const auto& wb = b.cell_weights();
    double exact = 0, calibrated = 0;
    auto leaf_pair = [&](const IstNode& x, const IstNode& y, const Vec3d& cy) {
        ++out.stats.leaf_pairs;
        const double v = sphere_intersection_volume(x.radius, y.radius, (x.center - cy).norm());
        if (v <= 0) return;
        exact += v;
        calibrated += v * wa[x.first] * wb[y.first];
        if (request.collect_pairs) out.pairs.push_back({x.first, y.first, v});
    };
    auto overlaps = [&](const IstNode& x, const Vec3d& cx, const IstNode& y, const Vec3d& cy) {
        ++out.stats.node_tests;
        const double rr = x.radius + y.radius;
        return (cx - cy).squaredNorm() < rr * rr;
    };

    if (request.max_node_tests == 0) {
        // Exact: depth-first, every overlapping pair.
        struct Pair { std::uint32_t a, b; };
        detail::SmallStack<Pair, 256> stack;
        if (overlaps(na[0], na[0].center, nb[0], to_a(nb[0].center))) stack.push({0, 0});
        while (!stack.empty()) {
            const Pair p = stack.pop();
            const IstNode& x = na[p.a];
            const IstNode& y = nb[p.b];
            const Vec3d cy = to_a(y.center);
            if (x.is_leaf() && y.is_leaf()) {
                leaf_pair(x, y, cy);
                continue;
            }
            if (y.is_leaf() || (!x.is_leaf() && x.radius >= y.radius)) {
                for (std::uint32_t j = x.first; j < x.first + x.count; ++j)
                    if (overlaps(na[j], na[j].center, y, cy)) stack.push({j, p.b});
            } else {
                for (std::uint32_t j = y.first; j < y.first + y.count; ++j)
                    if (overlaps(x, x.center, nb[j], to_a(nb[j].center))) stack.push({p.a, j});
            }
        }
        out.volume = out.volume_lower = out.volume_upper = exact;
        out.calibrated = calibrated;
        return out;
    }

    // Time-critical: best first by bound, stop at the budget.
    struct Item {
        double bound, estimate;
        std::uint32_t a, b;
        bool operator<(const Item& o) const noexcept { return bound < o.bound; }
    };
    std::priority_queue<Item> heap;
    auto push = [&](std::uint32_t ia, std::uint32_t ib) {
        const IstNode& x = na[ia];
        const IstNode& y = nb[ib];
        const Vec3d cy = to_a(y.center);
        if (!overlaps(x, x.center, y, cy)) return;
        if (x.is_leaf() && y.is_leaf()) return leaf_pair(x, y, cy);
        const double lens = sphere_intersection_volume(x.radius, y.radius, (x.center - cy).norm());
        const double bound = std::min({x.volume, y.volume, lens});
        const double fill = (x.volume / std::max(ball_volume(x.radius), 1e-300)) * (y.volume / std::max(ball_volume(y.radius), 1e-300));
        heap.push({bound, std::min(bound, lens * fill), ia, ib});
    };
    push(0, 0);
    while (!heap.empty() && out.stats.node_tests < request.max_node_tests) {
        const Item it = heap.top();
        heap.pop();
        const IstNode& x = na[it.a];
        const IstNode& y = nb[it.b];
        if (y.is_leaf() || (!x.is_leaf() && x.radius >= y.radius)) {
            for (std::uint32_t j = x.first; j < x.first + x.count; ++j) push(j, it.b);
        } else {
            for (std::uint32_t j = y.first; j < y.first + y.count; ++j) push(it.a, j);
        }
    }
    double rest_bound = 0, rest_estimate = 0;
    out.complete = heap.empty();
    while (!heap.empty()) {
        rest_bound += heap.top().bound;
        rest_estimate += heap.top().estimate;
        heap.pop();
    }
    out.volume_lower = exact;
    out.volume_upper = exact + rest_bound;
    out.volume = exact + rest_estimate;
    const double cov = std::max(a.coverage() * b.coverage(), 1e-12);
    out.calibrated = calibrated + rest_estimate / cov;
    return out;
}

IstDistanceResult sphere_distance(const InnerSphereTree& a, const Transform<double>& pose_a, const InnerSphereTree& b,
                                  const Transform<double>& pose_b, const IstRequest& request) {
    IstDistanceResult out;
    if (!pose_is_usable(pose_a) || !pose_is_usable(pose_b)) {
        out.status = QueryStatus::invalid_pose;
        return out;
    }
    if (a.empty() || b.empty()) return out;
    const Transform<double> rel = pose_a.inverse() * pose_b;
    const Frame to_a{rel.R, rel.t};
    const auto& na = a.nodes();
    const auto& nb = b.nodes();
    struct Item { std::uint32_t a, b; double lb; };
    auto bound = [&](std::uint32_t ia, std::uint32_t ib) {
        ++out.stats.node_tests;
        return Item{ia, ib, (na[ia].center - to_a(nb[ib].center)).norm() - na[ia].radius - nb[ib].radius};
    };
    double best = std::numeric_limits<double>::infinity();
    Vec3d pa = Vec3d::Zero(), pb = Vec3d::Zero();
    detail::SmallStack<Item, 512> stack;
    stack.push(bound(0, 0));
    std::vector<Item> kids;
    double unexplored = std::numeric_limits<double>::infinity();
    while (!stack.empty()) {
        const Item it = stack.pop();
        if (it.lb >= best) continue;
        if (request.max_node_tests && out.stats.node_tests >= request.max_node_tests) {
            // Out of budget: what is left on the stack bounds what was not looked at.
            out.complete = false;
            unexplored = std::min(unexplored, it.lb);
            while (!stack.empty()) unexplored = std::min(unexplored, stack.pop().lb);
            break;
        }
        const IstNode& x = na[it.a];
        const IstNode& y = nb[it.b];
        if (x.is_leaf() && y.is_leaf()) {
            ++out.stats.leaf_pairs;
            best = it.lb;
            const Vec3d cy = to_a(y.center);
            Vec3d u = cy - x.center;
            const double len = u.norm();
            u = len > 0 ? Vec3d(u / len) : Vec3d::UnitX();
            pa = x.center + x.radius * u;
            pb = cy - y.radius * u;
            out.sphere_a = x.first;
            out.sphere_b = y.first;
            if (best <= 0) break;  // overlapping inner spheres: nothing is nearer
            continue;
        }
        kids.clear();
        if (y.is_leaf() || (!x.is_leaf() && x.radius >= y.radius)) {
            for (std::uint32_t j = x.first; j < x.first + x.count; ++j) kids.push_back(bound(j, it.b));
        } else {
            for (std::uint32_t j = y.first; j < y.first + y.count; ++j) kids.push_back(bound(it.a, j));
        }
        std::sort(kids.begin(), kids.end(), [](const Item& l, const Item& r) { return l.lb > r.lb; });
        for (const Item& k : kids)
            if (k.lb < best) stack.push(k);  // nearest pushed last, popped first
    }
    if (best <= 0) {
        const Vec3d mid = (pa + pb) / 2;
        pa = pb = mid;
    }
    out.distance = std::max(0.0, best);
    out.lower_bound = std::max(0.0, std::min(best, unexplored));
    out.point_a = pose_a * pa;
    out.point_b = pose_a * pb;
    return out;
}

IstQueryResult ist_query(const InnerSphereTree& a, const Transform<double>& pose_a, const InnerSphereTree& b,
                         const Transform<double>& pose_b, const IstRequest& request) {
    IstQueryResult out;
    out.volume = penetration_volume(a, pose_a, b, pose_b, request);
    out.status = out.volume.status;
    if (out.status != QueryStatus::ok) return out;
    out.overlapping = out.volume.volume_lower > 0;
    if (!out.overlapping) {
        out.distance = sphere_distance(a, pose_a, b, pose_b, request);
        out.overlapping = out.distance.complete && out.distance.distance <= 0 && out.volume.volume_upper > 0;
    } else {
        out.distance.distance = 0;
        out.distance.lower_bound = 0;
    }
    return out;
}

}  // namespace cdkit
