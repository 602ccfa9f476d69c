#pragma once
/// \file The supporting feature of a convex shape along a direction: the face, edge or vertex that touches a plane
/// with that outward normal, in the world frame. A face is taken when its normal lies within the feature angle of
/// the direction, an edge when it lies within that angle of the plane, else the support vertex. Curved shapes
/// give their flat parts (a cylinder's or a cone's base as an inscribed octagon, their side lines, a capsule's
/// side line) and otherwise a point; shapes the function does not know give their support point.
///
/// Faces come counter-clockwise seen from outside, so that clip.hpp's side planes point outwards. Each point
/// carries a small key (its vertex number on the shape) for the manifold's ids.

#include "cdkit/narrowphase/convex_polyhedron.hpp"
#include "cdkit/narrowphase/convex_shapes.hpp"
#include "cdkit/narrowphase/support.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace cdkit::detail {

template <class S> struct ContactFeature {
    /// A face of more vertices keeps every k-th one: a polygon inscribed in the face, so its points still lie on it.
    static constexpr int capacity = 32;
    int count = 0;               ///< 1: vertex, 2: edge, ≥ 3: face
    std::uint32_t index = 0;     ///< which face / edge / vertex of the shape (the ids' first part)
    Vec3<S> normal = Vec3<S>::Zero();  ///< outward unit normal (world) of a face
    std::array<Vec3<S>, capacity> points{};
    std::array<std::uint32_t, capacity> keys{};

    void add(const Vec3<S>& p, std::uint32_t key) noexcept {
        points[count] = p;
        keys[count] = key;
        ++count;
    }
};

/// cos and sin of the feature angle.
template <class S> struct FeatureTolerance {
    S cos_face, sin_edge;
    explicit FeatureTolerance(double angle) noexcept
        : cos_face(S(std::cos(angle))), sin_edge(S(std::sin(angle))) {}
};

template <class S> ContactFeature<S> vertex_feature(const Vec3<S>& p, std::uint32_t index) noexcept {
    ContactFeature<S> f;
    f.index = index;
    f.add(p, index);
    return f;
}

/// Places a feature built in the shape's frame into the world.
template <class S> void place_feature(ContactFeature<S>& f, const Transform<S>& pose) noexcept {
    for (int i = 0; i < f.count; ++i) f.points[i] = pose * f.points[i];
    f.normal = pose.R * f.normal;
}

/// A disc of radius r at height z as an inscribed octagon, counter-clockwise seen from the side `up` (+1 / −1).
template <class S> void add_disc(ContactFeature<S>& f, S r, S z, int up) noexcept {
    constexpr int n = 8;
    for (int k = 0; k < n; ++k) {
        const int j = up > 0 ? k : (n - k) % n;
        const double a = 2 * std::numbers::pi * j / n;
        f.add(Vec3<S>(r * S(std::cos(a)), r * S(std::sin(a)), z), std::uint32_t(j));
    }
    f.normal = Vec3<S>(S(0), S(0), S(up));
}

/// The unit direction of d's projection on the xy-plane (e_x on the axis).
template <class S> Vec3<S> azimuth(const Vec3<S>& d) noexcept {
    const S rho = std::sqrt(d.x() * d.x() + d.y() * d.y());
    return rho > S(0) ? Vec3<S>(d.x() / rho, d.y() / rho, S(0)) : Vec3<S>(S(1), S(0), S(0));
}

// Local-frame features (d: unit direction in the shape's frame).

template <class S> ContactFeature<S> local_feature(const Box<S>& box, const Vec3<S>& d, const FeatureTolerance<S>& tol) {
    const Vec3<S>& h = box.half;
    int k = 0;
    for (int i = 1; i < 3; ++i)
        if (std::abs(d[i]) > std::abs(d[k])) k = i;
    const auto corner = [&](const Vec3<S>& s) { return Vec3<S>(s.cwiseProduct(h)); };
    const auto corner_key = [](const Vec3<S>& s) {
        return std::uint32_t((s.x() > 0) | ((s.y() > 0) << 1) | ((s.z() > 0) << 2));
    };
    ContactFeature<S> f;
    if (std::abs(d[k]) >= tol.cos_face) {  // face k on the side of d
        const S sk = d[k] >= S(0) ? S(1) : S(-1);
        const int i = (k + 1) % 3, j = (k + 2) % 3;  // (i, j, k) right-handed: (e_i, e_j) counter-clockwise about e_k
        const S u[4] = {-1, 1, 1, -1}, v[4] = {-1, -1, 1, 1};
        for (int c = 0; c < 4; ++c) {
            const int cc = sk > 0 ? c : 3 - c;  // seen from −e_k the order flips
            Vec3<S> s;
            s[k] = sk, s[i] = u[cc], s[j] = v[cc];
            f.add(corner(s), corner_key(s));
        }
        f.normal = Vec3<S>::Zero();
        f.normal[k] = sk;
        f.index = std::uint32_t(2 * k + (sk > 0));
        return f;
    }
    Vec3<S> s(d.x() >= 0 ? S(1) : S(-1), d.y() >= 0 ? S(1) : S(-1), d.z() >= 0 ? S(1) : S(-1));
    int e = 0;  // the edge direction: the axis d is most perpendicular to
    for (int i = 1; i < 3; ++i)
        if (std::abs(d[i]) < std::abs(d[e])) e = i;
    if (std::abs(d[e]) <= tol.sin_edge) {
        Vec3<S> s0 = s, s1 = s;
        s0[e] = S(-1), s1[e] = S(1);
        f.add(corner(s0), corner_key(s0));
        f.add(corner(s1), corner_key(s1));
        f.index = 8 + std::uint32_t(e) * 8 + corner_key(s0);
        return f;
    }
    return vertex_feature(corner(s), corner_key(s));
}

template <class S>
ContactFeature<S> local_feature(const ConvexPolyhedron<S>& hull, const Vec3<S>& d, const FeatureTolerance<S>& tol) {
    const std::uint32_t v = hull.support_index(d);
    if (!hull.has_topology()) return vertex_feature(hull.vertices()[v], v);
    // The best face and the most perpendicular edge among those around the support vertex.
    std::uint32_t best_face = std::uint32_t(-1), best_edge = std::uint32_t(-1);
    S face_cos = S(-2), edge_sin = S(2);
    const auto edges = hull.vertex_edges(v);
    const auto dirs = hull.vertex_edge_directions(v);
    for (std::size_t k = 0; k < edges.size(); ++k) {
        const PolyhedronEdge<S>& e = hull.edges()[edges[k]];
        for (std::uint32_t face : {e.face_left, e.face_right}) {
            const S c = hull.face_normal(face).dot(d);
            if (c > face_cos) face_cos = c, best_face = face;
        }
        const S s = std::abs(dirs[k].dot(d));
        if (s < edge_sin) edge_sin = s, best_edge = edges[k];
    }
    ContactFeature<S> f;
    if (best_face != std::uint32_t(-1) && face_cos >= tol.cos_face) {
        const auto loop = hull.face_vertices(best_face);
        const std::size_t step = (loop.size() + ContactFeature<S>::capacity - 1) / ContactFeature<S>::capacity;
        for (std::size_t k = 0; k < loop.size(); k += step) f.add(hull.vertices()[loop[k]], loop[k]);
        f.normal = hull.face_normal(best_face);
        f.index = best_face;
        return f;
    }
    if (best_edge != std::uint32_t(-1) && edge_sin <= tol.sin_edge) {
        const PolyhedronEdge<S>& e = hull.edges()[best_edge];
        f.add(hull.vertices()[e.v0], e.v0);
        f.add(hull.vertices()[e.v1], e.v1);
        f.index = best_edge;
        return f;
    }
    return vertex_feature(hull.vertices()[v], v);
}

template <class S>
ContactFeature<S> local_feature(const ConvexTriangle<S>& tri, const Vec3<S>& d, const FeatureTolerance<S>& tol) {
    const Vec3<S> n = safe_normalized(Vec3<S>((tri.b - tri.a).cross(tri.c - tri.a)));
    const S c = n.dot(d);
    ContactFeature<S> f;
    if (std::abs(c) >= tol.cos_face) {
        if (c > 0) f.add(tri.a, 0), f.add(tri.b, 1), f.add(tri.c, 2);
        else f.add(tri.a, 0), f.add(tri.c, 2), f.add(tri.b, 1);
        f.normal = c > 0 ? n : Vec3<S>(-n);
        f.index = c > 0 ? 0 : 1;
        return f;
    }
    const std::array<Vec3<S>, 3> v{tri.a, tri.b, tri.c};
    int best = 0;
    S best_sin = S(2);
    for (int k = 0; k < 3; ++k) {
        const Vec3<S> e = safe_normalized(Vec3<S>(v[(k + 1) % 3] - v[k]));
        const S s = std::abs(e.dot(d));
        // The edge must also be the supporting one: its vertices both near the top along d.
        if (s < best_sin && std::min(v[k].dot(d), v[(k + 1) % 3].dot(d)) >= v[(k + 2) % 3].dot(d)) best_sin = s, best = k;
    }
    if (best_sin <= tol.sin_edge) {
        f.add(v[best], std::uint32_t(best));
        f.add(v[(best + 1) % 3], std::uint32_t((best + 1) % 3));
        f.index = 2 + std::uint32_t(best);
        return f;
    }
    const Vec3<S> p = tri.support(d);
    return vertex_feature(p, p == tri.a ? 0u : p == tri.b ? 1u : 2u);
}

template <class S>
ContactFeature<S> local_feature(const Cylinder<S>& cyl, const Vec3<S>& d, const FeatureTolerance<S>& tol) {
    ContactFeature<S> f;
    if (std::abs(d.z()) >= tol.cos_face) {
        const int up = d.z() > 0 ? 1 : -1;
        add_disc(f, cyl.radius, S(up) * cyl.half_height, up);
        f.index = up > 0 ? 1 : 0;
        return f;
    }
    if (std::abs(d.z()) <= tol.sin_edge) {  // the side line at d's azimuth
        const Vec3<S> u = azimuth(d) * cyl.radius;
        f.add(Vec3<S>(u.x(), u.y(), -cyl.half_height), 0);
        f.add(Vec3<S>(u.x(), u.y(), cyl.half_height), 1);
        f.index = 2;
        return f;
    }
    return vertex_feature(cyl.support(d), 3);
}

template <class S>
ContactFeature<S> local_feature(const Cone<S>& cone, const Vec3<S>& d, const FeatureTolerance<S>& tol) {
    ContactFeature<S> f;
    if (-d.z() >= tol.cos_face) {
        add_disc(f, cone.radius, -cone.half_height, -1);
        f.index = 0;
        return f;
    }
    const Vec3<S> u = azimuth(d);
    const Vec3<S> side = safe_normalized(Vec3<S>(S(2) * cone.half_height * u.x(), S(2) * cone.half_height * u.y(), cone.radius));
    if (side.dot(d) >= tol.cos_face) {  // the side line from the rim to the apex
        f.add(Vec3<S>(cone.radius * u.x(), cone.radius * u.y(), -cone.half_height), 0);
        f.add(Vec3<S>(S(0), S(0), cone.half_height), 1);
        f.index = 1;
        return f;
    }
    return vertex_feature(cone.support(d), 2);
}

template <class S>
ContactFeature<S> local_feature(const Capsule<S>& cap, const Vec3<S>& d, const FeatureTolerance<S>& tol) {
    if (std::abs(d.z()) <= tol.sin_edge) {  // the side line, on the surface along d
        ContactFeature<S> f;
        const Vec3<S> r = cap.radius * d;
        f.add(Vec3<S>(r.x(), r.y(), r.z() - cap.half_length), 0);
        f.add(Vec3<S>(r.x(), r.y(), r.z() + cap.half_length), 1);
        f.index = 0;
        return f;
    }
    return vertex_feature(cap.support(d), 1);
}

/// Any other support-mapped shape (spheres, ellipsoids, ...): its support point.
template <class Shape>
ContactFeature<typename Shape::Scalar> local_feature(const Shape& shape, const Vec3<typename Shape::Scalar>& d,
                                                     const FeatureTolerance<typename Shape::Scalar>&) {
    return vertex_feature(Vec3<typename Shape::Scalar>(shape.support(d)), 0);
}

/// A rounded shape: the core's feature moved out by the radius along d.
template <class Shape>
ContactFeature<typename Shape::Scalar> local_feature(const Inflated<Shape>& s, const Vec3<typename Shape::Scalar>& d,
                                                     const FeatureTolerance<typename Shape::Scalar>& tol) {
    ContactFeature<typename Shape::Scalar> f = local_feature(s.shape, d, tol);
    for (int i = 0; i < f.count; ++i) f.points[i] += s.radius * d;
    return f;
}

/// The feature of `shape` at `pose` that supports it along the world direction `d` (unit).
template <class Shape>
ContactFeature<typename Shape::Scalar> supporting_feature(const Shape& shape, const Transform<typename Shape::Scalar>& pose,
                                                          const Vec3<typename Shape::Scalar>& d,
                                                          const FeatureTolerance<typename Shape::Scalar>& tol) {
    using S = typename Shape::Scalar;
    ContactFeature<S> f = local_feature(shape, Vec3<S>(pose.R.transpose() * d), tol);
    place_feature(f, pose);
    return f;
}

}  // namespace cdkit::detail
