// The exact proof behind the sliver-face regression (sliver_face_case.hpp): the plane that double GJK's cold
// boolean reports separates the hull and the needle ellipsoid, in exact rational arithmetic on the very doubles
// of the shapes, poses and normal. Long-double GJK had called the pair intersecting; this shows the oracle was
// wrong, not the double answer. For a direction u (world): the hull's extreme is max over its vertices x of
// u·(R_a x + t_a); the ellipsoid's is u·t_b − |diag(r)·R_bᵀu| (for any matrix R_b, orthonormal or not). The gap
// L − √Q with L = u·t_b − max_a and Q = |diag(r)·R_bᵀu|² is positive iff L > 0 and L² > Q: no root needed.
#include "sliver_face_case.hpp"

#include <cdkit/narrowphase/gjk.hpp>

#include <CGAL/Exact_rational.h>  // boost::multiprecision or Gmpq: results typed Q, never auto (expression templates)
#include <catch2/catch.hpp>

using namespace cdkit;
namespace sf = cdkit::test::sliver_face;

TEST_CASE("the sliver-face pair is separated in exact arithmetic", "[gjk][hard][exact]") {
    using Q = CGAL::Exact_rational;
    const auto r = gjk_intersect(sf::hull<double>(), sf::pose<double>(sf::pose_hull), sf::ellipsoid<double>(),
                                 sf::pose<double>(sf::pose_ellipsoid));
    REQUIRE(r.status == GjkStatus::separated);
    const Q u[3] = {Q(r.normal[0]), Q(r.normal[1]), Q(r.normal[2])};
    auto rot = [](const std::array<double, 12>& p, int i, int j) -> Q { return Q(p[std::size_t(3 * i + j)]); };
    auto rotated_u = [&](const std::array<double, 12>& p, int j) -> Q {  // (Rᵀu)_j
        return rot(p, 0, j) * u[0] + rot(p, 1, j) * u[1] + rot(p, 2, j) * u[2];
    };
    auto u_dot_t = [&](const std::array<double, 12>& p) -> Q {
        return u[0] * Q(p[9]) + u[1] * Q(p[10]) + u[2] * Q(p[11]);
    };
    const Q ua[3] = {rotated_u(sf::pose_hull, 0), rotated_u(sf::pose_hull, 1), rotated_u(sf::pose_hull, 2)};
    // The hull is the points' hull: its extreme along u is the largest over the points.
    bool first = true;
    Q top_a(0);
    for (const auto& x : sf::hull_points) {
        const Q h = ua[0] * Q(x[0]) + ua[1] * Q(x[1]) + ua[2] * Q(x[2]);
        if (first || h > top_a) top_a = h, first = false;
    }
    top_a += u_dot_t(sf::pose_hull);
    Q q(0);
    for (int j = 0; j < 3; ++j) {
        const Q c = Q(sf::ellipsoid_radii[std::size_t(j)]) * rotated_u(sf::pose_ellipsoid, j);
        q += c * c;
    }
    const Q l = u_dot_t(sf::pose_ellipsoid) - top_a;
    CHECK(l > Q(0));
    CHECK(l * l > q);  // L > √Q: the ellipsoid's lowest point along u lies above the hull's highest
    // The gap, (L² − Q)/(L + √Q), is 3.46e-14 (printed by a double estimate of the exact difference).
    const double lf = CGAL::to_double(l), gap = CGAL::to_double(l * l - q) / (lf + std::sqrt(CGAL::to_double(q)));
    INFO("exact gap ≈ " << gap);
    CHECK(gap > 3e-14);
}
