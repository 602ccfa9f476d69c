#pragma once
// An all-pairs reference for mesh–mesh collide and distance at any size, sharing no code with cdkit's trees: B's
// triangles carried into A's frame the way the queries carry them, a uniform grid over the triangles' boxes, every
// candidate pair tested — the exact-predicate triangle test for intersections (itself judged against CGAL in
// tests/narrowphase), and this file's own point–triangle and segment–segment distances for separation. Used by
// tests/query/test_dragon_scale.cpp and cdkit_bench_distance (its brute-force column on every mesh).
#include "cdkit/core/math.hpp"
#include "cdkit/core/mesh.hpp"
#include "cdkit/narrowphase/triangle.hpp"
#include "cdkit/query.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace cdkit::test::grid {

using V = Vec3<double>;
using Pairs = std::vector<std::pair<Index, Index>>;

struct Box {
    V lo, hi;
};
inline Box box_of(const V& a, const V& b, const V& c) { return {a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)}; }
inline bool boxes_within(const Box& a, const Box& b, double d) {
    return (a.lo.array() <= b.hi.array() + d).all() && (b.lo.array() <= a.hi.array() + d).all();
}

// Runs body(i) for i in [0, n) on every core; body must be thread-safe.
template <class F> void parallel_for(std::size_t n, F body) {
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t)
        pool.emplace_back([&] {
            for (std::size_t i; (i = next.fetch_add(256)) < n;)
                for (std::size_t j = i; j < std::min(n, i + 256); ++j) body(j);
        });
    for (auto& th : pool) th.join();
}

// Triangles of A (its own frame) and of B carried into A's frame the way the queries carry them.
struct PosedPair {
    std::vector<std::array<V, 3>> ta, tb;
    std::vector<Box> ba, bb;
};
inline PosedPair posed(const TriangleMesh<double>& ma, const Transform<double>& pa, const TriangleMesh<double>& mb,
                        const Transform<double>& pb) {
    const Transform<double> b_to_a = pa.inverse() * pb;
    PosedPair p;
    p.ta.resize(ma.num_triangles()), p.ba.resize(ma.num_triangles());
    p.tb.resize(mb.num_triangles()), p.bb.resize(mb.num_triangles());
    parallel_for(ma.num_triangles(), [&](std::size_t i) {
        for (int k = 0; k < 3; ++k) p.ta[i][k] = ma.vertices[ma.triangles[i][k]];
        p.ba[i] = box_of(p.ta[i][0], p.ta[i][1], p.ta[i][2]);
    });
    parallel_for(mb.num_triangles(), [&](std::size_t i) {
        for (int k = 0; k < 3; ++k) p.tb[i][k] = detail::to_frame_a(b_to_a, mb.vertices[mb.triangles[i][k]]);
        p.bb[i] = box_of(p.tb[i][0], p.tb[i][1], p.tb[i][2]);
    });
    return p;
}

// Every pair (i of A, j of B) whose boxes lie within `reach` of each other, through a uniform grid over the
// region both sets can meet in; `visit(i, j)` is called once per such pair, from several threads.
template <class Visit> void grid_pairs(const PosedPair& p, double reach, Visit visit) {
    Box all_a{V::Constant(1e300), V::Constant(-1e300)}, all_b = all_a;
    for (const Box& b : p.ba) all_a = {all_a.lo.cwiseMin(b.lo), all_a.hi.cwiseMax(b.hi)};
    for (const Box& b : p.bb) all_b = {all_b.lo.cwiseMin(b.lo), all_b.hi.cwiseMax(b.hi)};
    const Box region{all_a.lo.cwiseMax(all_b.lo - V::Constant(reach)), all_a.hi.cwiseMin(all_b.hi + V::Constant(reach))};
    if (!(region.lo.array() <= region.hi.array()).all()) return;
    std::vector<Index> in_a, in_b;
    for (Index i = 0; i < Index(p.ba.size()); ++i)
        if (boxes_within(p.ba[i], region, reach)) in_a.push_back(i);
    for (Index j = 0; j < Index(p.bb.size()); ++j)
        if (boxes_within(p.bb[j], region, reach)) in_b.push_back(j);
    if (in_a.empty() || in_b.empty()) return;
    // Cells about as many as B's candidates, at least the reach wide (so a pair within reach shares a cell of
    // B's grown box and A's box).
    const V ext = (region.hi - region.lo).cwiseMax(V::Constant(1e-12));
    const double cell = std::max(reach, std::cbrt(ext.prod() / double(in_b.size())));
    const Eigen::Array3i dims = ((ext / cell).array().floor().cast<int>() + 1).min(1024);
    auto cell_of = [&](const V& x) {
        return ((x - region.lo).array() / cell).floor().cast<int>().max(0).min(dims - 1).eval();
    };
    auto flat = [&](int x, int y, int z) { return (std::size_t(z) * dims.y() + y) * dims.x() + x; };
    std::vector<std::vector<Index>> cells(std::size_t(dims.prod()));
    for (Index j : in_b) {
        const auto lo = cell_of(p.bb[j].lo - V::Constant(reach)), hi = cell_of(p.bb[j].hi + V::Constant(reach));
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x) cells[flat(x, y, z)].push_back(j);
    }
    parallel_for(in_a.size(), [&](std::size_t k) {
        const Index i = in_a[k];
        const auto lo = cell_of(p.ba[i].lo), hi = cell_of(p.ba[i].hi);
        std::vector<Index> seen;
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x)
                    for (Index j : cells[flat(x, y, z)]) seen.push_back(j);
        std::sort(seen.begin(), seen.end());
        seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
        for (Index j : seen)
            if (boxes_within(p.ba[i], p.bb[j], reach)) visit(i, j);
    });
}

inline Pairs grid_intersecting_pairs(const PosedPair& p) {
    Pairs out;
    std::mutex m;
    grid_pairs(p, 0.0, [&](Index i, Index j) {
        const auto& a = p.ta[i];
        const auto& b = p.tb[j];
        if (!triangles_intersect(a[0], a[1], a[2], b[0], b[1], b[2])) return;
        const std::lock_guard<std::mutex> lock(m);
        out.emplace_back(i, j);
    });
    std::sort(out.begin(), out.end());
    return out;
}

inline double point_segment(const V& x, const V& a, const V& b) {
    const V d = b - a;
    const double dd = d.squaredNorm();
    const double t = dd > 0 ? std::clamp((x - a).dot(d) / dd, 0.0, 1.0) : 0.0;
    return (a + t * d - x).norm();
}
inline double point_triangle(const V& x, const std::array<V, 3>& t) {
    double best = std::min({point_segment(x, t[0], t[1]), point_segment(x, t[1], t[2]), point_segment(x, t[2], t[0])});
    const V n = (t[1] - t[0]).cross(t[2] - t[0]);
    const double nn = n.squaredNorm();
    if (nn > 0) {
        const V q = x - n * (n.dot(x - t[0]) / nn);
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside = inside && n.dot((t[(k + 1) % 3] - t[k]).cross(q - t[k])) >= 0;
        if (inside) best = std::min(best, (x - q).norm());
    }
    return best;
}
// Segments pq and rs: the unconstrained closest pair when it lies inside both, else an endpoint case.
inline double segment_segment(const V& p, const V& q, const V& r, const V& s) {
    double best = std::min({point_segment(p, r, s), point_segment(q, r, s), point_segment(r, p, q), point_segment(s, p, q)});
    const V d1 = q - p, d2 = s - r, w = p - r;
    const double a = d1.dot(d1), b = d1.dot(d2), c = d2.dot(d2), d = d1.dot(w), e = d2.dot(w);
    const double den = a * c - b * b;
    if (den > 1e-14 * a * c) {
        const double u = (b * e - c * d) / den, v = (a * e - b * d) / den;
        if (u > 0 && u < 1 && v > 0 && v < 1) best = std::min(best, (p + u * d1 - (r + v * d2)).norm());
    }
    return best;
}
// Distance of two disjoint triangles: a vertex against the other triangle, or two edges.
inline double triangle_gap(const std::array<V, 3>& a, const std::array<V, 3>& b) {
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) best = std::min({best, point_triangle(a[k], b), point_triangle(b[k], a)});
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) best = std::min(best, segment_segment(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]));
    return best;
}

/// The smallest distance between a triangle of A and one of B among the pairs whose boxes lie within `within`
/// (+inf when none does): the meshes' distance whenever it is at most `within`. Meant for disjoint meshes.
inline double grid_distance(const PosedPair& p, double within) {
    std::mutex m;
    double best = std::numeric_limits<double>::infinity();
    grid_pairs(p, within, [&](Index i, Index j) {
        const double g = triangle_gap(p.ta[i], p.tb[j]);
        const std::lock_guard<std::mutex> lock(m);
        best = std::min(best, g);
    });
    return best;
}

}  // namespace cdkit::test::grid
