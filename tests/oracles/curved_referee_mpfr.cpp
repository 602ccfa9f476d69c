// The curved-shape referee (curved_referee.hpp): the only TU that includes MPFR. Support functions of the shapes
// of convex_shapes.hpp written afresh from their definitions (sphere, box, capsule, cylinder, cone, ellipsoid,
// rounded box, vertex hull), posed by the given doubles, in 269-bit binary floating point (boost::multiprecision's
// MPFR backend); the search and the certificates as the header says.
#include "oracles/curved_referee.hpp"

#include <boost/multiprecision/mpfr.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace cdkit::test::curved {
namespace {

namespace mp = boost::multiprecision;
using R = mp::number<mp::mpfr_float_backend<81, mp::allocate_stack>, mp::et_off>;  // 81 digits: 270 bits

struct V {
    R x[3];
};
V operator+(const V& p, const V& q) { return {{p.x[0] + q.x[0], p.x[1] + q.x[1], p.x[2] + q.x[2]}}; }
V operator-(const V& p, const V& q) { return {{p.x[0] - q.x[0], p.x[1] - q.x[1], p.x[2] - q.x[2]}}; }
V operator-(const V& p) { return {{-p.x[0], -p.x[1], -p.x[2]}}; }
V operator*(const R& s, const V& p) { return {{s * p.x[0], s * p.x[1], s * p.x[2]}}; }
R dot(const V& p, const V& q) { return p.x[0] * q.x[0] + p.x[1] * q.x[1] + p.x[2] * q.x[2]; }
V cross(const V& p, const V& q) {
    return {{p.x[1] * q.x[2] - p.x[2] * q.x[1], p.x[2] * q.x[0] - p.x[0] * q.x[2], p.x[0] * q.x[1] - p.x[1] * q.x[0]}};
}
R norm(const V& p) { return sqrt(dot(p, p)); }
V from(const Vec3<double>& p) { return {{R(p[0]), R(p[1]), R(p[2])}}; }
// ±1 by sign; a zero component may take either extent (both are support points), this takes +.
R sgn(const R& x) { return x < 0 ? R(-1) : R(1); }

/// The support point of the shape in its local frame along w (any w; a zero w gives some point of the shape).
V local_support(const ShapeSpec& s, const V& w) {
    const R a(s.a), b(s.b), c(s.c);
    auto unit_ball = [&](const R& radius) -> V {  // radius · w/|w|
        const R n = norm(w);
        if (n == 0) return {{R(0), R(0), radius}};
        return (radius / n) * w;
    };
    switch (s.kind) {
        case ShapeKind::sphere: return unit_ball(a);
        case ShapeKind::box: return {{sgn(w.x[0]) * a, sgn(w.x[1]) * b, sgn(w.x[2]) * c}};
        case ShapeKind::rounded_box:
            return V{{sgn(w.x[0]) * a, sgn(w.x[1]) * b, sgn(w.x[2]) * c}} + unit_ball(R(s.r));
        case ShapeKind::capsule: return V{{R(0), R(0), sgn(w.x[2]) * b}} + unit_ball(a);
        case ShapeKind::cylinder: {
            const R rho = sqrt(w.x[0] * w.x[0] + w.x[1] * w.x[1]);
            if (rho == 0) return {{R(0), R(0), sgn(w.x[2]) * b}};
            return {{a * w.x[0] / rho, a * w.x[1] / rho, sgn(w.x[2]) * b}};
        }
        case ShapeKind::cone: {
            // The apex (0, 0, b) or the base rim's furthest point (a·w_xy/ρ, −b): whichever is further along w.
            const R rho = sqrt(w.x[0] * w.x[0] + w.x[1] * w.x[1]);
            const R apex = b * w.x[2], rim = a * rho - b * w.x[2];
            if (apex >= rim) return {{R(0), R(0), b}};
            if (rho == 0) return {{R(0), R(0), -b}};
            return {{a * w.x[0] / rho, a * w.x[1] / rho, -b}};
        }
        case ShapeKind::ellipsoid: {
            // max over |diag(1/r)·y| ≤ 1 of w·y = |diag(r)·w|, at y = diag(r)²·w / |diag(r)·w|.
            const V q{{a * w.x[0], b * w.x[1], c * w.x[2]}};
            const R n = norm(q);
            if (n == 0) return {{R(0), R(0), c}};
            return {{a * q.x[0] / n, b * q.x[1] / n, c * q.x[2] / n}};
        }
        case ShapeKind::hull: {
            const auto& vs = *s.vertices;
            std::size_t best = 0;
            R top = -std::numeric_limits<double>::infinity();
            for (std::size_t i = 0; i < vs.size(); ++i) {
                const R d = w.x[0] * vs[i][0] + w.x[1] * vs[i][1] + w.x[2] * vs[i][2];
                if (d > top) top = d, best = i;
            }
            return from(vs[best]);
        }
    }
    return {};
}

double bounding_radius(const ShapeSpec& s) {
    switch (s.kind) {
        case ShapeKind::sphere: return s.a;
        case ShapeKind::box: return std::sqrt(s.a * s.a + s.b * s.b + s.c * s.c);
        case ShapeKind::rounded_box: return std::sqrt(s.a * s.a + s.b * s.b + s.c * s.c) + s.r;
        case ShapeKind::capsule: return s.a + s.b;
        case ShapeKind::cylinder:
        case ShapeKind::cone: return std::sqrt(s.a * s.a + s.b * s.b);
        case ShapeKind::ellipsoid: return std::max({s.a, s.b, s.c});
        case ShapeKind::hull: {
            double m = 0;
            for (const auto& v : *s.vertices) m = std::max(m, v.norm());
            return m;
        }
    }
    return 0;
}

/// A shape posed by x ↦ M·x + t (M the given doubles, orthonormal or not: the support of the posed set along u
/// is M·s(Mᵀu) + t for any linear M).
struct Posed {
    const ShapeSpec* s;
    R m[3][3];
    V t;
    Posed(const ShapeSpec& spec, const Transform<double>& p) : s(&spec), t(from(p.t)) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) m[i][j] = R(p.R(i, j));
    }
    [[nodiscard]] V support(const V& u) const {
        V w;
        for (int j = 0; j < 3; ++j) w.x[j] = m[0][j] * u.x[0] + m[1][j] * u.x[1] + m[2][j] * u.x[2];
        const V y = local_support(*s, w);
        V out;
        for (int i = 0; i < 3; ++i) out.x[i] = m[i][0] * y.x[0] + m[i][1] * y.x[1] + m[i][2] * y.x[2] + t.x[i];
        return out;
    }
};

/// The minimum-norm point of conv(pts) (up to four points), by trying every sub-simplex: the minimum over conv is
/// the affine minimum of the face whose relative interior holds it, and every sub-simplex whose affine minimum has
/// positive weights gives a point of conv; so the least of those is the answer. Returns it and keeps in `pts` only
/// that sub-simplex's points.
struct MinNorm {
    V v;
    R norm2;
};
MinNorm min_norm(std::vector<V>& pts) {
    const int n = int(pts.size());
    MinNorm best{pts[0], dot(pts[0], pts[0])};
    int best_mask = 1;
    bool first = true;
    for (int mask = 1; mask < (1 << n); ++mask) {
        std::array<int, 4> idx{};
        int k = 0;
        for (int i = 0; i < n; ++i)
            if (mask & (1 << i)) idx[std::size_t(k++)] = i;
        const V& p0 = pts[std::size_t(idx[0])];
        if (k == 1) {
            const R nn = dot(p0, p0);
            if (first || nn < best.norm2) best = {p0, nn}, best_mask = mask, first = false;
            continue;
        }
        // G μ = −Qᵀ p0 with Q's columns p_i − p0; Gaussian elimination with partial pivoting on the (k−1)² system.
        const int m = k - 1;
        std::array<V, 3> q;
        R g[3][4];
        R scale = 1;
        for (int i = 0; i < m; ++i) q[std::size_t(i)] = pts[std::size_t(idx[std::size_t(i + 1)])] - p0;
        for (int i = 0; i < m; ++i) {
            for (int j = 0; j < m; ++j) g[i][j] = dot(q[std::size_t(i)], q[std::size_t(j)]);
            g[i][m] = -dot(q[std::size_t(i)], p0);
            scale *= g[i][i];
        }
        if (scale == 0) continue;
        R det = 1;
        bool ok = true;
        for (int col = 0; col < m && ok; ++col) {
            int piv = col;
            for (int r = col + 1; r < m; ++r)
                if (abs(g[r][col]) > abs(g[piv][col])) piv = r;
            if (piv != col)
                for (int j = 0; j <= m; ++j) std::swap(g[piv][j], g[col][j]);
            det *= g[col][col];
            if (g[col][col] == 0) ok = false;
            for (int r = col + 1; r < m && ok; ++r) {
                const R f = g[r][col] / g[col][col];
                for (int j = col; j <= m; ++j) g[r][j] -= f * g[col][j];
            }
        }
        // A (nearly) degenerate sub-simplex: its minimum is one of its faces', tried separately. 1e-60 of the
        // diagonal product, far above 270-bit rounding (~1e-80) and far below any geometry of the corpus.
        if (!ok || abs(det) <= R(1e-60) * scale) continue;
        R mu[3];
        for (int i = m - 1; i >= 0; --i) {
            R sum = g[i][m];
            for (int j = i + 1; j < m; ++j) sum -= g[i][j] * mu[j];
            mu[i] = sum / g[i][i];
        }
        R lambda0 = 1;
        bool positive = true;
        for (int i = 0; i < m; ++i) lambda0 -= mu[i], positive = positive && mu[i] > 0;
        if (!positive || !(lambda0 > 0)) continue;
        V v = p0;
        for (int i = 0; i < m; ++i) v = v + mu[i] * q[std::size_t(i)];
        const R nn = dot(v, v);
        if (nn < best.norm2) best = {v, nn}, best_mask = mask;
    }
    std::vector<V> kept;
    for (int i = 0; i < n; ++i)
        if (best_mask & (1 << i)) kept.push_back(pts[std::size_t(i)]);
    pts.swap(kept);
    return best;
}

/// Certified inward distance of the origin from the faces of the tetrahedron p (its depth inside it), less each
/// face's error bound (the points' error eps times 1 + 2·(longest edge)/(smallest altitude)); ≤ 0: no certificate.
R enclosure_margin(const std::array<V, 4>& p, const R& eps) {
    static constexpr int faces[4][4] = {{0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 3, 1}, {1, 2, 3, 0}};
    R margin = std::numeric_limits<double>::infinity();
    for (const auto& f : faces) {
        const V& a = p[std::size_t(f[0])];
        const V e1 = p[std::size_t(f[1])] - a, e2 = p[std::size_t(f[2])] - a, e3 = p[std::size_t(f[2])] - p[std::size_t(f[1])];
        V n = cross(e1, e2);
        const R nn = norm(n);
        if (nn == 0) return R(-1);
        const R side = dot(n, p[std::size_t(f[3])] - a);
        if (side == 0) return R(-1);
        if (side < 0) n = -n;
        const R dist = -dot(n, a) / nn;
        const R longest2 = std::max({dot(e1, e1), dot(e2, e2), dot(e3, e3)});
        const R err = eps * (1 + 2 * longest2 / nn);
        margin = std::min(margin, dist - err);
    }
    return margin;
}

struct Search {
    const Posed& A;
    const Posed& B;
    V offset;  // D = B − A − offset
    R eps;     // the evaluation error bound of a compared quantity
    R scale;   // the scene's scale Σ
    [[nodiscard]] V sd(const V& u) const { return B.support(u) - A.support(-u) - offset; }
};

/// Tries to enclose the origin in a tetrahedron of support points of D: the kept simplex (the origin on or near
/// it) plus the support points along ± the directions normal to it and ± eight directions in general position
/// (axis directions alone leave the origin on a face for shapes symmetric about the axes); the 4-subsets holding
/// the whole simplex first, then every other, until one certifies. Returns its margin (≤ 0: none).
R enclose(const Search& s, const std::vector<V>& simplex) {
    static constexpr double generic[4][3] = {{1, 0.31, -0.53}, {-0.47, 1, 0.29}, {0.37, -0.61, 1}, {0.71, 0.83, 0.91}};
    std::vector<V> dirs;
    if (simplex.size() == 2) {
        const V d = simplex[1] - simplex[0];
        const V n1 = cross(d, V{{R(0.31), R(-0.53), R(1)}}), n2 = cross(d, n1);
        dirs = {n1, -n1, n2, -n2};
    } else if (simplex.size() == 3) {
        const V n = cross(simplex[1] - simplex[0], simplex[2] - simplex[0]);
        dirs = {n, -n};
    }
    for (const auto& g : generic) {
        const V e{{R(g[0]), R(g[1]), R(g[2])}};
        dirs.push_back(e), dirs.push_back(-e);
    }
    std::vector<V> pts = simplex;
    for (const V& d : dirs)
        if (dot(d, d) > 0) pts.push_back(s.sd(d));
    const std::size_t n = pts.size(), fixed = simplex.size();
    auto holds_simplex = [&](std::size_t i, std::size_t j, std::size_t k, std::size_t l) {
        std::size_t in = 0;
        for (std::size_t x : {i, j, k, l}) in += x < fixed;
        return in == std::min<std::size_t>(fixed, 4);
    };
    for (int pass = 0; pass < 2; ++pass)
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i + 1; j < n; ++j)
                for (std::size_t k = j + 1; k < n; ++k)
                    for (std::size_t l = k + 1; l < n; ++l) {
                        if (holds_simplex(i, j, k, l) != (pass == 0)) continue;
                        const R m = enclosure_margin({pts[i], pts[j], pts[k], pts[l]}, s.eps);
                        if (m > 0) return m;
                    }
    return R(-1);
}

double round_down(const R& x) {
    const double d = x.convert_to<double>();
    return R(d) <= x ? d : std::nextafter(d, -std::numeric_limits<double>::infinity());
}
double round_up(const R& x) {
    const double d = x.convert_to<double>();
    return R(d) >= x ? d : std::nextafter(d, std::numeric_limits<double>::infinity());
}

CurvedAnswer search(const Search& s, V dir, bool may_offset = true) {
    constexpr int max_iterations = 200;
    CurvedAnswer out;
    if (dot(dir, dir) == 0) dir = V{{R(1), R(0), R(0)}};
    std::vector<V> simplex{s.sd(-dir)};
    MinNorm mn{simplex[0], dot(simplex[0], simplex[0])};
    R lower = -1, upper = std::numeric_limits<double>::infinity();
    const R tiny2 = s.eps * s.eps;
    for (int it = 1; it <= max_iterations; ++it) {
        out.iterations = it;
        if (mn.norm2 <= tiny2) break;  // the origin is (numerically) on the simplex: try to enclose it below
        const R hi = sqrt(mn.norm2);
        upper = std::min(upper, hi + s.eps);
        const V w = s.sd(-mn.v);
        const R vw = dot(mn.v, w);
        lower = std::max(lower, vw / hi - s.eps);  // min over D of v̂·d, less its error
        // Separated and converged (the interval 1e-24 of the distance wide), or no further progress.
        if (lower > 0 && upper - lower <= R(1e-24) * upper) break;
        if (mn.norm2 - vw <= R(1e-60) * mn.norm2) break;
        simplex.push_back(w);
        mn = min_norm(simplex);
        if (simplex.size() == 4) {  // the origin inside the tetrahedron (the full simplex was the minimum)
            const R margin = enclosure_margin({simplex[0], simplex[1], simplex[2], simplex[3]}, s.eps);
            if (margin > 0) {
                out.verdict = Verdict::intersecting;
                out.depth_lower = round_down(margin);
                if (out.depth_lower <= 0) out.depth_lower = std::numeric_limits<double>::denorm_min();
                return out;
            }
            break;
        }
    }
    if (lower > 0) {
        out.verdict = Verdict::separated;
        out.lower = round_down(lower);
        out.upper = round_up(upper);
        return out;
    }
    // The origin on or near the simplex: enclose it with more support points, or undecided.
    if (mn.norm2 <= R(1e-20) * s.scale * s.scale) {
        R margin = enclose(s, simplex);
        if (!(margin > 0) && may_offset) {
            // Coincident shapes (D symmetric about the origin: two equal cones' rim-to-rim differences put the
            // origin on a plane of support points) can leave every tetrahedron flat through the origin. Six points
            // ±c·e_k off it break the symmetry: all inside D puts their octahedron, and the ball of radius c/√3
            // about the origin, inside D.
            const R c = R(1e-30) * s.scale;
            bool all_inside = true;
            for (int k = 0; k < 3 && all_inside; ++k)
                for (int sg : {1, -1}) {
                    Search shifted = s;
                    shifted.offset.x[k] += sg * c;
                    if (search(shifted, dir, false).verdict != Verdict::intersecting) {
                        all_inside = false;
                        break;
                    }
                }
            if (all_inside) margin = c / sqrt(R(3)) - s.eps;
        }
        if (margin > 0) {
            out.verdict = Verdict::intersecting;
            out.depth_lower = std::max(round_down(margin), std::numeric_limits<double>::denorm_min());
        }
    }
    return out;
}

double scene_scale(const ShapeSpec& a, const Transform<double>& pa, const ShapeSpec& b, const Transform<double>& pb) {
    return std::max(pa.t.norm(), pb.t.norm()) + bounding_radius(a) + bounding_radius(b);
}

}  // namespace

CurvedAnswer curved_referee(const ShapeSpec& a, const Transform<double>& pa, const ShapeSpec& b,
                            const Transform<double>& pb, const Vec3<double>& hint) {
    const Posed A(a, pa), B(b, pb);
    const double sigma = scene_scale(a, pa, b, pb);
    const Search s{A, B, V{{R(0), R(0), R(0)}}, R(1e-70) * R(sigma), R(sigma)};
    V dir = from(hint);
    if (dot(dir, dir) == 0) dir = from(pb.t) - from(pa.t);
    return search(s, dir);
}

int depth_exceeds(const ShapeSpec& a, const Transform<double>& pa, const ShapeSpec& b, const Transform<double>& pb,
                  double rho) {
    const Posed A(a, pa), B(b, pb);
    const double sigma = scene_scale(a, pa, b, pb);
    const R c = sqrt(R(3)) * R(rho);
    bool all_inside = true;
    for (int k = 0; k < 3; ++k)
        for (int sg : {1, -1}) {
            V q{{R(0), R(0), R(0)}};
            q.x[k] = sg * c;
            const Search s{A, B, q, R(1e-70) * R(sigma), R(sigma)};
            // Start towards the point: the origin of D − q is q away from the centre of D's interior, roughly.
            const CurvedAnswer r = search(s, from(pb.t) - from(pa.t) - q);
            if (r.verdict == Verdict::separated) return -1;
            all_inside = all_inside && r.verdict == Verdict::intersecting;
        }
    return all_inside ? 1 : 0;
}

Vec3<double> support_point(const ShapeSpec& s, const Transform<double>& pose, const Vec3<double>& u) {
    const Posed p(s, pose);
    const V x = p.support(from(u));
    return {x.x[0].convert_to<double>(), x.x[1].convert_to<double>(), x.x[2].convert_to<double>()};
}

}  // namespace cdkit::test::curved
