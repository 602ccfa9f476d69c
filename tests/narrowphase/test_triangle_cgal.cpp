// The triangle test and the orientation predicates against CGAL's exact kernels: every exact-mode answer
// must equal CGAL's, on random and near-degenerate input (see triangle_cases.hpp). CGAL's triangle
// do_intersect has the precondition that neither triangle is degenerate, so the oracle reduces a
// zero-area triangle (decided exactly by CGAL) to the segment between its farthest vertices, or a point,
// and uses CGAL's segment/point predicates for those.
#include "oracles/cgal_simplex.hpp"
#include "test_common.hpp"
#include "triangle_cases.hpp"

#include "cdkit/core/predicates.hpp"
#include "cdkit/narrowphase/triangle.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using namespace cdkit;
namespace tri = cdkit::test::tri;

namespace {

namespace cgal = cdkit::test::cgal;
using cgal::EK;
using cgal::Simplex;
using cgal::simplex;
using IK = CGAL::Exact_predicates_inexact_constructions_kernel;  // exact predicates, fast on doubles
IK::Point_3 ip(const detail::Point3d& p) { return {p.x, p.y, p.z}; }

int cgal_orient3d(const detail::Point3d& a, const detail::Point3d& b, const detail::Point3d& c, const detail::Point3d& d) {
    // CGAL's orientation(p,q,r,s) is the sign of det[q−p, r−p, s−p]: the opposite of Shewchuk's orient3d.
    return -static_cast<int>(CGAL::orientation(ip(a), ip(b), ip(c), ip(d)));
}

/// The exact determinant det[a−d; b−d; c−d], rounded to double.
double exact_det3(const detail::Point3d& a, const detail::Point3d& b, const detail::Point3d& c, const detail::Point3d& d) {
    using FT = EK::FT;
    const FT ux = FT(a.x) - d.x, uy = FT(a.y) - d.y, uz = FT(a.z) - d.z;
    const FT vx = FT(b.x) - d.x, vy = FT(b.y) - d.y, vz = FT(b.z) - d.z;
    const FT wx = FT(c.x) - d.x, wy = FT(c.y) - d.y, wz = FT(c.z) - d.z;
    const FT det = ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
    return CGAL::to_double(CGAL::exact(det));  // to_double of the lazy number would use its interval
}

/// The exact point rounded to double (CGAL::to_double of a lazy number returns its interval's estimate,
/// which near degeneracies is far from the exact value).
Vec3<double> to_vec(const EK::Point_3& p) {
    return {CGAL::to_double(CGAL::exact(p.x())), CGAL::to_double(CGAL::exact(p.y())), CGAL::to_double(CGAL::exact(p.z()))};
}

/// A double with a random 53-bit significand and binary exponent in [lo, hi], random sign.
double random_magnitude(tri::Rng& r, int lo, int hi) {
    const double m = 1.0 + r.uniform();
    return (r.coin() ? 1 : -1) * std::ldexp(m, r.integer(lo, hi));
}

std::string sci(double x) {
    std::ostringstream o;
    o.precision(3);
    o << std::scientific << x;
    return o.str();
}

detail::Point3d pt(const Vec3<double>& v) { return {v.x(), v.y(), v.z()}; }

/// Four points, the last nearly in the plane of the first three (rounded affine combination, then nudged
/// by a few ulps), around a random offset and at a random scale.
void near_coplanar(tri::Rng& r, detail::Point3d (&P)[4], double offset, int scale_exp) {
    const Vec3<double> o = r.vec(-1, 1) * offset;
    Vec3<double> v[3];
    for (auto& x : v) x = (o + r.vec(-1, 1)) * std::ldexp(1.0, scale_exp);
    const double s = r.uniform(-1, 2), t = r.uniform(-1, 2);
    Vec3<double> d = v[0] + s * (v[1] - v[0]) + t * (v[2] - v[0]);
    const int nudge = r.integer(-2, 2);
    if (nudge != 0) {
        const int k = r.integer(0, 2);
        for (int i = 0; i < std::abs(nudge); ++i)
            d[k] = std::nextafter(d[k], nudge > 0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity());
    }
    for (int i = 0; i < 3; ++i) P[i] = pt(v[i]);
    P[3] = pt(d);
}

}  // namespace

TEST_CASE("orient3d equals CGAL's exact orientation", "[triangle][predicates][cgal]") {
    tri::Rng rng(31337);
    const int n = test::scaled(20000, 200);
    struct Stats {
        int zero = 0, pos = 0, neg = 0, fp_wrong = 0;
    };
    auto check = [&](const detail::Point3d (&P)[4], Stats& st) {
        const int expected = cgal_orient3d(P[0], P[1], P[2], P[3]);
        (expected == 0 ? st.zero : expected > 0 ? st.pos : st.neg)++;
        REQUIRE(detail::orient3d_filtered(P[0], P[1], P[2], P[3]) == expected);
        REQUIRE(detail::orient3d_exact(P[0], P[1], P[2], P[3]) == expected);
        REQUIRE(detail::Orient3dPlane(P[0], P[1], P[2]).sign(P[3]) == expected);
        REQUIRE(detail::orient3d_adapt(P[0], P[1], P[2], P[3], nullptr) == expected);
        int sign_b;  // the intermediate stages, where they claim to decide
        if (detail::orient3d_if_error_free(P[0], P[1], P[2], P[3], sign_b, nullptr)) REQUIRE(sign_b == expected);
        double perm;
        const detail::DoubleDouble r = detail::orient3d_dd(P[0], P[1], P[2], P[3], perm);
        if (std::abs(r.hi) > 0x1p-99 * perm) REQUIRE((r.hi > 0 ? 1 : -1) == expected);
        const double v = detail::orient3d_value(P[0], P[1], P[2], P[3]);
        st.fp_wrong += ((v > 0) - (v < 0)) != expected;
    };
    SECTION("random points (filter decides)") {
        Stats st;
        for (int i = 0; i < n; ++i) {
            detail::Point3d P[4];
            for (auto& p : P) p = pt(rng.vec(-1, 1));
            check(P, st);
        }
        CHECK(st.pos > n / 4);
        CHECK(st.neg > n / 4);
    }
    SECTION("nearly coplanar points, at offsets up to 1e15 and scales 2^-250 … 2^250") {
        Stats st;
        for (int i = 0; i < n; ++i) {
            detail::Point3d P[4];
            static const double offsets[] = {0, 1, 1e6, 1e15};
            near_coplanar(rng, P, offsets[rng.integer(0, 3)], rng.coin(0.7) ? 0 : rng.integer(-250, 250));
            check(P, st);
        }
        WARN("orient3d on nearly coplanar points: " << st.pos << " +, " << st.neg << " −, " << st.zero
                                                    << " zero; floating point wrong in " << st.fp_wrong << " / " << n);
        CHECK(st.pos > n / 10);
        CHECK(st.neg > n / 10);
        CHECK(st.fp_wrong > n / 20);
    }
    SECTION("exact path alone, full-precision coordinates spread over the whole range [2^-280, 2^280]") {
        Stats st;
        for (int i = 0; i < n; ++i) {
            detail::Point3d P[4];
            const int lo = rng.integer(-280, 270), hi = std::min(280, lo + rng.integer(0, 60));
            for (auto& p : P) p = {random_magnitude(rng, lo, hi), random_magnitude(rng, lo, hi), random_magnitude(rng, lo, hi)};
            if (rng.coin()) {  // make d nearly coplanar, in the same magnitude range
                const double s = rng.uniform(0, 1), t = rng.uniform(0, 1 - s);
                P[3] = {P[0].x + s * (P[1].x - P[0].x) + t * (P[2].x - P[0].x),
                        P[0].y + s * (P[1].y - P[0].y) + t * (P[2].y - P[0].y),
                        P[0].z + s * (P[1].z - P[0].z) + t * (P[2].z - P[0].z)};
                for (double* c : {&P[3].x, &P[3].y, &P[3].z})
                    if (*c != 0 && std::abs(*c) < std::ldexp(1.0, -280)) *c = 0;  // stay in the documented range
            }
            check(P, st);
        }
        CHECK(st.pos > n / 10);
        CHECK(st.neg > n / 10);
    }
}

TEST_CASE("orient2d equals CGAL's exact orientation", "[triangle][predicates][cgal]") {
    tri::Rng rng(4242);
    const int n = test::scaled(20000, 200);
    int zero = 0, fp_wrong = 0;
    for (int i = 0; i < n; ++i) {
        detail::Point2d P[3];
        if (rng.coin(0.2)) {
            for (auto& p : P) p = {rng.uniform(-1, 1), rng.uniform(-1, 1)};
        } else if (rng.coin(0.2)) {  // exactly collinear (small integers and sixteenths), scaled
            const int e = rng.integer(-250, 250);
            const double ax = rng.integer(-64, 64), ay = rng.integer(-64, 64), dx = rng.integer(-64, 64), dy = rng.integer(-64, 64);
            const double s0 = rng.dyadic(-32, 32), s1 = rng.dyadic(-32, 32);
            P[0] = {std::ldexp(ax, e), std::ldexp(ay, e)};
            P[1] = {std::ldexp(ax + s0 * dx, e), std::ldexp(ay + s0 * dy, e)};
            P[2] = {std::ldexp(ax + s1 * dx, e), std::ldexp(ay + s1 * dy, e)};
        } else {  // c nearly on the line ab, possibly far from the origin or scaled
            const double off = rng.coin() ? 0.0 : 1e6;
            const int e = rng.coin(0.7) ? 0 : rng.integer(-250, 250);
            for (int j = 0; j < 2; ++j) P[j] = {std::ldexp(off + rng.uniform(-1, 1), e), std::ldexp(off + rng.uniform(-1, 1), e)};
            const double s = rng.uniform(-1, 2);
            P[2] = {P[0].x + s * (P[1].x - P[0].x), P[0].y + s * (P[1].y - P[0].y)};
            const int nudge = rng.integer(-1, 1);
            if (nudge != 0) P[2].x = std::nextafter(P[2].x, nudge * std::numeric_limits<double>::infinity());
        }
        const int expected = static_cast<int>(CGAL::orientation(IK::Point_2(P[0].x, P[0].y), IK::Point_2(P[1].x, P[1].y),
                                                                IK::Point_2(P[2].x, P[2].y)));
        zero += expected == 0;
        REQUIRE(detail::orient2d_filtered(P[0], P[1], P[2]) == expected);
        REQUIRE(detail::orient2d_exact(P[0], P[1], P[2]) == expected);
        const double v = detail::orient2d_value(P[0], P[1], P[2]);
        fp_wrong += ((v > 0) - (v < 0)) != expected;
    }
    WARN("orient2d: " << zero << " collinear; floating point wrong in " << fp_wrong << " / " << n);
    CHECK(fp_wrong > 0);
    CHECK(zero > n / 20);
}

TEST_CASE("orient3d_accurate and the expansion estimate are within a few ulps of the exact determinant",
          "[triangle][predicates][cgal]") {
    tri::Rng rng(555);
    const int n = test::scaled(5000, 100);
    double worst_acc = 0, worst_est = 0;
    for (int i = 0; i < n; ++i) {
        detail::Point3d P[4];
        if (rng.coin(0.3)) {
            for (auto& p : P) p = pt(rng.vec(-1, 1));
        } else {
            near_coplanar(rng, P, rng.coin() ? 0.0 : 1e6, 0);
        }
        const double exact = exact_det3(P[0], P[1], P[2], P[3]);
        const double acc = detail::orient3d_accurate(P[0], P[1], P[2], P[3]);
        double est;
        detail::orient3d_exact(P[0], P[1], P[2], P[3], &est);
        if (exact == 0) {
            REQUIRE(acc == 0);
            REQUIRE(est == 0);
            continue;
        }
        worst_acc = std::max(worst_acc, std::abs(acc - exact) / std::abs(exact));
        worst_est = std::max(worst_est, std::abs(est - exact) / std::abs(exact));
    }
    INFO("worst relative error: orient3d_accurate " << worst_acc << ", expansion estimate " << worst_est);
    CHECK(worst_acc <= 4 * 0x1p-53);
    CHECK(worst_est <= 4 * 0x1p-53);
}

TEMPLATE_TEST_CASE("triangles_intersect equals CGAL's exact do_intersect", "[triangle][cgal]", float, double) {
    using S = TestType;
    const int per_kind = test::scaled(10000, 30);
    long all_hits = 0, all = 0, fp_wrong = 0, degenerate = 0;
    for (int k = 0; k < static_cast<int>(tri::Kind::count); ++k) {
        const auto kind = static_cast<tri::Kind>(k);
        tri::Rng rng(777 + k);
        int hits = 0;
        for (int i = 0; i < per_kind; ++i) {
            const auto x = tri::as<S>(tri::generate(kind, rng));
            const Simplex sp = simplex(x.p), sq = simplex(x.q);
            degenerate += sp.dim < 2 || sq.dim < 2;
            const bool expected = cgal::intersect(sp, sq);
            const bool got = triangles_intersect(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2]);
            if (got != expected) {
                INFO(tri::name(kind) << " case " << i);
                for (int j = 0; j < 3; ++j) INFO("p" << j << " " << x.p[j].transpose() << "   q" << j << " " << x.q[j].transpose());
                REQUIRE(got == expected);
            }
            REQUIRE(triangle_intersection(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2]).intersect == expected);
            fp_wrong += triangles_intersect(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2], PredicateMode::floating_point) != expected;
            hits += expected;
        }
        all_hits += hits;
        all += per_kind;
        INFO(tri::name(kind) << ": " << hits << " / " << per_kind << " intersect");
        CHECK(hits > 0);
    }
    WARN(std::string(sizeof(S) == 4 ? "float" : "double") + ": " + std::to_string(all) + " pairs checked against CGAL, " +
         std::to_string(all_hits) + " intersecting, " + std::to_string(degenerate) + " with a zero-area triangle; " +
         "floating_point mode wrong on " + std::to_string(fp_wrong));
    CHECK(all_hits > all / 5);
    CHECK(all_hits < all * 4 / 5);
    CHECK(degenerate > all / 20);
}

TEMPLATE_TEST_CASE("triangle_intersection: witness points against CGAL's exact intersection", "[triangle][cgal]", float,
                   double) {
    using S = TestType;
    const int per_kind = test::scaled(400, 10);
    const double slack = 16 * 0x1p-52 + 2 * double(std::numeric_limits<S>::epsilon());  // relative to M
    double worst_dist = 0, worst_end = 0, worst_diam = 0;
    int segments = 0, coplanar = 0;
    for (int k = 0; k < static_cast<int>(tri::Kind::count); ++k) {
        const auto kind = static_cast<tri::Kind>(k);
        tri::Rng rng(9000 + k);
        for (int i = 0; i < per_kind; ++i) {
            const auto x = tri::as<S>(tri::generate(kind, rng));
            const auto r = triangle_intersection(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2]);
            if (!r.intersect) continue;
            double M = 0;
            for (int j = 0; j < 3; ++j)
                M = std::max({M, double(x.p[j].cwiseAbs().maxCoeff()), double(x.q[j].cwiseAbs().maxCoeff())});
            const Simplex sp = simplex(x.p), sq = simplex(x.q);
            INFO(tri::name(kind) << " case " << i);
            // 1. Both points lie on both triangles (exact distances).
            for (const Vec3<S>& w : {r.a, r.b}) {
                const EK::Point_3 e = cgal::exact_point(w);
                const double d = std::sqrt(CGAL::to_double(CGAL::exact(std::max(cgal::squared_distance(e, sp), cgal::squared_distance(e, sq)))));
                worst_dist = std::max(worst_dist, d / M);
            }
            if (sp.dim < 2 || sq.dim < 2) {
                CHECK(!r.coplanar);
                continue;
            }
            // 2. Against CGAL's intersection: the segment's end points, or the overlap polygon's diameter.
            const auto res = CGAL::intersection(EK::Triangle_3(sp.a, sp.b, sp.c), EK::Triangle_3(sq.a, sq.b, sq.c));
            REQUIRE(static_cast<bool>(res));
            std::vector<Vec3<double>> pts;
            auto add = [&](const EK::Point_3& p) { pts.push_back(to_vec(p)); };
            bool polygon = false;
            if (const auto* p = boost::get<EK::Point_3>(&*res)) {
                add(*p);
            } else if (const auto* s = boost::get<EK::Segment_3>(&*res)) {
                add(s->source());
                add(s->target());
            } else if (const auto* t = boost::get<EK::Triangle_3>(&*res)) {
                polygon = true;
                for (int j = 0; j < 3; ++j) add(t->vertex(j));
            } else if (const auto* v = boost::get<std::vector<EK::Point_3>>(&*res)) {
                polygon = true;
                for (const auto& vertex : *v) add(vertex);
            }
            REQUIRE(!pts.empty());
            const bool cgal_coplanar = CGAL::coplanar(sp.a, sp.b, sp.c, sq.a) && CGAL::coplanar(sp.a, sp.b, sp.c, sq.b) &&
                                       CGAL::coplanar(sp.a, sp.b, sp.c, sq.c);
            REQUIRE(r.coplanar == cgal_coplanar);
            const Vec3<double> a = r.a.template cast<double>(), b = r.b.template cast<double>();
            if (!r.coplanar) {
                REQUIRE(!polygon);
                ++segments;
                const Vec3<double>& s0 = pts.front();
                const Vec3<double>& s1 = pts.back();
                const double e = std::min(std::max((a - s0).norm(), (b - s1).norm()), std::max((a - s1).norm(), (b - s0).norm()));
                worst_end = std::max(worst_end, e / M);
            } else {
                ++coplanar;
                double diam = 0;
                for (const auto& p : pts)
                    for (const auto& q : pts) diam = std::max(diam, (p - q).norm());
                worst_diam = std::max(worst_diam, std::abs((a - b).norm() - diam) / M);
            }
        }
    }
    WARN(std::string(sizeof(S) == 4 ? "float" : "double") + " witness, worst / M: distance to the triangles " +
         sci(worst_dist) + ", segment end points " + sci(worst_end) + ", coplanar diameter " +
         sci(worst_diam) + " (" + std::to_string(segments) + " segments, " + std::to_string(coplanar) +
         " coplanar); slack " + sci(slack));
    CHECK(segments > 100);
    CHECK(coplanar > 20);
    CHECK(worst_dist <= slack);
    CHECK(worst_end <= slack);
    CHECK(worst_diam <= 2 * slack);
}

// ---- outside the floating-point stages' range: subnormal and huge coordinates ------------------------

namespace {

/// A double of any finite magnitude: random significand, binary exponent in [lo, hi] (ldexp rounds it into
/// the subnormals below 2^-1022), sometimes zero.
double any_magnitude(tri::Rng& r, int lo, int hi) { return r.coin(0.1) ? 0.0 : random_magnitude(r, lo, hi); }

/// Exact orientation signs in rational arithmetic straight from the doubles (GMP through CGAL::Gmpq): the
/// referee for input where a floating-point filter could be fooled by underflow or overflow.
int gmp_orient3d(const detail::Point3d& a, const detail::Point3d& b, const detail::Point3d& c, const detail::Point3d& d) {
    using Q = CGAL::Gmpq;
    const Q adx = Q(a.x) - Q(d.x), ady = Q(a.y) - Q(d.y), adz = Q(a.z) - Q(d.z);
    const Q bdx = Q(b.x) - Q(d.x), bdy = Q(b.y) - Q(d.y), bdz = Q(b.z) - Q(d.z);
    const Q cdx = Q(c.x) - Q(d.x), cdy = Q(c.y) - Q(d.y), cdz = Q(c.z) - Q(d.z);
    const Q det = adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady);
    return CGAL::sign(det);
}
int gmp_orient2d(const detail::Point2d& a, const detail::Point2d& b, const detail::Point2d& c) {
    using Q = CGAL::Gmpq;
    const Q det = (Q(a.x) - Q(c.x)) * (Q(b.y) - Q(c.y)) - (Q(a.y) - Q(c.y)) * (Q(b.x) - Q(c.x));
    return CGAL::sign(det);
}

/// One coordinate stepped k ulps (k in −3 … 3); from 0 that is a subnormal.
double step_ulps(double x, int k) {
    for (int i = 0; i < std::abs(k); ++i) x = std::nextafter(x, k > 0 ? HUGE_VAL : -HUGE_VAL);
    return x;
}

}  // namespace

TEST_CASE("orient3d and orient2d are exact outside the floating-point range (subnormal, huge)",
          "[triangle][predicates][cgal]") {
    tri::Rng rng(2718);
    const int n = test::scaled(3000, 150);
    int wide = 0, zero = 0, pos = 0, neg = 0, filtered_wrong = 0, cgal_wrong = 0;
    auto check = [&](const detail::Point3d (&P)[4]) {
        const int expected = gmp_orient3d(P[0], P[1], P[2], P[3]);
        (expected == 0 ? zero : expected > 0 ? pos : neg)++;
        cgal_wrong += cgal_orient3d(P[0], P[1], P[2], P[3]) != expected;
        INFO(std::hexfloat << P[0].x << " " << P[0].y << " " << P[0].z << " | " << P[1].x << " " << P[1].y << " " << P[1].z
                           << " | " << P[2].x << " " << P[2].y << " " << P[2].z << " | " << P[3].x << " " << P[3].y << " "
                           << P[3].z);
        const double x[12] = {P[0].x, P[0].y, P[0].z, P[1].x, P[1].y, P[1].z, P[2].x, P[2].y, P[2].z, P[3].x, P[3].y, P[3].z};
        wide += detail::any_outside_predicate_range(x);
        double v;
        REQUIRE(detail::orient3d_wide(P[0], P[1], P[2], P[3], &v) == expected);
        REQUIRE((v > 0) - (v < 0) == expected);
        REQUIRE(detail::orient3d_any_range(P[0], P[1], P[2], P[3]) == expected);
        const Vec3<double> a(P[0].x, P[0].y, P[0].z), b(P[1].x, P[1].y, P[1].z), c(P[2].x, P[2].y, P[2].z),
            d(P[3].x, P[3].y, P[3].z);
        REQUIRE(orient3d(a, b, c, d) == expected);
        filtered_wrong += detail::orient3d_filtered(P[0], P[1], P[2], P[3]) != expected;
        // orient2d on the xy projection of the first three points.
        const detail::Point2d q[3] = {{P[0].x, P[0].y}, {P[1].x, P[1].y}, {P[3].x, P[3].y}};
        const int expected2 = gmp_orient2d(q[0], q[1], q[2]);
        cgal_wrong += static_cast<int>(CGAL::orientation(IK::Point_2(q[0].x, q[0].y), IK::Point_2(q[1].x, q[1].y),
                                                         IK::Point_2(q[2].x, q[2].y))) != expected2;
        REQUIRE(detail::orient2d_any_range(q[0], q[1], q[2]) == expected2);
        REQUIRE(orient2d(Eigen::Vector2d(q[0].x, q[0].y), Eigen::Vector2d(q[1].x, q[1].y),
                         Eigen::Vector2d(q[2].x, q[2].y)) == expected2);
    };
    SECTION("a point one to three ulps off a plane through the origin (subnormal offsets)") {
        for (int i = 0; i < n; ++i) {
            detail::Point3d P[4];
            for (int j = 0; j < 3; ++j) P[j] = {double(rng.integer(-8, 8)), double(rng.integer(-8, 8)), 0.0};
            P[3] = {rng.dyadic(-8, 8), rng.dyadic(-8, 8), step_ulps(0.0, rng.integer(-3, 3))};
            if (rng.coin()) std::swap(P[3], P[rng.integer(0, 2)]);
            check(P);
        }
    }
    SECTION("coordinates spread over the whole double range") {
        for (int i = 0; i < n; ++i) {
            detail::Point3d P[4];
            const int lo = rng.integer(-1080, 1000), hi = std::min(1020, lo + rng.integer(0, 400));
            for (auto& p : P) p = {any_magnitude(rng, lo, hi), any_magnitude(rng, lo, hi), any_magnitude(rng, lo, hi)};
            check(P);
        }
    }
    SECTION("nearly coplanar points scaled to the subnormal and the huge end") {
        for (int i = 0; i < n; ++i) {
            detail::Point3d P[4];
            near_coplanar(rng, P, 0.0, 0);
            const int e = rng.coin() ? rng.integer(-1075, -1000) : rng.integer(1000, 1020);
            for (auto& p : P) p = {std::ldexp(p.x, e), std::ldexp(p.y, e), std::ldexp(p.z, e)};
            check(P);
        }
    }
    SECTION("determinants far below the smallest double") {
        const double t = std::numeric_limits<double>::denorm_min();
        detail::Point3d P[4] = {{t, 0, 0}, {0, t, 0}, {0, 0, t}, {0, 0, 0}};
        check(P);
        std::swap(P[0], P[1]);
        check(P);
        CHECK(pos == 1);
        CHECK(neg == 1);
    }
    WARN("wide-range orient3d: " << pos << " +, " << neg << " −, " << zero << " zero; " << wide
                                 << " outside the filter's range; the floating-point stages alone wrong on "
                                 << filtered_wrong << "; CGAL's Epick orientation wrong on " << cgal_wrong);
    CHECK(wide > 0);
}

TEST_CASE("triangles_intersect equals CGAL with subnormal and huge coordinates", "[triangle][cgal]") {
    using S = double;
    const int per_kind = test::scaled(1500, 20);
    long wrong_before_fix = 0, all = 0;
    for (int k = 0; k < static_cast<int>(tri::Kind::count); ++k) {
        const auto kind = static_cast<tri::Kind>(k);
        tri::Rng rng(9100 + k);
        for (int i = 0; i < per_kind; ++i) {
            auto x = tri::as<S>(tri::generate(kind, rng));
            const int mode = rng.integer(0, 2);
            if (mode == 0) {  // P in the plane z = 0, one vertex of Q a few ulps (subnormal) off it
                for (auto& v : x.p) v.z() = 0;
                x.q[0].z() = step_ulps(0.0, rng.integer(-3, 3));
            } else {  // everything scaled into the subnormal or the huge end (exact unless it rounds)
                double m = 0;
                for (const auto* t : {&x.p, &x.q})
                    for (const auto& v : *t) m = std::max(m, v.cwiseAbs().maxCoeff());
                int top;
                std::frexp(m, &top);  // the largest coordinate is below 2^top; keep it below 2^1020
                const int e = mode == 1 ? rng.integer(-1070, -1030) : rng.integer(990, 1020) - std::max(top, 0);
                for (auto* t : {&x.p, &x.q})
                    for (auto& v : *t) v = Vec3<S>(std::ldexp(v.x(), e), std::ldexp(v.y(), e), std::ldexp(v.z(), e));
            }
            const bool expected = cgal::intersect(simplex(x.p), simplex(x.q));
            const bool got = triangles_intersect(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2]);
            if (got != expected) {
                INFO(tri::name(kind) << " case " << i << " mode " << mode);
                for (int j = 0; j < 3; ++j) INFO("p" << j << " " << x.p[j].transpose() << "   q" << j << " " << x.q[j].transpose());
                REQUIRE(got == expected);
            }
            const auto w = triangle_intersection(x.p[0], x.p[1], x.p[2], x.q[0], x.q[1], x.q[2]);
            REQUIRE(w.intersect == expected);
            REQUIRE(w.a.allFinite());
            REQUIRE(w.b.allFinite());
            // What the in-range kernel alone would answer: shows the cases the wide stage exists for.
            const auto pts = [](const std::array<Vec3<S>, 3>& t) {
                return std::array<detail::Point3d, 3>{pt(t[0]), pt(t[1]), pt(t[2])};
            };
            const auto p = pts(x.p), q = pts(x.q);
            detail::Point3d pp[3] = {p[0], p[1], p[2]}, qq[3] = {q[0], q[1], q[2]};
            wrong_before_fix +=
                detail::tritri::triangle_triangle<detail::tritri::ExactKernel, false>(pp, qq, nullptr) != expected;
            ++all;
        }
    }
    WARN(all << " pairs with subnormal or huge coordinates equal CGAL; the floating-point stages alone were wrong on "
             << wrong_before_fix);
    CHECK(wrong_before_fix > 0);
}
