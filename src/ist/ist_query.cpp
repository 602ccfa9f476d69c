// Inner sphere tree queries: penetration volume (exact and time-critical), distance, combined.
#include "cdkit/ist/ist_query.hpp"

#include "cdkit/bvh/traverse.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>
#include <type_traits>
#include <vector>

namespace cdkit {
namespace {

using Vec3d = Vec3<double>;
constexpr double kPi = 3.14159265358979323846;

double ball_volume(double r) noexcept { return 4.0 / 3.0 * kPi * r * r * r; }

/// The closest points of the spheres of nodes x (in A's frame) and y (its centre cy carried to A's frame),
/// on the line of their centres (along x when the centres coincide).
void sphere_witness(const IstNode& x, const IstNode& y, const Vec3d& cy, Vec3d& pa, Vec3d& pb) noexcept {
    Vec3d u = cy - x.center;
    const double len = u.norm();
    u = len > 0 ? Vec3d(u / len) : Vec3d::UnitX();
    pa = x.center + x.radius * u;
    pb = cy - y.radius * u;
}

struct Frame {
    Mat3<double> R;
    Vec3d t;
    [[nodiscard]] Vec3d operator()(const Vec3d& p) const noexcept { return R * p + t; }
};

/// The start every query shares: B's frame carried into A's, or nothing when there is nothing to traverse —
/// `status` becomes invalid_pose for a pose that is not a rigid motion, and stays as it is for an empty tree.
std::optional<Frame> query_frame(const InnerSphereTree& a, const Transform<double>& pose_a, const InnerSphereTree& b,
                                 const Transform<double>& pose_b, QueryStatus& status) noexcept {
    if (!pose_is_usable(pose_a) || !pose_is_usable(pose_b)) {
        status = QueryStatus::invalid_pose;
        return std::nullopt;
    }
    if (a.empty() || b.empty()) return std::nullopt;
    const Transform<double> rel = pose_a.inverse() * pose_b;
    return Frame{rel.R, rel.t};
}

/// Which node of a pair to split: the larger one (A's on a tie), never a leaf.
bool split_a(const IstNode& x, const IstNode& y) noexcept { return y.is_leaf() || (!x.is_leaf() && x.radius >= y.radius); }

/// Insertion sort by descending key (≤ 16 items): pushed in this order, the smallest key is popped first.
/// Equal keys keep their index order, so the order is the same wherever it is used.
template <class T> void sort_deepest_last(T* v, std::size_t n) noexcept {
    for (std::size_t i = 1; i < n; ++i) {
        const T t = v[i];
        std::size_t j = i;
        for (; j > 0 && v[j - 1].key < t.key; --j) v[j] = v[j - 1];
        v[j] = t;
    }
}

/// A node pair and its sort key.
struct PairKey {
    std::uint32_t a, b;
    double key;
};

/// The exact volume traversal, shared by penetration_volume() and ist_query() so that both visit the same
/// pairs in the same order and sum bit for bit alike: depth first over the pairs whose bounding spheres (and
/// all their ancestors') overlap, children deepest overlap first (smallest |c_a − c_b|² − (r_a + r_b)², which
/// finds near pairs early). With `Frontier`, until the first overlapping inner-sphere pair it also keeps the
/// children that leave that path in `far` (key = |c_a − c_b|²) and reports the path's leaf pairs to
/// `on_leaf(x, y, cy, |c_a − c_b| − r_a − r_b)`, for ist_query()'s distance.
template <bool Frontier, class OnLeaf>
void volume_descent(const InnerSphereTree& a, const InnerSphereTree& b, const Frame& to_a, bool collect_pairs,
                    PenetrationVolumeResult& out, std::vector<PairKey>* far, OnLeaf&& on_leaf) {
    const auto& na = a.nodes();
    const auto& nb = b.nodes();
    const auto& ca = a.cell_radii();
    const auto& cb = b.cell_radii();
    double exact = 0, calibrated = 0;
    detail::SmallStack<PairKey, 256> stack;
    std::array<PairKey, 16> kids, far_kids;  // out-degree ≤ 16 (validated)
    {
        ++out.stats.node_tests;
        const Vec3d cy = to_a(nb[0].center);
        const double rr = na[0].radius + nb[0].radius;
        const double d2 = (na[0].center - cy).squaredNorm();
        if (d2 < rr * rr) stack.push({0, 0, d2 - rr * rr});
        else if constexpr (Frontier) far->push_back({0, 0, d2});
    }
    // One step of the descent; the frontier variant runs only until the first overlap, then the plain one
    // goes on with the same stack (same order), so the volume-only part costs what penetration_volume()'s does.
    auto step = [&](auto frontier) {
        constexpr bool keep_far = decltype(frontier)::value;
        const PairKey p = stack.pop();
        const IstNode& x = na[p.a];
        const IstNode& y = nb[p.b];
        const Vec3d cy = to_a(y.center);
        if (x.is_leaf() && y.is_leaf()) {
            ++out.stats.leaf_pairs;
            const double d = (x.center - cy).norm();
            const double v = sphere_intersection_volume(x.radius, y.radius, d);
            if (v > 0) {
                exact += v;
                calibrated += sphere_intersection_volume(ca[x.first], cb[y.first], d);
                if (collect_pairs) out.pairs.push_back({x.first, y.first, v});
                if constexpr (keep_far) far->clear();
            }
            if constexpr (keep_far)
                if (exact == 0) on_leaf(x, y, cy, d - x.radius - y.radius);
            return;
        }
        std::size_t n = 0, nf = 0;
        auto child = [&](std::uint32_t ia, std::uint32_t ib, const IstNode& cx, const IstNode& cn, const Vec3d& c) {
            ++out.stats.node_tests;
            const double rr = cx.radius + cn.radius;
            const double d2 = (cx.center - c).squaredNorm();
            if (d2 < rr * rr) kids[n++] = {ia, ib, d2 - rr * rr};
            else if constexpr (keep_far) far_kids[nf++] = {ia, ib, d2};  // the bound's square root waits for the distance search
        };
        if (split_a(x, y)) {
            for (std::uint32_t j = x.first; j < x.first + x.count; ++j) child(j, p.b, na[j], y, cy);
        } else {
            for (std::uint32_t j = y.first; j < y.first + y.count; ++j) child(p.a, j, x, nb[j], to_a(nb[j].center));
        }
        sort_deepest_last(kids.data(), n);
        for (std::size_t k = 0; k < n; ++k) stack.push(kids[k]);
        if constexpr (keep_far) far->insert(far->end(), far_kids.begin(), far_kids.begin() + std::ptrdiff_t(nf));
    };
    if constexpr (Frontier)
        while (!stack.empty() && exact == 0) step(std::true_type{});
    while (!stack.empty()) step(std::false_type{});
    out.volume = out.volume_lower = out.volume_upper = exact;
    out.colliding = out.volume_upper > 0;
    out.calibrated = calibrated;
}

/// The time-critical volume traversal, shared by penetration_volume() and ist_query(): pairs expanded best
/// first by their bound, stopped at the node budget (see ist_query.hpp). `on_apart(a, b, |c_a − c_b|²)`
/// receives every pair whose bounding spheres are apart while no inner spheres have overlapped yet (the
/// distance frontier of ist_query()).
template <class OnApart>
void volume_best_first(const InnerSphereTree& a, const InnerSphereTree& b, const Frame& to_a, const IstRequest& request,
                       PenetrationVolumeResult& out, OnApart&& on_apart) {
    const auto& na = a.nodes();
    const auto& nb = b.nodes();
    const auto& ca = a.cell_radii();
    const auto& cb = b.cell_radii();
    double exact = 0, calibrated = 0;
    auto leaf_pair = [&](const IstNode& x, const IstNode& y, const Vec3d& cy) {
        ++out.stats.leaf_pairs;
        const double d = (x.center - cy).norm();
        const double v = sphere_intersection_volume(x.radius, y.radius, d);
        if (v <= 0) return;
        exact += v;
        calibrated += sphere_intersection_volume(ca[x.first], cb[y.first], d);
        if (request.collect_pairs) out.pairs.push_back({x.first, y.first, v});
    };
    struct Item {
        double bound, estimate;
        std::uint32_t a, b;
        bool operator<(const Item& o) const noexcept { return bound < o.bound; }
    };
    std::priority_queue<Item> heap;
    // Every frontier of the expansion bounds the volume: exact + Σ open bounds. A split can raise that sum
    // (the children's lens bounds may add up past their parent's), so the least sum seen is kept, which also
    // makes volume_upper non-increasing in the budget (a larger budget runs the same expansion further). The
    // running sum `open` drifts by at most one rounding of its largest magnitude per update; that is added
    // back to each sum before it competes.
    double open = 0, open_peak = 0, least_upper = std::numeric_limits<double>::infinity();
    std::uint64_t updates = 0;
    auto note_frontier = [&] {
        const double drift = double(updates + 2) * std::numeric_limits<double>::epsilon() * (open_peak + exact);
        least_upper = std::min(least_upper, exact + std::max(open, 0.0) + drift);
    };
    auto push = [&](std::uint32_t ia, std::uint32_t ib) {
        const IstNode& x = na[ia];
        const IstNode& y = nb[ib];
        const Vec3d cy = to_a(y.center);
        ++out.stats.node_tests;
        const double rr = x.radius + y.radius;
        const double d2 = (x.center - cy).squaredNorm();
        if (!(d2 < rr * rr)) {
            if (exact == 0) on_apart(ia, ib, d2);
            return;
        }
        if (x.is_leaf() && y.is_leaf()) return leaf_pair(x, y, cy);
        const double lens = sphere_intersection_volume(x.radius, y.radius, (x.center - cy).norm());
        const double bound = std::min({x.volume, y.volume, lens});
        const double fill = (x.volume / std::max(ball_volume(x.radius), 1e-300)) * (y.volume / std::max(ball_volume(y.radius), 1e-300));
        heap.push({bound, std::min(bound, lens * fill), ia, ib});
        open += bound;
        open_peak = std::max(open_peak, open);
        ++updates;
    };
    push(0, 0);
    note_frontier();
    while (!heap.empty() && out.stats.node_tests < request.max_node_tests) {
        const Item it = heap.top();
        heap.pop();
        open -= it.bound;
        ++updates;
        const IstNode& x = na[it.a];
        const IstNode& y = nb[it.b];
        if (y.is_leaf() || (!x.is_leaf() && x.radius >= y.radius)) {
            for (std::uint32_t j = x.first; j < x.first + x.count; ++j) push(j, it.b);
        } else {
            for (std::uint32_t j = y.first; j < y.first + y.count; ++j) push(it.a, j);
        }
        note_frontier();
    }
    double rest_estimate = 0;
    out.complete = heap.empty();
    while (!heap.empty()) {
        rest_estimate += heap.top().estimate;
        heap.pop();
    }
    out.volume_lower = exact;
    out.volume_upper = out.complete ? exact : least_upper;
    out.volume = std::min(exact + rest_estimate, out.volume_upper);
    out.colliding = out.volume_upper > 0;
    const double cov = std::max(a.coverage() * b.coverage(), 1e-12);
    const double ratio = (calibrated + rest_estimate / cov) / std::max(exact + rest_estimate, 1e-300);
    out.calibrated = calibrated + rest_estimate * ratio;
}

}  // namespace

PenetrationVolumeResult penetration_volume(const InnerSphereTree& a, const Transform<double>& pose_a,
                                           const InnerSphereTree& b, const Transform<double>& pose_b,
                                           const IstRequest& request) {
    PenetrationVolumeResult out;
    const std::optional<Frame> frame = query_frame(a, pose_a, b, pose_b, out.status);
    if (!frame) return out;
    const Frame& to_a = *frame;
    if (request.max_node_tests == 0) {
        volume_descent<false>(a, b, to_a, request.collect_pairs, out, nullptr, [](auto&&...) {});
        return out;
    }
    volume_best_first(a, b, to_a, request, out, [](std::uint32_t, std::uint32_t, double) {});
    return out;
}

IstDistanceResult sphere_distance(const InnerSphereTree& a, const Transform<double>& pose_a, const InnerSphereTree& b,
                                  const Transform<double>& pose_b, const IstRequest& request) {
    IstDistanceResult out;
    const std::optional<Frame> frame = query_frame(a, pose_a, b, pose_b, out.status);
    if (!frame) return out;
    const Frame& to_a = *frame;
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
            sphere_witness(x, y, to_a(y.center), pa, pb);
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

namespace {

/// The combined query with a node budget, in one pass over one budget: the best-first volume traversal
/// (volume_best_first(), so the volume part is penetration_volume()'s with the same budget) keeps the pairs
/// whose bounding spheres are apart while no inner spheres overlap; if it ends without an overlap, the
/// distance search goes on from them, best first, with what is left of the budget.
void ist_query_budget(const InnerSphereTree& a, const Transform<double>& pose_a, const InnerSphereTree& b, const Frame& to_a,
                      const IstRequest& request, IstQueryResult& out) {
    const auto& na = a.nodes();
    const auto& nb = b.nodes();
    std::vector<PairKey> far;  // pairs apart, keyed by their distance bound
    // Bounds formed as sphere_distance() forms them (Eigen's norm() is the root of squaredNorm()).
    volume_best_first(a, b, to_a, request, out.volume, [&](std::uint32_t ia, std::uint32_t ib, double d2) {
        far.push_back({ia, ib, std::sqrt(d2) - na[ia].radius - nb[ib].radius});
    });
    out.stats = out.volume.stats;
    out.colliding = out.volume.volume_lower > 0;
    if (out.colliding) {
        out.distance.distance = out.distance.lower_bound = 0;
        out.distance.stats = out.stats;
        return;
    }
    double best = std::numeric_limits<double>::infinity();
    // Pairs of overlapping bounding spheres left unexpanded by the volume traversal bound the distance by 0.
    double unexplored = out.volume.complete ? std::numeric_limits<double>::infinity() : 0.0;
    Vec3d pa = Vec3d::Zero(), pb = Vec3d::Zero();
    auto farther = [](const PairKey& l, const PairKey& r) { return l.key > r.key; };
    std::make_heap(far.begin(), far.end(), farther);
    while (!far.empty() && far.front().key < best) {
        if (out.stats.node_tests >= request.max_node_tests) {
            unexplored = std::min(unexplored, far.front().key);
            break;
        }
        std::pop_heap(far.begin(), far.end(), farther);
        const PairKey it = far.back();
        far.pop_back();
        const IstNode& x = na[it.a];
        const IstNode& y = nb[it.b];
        const Vec3d cy = to_a(y.center);
        if (x.is_leaf() && y.is_leaf()) {
            ++out.stats.leaf_pairs;
            best = it.key;
            sphere_witness(x, y, cy, pa, pb);
            out.distance.sphere_a = x.first;
            out.distance.sphere_b = y.first;
            continue;
        }
        auto child = [&](std::uint32_t ia, std::uint32_t ib, const IstNode& cx, const IstNode& cn, const Vec3d& c) {
            ++out.stats.node_tests;
            const double lb = (cx.center - c).norm() - cx.radius - cn.radius;
            if (lb < best) far.push_back({ia, ib, lb}), std::push_heap(far.begin(), far.end(), farther);
        };
        if (split_a(x, y)) {
            for (std::uint32_t j = x.first; j < x.first + x.count; ++j) child(j, it.b, na[j], y, cy);
        } else {
            for (std::uint32_t j = y.first; j < y.first + y.count; ++j) child(it.a, j, x, nb[j], to_a(nb[j].center));
        }
    }
    out.distance.complete = !(unexplored < best);
    if (best <= 0) pa = pb = (pa + pb) / 2;
    out.distance.distance = std::max(0.0, best);
    out.distance.lower_bound = std::max(0.0, std::min(best, unexplored));
    out.distance.point_a = pose_a * pa;
    out.distance.point_b = pose_a * pb;
    out.distance.stats = out.stats;
}

}  // namespace

IstQueryResult ist_query(const InnerSphereTree& a, const Transform<double>& pose_a, const InnerSphereTree& b,
                         const Transform<double>& pose_b, const IstRequest& request) {
    IstQueryResult out;
    const std::optional<Frame> frame = query_frame(a, pose_a, b, pose_b, out.status);
    if (!frame) {
        out.volume.status = out.distance.status = out.status;
        return out;
    }
    const Frame& to_a = *frame;
    if (request.max_node_tests != 0) {
        ist_query_budget(a, pose_a, b, to_a, request, out);
        return out;
    }
    const auto& na = a.nodes();
    const auto& nb = b.nodes();

    // One descent, every node pair tested at most once. A pair is on the volume path while its bounding
    // spheres and all its ancestors' overlap: those pairs are visited first, by penetration_volume()'s own
    // traversal (volume_descent), so volume, calibrated volume and pairs are bit for bit the same. While no
    // inner spheres overlap, the children that leave the volume path are kept as a frontier; the first
    // overlapping inner-sphere pair makes the distance 0 and drops it. If the volume path ends without an
    // overlap, the distance search goes on from that frontier, best first, with the best inner-sphere
    // distance the path's leaves gave (sphere_distance()'s bound), instead of starting again from the roots.
    using Item = PairKey;
    auto bound = [&](const IstNode& x, const IstNode& y, const Vec3d& cy) { return (x.center - cy).norm() - x.radius - y.radius; };
    double best = std::numeric_limits<double>::infinity();
    Vec3d pa = Vec3d::Zero(), pb = Vec3d::Zero();
    auto leaf = [&](const IstNode& x, const IstNode& y, const Vec3d& cy, double lb) {
        if (!(lb < best)) return;
        best = lb;
        sphere_witness(x, y, cy, pa, pb);
        out.distance.sphere_a = x.first;
        out.distance.sphere_b = y.first;
    };
    std::vector<Item> far;  // the distance frontier
    volume_descent<true>(a, b, to_a, request.collect_pairs, out.volume, &far, leaf);
    out.stats = out.volume.stats;
    const double exact = out.volume.volume;
    if (exact == 0) {
        // Distance search from the frontier, best first (a min-heap on the bound). The frontier holds
        // |c_a − c_b|²; the bound is formed as bound() forms it, so the distances are bit for bit sphere_distance()'s.
        for (Item& f : far) f.key = std::sqrt(f.key) - na[f.a].radius - nb[f.b].radius;
        auto farther = [](const Item& l, const Item& r) { return l.key > r.key; };
        std::make_heap(far.begin(), far.end(), farther);
        while (!far.empty() && best > 0) {
            std::pop_heap(far.begin(), far.end(), farther);
            const Item it = far.back();
            far.pop_back();
            if (!(it.key < best)) break;  // every other bound is larger
            const IstNode& x = na[it.a];
            const IstNode& y = nb[it.b];
            if (x.is_leaf() && y.is_leaf()) {
                ++out.stats.leaf_pairs;
                leaf(x, y, to_a(y.center), it.key);
                continue;
            }
            const Vec3d cy = to_a(y.center);
            auto child = [&](std::uint32_t ia, std::uint32_t ib, const IstNode& cx, const IstNode& cn, const Vec3d& c) {
                ++out.stats.node_tests;
                const double lb = bound(cx, cn, c);
                if (lb < best) far.push_back({ia, ib, lb}), std::push_heap(far.begin(), far.end(), farther);
            };
            if (split_a(x, y)) {
                for (std::uint32_t j = x.first; j < x.first + x.count; ++j) child(j, it.b, na[j], y, cy);
            } else {
                for (std::uint32_t j = y.first; j < y.first + y.count; ++j) child(it.a, j, x, nb[j], to_a(nb[j].center));
            }
        }
    }

    out.volume.stats = out.stats;
    out.colliding = exact > 0;
    if (out.colliding) {
        out.distance.distance = out.distance.lower_bound = 0;
        out.distance.sphere_a = out.distance.sphere_b = 0;
        return out;
    }
    if (best <= 0) pa = pb = (pa + pb) / 2;
    out.distance.distance = out.distance.lower_bound = std::max(0.0, best);
    out.distance.point_a = pose_a * pa;
    out.distance.point_b = pose_a * pb;
    out.distance.stats = out.stats;
    return out;
}

}  // namespace cdkit
