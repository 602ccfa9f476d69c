// The time-only exclusion of the CCD root search (detail::coplanarity_excludes: the Bernstein coefficients of
// c(t) = det(B(t), E1(t), E2(t)) on a box's time interval) judged in exact rational arithmetic: it must never
// exclude an interval on which the exact cubic of the exact inputs has a zero, on random motions, motions in one
// plane (c ≡ 0), near-planar ones (c within rounding of 0) and motions built to become coplanar inside the
// interval. "_cgal": GMP's rationals through CGAL.

#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <CGAL/Gmpq.h>

#include <cdkit/ccd/detail/primitive_setup.hpp>

#include <array>
#include <random>

using cdkit::Vec3;
using Q = CGAL::Gmpq;

namespace {

using QVec = std::array<Q, 3>;

QVec exact_lerp(const Vec3<double>& p0, const Vec3<double>& p1, const Q& t) {
    QVec r;
    for (int k = 0; k < 3; ++k) r[k] = Q(p0[k]) + t * (Q(p1[k]) - Q(p0[k]));
    return r;
}
QVec minus(const QVec& a, const QVec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Q det(const QVec& x, const QVec& y, const QVec& z) {
    return x[0] * (y[1] * z[2] - y[2] * z[1]) + x[1] * (y[2] * z[0] - y[0] * z[2]) + x[2] * (y[0] * z[1] - y[1] * z[0]);
}

/// Edge–edge terms as edge_edge_ccd forms them: points a0 a1 (edge A), b0 b1 (edge B), at t = 0 then t = 1;
/// F = (a0 − b0) + u·(a1 − a0) − v·(b1 − b0) up to the order of terms, and c(t) of the exact points.
struct Motion {
    std::array<Vec3<double>, 8> p;
    Q c(const Q& t) const {
        const QVec a0 = exact_lerp(p[0], p[4], t), a1 = exact_lerp(p[1], p[5], t);
        const QVec b0 = exact_lerp(p[2], p[6], t), b1 = exact_lerp(p[3], p[7], t);
        return det(minus(a0, b0), minus(a1, a0), minus(b1, b0));
    }
    cdkit::detail::GapFunction gap() const {
        const cdkit::detail::CcdPoints pts{&p[0], &p[1], &p[2], &p[3], &p[4], &p[5], &p[6], &p[7]};
        return cdkit::detail::make_gap_function(pts, {0, 2}, {1, 0}, {3, 2}, false);
    }
};

/// Whether the exact cubic has a zero on [a, b], as far as 33 samples show (a sign change or a zero among them
/// proves one; no change proves nothing, so such intervals only count towards "the test excludes something").
bool exact_zero_seen(const Motion& m, double a, double b) {
    int sign = 0;
    for (int i = 0; i <= 32; ++i) {
        const Q t = Q(a) + (Q(b) - Q(a)) * Q(i, 32);
        const Q v = m.c(t);
        const int s = CGAL::sign(v);
        if (s == 0) return true;
        if (sign != 0 && s != sign) return true;
        sign = s;
    }
    return false;
}

}  // namespace

TEST_CASE("the coplanarity cubic's time test never excludes an interval holding an exact zero", "[ccd][exact]") {
    std::mt19937_64 rng(34);
    std::uniform_real_distribution<double> U(-1, 1), T(0, 1);
    int with_zero = 0, excluded = 0, checked = 0;
    for (int i = 0; i < cdkit::test::scaled(20000, 4000); ++i) {
        Motion m;
        const int family = i % 5;
        const double scale = std::ldexp(1.0, int(rng() % 40) - 20);  // 2^-20 … 2^19
        for (auto& q : m.p) q = Vec3<double>(U(rng), U(rng), U(rng)) * scale;
        if (family == 1)  // in one plane throughout: c ≡ 0
            for (auto& q : m.p) q.z() = 0.25 * scale;
        if (family == 2)  // within rounding of one plane
            for (auto& q : m.p) q.z() = 0.25 * scale + U(rng) * scale * 1e-14;
        double a = T(rng), b = T(rng);
        if (a > b) std::swap(a, b);
        if (i % 3 == 0) b = std::min(1.0, a + std::ldexp(1.0, -int(rng() % 30)));  // narrow intervals too
        if (family >= 3) {
            // Coplanar near t = s (exactly but for the rounding of the moved coordinates): the points at t = 1 are
            // those at 0 moved so that at s all four lie in z = 0. Family 4 takes an interval around s only a few
            // hundred ulps wide, where the computed coefficients are as small as their rounding.
            const double s = 0.25 + 0.5 * T(rng);
            for (int k = 0; k < 4; ++k) m.p[k + 4].z() = -m.p[k].z() * (1 - s) / s;
            if (family == 4) {
                const double w = std::ldexp(s, -44 - int(rng() % 8));
                a = s - w;
                b = s + w;
            }
        }
        const cdkit::detail::GapFunction g = m.gap();
        cdkit::detail::InclusionBox box{{a, 0, 0}, {b, 1, 1}, 0};
        cdkit::detail::BoxCorners corners;
        cdkit::detail::evaluate_corners(g, box, corners);
        const bool excludes = cdkit::detail::coplanarity_excludes(corners, g);
        const bool zero = exact_zero_seen(m, a, b);
        INFO("motion " << i << " family " << family << " interval [" << a << ", " << b << "]");
        if (zero) REQUIRE_FALSE(excludes);
        with_zero += zero;
        excluded += excludes;
        ++checked;
    }
    // Not vacuous: many intervals hold a zero (families 1 and 3 always or often), and the test excludes many others.
    CHECK(with_zero > checked / 4);
    CHECK(excluded > checked / 5);
}
