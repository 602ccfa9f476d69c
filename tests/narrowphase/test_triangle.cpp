// Triangle–triangle test and orientation predicates, without the CGAL oracle (that is in
// test_triangle_cgal.cpp): sign conventions, exactness against integer arithmetic over the documented
// exponent range, hand-made touching/degenerate cases, hit rates, invariance under the 36 vertex orders and
// swapping, witness points on both triangles, and how often floating_point mode gets it wrong.
#include "test_common.hpp"
#include "triangle_cases.hpp"

#include "cdkit/core/predicates.hpp"
#include "cdkit/narrowphase/triangle.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

using namespace cdkit;
namespace tri = cdkit::test::tri;

namespace {

using i128 = __int128;

int sgn(i128 v) { return (v > 0) - (v < 0); }

/// Exact det[a−d; b−d; c−d] of integer points (|coordinates| < 2^22: products fit easily in 128 bits).
i128 det3(const std::int64_t (&a)[3], const std::int64_t (&b)[3], const std::int64_t (&c)[3], const std::int64_t (&d)[3]) {
    const i128 u[3] = {a[0] - d[0], a[1] - d[1], a[2] - d[2]};
    const i128 v[3] = {b[0] - d[0], b[1] - d[1], b[2] - d[2]};
    const i128 w[3] = {c[0] - d[0], c[1] - d[1], c[2] - d[2]};
    return u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

// Wide arithmetic for the distance check: the witness points are within an ulp or so of both triangles,
// and a double closest-point computation has errors of many ulps of its own on thin triangles.
#if defined(__SIZEOF_FLOAT128__)
using Wide = __float128;
#else
using Wide = long double;
#endif
struct W3 {
    Wide x, y, z;
};
W3 operator-(const W3& a, const W3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
W3 operator+(const W3& a, const W3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
W3 operator*(const W3& a, Wide s) { return {a.x * s, a.y * s, a.z * s}; }
Wide dot(const W3& a, const W3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class S> W3 wide(const Vec3<S>& v) { return {Wide(v.x()), Wide(v.y()), Wide(v.z())}; }

/// Squared distance from p to the closed triangle (a, b, c) (Ericson, Real-Time Collision Detection
/// §5.1.5), in Wide arithmetic; for non-degenerate triangles.
Wide dist2_point_triangle(const W3& p, const W3& a, const W3& b, const W3& c) {
    const W3 ab = b - a, ac = c - a, ap = p - a;
    const Wide d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return dot(ap, ap);
    const W3 bp = p - b;
    const Wide d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return dot(bp, bp);
    const Wide vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const W3 e = p - (a + ab * (d1 / (d1 - d3)));
        return dot(e, e);
    }
    const W3 cp = p - c;
    const Wide d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return dot(cp, cp);
    const Wide vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const W3 e = p - (a + ac * (d2 / (d2 - d6)));
        return dot(e, e);
    }
    const Wide va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const W3 e = p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
        return dot(e, e);
    }
    const Wide den = 1 / (va + vb + vc);
    const W3 e = p - (a + ab * (vb * den) + ac * (vc * den));
    return dot(e, e);
}

template <class S> using T3 = std::array<Vec3<S>, 3>;

template <class S>
bool intersect_in_order(const T3<S>& p, const T3<S>& q, int pi, int qi, bool swap, PredicateMode m) {
    const int* a = tri::kPerm[pi];
    const int* b = tri::kPerm[qi];
    if (swap) return triangles_intersect(q[b[0]], q[b[1]], q[b[2]], p[a[0]], p[a[1]], p[a[2]], m);
    return triangles_intersect(p[a[0]], p[a[1]], p[a[2]], q[b[0]], q[b[1]], q[b[2]], m);
}

template <class S> Vec3<S> v3(double x, double y, double z) { return Vec3<S>(S(x), S(y), S(z)); }

}  // namespace

// ---- predicates ----------------------------------------------------------------------------------

TEST_CASE("orient3d and orient2d follow Shewchuk's sign conventions", "[triangle][predicates]") {
    const Vec3<double> a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    // a, b, c counterclockwise seen from +z: a point below (−z) is positive.
    CHECK(orient3d(a, b, c, Vec3<double>(0.3, 0.3, -1)) == 1);
    CHECK(orient3d(a, b, c, Vec3<double>(0.3, 0.3, 1)) == -1);
    CHECK(orient3d(a, b, c, Vec3<double>(7, -3, 0)) == 0);
    CHECK(orient3d(a, b, c, Vec3<double>(0.3, 0.3, -1), PredicateMode::floating_point) == 1);
    CHECK(orient3d<float>(a.cast<float>(), b.cast<float>(), c.cast<float>(), Vec3<float>(0, 0, 1)) == -1);
    using V2 = Eigen::Matrix<double, 2, 1>;
    CHECK(orient2d(V2(0, 0), V2(1, 0), V2(0, 1)) == 1);
    CHECK(orient2d(V2(0, 0), V2(0, 1), V2(1, 0)) == -1);
    CHECK(orient2d(V2(0, 0), V2(1, 1), V2(3, 3)) == 0);
    // Nearly collinear points (after Kettner et al., "Classroom examples of robustness problems in geometric
    // computations"): exactly, orient2d(x, q, r) = 12·(x.y − x.x), which plain floating point loses.
    const V2 q(12, 12), r(24, 24);
    int disagreements = 0;
    for (int i = 0; i < 64; ++i)
        for (int j = 0; j < 64; ++j) {
            const V2 x(0.5 + i * 0x1p-53, 0.5 + j * 0x1p-53);
            const int exact = orient2d(x, q, r);
            CHECK(exact == (j > i ? 1 : (j < i ? -1 : 0)));
            if (exact != orient2d(x, q, r, PredicateMode::floating_point)) ++disagreements;
        }
    INFO("orient2d floating-point disagreements near (0.5,0.5): " << disagreements << " / 4096");
    CHECK(disagreements > 0);
}

TEST_CASE("orient3d and orient2d are exact on integer input scaled across the documented range",
          "[triangle][predicates]") {
    // Coordinates k·2^e_axis with |k| < 2^20, e per axis in [-280, 260]: every nonzero magnitude in
    // [2^-280, 2^280]. Scaling an axis by a power of two scales the determinant by it, so the sign of the
    // integer determinant is the exact answer.
    tri::Rng rng(0x0123'4567);
    const int n = test::scaled(20000, 200);
    int zeros = 0, fp_wrong = 0;
    for (int it = 0; it < n; ++it) {
        std::int64_t P[4][3];
        const int mag = rng.integer(1, 20);
        const int lim = (1 << mag) - 1;
        for (auto& p : P)
            for (auto& x : p) x = rng.integer(-lim, lim);
        const int mode = rng.integer(0, 2);
        if (mode >= 1) {  // d near or in the plane of a, b, c
            const int s = rng.integer(-8, 8), t = rng.integer(-8, 8), den = mode == 1 ? 1 : 8;
            for (int k = 0; k < 3; ++k)
                P[3][k] = P[0][k] + (s * (P[1][k] - P[0][k]) + t * (P[2][k] - P[0][k])) / den;
            if (std::abs(P[3][0]) >= (1 << 21) || std::abs(P[3][1]) >= (1 << 21) || std::abs(P[3][2]) >= (1 << 21))
                continue;
        }
        const int expected = sgn(det3(P[0], P[1], P[2], P[3]));
        zeros += expected == 0;
        int e[3];
        for (int& x : e) x = rng.integer(-280, 260);
        detail::Point3d D[4];
        for (int i = 0; i < 4; ++i)
            D[i] = {std::ldexp(double(P[i][0]), e[0]), std::ldexp(double(P[i][1]), e[1]), std::ldexp(double(P[i][2]), e[2])};
        REQUIRE(detail::orient3d_filtered(D[0], D[1], D[2], D[3]) == expected);
        REQUIRE(detail::orient3d_exact(D[0], D[1], D[2], D[3]) == expected);
        REQUIRE(detail::orient3d_adapt(D[0], D[1], D[2], D[3], nullptr) == expected);
        // Each intermediate stage, where it claims to decide, must agree.
        int sign_b;
        if (detail::orient3d_if_error_free(D[0], D[1], D[2], D[3], sign_b, nullptr)) REQUIRE(sign_b == expected);
        double perm;
        const detail::DoubleDouble r = detail::orient3d_dd(D[0], D[1], D[2], D[3], perm);
        if (std::abs(r.hi) > 0x1p-99 * perm) REQUIRE((r.hi > 0 ? 1 : -1) == expected);
        const detail::Orient3dPlane plane(D[0], D[1], D[2]);
        REQUIRE(plane.sign(D[3]) == expected);
        const Vec3<double> va(D[0].x, D[0].y, D[0].z), vb(D[1].x, D[1].y, D[1].z), vc(D[2].x, D[2].y, D[2].z),
            vd(D[3].x, D[3].y, D[3].z);
        REQUIRE(orient3d(va, vb, vc, vd) == expected);
        if (orient3d(va, vb, vc, vd, PredicateMode::floating_point) != expected) ++fp_wrong;
        // orient2d on the (x, y) projection.
        const i128 o2 = i128(P[0][0] - P[2][0]) * (P[1][1] - P[2][1]) - i128(P[0][1] - P[2][1]) * (P[1][0] - P[2][0]);
        const detail::Point2d A{D[0].x, D[0].y}, B{D[1].x, D[1].y}, C{D[2].x, D[2].y};
        REQUIRE(detail::orient2d_filtered(A, B, C) == sgn(o2));
        REQUIRE(detail::orient2d_exact(A, B, C) == sgn(o2));
    }
    INFO("coplanar cases " << zeros << ", floating-point sign wrong in " << fp_wrong << " of " << n);
    CHECK(zeros > n / 10);
}

TEST_CASE("expansion estimates and orient3d_accurate are accurate to a few ulps", "[triangle][predicates]") {
    tri::Rng rng(77);
    const int n = test::scaled(5000, 100);
    double worst_est = 0, worst_acc = 0;
    for (int it = 0; it < n; ++it) {
        std::int64_t P[4][3];
        for (auto& p : P)
            for (auto& x : p) x = rng.integer(-(1 << 20), 1 << 20);
        if (rng.coin()) {
            const int s = rng.integer(-8, 8), t = rng.integer(-8, 8);
            for (int k = 0; k < 3; ++k) P[3][k] = P[0][k] + (s * (P[1][k] - P[0][k]) + t * (P[2][k] - P[0][k])) / 8;
            if (std::abs(P[3][0]) >= (1 << 21) || std::abs(P[3][1]) >= (1 << 21) || std::abs(P[3][2]) >= (1 << 21))
                continue;
        }
        const i128 exact = det3(P[0], P[1], P[2], P[3]);
        const double ex = double(exact);  // int128 → double is correctly rounded
        detail::Point3d D[4];
        for (int i = 0; i < 4; ++i) D[i] = {double(P[i][0]), double(P[i][1]), double(P[i][2])};
        double est;
        detail::orient3d_exact(D[0], D[1], D[2], D[3], &est);
        const double acc = detail::orient3d_accurate(D[0], D[1], D[2], D[3]);
        if (exact == 0) {
            REQUIRE(est == 0);
            REQUIRE(acc == 0);
            continue;
        }
        worst_est = std::max(worst_est, std::abs(est - ex) / std::abs(ex));
        worst_acc = std::max(worst_acc, std::abs(acc - ex) / std::abs(ex));
    }
    INFO("worst relative error: expansion estimate " << worst_est << ", orient3d_accurate " << worst_acc);
    CHECK(worst_est <= 4 * 0x1p-53);
    CHECK(worst_acc <= 4 * 0x1p-53);
}

// ---- hand-made cases -----------------------------------------------------------------------------

TEMPLATE_TEST_CASE("triangle test: hand-made touching, coplanar and degenerate cases", "[triangle]", float, double) {
    using S = TestType;
    const T3<S> P = {v3<S>(0, 0, 0), v3<S>(1, 0, 0), v3<S>(0, 1, 0)};
    struct Case {
        const char* what;
        T3<S> q;
        bool expected;
    };
    const S tiny = std::ldexp(S(1), -100);
    const Case cases[] = {
        {"parallel above", {v3<S>(0, 0, 1), v3<S>(1, 0, 1), v3<S>(0, 1, 1)}, false},
        {"crossing", {v3<S>(0.2, 0.2, -1), v3<S>(0.3, 0.2, 1), v3<S>(0.2, 0.3, 1)}, true},
        {"shared vertex only", {v3<S>(0, 0, 0), v3<S>(-1, -1, 1), v3<S>(-1, 0, 1)}, true},
        {"vertex on face", {v3<S>(0.25, 0.25, 0), v3<S>(0, 0, 1), v3<S>(1, 0, 1)}, true},
        {"vertex 2^-100 above face", {v3<S>(0.25, 0.25, 0) + Vec3<S>(0, 0, tiny), v3<S>(0, 0, 1), v3<S>(1, 0, 1)}, false},
        {"edge touches edge", {v3<S>(0.5, -1, 1), v3<S>(0.5, 1, -1), v3<S>(0.5, -1, -1)}, true},
        {"vertical edge touches edge", {v3<S>(0.5, 0, 1), v3<S>(0.5, 0, -1), v3<S>(0.5, -1, 0)}, true},
        {"vertical edge 2^-100 beside edge",
         {v3<S>(0.5, 0, 1) - Vec3<S>(0, tiny, 0), v3<S>(0.5, 0, -1) - Vec3<S>(0, tiny, 0), v3<S>(0.5, -1, 0)},
         false},
        {"shared edge, folded", {v3<S>(0, 0, 0), v3<S>(1, 0, 0), v3<S>(0, 0, 1)}, true},
        {"coplanar overlap", {v3<S>(0.2, 0.2, 0), v3<S>(2, 0.2, 0), v3<S>(0.2, 2, 0)}, true},
        {"coplanar vertex touch", {v3<S>(1, 0, 0), v3<S>(2, 0, 0), v3<S>(2, 1, 0)}, true},
        {"coplanar disjoint", {v3<S>(1, 1, 0), v3<S>(2, 1, 0), v3<S>(1, 2, 0)}, false},
        {"coplanar shared hypotenuse", {v3<S>(1, 0, 0), v3<S>(0, 1, 0), v3<S>(1, 1, 0)}, true},
        {"coplanar contained", {v3<S>(0.1, 0.1, 0), v3<S>(0.2, 0.1, 0), v3<S>(0.1, 0.2, 0)}, true},
        {"identical", P, true},
        {"segment through face", {v3<S>(0.25, 0.25, -1), v3<S>(0.25, 0.25, 1), v3<S>(0.25, 0.25, 0.5)}, true},
        {"segment ending on face", {v3<S>(0.25, 0.25, 0), v3<S>(0.25, 0.25, 1), v3<S>(0.25, 0.25, 0.5)}, true},
        {"segment beside face", {v3<S>(1, 1, -1), v3<S>(1, 1, 1), v3<S>(1, 1, 0)}, false},
        {"segment in plane, crossing", {v3<S>(-1, 0.5, 0), v3<S>(2, 0.5, 0), v3<S>(0.5, 0.5, 0)}, true},
        {"segment in plane, outside", {v3<S>(-1, 2.5, 0), v3<S>(2, -0.5, 0), v3<S>(0.5, 1, 0)}, false},
        {"segment in plane along hypotenuse", {v3<S>(2, -1, 0), v3<S>(-1, 2, 0), v3<S>(0.5, 0.5, 0)}, true},
        {"point on edge", {v3<S>(0.5, 0, 0), v3<S>(0.5, 0, 0), v3<S>(0.5, 0, 0)}, true},
        {"point off plane", {v3<S>(0.1, 0.1, 1), v3<S>(0.1, 0.1, 1), v3<S>(0.1, 0.1, 1)}, false},
        {"point in plane outside", {v3<S>(0.6, 0.6, 0), v3<S>(0.6, 0.6, 0), v3<S>(0.6, 0.6, 0)}, false},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        for (int pi = 0; pi < 6; ++pi)
            for (int qi = 0; qi < 6; ++qi)
                for (bool swap : {false, true})
                    REQUIRE(intersect_in_order(P, c.q, pi, qi, swap, PredicateMode::filtered_exact) == c.expected);
        const auto x = triangle_intersection(P[0], P[1], P[2], c.q[0], c.q[1], c.q[2]);
        REQUIRE(x.intersect == c.expected);
    }
    // Both degenerate.
    const T3<S> seg = {v3<S>(0, 0, 0), v3<S>(2, 2, 2), v3<S>(1, 1, 1)};
    CHECK(triangles_intersect(seg[0], seg[1], seg[2], v3<S>(0, 2, 0), v3<S>(2, 0, 2), v3<S>(1, 1, 1)));  // cross at (1,1,1)
    CHECK(triangles_intersect(seg[0], seg[1], seg[2], v3<S>(0, 2, 1), v3<S>(2, 0, 1), v3<S>(1, 1, 3)));  // (1,1,1) on an edge
    CHECK(!triangles_intersect(seg[0], seg[1], seg[2], v3<S>(0, 2, 1.5), v3<S>(2, 0, 1.5), v3<S>(1, 1, 3)));
    CHECK(!triangles_intersect(seg[0], seg[1], seg[2], v3<S>(0, 2, 0), v3<S>(2, 0, 0), v3<S>(1, 1, 0)));  // skew
    CHECK(triangles_intersect(seg[0], seg[1], seg[2], v3<S>(2, 2, 2), v3<S>(3, 3, 3), v3<S>(5, 5, 5)));  // collinear touch
    CHECK(!triangles_intersect(seg[0], seg[1], seg[2], v3<S>(2.5, 2.5, 2.5), v3<S>(3, 3, 3), v3<S>(5, 5, 5)));
    CHECK(triangles_intersect(seg[0], seg[0], seg[0], seg[0], seg[0], seg[0]));  // point = point
    CHECK(!triangles_intersect(seg[0], seg[0], seg[0], seg[2], seg[2], seg[2]));
    CHECK(triangles_intersect(seg[2], seg[2], seg[2], seg[0], seg[1], seg[0]));  // point on segment
}

TEMPLATE_TEST_CASE("triangle_intersection: witness segments of hand-made cases", "[triangle]", float, double) {
    using S = TestType;
    const T3<S> P = {v3<S>(0, 0, 0), v3<S>(1, 0, 0), v3<S>(0, 1, 0)};
    auto same = [](const Vec3<S>& a, const Vec3<S>& b) { return (a - b).norm() <= S(8) * std::numeric_limits<S>::epsilon(); };
    auto seg_is = [&](const TriangleIntersection<S>& x, const Vec3<S>& a, const Vec3<S>& b) {
        return (same(x.a, a) && same(x.b, b)) || (same(x.a, b) && same(x.b, a));
    };
    {
        const auto x = triangle_intersection(P[0], P[1], P[2], v3<S>(0.2, 0.2, -1), v3<S>(0.3, 0.2, 1), v3<S>(0.2, 0.3, 1));
        REQUIRE(x.intersect);
        CHECK(!x.coplanar);
        CHECK(seg_is(x, v3<S>(0.25, 0.2, 0), v3<S>(0.2, 0.25, 0)));
    }
    {
        const auto x = triangle_intersection(P[0], P[1], P[2], v3<S>(0.5, -1, 1), v3<S>(0.5, 1, -1), v3<S>(0.5, -1, -1));
        REQUIRE(x.intersect);
        CHECK(seg_is(x, v3<S>(0.5, 0, 0), v3<S>(0.5, 0, 0)));
    }
    {
        const auto x = triangle_intersection(P[0], P[1], P[2], v3<S>(0, 0, 0), v3<S>(1, 0, 0), v3<S>(0, 0, 1));
        REQUIRE(x.intersect);
        CHECK(seg_is(x, v3<S>(0, 0, 0), v3<S>(1, 0, 0)));
    }
    {
        // Q crosses all of P: the segment is P's part of the line.
        const auto x = triangle_intersection(P[0], P[1], P[2], v3<S>(-1, 0.5, -1), v3<S>(3, 0.5, -1), v3<S>(-1, 0.5, 3));
        REQUIRE(x.intersect);
        CHECK(seg_is(x, v3<S>(0, 0.5, 0), v3<S>(0.5, 0.5, 0)));
    }
    {
        const auto x = triangle_intersection(P[0], P[1], P[2], v3<S>(0.5, 0, 0), v3<S>(1, 0, 0), v3<S>(1, 1, 0));
        REQUIRE(x.intersect);
        CHECK(x.coplanar);
        // Overlap polygon (0.5,0), (1,0), (2/3,1/3): its diameter is (0.5,0)–(1,0).
        CHECK(seg_is(x, v3<S>(0.5, 0, 0), v3<S>(1, 0, 0)));
    }
    {
        const auto x = triangle_intersection(P[0], P[1], P[2], v3<S>(0.25, 0.25, -1), v3<S>(0.25, 0.25, 1),
                                             v3<S>(0.25, 0.25, 0.5));
        REQUIRE(x.intersect);
        CHECK(!x.coplanar);
        CHECK(seg_is(x, v3<S>(0.25, 0.25, 0), v3<S>(0.25, 0.25, 0)));
    }
    {
        const auto x = triangle_intersection(P[0], P[1], P[2], v3<S>(-1, 0.5, 0), v3<S>(2, 0.5, 0), v3<S>(0.5, 0.5, 0));
        REQUIRE(x.intersect);
        CHECK(seg_is(x, v3<S>(0, 0.5, 0), v3<S>(0.5, 0.5, 0)));
    }
    {
        const auto x = triangle_intersection(P[0], P[1], P[2], v3<S>(0, 0, 1), v3<S>(1, 0, 1), v3<S>(0, 1, 1));
        CHECK(!x.intersect);
        CHECK(!x.coplanar);
    }
}

// ---- generated cases -----------------------------------------------------------------------------

TEMPLATE_TEST_CASE("triangle test: hit rates on random pairs", "[triangle]", float, double) {
    using S = TestType;
    tri::Rng rng(2024);
    const int n = test::scaled(20000, 200);
    int hits = 0;
    for (int i = 0; i < n; ++i) {
        const auto x = tri::as<S>(tri::generate(tri::Kind::random, rng));
        const bool r = triangles_intersect(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2]);
        hits += r;
        REQUIRE(triangle_intersection(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2]).intersect == r);
    }
    INFO("random pairs intersecting: " << hits << " / " << n);
    CHECK(hits > n / 10);
    CHECK(hits < n * 9 / 10);
}

TEMPLATE_TEST_CASE("triangle test: same answer for all 36 vertex orders, both argument orders and exact rigid moves", "[triangle]", float,
                   double) {
    using S = TestType;
    const int per_kind = test::scaled(3000, 20);
    for (int k = 0; k < static_cast<int>(tri::Kind::count); ++k) {
        const auto kind = static_cast<tri::Kind>(k);
        tri::Rng rng(1000 + k);
        int hits = 0;
        for (int i = 0; i < per_kind; ++i) {
            const auto x = tri::as<S>(tri::generate(kind, rng));
            const bool ref = intersect_in_order(x.p, x.q, 0, 0, false, PredicateMode::filtered_exact);
            hits += ref;
            int differing = 0;
            for (int pi = 0; pi < 6; ++pi)
                for (int qi = 0; qi < 6; ++qi)
                    for (bool swap : {false, true})
                        differing += intersect_in_order(x.p, x.q, pi, qi, swap, PredicateMode::filtered_exact) != ref;
            // Exact rigid motions (and reflections): signed permutations of the axes move no bit.
            for (int m = 0; m < 4; ++m) {
                const int perm = rng.integer(0, 5);
                const Vec3<S> sign(rng.coin() ? 1 : -1, rng.coin() ? 1 : -1, rng.coin() ? 1 : -1);
                auto move = [&](const Vec3<S>& v) -> Vec3<S> {
                    const int* a = tri::kPerm[perm];
                    return Vec3<S>(v[a[0]], v[a[1]], v[a[2]]).cwiseProduct(sign);
                };
                T3<S> p, q;
                for (int j = 0; j < 3; ++j) {
                    p[j] = move(x.p[j]);
                    q[j] = move(x.q[j]);
                }
                differing += intersect_in_order(p, q, m, 5 - m, m % 2 == 1, PredicateMode::filtered_exact) != ref;
            }
            if (differing != 0) {
                INFO(tri::name(kind) << " case " << i);
                REQUIRE(differing == 0);
            }
        }
        INFO(tri::name(kind) << ": " << hits << " / " << per_kind << " intersect");
        // Every family must produce both answers, or the invariance check is vacuous for it; triangles
        // sharing a vertex or an edge always touch.
        if (kind == tri::Kind::shared_vertex || kind == tri::Kind::shared_edge) {
            CHECK(hits == per_kind);
        } else {
            CHECK(hits > per_kind / 20);
            CHECK(hits < per_kind - per_kind / 20);
        }
    }
}

TEMPLATE_TEST_CASE("triangle_intersection: witness points lie on both triangles (random pairs)", "[triangle]", float,
                   double) {
    using S = TestType;
    tri::Rng rng(99);
    const int n = test::scaled(20000, 200);
    double worst = 0;
    int hits = 0;
    for (int i = 0; i < n; ++i) {
        const auto x = tri::as<S>(tri::generate(tri::Kind::random, rng));
        const auto r = triangle_intersection(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2]);
        if (!r.intersect) continue;
        ++hits;
        double M = 0;
        for (int j = 0; j < 3; ++j) M = std::max({M, double(x.p[j].cwiseAbs().maxCoeff()), double(x.q[j].cwiseAbs().maxCoeff())});
        for (const Vec3<S>& w : {r.a, r.b}) {
            const Wide dp = dist2_point_triangle(wide(w), wide(x.p[0]), wide(x.p[1]), wide(x.p[2]));
            const Wide dq = dist2_point_triangle(wide(w), wide(x.q[0]), wide(x.q[1]), wide(x.q[2]));
            worst = std::max(worst, std::sqrt(double(dp > dq ? dp : dq)) / M);
        }
    }
    // Documented: 16·2^-52·M plus the rounding to S.
    const double tol = 16 * 0x1p-52 + 2 * double(std::numeric_limits<S>::epsilon());
    INFO("witness distance to the triangles, worst / M: " << worst << " (tolerance " << tol << "), hits " << hits);
    CHECK(hits > n / 10);
    CHECK(worst <= tol);
}

TEMPLATE_TEST_CASE("floating_point mode disagrees with the exact test on near-degenerate input", "[triangle]", float, double) {
    using S = TestType;
    const int per_kind = test::scaled(3000, 50);
    long total = 0, wrong = 0, wrong_random = 0, total_random = 0;
    for (int k = 0; k < static_cast<int>(tri::Kind::count); ++k) {
        const auto kind = static_cast<tri::Kind>(k);
        tri::Rng rng(5000 + k);
        long kind_wrong = 0;
        for (int i = 0; i < per_kind; ++i) {
            const auto x = tri::as<S>(tri::generate(kind, rng));
            const bool exact = triangles_intersect(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2]);
            const bool fp = triangles_intersect(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2], PredicateMode::floating_point);
            const auto w = triangle_intersection(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2], PredicateMode::floating_point);
            REQUIRE(w.intersect == fp);  // the witness path decides like the boolean one in either mode
            kind_wrong += exact != fp;
        }
        if (kind == tri::Kind::random) {
            wrong_random += kind_wrong;
            total_random += per_kind;
        } else {
            wrong += kind_wrong;
            total += per_kind;
        }
        WARN(std::string(sizeof(S) == 4 ? "float " : "double ") + "floating_point mode wrong on " + tri::name(kind) +
             ": " + std::to_string(kind_wrong) + " / " + std::to_string(per_kind));
    }
    WARN(std::string(sizeof(S) == 4 ? "float" : "double") + " floating_point mode disagreement: near-degenerate " +
         std::to_string(wrong) + " / " + std::to_string(total) + " = " +
         std::to_string(std::lround(1000.0 * wrong / total) / 10.0).substr(0, 4) + "%, random " + std::to_string(wrong_random) + " / " + std::to_string(total_random));
    CHECK(wrong > 0);
}
