// Sphere packing: spheres inside the mesh and disjoint (independent brute force), coverage, determinism,
// and the input gate (open, non-manifold, flipped, empty, flat meshes).
#include "ist_test_util.hpp"

#include "cdkit/ist/closed_mesh.hpp"
#include "cdkit/ist/detail/min_norm_point.hpp"
#include "cdkit/ist/inside_test.hpp"
#include "cdkit/ist/point_mesh_distance.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#if defined(CDKIT_HAS_TBB) && CDKIT_HAS_TBB
#include <tbb/global_control.h>
#endif

using namespace cdkit;
using cdkit::test::scaled;

namespace {

// Distance from p to the mesh by brute force over the triangles (independent of the packer's BVH search:
// a projection-or-segment computation, not the Voronoi-region code).
double brute_surface_distance(const TriangleMesh<double>& m, const Vec3<double>& p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const auto [a, b, c] = m.triangle(t);
        const Vec3<double> n = (b - a).cross(c - a);
        const double nn = n.squaredNorm();
        if (nn > 0) {
            const Vec3<double> q = p - n * (n.dot(p - a) / nn);
            if (n.dot((b - a).cross(q - a)) >= 0 && n.dot((c - b).cross(q - b)) >= 0 && n.dot((a - c).cross(q - c)) >= 0)
                best = std::min(best, (p - q).norm());
        }
        for (const auto& [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
            const Vec3<double> e = v - u;
            const double s = std::clamp((p - u).dot(e) / std::max(e.squaredNorm(), 1e-300), 0.0, 1.0);
            best = std::min(best, (p - (u + s * e)).norm());
        }
    }
    return best;
}

void require_error_containing(const TriangleMesh<double>& m, const std::string& what) {
    try {
        (void)pack_spheres(m, PackingOptions{50});
        FAIL("no cdkit::Error for " << what);
    } catch (const Error& e) {
        INFO(e.what());
        CHECK(std::string(e.what()).find(what) != std::string::npos);
        CHECK(std::string(e.what()).find(m.source) != std::string::npos);
    }
}

TriangleMesh<double> tetra() {
    TriangleMesh<double> m;
    m.source = "<tetra>";
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
}

}  // namespace

TEST_CASE("closed mesh gate: volume of known solids", "[ist][packing]") {
    const auto sphere = test::uv_sphere(1.0, 48, 96);
    CHECK(check_closed_mesh(sphere) == Approx(4.0 / 3.0 * 3.14159265358979 ).epsilon(0.01));
    CHECK(check_closed_mesh(tetra()) == Approx(1.0 / 6.0).epsilon(1e-12));
    auto inward = tetra();
    for (auto& t : inward.triangles) std::swap(t[1], t[2]);
    CHECK(signed_mesh_volume(inward) == Approx(-1.0 / 6.0).epsilon(1e-12));
    CHECK(check_closed_mesh(inward) == Approx(1.0 / 6.0).epsilon(1e-12));  // inward-facing but consistent
}

TEST_CASE("bad meshes are rejected with cdkit::Error and the edge counts", "[ist][packing]") {
    SECTION("open teapot") {
        require_error_containing(load_mesh(test::data_path("teapot.obj")), "boundary (open) edges");
    }
    SECTION("one flipped face") {
        auto m = test::uv_sphere(1.0, 8, 16);
        std::swap(m.triangles[5][1], m.triangles[5][2]);
        require_error_containing(m, "3 inconsistently oriented edges");
    }
    SECTION("non-manifold: two tetrahedra on one edge") {
        auto m = tetra();
        m.vertices.push_back({0.5, -1, -1});
        m.vertices.push_back({0.5, -1, 1});
        m.triangles.push_back({0, 1, 4});
        m.triangles.push_back({1, 0, 5});
        m.triangles.push_back({0, 4, 5});
        m.triangles.push_back({1, 5, 4});
        require_error_containing(m, "non-manifold edges");
    }
    SECTION("empty") {
        TriangleMesh<double> m;
        m.source = "<empty>";
        require_error_containing(m, "no triangles");
    }
    SECTION("zero volume: a doubled triangle") {
        TriangleMesh<double> m;
        m.source = "<flat>";
        m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        m.triangles = {{0, 1, 2}, {0, 2, 1}};
        require_error_containing(m, "encloses no volume");
    }
    SECTION("tiny: volume underflows") {
        auto m = tetra();
        for (auto& v : m.vertices) v *= 1e-120;
        require_error_containing(m, "encloses no volume");
    }
    SECTION("NaN vertex") {
        auto m = tetra();
        m.vertices[2].x() = std::numeric_limits<double>::quiet_NaN();
        require_error_containing(m, "NaN");
    }
    SECTION("options out of range") {
        PackingOptions o;
        o.target_coverage = 1.5;
        CHECK_THROWS_AS(pack_spheres(tetra(), o), Error);
        o = {};
        o.max_spheres = 0;
        CHECK_THROWS_AS(pack_spheres(tetra(), o), Error);
        o = {};
        o.lookahead = -0.1;
        CHECK_THROWS_AS(pack_spheres(tetra(), o), Error);
        o.lookahead = 4.5;
        CHECK_THROWS_AS(pack_spheres(tetra(), o), Error);
        CHECK_THROWS_AS(InnerSphereTree(SpherePacking{}), Error);
    }
}

TEST_CASE("inside test agrees with the generalised winding number", "[ist][packing]") {
    const auto bunny = test::unit_bunny();
    const InsideTest inside(bunny);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.05, 1.05);
    int in = 0;
    const int n = scaled(400, 60);
    for (int i = 0; i < n; ++i) {
        const Vec3<double> p(u(rng), u(rng), u(rng));
        const double w = winding_number(bunny, p);
        if (std::abs(w - std::round(w)) > 0.01) continue;  // too near the surface to call
        INFO("point " << p.transpose() << " winding " << w);
        CHECK(inside.winding(p) == int(std::lround(w)));
        in += inside.inside(p);
    }
    CHECK(in > n / 20);  // the test must see inside points, not only outside ones
}

TEST_CASE("packed spheres lie inside the mesh and do not overlap (brute force)", "[ist][packing]") {
    const auto bunny = test::unit_bunny();
    PackingOptions o;
    o.max_spheres = std::size_t(scaled(300, 60));
    o.grid_resolution = 32;
    // With the look-ahead (default) refined centres wait in the heap while other spheres are placed; without
    // it each refinement is placed at once.
    const double look = GENERATE(PackingOptions{}.lookahead, 0.0);
    o.lookahead = look;
    INFO("lookahead " << look);
    const SpherePacking p = pack_spheres(bunny, o);
    REQUIRE(p.spheres.size() == o.max_spheres);
    CHECK(p.stop == PackingStop::max_spheres);
    const auto& s = p.spheres;
    for (std::size_t i = 0; i < s.size(); ++i) {
        INFO("sphere " << i << " at " << s[i].center.transpose() << " r " << s[i].radius);
        REQUIRE(s[i].radius > 0);
        CHECK(std::abs(winding_number(bunny, s[i].center) - 1.0) < 1e-6);
        CHECK(brute_surface_distance(bunny, s[i].center) >= s[i].radius);
        for (std::size_t j = 0; j < i; ++j) REQUIRE((s[i].center - s[j].center).norm() >= s[i].radius + s[j].radius);
    }
    double vol = 0;
    for (const auto& x : s) vol += x.volume();
    CHECK(p.sphere_volume == Approx(vol).epsilon(1e-12));
    CHECK(p.coverage() == Approx(vol / p.mesh_volume).epsilon(1e-12));
    CHECK(p.coverage() > 0.5);
    CHECK(p.coverage() < 1.0);
    REQUIRE(p.cell_weights.size() == s.size());
    double cells = 0;
    for (std::size_t i = 0; i < s.size(); ++i) cells += p.cell_weights[i] * s[i].volume();
    CHECK(cells >= vol);                      // weights ≥ 1
    CHECK(cells == Approx(p.mesh_volume).epsilon(0.2));  // cells tile the mesh (up to the clamping at 1)
}

TEST_CASE("coverage grows with the sphere count; packing is deterministic per seed", "[ist][packing]") {
    const auto bunny = test::unit_bunny();
    PackingOptions o;
    o.grid_resolution = 40;
    o.max_spheres = 600;
    o.depth_calibration = false;  // the spheres do not depend on it
    const SpherePacking p = pack_spheres(bunny, o);
    double last = 0;
    for (std::size_t n : {1, 10, 50, 200, 600}) {
        const double c = p.coverage_of_first(n);
        CHECK(c > last);
        last = c;
    }
    CHECK(p.coverage_of_first(600) > p.coverage_of_first(50) + 0.05);
    const SpherePacking again = pack_spheres(bunny, o);
    REQUIRE(again.spheres.size() == p.spheres.size());
    for (std::size_t i = 0; i < p.spheres.size(); ++i) {
        CHECK(again.spheres[i].center == p.spheres[i].center);
        CHECK(again.spheres[i].radius == p.spheres[i].radius);
    }
    o.target_coverage = 0.6;
    const SpherePacking partial = pack_spheres(bunny, o);
    CHECK(partial.stop == PackingStop::target_coverage);
    CHECK(partial.coverage() >= 0.6);
    CHECK(partial.spheres.size() < p.spheres.size());
}

TEST_CASE("point-mesh distance on the tree equals brute force", "[ist][packing]") {
    const auto bunny = test::unit_bunny();
    const PointMeshDistance dist(bunny);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.3, 1.3);
    for (int i = 0; i < scaled(100, 20); ++i) {
        const Vec3<double> p(u(rng), u(rng), u(rng));
        const auto q = dist.query(p);
        CHECK(q.distance == Approx(brute_surface_distance(bunny, p)).epsilon(1e-9).margin(1e-12));
        CHECK((q.point - p).norm() == Approx(q.distance).epsilon(1e-12));
    }
}

TEST_CASE("point-mesh distance: hint, stop_at and quantum keep their promises", "[ist][packing]") {
    const auto bunny = test::unit_bunny();
    const PointMeshDistance dist(bunny);
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> u(-1.1, 1.1);
    std::uniform_int_distribution<Index> tri(0, Index(bunny.triangles.size() - 1));
    const double quantum = 0.03;
    for (int i = 0; i < scaled(100, 20); ++i) {
        const Vec3<double> p(u(rng), u(rng), u(rng));
        const double exact = dist.query(p).distance;
        PointMeshDistance::PointMeshQuery o;
        o.hint = tri(rng);  // any triangle: the answer must not depend on it
        CHECK(dist.query(p, o).distance == exact);
        o.hint = dist.query(p).triangle;  // the closest one itself
        CHECK(dist.query(p, o).distance == exact);
        // stop_at: exact above the threshold; at most the threshold (and not below the distance) otherwise.
        for (const double stop : {0.5 * exact, exact * 0.999, 1.5 * exact + 0.01}) {
            o.hint = tri(rng);
            o.stop_at = stop;
            const double d = dist.query(p, o).distance;
            if (exact > stop) CHECK(d == exact);
            else CHECK((d <= stop && d >= exact));
        }
        // quantum: the same ⌊d / quantum⌋, never below the distance.
        o.stop_at = -1;
        o.quantum = quantum;
        const double dq = dist.query(p, o).distance;
        CHECK(std::floor(dq / quantum) == std::floor(exact / quantum));
        CHECK(dq >= exact);
        o.quantum = 0;
    }
}

TEST_CASE("tree over the packing: valid, out-degree respected, leaves are the spheres", "[ist][tree]") {
    const auto bunny = test::unit_bunny();
    PackingOptions o;
    o.grid_resolution = 32;
    o.max_spheres = 300;
    const SpherePacking p = pack_spheres(bunny, o);
    for (int degree : {2, 4, 8}) {
        IstBuildOptions b;
        b.out_degree = degree;
        const InnerSphereTree t(p, b);
        CHECK_NOTHROW(t.validate());
        CHECK(t.spheres().size() == p.spheres.size());
        CHECK(t.coverage() == Approx(p.coverage()).epsilon(1e-9));
        std::size_t leaves = 0, max_children = 0;
        for (const auto& n : t.nodes()) {
            leaves += n.is_leaf();
            max_children = std::max<std::size_t>(max_children, n.count);
        }
        CHECK(leaves == p.spheres.size());
        CHECK(max_children <= std::size_t(degree));
        CHECK(t.stats().depth >= 2);
        CHECK(t.stats().depth < 40);
    }
}

TEST_CASE("depth calibration: rescales the cell weights, keeps them ≥ 1 and their total near the volume", "[ist][packing]") {
    const auto bunny = test::unit_bunny();
    PackingOptions o;
    // On a coarse lattice the derived α sits at or near 1: for the cell-sphere estimate, 400 spheres, 0.97 at
    // 48 samples across (1.0 in the clang build: the clamp), 0.91 at 64, 0.64 at 80 — used here, well inside
    // (0, 1). The look-ahead (placement order) is off: it does not touch the calibration, and seven packings
    // with it would cost the sanitizer job seconds.
    o.grid_resolution = 80;
    o.lookahead = 0;
    o.max_spheres = 400;
    o.depth_calibration = false;
    const SpherePacking plain = pack_spheres(bunny, o);
    o.depth_calibration = true;
    o.depth_calibration_iterations = 0;
    const SpherePacking none = pack_spheres(bunny, o);  // zero rounds: the plain cell weights
    o.depth_calibration_iterations = 4;
    o.depth_calibration_strength = 0;
    const SpherePacking zero = pack_spheres(bunny, o);  // zero strength: the plain cell weights too
    o.depth_calibration_strength = 1;
    const SpherePacking full = pack_spheres(bunny, o);
    o.depth_calibration_strength = PackingOptions{}.depth_calibration_strength;
    const SpherePacking fitted = pack_spheres(bunny, o);
    REQUIRE(fitted.spheres.size() == plain.spheres.size());
    REQUIRE(fitted.cell_weights.size() == plain.cell_weights.size());
    CHECK(none.cell_weights == plain.cell_weights);
    REQUIRE(full.cell_weights.size() == plain.cell_weights.size());
    CHECK(PackingOptions{}.depth_calibration);  // on by default
    CHECK(zero.cell_weights == plain.cell_weights);
    // The default strength is derived (self-contacts), recorded, strictly inside (0, 1) on the bunny, and the
    // weights are the geometric blend of the plain and the fully fitted ones at it: between them.
    const double alpha = fitted.calibration_strength;
    CHECK(alpha > 0);
    CHECK(alpha < 1);
    CHECK(full.calibration_strength == 1);
    CHECK(plain.calibration_strength == 0);
    std::size_t between = 0;
    for (std::size_t i = 0; i < fitted.spheres.size(); ++i) {
        const double lo = std::min(plain.cell_weights[i], full.cell_weights[i]), hi = std::max(plain.cell_weights[i], full.cell_weights[i]);
        between += fitted.cell_weights[i] >= lo * (1 - 1e-12) && fitted.cell_weights[i] <= hi * (1 + 1e-12);
        CHECK(fitted.cell_weights[i] == Approx(std::pow(plain.cell_weights[i], 1 - alpha) * std::pow(full.cell_weights[i], alpha)).epsilon(1e-12));
    }
    {   // A fixed strength equal to the derived one gives the same weights; the derivation is deterministic.
        PackingOptions fixed = o;
        fixed.depth_calibration_strength = alpha;
        const SpherePacking same = pack_spheres(bunny, fixed);
        CHECK(same.calibration_strength == alpha);
        CHECK(pack_spheres(bunny, o).cell_weights == fitted.cell_weights);
        for (std::size_t i = 0; i < fitted.spheres.size(); ++i) CHECK(same.cell_weights[i] == Approx(fitted.cell_weights[i]).epsilon(1e-12));
    }
    CHECK(between == fitted.spheres.size());
    double total = 0;
    std::size_t changed = 0, raised_small = 0, small = 0;
    double median_radius = 0;
    {
        std::vector<double> r;
        for (const auto& s : fitted.spheres) r.push_back(s.radius);
        std::nth_element(r.begin(), r.begin() + std::ptrdiff_t(r.size() / 2), r.end());
        median_radius = r[r.size() / 2];
    }
    for (std::size_t i = 0; i < fitted.spheres.size(); ++i) {
        CHECK(fitted.spheres[i].radius == plain.spheres[i].radius);  // the spheres themselves do not change
        CHECK(fitted.cell_weights[i] >= 1.0);
        total += fitted.cell_weights[i] * fitted.spheres[i].volume();
        changed += fitted.cell_weights[i] != plain.cell_weights[i];
        if (fitted.spheres[i].radius < median_radius) {
            ++small;
            raised_small += fitted.cell_weights[i] > plain.cell_weights[i];
        }
    }
    CHECK(changed > fitted.spheres.size() / 2);
    CHECK(total == Approx(fitted.mesh_volume).epsilon(0.2));
    // The outer layer holds the most empty space, and the small spheres sit there: most of them gain weight.
    CHECK(raised_small > small / 2);
    o.depth_calibration_strength = 1.5;
    CHECK_THROWS_AS(pack_spheres(bunny, o), Error);
    o.depth_calibration_strength = -0.1;
    CHECK_THROWS_AS(pack_spheres(bunny, o), Error);
    o.depth_calibration_strength = PackingOptions::derived_strength;
    o.depth_calibration_contact_depth = 0;
    CHECK_THROWS_AS(pack_spheres(bunny, o), Error);
    o.depth_calibration_contact_depth = 0.6;
    CHECK_THROWS_AS(pack_spheres(bunny, o), Error);
    o.depth_calibration_contact_depth = 0.05;
    o.depth_calibration_iterations = -1;
    CHECK_THROWS_AS(pack_spheres(bunny, o), Error);
    o.depth_calibration_iterations = 101;
    CHECK_THROWS_AS(pack_spheres(bunny, o), Error);
}

TEST_CASE("least-norm point of a hull: optimal, against a dense search of the hull", "[ist][packing]") {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g;
    int zero = 0, nonzero = 0;
    for (int trial = 0; trial < scaled(300, 60); ++trial) {
        const int n = 1 + trial % 4;
        std::vector<Vec3<double>> v(static_cast<std::size_t>(n), Vec3<double>::Zero());
        // Unit vectors, as the packing's gradients; half the trials lean on one side (a nonzero answer).
        const Vec3<double> lean = (trial / 4) % 2 ? Vec3<double>(g(rng), g(rng), g(rng)).normalized() : Vec3<double>::Zero();
        for (auto& x : v) x = (Vec3<double>(g(rng), g(rng), g(rng)).normalized() + 1.2 * lean).normalized();
        if (trial % 5 == 0 && n >= 2) v[1] = -v[0];  // opposite constraints: the origin lies in the hull
        const Vec3<double> z = detail::min_norm_in_hull(v);
        // Optimal: no hull point is shorter (z·v_i ≥ |z|² for all i means z·p ≥ |z|² for every hull point p).
        for (const auto& x : v) CHECK(z.dot(x) >= z.squaredNorm() - 1e-9);
        // Attained: a simplex lattice of convex weights (step 1/24) gets within its spacing of |z|.
        double lattice = std::numeric_limits<double>::infinity();
        constexpr int m = 24;
        for (int a = 0; a <= m; ++a)
            for (int b = 0; b <= m - a; ++b)
                for (int c = 0; c <= m - a - b; ++c) {
                    const int d = m - a - b - c;
                    if ((n < 2 && b) || (n < 3 && c) || (n < 4 && d)) continue;  // weights of absent vectors
                    const Vec3<double> p = (double(a) * v[0] + double(b) * v[std::size_t(std::min(1, n - 1))] +
                                            double(c) * v[std::size_t(std::min(2, n - 1))] +
                                            double(d) * v[std::size_t(std::min(3, n - 1))]) / double(m);
                    lattice = std::min(lattice, p.norm());
                }
        INFO("trial " << trial << " n " << n << " |z| " << z.norm() << " lattice " << lattice);
        CHECK(z.norm() <= lattice + 1e-12);
        CHECK(z.norm() >= lattice - 2.0 / m);
        (z.norm() < 1e-9 ? zero : nonzero) += 1;
    }
    CHECK(zero > 0);  // both kinds of answer were exercised
    CHECK(nonzero > zero);
}

TEST_CASE("look-ahead: more coverage for the same count; deterministic and thread-count independent", "[ist][packing]") {
    const auto bunny = test::unit_bunny();
    PackingOptions o;
    o.grid_resolution = 32;
    o.max_spheres = std::size_t(scaled(400, 100));
    o.depth_calibration = false;
    const SpherePacking ahead = pack_spheres(bunny, o);
    o.lookahead = 0;
    const SpherePacking direct = pack_spheres(bunny, o);
    INFO("coverage with look-ahead " << ahead.coverage() << ", without " << direct.coverage());
    CHECK(ahead.coverage() > direct.coverage());
    // The greedy order is (almost) largest first either way: radii non-increasing up to the polish step.
    std::size_t rises = 0;
    for (std::size_t i = 1; i < ahead.spheres.size(); ++i) rises += ahead.spheres[i].radius > ahead.spheres[i - 1].radius * 1.05;
    CHECK(rises < ahead.spheres.size() / 10);
#if defined(CDKIT_HAS_TBB) && CDKIT_HAS_TBB
    o.lookahead = PackingOptions{}.lookahead;
    o.depth_calibration = true;
    const SpherePacking many = pack_spheres(bunny, o);
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    const SpherePacking single = pack_spheres(bunny, o);
    REQUIRE(single.spheres.size() == many.spheres.size());
    for (std::size_t i = 0; i < many.spheres.size(); ++i) {
        CHECK(single.spheres[i].center == many.spheres[i].center);
        CHECK(single.spheres[i].radius == many.spheres[i].radius);
        CHECK(single.cell_weights[i] == many.cell_weights[i]);
    }
    CHECK(single.calibration_strength == many.calibration_strength);
#endif
}

TEST_CASE("the Armadillo: coverage at 10k spheres meets issue #7's 85% (76% at 1k in reduced runs)", "[ist][packing]") {
    // The same packing as cdkit_bench_ist's (default options; the depth calibration does not move the spheres).
    // Measured: 85.3% at 10,000 spheres and 76.7% at 1,000 (g++ 12, Release); the bounds leave a small margin
    // for another compiler's rounding of the greedy order.
    const bool full = test::scale() >= 1;
    PackingOptions o;
    o.max_spheres = full ? 10000 : 1000;
    o.depth_calibration = false;
    const SpherePacking p = pack_spheres(test::unit_scaled(load_mesh(test::data_path("armadillo.obj"))), o);
    INFO(p.spheres.size() << " spheres, coverage " << p.coverage());
    CHECK(p.spheres.size() == o.max_spheres);
    CHECK(p.coverage() >= (full ? 0.85 : 0.76));
}
