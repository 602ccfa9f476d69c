// Speculative contacts pay for one GJK search (issue 35, "World's contact path runs GJK once"): gjk_distance_within
// against the two calls it replaces (gjk_intersect, then gjk_distance for a pair within the margin), and
// contact_manifold with a margin against a copy of its former two-call body. Seeded random pairs of boxes, hulls,
// capsules, cylinders and spheres, overlapping, within the margin and beyond it, cold (no cache) and warm (a
// coherent motion with per-pair caches): the same colliding flags and classifications, distances within GJK's
// tolerance, the same manifold points, and fewer GJK iterations than the two calls on the pairs within the margin.
#include "cdkit/manifold/contact_manifold.hpp"
#include "cdkit/narrowphase/convex_polyhedron.hpp"
#include "cdkit/narrowphase/convex_shapes.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <tuple>
#include <typeinfo>
#include <vector>

using namespace cdkit;

namespace {

using OV = Vec3<double>;
using OT = Transform<double>;

OT one_search_random_pose(std::mt19937_64& rng, const OV& t) {
    std::uniform_real_distribution<double> u(-1, 1);
    const OV axis(u(rng), u(rng), u(rng));
    return {Eigen::AngleAxisd(3.0 * u(rng), axis.normalized()).toRotationMatrix(), t};
}

std::vector<OV> one_search_hull_points(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<OV> p;
    for (int i = 0; i < 24; ++i) p.emplace_back(0.5 * u(rng), 0.35 * u(rng), 0.3 * u(rng));
    return p;
}

/// The former contact_manifold body after its argument checks: gjk_intersect, then, for a pair apart by at most the
/// margin, gjk_distance from scratch (the caller's cache shared by both), then the same features and clipping.
template <class A, class B>
ContactManifold<double> one_search_old_manifold(const A& a, const OT& pose_a, const B& b, const OT& pose_b,
                                                const ManifoldRequest& request, ManifoldCache<double>* cache) {
    using S = double;
    ContactManifold<S> m;
    if constexpr (std::is_same_v<A, Box<S>> && std::is_same_v<B, Box<S>>) {
        if (!request.single_point) {
            const detail::BoxBoxOutcome o = detail::box_box_manifold(a, pose_a, b, pose_b, S(request.margin), m);
            if (o == detail::BoxBoxOutcome::done) {
                if (cache) detail::carry_ids(m, pose_a, *cache);
                return m;
            }
            m = ContactManifold<S>{};
        }
    }
    GjkCache<S>* gjk_cache = cache ? &cache->gjk : nullptr;
    const GjkResult<S> g = gjk_intersect(a, pose_a, b, pose_b, gjk_cache);
    m.stats.gjk_iterations = g.iterations;
    ManifoldPoint<S> deepest;
    Vec3<S> n;
    if (g.colliding) {
        const PenetrationResult<S> p = penetration(a, pose_a, b, pose_b, g);
        m.stats.gjk_iterations += p.gjk_iterations;
        m.stats.epa_iterations = p.epa_iterations;
        m.colliding = true;
        n = p.normal;
        deepest = {p.point_a, p.point_b, p.status == GjkStatus::intersecting ? p.depth : S(0), 0};
    } else {
        m.distance = g.distance;
        if (!(request.margin > 0) || g.distance > S(request.margin)) {
            if (cache) cache->count = 0;
            return m;
        }
        const GjkResult<S> d = gjk_distance(a, pose_a, b, pose_b, gjk_cache);
        m.stats.gjk_iterations += d.iterations;
        m.distance = d.distance;
        if (d.distance > S(request.margin)) {
            if (cache) cache->count = 0;
            return m;
        }
        m.colliding = d.colliding;
        n = d.normal;
        deepest = {d.point_a, d.point_b, -d.distance, 0};
    }
    if (!n.allFinite() || !(n.squaredNorm() > S(0.5))) {
        n = detail::safe_normalized(Vec3<S>(pose_b * Vec3<S>(b.center()) - pose_a * Vec3<S>(a.center())));
        if (!(n.squaredNorm() > S(0.5))) n = Vec3<S>(S(0), S(0), S(1));
    }
    const detail::FeatureTolerance<S> tol(request.feature_angle);
    const detail::ContactFeature<S> fa = detail::supporting_feature(a, pose_a, n, tol);
    const detail::ContactFeature<S> fb = detail::supporting_feature(b, pose_b, Vec3<S>(-n), tol);
    if (fa.count == 1 || fb.count == 1 || !detail::clip_features(fa, fb, n, S(request.margin), m)) {
        m.normal = n;
        m.count = 1;
        deepest.id = detail::contact_id(std::uint64_t(fa.index) << 1, fb.index, 0xFFFFFFFFull);
        m.points[0] = deepest;
    }
    if (cache) detail::carry_ids(m, pose_a, *cache);
    return m;
}

/// What the comparisons found, over all shape pairs.
struct OneSearchTally {
    int colliding = 0, within = 0, beyond = 0;
    long old_within_iterations = 0, new_within_iterations = 0;  // GJK iterations on the pairs within the margin
    long old_all_iterations = 0, new_all_iterations = 0;
    int manifold_points = 0;
    int compared_ids = 0, same_ids = 0;
};

/// B's poses: a random direction from A, pushed from touching (bisection on the boolean) by a gap drawn from
/// [−margin, 3·margin], then moved coherently over `frames` steps (small turns and shifts).
template <class A, class B>
std::vector<OT> one_search_motion(const A& a, const OT& pa, const B& b, std::mt19937_64& rng, double margin,
                                  int frames) {
    std::uniform_real_distribution<double> u(-1, 1);
    const OT pb0 = one_search_random_pose(rng, OV::Zero());
    const OV dir = OV(u(rng), u(rng), u(rng)).normalized();
    double lo = 0, hi = 6;
    for (int i = 0; i < 50; ++i) {
        const double mid = (lo + hi) / 2;
        (gjk_intersect(a, pa, b, OT(pb0.R, pa.t + mid * dir)).colliding ? lo : hi) = mid;
    }
    const double gap = margin * (1 + 2 * u(rng));
    std::vector<OT> poses{OT(pb0.R, pa.t + (hi + gap) * dir)};
    const OV drift = 0.2 * margin * OV(u(rng), u(rng), u(rng));
    const OV spin(u(rng), u(rng), u(rng));
    for (int f = 1; f < frames; ++f) {
        const OT& p = poses.back();
        const Mat3<double> turn = Eigen::AngleAxisd(0.01, spin.normalized()).toRotationMatrix();
        poses.emplace_back(turn * p.R, p.t + drift);
    }
    return poses;
}

/// gjk_distance_within(margin) against gjk_intersect then gjk_distance, cold and warm, over `pairs` motions.
template <class A, class B>
void one_search_compare_gjk(const A& a, const B& b, std::mt19937_64& rng, double margin, int pairs, OneSearchTally& t) {
    for (int pair = 0; pair < pairs; ++pair) {
        const OT pa = one_search_random_pose(rng, OV(0.1, -0.2, 0.3));
        const std::vector<OT> poses = one_search_motion(a, pa, b, rng, margin, 12);
        GjkCache<double> old_cache, new_cache;
        for (std::size_t f = 0; f < poses.size(); ++f) {
            const OT& pb = poses[f];
            const GjkResult<double> reference = gjk_distance(a, pa, b, pb);
            // A pair within GJK's tolerance of the margin may fall either side of it: not a disagreement.
            if (std::abs(reference.distance - margin) < 1e-7) continue;
            for (bool warm : {false, true}) {
                INFO("pair " << pair << " frame " << f << (warm ? " warm" : " cold") << " distance "
                             << reference.distance);
                const GjkResult<double> gi = gjk_intersect(a, pa, b, pb, warm ? &old_cache : nullptr);
                const bool old_tested = !gi.colliding && gi.distance <= margin;
                GjkResult<double> gd;
                if (old_tested) gd = gjk_distance(a, pa, b, pb, warm ? &old_cache : nullptr);
                const bool old_colliding = gi.colliding || (old_tested && gd.colliding);
                const bool old_within = old_tested && !gd.colliding && gd.distance <= margin;
                const GjkResult<double> g = gjk_distance_within(a, pa, b, pb, margin, warm ? &new_cache : nullptr);
                const bool new_within = !g.colliding && g.distance <= margin;
                REQUIRE(g.colliding == old_colliding);
                REQUIRE(new_within == old_within);
                const int old_iterations = gi.iterations + (old_tested ? gd.iterations : 0);
                t.old_all_iterations += old_iterations;
                t.new_all_iterations += g.iterations;
                if (g.colliding) {
                    ++t.colliding;
                } else if (new_within) {
                    ++t.within;
                    // Both within GJK's tolerance of the true distance (rel_tolerance 1e-10, plus rounding).
                    CHECK(std::abs(g.distance - gd.distance) <= 4e-10 * gd.distance + 1e-12);
                    CHECK(g.status == gd.status);
                    if (gd.distance > 1e-6) CHECK((g.normal - gd.normal).norm() < 1e-5);
                    t.old_within_iterations += old_iterations;
                    t.new_within_iterations += g.iterations;
                } else {
                    ++t.beyond;
                    CHECK(g.distance > margin);  // a lower bound beyond the margin
                    CHECK(g.distance <= reference.distance + 1e-9);
                }
            }
        }
    }
}

/// contact_manifold with a margin against the former two-call body, with per-pair caches over the motion.
template <class A, class B>
void one_search_compare_manifold(const A& a, const B& b, std::mt19937_64& rng, double margin, int pairs,
                                 OneSearchTally& t) {
    ManifoldRequest request;
    request.margin = margin;
    for (int pair = 0; pair < pairs; ++pair) {
        const OT pa = one_search_random_pose(rng, OV(-0.3, 0.2, 0.1));
        const std::vector<OT> poses = one_search_motion(a, pa, b, rng, margin, 12);
        ManifoldCache<double> old_cache, new_cache;
        for (std::size_t f = 0; f < poses.size(); ++f) {
            const OT& pb = poses[f];
            if (std::abs(gjk_distance(a, pa, b, pb).distance - margin) < 1e-7) continue;
            INFO(typeid(A).name() << " / " << typeid(B).name() << " pair " << pair << " frame " << f);
            const ContactManifold<double> old_m = one_search_old_manifold(a, pa, b, pb, request, &old_cache);
            const ContactManifold<double> new_m = contact_manifold(a, pa, b, pb, request, &new_cache);
            REQUIRE(new_m.colliding == old_m.colliding);
            REQUIRE(new_m.count == old_m.count);
            if (new_m.count == 0) continue;
            INFO("colliding " << new_m.colliding << " distance " << new_m.distance << " depth " << new_m.max_depth());
            // Polytope cores: both searches end on the same feature, the same normal up to rounding. Curved ones: two
            // GJK runs that meet the distance tolerance (1e-10 relative) agree on the normal only to about its square
            // root, and a colliding pair's EPA, started from another tetrahedron, to its own tolerance.
            const double tol = HasPolytopeCore<A> && HasPolytopeCore<B> ? 1e-8 : 1e-4;
            CHECK((new_m.normal - old_m.normal).norm() < tol);
            CHECK(std::abs(new_m.max_depth() - old_m.max_depth()) < tol);
            if (new_m.colliding) continue;  // EPA's witness point on a curved pair: only its depth is well defined
            CHECK(std::abs(new_m.distance - old_m.distance) <= 4e-10 * old_m.distance + 1e-12);
            for (int i = 0; i < new_m.count; ++i) {
                double nearest = 1e300;
                int j = 0;
                for (int k = 0; k < old_m.count; ++k) {
                    const double d = (new_m.points[i].point_a - old_m.points[k].point_a).norm();
                    if (d < nearest) nearest = d, j = k;
                }
                INFO("point " << i << " nearest old point " << j);
                CHECK(nearest < tol);
                CHECK((new_m.points[i].point_b - old_m.points[j].point_b).norm() < tol);
                CHECK(std::abs(new_m.points[i].depth - old_m.points[j].depth) < tol);
                // Ids: the same features; a single point keeps last frame's id only when its position repeats
                // to the last bit (carry_ids), which the two searches' rounding need not share.
                ++t.compared_ids;
                t.same_ids += new_m.points[i].id == old_m.points[j].id;
            }
            t.manifold_points += new_m.count;
            if (!new_m.colliding) {
                t.old_within_iterations += old_m.stats.gjk_iterations;
                t.new_within_iterations += new_m.stats.gjk_iterations;
            }
        }
    }
}

/// Every ordered pair of the five shapes through `f(a, b)`.
template <class F> void one_search_each_pair(std::mt19937_64& rng, F&& f) {
    const Box<double> box(OV(0.5, 0.3, 0.2));
    const ConvexPolyhedron<double> hull(one_search_hull_points(rng));
    const Capsule<double> capsule(0.2, 0.4);
    const Cylinder<double> cylinder(0.3, 0.25);
    const Sphere<double> sphere(0.35);
    const auto shapes = std::tie(box, hull, capsule, cylinder, sphere);
    const auto against_each = [&](const auto& x) { std::apply([&](const auto&... y) { (f(x, y), ...); }, shapes); };
    std::apply([&](const auto&... x) { (against_each(x), ...); }, shapes);
}

}  // namespace

TEST_CASE("gjk_distance_within answers as gjk_intersect then gjk_distance, in fewer iterations", "[gjk][manifold]") {
    std::mt19937_64 rng(35);
    OneSearchTally t;
    for (double margin : {0.02, 0.2})
        one_search_each_pair(rng, [&](const auto& a, const auto& b) { one_search_compare_gjk(a, b, rng, margin, 6, t); });
    INFO("colliding " << t.colliding << " within " << t.within << " beyond " << t.beyond << "; iterations within: old "
                      << t.old_within_iterations << " new " << t.new_within_iterations << "; all: old "
                      << t.old_all_iterations << " new " << t.new_all_iterations);
    // Every class is hit often enough that the comparisons above mean something.
    CHECK(t.colliding > 300);
    CHECK(t.within > 300);
    CHECK(t.beyond > 300);
    // One search instead of two on the pairs within the margin: the distance loop goes on from the boolean's simplex.
    CHECK(t.new_within_iterations < t.old_within_iterations);
}

TEST_CASE("gjk_distance_within's bound: +infinity is gjk_distance, negative or NaN is 0", "[gjk]") {
    const Box<double> box(OV(0.5, 0.3, 0.2));
    const Capsule<double> capsule(0.2, 0.4);
    std::mt19937_64 rng(7);
    for (int i = 0; i < 50; ++i) {
        const OT pa = one_search_random_pose(rng, OV::Zero());
        const OT pb = one_search_random_pose(rng, OV(0.6 + 0.02 * i, 0.1, 0));
        const GjkResult<double> d = gjk_distance(box, pa, capsule, pb);
        const GjkResult<double> inf = gjk_distance_within(box, pa, capsule, pb, std::numeric_limits<double>::infinity());
        CHECK(inf.status == d.status);
        CHECK(inf.distance == d.distance);
        CHECK(inf.iterations == d.iterations);
        const GjkResult<double> zero = gjk_distance_within(box, pa, capsule, pb, 0.0);
        for (double bad : {-1.0, std::numeric_limits<double>::quiet_NaN()}) {
            const GjkResult<double> g = gjk_distance_within(box, pa, capsule, pb, bad);
            CHECK(g.status == zero.status);
            CHECK(g.distance == zero.distance);
        }
        CHECK(zero.colliding == gjk_intersect(box, pa, capsule, pb).colliding);
    }
}

TEST_CASE("contact_manifold with a margin: the former two-call manifolds, in fewer GJK iterations", "[manifold]") {
    std::mt19937_64 rng(36);
    OneSearchTally t;
    for (double margin : {0.02, 0.2})
        one_search_each_pair(rng,
                             [&](const auto& a, const auto& b) { one_search_compare_manifold(a, b, rng, margin, 4, t); });
    INFO("points " << t.manifold_points << "; GJK iterations on speculative pairs: old " << t.old_within_iterations
                   << " new " << t.new_within_iterations);
    INFO("ids: " << t.same_ids << " of " << t.compared_ids << " the same");
    CHECK(t.manifold_points > 500);
    CHECK(t.same_ids >= 0.95 * t.compared_ids);
    CHECK(t.new_within_iterations < t.old_within_iterations);
}
