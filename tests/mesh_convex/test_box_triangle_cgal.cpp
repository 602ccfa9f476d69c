// The box–triangle separating-axis test (mesh_convex/box_triangle.hpp) judged by the exact polytope referee
// (tests/oracles/exact_polytope.hpp: CGAL's exact quadratic program on exactly posed vertices): random boxes and
// triangles (slivers and needles among them) placed at gaps and overlaps of 10^-12 … 10^-1 along GJK's normal, and
// at random. "Disjoint" must be exactly disjoint; "touching" must be exactly touching or overlapping, or apart by
// no more than the slack the test was given (the touching rule of the mesh–convex queries).
#include <catch2/catch.hpp>

#include <cdkit/mesh_convex/box_triangle.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include "mesh_factory.hpp"
#include "oracles/exact_polytope.hpp"
#include "test_common.hpp"

#include <cmath>
#include <random>

using namespace cdkit;

TEST_CASE("box-triangle separating axes against the exact referee", "[mesh_convex][box][exact]") {
    std::mt19937_64 rng(2001);
    std::uniform_real_distribution<double> u(-1, 1), size(0.05, 1.0);
    std::normal_distribution<double> g;
    int cases = 0, touching = 0, wrong_disjoint = 0, wrong_touch = 0, within_slack = 0;
    const int n = test::scaled(3000, 300);
    for (int i = 0; i < n; ++i) {
        const Vec3<double> h(size(rng), size(rng), i % 7 == 0 ? 0.0 : size(rng));  // flat boxes too
        const Box<double> box(h);
        std::vector<Vec3<double>> box_vertices;
        for (int k = 0; k < 8; ++k) box_vertices.emplace_back(k & 1 ? h.x() : -h.x(), k & 2 ? h.y() : -h.y(), k & 4 ? h.z() : -h.z());
        Vec3<double> v[3];
        for (auto& x : v) x = Vec3<double>(u(rng), u(rng), u(rng)) * size(rng);
        if (i % 5 == 1) v[2] = v[0] + (v[1] - v[0]) * 0.5 + Vec3<double>(1e-9, 0, 0);  // a sliver
        if (i % 5 == 2) v[1] = v[0] + Vec3<double>(1e-7, 0, 0);                         // a needle
        Transform<double> pose(test::random_rotation(rng), Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 2.0);
        if (i % 4 != 3) {  // near contact: along GJK's normal to a gap or overlap of 10^-12 … 10^-1
            const ConvexTriangle<double> tri(v[0], v[1], v[2]);
            const auto d = gjk_distance(box, Transform<double>{}, tri, pose);
            if (d.status != GjkStatus::separated) continue;
            const double mag = std::pow(10.0, -12.0 + double(rng() % 12));
            pose.t += ((i % 2 ? mag : -mag) - d.distance) * d.normal;
        }
        const double slack = 1024 * std::numeric_limits<double>::epsilon() * 4;
        const Vec3<double> w0 = pose * v[0], w1 = pose * v[1], w2 = pose * v[2];  // the triangle in the box's frame
        const bool touch = detail::box_triangle_touch(h, w0, w1, w2, slack);
        const auto exact = test::exact::exact_polytope_pair(box_vertices, Transform<double>{}, {w0, w1, w2}, Transform<double>{}, false);
        ++cases;
        touching += touch;
        if (!touch) wrong_disjoint += exact.intersect;
        if (touch && !exact.intersect) {
            // Touching by the slack: apart by at most slack times the largest axis' factor (|a|₁ ≤ √3 |a|).
            if (exact.distance <= 2 * slack) ++within_slack;
            else ++wrong_touch;
        }
    }
    INFO(cases << " cases, " << touching << " touching (" << within_slack << " of them apart by at most the slack)");
    CHECK(wrong_disjoint == 0);
    CHECK(wrong_touch == 0);
    CHECK(touching > cases / 4);
    CHECK(touching < cases * 3 / 4);
}
