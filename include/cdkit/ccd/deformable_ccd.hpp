#pragma once
/// \file Continuous self-collision of a deforming triangle mesh (cloth, soft bodies, a whole scene in one mesh):
/// every vertex moves linearly from its position at the step's start to the one at its end, and the query finds
/// the vertex–face and edge–edge pairs that touch during the step, or the earliest of them.
///
/// Broad phase: each feature's swept box (the box of its vertices at both ends of the step: linear motion keeps a
/// point in it) in a dynamic AABB tree, faces in one, edges in another; every vertex box is queried against the
/// faces, every edge box against the edges. Pairs that share a vertex are no candidates (a triangle always
/// "touches" its neighbours). Narrow phase: vertex_face_ccd / edge_edge_ccd, which never miss a contact; in
/// ContactMode::first each candidate only searches up to the earliest contact found so far. This is the
/// structure of the "Scalable CCD" pipeline (Belgrod, Ferguson, Schneider, Panozzo et al., 2023: sweep over
/// swept boxes, then a conservative narrow phase), with cdkit's tree as the broad phase.
/// Thread safety: the function is reentrant; with TBB both phases run in parallel.

#include "cdkit/broadphase/dynamic_aabb_tree.hpp"
#include "cdkit/ccd/edge_edge.hpp"
#include "cdkit/ccd/vertex_face.hpp"
#include "cdkit/core/contact_mode.hpp"
#include "cdkit/core/error.hpp"
#include "cdkit/core/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#if defined(CDKIT_HAS_TBB)
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#endif

namespace cdkit {

using Edge = std::array<Index, 2>;

/// The mesh's undirected edges, each once as (lower index, higher index), ordered by (higher, lower) — the order
/// libigl's `edges()` gives, which is how the public CCD data numbers edges.
[[nodiscard]] inline std::vector<Edge> mesh_edges(const std::vector<Triangle>& triangles) {
    std::vector<Edge> e;
    e.reserve(triangles.size() * 3);
    for (const Triangle& t : triangles)
        for (int k = 0; k < 3; ++k) {
            const Index a = t[k], b = t[(k + 1) % 3];
            if (a != b) e.push_back({std::min(a, b), std::max(a, b)});
        }
    std::sort(e.begin(), e.end(), [](const Edge& x, const Edge& y) { return x[1] != y[1] ? x[1] < y[1] : x[0] < y[0]; });
    e.erase(std::unique(e.begin(), e.end()), e.end());
    return e;
}

struct DeformableCcdRequest {
    ContactMode mode = ContactMode::first;  ///< first: the earliest contact; all: every colliding feature pair
    CcdRequest primitive;                   ///< per pair: tolerance, minimum separation, work cap
    bool parallel = true;                   ///< use TBB where the library was built with it
};

/// One colliding feature pair: vertex `a` against face `b` (a triangle index), or edge `a` against edge `b`
/// (self_ccd: indices into mesh_edges(); mesh_ccd numbers them per triangle, see there).
struct CcdContact {
    bool vertex_face = true;
    Index a = 0, b = 0;
    CcdResult ccd;
    bool vertex_on_b = false;  ///< mesh_ccd: the vertex is B's and the face A's
};

struct DeformableCcdStats {
    std::size_t vertex_face_candidates = 0, edge_edge_candidates = 0;  ///< pairs whose swept boxes overlap
    std::size_t capped = 0;  ///< candidates whose primitive query reached its work cap (conservative answers)
};

struct DeformableCcdResult {
    QueryStatus status = QueryStatus::ok;
    bool colliding = false;
    double toi = 1;  ///< certified lower bound of the first contact over all pairs (1 when none)
    /// mode first: the pair that gave `toi` (one entry); mode all: every colliding pair, in no particular order.
    std::vector<CcdContact> contacts;
    DeformableCcdStats stats;
};

namespace detail {

/// Box of a feature's vertices at both ends of the step, grown outward by `grow` (the minimum separation).
template <std::size_t N>
[[nodiscard]] BroadBox<double> swept_box(const std::vector<Vec3<double>>& x0, const std::vector<Vec3<double>>& x1,
                                         const std::array<Index, N>& ids, double grow) noexcept {
    BroadBox<double> b{x0[ids[0]], x0[ids[0]]};
    for (Index i : ids)
        for (const auto* x : {&x0, &x1}) {
            b.lo = b.lo.cwiseMin((*x)[i]);
            b.hi = b.hi.cwiseMax((*x)[i]);
        }
    if (grow > 0) {
        const double g = grow * (1 + 4 * std::numeric_limits<double>::epsilon());
        for (int k = 0; k < 3; ++k) {
            b.lo[k] = std::nextafter(b.lo[k] - g, -std::numeric_limits<double>::infinity());
            b.hi[k] = std::nextafter(b.hi[k] + g, std::numeric_limits<double>::infinity());
        }
    }
    return b;
}

template <class F> void for_range(std::size_t n, bool parallel, F&& body) {
#if defined(CDKIT_HAS_TBB)
    if (parallel && n > 1024) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256),
                          [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
        return;
    }
#endif
    (void)parallel;
    body(std::size_t(0), n);
}

}  // namespace detail

/// Continuous self-collision of a mesh whose vertex i moves linearly from start[i] to end[i] over the step.
/// Throws cdkit::Error when the inputs disagree (vertex counts, an index out of range) or a coordinate is not
/// finite; `source` names the mesh in the message. Degenerate triangles are allowed (their features are tested).
[[nodiscard]] inline DeformableCcdResult self_ccd(const std::vector<Vec3<double>>& start,
                                                  const std::vector<Vec3<double>>& end,
                                                  const std::vector<Triangle>& triangles,
                                                  const DeformableCcdRequest& request = {},
                                                  const std::string& source = "<mesh>") {
    if (start.size() != end.size())
        throw Error(source, "vertices", std::to_string(start.size()) + " vertices at the step's start but " +
                                            std::to_string(end.size()) + " at its end");
    for (std::size_t i = 0; i < start.size(); ++i)
        if (!start[i].allFinite() || !end[i].allFinite())
            throw Error(source, "vertex " + std::to_string(i),
                        std::string("not finite at the step's ") + (start[i].allFinite() ? "end" : "start"));
    for (std::size_t f = 0; f < triangles.size(); ++f)
        for (Index v : triangles[f])
            if (v >= start.size())
                throw Error(source, "triangle " + std::to_string(f),
                            "uses vertex " + std::to_string(v) + " of " + std::to_string(start.size()));
    DeformableCcdResult out;
    if (!detail::ccd_request_is_valid(request.primitive)) {
        out.status = QueryStatus::invalid_input;
        return out;
    }
    const std::vector<Edge> edges = mesh_edges(triangles);
    const double grow = request.primitive.min_separation;
    DynamicAabbTree<double> faces(typename DynamicAabbTree<double>::Options{0, 0});
    DynamicAabbTree<double> edge_tree(typename DynamicAabbTree<double>::Options{0, 0});
    // A fresh tree hands out ids 0, 1, 2, … in insertion order: object id = triangle (edge) index.
    for (const Triangle& t : triangles) (void)faces.insert(detail::swept_box(start, end, t, grow));
    for (const Edge& e : edges) (void)edge_tree.insert(detail::swept_box(start, end, e, grow));
    faces.rebuild();
    edge_tree.rebuild();

    // Candidates, then the primitive queries; per chunk into local lists, merged under a lock.
    std::mutex merge;
    double best = request.primitive.t_max;  // ContactMode::first: only contacts before this matter
    auto record = [&](std::vector<CcdContact>& found, std::size_t vf, std::size_t ee, std::size_t capped) {
        std::lock_guard<std::mutex> lock(merge);
        out.stats.vertex_face_candidates += vf;
        out.stats.edge_edge_candidates += ee;
        out.stats.capped += capped;
        for (CcdContact& c : found) {
            if (request.mode == ContactMode::all) {
                out.contacts.push_back(c);
            } else {
                if (out.contacts.empty() || c.ccd.toi < out.contacts[0].ccd.toi) out.contacts.assign(1, c);
                best = std::min(best, c.ccd.toi_upper);  // a contact exists by then: later ones cannot be first
            }
        }
    };
    auto current_limit = [&] {
        std::lock_guard<std::mutex> lock(merge);
        return best;
    };
    auto run = [&](bool vertex_face, Index a, Index b, std::vector<CcdContact>& found, std::size_t& capped,
                   double t_max) {
        CcdRequest req = request.primitive;
        req.t_max = std::min(req.t_max, t_max);
        CcdResult r;
        if (vertex_face) {
            const Triangle& t = triangles[b];
            r = vertex_face_ccd(start[a], start[t[0]], start[t[1]], start[t[2]], end[a], end[t[0]], end[t[1]],
                                end[t[2]], req);
        } else {
            const Edge& e = edges[a];
            const Edge& f = edges[b];
            r = edge_edge_ccd(start[e[0]], start[e[1]], start[f[0]], start[f[1]], end[e[0]], end[e[1]], end[f[0]],
                              end[f[1]], req);
        }
        capped += r.stats.capped;
        if (r.colliding) found.push_back({vertex_face, a, b, r});
    };
    const bool first = request.mode == ContactMode::first;
    detail::for_range(start.size(), request.parallel, [&](std::size_t lo, std::size_t hi) {
        std::vector<CcdContact> found;
        std::size_t candidates = 0, capped = 0;
        double limit = first ? current_limit() : request.primitive.t_max;
        for (std::size_t v = lo; v < hi; ++v) {
            const BroadBox<double> box = detail::swept_box(start, end, std::array<Index, 1>{Index(v)}, grow);
            faces.query(box, [&](ObjectId f) {
                const Triangle& t = triangles[f];
                if (t[0] != v && t[1] != v && t[2] != v && overlap(box, faces.box(f))) {
                    ++candidates;
                    run(true, Index(v), Index(f), found, capped, limit);
                    if (first && !found.empty()) limit = std::min(limit, found.back().ccd.toi_upper);
                }
                return true;
            });
        }
        record(found, candidates, 0, capped);
    });
    detail::for_range(edges.size(), request.parallel, [&](std::size_t lo, std::size_t hi) {
        std::vector<CcdContact> found;
        std::size_t candidates = 0, capped = 0;
        double limit = first ? current_limit() : request.primitive.t_max;
        for (std::size_t i = lo; i < hi; ++i) {
            const Edge& e = edges[i];
            const BroadBox<double>& box = edge_tree.box(ObjectId(i));
            edge_tree.query(box, [&](ObjectId j) {
                const Edge& f = edges[j];
                if (j > i && e[0] != f[0] && e[0] != f[1] && e[1] != f[0] && e[1] != f[1] &&
                    overlap(box, edge_tree.box(j))) {
                    ++candidates;
                    run(false, Index(i), Index(j), found, capped, limit);
                    if (first && !found.empty()) limit = std::min(limit, found.back().ccd.toi_upper);
                }
                return true;
            });
        }
        record(found, 0, candidates, capped);
    });
    out.colliding = !out.contacts.empty();
    out.toi = request.primitive.t_max;
    for (const CcdContact& c : out.contacts) out.toi = std::min(out.toi, c.ccd.toi);
    return out;
}

}  // namespace cdkit
