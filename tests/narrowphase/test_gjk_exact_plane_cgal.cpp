// Exact proofs behind two regressions (tests/data/convex) where long-double GJK, the hard-case count's reference, was wrong: the plane
// that double GJK's cold boolean reports separates the shapes, in exact rational arithmetic on the very doubles of
// the shapes, poses and normal. For a direction u (world) and a shape given by points X (a hull's vertices, a box's
// corners, a capsule core's end points) the extreme is max over x ∈ X of u·(R x + t); an ellipsoid adds
// |diag(r)·Rᵀu| to its centre's u·t, a capsule's radius r·|u| (for any matrix R, orthonormal or not). The pair is
// apart along u when L = min_B − max_A (points only) exceeds those root terms: L > 0 and L² > Q, no root taken.
#include "convex_case_file.hpp"
#include "test_common.hpp"

#include <cdkit/narrowphase/gjk.hpp>

#include <array>

#include <CGAL/Exact_rational.h>  // boost::multiprecision or Gmpq: results typed Q, never auto (expression templates)
#include <catch2/catch.hpp>

using namespace cdkit;
using Q = CGAL::Exact_rational;

namespace {

struct ExactPose {
    Q r[3][3], t[3];
    explicit ExactPose(const Transform<double>& p) {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) r[i][j] = Q(p.R(i, j));
            t[i] = Q(p.t[i]);
        }
    }
    /// (Rᵀu)_j
    [[nodiscard]] Q rotated(const Q u[3], int j) const { return r[0][j] * u[0] + r[1][j] * u[1] + r[2][j] * u[2]; }
    [[nodiscard]] Q offset(const Q u[3]) const { return u[0] * t[0] + u[1] * t[1] + u[2] * t[2]; }
};

/// The extreme of u·(R x + t) over the points: the largest (sign +1) or the smallest (−1).
Q extreme(const Q u[3], const ExactPose& p, const std::vector<Vec3<double>>& points, int sign) {
    const Q ru[3] = {p.rotated(u, 0), p.rotated(u, 1), p.rotated(u, 2)};
    Q best(0);
    bool first = true;
    for (const auto& x : points) {
        const Q h = ru[0] * Q(x[0]) + ru[1] * Q(x[1]) + ru[2] * Q(x[2]);
        if (first || (sign > 0 ? h > best : h < best)) best = h, first = false;
    }
    return best + p.offset(u);
}

/// The cold boolean's separating direction (world, A towards B) as exact rationals; the query must say separated.
template <class A, class B>
std::array<Q, 3> reported_direction(const A& a, const Transform<double>& pa, const B& b, const Transform<double>& pb) {
    const auto r = gjk_intersect(a, pa, b, pb);
    REQUIRE(r.status == GjkStatus::separated);
    return {Q(r.normal[0]), Q(r.normal[1]), Q(r.normal[2])};
}

/// The gap (L² − Q)/(L + √Q) as a double, for the message.
double gap_estimate(const Q& l, const Q& q) {
    return CGAL::to_double(l * l - q) / (CGAL::to_double(l) + std::sqrt(CGAL::to_double(q)));
}

}  // namespace

TEST_CASE("the sliver-face pair is separated in exact arithmetic", "[gjk][hard][exact]") {
    const auto c = cdkit::test::read_convex_case(cdkit::test::test_data_path("convex/hull_needle_sliver_face.txt"));
    const auto hull = cdkit::test::build<ConvexPolyhedron, double>(c.a);
    const auto needle = cdkit::test::build<Ellipsoid, double>(c.b);
    const auto direction = reported_direction(hull, c.pose_a, needle, c.pose_b);
    const Q* u = direction.data();
    std::vector<Vec3<double>> points;  // the file's points: their hull is the shape
    for (std::size_t i = 0; i + 2 < c.a.numbers.size(); i += 3)
        points.emplace_back(c.a.numbers[i], c.a.numbers[i + 1], c.a.numbers[i + 2]);
    const ExactPose needle_pose(c.pose_b);
    const Q top_a = extreme(u, ExactPose(c.pose_a), points, +1);
    Q q(0);  // |diag(r)·R_bᵀu|²
    for (int j = 0; j < 3; ++j) {
        const Q e = Q(needle.radii[j]) * needle_pose.rotated(u, j);
        q += e * e;
    }
    const Q l = needle_pose.offset(u) - top_a;
    CHECK(l > Q(0));
    CHECK(l * l > q);  // L > √Q: the ellipsoid's lowest point along u lies above the hull's highest
    INFO("exact gap ≈ " << gap_estimate(l, q));
    CHECK(gap_estimate(l, q) > 3e-14);  // 3.46e-14
}

TEST_CASE("the capsule beside a box needle is separated in exact arithmetic", "[gjk][hard][exact]") {
    const auto c = cdkit::test::read_convex_case(cdkit::test::test_data_path("convex/capsule_box_needle.txt"));
    const auto capsule = cdkit::test::build<Capsule, double>(c.a);
    const auto box = cdkit::test::build<Box, double>(c.b);
    const auto direction = reported_direction(capsule, c.pose_a, box, c.pose_b);
    const Q* u = direction.data();
    const std::vector<Vec3<double>> core = {{0, 0, -capsule.half_length}, {0, 0, capsule.half_length}};
    std::vector<Vec3<double>> corners;
    for (int k = 0; k < 8; ++k)
        corners.emplace_back(k & 1 ? box.half[0] : -box.half[0], k & 2 ? box.half[1] : -box.half[1],
                             k & 4 ? box.half[2] : -box.half[2]);
    const Q l = extreme(u, ExactPose(c.pose_b), corners, -1) - extreme(u, ExactPose(c.pose_a), core, +1);
    const Q q = Q(capsule.radius) * Q(capsule.radius) * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);  // (r·|u|)²
    CHECK(l > Q(0));
    CHECK(l * l > q);
    INFO("exact gap ≈ " << gap_estimate(l, q));
    CHECK(gap_estimate(l, q) > 7e-11);  // 7.9e-11
}
