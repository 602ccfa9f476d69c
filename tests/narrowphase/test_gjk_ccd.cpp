// cdkit GJK/EPA against libccd (GJK, MPR, GJK+EPA penetration) on the same shapes and poses. The only
// test TU that includes libccd.
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/epa.hpp>

#include "../../benchmarks/convex/ccd_adapter.hpp"
#include "mesh_factory.hpp"
#include "test_common.hpp"

using namespace cdkit;

namespace {
Transform<double> rpose(std::mt19937_64& rng, double spread) {
    std::uniform_real_distribution<double> u(-spread, spread);
    return {test::random_rotation(rng), Vec3<double>(u(rng), u(rng), u(rng))};
}
std::vector<Vec3<double>> rpoints(std::mt19937_64& rng, int n, double r) {
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0.3, 1.0);
    std::vector<Vec3<double>> p;
    for (int i = 0; i < n; ++i) p.push_back(Vec3<double>(g(rng), g(rng), g(rng)).normalized() * r * u(rng));
    return p;
}

struct Tally {
    int cases = 0, hits = 0, gjk_disagree = 0, mpr_disagree = 0, ours_below = 0, ccd_off = 0, ccd_pen_fail = 0,
        compared = 0;
};

template <class A, class B> void compare(const A& a, const B& b, std::mt19937_64& rng, Tally& t, double depth_tol) {
    Transform<double> pa = rpose(rng, 0.4), pb = rpose(rng, 0.9);
    auto d = gjk_distance(a, pa, b, pb);
    auto p = penetration(a, pa, b, pb);
    bench::CcdObject oa = bench::make_ccd_object(a, pa), ob = bench::make_ccd_object(b, pb);
    ccd_t ccd = bench::make_ccd();
    bool ccd_gjk = ccdGJKIntersect(&oa, &ob, &ccd) != 0;
    bool ccd_mpr = ccdMPRIntersect(&oa, &ob, &ccd) != 0;
    ++t.cases;
    // Only clear-cut cases are compared: libccd decides with its own tolerances near contact.
    bool clear_sep = d.status == GjkStatus::separated && d.distance > 1e-4;
    bool clear_hit = p.status == GjkStatus::intersecting && p.depth > 1e-4;
    if (clear_hit) ++t.hits;
    if (clear_sep || clear_hit) {
        if (ccd_gjk != clear_hit) ++t.gjk_disagree;
        if (ccd_mpr != clear_hit) ++t.mpr_disagree;
    }
    if (clear_hit) {
        ccd_real_t depth;
        ccd_vec3_t dir, pos;
        if (ccdGJKPenetration(&oa, &ob, &ccd, &depth, &dir, &pos) != 0) { ++t.ccd_pen_fail; return; }
        ++t.compared;
        // Both EPAs converge from inside D, so a converged depth is a lower bound of the true depth: ours
        // must never be below libccd's (test_epa.cpp checks ours against an exact SAT reference).
        if (p.depth < double(depth) - depth_tol * std::max(1.0, p.depth)) ++t.ours_below;
        if (std::abs(double(depth) - p.depth) > 1e-3 * std::max(1.0, p.depth)) ++t.ccd_off;
    }
}
}  // namespace

TEST_CASE("cdkit GJK/EPA agree with libccd GJK, MPR and penetration", "[gjk][epa][ccd]") {
    std::mt19937_64 rng(77);
    ConvexPolyhedron<double> hull1(rpoints(rng, 60, 0.8)), hull2(rpoints(rng, 400, 0.6));
    Box<double> box({0.5, 0.3, 0.4});
    Cylinder<double> cyl(0.3, 0.5);
    Cone<double> cone(0.4, 0.5);
    Ellipsoid<double> ell({0.5, 0.25, 0.35});
    Capsule<double> cap(0.2, 0.4);
    Tally poly, curved;
    int n = test::scaled(400, 20);
    for (int i = 0; i < n; ++i) {
        compare(hull1, hull2, rng, poly, 1e-9);
        compare(box, hull1, rng, poly, 1e-9);
        compare(cyl, cone, rng, curved, 1e-4);
        compare(ell, box, rng, curved, 1e-4);
        compare(cap, hull2, rng, curved, 1e-4);
    }
    for (const Tally* t : {&poly, &curved}) {
        INFO("cases " << t->cases << " hits " << t->hits << " compared " << t->compared << " ours below ccd "
                      << t->ours_below << " ccd off by > 1e-3: " << t->ccd_off << " ccd penetration failures "
                      << t->ccd_pen_fail);
        CHECK(t->gjk_disagree == 0);
        CHECK(t->mpr_disagree == 0);
        CHECK(t->hits > t->cases / 10);
        CHECK(t->hits < t->cases * 9 / 10);
        CHECK(t->ours_below == 0);
        CHECK(t->compared > t->hits / 2);
    }
}
