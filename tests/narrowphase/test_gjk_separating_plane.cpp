// Separating-plane test (perceptron with temporal coherence): never wrong against GJK, and under coherent
// motion most frames are decided by the cached plane without GJK.
#include <catch2/catch.hpp>

#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/separating_plane.hpp>

#include "mesh_factory.hpp"
#include "test_common.hpp"

using namespace cdkit;

TEST_CASE("separating plane agrees with GJK; coherence avoids GJK", "[gjk][separating_plane]") {
    std::mt19937_64 rng(21);
    std::normal_distribution<double> g;
    std::vector<Vec3<double>> pts;
    for (int i = 0; i < 300; ++i) pts.push_back(Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 0.5);
    ConvexPolyhedron<double> hull(pts);
    Cylinder<double> cyl(0.3, 0.4);
    SeparatingPlaneCache<double> cache;
    int frames = test::scaled(2000, 200), wrong = 0, hits = 0, gjk_calls = 0;
    for (int f = 0; f < frames; ++f) {
        double t = 0.01 * f;
        Transform<double> pa(Eigen::AngleAxisd(0.7 * t, Vec3<double>(0, 0, 1)).toRotationMatrix(), Vec3<double>::Zero());
        Transform<double> pb(Eigen::AngleAxisd(0.3 * t, Vec3<double>(1, 0, 0)).toRotationMatrix(),
                             Vec3<double>(1.1 * std::cos(t), 0.9 * std::sin(1.3 * t), 0.2));
        auto r = separating_plane_intersect(hull, pa, cyl, pb, cache);
        bool ref = gjk_distance(hull, pa, cyl, pb).colliding();
        if (r.colliding != ref) ++wrong;
        hits += ref;
        gjk_calls += r.used_gjk;
    }
    CHECK(wrong == 0);
    CHECK(hits > frames / 20);
    CHECK(hits < frames * 19 / 20);
    // Separated frames are far more common than GJK fallbacks: coherence works.
    CHECK(gjk_calls < frames / 2);
    UNSCOPED_INFO("frames " << frames << " colliding " << hits << " GJK fallbacks " << gjk_calls);
    // Random (incoherent) poses: still never wrong.
    SeparatingPlaneCache<double> c2;
    int wrong2 = 0;
    for (int i = 0; i < test::scaled(1000, 50); ++i) {
        Transform<double> pb(test::random_rotation(rng), Vec3<double>(g(rng), g(rng), g(rng)));
        auto r = separating_plane_intersect(hull, Transform<double>{}, cyl, pb, c2);
        if (r.colliding != gjk_distance(hull, Transform<double>{}, cyl, pb).colliding()) ++wrong2;
    }
    CHECK(wrong2 == 0);
}
