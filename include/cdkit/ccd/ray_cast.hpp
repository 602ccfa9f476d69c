#pragma once
/// \file Ray casts against a triangle mesh through its tree: the closest hit, any hit, or all hits.
///
/// The ray–triangle test is the watertight one of S. Woop, C. Benthin, I. Wald, "Watertight Ray/Triangle
/// Intersection", JCGT 2(1), 2013: the triangle is moved into a frame where the ray runs along +z from the origin
/// (a permutation that puts the ray's largest component last, then a shear), and the three 2D edge functions
/// decide. An edge shared by two triangles gives both of them the same edge function with opposite sign (the same
/// products in the other order), so a ray through the edge is never lost between them; one through a vertex
/// hits at least one of the triangles around it. The tree's volumes are tested by their axis-aligned box in the
/// mesh frame (a conservative slab test, any BV of the family).
/// Const and thread-safe; `ray_cast_many` runs a batch in parallel with TBB.

#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/bvh/traverse.hpp"
#include "cdkit/ccd/detail/swept_node_box.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#if defined(CDKIT_HAS_TBB)
#include <tbb/parallel_for.h>
#endif

namespace cdkit {

/// A ray origin + t·direction, t ∈ [t_min, t_max], in world coordinates.
struct Ray {
    Vec3<double> origin = Vec3<double>::Zero();
    Vec3<double> direction = Vec3<double>::UnitZ();  ///< need not be unit; t is measured in its lengths
    double t_min = 0;
    double t_max = std::numeric_limits<double>::infinity();
};

enum class RayMode { closest, any, all };

struct RayHit {
    Index triangle = 0;
    double t = 0;              ///< origin + t·direction is the hit point
    double u = 0, v = 0;       ///< barycentric: point = (1 − u − v)·p0 + u·p1 + v·p2 of the triangle's vertices
    Vec3<double> point = Vec3<double>::Zero();   ///< world
    Vec3<double> normal = Vec3<double>::Zero();  ///< unit, world, the triangle's (p1 − p0) × (p2 − p0)
};

struct RayCastResult {
    QueryStatus status = QueryStatus::ok;  ///< invalid_pose, or invalid_input for a NaN or zero direction
    bool hit = false;
    std::vector<RayHit> hits;  ///< closest / any: at most one; all: every hit, by increasing t
    std::uint64_t bv_tests = 0, triangle_tests = 0;
    bool capped = false;  ///< convex casts only: out of steps, the hit is the conservative answer
};

namespace detail {

/// Woop et al.'s ray frame: axis permutation (kx, ky, kz) and shear, computed once per ray.
struct RayFrame {
    int kx, ky, kz;
    double sx, sy, sz;
    Vec3<double> origin;
    explicit RayFrame(const Ray& r) : origin(r.origin) {
        const Vec3<double> a = r.direction.cwiseAbs();
        kz = a.x() > a.y() ? (a.x() > a.z() ? 0 : 2) : (a.y() > a.z() ? 1 : 2);
        kx = (kz + 1) % 3;
        ky = (kx + 1) % 3;
        if (r.direction[kz] < 0) std::swap(kx, ky);  // keeps the winding
        sx = r.direction[kx] / r.direction[kz];
        sy = r.direction[ky] / r.direction[kz];
        sz = 1.0 / r.direction[kz];
    }
};

/// The watertight test; on a hit fills t (in the ray's parameter) and the barycentrics.
inline bool ray_triangle(const RayFrame& f, const Vec3<double>& p0, const Vec3<double>& p1, const Vec3<double>& p2,
                         double t_min, double t_max, double& t, double& u, double& v) noexcept {
    const Vec3<double> a = p0 - f.origin, b = p1 - f.origin, c = p2 - f.origin;
    const double ax = a[f.kx] - f.sx * a[f.kz], ay = a[f.ky] - f.sy * a[f.kz];
    const double bx = b[f.kx] - f.sx * b[f.kz], by = b[f.ky] - f.sy * b[f.kz];
    const double cx = c[f.kx] - f.sx * c[f.kz], cy = c[f.ky] - f.sy * c[f.kz];
    // Edge functions: each written as the same two products for both triangles that share the edge.
    const double U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
    if ((U < 0 || V < 0 || W < 0) && (U > 0 || V > 0 || W > 0)) return false;
    const double det = U + V + W;
    if (det == 0) return false;  // the ray lies in the triangle's plane
    const double az = f.sz * a[f.kz], bz = f.sz * b[f.kz], cz = f.sz * c[f.kz];
    const double T = U * az + V * bz + W * cz;
    const double inv = 1.0 / det;
    t = T * inv;
    if (!(t >= t_min && t <= t_max)) return false;
    u = V * inv;
    v = W * inv;
    return true;
}

/// Slab test of the ray (in the mesh frame) against a box; the entry time, or +∞ for a miss.
inline double ray_box(const Vec3<double>& o, const Vec3<double>& inv_d, const BroadBox<double>& box, double t_min,
                      double t_max) noexcept {
    for (int k = 0; k < 3; ++k) {
        double t0 = (box.lo[k] - o[k]) * inv_d[k], t1 = (box.hi[k] - o[k]) * inv_d[k];
        if (t0 > t1) std::swap(t0, t1);
        if (std::isnan(t0) || std::isnan(t1)) continue;  // o on a slab plane of a parallel ray: inside that slab
        t_min = std::max(t_min, t0);
        t_max = std::min(t_max, t1 * (1 + 4 * std::numeric_limits<double>::epsilon()));
        if (t_min > t_max) return std::numeric_limits<double>::infinity();
    }
    return t_min;
}

}  // namespace detail

/// Casts `ray` (world) against mesh `model` placed by `pose`.
template <class BV>
[[nodiscard]] RayCastResult ray_cast(const MeshModel<BV, double>& model, const Transform<double>& pose, Ray ray,
                                     RayMode mode = RayMode::closest) {
    RayCastResult out;
    if (!pose_is_usable(pose)) {
        out.status = QueryStatus::invalid_pose;
        return out;
    }
    if (!ray.origin.allFinite() || !ray.direction.allFinite() || ray.direction.squaredNorm() == 0 ||
        std::isnan(ray.t_min) || std::isnan(ray.t_max)) {
        out.status = QueryStatus::invalid_input;
        return out;
    }
    // Into the mesh frame: the rotation keeps t's scale.
    const Transform<double> to_mesh = pose.inverse();
    Ray local = ray;
    local.origin = to_mesh * ray.origin;
    local.direction = to_mesh.R * ray.direction;
    const detail::RayFrame frame(local);
    const Vec3<double> inv_d = local.direction.cwiseInverse();
    const auto& nodes = model.bvh().nodes();
    const auto& order = model.bvh().triangle_order();
    const auto& mesh = model.mesh();
    if (nodes.empty()) return out;
    const Transform<double> identity;
    double t_max = ray.t_max;
    std::vector<RayHit> hits;
    detail::SmallStack<std::uint32_t, 128> stack;
    stack.push(0);
    while (!stack.empty()) {
        const BvhNode<BV>& n = nodes[stack.pop()];
        ++out.bv_tests;
        if (detail::ray_box(local.origin, inv_d, detail::world_box(n.bv, identity), ray.t_min, t_max) ==
            std::numeric_limits<double>::infinity())
            continue;
        if (!n.is_leaf()) {
            stack.push(n.first + 1);
            stack.push(n.first);
            continue;
        }
        for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
            const Index tri = order[i];
            const Triangle& t = mesh.triangles[tri];
            ++out.triangle_tests;
            RayHit h;
            if (!detail::ray_triangle(frame, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]], ray.t_min,
                                      t_max, h.t, h.u, h.v))
                continue;
            h.triangle = tri;
            hits.push_back(h);
            if (mode == RayMode::closest) t_max = h.t;  // later nodes only matter if they are nearer
            if (mode == RayMode::any) break;
        }
        if (mode == RayMode::any && !hits.empty()) break;
    }
    if (mode == RayMode::closest && !hits.empty()) {
        const RayHit best = *std::min_element(hits.begin(), hits.end(), [](const RayHit& a, const RayHit& b) {
            return a.t < b.t || (a.t == b.t && a.triangle < b.triangle);
        });
        hits.assign(1, best);
    }
    std::sort(hits.begin(), hits.end(), [](const RayHit& a, const RayHit& b) { return a.t < b.t; });
    for (RayHit& h : hits) {
        const Triangle& t = mesh.triangles[h.triangle];
        const Vec3<double>&p0 = mesh.vertices[t[0]], &p1 = mesh.vertices[t[1]], &p2 = mesh.vertices[t[2]];
        h.point = pose * ((1 - h.u - h.v) * p0 + h.u * p1 + h.v * p2);
        const Vec3<double> n = pose.R * (p1 - p0).cross(p2 - p0);
        h.normal = n.norm() > 0 ? Vec3<double>(n.normalized()) : Vec3<double>::Zero();
    }
    out.hit = !hits.empty();
    out.hits = std::move(hits);
    return out;
}

/// Every ray of `rays` against the mesh, in parallel with TBB where the library was built with it.
template <class BV>
[[nodiscard]] std::vector<RayCastResult> ray_cast_many(const MeshModel<BV, double>& model, const Transform<double>& pose,
                                                       const std::vector<Ray>& rays, RayMode mode = RayMode::closest) {
    std::vector<RayCastResult> out(rays.size());
#if defined(CDKIT_HAS_TBB)
    tbb::parallel_for(std::size_t(0), rays.size(), [&](std::size_t i) { out[i] = ray_cast(model, pose, rays[i], mode); });
#else
    for (std::size_t i = 0; i < rays.size(); ++i) out[i] = ray_cast(model, pose, rays[i], mode);
#endif
    return out;
}

}  // namespace cdkit
