#pragma once
/// \file What vertex–face and edge–edge CCD share around the root search: the input check, the gap function's
/// terms from the eight points, and the contact point and normal at the time found.

#include "cdkit/ccd/detail/inclusion_search.hpp"

#include <array>
#include <cmath>

namespace cdkit::detail {

using CcdPoints = std::array<const Vec3<double>*, 8>;  ///< four points at t = 0, then the same four at t = 1

[[nodiscard]] inline bool ccd_points_finite(const CcdPoints& p) noexcept {
    for (const auto* q : p)
        if (!q->allFinite()) return false;
    return true;
}

/// F = B + u·E1 + v·E2 with each term x − y of two of the four points (given by index pairs), at t = 0 and 1.
[[nodiscard]] inline GapFunction make_gap_function(const CcdPoints& p, std::array<int, 2> b, std::array<int, 2> e1,
                                                   std::array<int, 2> e2, bool triangle_domain) noexcept {
    GapFunction g;
    g.triangle_domain = triangle_domain;
    for (int k = 0; k < 3; ++k) {
        double m = 0;
        for (const auto* q : p) m = std::max(m, std::abs((*q)[k]));
        g.error[k] = gap_error_bound(m);
        auto diff = [&](std::array<int, 2> ij, int time) { return (*p[ij[0] + 4 * time])[k] - (*p[ij[1] + 4 * time])[k]; };
        g.b0[k] = diff(b, 0);
        g.b1[k] = diff(b, 1);
        g.e10[k] = diff(e1, 0);
        g.e11[k] = diff(e1, 1);
        g.e20[k] = diff(e2, 0);
        g.e21[k] = diff(e2, 1);
    }
    g.coplanarity_error = coplanarity_error_bound(g);
    return g;
}

/// F's terms at time t, as vectors.
struct GapAt {
    Vec3<double> B, E1, E2;
};
[[nodiscard]] inline GapAt gap_at(const GapFunction& g, double t) noexcept {
    GapAt r;
    for (int k = 0; k < 3; ++k) {
        r.B[k] = g.b0[k] + t * (g.b1[k] - g.b0[k]);
        r.E1[k] = g.e10[k] + t * (g.e11[k] - g.e10[k]);
        r.E2[k] = g.e20[k] + t * (g.e21[k] - g.e20[k]);
    }
    return r;
}

/// The contact normal at the time found: E1 × E2 (face normal, common normal of the edges), or where that
/// vanishes (parallel edges, a degenerate face) the gap vector's direction; oriented along F at t = 0 (from the
/// face or edge B towards the vertex or edge A). Zero only when nothing defines a direction.
[[nodiscard]] inline Vec3<double> ccd_normal(const GapFunction& g, const CcdResult& r) noexcept {
    const GapAt at = gap_at(g, r.toi);
    const GapAt start = gap_at(g, 0);
    const Vec3<double> f0 = start.B + r.u * start.E1 + r.v * start.E2;
    Vec3<double> n = at.E1.cross(at.E2);
    const double scale = at.E1.norm() * at.E2.norm();
    if (!(n.norm() > 1e-12 * scale)) n = f0.norm() > 0 ? f0 : Vec3<double>(at.B + r.u * at.E1 + r.v * at.E2);
    if (n.dot(f0) < 0) n = -n;
    const double len = n.norm();
    return len > 0 && std::isfinite(len) ? Vec3<double>(n / len) : Vec3<double>::Zero();
}

[[nodiscard]] inline Vec3<double> lerp_point(const Vec3<double>& p0, const Vec3<double>& p1, double t) noexcept {
    return p0 + t * (p1 - p0);
}

/// The whole primitive query: input check, F = B + u·E1 + v·E2 from the given point pairs, the search, then the
/// contact point (on the face, or on edge A: points p[i] + u·(p[j] − p[i]) + v·(p[k] − p[i]) at t = toi, with
/// `point_terms` = {i, j, k}; k < 0 for none) and normal.
[[nodiscard]] inline CcdResult primitive_ccd(const CcdPoints& pts, std::array<int, 2> b, std::array<int, 2> e1,
                                             std::array<int, 2> e2, bool triangle_domain, std::array<int, 3> point_terms,
                                             const CcdRequest& request) {
    CcdResult out;
    if (!ccd_points_finite(pts) || !ccd_request_is_valid(request)) {
        out.status = QueryStatus::invalid_input;
        return out;
    }
    const GapFunction g = make_gap_function(pts, b, e1, e2, triangle_domain);
    inclusion_search(g, request, out);
    if (out.colliding) {
        auto at = [&](int i) { return lerp_point(*pts[i], *pts[i + 4], out.toi); };
        const Vec3<double> base = at(point_terms[0]);
        out.point = base + out.u * (at(point_terms[1]) - base);
        if (point_terms[2] >= 0) out.point += out.v * (at(point_terms[2]) - base);
        out.normal = ccd_normal(g, out);
    }
    return out;
}

}  // namespace cdkit::detail
