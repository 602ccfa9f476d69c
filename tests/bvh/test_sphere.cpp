// BoundingSphere trees: the fit contains its vertices and is (near) minimal, merge holds both balls, the overlap
// test is conservative, and collide() on sphere trees equals brute force.
#include "brute_force_check.hpp"

#include "cdkit/bv/sphere.hpp"

using namespace cdkit;

TEMPLATE_TEST_CASE("sphere fit contains every vertex and is tight", "[bv][sphere]", float, double) {
    using S = TestType;
    for (unsigned seed = 1; seed <= 20; ++seed) {
        auto m = test::random_soup<S>(50, S(0.3), seed);
        if (seed % 2 == 0)
            for (auto& v : m.vertices) v += Vec3<S>(S(1000), S(-2000), S(500));
        const auto s = test::fit_all<BoundingSphere<S>>(m);
        REQUIRE(s.is_valid());
        for (const auto& v : m.vertices) REQUIRE(s.contains(v));
        // Some vertex lies on (near) the boundary: the ball cannot shrink about its centre.
        S far = 0;
        for (const auto& v : m.vertices) far = std::max(far, (v - s.center).norm());
        CHECK(far >= s.radius * S(0.999) - S(80) * std::numeric_limits<S>::epsilon() * S(2001));  // padding aside
        const auto other = test::fit_all<BoundingSphere<S>>(test::random_soup<S>(5, S(0.3), seed + 50));
        const auto both = BoundingSphere<S>::merge(s, other);
        for (const auto& v : m.vertices) REQUIRE(both.contains(v));
        CHECK(both.radius >= s.radius);
        CHECK(both.radius >= other.radius);
    }
    // The unit sphere's mesh: the minimum ball is the unit ball (Ritter alone is typically a few % larger).
    const auto ball = test::fit_all<BoundingSphere<S>>(test::uv_sphere<S>(S(1), 16, 32));
    CHECK(ball.radius == Approx(1.0).epsilon(1e-4));
    CHECK(ball.center.norm() < S(1e-4));
    // Degenerate input: all vertices at one point, and collinear points.
    TriangleMesh<S> dot;
    dot.vertices = {Vec3<S>(S(1), S(2), S(3))};
    dot.triangles = {{0, 0, 0}};
    CHECK(test::fit_all<BoundingSphere<S>>(dot).contains(dot.vertices[0]));
    TriangleMesh<S> line;
    line.vertices = {Vec3<S>(S(0), S(0), S(0)), Vec3<S>(S(1), S(1), S(1)), Vec3<S>(S(2), S(2), S(2))};
    line.triangles = {{0, 1, 2}, {2, 1, 0}};
    const auto ls = test::fit_all<BoundingSphere<S>>(line);
    for (const auto& v : line.vertices) CHECK(ls.contains(v));
    CHECK(ls.radius == Approx(std::sqrt(3.0)).epsilon(1e-4));
}

TEMPLATE_TEST_CASE("sphere overlap under a relative transform is conservative and culls", "[bv][sphere]", float, double) {
    using S = TestType;
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-1, 1);
    test::OverlapCounts counts;
    const int n = test::scaled(3000, 200);
    for (int i = 0; i < n; ++i) {
        const auto a = test::fit_all<BoundingSphere<S>>(test::random_soup<S>(4, S(0.4), unsigned(2 * i + 1)));
        const auto b = test::fit_all<BoundingSphere<S>>(test::random_soup<S>(4, S(0.4), unsigned(2 * i + 2)));
        const Transform<S> b_to_a(test::random_rotation<S>(rng), Vec3<S>(S(2 * u(rng)), S(2 * u(rng)), S(2 * u(rng))));
        test::record_overlap(a, b, b_to_a, [&](Vec3<S>& p) {
            const Vec3<S> d(S(u(rng)), S(u(rng)), S(u(rng)));
            p = b.center + b.radius * d;
            return d.norm() <= S(1);
        }, counts);
    }
    test::check_hit_rates(counts);
}

TEMPLATE_TEST_CASE("collide on sphere trees equals brute force", "[collide][sphere]", float, double) {
    using S = TestType;
    const int poses = test::scaled(16, 8);
    const MeshModel<BoundingSphere<S>> sphere(test::uv_sphere<S>(S(1), 8, 16));
    REQUIRE_NOTHROW(sphere.validate());
    int hits = test::collide_equals_brute_force(sphere, sphere, poses, 2.6, 11);
    CHECK(hits > poses / 5);
    CHECK(hits < poses - poses / 10);
    BuildOptions opt;
    opt.split = SplitStrategy::mean;
    opt.max_leaf_triangles = 2;
    const MeshModel<BoundingSphere<S>> a(test::random_soup<S>(200, S(0.15), 5), opt), b(test::random_soup<S>(150, S(0.2), 6));
    REQUIRE_NOTHROW(a.validate());
    REQUIRE_NOTHROW(b.validate());
    hits = test::collide_equals_brute_force(a, b, poses, 3.5, 12);
    CHECK(hits > poses / 5);
    CHECK(hits < poses - poses / 10);
}
