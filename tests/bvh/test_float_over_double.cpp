// Float bounding volumes over double meshes (MeshModel<BV<float>, double>): every BV rounded outward from
// the double tree's must still hold the double triangles, so collide() and distance() equal the double
// brute force exactly, at ordinary scales, far from the origin and at tiny scales; the tree takes fewer bytes.
#include "brute_force_check.hpp"

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/kdop.hpp"
#include "cdkit/bv/narrow_outward.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bv/sphere.hpp"
#include "cdkit/distance.hpp"
#include "cdkit/io/load_mesh.hpp"

#include <random>

using namespace cdkit;

namespace {
TriangleMesh<double> moved(TriangleMesh<double> m, double scale, const Vec3<double>& offset) {
    for (auto& v : m.vertices) v = v * scale + offset;
    return m;
}
}  // namespace

TEMPLATE_TEST_CASE("narrow_outward: the float BV holds every point of the double BV", "[bv][float_over_double]",
                   Aabb<double>, Obb<double>, (Kdop<double, 18>), BoundingSphere<double>) {
    using BV = TestType;
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(-1, 1);
    const int n = test::scaled(300, 30);
    for (int i = 0; i < n; ++i) {
        const double scale = std::ldexp(1.0, int(u(rng) * 20));
        const Vec3<double> offset = Vec3<double>(u(rng), u(rng), u(rng)) * (i % 3 == 0 ? 1e6 : 1.0);
        const auto soup = moved(test::random_soup<double>(8, 0.3, unsigned(i)), scale, offset);
        const BV wide = test::fit_all<BV>(soup);
        const auto narrow = narrow_outward(wide);
        for (const auto& v : soup.vertices) {
            INFO("soup " << i << ", scale " << scale);
            REQUIRE(narrow.contains(v.cast<float>()));
        }
        CHECK(narrow.volume() >= float(wide.volume()) * 0.999f);
    }
}

TEMPLATE_TEST_CASE("float BVs over a double mesh: collide equals the double brute force", "[collide][float_over_double]",
                   Aabb<float>, Obb<float>, (Kdop<float, 14>), BoundingSphere<float>) {
    using BV = TestType;
    const int poses = test::scaled(50, 10);
    std::mt19937_64 rng(11);
    CollisionRequest all;
    all.mode = ContactMode::all;
    for (const auto& [scale, offset] : {std::pair{1.0, 0.0}, std::pair{1.0, 1e6}, std::pair{1e-6, 1.0}, std::pair{1e3, -3e4}}) {
        INFO("scale " << scale << ", offset " << offset);
        const Vec3<double> o = Vec3<double>::Constant(offset);
        const auto ma = moved(test::uv_sphere<double>(1.0, 10, 20), scale, o);
        const auto mb = moved(test::random_soup<double>(200, 0.25, 3), scale, o);
        const MeshModel<BV, double> a(ma), b(mb);
        REQUIRE_NOTHROW(a.validate());
        REQUIRE_NOTHROW(b.validate());
        int hits = 0;
        for (int i = 0; i < poses; ++i) {
            // Both near their common centre o: rotations about o, translations of the meshes' scale.
            const Transform<double> local = test::near_pose<double>(rng, 3.5 * scale);
            const Transform<double> pb(local.R, o - local.R * o + local.t);
            const auto ref = collide_brute_force(ma, Transform<double>(), mb, pb, all);
            const auto got = collide(a, Transform<double>(), b, pb, all);
            REQUIRE(test::contact_pairs(got) == test::contact_pairs(ref));
            REQUIRE(collide(a, Transform<double>(), b, pb).colliding == ref.colliding);
            hits += ref.colliding;
        }
        CHECK(hits > 0);
        CHECK(hits < poses);
    }
}

TEMPLATE_TEST_CASE("float BVs over a double mesh: the bunny at near-contact poses", "[collide][float_over_double]",
                   Aabb<float>, Obb<float>) {
    using BV = TestType;
    const auto bunny = std::make_shared<const TriangleMesh<double>>(test::unit_scaled(load_mesh(test::data_path("bunny.obj"))));
    const MeshModel<BV, double> model(bunny);
    const MeshModel<Obb<double>> wide(bunny);
    REQUIRE_NOTHROW(model.validate());
    CHECK(model.memory_bytes() < wide.memory_bytes() * 6 / 10);  // float nodes: about half
    // Bunny against bunny is 13.5M triangle pairs for brute force: compare with the double tree instead (both
    // exact, so their pair sets must be equal), and with brute force against a small sphere.
    std::mt19937_64 rng(5);
    CollisionRequest all;
    all.mode = ContactMode::all;
    const int poses = test::scaled(60, 30);  // cheap (two tree queries per pose): the hit-rate checks need 30
    int hits = 0;
    for (int i = 0; i < poses; ++i) {
        const Transform<double> pb = test::near_pose<double>(rng, 2.0);
        const auto ref = collide(wide, Transform<double>(), wide, pb, all);
        REQUIRE(test::contact_pairs(collide(model, Transform<double>(), model, pb, all)) == test::contact_pairs(ref));
        hits += ref.colliding;
    }
    CHECK(hits > 0);
    CHECK(hits < poses);
    const MeshModel<BV, double> ball(test::uv_sphere<double>(0.3, 6, 12));
    test::collide_equals_brute_force(model, ball, test::scaled(30, 4), 1.0, 6);  // REQUIREs inside
}

TEMPLATE_TEST_CASE("float BVs over a double mesh: distance equals the double brute force", "[distance][float_over_double]",
                   Aabb<float>, Obb<float>) {
    using BV = TestType;
    std::mt19937_64 rng(23);
    const int poses = test::scaled(80, 10);
    for (double offset : {0.0, 1e5}) {
        const Vec3<double> o = Vec3<double>::Constant(offset);
        const auto ma = moved(test::uv_sphere<double>(1.0, 8, 16), 1.0, o);
        const auto mb = moved(test::random_soup<double>(120, 0.3, 8), 1.0, o);
        const MeshModel<BV, double> a(ma), b(mb);
        for (int i = 0; i < poses; ++i) {
            const Transform<double> pa = test::near_pose<double>(rng, 0.5), pb = test::near_pose<double>(rng, 4.0);
            const auto got = distance(a, pa, b, pb);
            const auto ref = distance_brute_force(ma, pa, mb, pb);
            INFO("offset " << offset << ", pose " << i);
            REQUIRE(got.distance == ref.distance);  // same triangle routine on the same double points
        }
    }
}

TEST_CASE("float BVs over a double mesh: refit and bad input", "[bvh][float_over_double]") {
    const TriangleMesh<double> m = test::uv_sphere<double>(1.0, 10, 20);
    MeshModel<Obb<float>, double> model(m);
    auto bent = std::make_shared<TriangleMesh<double>>(m);
    for (auto& v : bent->vertices) v.x() *= 1.0 + 0.3 * v.z();
    model.refit(bent);
    REQUIRE_NOTHROW(model.validate());
    CHECK(model.degradation() >= 1.0);
    const MeshModel<Obb<float>, double> fresh(*bent);
    CHECK(test::collide_equals_brute_force(model, fresh, test::scaled(40, 5), 1.5, 9) > 0);
    // Finite in double, too large for float BVs: rejected with a message, not an infinite box.
    TriangleMesh<double> huge = m;
    huge.source = "huge";
    huge.vertices[3].y() = 1e30;
    try {
        const MeshModel<Aabb<float>, double> bad(huge);
        FAIL("accepted a coordinate of 1e30 for float BVs");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("too large for the float bounding volumes") != std::string::npos);
    }
    CHECK_NOTHROW(MeshModel<Aabb<double>>(huge));
}
