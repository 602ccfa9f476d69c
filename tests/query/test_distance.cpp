// distance() on BVHs against distance_brute_force() (same triangle routine, so equal values when no error
// is allowed), the error bound when one is, closest points on their triangles, intersecting poses, parallel
// faces, degenerate triangles, both scalars, every BV (Aabb, Obb, Rss, k-DOPs, spheres; also float Rss over double
// meshes, and SAH-built trees), every BV's lower bound against the triangles under its nodes, the traversal's pruning at work, concurrent queries, the reused per-thread heap, and the leaf-pair
// shortcut past the exact intersection test (same bits as triangle_distance). Fixed seeds.
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/distance.hpp"

#include <catch2/catch.hpp>

#include <algorithm>

#include <random>
#include <thread>

using namespace cdkit;

namespace {

// Distance from x to the closed triangle (a,b,c) in double, possibly degenerate.
double point_triangle(const Vec3<double>& X, const Vec3<double>& A, const Vec3<double>& B, const Vec3<double>& C) {
    auto seg = [&](const Vec3<double>& a, const Vec3<double>& b) {
        const Vec3<double> d = b - a;
        const double dd = d.squaredNorm();
        const double t = dd > 0 ? std::clamp((X - a).dot(d) / dd, 0.0, 1.0) : 0.0;
        return (a + t * d - X).norm();
    };
    double best = std::min({seg(A, B), seg(B, C), seg(C, A)});
    const Vec3<double> n = (B - A).cross(C - A);
    const double nn = n.squaredNorm();
    if (nn > 0) {
        const Vec3<double> p = X - n * (n.dot(X - A) / nn);
        const double u = n.dot((C - B).cross(p - B)) / nn, v = n.dot((A - C).cross(p - C)) / nn;
        if (u >= 0 && v >= 0 && 1 - u - v >= 0) best = std::min(best, (X - p).norm());
    }
    return best;
}

template <class S> double on_triangle(const TriangleMesh<S>& m, Index t, const Transform<S>& pose, const Vec3<S>& p) {
    const auto tri = m.triangle(t);
    const Transform<double> P = pose.template cast<double>();
    return point_triangle(p.template cast<double>(), P * tri[0].template cast<double>(), P * tri[1].template cast<double>(),
                          P * tri[2].template cast<double>());
}

template <class S> double tol() { return std::is_same_v<S, float> ? 1e-4 : 1e-10; }

template <class S> Transform<S> random_pose(std::mt19937_64& rng, double spread) {
    std::uniform_real_distribution<double> u(-spread, spread);
    return Transform<double>(test::random_rotation<double>(rng), Vec3<double>(u(rng), u(rng), u(rng))).template cast<S>();
}

template <class S>
void check_result(const TriangleMesh<S>& ma, const Transform<S>& pa, const TriangleMesh<S>& mb, const Transform<S>& pb,
                  const DistanceResult<S>& r) {
    CHECK(on_triangle(ma, r.triangle_a, pa, r.point_a) <= tol<S>());
    CHECK(on_triangle(mb, r.triangle_b, pb, r.point_b) <= tol<S>());
    CHECK(std::abs((r.point_a - r.point_b).template cast<double>().norm() - double(r.distance)) <= tol<S>());
}

}  // namespace

TEMPLATE_TEST_CASE("distance equals brute force on random soups and spheres", "[distance]", Aabb<float>, Aabb<double>,
                   Obb<float>, Obb<double>, Rss<float>, Rss<double>, (Kdop<float, 18>), (Kdop<double, 14>),
                   (Kdop<double, 26>), BoundingSphere<float>, BoundingSphere<double>) {
    using BV = TestType;
    using S = typename BV::Scalar;
    std::mt19937_64 rng(2024);
    const MeshModel<BV> soup_a(test::random_soup<S>(90, S(0.3), 1));
    const MeshModel<BV> soup_b(test::random_soup<S>(70, S(0.2), 2));
    const MeshModel<BV> sphere(test::uv_sphere<S>(S(0.8), 8, 10));
    const std::pair<const MeshModel<BV>*, const MeshModel<BV>*> pairs[] = {
        {&soup_a, &soup_b}, {&sphere, &soup_b}, {&sphere, &sphere}};
    int intersecting = 0, separated = 0;
    const int per_pair = test::scaled(30, 4);
    for (const auto& [a, b] : pairs)
        for (int k = 0; k < per_pair; ++k) {
            const Transform<S> pa = random_pose<S>(rng, 1.0), pb = random_pose<S>(rng, 2.5);
            const DistanceResult<S> r = distance(*a, pa, *b, pb);
            const DistanceResult<S> ref = distance_brute_force(a->mesh(), pa, b->mesh(), pb);
            INFO("pose " << k);
            REQUIRE(r.distance == ref.distance);
            check_result(a->mesh(), pa, b->mesh(), pb, r);
            const bool hit = collide(*a, pa, *b, pb).colliding;
            CHECK((r.distance == S(0)) == hit);
            (hit ? intersecting : separated) += 1;
            CHECK(r.stats.primitive_tests <= a->mesh().num_triangles() * b->mesh().num_triangles());
            // With an error allowed: within the bound, never below the exact answer.
            for (const auto& [rel, abs] : {std::pair<S, S>{S(0.05), S(0)}, {S(0), S(0.05)}, {S(0.5), S(0.1)}}) {
                const DistanceResult<S> e = distance(*a, pa, *b, pb, {rel, abs});
                CHECK(e.distance >= ref.distance);
                CHECK(e.distance <= (1 + rel) * ref.distance + abs);
                check_result(a->mesh(), pa, b->mesh(), pb, e);
            }
        }
    // Both outcomes occur often (at full size: ≥ 5 and ≥ 15 of 90; scaled runs keep the proportion).
    CHECK(intersecting >= std::max(1, per_pair / 6));
    CHECK(separated >= per_pair / 2);
}

TEMPLATE_TEST_CASE("distance: boxes face to face, parallel faces at a gap", "[distance]", Aabb<float>, Aabb<double>,
                   Obb<float>, Obb<double>, Rss<float>, Rss<double>) {
    using BV = TestType;
    using S = typename BV::Scalar;
    const MeshModel<BV> box(test::grid_box<S>({0.5, 0.3, 0.2}, 4));
    std::mt19937_64 rng(5);
    for (double gap : {0.0, 1e-3, 0.01, 0.1, 0.7}) {
        // B shifted along x by the sum of half extents + gap, then both rotated rigidly together.
        const Transform<double> common(test::random_rotation<double>(rng), Vec3<double>(0.3, -0.2, 0.1));
        const Transform<S> pa = common.template cast<S>();
        const Transform<S> pb = (common * Transform<double>::translation({1.0 + gap, 0.05, -0.02})).template cast<S>();
        const DistanceResult<S> r = distance(box, pa, box, pb);
        const DistanceResult<S> ref = distance_brute_force(box.mesh(), pa, box.mesh(), pb);
        INFO("gap " << gap);
        CHECK(r.distance == ref.distance);
        CHECK(std::abs(double(r.distance) - gap) <= tol<S>() * 10);
        check_result(box.mesh(), pa, box.mesh(), pb, r);
    }
}

TEMPLATE_TEST_CASE("distance: meshes with degenerate triangles", "[distance]", Aabb<float>, Aabb<double>, Obb<float>,
                   Obb<double>, Rss<float>, Rss<double>) {
    using BV = TestType;
    using S = typename BV::Scalar;
    TriangleMesh<S> m = test::random_soup<S>(80, S(0.3), 9);
    // Collapse every fourth triangle to a segment and every seventh to a point.
    for (std::size_t i = 0; i < m.triangles.size(); i += 4) m.triangles[i][2] = m.triangles[i][1];
    for (std::size_t i = 1; i < m.triangles.size(); i += 7) m.triangles[i] = {m.triangles[i][0], m.triangles[i][0], m.triangles[i][0]};
    const MeshModel<BV> a(m);
    // A mesh of degenerate triangles only.
    TriangleMesh<S> d;
    for (int i = 0; i < 30; ++i) {
        d.vertices.push_back(Vec3<S>(S(0.03 * i), S(0.5), S(0)));
        d.vertices.push_back(Vec3<S>(S(0.03 * i), S(0.6), S(0.1)));
        d.triangles.push_back({Index(2 * i), Index(2 * i + 1), Index(2 * i + 1)});
    }
    const MeshModel<BV> b(d);
    std::mt19937_64 rng(77);
    for (int k = 0; k < test::scaled(15, 3); ++k) {
        const Transform<S> pa = random_pose<S>(rng, 0.5), pb = random_pose<S>(rng, 1.5);
        const DistanceResult<S> r = distance(a, pa, b, pb);
        const DistanceResult<S> ref = distance_brute_force(a.mesh(), pa, b.mesh(), pb);
        REQUIRE(r.distance == ref.distance);
        check_result(a.mesh(), pa, b.mesh(), pb, r);
        const DistanceResult<S> r2 = distance(a, pa, a, pb);
        REQUIRE(r2.distance == distance_brute_force(a.mesh(), pa, a.mesh(), pb).distance);
    }
}

TEMPLATE_TEST_CASE("every BV's distance lower bound stays below the distance of the triangles it holds", "[distance][bv]",
                   Aabb<double>, Obb<double>, Rss<double>, (Kdop<double, 6>), (Kdop<double, 14>), (Kdop<double, 18>),
                   (Kdop<double, 26>), BoundingSphere<double>, Obb<float>, (Kdop<float, 18>), BoundingSphere<float>) {
    using BV = TestType;
    using S = typename BV::Scalar;
    const MeshModel<BV> a(test::random_soup<S>(60, S(0.3), 3)), b(test::random_soup<S>(50, S(0.25), 4));
    std::mt19937_64 rng(17);
    const auto& na = a.bvh().nodes();
    const auto& nb = b.bvh().nodes();
    // Triangles under a node: the leaves' ranges below it.
    const auto triangles = [](const MeshModel<BV>& m, std::uint32_t node) {
        std::vector<Index> out;
        std::vector<std::uint32_t> stack{node};
        while (!stack.empty()) {
            const auto& n = m.bvh().nodes()[stack.back()];
            stack.pop_back();
            if (n.is_leaf())
                for (std::uint32_t i = n.first; i < n.first + n.count; ++i) out.push_back(m.bvh().triangle_order()[i]);
            else stack.push_back(n.first), stack.push_back(n.first + 1);
        }
        return out;
    };
    int positive = 0, checked = 0;
    for (int k = 0; k < test::scaled(40, 4); ++k) {
        const Transform<S> rel = random_pose<S>(rng, 1.5);
        const auto r = BV::relative(rel);
        for (int q = 0; q < 20; ++q) {
            const std::uint32_t ia = std::uniform_int_distribution<std::uint32_t>(0, std::uint32_t(na.size() - 1))(rng);
            const std::uint32_t ib = std::uniform_int_distribution<std::uint32_t>(0, std::uint32_t(nb.size() - 1))(rng);
            const S lb = distance_lower_bound(na[ia].bv, nb[ib].bv, r, std::numeric_limits<S>::infinity());
            double best = std::numeric_limits<double>::infinity();
            for (Index ta : triangles(a, ia)) {
                const auto x = a.mesh().triangle(ta);
                for (Index tb : triangles(b, ib)) {
                    const auto y = b.mesh().triangle(tb);
                    const TriangleDistance<S> d = triangle_distance(x[0], x[1], x[2], Vec3<S>(rel * y[0]),
                                                                    Vec3<S>(rel * y[1]), Vec3<S>(rel * y[2]));
                    best = std::min(best, double(d.distance));
                }
            }
            INFO("pose " << k << " nodes " << ia << ", " << ib);
            CHECK(double(lb) <= best);
            CHECK(lb >= S(0));
            positive += lb > S(0);
            ++checked;
        }
    }
    CHECK(positive > checked / 4);  // the bounds prune: most random node pairs are apart
}

TEST_CASE("distance lower bounds of boxes never exceed the sampled distance", "[distance][bv]") {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1), h(0.01, 0.6);
    int positive = 0;
    const int n = test::scaled(2000, 100);
    for (int k = 0; k < n; ++k) {
        const Transform<double> rel_t(test::random_rotation<double>(rng), Vec3<double>(2 * u(rng), 2 * u(rng), 2 * u(rng)));
        Obb<double> a, b;
        a.axes = test::random_rotation<double>(rng);
        b.axes = test::random_rotation<double>(rng);
        a.center = Vec3<double>(u(rng), u(rng), u(rng)) * 0.3;
        b.center = Vec3<double>(u(rng), u(rng), u(rng)) * 0.3;
        a.half = Vec3<double>(h(rng), h(rng), h(rng));
        b.half = Vec3<double>(h(rng), h(rng), h(rng));
        const double lb = distance_lower_bound(a, b, Obb<double>::relative(rel_t));
        Aabb<double> aa{a.center, a.half}, ab{b.center, b.half};
        const double lba = distance_lower_bound(aa, ab, Aabb<double>::relative(rel_t));
        positive += lb > 0;
        // Sample the distance of the two boxes as the minimum over the 8 corners of one against the other's
        // faces and over corner pairs: it is an upper bound of the true distance, so lb must not exceed it.
        auto box_point_dist = [](const Vec3<double>& p, const Mat3<double>& axes, const Vec3<double>& c,
                                 const Vec3<double>& half) {
            const Vec3<double> l = axes.transpose() * (p - c);
            return (l.cwiseAbs() - half).cwiseMax(0.0).norm();
        };
        auto corners_upper = [&](const Mat3<double>& Ra, const Vec3<double>& ca, const Vec3<double>& ha,
                                 const Mat3<double>& Rb, const Vec3<double>& cb, const Vec3<double>& hb) {
            double best = 1e300;
            std::uniform_real_distribution<double> s(-1, 1);
            for (int i = 0; i < 8; ++i) {
                const Vec3<double> sgn(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
                best = std::min(best, box_point_dist(Rb * sgn.cwiseProduct(hb) + cb, Ra, ca, ha));
                best = std::min(best, box_point_dist(Ra * sgn.cwiseProduct(ha) + ca, Rb, cb, hb));
            }
            for (int i = 0; i < 200; ++i) {  // points on B's surface region: random points in B
                const Vec3<double> q(s(rng), s(rng), s(rng));
                best = std::min(best, box_point_dist(Rb * q.cwiseProduct(hb) + cb, Ra, ca, ha));
            }
            return best;
        };
        const double up = corners_upper(a.axes, a.center, a.half, rel_t.R * b.axes, rel_t * b.center, b.half);
        CHECK(lb <= up + 1e-12);
        const double upa = corners_upper(Mat3<double>::Identity(), a.center, a.half, rel_t.R, rel_t * b.center, b.half);
        CHECK(lba <= upa + 1e-12);
        CHECK(lb >= 0);
        // Positive exactly when the SAT says disjoint.
        CHECK((lb > 0) <= !overlap(a, b, Obb<double>::relative(rel_t)));
    }
    CHECK(positive > n / 4);
    CHECK(positive < n);
}

TEMPLATE_TEST_CASE("distance queries are thread-safe", "[distance]", Obb<double>, Rss<double>) {
    using BV = TestType;
    const MeshModel<BV> a(test::uv_sphere<double>(0.7, 16, 24));
    const MeshModel<BV> b(test::random_soup<double>(300, 0.2, 3));
    std::mt19937_64 rng(99);
    std::vector<Transform<double>> poses;
    for (int k = 0; k < test::scaled(64, 8); ++k) poses.push_back(random_pose<double>(rng, 2.0));
    std::vector<double> serial;
    for (const auto& p : poses) serial.push_back(distance(a, Transform<double>(), b, p).distance);
    std::vector<std::vector<double>> par(4, std::vector<double>(poses.size()));
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (std::size_t i = 0; i < poses.size(); ++i)
                par[t][(i + t * 7) % poses.size()] = distance(a, Transform<double>(), b, poses[(i + t * 7) % poses.size()]).distance;
        });
    for (auto& th : threads) th.join();
    for (int t = 0; t < 4; ++t) CHECK(par[t] == serial);
}

TEMPLATE_TEST_CASE("distance over float BVs on double meshes and SAH-built RSS trees equals brute force",
                   "[distance][float_over_double]", (MeshModel<Rss<float>, double>), (MeshModel<Obb<float>, double>),
                   MeshModel<Rss<double>>) {
    using Model = TestType;
    BuildOptions sah;
    sah.split = SplitStrategy::sah;
    std::mt19937_64 rng(4242);
    int separated = 0, total = 0;
    // Ordinary scale, far from the origin, tiny: the float bounds must stay below the double distances.
    for (const auto& scale_offset : {std::pair{1.0, 0.0}, std::pair{1.0, 1e5}, std::pair{1e-5, 1.0}}) {
        const double scale = scale_offset.first, offset = scale_offset.second;  // (lambdas cannot capture bindings in clang 14)
        auto moved = [&](TriangleMesh<double> m) {
            for (auto& v : m.vertices) v = v * scale + Vec3<double>::Constant(offset);
            return m;
        };
        const Model a(moved(test::uv_sphere<double>(0.8, 8, 12)), sah);
        const Model b(moved(test::random_soup<double>(80, 0.25, 6)), sah);
        REQUIRE_NOTHROW(a.validate());
        REQUIRE_NOTHROW(b.validate());
        for (int k = 0; k < test::scaled(20, 4); ++k) {
            // Poses about the meshes' own centre (the offset), so that they meet.
            const Transform<double> c = Transform<double>::translation(Vec3<double>::Constant(offset));
            const Transform<double> pa = c * random_pose<double>(rng, 0.5 * scale) * c.inverse();
            const Transform<double> pb = c * random_pose<double>(rng, 2.0 * scale) * c.inverse();
            const auto r = distance(a, pa, b, pb);
            const auto ref = distance_brute_force(a.mesh(), pa, b.mesh(), pb);
            INFO("scale " << scale << ", offset " << offset << ", pose " << k);
            REQUIRE(r.distance == ref.distance);
            separated += r.distance > 0;
            ++total;
        }
    }
    CHECK(separated >= total / 3);
    CHECK(separated < total);
}

TEMPLATE_TEST_CASE("distance: a leaf pair with a positive bound skips the intersection test with the same answer",
                   "[distance]", float, double) {
    // distance() passes `disjoint` for leaf pairs whose bound is positive and then computes the 15 feature
    // candidates only. For every disjoint pair that is exactly what triangle_distance returns (same bits,
    // same points); pairs a hair apart, touching and crossing pairs are drawn too.
    using S = TestType;
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> u(-1, 1);
    int separated = 0;
    for (int k = 0; k < test::scaled(3000, 300); ++k) {
        TriangleMesh<S> a, b;
        for (int i = 0; i < 3; ++i) a.vertices.push_back(Vec3<double>(u(rng), u(rng), u(rng)).cast<S>());
        for (int i = 0; i < 3; ++i) b.vertices.push_back(Vec3<double>(u(rng), u(rng), u(rng)).cast<S>());
        a.triangles = b.triangles = {{0, 1, 2}};
        const Transform<S> b_to_a = random_pose<S>(rng, k % 3 == 0 ? 0.5 : 2.5);
        const Vec3<S> q[3] = {detail::to_frame_a(b_to_a, b.vertices[0]), detail::to_frame_a(b_to_a, b.vertices[1]),
                              detail::to_frame_a(b_to_a, b.vertices[2])};
        const TriangleDistance<S> ref = triangle_distance(a.vertices[0], a.vertices[1], a.vertices[2], q[0], q[1], q[2]);
        if (!(ref.distance > S(0))) continue;
        ++separated;
        DistanceResult<S> got;
        detail::distance_triangle_pair(a, 0, b, 0, b_to_a, got, true);
        INFO("pair " << k);
        REQUIRE(got.distance == ref.distance);
        CHECK(got.point_a == ref.point_on_p);
        CHECK(got.point_b == ref.point_on_q);
    }
    CHECK(separated >= test::scaled(3000, 300) / 3);
}

TEMPLATE_TEST_CASE("distance: the triangle gap test skips only pairs at least the threshold apart", "[distance]", float,
                   double) {
    // distance() skips a leaf pair's 15 feature candidates when triangle_gap_reaches() says the pair is at
    // least the current answer apart. It must never say so for a threshold just above the distance that
    // triangle_distance computes (or the answer could change), and it must say so often at half of it (or it
    // would skip nothing). Random pairs near and far, slivers, parallel shifted copies, far from the origin.
    using S = TestType;
    std::mt19937_64 rng(29);
    std::uniform_real_distribution<double> u(-1, 1);
    int separated = 0, skipped_at_half = 0;
    const double offset = std::is_same_v<S, float> ? 1e3 : 1e6;
    for (int k = 0; k < test::scaled(4000, 400); ++k) {
        Vec3<double> p[3], q[3];
        for (auto& v : p) v = Vec3<double>(u(rng), u(rng), u(rng));
        const int kind = k % 5;
        if (kind == 3) {  // a parallel copy, shifted along the normal (and a little sideways)
            const Vec3<double> n = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
            const Vec3<double> shift = n * (0.01 + 0.5 * std::abs(u(rng))) + Vec3<double>(u(rng), u(rng), u(rng)) * 0.1;
            for (int i = 0; i < 3; ++i) q[i] = p[i] + shift;
        } else {
            const Transform<double> pose = random_pose<double>(rng, kind == 0 ? 0.5 : 2.5);
            for (int i = 0; i < 3; ++i) q[i] = pose * Vec3<double>(u(rng), u(rng), u(rng));
        }
        if (kind == 1) p[2] = p[0] + (p[1] - p[0]) * 0.3 + Vec3<double>(1e-9, 0, 0);  // a sliver
        if (kind == 2) q[1] = q[0];                                                     // a segment
        if (kind == 4)
            for (int i = 0; i < 3; ++i) p[i].x() += offset, q[i].x() += offset;
        const Vec3<S> P[3] = {p[0].cast<S>(), p[1].cast<S>(), p[2].cast<S>()};
        const Vec3<S> Q[3] = {q[0].cast<S>(), q[1].cast<S>(), q[2].cast<S>()};
        const S d = triangle_distance(P[0], P[1], P[2], Q[0], Q[1], Q[2]).distance;
        if (!(d > S(0))) continue;
        ++separated;
        INFO("pair " << k << " kind " << kind << " distance " << d);
        REQUIRE(!detail::triangle_gap_reaches(P, Q, std::nextafter(d, std::numeric_limits<S>::infinity())));
        REQUIRE(!detail::triangle_gap_reaches(P, Q, std::numeric_limits<S>::infinity()));
        skipped_at_half += detail::triangle_gap_reaches(P, Q, d / 2);
        // Through distance_triangle_pair: a skip leaves the result as it was, no skip records the same bits.
        TriangleMesh<S> a, b;
        a.vertices = {P[0], P[1], P[2]}, b.vertices = {Q[0], Q[1], Q[2]};
        a.triangles = b.triangles = {{0, 1, 2}};
        DistanceResult<S> got;
        detail::distance_triangle_pair(a, 0, b, 0, Transform<S>(), got, true, std::nextafter(d, std::numeric_limits<S>::infinity()));
        REQUIRE(got.distance == d);
        CHECK(got.stats.primitive_skips == 0);
    }
    CHECK(separated >= test::scaled(4000, 400) * 3 / 5);
    CHECK(skipped_at_half >= separated / 2);
    // Non-positive thresholds: nothing is nearer, every pair may be skipped.
    const Vec3<S> P[3] = {Vec3<S>(0, 0, 0), Vec3<S>(1, 0, 0), Vec3<S>(0, 1, 0)};
    CHECK(detail::triangle_gap_reaches(P, P, S(0)));
    CHECK(detail::triangle_gap_reaches(P, P, S(-1)));
}

TEST_CASE("distance over RSS trees prunes: far fewer triangle pairs than brute force", "[distance]") {
    // Two spheres of 2·16·24 triangles apart: best-first order with tight bounds measures a tiny share of pairs.
    const MeshModel<Rss<double>> a(test::uv_sphere<double>(0.5, 16, 24));
    std::mt19937_64 rng(8);
    for (int k = 0; k < test::scaled(10, 3); ++k) {
        const Transform<double> pb(test::random_rotation<double>(rng), Vec3<double>(1.2, 0.1 * k, 0));
        const auto r = distance(a, Transform<double>(), a, pb);
        REQUIRE(r.distance == distance_brute_force(a.mesh(), Transform<double>(), a.mesh(), pb).distance);
        CHECK(r.distance > 0.1);
        CHECK(r.stats.primitive_tests < 300);  // of 768² ≈ 590k pairs
        CHECK(r.stats.bv_tests < 2000);
    }
}

TEST_CASE("distance: the thread's reused open-pair heap carries nothing from one query to the next", "[distance]") {
    // A query with many open pairs, then tiny and intersecting ones, then the first again: each answer
    // equals brute force and the repeat equals the first bit for bit (same work counters too).
    const MeshModel<Rss<double>> sphere(test::uv_sphere<double>(0.5, 12, 16));
    TriangleMesh<double> one;
    one.vertices = {Vec3<double>(0, 0, 0), Vec3<double>(1, 0, 0), Vec3<double>(0, 1, 0)};
    one.triangles = {{0, 1, 2}};
    const MeshModel<Rss<double>> tri(one);
    const Transform<double> far(Mat3<double>::Identity(), Vec3<double>(1.05, 0.02, 0.01));
    const Transform<double> near(Mat3<double>::Identity(), Vec3<double>(0.3, 0.2, 0.1));
    const auto big = distance(sphere, Transform<double>(), sphere, far);
    REQUIRE(big.distance == distance_brute_force(sphere.mesh(), Transform<double>(), sphere.mesh(), far).distance);
    CHECK(big.stats.bv_tests > 20);
    const auto small = distance(tri, Transform<double>(), tri, far);
    CHECK(small.distance == distance_brute_force(one, Transform<double>(), one, far).distance);
    const auto hit = distance(sphere, Transform<double>(), tri, near);
    CHECK(hit.distance == 0);
    CHECK(collide(sphere, Transform<double>(), tri, near).colliding);
    const auto again = distance(sphere, Transform<double>(), sphere, far);
    CHECK(again.distance == big.distance);
    CHECK(again.triangle_a == big.triangle_a);
    CHECK(again.triangle_b == big.triangle_b);
    CHECK(again.stats.bv_tests == big.stats.bv_tests);
    CHECK(again.stats.primitive_tests == big.stats.primitive_tests);
}
