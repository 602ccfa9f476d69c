#pragma once
/// \file Discrete oriented polytopes (k-DOPs) with K = 6, 14, 18 or 26 fixed face normals (Klosowski, Held,
/// Mitchell, Sowizral, Zikan, "Efficient collision detection using bounding volume hierarchies of k-DOPs",
/// IEEE TVCG 1998). The overlap test under a relative rigid motion re-aligns the other tree's DOP: it
/// encloses the rotated DOP of B in an axis-aligned DOP of A's frame and compares the K/2 slabs (Zachmann,
/// "Rapid collision detection by dynamically aligned DOP-trees", IEEE VRAIS 1998).
///
/// Re-alignment. The extent of B's DOP P = {x : D_k·x ≤ h_k} along a direction c (c = Rᵀd_j for A's normal
/// d_j) is the linear programme max c·x over P. Any non-negative combination c = Σ λ_m D_m bounds it from
/// above, c·x = Σ λ_m D_m·x ≤ Σ λ_m h_m (weak LP duality), whatever the h's are. So the per-query work picks,
/// for each of the K signed directions of A, three of B's normals whose cone contains c (the facet of the
/// normal fan of the regular DOP that the ray along c crosses: Zachmann's vertex correspondence) and the
/// weights λ; a per-node test is then three multiply-adds per direction, O(K). The bound equals the true
/// extent when the node's DOP has the regular combinatorial structure (the vertex exists) and is larger
/// otherwise, never smaller: the test is conservative for every DOP. For K > 6 the axis-only certificate
/// c = Σ |c_k| (±e_k) is taken too and the smaller bound kept (it wins on thin, irregular DOPs).

#include "cdkit/bv/fit.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace cdkit {

namespace detail {
/// The K/2 fixed directions of a K-DOP, unnormalised with entries in {−1, 0, 1} so that projections are
/// sums and differences of coordinates. Axes first, then the cube diagonals (14, 26), then the edge
/// directions (18, 26).
template <int K> [[nodiscard]] constexpr std::array<std::array<int, 3>, K / 2> kdop_directions() noexcept {
    std::array<std::array<int, 3>, K / 2> d{};
    int n = 0;
    d[n++] = {1, 0, 0};
    d[n++] = {0, 1, 0};
    d[n++] = {0, 0, 1};
    if constexpr (K == 14 || K == 26) {
        d[n++] = {1, 1, 1};
        d[n++] = {1, 1, -1};
        d[n++] = {1, -1, 1};
        d[n++] = {-1, 1, 1};
    }
    if constexpr (K == 18 || K == 26) {
        d[n++] = {1, 1, 0};
        d[n++] = {1, 0, 1};
        d[n++] = {0, 1, 1};
        d[n++] = {1, -1, 0};
        d[n++] = {1, 0, -1};
        d[n++] = {0, 1, -1};
    }
    return d;
}

/// d·v for a direction with entries in {−1, 0, 1}. The fit, contains() and the tests all use this one
/// function, so a vertex projects to the same rounded value everywhere.
template <class S> [[nodiscard]] inline S kdop_project(const std::array<int, 3>& d, const Vec3<S>& v) noexcept {
    S s = S(0);
    for (int k = 0; k < 3; ++k) {
        if (d[k] > 0) s += v[k];
        else if (d[k] < 0) s -= v[k];
    }
    return s;
}

/// The normal fan of the regular K-DOP: the facets of the convex hull of its K unit normals. The ray along
/// a direction c leaves the hull through the facet f maximising g_f·c (g_f = facet normal / facet offset);
/// c then lies in the cone of that facet's three normals. `inverse` maps c to the weights λ over the three
/// (unnormalised, signed) DOP normals. Computed once per K (brute force over triples, a few ms at most).
template <int K> struct KdopFan {
    struct Facet {
        std::array<std::uint8_t, 3> plane;  ///< signed normal indices: k < K/2 is +d_k, K/2 + k is −d_k
        Eigen::Matrix<double, 3, 3> inverse;
        Eigen::Matrix<double, 3, 1> g;
    };
    std::vector<Facet> facets;

    static const KdopFan& get() {
        static const KdopFan fan = make();  // thread-safe initialisation (C++11 magic statics)
        return fan;
    }

private:
    static KdopFan make() {
        constexpr int N = K / 2;
        constexpr auto dirs = kdop_directions<K>();
        std::array<Eigen::Matrix<double, 3, 1>, K> D, u;
        for (int k = 0; k < K; ++k) {
            const auto& d = dirs[k % N];
            const double s = k < N ? 1.0 : -1.0;
            D[k] = s * Eigen::Matrix<double, 3, 1>(d[0], d[1], d[2]);
            u[k] = D[k].normalized();
        }
        KdopFan fan;
        for (int i = 0; i < K; ++i)
            for (int j = i + 1; j < K; ++j)
                for (int l = j + 1; l < K; ++l) {
                    Eigen::Matrix<double, 3, 1> n = (u[j] - u[i]).cross(u[l] - u[i]);
                    if (n.norm() < 1e-9) continue;
                    double o = n.dot(u[i]);
                    if (o < 0) n = -n, o = -o;
                    if (o < 1e-9) continue;
                    bool hull = true;
                    for (int m = 0; m < K && hull; ++m) hull = n.dot(u[m]) <= o + 1e-9;
                    if (!hull) continue;
                    Eigen::Matrix<double, 3, 3> M;
                    M << D[i], D[j], D[l];
                    Facet f;
                    f.plane = {std::uint8_t(i), std::uint8_t(j), std::uint8_t(l)};
                    f.inverse = M.inverse();
                    f.g = n / o;
                    fan.facets.push_back(f);
                }
        return fan;
    }
};
}  // namespace detail

/// A K-DOP: the intersection of K/2 slabs with fixed normals (detail::kdop_directions). Stored as K support
/// values: h[k] = max d_k·x and h[K/2 + k] = max (−d_k)·x = −min d_k·x over the enclosed points.
template <class S, int K> struct Kdop {
    static_assert(K == 6 || K == 14 || K == 18 || K == 26, "Kdop supports K = 6, 14, 18 or 26");
    using Scalar = S;
    template <class T> using rebind = Kdop<T, K>;  ///< the same BV in another scalar type
    static constexpr int N = K / 2;  ///< number of slabs
    static constexpr const char* name = K == 6 ? "KDOP6" : K == 14 ? "KDOP14" : K == 18 ? "KDOP18" : "KDOP26";
    static constexpr std::array<std::array<int, 3>, N> directions = detail::kdop_directions<K>();

    /// Support values (see the struct's comment); −∞ everywhere = empty.
    std::array<S, K> h = filled(-std::numeric_limits<S>::infinity());

    [[nodiscard]] static Kdop empty() noexcept { return {}; }
    [[nodiscard]] bool is_empty() const noexcept {
        for (int k = 0; k < N; ++k)
            if (!(h[k] + h[N + k] >= S(0))) return true;
        return false;
    }
    [[nodiscard]] bool is_valid() const noexcept {
        for (int k = 0; k < N; ++k)
            if (!std::isfinite(h[k]) || !std::isfinite(h[N + k]) || h[k] + h[N + k] < S(0)) return false;
        return true;
    }
    /// Lower and upper end of slab k along directions[k] (unnormalised).
    [[nodiscard]] S lo(int k) const noexcept { return -h[N + k]; }
    [[nodiscard]] S hi(int k) const noexcept { return h[k]; }

    /// A volume proxy: the volume of the box formed by the three axis slabs, an upper bound of the DOP's
    /// volume (the exact volume needs the polytope's vertices). Used for refit degradation and statistics.
    [[nodiscard]] S volume() const noexcept {
        return is_empty() ? S(0) : (h[0] + h[N]) * (h[1] + h[N + 1]) * (h[2] + h[N + 2]);
    }
    /// The surface area of the same axis-aligned box (the proxy of volume()).
    [[nodiscard]] S surface_area() const noexcept {
        if (is_empty()) return S(0);
        const S x = h[0] + h[N], y = h[1] + h[N + 1], z = h[2] + h[N + 2];
        return S(2) * (x * y + y * z + z * x);
    }
    /// Used by the traversal to decide which tree to descend: the sum of the axis half extents, as for Aabb.
    [[nodiscard]] S size() const noexcept { return S(0.5) * (h[0] + h[N] + h[1] + h[N + 1] + h[2] + h[N + 2]); }
    /// The unit normal of the widest slab (widths measured along the normalised directions).
    [[nodiscard]] Vec3<S> split_axis() const noexcept {
        int best = 0;
        S width = -std::numeric_limits<S>::infinity();
        for (int k = 0; k < N; ++k) {
            const S w = (h[k] + h[N + k]) / std::sqrt(S(norm2(k)));
            if (w > width) width = w, best = k;
        }
        return Vec3<S>(S(directions[best][0]), S(directions[best][1]), S(directions[best][2])).normalized();
    }
    /// True when p lies in every slab widened by `tol` (a distance).
    [[nodiscard]] bool contains(const Vec3<S>& p, S tol = S(0)) const noexcept {
        for (int k = 0; k < N; ++k) {
            const S x = detail::kdop_project(directions[k], p);
            const S w = tol * std::sqrt(S(norm2(k)));
            if (x > h[k] + w || -x > h[N + k] + w) return false;
        }
        return true;
    }
    /// Smallest K-DOP holding both (exact: a componentwise maximum).
    [[nodiscard]] static Kdop merge(const Kdop& a, const Kdop& b) noexcept {
        Kdop m;
        for (int k = 0; k < K; ++k) m.h[k] = std::max(a.h[k], b.h[k]);
        return m;
    }

    /// Min/max of the vertices' projections on the K/2 directions, padded conservatively: a projection sums
    /// up to three coordinates, so the padding is three times Aabb's (detail::fit_padding).
    [[nodiscard]] static Kdop fit(const TriangleMesh<S>& mesh, TriangleRange tris) noexcept {
        Kdop b;
        if (tris.empty()) return b;
        S magnitude = 0;
        for (Index t : tris)
            for (Index v : mesh.triangles[t]) {
                const Vec3<S>& p = mesh.vertices[v];
                magnitude = std::max(magnitude, p.cwiseAbs().maxCoeff());
                for (int k = 0; k < N; ++k) {
                    const S x = detail::kdop_project(directions[k], p);
                    b.h[k] = std::max(b.h[k], x);
                    b.h[N + k] = std::max(b.h[N + k], -x);
                }
            }
        const S pad = S(3) * detail::fit_padding(magnitude);
        for (S& x : b.h) x += pad;
        return b;
    }

    /// Per-query data: for each of A's K signed directions, B's normals and weights of the certificates
    /// bounding B's extent along it (see the file comment), the translation's projections, and the slack.
    struct Relative {
        static constexpr int C = K == 6 ? 3 : 6;  ///< terms per direction: the fan facet (+ the axes for K > 6)
        std::array<std::array<std::uint8_t, C>, K> plane;
        std::array<std::array<S, C>, K> lambda;
        std::array<S, N> dt;  ///< d_j·t
        S scale;              ///< slack per unit of B's coordinate magnitude
        S t_slack;            ///< slack for the translation's rounding
    };
    [[nodiscard]] static Relative relative(const Transform<S>& b_to_a) noexcept {
        Relative rel;
        const auto& fan = detail::KdopFan<K>::get();
        const Eigen::Matrix<double, 3, 3> Rt = b_to_a.R.template cast<double>().transpose();
        double lambda_max = 0, residual_max = 0;
        auto certify = [&](int k, const Eigen::Matrix<double, 3, 1>& c, const typename detail::KdopFan<K>::Facet& f) {
            Eigen::Matrix<double, 3, 1> l = (f.inverse * c).cwiseMax(0.0);
            Eigen::Matrix<double, 3, 1> r = c;
            double sum = 0;
            for (int m = 0; m < 3; ++m) {
                rel.plane[k][m] = f.plane[m];
                rel.lambda[k][m] = S(l[m]);
                const auto& d = directions[f.plane[m] % N];
                const double s = f.plane[m] < N ? 1.0 : -1.0;
                r -= s * double(rel.lambda[k][m]) * Eigen::Matrix<double, 3, 1>(d[0], d[1], d[2]);
                sum += double(rel.lambda[k][m]);
            }
            lambda_max = std::max(lambda_max, sum);
            residual_max = std::max(residual_max, r.cwiseAbs().sum());
            if constexpr (Relative::C == 6) {
                // The axis certificate: c = Σ |c_i| (sign c_i) e_i, exact in λ.
                for (int i = 0; i < 3; ++i) {
                    rel.plane[k][3 + i] = std::uint8_t(c[i] >= 0 ? i : N + i);
                    rel.lambda[k][3 + i] = S(std::abs(c[i]));
                }
                lambda_max = std::max(lambda_max, c.cwiseAbs().sum());
            }
        };
        for (int j = 0; j < N; ++j) {
            const auto& d = directions[j];
            const Eigen::Matrix<double, 3, 1> c = Rt * Eigen::Matrix<double, 3, 1>(d[0], d[1], d[2]);
            // One pass finds the facet for +c (largest g·c) and for −c (smallest g·c): the fan is symmetric.
            std::size_t fmax = 0, fmin = 0;
            double vmax = -std::numeric_limits<double>::infinity(), vmin = std::numeric_limits<double>::infinity();
            for (std::size_t f = 0; f < fan.facets.size(); ++f) {
                const double v = fan.facets[f].g.dot(c);
                if (v > vmax) vmax = v, fmax = f;
                if (v < vmin) vmin = v, fmin = f;
            }
            certify(j, c, fan.facets[fmax]);
            certify(N + j, -c, fan.facets[fmin]);
            rel.dt[j] = detail::kdop_project(d, b_to_a.t);
        }
        const S eps = std::numeric_limits<S>::epsilon();
        // Rounding of the weighted sums and of the transformed vertices (collide's R·v + t), plus the
        // weights' residual (c − Σ λ D)·x ≤ |residual|₁ |x|∞.
        rel.scale = S(64) * eps * S(lambda_max + 3) + S(2 * residual_max);
        rel.t_slack = S(64) * eps * S(3) * b_to_a.t.cwiseAbs().maxCoeff();
        return rel;
    }

private:
    static constexpr std::array<S, K> filled(S v) noexcept {
        std::array<S, K> a{};
        for (S& x : a) x = v;
        return a;
    }
    static constexpr int norm2(int k) noexcept {
        return directions[k][0] * directions[k][0] + directions[k][1] * directions[k][1] +
               directions[k][2] * directions[k][2];
    }
};

/// Overlap of DOP `a` (in A's frame) with DOP `b` (in B's frame), `rel` taking B's frame to A's: B's DOP is
/// enclosed in an axis-aligned DOP of A's frame (see the file comment) and the K/2 slabs are compared.
/// Conservative: never false when the two DOPs intersect. O(K).
template <class S, int K>
[[nodiscard]] inline bool overlap(const Kdop<S, K>& a, const Kdop<S, K>& b,
                                  const typename Kdop<S, K>::Relative& rel) noexcept {
    constexpr int N = K / 2;
    constexpr int C = Kdop<S, K>::Relative::C;
    // B lies in the box of its axis slabs: |x|∞ ≤ magnitude.
    S magnitude = 0;
    for (int i = 0; i < 3; ++i) magnitude = std::max({magnitude, std::abs(b.h[i]), std::abs(b.h[N + i])});
    const S slack = rel.scale * magnitude + rel.t_slack;
    auto extent = [&](int k) {
        const auto& p = rel.plane[k];
        const auto& l = rel.lambda[k];
        S e = l[0] * b.h[p[0]] + l[1] * b.h[p[1]] + l[2] * b.h[p[2]];
        if constexpr (C == 6) e = std::min(e, l[3] * b.h[p[3]] + l[4] * b.h[p[4]] + l[5] * b.h[p[5]]);
        return e + slack;
    };
    for (int j = 0; j < N; ++j) {
        if (rel.dt[j] + extent(j) < -a.h[N + j]) return false;  // B's image below A's slab
        if (rel.dt[j] - extent(N + j) > a.h[j]) return false;   // above it
    }
    return true;
}

}  // namespace cdkit

// Node layout: K support values, nothing else (a Bvh node adds 8 bytes).
static_assert(sizeof(cdkit::Kdop<double, 26>) == 26 * 8 && sizeof(cdkit::Kdop<float, 14>) == 14 * 4);
