// Mesh penetration depth (mesh_depth/): the triangle-pair translation interval against a boolean triangle test on
// sampled translations, the directional depth on boxes with known answers (one face pair, a diagonal, a direction
// that runs B into A's inside), the surface normal's choice, the inner-sphere-tree variant, float meshes, bad input,
// and concurrent queries.
#include "cdkit/mesh_depth/penetration_depth.hpp"
#include "cdkit/narrowphase/triangle.hpp"
#include "ist/ist_test_util.hpp"
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

using namespace cdkit;
using V = Vec3<double>;
using T = Transform<double>;

namespace {

using BoxModel = MeshModel<Obb<double>>;

V random_unit(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    return V(g(rng), g(rng), g(rng)).normalized();
}

}  // namespace

TEST_CASE("mesh depth: a triangle pair's translation interval is where the moved triangles meet", "[mesh_depth]") {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    int nonempty = 0, checked = 0;
    for (int k = 0; k < 300; ++k) {
        std::array<V, 3> P, Q;
        for (auto& p : P) p = V(u(rng), u(rng), u(rng));
        for (auto& q : Q) q = V(u(rng), u(rng), u(rng)) * 0.7 + V(0.3, 0, 0);
        const V n = random_unit(rng);
        const detail::TranslationInterval r = detail::triangle_translation_interval(P, Q, n);
        const auto meet = [&](double t) {
            return triangles_intersect(P[0], P[1], P[2], V(Q[0] + t * n), V(Q[1] + t * n), V(Q[2] + t * n));
        };
        if (!r.empty()) {
            ++nonempty;
            CHECK((r.at_hi_a - r.at_hi_b - r.hi * n).norm() < 1e-9);
        }
        for (double t = -4; t <= 4; t += 0.01) {
            // Away from the ends (by more than the rounding of the clip), the interval and the test agree.
            if (!r.empty() && (std::abs(t - r.lo) < 1e-7 || std::abs(t - r.hi) < 1e-7)) continue;
            const bool inside = !r.empty() && t > r.lo && t < r.hi;
            INFO("pair " << k << " t " << t << " interval [" << r.lo << ", " << r.hi << "]");
            CHECK(meet(t) == inside);
            ++checked;
        }
    }
    CHECK(nonempty > 60);
    CHECK(checked > 200000);
}

TEST_CASE("mesh depth: boxes give the known translations", "[mesh_depth]") {
    const BoxModel a(test::grid_box<double>(V(0.5, 0.5, 0.5), 3));
    const BoxModel b(test::grid_box<double>(V(0.4, 0.4, 0.4), 3));
    const T pa;
    const T pb = T::translation(V(0.7, 0, 0));  // B's x range [0.3, 1.1] against A's [-0.5, 0.5]: 0.2 deep

    SECTION("along the face normal, a diagonal, and a direction that runs B into A") {
        MeshDepthResult r = directional_depth(a, pa, b, pb, V(1, 0, 0));
        REQUIRE(r.status == QueryStatus::ok);
        REQUIRE(r.colliding);
        CHECK(r.depth == Approx(0.2).margin(1e-12));
        CHECK(r.normal.isApprox(V(1, 0, 0)));
        CHECK((r.point_a - r.point_b - r.depth * r.normal).norm() < 1e-12);
        CHECK(std::abs(r.point_a.x() - 0.5) < 1e-12);  // on A's face x = 0.5 ...
        CHECK(std::abs(r.point_b.x() - 0.3) < 1e-12);  // ... met by B's face x = 0.3

        r = directional_depth(a, pa, b, pb, V(3, 3, 0));  // any length
        CHECK(r.depth == Approx(0.2 * std::sqrt(2.0)).margin(1e-12));

        // Along −x, B slides until it lies wholly inside A (x range [-0.3, 0.5] at 0.6): there the surfaces stop
        // crossing, which this measure reports (the file comment says so). It takes more than one pass.
        r = directional_depth(a, pa, b, pb, V(-1, 0, 0));
        CHECK(r.depth == Approx(0.6).margin(1e-12));
        CHECK(r.stats.passes >= 2);
    }
    SECTION("penetration_depth picks the face normal; refinement cannot make it worse") {
        const MeshDepthResult r = penetration_depth(a, pa, b, pb);
        REQUIRE(r.colliding);
        CHECK(r.direction == DepthDirection::surface_normal);
        CHECK(r.normal.isApprox(V(1, 0, 0), 1e-9));
        CHECK(r.depth == Approx(0.2).margin(1e-9));
        MeshDepthRequest refine;
        refine.refine_steps = 3;
        const MeshDepthResult s = penetration_depth(a, pa, b, pb, refine);
        CHECK(s.depth <= r.depth);
        CHECK(s.stats.directions > r.stats.directions);
        // A rotated pose gives the same depth (the query is frame-independent).
        std::mt19937_64 rng(5);
        const T q{test::random_rotation(rng), V(0.3, -0.2, 0.9)};
        const MeshDepthResult m = penetration_depth(a, q * pa, b, q * pb);
        CHECK(m.depth == Approx(0.2).margin(1e-9));
        CHECK(m.normal.isApprox(q.R * V(1, 0, 0), 1e-9));
    }
    SECTION("apart, touching, nested") {
        CHECK_FALSE(penetration_depth(a, pa, b, T::translation(V(1.2, 0, 0))).colliding);
        const MeshDepthResult touch = penetration_depth(a, pa, b, T::translation(V(0.9, 0, 0)));
        CHECK(touch.colliding);
        CHECK(touch.depth == Approx(0).margin(1e-12));
        // B wholly inside A: no surface crosses (as collide() says), so there is no depth to report.
        const MeshDepthResult nested = penetration_depth(a, pa, b, T::translation(V(0.05, 0, 0)));
        CHECK_FALSE(nested.colliding);
        CHECK(nested.depth == 0);
        CHECK(nested.direction == DepthDirection::none);
    }
    SECTION("bad input") {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        CHECK(penetration_depth(a, T::translation(V(nan, 0, 0)), b, pb).status == QueryStatus::invalid_pose);
        T skew = pb;
        skew.R(0, 0) = 2;
        CHECK(penetration_depth(a, pa, b, skew).status == QueryStatus::invalid_pose);
        CHECK(directional_depth(a, pa, b, pb, V::Zero()).status == QueryStatus::invalid_input);
        CHECK(directional_depth(a, pa, b, pb, V(nan, 1, 0)).status == QueryStatus::invalid_input);
        MeshDepthRequest given;
        given.direction = V(0, 0, 0);
        CHECK(penetration_depth(a, pa, b, pb, given).status == QueryStatus::invalid_input);
    }
}

TEST_CASE("mesh depth: every BV and float meshes give the same depth", "[mesh_depth]") {
    const auto ma = test::grid_box<double>(V(0.5, 0.5, 0.5), 2), mb = test::grid_box<double>(V(0.4, 0.3, 0.4), 2);
    std::mt19937_64 rng(9);
    const T pa{test::random_rotation(rng), V(0.1, 0.2, 0.3)};
    const T pb = pa * T{test::random_rotation(rng), V(0.75, 0.1, 0)};
    const double ref = penetration_depth(BoxModel(ma), pa, BoxModel(mb), pb).depth;
    REQUIRE(ref > 0.05);
    CHECK(penetration_depth(MeshModel<Aabb<double>>(ma), pa, MeshModel<Aabb<double>>(mb), pb).depth == Approx(ref).margin(1e-9));
    CHECK(penetration_depth(MeshModel<Rss<double>>(ma), pa, MeshModel<Rss<double>>(mb), pb).depth == Approx(ref).margin(1e-9));
    CHECK(penetration_depth(MeshModel<Kdop<double, 18>>(ma), pa, MeshModel<Kdop<double, 18>>(mb), pb).depth ==
          Approx(ref).margin(1e-9));
    CHECK(penetration_depth(MeshModel<BoundingSphere<double>>(ma), pa, MeshModel<BoundingSphere<double>>(mb), pb).depth ==
          Approx(ref).margin(1e-9));
    const auto to_float = [](const TriangleMesh<double>& m) {
        TriangleMesh<float> f;
        f.triangles = m.triangles;
        for (const auto& v : m.vertices) f.vertices.push_back(v.cast<float>());
        return f;
    };
    const MeshModel<Obb<float>, float> fa(to_float(ma)), fb(to_float(mb));
    const MeshDepthResult f = penetration_depth(fa, pa.cast<float>(), fb, pb.cast<float>());
    CHECK(f.depth == Approx(ref).margin(1e-5));
}

TEST_CASE("mesh depth: with inner sphere trees the force direction competes and the volume is reported", "[mesh_depth]") {
    const TriangleMesh<double> bunny = test::unit_bunny();
    const BoxModel model(bunny);
    const InnerSphereTree& ist = test::small_bunny_tree();
    const T pa;
    const T pb = T::translation(V(0.55, 0.1, 0));  // deep enough that inner spheres overlap
    const MeshDepthResult r = penetration_depth(model, ist, pa, model, ist, pb);
    REQUIRE(r.colliding);
    CHECK(r.volume == Approx(penetration_volume(ist, pa, ist, pb).volume));
    REQUIRE(r.volume > 0);
    CHECK(r.force_direction.norm() == Approx(1));
    CHECK(r.force_direction.x() > 0.5);  // B sits at +x of A: the force pushes it on
    const MeshDepthResult s = penetration_depth(model, pa, model, pb);
    CHECK(r.depth <= s.depth);  // the force direction is one more candidate
    CHECK(r.stats.directions >= 2);
    // Along the force direction alone the depth is that direction's.
    MeshDepthRequest along;
    along.direction = r.force_direction;
    const MeshDepthResult f = penetration_depth(model, ist, pa, model, ist, pb, along);
    CHECK(f.direction == DepthDirection::given);
    CHECK(f.depth >= r.depth - 1e-9);
}

TEST_CASE("mesh depth: queries are const and thread-safe", "[mesh_depth]") {
    const BoxModel model(test::unit_bunny());
    std::mt19937_64 rng(3);
    std::vector<T> poses;
    std::vector<double> expected;
    for (int k = 0; k < 16; ++k) {
        poses.push_back(T{test::random_rotation(rng), 0.6 * random_unit(rng)});
        expected.push_back(penetration_depth(model, T{}, model, poses.back()).depth);
    }
    std::vector<std::vector<double>> got(4);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (const T& p : poses) got[t].push_back(penetration_depth(model, T{}, model, p).depth);
        });
    for (auto& th : threads) th.join();
    for (const auto& g : got) CHECK(g == expected);
}
