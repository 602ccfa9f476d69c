#pragma once
/// \file Continuous collision of two rigid meshes, each moving from one pose to another over the step, on the
/// trees they already have (any BV of the family; nothing is rebuilt per step).
///
/// Motion: every vertex v of A moves linearly from a_start·v to a_end·v (and B's likewise) — the convention of the
/// public CCD benchmark, under which the primitive tests are exact; a rotation is then approximated by the chord of
/// each vertex's arc (for large rotations per step, split the step). Broad phase: simultaneous descent of the two
/// trees, where a node stands for the world box of its BV at both poses; since each vertex moves linearly, the
/// node's triangles are at time t inside the box whose corners are the lerp of those two boxes' corners, so two
/// nodes can only meet in the window of t where their lerped boxes overlap (six linear inequalities). Pairs go
/// through a queue ordered by the window's start. At two leaves, each triangle pair whose window is not empty
/// gives its 6 vertex–face and 9 edge–edge feature pairs to vertex_face_ccd / edge_edge_ccd, which never miss a
/// contact. In ContactMode::first each feature pair only searches up to the earliest contact found so far, and
/// the descent stops once every pair left starts after it.
/// Thread safety: const and reentrant (the models are only read).

#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/bvh/traverse.hpp"
#include "cdkit/ccd/deformable_ccd.hpp"
#include "cdkit/ccd/detail/swept_node_box.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace cdkit {

namespace detail {

/// A vertex of a rigid mesh at a pose: computed the same way by the tree query and by the brute-force check.
[[nodiscard]] inline Vec3<double> posed_vertex(const Transform<double>& pose, const Vec3<double>& v) noexcept {
    return pose.R * v + pose.t;
}

/// Triangle t of mesh m at a pose, vertex by vertex as posed_vertex places them.
[[nodiscard]] inline std::array<Vec3<double>, 3> posed_triangle(const TriangleMesh<double>& m, Index t,
                                                                const Transform<double>& pose) noexcept {
    const Triangle& tri = m.triangles[t];
    return {posed_vertex(pose, m.vertices[tri[0]]), posed_vertex(pose, m.vertices[tri[1]]),
            posed_vertex(pose, m.vertices[tri[2]])};
}

/// A box that moves over the step: every point of the feature it bounds is in `at0` at t = 0 and in `at1` at t = 1,
/// and moves linearly between, so at time t it lies in the box whose corners are the lerp of the two boxes'.
struct MovingBox {
    BroadBox<double> at0, at1;
};

/// The times in [lo, hi] at which two moving boxes can overlap (each axis gives two linear inequalities in t), or
/// an empty window (lo > hi). Rounding is covered by a slack relative to the coordinates.
[[nodiscard]] inline std::pair<double, double> overlap_window(const MovingBox& x, const MovingBox& y, double lo,
                                                              double hi) noexcept {
    for (int k = 0; k < 3 && lo <= hi; ++k) {
        // x.lo(t) − y.hi(t) ≤ 0 and y.lo(t) − x.hi(t) ≤ 0, each α + β·t ≤ 0.
        const double f0[2] = {x.at0.lo[k] - y.at0.hi[k], y.at0.lo[k] - x.at0.hi[k]};
        const double f1[2] = {x.at1.lo[k] - y.at1.hi[k], y.at1.lo[k] - x.at1.hi[k]};
        const double mag = std::abs(x.at0.lo[k]) + std::abs(x.at0.hi[k]) + std::abs(y.at0.lo[k]) + std::abs(y.at0.hi[k]) +
                           std::abs(x.at1.lo[k]) + std::abs(x.at1.hi[k]) + std::abs(y.at1.lo[k]) + std::abs(y.at1.hi[k]);
        const double slack = 8 * std::numeric_limits<double>::epsilon() * mag;
        for (int i = 0; i < 2; ++i) {
            const double a = f0[i] - slack, b = f1[i] - slack;  // f(t) = (1 − t)·a + t·b ≤ 0, loosened
            if (a <= 0 && b <= 0) continue;
            if (a > 0 && b > 0) return {1, 0};
            const double root = a / (a - b);  // where f crosses 0
            const double pad = 1e-9 + 4 * std::numeric_limits<double>::epsilon();
            if (a > 0) lo = std::max(lo, root - pad);  // f ≤ 0 after the root
            else hi = std::min(hi, root + pad);        // f ≤ 0 before it
        }
    }
    return {lo, hi};
}

/// Tests the 15 feature pairs of triangle ta of A and tb of B; `limit` is the search's end time (ContactMode::first
/// lowers it as contacts are found). Contacts are appended to `found`.
inline void triangle_pair_ccd(const TriangleMesh<double>& ma, Index ta, const std::array<Vec3<double>, 3>& a0,
                              const std::array<Vec3<double>, 3>& a1, const TriangleMesh<double>& mb, Index tb,
                              const std::array<Vec3<double>, 3>& b0, const std::array<Vec3<double>, 3>& b1,
                              const CcdRequest& base, double& limit, bool first, std::vector<CcdContact>& found,
                              DeformableCcdStats& stats) {
    CcdRequest req = base;
    auto keep = [&](const CcdResult& r, CcdContact c) {
        stats.capped += r.stats.capped;
        if (!r.colliding) return;
        c.ccd = r;
        found.push_back(c);
        if (first) limit = std::min(limit, r.toi_upper);
    };
    for (int k = 0; k < 3; ++k) {
        req.t_max = limit;
        ++stats.vertex_face_candidates;
        keep(vertex_face_ccd(a0[k], b0[0], b0[1], b0[2], a1[k], b1[0], b1[1], b1[2], req),
             {true, ma.triangles[ta][k], tb, {}, false});
        req.t_max = limit;
        ++stats.vertex_face_candidates;
        keep(vertex_face_ccd(b0[k], a0[0], a0[1], a0[2], b1[k], a1[0], a1[1], a1[2], req),
             {true, mb.triangles[tb][k], ta, {}, true});
    }
    for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) {
            req.t_max = limit;
            ++stats.edge_edge_candidates;
            const int k1 = (k + 1) % 3, l1 = (l + 1) % 3;
            keep(edge_edge_ccd(a0[k], a0[k1], b0[l], b0[l1], a1[k], a1[k1], b1[l], b1[l1], req),
                 {false, 3 * ta + Index(k), 3 * tb + Index(l), {}, false});
        }
}

/// The same feature pair reached through another triangle pair (a vertex lies in several triangles, an edge in
/// two): one key per pair, so that ContactMode::all reports each once.
[[nodiscard]] inline std::array<Index, 5> feature_key(const CcdContact& c, const TriangleMesh<double>& ma,
                                                      const TriangleMesh<double>& mb) noexcept {
    if (c.vertex_face) return {0, Index(c.vertex_on_b), c.a, c.b, 0};
    const Triangle& ta = ma.triangles[c.a / 3];
    const Triangle& tb = mb.triangles[c.b / 3];
    const Index a0 = ta[c.a % 3], a1 = ta[(c.a % 3 + 1) % 3], b0 = tb[c.b % 3], b1 = tb[(c.b % 3 + 1) % 3];
    return {1, std::min(a0, a1), std::max(a0, a1), std::min(b0, b1), std::max(b0, b1)};
}

/// The earliest contact first; ContactMode::all: one contact per feature pair.
inline void finish_mesh_ccd(DeformableCcdResult& out, std::vector<CcdContact>& found, ContactMode mode,
                            double t_max, const TriangleMesh<double>& ma, const TriangleMesh<double>& mb) {
    out.toi = t_max;
    for (const CcdContact& c : found) out.toi = std::min(out.toi, c.ccd.toi);
    out.colliding = !found.empty();
    if (mode == ContactMode::first) {
        if (!found.empty())
            out.contacts.assign(1, *std::min_element(found.begin(), found.end(), [](const auto& x, const auto& y) {
                return x.ccd.toi < y.ccd.toi;
            }));
        return;
    }
    std::vector<std::pair<std::array<Index, 5>, std::size_t>> keys;
    for (std::size_t i = 0; i < found.size(); ++i) keys.push_back({feature_key(found[i], ma, mb), i});
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 0; i < keys.size(); ++i)
        if (i == 0 || keys[i].first != keys[i - 1].first) out.contacts.push_back(found[keys[i].second]);
}

}  // namespace detail

/// First contact (or every contact) of meshes A and B while A moves from pose a_start to a_end and B from b_start
/// to b_end (vertices linear in t between their posed positions). Contacts: vertex_face with vertex_on_b false is
/// vertex `a` of A against triangle `b` of B, with vertex_on_b true vertex `a` of B against triangle `b` of A;
/// edge_edge pairs give edge k of triangle t as 3·t + k (A's in `a`, B's in `b`), its vertices t[k] and t[(k+1)%3].
/// A pose that is not a rigid motion gives status invalid_pose; unusable request settings invalid_input.
template <class BV>
[[nodiscard]] DeformableCcdResult mesh_ccd(const MeshModel<BV, double>& a, const Transform<double>& a_start,
                                           const Transform<double>& a_end, const MeshModel<BV, double>& b,
                                           const Transform<double>& b_start, const Transform<double>& b_end,
                                           const DeformableCcdRequest& request = {}) {
    DeformableCcdResult out;
    if (!detail::motion_poses_usable({&a_start, &a_end, &b_start, &b_end})) {
        out.status = QueryStatus::invalid_pose;
        return out;
    }
    if (!detail::ccd_request_is_valid(request.primitive)) {
        out.status = QueryStatus::invalid_input;
        return out;
    }
    const auto& ma = a.mesh();
    const auto& mb = b.mesh();
    const auto& na = a.bvh().nodes();
    const auto& nb = b.bvh().nodes();
    std::vector<CcdContact> found;
    if (na.empty() || nb.empty()) return out;
    const bool first = request.mode == ContactMode::first;
    double limit = request.primitive.t_max;
    const double grow = request.primitive.min_separation;
    auto grown = [grow](BroadBox<double> box) {
        box.lo.array() -= grow * (1 + 1e-12);
        box.hi.array() += grow * (1 + 1e-12);
        return box;
    };
    auto points_box = [](const std::array<Vec3<double>, 3>& p) {
        BroadBox<double> box{p[0], p[0]};
        for (const auto& v : p) box.lo = box.lo.cwiseMin(v), box.hi = box.hi.cwiseMax(v);
        return box;
    };
    auto node_box = [&](const auto& bv, const Transform<double>& s, const Transform<double>& e, bool is_a) {
        detail::MovingBox m{detail::world_box(bv, s), detail::world_box(bv, e)};
        if (is_a) m.at0 = grown(m.at0), m.at1 = grown(m.at1);
        return m;
    };
    const auto& order_a = a.bvh().triangle_order();
    const auto& order_b = b.bvh().triangle_order();
    // Node pairs in order of the earliest time their boxes can meet, so that ContactMode::first stops as soon as
    // every pair left starts after the earliest contact found.
    struct Pair {
        std::uint32_t a, b;
        double t_in, t_out;
    };
    auto later = [](const Pair& x, const Pair& y) { return x.t_in > y.t_in; };
    std::vector<Pair> heap;
    auto consider = [&](std::uint32_t ia, std::uint32_t ib) {
        const auto w = detail::overlap_window(node_box(na[ia].bv, a_start, a_end, true),
                                              node_box(nb[ib].bv, b_start, b_end, false), 0.0, limit);
        if (w.first > w.second) return;
        heap.push_back({ia, ib, w.first, w.second});
        std::push_heap(heap.begin(), heap.end(), later);
    };
    consider(0, 0);
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), later);
        const Pair p = heap.back();
        heap.pop_back();
        if (p.t_in > limit) {
            if (first) break;  // every pair left starts later: none can hold the first contact
            continue;
        }
        const BvhNode<BV>& x = na[p.a];
        const BvhNode<BV>& y = nb[p.b];
        const bool xl = x.is_leaf(), yl = y.is_leaf();
        if (xl && yl) {
            for (std::uint32_t i = x.first; i < x.first + x.count; ++i) {
                const Index ta = order_a[i];
                const auto a0 = detail::posed_triangle(ma, ta, a_start);
                const auto a1 = detail::posed_triangle(ma, ta, a_end);
                const detail::MovingBox boxa{grown(points_box(a0)), grown(points_box(a1))};
                for (std::uint32_t j = y.first; j < y.first + y.count; ++j) {
                    const Index tb = order_b[j];
                    const auto b0 = detail::posed_triangle(mb, tb, b_start);
                    const auto b1 = detail::posed_triangle(mb, tb, b_end);
                    const auto w = detail::overlap_window(boxa, {points_box(b0), points_box(b1)}, 0.0, limit);
                    if (w.first > w.second) continue;
                    detail::triangle_pair_ccd(ma, ta, a0, a1, mb, tb, b0, b1, request.primitive, limit, first, found,
                                              out.stats);
                }
            }
            continue;
        }
        const double sx = x.bv.size(), sy = y.bv.size();
        if (yl || (!xl && sx >= sy)) {
            consider(x.first, p.b);
            consider(x.first + 1, p.b);
        } else {
            consider(p.a, y.first);
            consider(p.a, y.first + 1);
        }
    }
    detail::finish_mesh_ccd(out, found, request.mode, request.primitive.t_max, ma, mb);
    return out;
}

/// The same answer by testing every feature pair of the two meshes: the reference the tree query is checked
/// against, O(|A|·|B|).
[[nodiscard]] inline DeformableCcdResult mesh_ccd_brute_force(const TriangleMesh<double>& ma,
                                                              const Transform<double>& a_start,
                                                              const Transform<double>& a_end,
                                                              const TriangleMesh<double>& mb,
                                                              const Transform<double>& b_start,
                                                              const Transform<double>& b_end,
                                                              const DeformableCcdRequest& request = {}) {
    DeformableCcdResult out;
    std::vector<CcdContact> found;
    double limit = request.primitive.t_max;
    const bool first = request.mode == ContactMode::first;
    for (Index ta = 0; ta < ma.triangles.size(); ++ta) {
        const auto a0 = detail::posed_triangle(ma, ta, a_start);
        const auto a1 = detail::posed_triangle(ma, ta, a_end);
        for (Index tb = 0; tb < mb.triangles.size(); ++tb)
            detail::triangle_pair_ccd(ma, ta, a0, a1, mb, tb, detail::posed_triangle(mb, tb, b_start),
                                      detail::posed_triangle(mb, tb, b_end),
                                      request.primitive, limit, first, found, out.stats);
    }
    detail::finish_mesh_ccd(out, found, request.mode, request.primitive.t_max, ma, mb);
    return out;
}

}  // namespace cdkit
