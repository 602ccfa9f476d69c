// ConvexPolyhedron support queries that start hill climbing from the direction table (hulls above
// brute_force_limit vertices): the answer is a maximising vertex for every direction, in particular on the
// table's cell boundaries, on the cube's edges and corners (face ties), and for tiny, huge, subnormal,
// zero, infinite and NaN directions (those must give some vertex, never a crash).
#include <catch2/catch.hpp>

#include <cdkit/io/load_mesh.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>

#include "test_common.hpp"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace cdkit;

namespace {

template <class S> std::vector<Vec3<S>> cloud(std::mt19937_64& rng, int n, const Vec3<S>& radii) {
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0.5, 1.0);
    std::vector<Vec3<S>> p;
    for (int i = 0; i < n; ++i) {
        Vec3<double> x = Vec3<double>(g(rng), g(rng), g(rng)).normalized() * u(rng);
        p.push_back(Vec3<S>(S(x[0]) * radii[0], S(x[1]) * radii[1], S(x[2]) * radii[2]));
    }
    return p;
}

/// Directions on and next to the table's cell boundaries, cube edges and corners, plus random ones. Larger hulls
/// tabulate 2 or 4 times finer (table_res … 4·table_res cells per face side): their boundaries are all among these.
template <class S> std::vector<Vec3<S>> probe_directions(std::mt19937_64& rng, int random_count) {
    std::vector<Vec3<S>> ds;
    const int k = 4 * ConvexPolyhedron<S>::table_res;
    const S big = std::numeric_limits<S>::max();
    for (int axis = 0; axis < 3; ++axis)
        for (S sgn : {S(-1), S(1)})
            for (int i = 0; i <= k; ++i)
                for (int j = 0; j <= k; ++j) {
                    Vec3<S> d;
                    d[axis] = sgn;
                    d[(axis + 1) % 3] = S(2 * i) / S(k) - S(1);
                    d[(axis + 2) % 3] = S(2 * j) / S(k) - S(1);
                    ds.push_back(d);
                    Vec3<S> e = d;  // just off the boundary, both ways
                    e[(axis + 1) % 3] = std::nextafter(e[(axis + 1) % 3], big);
                    e[(axis + 2) % 3] = std::nextafter(e[(axis + 2) % 3], -big);
                    ds.push_back(e);
                    e[axis] = std::nextafter(e[axis], S(0));  // the main axis no longer the largest at the rim
                    ds.push_back(e);
                }
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z)
                if (x || y || z) ds.push_back(Vec3<S>(S(x), S(y), S(z)));
    std::normal_distribution<double> g;
    for (int i = 0; i < random_count; ++i) ds.push_back(Vec3<S>(S(g(rng)), S(g(rng)), S(g(rng))));
    // Magnitudes: the cell depends on ratios only, but the ratio must not overflow.
    const std::size_t base = ds.size();
    for (std::size_t i = 0; i < base; i += 7)
        for (S f : {S(1e-30), S(1e30), std::numeric_limits<S>::min(), std::numeric_limits<S>::max() / S(4)})
            ds.push_back(ds[i] * f);
    return ds;
}

template <class S> void check_hull(const ConvexPolyhedron<S>& hull, std::mt19937_64& rng, int random_count) {
    const auto& vs = hull.vertices();
    std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(vs.size()) + 5);
    int wrong = 0, checked = 0;
    for (const Vec3<S>& d : probe_directions<S>(rng, random_count)) {
        S best = -std::numeric_limits<S>::infinity();
        for (const auto& v : vs) best = std::max(best, d.dot(v));
        if (!std::isfinite(best)) continue;  // products overflow at the largest magnitudes: nothing to compare
        ++checked;
        if (d.dot(hull.support(d)) != best) { ++wrong; UNSCOPED_INFO("nohint d " << d.transpose() << " got " << d.dot(hull.support(d)) << " best " << best); }
        std::uint32_t hint = pick(rng);
        const std::uint32_t hint0 = hint;
        if (d.dot(hull.support(d, hint)) != best) { ++wrong; UNSCOPED_INFO("d " << d.transpose() << " hint " << hint0 << " got " << d.dot(vs[hint]) << " best " << best); }
        if (hint >= vs.size() || d.dot(vs[hint]) != best) ++wrong;
    }
    CHECK(checked > 1000);
    CHECK(wrong == 0);
    // Degenerate directions: some vertex, no crash (the table is skipped, the seeds answer).
    const S inf = std::numeric_limits<S>::infinity(), nan = std::numeric_limits<S>::quiet_NaN();
    const S sub = std::numeric_limits<S>::denorm_min();
    for (const Vec3<S>& d : {Vec3<S>(0, 0, 0), Vec3<S>(sub, sub, -sub), Vec3<S>(nan, 1, 0), Vec3<S>(1, nan, 2),
                             Vec3<S>(0, 0, nan), Vec3<S>(inf, 1, 0), Vec3<S>(1, -inf, inf), Vec3<S>(nan, nan, nan)}) {
        CHECK(hull.support_index(d) < vs.size());
        std::uint32_t hint = 3;
        (void)hull.support(d, hint);
        CHECK(hint < vs.size());
    }
}

}  // namespace

TEMPLATE_TEST_CASE("hull support from the direction table equals brute force on cell boundaries", "[gjk][convex_hull]",
                   float, double) {
    using S = TestType;
    std::mt19937_64 rng(77);
    const int random_count = test::scaled(2000, 200);
    for (int n : {80, 200, 2000}) {
        INFO("points " << n);
        ConvexPolyhedron<S> hull(cloud<S>(rng, n, Vec3<S>(1, 1, 1)));
        REQUIRE(hull.vertices().size() > ConvexPolyhedron<S>::brute_force_limit);
        check_hull(hull, rng, random_count);
    }
    // Anisotropic and far from the origin: the table's cells are directions, whatever the shape.
    ConvexPolyhedron<S> needle(cloud<S>(rng, 300, Vec3<S>(S(1e3), S(1), S(1e-3))));
    check_hull(needle, rng, random_count);
    std::vector<Vec3<S>> shifted = cloud<S>(rng, 300, Vec3<S>(1, 2, 3));
    for (auto& p : shifted) p += Vec3<S>(S(1e4), S(-2e4), S(5));
    check_hull(ConvexPolyhedron<S>(shifted), rng, random_count);
}

// Hulls of real meshes (issue 39): elongated, with vertices whose normal cones range from wide (at the corners) to
// narrow (smooth parts), where many table cells answer without a scan (certified cells; the margin argument in
// build_start_table). Directions clustered about a few random axes, at small angles, probe near the certified
// cells' borders, where a wrong certificate would show first.
TEMPLATE_TEST_CASE("hull support equals brute force on hulls of real meshes", "[gjk][convex_hull]", float, double) {
    using S = TestType;
    std::mt19937_64 rng(39);
    for (const char* name : {"bunny.obj", "teapot.obj", "armadillo.obj"}) {
        INFO(name);
        const TriangleMesh<double> mesh = load_mesh(test::data_path(name));
        Vec3<double> lo = mesh.vertices[0], hi = lo;
        for (const auto& v : mesh.vertices) {
            lo = lo.cwiseMin(v);
            hi = hi.cwiseMax(v);
        }
        std::vector<Vec3<S>> pts;
        for (const auto& v : mesh.vertices) pts.push_back(((v - (lo + hi) / 2) * (2 / (hi - lo).maxCoeff())).template cast<S>());
        const ConvexPolyhedron<S> hull(pts);
        REQUIRE(hull.vertices().size() > ConvexPolyhedron<S>::brute_force_limit);
        check_hull(hull, rng, test::scaled(2000, 200));
        std::normal_distribution<double> g;
        int wrong = 0, checked = 0;
        for (int axis = 0; axis < test::scaled(200, 20); ++axis) {
            const Vec3<double> c = Vec3<double>(g(rng), g(rng), g(rng)).normalized();
            std::uint32_t hint = std::uint32_t(-1);
            for (double spread : {1e-1, 1e-2, 1e-4, 1e-7}) {
                for (int i = 0; i < 10; ++i) {
                    const Vec3<S> d = (c + spread * Vec3<double>(g(rng), g(rng), g(rng))).template cast<S>();
                    S best = -std::numeric_limits<S>::infinity();
                    for (const auto& v : hull.vertices()) best = std::max(best, d.dot(v));
                    ++checked;
                    wrong += d.dot(hull.support(d)) != best;
                    wrong += d.dot(hull.support(d, hint)) != best;
                }
            }
        }
        CHECK(checked > 100);
        CHECK(wrong == 0);
    }
}
