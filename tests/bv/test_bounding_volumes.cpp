// Bounding volumes: fits contain what they fit, and the overlap test under a relative transform is
// conservative (never "disjoint" when a point of one box lies in the other) yet culls most far pairs.
#include "bvh/brute_force_check.hpp"
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/obb.hpp"

#include <catch2/catch.hpp>

#include <numeric>

using namespace cdkit;

namespace {
using test::fit_all;

// A random point inside `bv` (in its own frame) from three uniform coordinates in [-1, 1].
template <class S> Vec3<S> point_in(const Aabb<S>& b, const Vec3<S>& u) { return b.center + b.half.cwiseProduct(u); }
template <class S> Vec3<S> point_in(const Obb<S>& b, const Vec3<S>& u) {
    return b.center + b.axes * b.half.cwiseProduct(u);
}
}  // namespace

TEMPLATE_PRODUCT_TEST_CASE("bounding volume fits contain every vertex", "[bv]", (cdkit::Aabb, cdkit::Obb),
                           (float, double)) {
    using BV = TestType;
    using S = typename BV::Scalar;
    for (unsigned seed = 1; seed <= 20; ++seed) {
        auto m = test::random_soup<S>(50, S(0.3), seed);
        // Far from the origin, where rounding is largest against the extent.
        if (seed % 2 == 0)
            for (auto& v : m.vertices) v += Vec3<S>(S(1000), S(-2000), S(500));
        const BV bv = fit_all<BV>(m);
        REQUIRE(bv.is_valid());
        for (const auto& v : m.vertices) REQUIRE(bv.contains(v));
    }
}

TEST_CASE("OBB fit of a thin rotated slab is tight", "[bv]") {
    // A 2 × 1 × 0.01 slab, rotated: the PCA box must find its frame (volume ≪ the AABB's).
    TriangleMesh<double> m = test::uv_sphere<double>(1.0, 12, 24);
    for (auto& v : m.vertices) v = Vec3<double>(2 * v.x(), v.y(), 0.01 * v.z());
    std::mt19937_64 rng(7);
    const Mat3<double> R = test::random_rotation(rng);
    for (auto& v : m.vertices) v = R * v;
    const auto obb = fit_all<Obb<double>>(m);
    const auto aabb = fit_all<Aabb<double>>(m);
    CHECK(obb.volume() < 0.1 * aabb.volume());
    CHECK(obb.volume() == Approx(8 * 2 * 1 * 0.01).epsilon(0.05));
    CHECK(std::abs(obb.axes.determinant() - 1.0) < 1e-9);
}

TEMPLATE_PRODUCT_TEST_CASE("BV overlap under a relative transform is conservative and culls", "[bv]",
                           (cdkit::Aabb, cdkit::Obb), (float, double)) {
    using BV = TestType;
    using S = typename BV::Scalar;
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-1, 1);
    test::OverlapCounts counts;
    const int n = test::scaled(4000, 200);
    for (int i = 0; i < n; ++i) {
        const auto ma = test::random_soup<S>(4, S(0.4), unsigned(2 * i + 1));
        const auto mb = test::random_soup<S>(4, S(0.4), unsigned(2 * i + 2));
        const BV a = fit_all<BV>(ma), b = fit_all<BV>(mb);
        Transform<S> b_to_a(test::random_rotation<S>(rng),
                            Vec3<S>(S(1.5 * u(rng)), S(1.5 * u(rng)), S(1.5 * u(rng))));
        test::record_overlap(a, b, b_to_a, [&](Vec3<S>& p) {
            p = point_in(b, Vec3<S>(S(u(rng)), S(u(rng)), S(u(rng))));
            return true;
        }, counts);
    }
    test::check_hit_rates(counts);
}

TEST_CASE("AABB and OBB overlap agree with each other on identical boxes", "[bv]") {
    // An OBB with identity axes is an AABB: both tests must give the same answer.
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < test::scaled(2000, 100); ++i) {
        Aabb<double> a{{u(rng), u(rng), u(rng)}, {0.1 + std::abs(u(rng)), 0.1 + std::abs(u(rng)), 0.1 + std::abs(u(rng)) }};
        Aabb<double> b{{u(rng), u(rng), u(rng)}, {0.1 + std::abs(u(rng)), 0.1 + std::abs(u(rng)), 0.1 + std::abs(u(rng)) }};
        Obb<double> oa, ob;
        oa.center = a.center, oa.half = a.half, ob.center = b.center, ob.half = b.half;
        Transform<double> rel(test::random_rotation(rng), Vec3<double>(u(rng), u(rng), u(rng)));
        REQUIRE(overlap(a, b, Aabb<double>::relative(rel)) == overlap(oa, ob, Obb<double>::relative(rel)));
    }
}

TEST_CASE("Transform validity", "[core]") {
    Transform<double> t;
    CHECK(t.is_valid());
    t.R(0, 0) = 2;
    CHECK_FALSE(t.is_valid());
    t = Transform<double>();
    t.t.x() = std::numeric_limits<double>::quiet_NaN();
    CHECK_FALSE(t.is_valid());
    std::mt19937_64 rng(1);
    Transform<double> r(test::random_rotation(rng), Vec3<double>(1, 2, 3));
    CHECK(r.is_valid());
    const Transform<double> id = r * r.inverse();
    CHECK((id.R - Mat3<double>::Identity()).norm() < 1e-12);
    CHECK(id.t.norm() < 1e-12);
    Eigen::Isometry3d iso = r.to_isometry();
    CHECK((Transform<double>(iso).R - r.R).norm() == 0);
    Transform<double> mirrored = r;
    mirrored.R.col(0) *= -1;  // orthonormal but a reflection
    CHECK_FALSE(mirrored.is_valid());
}

TEST_CASE("OBB of one triangle: flat, edge-aligned, never larger than the PCA box", "[bv]") {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < test::scaled(2000, 200); ++i) {
        TriangleMesh<double> m;
        const double stretch = std::pow(10.0, 3 * std::abs(u(rng)));  // slivers up to 1000:1
        for (int k = 0; k < 3; ++k) m.vertices.emplace_back(stretch * u(rng), u(rng), 0.5 * u(rng));
        m.triangles = {{0, 1, 2}};
        const Obb<double> box = fit_all<Obb<double>>(m);
        REQUIRE(std::abs(box.axes.determinant() - 1.0) < 1e-9);
        for (const auto& v : m.vertices) REQUIRE(box.contains(v));
        const Index only = 0;
        const Obb<double> pca = Obb<double>::fit_in_frame(m, TriangleRange(&only, 1),
                                                          Obb<double>::principal_frame(Obb<double>::local_covariance(m, TriangleRange(&only, 1))));
        // Flat: the normal extent is only the padding; the rectangle is the smallest (a side on an edge). The
        // PCA box can be far worse on slivers: its two small eigenvectors mix, and the box tilts about the
        // long axis.
        CHECK(box.half.minCoeff() < 1e-12 * stretch);
        CHECK(box.volume() <= pca.volume() * (1 + 1e-6));
    }
    // A zero-area triangle falls back to the PCA frame and still holds its vertices.
    TriangleMesh<double> line;
    line.vertices = {{0, 0, 0}, {1, 2, 3}, {2, 4, 6}};
    line.triangles = {{0, 1, 2}};
    const Obb<double> lb = fit_all<Obb<double>>(line);
    CHECK(std::abs(lb.axes.determinant() - 1.0) < 1e-9);
    for (const auto& v : line.vertices) CHECK(lb.contains(v));
    CHECK(lb.half.maxCoeff() > 3.0);  // it spans the segment
    // Two coincident vertices (one edge of zero length) and all three coincident: still a rotation.
    for (const auto& verts : {std::vector<Vec3<double>>{{0, 0, 0}, {0, 0, 0}, {1, 2, 3}},
                              std::vector<Vec3<double>>{{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}}) {
        TriangleMesh<double> d;
        d.vertices = verts;
        d.triangles = {{0, 1, 2}};
        const Obb<double> db = fit_all<Obb<double>>(d);
        CHECK(std::abs(db.axes.determinant() - 1.0) < 1e-9);
        for (const auto& v : d.vertices) CHECK(db.contains(v));
    }
}
