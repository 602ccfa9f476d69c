// k-DOPs: fits contain what they fit, the re-aligned overlap test is conservative against sampling and
// culls, and collide() on k-DOP trees equals brute force for K = 6, 14, 18, 26 in float and double.
#include "brute_force_check.hpp"

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/sphere.hpp"

#include <thread>

using namespace cdkit;

namespace {
// A random point of the DOP (rejection sampling in the box of its axis slabs); false if none was found.
template <class S, int K> bool sample_in(const Kdop<S, K>& b, std::mt19937_64& rng, Vec3<S>& p) {
    std::uniform_real_distribution<double> u(0, 1);
    for (int tries = 0; tries < 200; ++tries) {
        for (int i = 0; i < 3; ++i) p[i] = S(b.lo(i) + (b.hi(i) - b.lo(i)) * u(rng));
        if (b.contains(p)) return true;
    }
    return false;
}
}  // namespace

#define CDKIT_KDOP_TYPES (Kdop<float, 6>), (Kdop<double, 6>), (Kdop<float, 14>), (Kdop<double, 14>), \
    (Kdop<float, 18>), (Kdop<double, 18>), (Kdop<float, 26>), (Kdop<double, 26>)

TEMPLATE_TEST_CASE("k-DOP fit contains every vertex and merge contains both", "[bv][kdop]", CDKIT_KDOP_TYPES) {
    using BV = TestType;
    using S = typename BV::Scalar;
    for (unsigned seed = 1; seed <= 20; ++seed) {
        auto m = test::random_soup<S>(50, S(0.3), seed);
        if (seed % 2 == 0)
            for (auto& v : m.vertices) v += Vec3<S>(S(1000), S(-2000), S(500));
        const BV bv = test::fit_all<BV>(m);
        REQUIRE(bv.is_valid());
        REQUIRE_FALSE(bv.is_empty());
        for (const auto& v : m.vertices) REQUIRE(bv.contains(v));
        const BV other = test::fit_all<BV>(test::random_soup<S>(10, S(0.3), seed + 100));
        const BV both = BV::merge(bv, other);
        for (const auto& v : m.vertices) REQUIRE(both.contains(v));
        CHECK(both.volume() >= bv.volume());
    }
    CHECK(BV::empty().is_empty());
    CHECK_FALSE(BV::empty().is_valid());
}

TEST_CASE("k-DOPs tighten with K", "[bv][kdop]") {
    // On a sphere the extra slabs cut the box's corners: the fraction of box samples a DOP holds drops.
    const auto m = test::uv_sphere<double>(1.0, 16, 32);
    const auto k6 = test::fit_all<Kdop<double, 6>>(m);
    const auto k14 = test::fit_all<Kdop<double, 14>>(m);
    const auto k26 = test::fit_all<Kdop<double, 26>>(m);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    int in6 = 0, in14 = 0, in26 = 0;
    for (int i = 0; i < 4000; ++i) {
        const Vec3<double> p(u(rng), u(rng), u(rng));
        in6 += k6.contains(p), in14 += k14.contains(p), in26 += k26.contains(p);
    }
    CHECK(in6 == 4000);
    CHECK(in14 < in6 * 0.9);
    CHECK(in26 < in14);
}

TEMPLATE_TEST_CASE("k-DOP overlap under a relative transform is conservative and culls", "[bv][kdop]",
                   CDKIT_KDOP_TYPES) {
    using BV = TestType;
    using S = typename BV::Scalar;
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-1, 1);
    test::OverlapCounts counts;
    const int n = test::scaled(3000, 200);
    for (int i = 0; i < n; ++i) {
        // Thin and fat soups, so that irregular DOPs (redundant planes) occur.
        const S size = (i % 3 == 0) ? S(0.05) : S(0.4);
        auto ma = test::random_soup<S>(4, S(0.4), unsigned(2 * i + 1));
        auto mb = test::random_soup<S>(3, size, unsigned(2 * i + 2));
        if (i % 5 == 0)
            for (auto& v : mb.vertices) v.z() *= S(0.01);
        const BV a = test::fit_all<BV>(ma), b = test::fit_all<BV>(mb);
        Transform<S> b_to_a(test::random_rotation<S>(rng),
                            Vec3<S>(S(1.2 * u(rng)), S(1.2 * u(rng)), S(1.2 * u(rng))));
        test::record_overlap(a, b, b_to_a, [&](Vec3<S>& p) { return sample_in(b, rng, p); }, counts);
    }
    test::check_hit_rates(counts);
}

TEST_CASE("k-DOP overlap: touching DOPs and the 6-DOP against the AABB test", "[bv][kdop]") {
    // Two unit cubes sharing a face (identity rotation) overlap; one ulp-scale gap beyond the padding does not.
    TriangleMesh<double> cube;
    cube.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    cube.triangles = {{0, 1, 2}, {0, 3, 4}};
    const auto k = test::fit_all<Kdop<double, 26>>(cube);
    CHECK(overlap(k, k, Kdop<double, 26>::relative(Transform<double>::translation({1, 0, 0}))));
    CHECK_FALSE(overlap(k, k, Kdop<double, 26>::relative(Transform<double>::translation({1.001, 0, 0}))));
    // The 6-DOP test only checks A's three slabs: whenever the 15-axis AABB test says overlap, so must it.
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    int agree = 0;
    const int n = test::scaled(2000, 100);
    for (int i = 0; i < n; ++i) {
        const auto ma = test::random_soup<double>(3, 0.3, unsigned(7 * i + 1));
        const auto mb = test::random_soup<double>(3, 0.3, unsigned(7 * i + 2));
        const auto a6 = test::fit_all<Kdop<double, 6>>(ma), b6 = test::fit_all<Kdop<double, 6>>(mb);
        const auto aa = test::fit_all<Aabb<double>>(ma), ab = test::fit_all<Aabb<double>>(mb);
        const Transform<double> rel(test::random_rotation(rng), Vec3<double>(u(rng), u(rng), u(rng)));
        const bool box = overlap(aa, ab, Aabb<double>::relative(rel));
        const bool dop = overlap(a6, b6, Kdop<double, 6>::relative(rel));
        if (box) REQUIRE(dop);
        agree += box == dop;
    }
    CHECK(agree > n * 8 / 10);  // the two differ only by the 12 axes the DOP test leaves out
}

TEMPLATE_TEST_CASE("collide on k-DOP trees equals brute force", "[collide][kdop]", CDKIT_KDOP_TYPES) {
    using BV = TestType;
    using S = typename BV::Scalar;
    const int poses = test::scaled(16, 8);
    const MeshModel<BV> sphere(test::uv_sphere<S>(S(1), 8, 16));
    REQUIRE_NOTHROW(sphere.validate());
    int hits = test::collide_equals_brute_force(sphere, sphere, poses, 2.6, 11);
    CHECK(hits > poses / 5);
    CHECK(hits < poses - poses / 10);
    BuildOptions opt;
    opt.split = SplitStrategy::mean;
    opt.max_leaf_triangles = 3;
    const MeshModel<BV> a(test::random_soup<S>(200, S(0.15), 5), opt), b(test::random_soup<S>(150, S(0.2), 6), opt);
    REQUIRE_NOTHROW(a.validate());
    hits = test::collide_equals_brute_force(a, b, poses, 3.5, 12);
    CHECK(hits > poses / 5);
    CHECK(hits < poses - poses / 10);
}

TEST_CASE("k-DOP and sphere trees of degenerate input", "[bvh][kdop][sphere]") {
    TriangleMesh<double> m;
    m.vertices = {{1, 1, 1}, {1, 1, 1 + 1e-300}};
    for (int i = 0; i < 100; ++i) m.triangles.push_back({0, Index(i % 2), 0});  // collapsed to a point
    REQUIRE_NOTHROW(MeshModel<Kdop<double, 26>>(m).validate());
    REQUIRE_NOTHROW(MeshModel<Kdop<float, 14>>(m.cast<float>()).validate());
    REQUIRE_NOTHROW(MeshModel<BoundingSphere<double>>(m).validate());
    const MeshModel<Kdop<double, 18>> k(m);
    CHECK(collide(k, Transform<double>(), k, Transform<double>()).colliding);
    CHECK_FALSE(collide(k, Transform<double>(), k, Transform<double>::translation({0, 0, 1e-9})).colliding);
}

TEST_CASE("collide on k-DOP and sphere trees is thread-safe", "[collide][kdop][threads]") {
    const MeshModel<Kdop<double, 26>> a(test::uv_sphere<double>(1.0, 12, 24));
    const MeshModel<Kdop<double, 26>> b(test::random_soup<double>(300, 0.2, 3));
    const MeshModel<BoundingSphere<double>> sa(a.mesh_ptr()), sb(b.mesh_ptr());
    std::mt19937_64 rng(99);
    std::vector<Transform<double>> poses;
    for (int i = 0; i < 100; ++i) poses.push_back(test::near_pose<double>(rng, 2.0));
    std::vector<std::size_t> expected;
    for (const auto& p : poses) expected.push_back(collide(a, Transform<double>(), b, p, {ContactMode::all}).contacts.size());
    std::vector<int> mismatches(4, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (std::size_t i = 0; i < poses.size(); ++i) {
                if (collide(a, Transform<double>(), b, poses[i], {ContactMode::all}).contacts.size() != expected[i])
                    ++mismatches[t];
                if (collide(sa, Transform<double>(), sb, poses[i], {ContactMode::all}).contacts.size() != expected[i])
                    ++mismatches[t];
            }
        });
    for (auto& th : threads) th.join();
    CHECK(mismatches == std::vector<int>(4, 0));
    CHECK(std::count_if(expected.begin(), expected.end(), [](std::size_t n) { return n > 0; }) > 10);
}
