#pragma once
/// \file "Model only what a scene needs": inspect a mesh (closed? convex? how large?) and suggest the
/// cheapest World representation that still answers collision queries for it, then build that Shape.
///
/// Rules, in order (tolerances in SuggestOptions):
///  1. open, non-manifold or inconsistently oriented → mesh BVH (a volume is not defined; only the surface is
///     exact);
///  2. closed, and its volume is not within `convex_tolerance` of its convex hull's → mesh BVH;
///  3. convex and it fills its tightest face-aligned box (volume ratio ≥ 1 − box_tolerance) → box;
///  4. convex and it fills its bounding sphere (ratio ≥ sphere_min_fill, e.g. a tessellated ball) → sphere
///     (radius = farthest vertex: conservative, never misses a contact of the mesh);
///  5. otherwise convex → convex hull.
/// Capsules are not detected; choose them by hand. The suggestion is advice: the user picks.

#include "cdkit/core/mesh.hpp"
#include "cdkit/world/shape.hpp"

#include <cmath>
#include <string>

namespace cdkit {

struct SuggestOptions {
    double convex_tolerance = 1e-3;  ///< convex when volume ≥ (1 − tol) · hull volume
    double box_tolerance = 1e-3;     ///< box when volume ≥ (1 − tol) · best box volume
    double sphere_min_fill = 0.9;    ///< sphere when volume ≥ fill · bounding-sphere volume
};

/// What suggest_representation found and recommends.
template <class S = double> struct RepresentationSuggestion {
    ShapeKind kind = ShapeKind::mesh;
    bool closed = false;             ///< closed, manifold and consistently oriented
    bool convex = false;             ///< closed and (nearly) equal to its convex hull
    std::size_t triangles = 0;
    double volume = 0;               ///< enclosed volume (closed meshes), else 0
    double hull_volume = 0;          ///< volume of the convex hull (0 when it could not be built)
    Vec3<S> extent = Vec3<S>::Zero();   ///< size of the axis-aligned bounding box in the mesh frame
    /// Frame of the suggested sphere / box in the mesh frame (centre and axes); identity otherwise.
    Transform<S> offset{};
    S radius = S(0);                 ///< sphere radius
    Vec3<S> half_extents = Vec3<S>::Zero();  ///< box half extents
    std::string reason;              ///< one line: why this kind
};

namespace detail {
template <class S> double signed_volume(const std::vector<Vec3<S>>& v, const Vec3<double>& c,
                                        const std::array<std::uint32_t, 3>& t) noexcept {
    const Vec3<double> a = v[t[0]].template cast<double>() - c, b = v[t[1]].template cast<double>() - c,
                       d = v[t[2]].template cast<double>() - c;
    return a.dot(b.cross(d)) / 6.0;
}
}  // namespace detail

/// Inspects `mesh` (validated first: cdkit::Error naming mesh.source on bad data) and suggests a kind.
/// O(n log n) plus a hull; the box search tries the frames of up to 256 hull faces.
template <class S>
[[nodiscard]] RepresentationSuggestion<S> suggest_representation(const TriangleMesh<S>& mesh, const SuggestOptions& opt = {}) {
    validate(mesh);
    RepresentationSuggestion<S> r;
    r.triangles = mesh.triangles.size();
    Vec3<S> lo = mesh.vertices.front(), hi = lo;
    for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    r.extent = hi - lo;
    const MeshStats st = compute_stats(mesh);
    r.closed = st.consistently_oriented && st.degenerate_triangles == 0;
    if (!r.closed) {
        r.kind = ShapeKind::mesh;
        r.reason = "open, non-manifold or inconsistently oriented: only the surface is defined, keep the mesh BVH";
        return r;
    }
    const Vec3<double> c = ((lo + hi) / S(2)).template cast<double>();
    double vol = 0;
    for (const auto& t : mesh.triangles) vol += detail::signed_volume(mesh.vertices, c, {t[0], t[1], t[2]});
    r.volume = std::abs(vol);
    std::vector<Vec3<double>> pts;
    pts.reserve(mesh.vertices.size());
    for (const auto& v : mesh.vertices) pts.push_back(v.template cast<double>());
    detail::HullData hull;
    try {
        hull = detail::convex_hull(pts);
    } catch (const Error&) {
        r.reason = "closed but flat (no 3-D hull): keep the mesh BVH";
        return r;
    }
    double hv = 0;
    for (const auto& t : hull.triangles) hv += detail::signed_volume(hull.vertices, c, t);
    r.hull_volume = std::abs(hv);
    r.convex = r.hull_volume > 0 && r.volume >= (1 - opt.convex_tolerance) * r.hull_volume;
    if (!r.convex) {
        r.kind = ShapeKind::mesh;
        r.reason = "closed but not convex (volume " + std::to_string(r.volume / r.hull_volume) +
                   " of its hull's): keep the mesh BVH";
        return r;
    }
    // Tightest box over the frames of the hull's faces (a box's own face frame gives it exactly).
    double best = (hi - lo).template cast<double>().prod();
    Mat3<double> best_axes = Mat3<double>::Identity();
    const std::size_t faces = std::min<std::size_t>(hull.triangles.size(), 256);
    for (std::size_t f = 0; f < faces; ++f) {
        const auto& t = hull.triangles[f];
        const Vec3<double> p[3] = {hull.vertices[t[0]], hull.vertices[t[1]], hull.vertices[t[2]]};
        const Vec3<double> n = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
        for (int k = 0; k < 3; ++k) {
            Vec3<double> e = p[(k + 1) % 3] - p[k];
            e -= n * n.dot(e);
            if (!(e.norm() > 0)) continue;
            e.normalize();
            Mat3<double> axes;
            axes.col(0) = e;
            axes.col(1) = n.cross(e);
            axes.col(2) = n;
            Vec3<double> blo = Vec3<double>::Constant(1e300), bhi = Vec3<double>::Constant(-1e300);
            for (const auto& v : hull.vertices) {
                const Vec3<double> q = axes.transpose() * v;
                blo = blo.cwiseMin(q), bhi = bhi.cwiseMax(q);
            }
            const double bv = (bhi - blo).prod();
            if (bv < best) best = bv, best_axes = axes;
        }
    }
    if (r.volume >= (1 - opt.box_tolerance) * best) {
        Vec3<double> blo = Vec3<double>::Constant(1e300), bhi = Vec3<double>::Constant(-1e300);
        for (const auto& v : hull.vertices) {
            const Vec3<double> q = best_axes.transpose() * v;
            blo = blo.cwiseMin(q), bhi = bhi.cwiseMax(q);
        }
        r.kind = ShapeKind::box;
        r.half_extents = ((bhi - blo) / 2).template cast<S>();
        r.offset = Transform<S>(best_axes.template cast<S>(), (best_axes * ((blo + bhi) / 2)).template cast<S>());
        r.reason = "convex and fills its box: box";
        return r;
    }
    double rmax = 0;
    for (const auto& v : hull.vertices) rmax = std::max(rmax, (v - c).norm());
    const double ball = 4.0 / 3.0 * 3.14159265358979323846 * rmax * rmax * rmax;
    if (r.volume >= opt.sphere_min_fill * ball) {
        r.kind = ShapeKind::sphere;
        r.radius = S(rmax);
        if (double(r.radius) < rmax) r.radius = std::nextafter(r.radius, std::numeric_limits<S>::infinity());
        r.offset = Transform<S>::translation(c.template cast<S>());
        r.reason = "convex and fills its bounding sphere: sphere";
        return r;
    }
    r.kind = ShapeKind::convex_hull;
    r.reason = "convex: convex hull (" + std::to_string(hull.vertices.size()) + " vertices)";
    return r;
}

/// Builds the suggested Shape for `mesh` (copies the mesh for ShapeKind::mesh).
template <class S> [[nodiscard]] Shape<S> make_shape(const TriangleMesh<S>& mesh, const RepresentationSuggestion<S>& s) {
    switch (s.kind) {
        case ShapeKind::sphere: return Shape<S>::sphere(s.radius).with_offset(s.offset);
        case ShapeKind::box: return Shape<S>::box(s.half_extents).with_offset(s.offset);
        case ShapeKind::capsule: break;  // never suggested
        case ShapeKind::convex_hull: return Shape<S>::convex_hull(mesh.vertices);
        default: break;  // mesh (and kinds never suggested)
    }
    return Shape<S>::mesh(mesh);
}

}  // namespace cdkit
