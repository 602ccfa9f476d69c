// IST queries against brute force over all sphere pairs and against the analytic lens volume; symmetry,
// ist_query's one descent against the two traversals (bit for bit), time-critical bounds, invalid poses
// and concurrent const queries.
#include "ist_test_util.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <set>
#include <thread>

using namespace cdkit;
using cdkit::test::scaled;

namespace {

constexpr double kPi = 3.14159265358979323846;

Transform<double> random_pose(std::mt19937_64& rng, double spread) {
    std::uniform_real_distribution<double> u(-spread, spread);
    return {test::random_rotation(rng), Vec3<double>(u(rng), u(rng), u(rng))};
}

const InnerSphereTree& sphere_tree() {
    static const InnerSphereTree tree = [] {
        PackingOptions p;
        p.max_spheres = 300;
        p.grid_resolution = 32;
        return build_inner_sphere_tree(test::uv_sphere(1.0, 32, 64), p);
    }();
    return tree;
}

}  // namespace

TEST_CASE("lens volume formula: limits and symmetry", "[ist][query]") {
    CHECK(sphere_intersection_volume(1, 1, 2) == 0);
    CHECK(sphere_intersection_volume(1, 1, 3) == 0);
    CHECK(sphere_intersection_volume(1, 0.5, 0.2) == Approx(4.0 / 3.0 * kPi * 0.125));
    CHECK(sphere_intersection_volume(1, 1, 1e-9) == Approx(4.0 / 3.0 * kPi).epsilon(1e-6));
    // Two unit spheres at distance 1: 5π/12.
    CHECK(sphere_intersection_volume(1, 1, 1) == Approx(5 * kPi / 12).epsilon(1e-12));
    CHECK(sphere_intersection_volume(0.7, 0.4, 0.9) == Approx(sphere_intersection_volume(0.4, 0.7, 0.9)).epsilon(1e-14));
    // Continuous at both ends of the lens range.
    CHECK(sphere_intersection_volume(1, 0.5, 1.5 - 1e-9) < 1e-12);
    CHECK(sphere_intersection_volume(1, 0.5, 0.5 + 1e-9) == Approx(4.0 / 3.0 * kPi * 0.125).epsilon(1e-6));
}

TEST_CASE("penetration volume equals brute force over all sphere pairs", "[ist][query]") {
    const InnerSphereTree& t = test::small_bunny_tree();
    std::mt19937_64 rng(21);
    int hits = 0;
    const int n = scaled(40, 8);
    for (int i = 0; i < n; ++i) {
        const auto pa = random_pose(rng, 0.3), pb = random_pose(rng, 0.9);
        const auto r = penetration_volume(t, pa, t, pb);
        const auto bf = test::brute_volume(t, pa, t, pb);
        REQUIRE(r.status == QueryStatus::ok);
        CHECK(r.complete);
        CHECK(r.volume == Approx(bf.volume).epsilon(1e-10).margin(1e-15));
        CHECK(r.volume_lower == r.volume);
        CHECK(r.volume_upper == r.volume);
        std::set<std::pair<std::uint32_t, std::uint32_t>> got;
        double sum = 0;
        for (const auto& p : r.pairs) got.emplace(p.a, p.b), sum += p.volume;
        CHECK(got == std::set<std::pair<std::uint32_t, std::uint32_t>>(bf.pairs.begin(), bf.pairs.end()));
        CHECK(sum == Approx(r.volume).epsilon(1e-12).margin(1e-15));
        CHECK(r.calibrated >= r.volume);
        // The estimate: the cell spheres' lens volumes (radius r·∛w) over the same pairs.
        double cells = 0;
        for (const auto& p : bf.pairs) {
            const double d = (pa * t.spheres()[p.first].center - pb * t.spheres()[p.second].center).norm();
            const double ra = t.spheres()[p.first].radius * std::cbrt(t.cell_weights()[p.first]);
            const double rb = t.spheres()[p.second].radius * std::cbrt(t.cell_weights()[p.second]);
            cells += sphere_intersection_volume(ra, rb, d);
        }
        CHECK(r.calibrated == Approx(cells).epsilon(1e-10).margin(1e-15));
        // Symmetric in A and B.
        const auto s = penetration_volume(t, pb, t, pa);
        CHECK(s.volume == Approx(r.volume).epsilon(1e-10).margin(1e-15));
        hits += r.volume > 0;
    }
    CHECK(hits >= n / 4);
    CHECK(hits < n);  // some poses must be apart, or the test could not see a false overlap
}

TEST_CASE("penetration volume is zero when apart, and distance equals brute force", "[ist][query]") {
    const InnerSphereTree& t = test::small_bunny_tree();
    std::mt19937_64 rng(22);
    int apart = 0;
    for (int i = 0; i < scaled(40, 8); ++i) {
        const auto pa = random_pose(rng, 0.2), pb = random_pose(rng, 2.0);
        const auto q = ist_query(t, pa, t, pb);
        const double bf = test::brute_distance(t, pa, t, pb);
        REQUIRE(q.status == QueryStatus::ok);
        if (bf > 0) {
            ++apart;
            CHECK_FALSE(q.colliding);
            CHECK(q.volume.volume == 0);
            CHECK(q.volume.pairs.empty());
            CHECK(q.distance.distance == Approx(bf).epsilon(1e-10));
            CHECK((q.distance.point_a - q.distance.point_b).norm() == Approx(bf).epsilon(1e-9));
            const auto& sa = t.spheres()[q.distance.sphere_a];
            const auto& sb = t.spheres()[q.distance.sphere_b];
            CHECK((pa * sa.center - q.distance.point_a).norm() == Approx(sa.radius).epsilon(1e-9));
            CHECK((pb * sb.center - q.distance.point_b).norm() == Approx(sb.radius).epsilon(1e-9));
        } else if (bf < -1e-12) {
            CHECK(q.colliding);
            CHECK(q.volume.volume > 0);
            CHECK(sphere_distance(t, pa, t, pb).distance == 0);
        }
    }
    CHECK(apart >= 4);
}

TEST_CASE("ist_query's one descent gives the two traversals' answers bit for bit", "[ist][query]") {
    const InnerSphereTree& t = test::small_bunny_tree();
    std::mt19937_64 rng(23);
    int apart = 0, overlapping = 0;
    const int n = scaled(60, 12);
    for (int i = 0; i < n; ++i) {
        // Spreads from deep overlap to well apart, so both branches are exercised at every scale.
        const auto pa = random_pose(rng, 0.2), pb = random_pose(rng, 0.4 + 1.6 * double(i % 4) / 3);
        const auto q = ist_query(t, pa, t, pb);
        const auto v = penetration_volume(t, pa, t, pb);
        REQUIRE(q.status == QueryStatus::ok);
        CHECK(q.volume.volume == v.volume);
        CHECK(q.volume.calibrated == v.calibrated);
        CHECK(q.volume.volume_lower == v.volume_lower);
        CHECK(q.volume.volume_upper == v.volume_upper);
        REQUIRE(q.volume.pairs.size() == v.pairs.size());
        for (std::size_t k = 0; k < v.pairs.size(); ++k) {
            CHECK(q.volume.pairs[k].a == v.pairs[k].a);
            CHECK(q.volume.pairs[k].b == v.pairs[k].b);
            CHECK(q.volume.pairs[k].volume == v.pairs[k].volume);
        }
        CHECK(q.colliding == (v.volume > 0));
        if (v.volume > 0) {
            ++overlapping;
            CHECK(q.distance.distance == 0);
            continue;
        }
        ++apart;
        const auto d = sphere_distance(t, pa, t, pb);
        CHECK(q.distance.distance == d.distance);
        CHECK(q.distance.lower_bound == d.lower_bound);
        CHECK(q.distance.complete);
        if (q.distance.sphere_a == d.sphere_a && q.distance.sphere_b == d.sphere_b) {  // ties may pick another pair
            CHECK(q.distance.point_a == d.point_a);
            CHECK(q.distance.point_b == d.point_b);
        }
        // Less work than the two traversals: the volume pass's tests are shared.
        CHECK(q.stats.node_tests <= v.stats.node_tests + d.stats.node_tests);
    }
    CHECK(apart >= n / 8);
    CHECK(overlapping >= n / 8);
    // The same on trees of different objects (different depths and radii), both ways round.
    const InnerSphereTree& s = sphere_tree();
    for (int i = 0; i < scaled(20, 6); ++i) {
        const auto pa = random_pose(rng, 0.3), pb = random_pose(rng, 0.6 + 1.2 * double(i % 3) / 2);
        for (int swap = 0; swap < 2; ++swap) {
            const InnerSphereTree& x = swap ? s : t;
            const InnerSphereTree& y = swap ? t : s;
            const auto q = ist_query(x, pa, y, pb);
            const auto v = penetration_volume(x, pa, y, pb);
            CHECK(q.volume.volume == v.volume);
            CHECK(q.volume.calibrated == v.calibrated);
            CHECK(q.volume.pairs.size() == v.pairs.size());
            if (v.volume == 0) CHECK(q.distance.distance == sphere_distance(x, pa, y, pb).distance);
        }
    }
}

TEST_CASE("sphere meshes: penetration volume matches the analytic lens", "[ist][query]") {
    const InnerSphereTree& t = sphere_tree();
    CHECK(t.coverage() > 0.9);  // the first inner sphere nearly fills the tessellated ball
    for (double d : {0.3, 0.6, 1.0, 1.4, 1.8}) {
        const Transform<double> pb(Mat3<double>::Identity(), Vec3<double>(d, 0.1 * d, 0));
        const double dist = pb.t.norm();
        const double exact = sphere_intersection_volume(1, 1, dist);
        const auto r = penetration_volume(t, {}, t, pb);
        INFO("distance " << dist << " IST " << r.volume << " analytic " << exact);
        // Thin lenses (d near 2) are the most sensitive to the tessellation's inward sag (~0.5% of r).
        CHECK(r.volume == Approx(exact).epsilon(dist < 1.5 ? 0.05 : 0.12));
        CHECK(r.volume <= exact);  // inner spheres lie inside the ball
    }
    const Transform<double> apart(Mat3<double>::Identity(), Vec3<double>(2.05, 0, 0));
    CHECK(penetration_volume(t, {}, t, apart).volume == 0);
    CHECK(sphere_distance(t, {}, t, apart).distance == Approx(0.05).margin(0.03));
}

TEST_CASE("time-critical mode: the interval holds the exact volume and tightens with the budget", "[ist][query]") {
    const InnerSphereTree& t = test::small_bunny_tree();
    std::mt19937_64 rng(23);
    int tested = 0;
    for (int i = 0; i < scaled(20, 6); ++i) {
        const auto pa = random_pose(rng, 0.2), pb = random_pose(rng, 0.6);
        const auto full = penetration_volume(t, pa, t, pb);
        const double exact = full.volume;
        if (exact == 0) continue;
        ++tested;
        double first_width = -1, last_lower = 0, last_upper = std::numeric_limits<double>::infinity();
        for (std::uint64_t budget : {10, 100, 1000, 100000000}) {
            IstRequest req;
            req.max_node_tests = budget;
            const auto r = penetration_volume(t, pa, t, pb, req);
            INFO("budget " << budget << " exact " << exact << " [" << r.volume_lower << ", " << r.volume_upper << "]");
            CHECK(r.volume_lower <= exact * (1 + 1e-12));
            CHECK(r.volume_upper >= exact * (1 - 1e-12));
            CHECK(r.volume >= r.volume_lower);
            CHECK(r.volume <= r.volume_upper);
            // A larger budget runs the same expansion further: the interval never widens.
            CHECK(r.volume_lower >= last_lower);
            CHECK(r.volume_upper <= last_upper);
            last_lower = r.volume_lower;
            last_upper = r.volume_upper;
            if (first_width < 0) first_width = r.volume_upper - r.volume_lower;
            if (budget == 1000) CHECK(r.volume_upper - r.volume_lower < first_width);
            if (budget == 100000000) {
                CHECK(r.complete);
                CHECK(r.volume == Approx(exact).epsilon(1e-10));
                CHECK(r.calibrated == Approx(full.calibrated).epsilon(1e-10));  // nothing left to extrapolate
            } else if (!r.complete) {
                // The estimate of what is left: its raw estimate times a ratio between the prior 1/coverage²
                // and the ratio seen so far, so never below the pairs already summed.
                CHECK(r.calibrated >= r.volume_lower);
                CHECK(std::isfinite(r.calibrated));
            }
        }
        IstRequest req;
        req.max_node_tests = 20;
        const auto d = sphere_distance(t, pa, t, pb, req);
        CHECK(d.lower_bound <= std::max(0.0, test::brute_distance(t, pa, t, pb)) + 1e-12);
    }
    CHECK(tested >= 2);
}

TEST_CASE("time-critical ist_query: one pass over one budget; volume as penetration_volume's, distance bounded", "[ist][query]") {
    const InnerSphereTree& t = test::small_bunny_tree();
    std::mt19937_64 rng(25);
    int apart = 0, overlapping = 0, apart_complete = 0, apart_cut = 0;
    for (int i = 0; i < scaled(40, 10); ++i) {
        const auto pa = random_pose(rng, 0.2), pb = random_pose(rng, 1.4);
        const auto full = ist_query(t, pa, t, pb);
        const double bf = test::brute_distance(t, pa, t, pb);
        for (std::uint64_t budget : {5, 40, 400, 100000000}) {
            IstRequest req;
            req.max_node_tests = budget;
            const auto q = ist_query(t, pa, t, pb, req);
            const auto v = penetration_volume(t, pa, t, pb, req);
            INFO("pose " << i << " budget " << budget);
            REQUIRE(q.status == QueryStatus::ok);
            // The volume part is the budgeted volume traversal, bit for bit.
            CHECK(q.volume.volume == v.volume);
            CHECK(q.volume.volume_lower == v.volume_lower);
            CHECK(q.volume.volume_upper == v.volume_upper);
            CHECK(q.volume.calibrated == v.calibrated);
            CHECK(q.volume.complete == v.complete);
            // One budget for both parts: at most one node's children past it.
            CHECK(q.stats.node_tests <= budget + 16);
            if (q.colliding) {
                CHECK(q.distance.distance == 0);
                CHECK(full.colliding);
                continue;
            }
            CHECK(q.distance.lower_bound <= std::max(0.0, bf) + 1e-12);
            if (q.distance.complete) {
                CHECK(q.volume.complete);
                CHECK(q.distance.distance == sphere_distance(t, pa, t, pb).distance);
                CHECK(q.distance.lower_bound == q.distance.distance);
            } else if (std::isfinite(q.distance.distance)) {
                CHECK(q.distance.distance >= std::max(0.0, bf) - 1e-12);  // a pair found: an upper bound
            }
            if (budget == 100000000) {
                CHECK(q.volume.complete);
                CHECK(q.distance.complete);
                CHECK(q.colliding == full.colliding);
                CHECK(q.distance.distance == full.distance.distance);
            }
            if (bf > 0 && budget == 400) (q.distance.complete ? apart_complete : apart_cut) += 1;
        }
        (bf > 0 ? apart : overlapping) += 1;
    }
    CHECK(apart >= 2);
    CHECK(overlapping >= 2);
    CHECK(apart_complete + apart_cut == apart);
}

TEST_CASE("invalid poses are refused", "[ist][query]") {
    const InnerSphereTree& t = test::small_bunny_tree();
    Transform<double> bad;
    bad.R(0, 0) = 2;
    CHECK(penetration_volume(t, {}, t, bad).status == QueryStatus::invalid_pose);
    CHECK(sphere_distance(t, bad, t, {}).status == QueryStatus::invalid_pose);
    bad = {};
    bad.t.x() = std::numeric_limits<double>::quiet_NaN();
    CHECK(ist_query(t, {}, t, bad).status == QueryStatus::invalid_pose);
}

TEST_CASE("const queries from several threads give identical results", "[ist][query]") {
    const InnerSphereTree& t = test::small_bunny_tree();
    std::mt19937_64 rng(24);
    std::vector<std::pair<Transform<double>, Transform<double>>> poses;
    for (int i = 0; i < scaled(30, 6); ++i) poses.emplace_back(random_pose(rng, 0.2), random_pose(rng, 1.2));
    std::vector<double> ref_volume, ref_distance;
    for (const auto& [pa, pb] : poses) {
        const auto q = ist_query(t, pa, t, pb);
        ref_volume.push_back(q.volume.volume);
        ref_distance.push_back(q.distance.distance);
    }
    std::vector<int> mismatches(4, 0);
    std::vector<std::thread> threads;
    for (int k = 0; k < 4; ++k)
        threads.emplace_back([&, k] {
            for (int rep = 0; rep < 3; ++rep)
                for (std::size_t i = 0; i < poses.size(); ++i) {
                    const auto q = ist_query(t, poses[i].first, t, poses[i].second);
                    mismatches[k] += q.volume.volume != ref_volume[i] || q.distance.distance != ref_distance[i];
                }
        });
    for (auto& th : threads) th.join();
    for (int m : mismatches) CHECK(m == 0);
}
