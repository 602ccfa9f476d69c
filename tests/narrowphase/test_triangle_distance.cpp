// triangle_distance() against independent references: a point–triangle closest point by Voronoi regions
// (written separately here), dense barycentric sampling, known parallel and degenerate configurations, and
// the exact intersection test. Fixed seeds.
#include "test_common.hpp"

#include "cdkit/narrowphase/triangle_distance.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <random>

using namespace cdkit;

namespace {

template <class S> using V = Vec3<S>;

// Distance from x to segment [a,b] (independent of the library's segment routine).
template <class S> double point_segment(const V<S>& x, const V<S>& a, const V<S>& b) {
    const V<double> X = x.template cast<double>(), A = a.template cast<double>(), B = b.template cast<double>();
    const V<double> d = B - A;
    const double dd = d.squaredNorm();
    const double t = dd > 0 ? std::clamp((X - A).dot(d) / dd, 0.0, 1.0) : 0.0;
    return (A + t * d - X).norm();
}

// Distance from x to the closed triangle (a,b,c), possibly degenerate: inside test by barycentrics of the
// projection, else the nearest edge.
template <class S> double point_triangle(const V<S>& x, const V<S>& a, const V<S>& b, const V<S>& c) {
    const V<double> X = x.template cast<double>(), A = a.template cast<double>(), B = b.template cast<double>(),
                    C = c.template cast<double>();
    double best = std::min({point_segment(x, a, b), point_segment(x, b, c), point_segment(x, c, a)});
    const V<double> n = (B - A).cross(C - A);
    const double nn = n.squaredNorm();
    if (nn > 0) {
        const V<double> p = X - n * (n.dot(X - A) / nn);
        const double u = n.dot((C - B).cross(p - B)) / nn, v = n.dot((A - C).cross(p - C)) / nn, w = 1 - u - v;
        if (u >= 0 && v >= 0 && w >= 0) best = std::min(best, (X - p).norm());
    }
    return best;
}

// Minimum distance over a barycentric grid of both triangles: an upper bound of the true distance.
template <class S> double sampled(const std::array<V<S>, 3>& P, const std::array<V<S>, 3>& Q, int n) {
    std::vector<V<double>> ps, qs;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
            const double u = double(i) / n, v = double(j) / n, w = 1 - u - v;
            ps.push_back(u * P[0].template cast<double>() + v * P[1].template cast<double>() + w * P[2].template cast<double>());
            qs.push_back(u * Q[0].template cast<double>() + v * Q[1].template cast<double>() + w * Q[2].template cast<double>());
        }
    double best = 1e300;
    // Points of P against the exact triangle Q and vice versa: tighter than point pairs.
    for (const auto& p : ps) best = std::min(best, point_triangle<double>(p, Q[0].template cast<double>(), Q[1].template cast<double>(), Q[2].template cast<double>()));
    for (const auto& q : qs) best = std::min(best, point_triangle<double>(q, P[0].template cast<double>(), P[1].template cast<double>(), P[2].template cast<double>()));
    return best;
}

template <class S> TriangleDistance<S> td(const std::array<V<S>, 3>& P, const std::array<V<S>, 3>& Q) {
    return triangle_distance(P[0], P[1], P[2], Q[0], Q[1], Q[2]);
}

template <class S> double tol() { return std::is_same_v<S, float> ? 2e-5 : 1e-12; }

template <class S> void check_points(const std::array<V<S>, 3>& P, const std::array<V<S>, 3>& Q, const TriangleDistance<S>& d,
                                     double scale) {
    INFO("distance " << d.distance);
    CHECK(point_triangle(d.point_on_p, P[0], P[1], P[2]) <= tol<S>() * scale);
    CHECK(point_triangle(d.point_on_q, Q[0], Q[1], Q[2]) <= tol<S>() * scale);
    CHECK(std::abs((d.point_on_p - d.point_on_q).template cast<double>().norm() - double(d.distance)) <= tol<S>() * scale);
}

}  // namespace

TEMPLATE_TEST_CASE("triangle_distance matches sampling on random pairs", "[distance][triangle]", float, double) {
    using S = TestType;
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-1, 1);
    const int n = test::scaled(400, 400);  // cheap: the hit-rate check needs the full count
    int separated = 0, intersecting = 0;
    for (int k = 0; k < n; ++k) {
        std::array<V<S>, 3> P, Q;
        const V<double> off(u(rng) * 1.2, u(rng) * 1.2, u(rng) * 1.2);
        for (auto& p : P) p = V<double>(u(rng), u(rng), u(rng)).template cast<S>();
        for (auto& q : Q) q = (V<double>(u(rng), u(rng), u(rng)) + off).template cast<S>();
        const TriangleDistance<S> d = td(P, Q);
        const bool hit = triangles_intersect(P[0], P[1], P[2], Q[0], Q[1], Q[2]);
        if (hit) {
            ++intersecting;
            CHECK(d.distance == S(0));
        } else {
            ++separated;
            CHECK(d.distance > S(0));
        }
        check_points(P, Q, d, 4.0);
        const double ref = sampled(P, Q, 24);
        // The true distance is below any sampled value, and above it minus the grid's resolution.
        CHECK(double(d.distance) <= ref + tol<S>() * 4);
        CHECK(double(d.distance) >= ref - 0.2);
    }
    CHECK(separated > n / 5);
    CHECK(intersecting > n / 20);
}

TEMPLATE_TEST_CASE("triangle_distance is invariant under vertex orders and swapping", "[distance][triangle]", float, double) {
    using S = TestType;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int k = 0; k < test::scaled(60, 5); ++k) {
        std::array<V<S>, 3> P, Q;
        for (auto& p : P) p = V<double>(u(rng), u(rng), u(rng)).template cast<S>();
        for (auto& q : Q) q = (V<double>(u(rng), u(rng), u(rng)) + V<double>(1.2, 0, 0)).template cast<S>();
        const double ref = td(P, Q).distance;
        const int perms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
        for (const auto& pp : perms)
            for (const auto& qp : perms) {
                const std::array<V<S>, 3> P2 = {P[pp[0]], P[pp[1]], P[pp[2]]}, Q2 = {Q[qp[0]], Q[qp[1]], Q[qp[2]]};
                CHECK(std::abs(double(td(P2, Q2).distance) - ref) <= tol<S>() * 4);
                CHECK(std::abs(double(td(Q2, P2).distance) - ref) <= tol<S>() * 4);
            }
    }
}

TEMPLATE_TEST_CASE("triangle_distance: parallel faces, parallel edges, degenerate triangles", "[distance][triangle]", float, double) {
    using S = TestType;
    const S g = S(0.25);
    // Parallel, overlapping faces at gap g: every vertex–face and edge–edge candidate ties or exceeds g.
    const std::array<V<S>, 3> P = {V<S>(0, 0, 0), V<S>(1, 0, 0), V<S>(0, 1, 0)};
    const std::array<V<S>, 3> Q = {V<S>(0.1, 0.1, g), V<S>(1.1, 0.1, g), V<S>(0.1, 1.1, g)};
    auto d = td(P, Q);
    CHECK(std::abs(d.distance - g) <= S(tol<S>()));
    check_points(P, Q, d, 1.0);
    // Identical triangle shifted along its normal: all 15 candidates tie.
    const std::array<V<S>, 3> P2 = {P[0] + V<S>(0, 0, g), P[1] + V<S>(0, 0, g), P[2] + V<S>(0, 0, g)};
    d = td(P, P2);
    CHECK(std::abs(d.distance - g) <= S(tol<S>()));
    check_points(P, P2, d, 1.0);
    // Parallel edges side by side, overlapping in extent: faces turned away, so an edge–edge pair decides.
    const std::array<V<S>, 3> E1 = {V<S>(0, 0, 0), V<S>(2, 0, 0), V<S>(1, -1, 0)};
    const std::array<V<S>, 3> E2 = {V<S>(0.5, 0.3, 0), V<S>(3, 0.3, 0), V<S>(1, 1.3, 0.2)};
    d = td(E1, E2);
    CHECK(std::abs(d.distance - S(0.3)) <= S(tol<S>()));
    check_points(E1, E2, d, 3.0);
    // Collinear edges with a gap along their common line.
    const std::array<V<S>, 3> C2 = {V<S>(2.5, 0, 0), V<S>(4, 0, 0), V<S>(3, 1, 0)};
    d = td(E1, C2);
    CHECK(std::abs(d.distance - S(0.5)) <= S(tol<S>()));
    // Zero-area triangles: a segment (collinear vertices, one repeated) and a point.
    const std::array<V<S>, 3> seg = {V<S>(0.2, 0.2, 1), V<S>(0.4, 0.2, 1), V<S>(0.3, 0.2, 1)};
    d = td(P, seg);
    CHECK(std::abs(d.distance - S(1)) <= S(tol<S>()));
    check_points(P, seg, d, 1.0);
    const std::array<V<S>, 3> pt = {V<S>(2, 2, 0), V<S>(2, 2, 0), V<S>(2, 2, 0)};
    d = td(P, pt);
    CHECK(std::abs(double(d.distance) - point_triangle(pt[0], P[0], P[1], P[2])) <= tol<S>() * 4);
    check_points(P, pt, d, 3.0);
    d = td(pt, pt);
    CHECK(d.distance == S(0));
    const std::array<V<S>, 3> pt2 = {V<S>(2, 2, 3), V<S>(2, 2, 3), V<S>(2, 2, 3)};
    d = td(pt, pt2);
    CHECK(std::abs(d.distance - S(3)) <= S(tol<S>()));
    // A segment piercing the face: intersecting, distance 0, witness on both.
    const std::array<V<S>, 3> pierce = {V<S>(0.2, 0.2, -1), V<S>(0.2, 0.2, 1), V<S>(0.2, 0.2, 0.5)};
    d = td(P, pierce);
    CHECK(d.distance == S(0));
    check_points(P, pierce, d, 1.0);
}

TEMPLATE_TEST_CASE("segment closest points: parallel and zero length", "[distance][triangle]", float, double) {
    using S = TestType;
    using detail::closest_points_segments;
    auto c = closest_points_segments<S>(V<S>(0, 0, 0), V<S>(1, 0, 0), V<S>(0.5, 1, 0), V<S>(3, 1, 0));
    CHECK(std::abs(c.dist2 - S(1)) <= S(tol<S>()));
    c = closest_points_segments<S>(V<S>(0, 0, 0), V<S>(1, 0, 0), V<S>(2, 1, 0), V<S>(3, 1, 0));
    CHECK(std::abs(c.dist2 - S(2)) <= S(tol<S>()));  // parallel, disjoint extents: end point to end point
    c = closest_points_segments<S>(V<S>(0, 0, 0), V<S>(0, 0, 0), V<S>(1, 1, 0), V<S>(1, 1, 0));
    CHECK(std::abs(c.dist2 - S(2)) <= S(tol<S>()));
    c = closest_points_segments<S>(V<S>(0, 0, 0), V<S>(0, 0, 0), V<S>(-1, 1, 0), V<S>(1, 1, 0));
    CHECK(std::abs(c.dist2 - S(1)) <= S(tol<S>()));
    c = closest_points_segments<S>(V<S>(-1, 1, 0), V<S>(1, 1, 0), V<S>(0, 0, 0), V<S>(0, 0, 0));
    CHECK(std::abs(c.dist2 - S(1)) <= S(tol<S>()));
    CHECK(c.s == Approx(0.5));
    // Nearly parallel (angle 1e-9): still a true closest pair.
    c = closest_points_segments<S>(V<S>(0, 0, 0), V<S>(1, 0, 0), V<S>(-5, 0.5, 0), V<S>(5, S(0.5 + 1e-9), 0));
    CHECK(std::abs(double(c.dist2) - (0.25 + 5e-10)) <= tol<S>() * 4);  // nearest at x = 0: y = 0.5 + 5e-10
    CHECK(c.s >= S(0));
    CHECK(c.s <= S(1));
}
