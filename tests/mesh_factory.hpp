#pragma once
// Small procedural meshes for tests: closed spheres and boxes, random triangle soups.
#include "cdkit/core/mesh.hpp"

#include <cmath>
#include <random>

namespace cdkit::test {

/// A closed UV sphere of radius r with `rings` × `segments` quads split into triangles (poles fanned).
template <class S = double> TriangleMesh<S> uv_sphere(S r, int rings, int segments) {
    TriangleMesh<S> m;
    m.source = "<uv_sphere>";
    const double pi = 3.14159265358979323846;
    m.vertices.push_back({0, 0, r});
    for (int i = 1; i < rings; ++i) {
        const double th = pi * i / rings;
        for (int j = 0; j < segments; ++j) {
            const double ph = 2 * pi * j / segments;
            m.vertices.push_back(Vec3<S>(S(r * std::sin(th) * std::cos(ph)), S(r * std::sin(th) * std::sin(ph)),
                                         S(r * std::cos(th))));
        }
    }
    m.vertices.push_back({0, 0, -r});
    const Index south = Index(m.vertices.size() - 1);
    auto ring = [&](int i, int j) { return Index(1 + (i - 1) * segments + (j % segments)); };
    for (int j = 0; j < segments; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
    for (int i = 1; i < rings - 1; ++i)
        for (int j = 0; j < segments; ++j) {
            m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
            m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
        }
    for (int j = 0; j < segments; ++j) m.triangles.push_back({south, ring(rings - 1, j + 1), ring(rings - 1, j)});
    return m;
}

/// n random triangles with vertices in [-1, 1]^3 and edge lengths up to `size` (a polygon soup).
template <class S = double> TriangleMesh<S> random_soup(int n, S size, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    TriangleMesh<S> m;
    m.source = "<random_soup>";
    for (int i = 0; i < n; ++i) {
        const Vec3<double> c(u(rng), u(rng), u(rng));
        for (int k = 0; k < 3; ++k)
            m.vertices.push_back((c + size * Vec3<double>(u(rng), u(rng), u(rng))).template cast<S>());
        m.triangles.push_back({Index(3 * i), Index(3 * i + 1), Index(3 * i + 2)});
    }
    return m;
}

/// The mesh scaled uniformly into [-1, 1]^3 and centred at its bounding-box centre (BENCHMARKS.md).
inline TriangleMesh<double> unit_scaled(TriangleMesh<double> m) {
    Vec3<double> lo = m.vertices[0], hi = m.vertices[0];
    for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    for (auto& v : m.vertices) v = (v - (lo + hi) / 2) * (2 / (hi - lo).maxCoeff());
    return m;
}

/// A smooth non-rigid deformation (bend and bulge) of a mesh, for refit tests: same vertices and triangles.
template <class S> TriangleMesh<S> deformed(const TriangleMesh<S>& m, double amount) {
    TriangleMesh<S> d = m;
    d.source = "<deformed>";
    for (auto& v : d.vertices) {
        const Vec3<double> p = v.template cast<double>();
        v = Vec3<double>(p.x() * (1 + amount * p.z()), p.y() + amount * std::sin(3 * p.x()),
                         p.z() + amount * p.x() * p.y())
                .template cast<S>();
    }
    return d;
}

/// The surface of a box of half extents h centred at the origin, each face split into 2·n² triangles facing
/// outwards (faces do not share vertices). Face-to-face poses tie many triangle pairs, and at an axis-aligned
/// pose box bounds are exact: tests of pruning bounds need both.
template <class S = double> TriangleMesh<S> grid_box(const Vec3<double>& h, int n) {
    TriangleMesh<S> m;
    for (int axis = 0; axis < 3; ++axis)
        for (int sign = -1; sign <= 1; sign += 2) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            const Index base = Index(m.vertices.size());
            for (int i = 0; i <= n; ++i)
                for (int j = 0; j <= n; ++j) {
                    Vec3<double> p;
                    p[axis] = sign * h[axis];
                    p[u] = h[u] * (2.0 * i / n - 1);
                    p[v] = h[v] * (2.0 * j / n - 1);
                    m.vertices.push_back(p.cast<S>());
                }
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    const Index a = base + Index(i * (n + 1) + j), b = a + 1, c = a + Index(n + 1), d = c + 1;
                    if (sign > 0) m.triangles.push_back({a, c, d}), m.triangles.push_back({a, d, b});
                    else m.triangles.push_back({a, d, c}), m.triangles.push_back({a, b, d});
                }
        }
    return m;
}

/// A uniformly random rotation (from a uniform unit quaternion).
template <class S = double> Mat3<S> random_rotation(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    q.normalize();
    return q.toRotationMatrix().template cast<S>();
}

}  // namespace cdkit::test
