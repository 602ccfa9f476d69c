// Bad input that does not come from a file: meshes handed to MeshModel (empty, NaN/Inf, indices out of
// range, absurd magnitudes) must raise cdkit::Error at construction; transforms that are not rigid motions
// (NaN, Inf, scaled, sheared) are detected by Transform::is_valid(), and what collide() does with them
// today is pinned down here (see docs/robustness.md, "Invalid transforms", for the recommended policy).
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/distance.hpp"
#include "cdkit/query.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

using namespace cdkit;

namespace {

template <class S> TriangleMesh<S> unit_triangle() {
    TriangleMesh<S> m;
    m.vertices = {Vec3<S>(0, 0, 0), Vec3<S>(1, 0, 0), Vec3<S>(0, 1, 0)};
    m.triangles = {{0, 1, 2}};
    m.source = "unit_triangle";
    return m;
}

/// Builds MeshModel<BV>(mesh) and returns the Error's text ("" when it did not throw).
template <class BV> std::string build_error(TriangleMesh<typename BV::Scalar> mesh) {
    try {
        const MeshModel<BV> model(std::move(mesh));
        return "";
    } catch (const Error& e) {
        return e.what();
    }
}

template <class S> using Pairs = std::vector<std::pair<Index, Index>>;
template <class S> Pairs<S> pairs(const CollisionResult<S>& r) {
    Pairs<S> p;
    for (const auto& c : r.contacts) p.emplace_back(c.triangle_a, c.triangle_b);
    std::sort(p.begin(), p.end());
    return p;
}

}  // namespace

TEMPLATE_TEST_CASE("MeshModel rejects empty and malformed meshes with cdkit::Error", "[robustness]", Obb<double>,
                   Obb<float>, Aabb<double>, Aabb<float>) {
    using BV = TestType;
    using S = typename BV::Scalar;
    const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();

    SECTION("no vertices, no triangles") { CHECK(build_error<BV>(TriangleMesh<S>{}) == "<mesh>: mesh has no triangles"); }
    SECTION("vertices but no triangles") {
        TriangleMesh<S> m = unit_triangle<S>();
        m.triangles.clear();
        CHECK(build_error<BV>(m) == "unit_triangle: mesh has no triangles");
    }
    SECTION("a null shared mesh") {
        CHECK_THROWS_AS(MeshModel<BV>(std::shared_ptr<const TriangleMesh<S>>()), Error);
    }
    SECTION("NaN, +Inf, -Inf coordinates name the vertex") {
        for (const S bad : {nan, inf, -inf}) {
            for (int k = 0; k < 3; ++k) {
                TriangleMesh<S> m = unit_triangle<S>();
                m.vertices[2][k] = bad;
                CHECK(build_error<BV>(m) == "unit_triangle: vertex 2: coordinate is NaN or infinite");
            }
        }
    }
    SECTION("a NaN in a vertex that no triangle uses is still rejected") {
        TriangleMesh<S> m = unit_triangle<S>();
        m.vertices.push_back(Vec3<S>(nan, 0, 0));
        CHECK(build_error<BV>(m) == "unit_triangle: vertex 3: coordinate is NaN or infinite");
    }
    SECTION("indices out of range, up to the largest Index") {
        for (const Index bad : {Index(3), Index(1000), std::numeric_limits<Index>::max()}) {
            TriangleMesh<S> m = unit_triangle<S>();
            m.triangles.push_back({0, bad, 1});
            const std::string e = build_error<BV>(m);
            CHECK(e.rfind("unit_triangle: triangle 1: vertex index " + std::to_string(bad) + " out of range", 0) == 0);
        }
    }
    SECTION("degenerate triangles are legal") {
        TriangleMesh<S> m = unit_triangle<S>();
        m.triangles.push_back({0, 0, 0});  // a point
        m.vertices.push_back(Vec3<S>(2, 0, 0));
        m.triangles.push_back({0, 1, 3});  // collinear
        CHECK(build_error<BV>(m).empty());
    }
}

TEST_CASE("Absurd magnitudes: finite double coordinates beyond float's range fail at the float MeshModel",
          "[robustness]") {
    TriangleMesh<double> m = unit_triangle<double>();
    m.vertices[1].x() = 1e300;  // finite in double, +Inf once cast to float
    CHECK(build_error<Obb<double>>(m).empty());
    CHECK(build_error<Aabb<double>>(m).empty());
    CHECK(build_error<Aabb<float>>(m.cast<float>()) == "unit_triangle: vertex 1: coordinate is NaN or infinite");
    CHECK(build_error<Obb<float>>(m.cast<float>()) == "unit_triangle: vertex 1: coordinate is NaN or infinite");
}

TEMPLATE_TEST_CASE("Large and tiny magnitudes: collide() agrees with brute force", "[robustness]", Obb<double>,
                   Aabb<double>, Aabb<float>) {
    using BV = TestType;
    using S = typename BV::Scalar;
    // Inside the predicates' documented range, far from unit scale: 1e±30 (float: within its range too).
    for (const S scale : {S(1e30), S(1e-30), S(1e6), S(1e-6)}) {
        TriangleMesh<S> sphere = test::uv_sphere<S>(S(1), 6, 12);
        for (auto& v : sphere.vertices) v *= scale;
        const MeshModel<BV> m(sphere);
        m.validate();
        CollisionRequest all;
        all.mode = ContactMode::all;
        for (const S shift : {S(0), S(0.5), S(1.9), S(2.5)}) {
            const Transform<S> pose = Transform<S>::translation(Vec3<S>(shift * scale, 0, 0));
            const auto fast = collide(m, Transform<S>(), m, pose, all);
            const auto slow = collide_brute_force(sphere, Transform<S>(), sphere, pose, all);
            INFO("scale " << scale << ", shift " << shift);
            CHECK(fast.colliding == (shift < S(2)));
            CHECK(pairs(fast) == pairs(slow));
        }
    }
}

TEMPLATE_TEST_CASE("Transform::is_valid() flags every non-rigid or non-finite pose", "[robustness]", float, double) {
    using S = TestType;
    const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
    CHECK(Transform<S>().is_valid());
    CHECK(Transform<S>(Eigen::AngleAxis<S>(S(0.7), Vec3<S>(1, 2, 3).normalized()).toRotationMatrix(), Vec3<S>(1, 2, 3))
              .is_valid());
    CHECK_FALSE(Transform<S>::translation(Vec3<S>(nan, 0, 0)).is_valid());
    CHECK_FALSE(Transform<S>::translation(Vec3<S>(0, inf, 0)).is_valid());
    Mat3<S> r = Mat3<S>::Identity();
    r(1, 1) = nan;
    CHECK_FALSE(Transform<S>(r, Vec3<S>::Zero()).is_valid());
    CHECK_FALSE(Transform<S>(S(2) * Mat3<S>::Identity(), Vec3<S>::Zero()).is_valid());  // scaled
    r = Mat3<S>::Identity();
    r(0, 1) = S(0.5);
    CHECK_FALSE(Transform<S>(r, Vec3<S>::Zero()).is_valid());  // sheared
    r = Mat3<S>::Identity();
    r(0, 0) = S(-1);
    CHECK_FALSE(Transform<S>(r, Vec3<S>::Zero()).is_valid());  // a reflection: orthonormal, det −1
    CHECK_FALSE(Transform<S>(Mat3<S>::Zero(), Vec3<S>::Zero()).is_valid());
    // A rotation perturbed by 1e-3 is not a rotation any more; one rounded to S still is.
    r = Eigen::AngleAxis<S>(S(1.1), Vec3<S>(0, 0, 1)).toRotationMatrix();
    CHECK(Transform<S>(r, Vec3<S>::Zero()).is_valid());
    r(0, 0) += S(1e-3);
    CHECK_FALSE(Transform<S>(r, Vec3<S>::Zero()).is_valid());
}

// Poses that are not rigid motions: every query refuses them with QueryStatus::invalid_pose instead of
// answering (NaN made every test false, a silent "no collision"; a shear made the BVH disagree with brute
// force). A rotation that drifted by 1e-9, as long simulations produce, is still accepted.
TEMPLATE_TEST_CASE("queries refuse poses that are not rigid motions", "[robustness]", Obb<double>, Aabb<float>) {
    using BV = TestType;
    using S = typename BV::Scalar;
    const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
    const TriangleMesh<S> sphere = test::uv_sphere<S>(S(1), 8, 16);
    const MeshModel<BV> m(sphere);
    CollisionRequest all;
    all.mode = ContactMode::all;
    Mat3<S> nan_r = Mat3<S>::Identity();
    nan_r(2, 2) = nan;
    Mat3<S> reflection = Mat3<S>::Identity();
    reflection(0, 0) = S(-1);
    Mat3<S> shear = Mat3<S>::Identity();
    shear(0, 1) = S(0.5);
    for (const Transform<S>& pose :
         {Transform<S>::translation(Vec3<S>(nan, 0, 0)), Transform<S>::translation(Vec3<S>(0, 0, inf)),
          Transform<S>(nan_r, Vec3<S>::Zero()), Transform<S>(reflection, Vec3<S>(S(0.5), 0, 0)),
          Transform<S>(shear, Vec3<S>(S(1.9), 0, 0)), Transform<S>(S(2) * Mat3<S>::Identity(), Vec3<S>::Zero())}) {
        REQUIRE_FALSE(pose_is_usable(pose));
        for (const auto& res : {collide(m, Transform<S>(), m, pose, all), collide(m, pose, m, Transform<S>()),
                                collide_brute_force(sphere, Transform<S>(), sphere, pose, all)}) {
            CHECK(res.status == QueryStatus::invalid_pose);
            CHECK_FALSE(res.colliding);
            CHECK(res.contacts.empty());
            CHECK(res.stats.bv_tests == 0);
        }
        const auto d = distance(m, Transform<S>(), m, pose);
        CHECK(d.status == QueryStatus::invalid_pose);
        CHECK(d.distance == std::numeric_limits<S>::infinity());
    }
    // A slightly drifted rotation is accepted and answered.
    Mat3<S> drifted = Eigen::AngleAxis<S>(S(0.3), Vec3<S>::UnitZ()).toRotationMatrix();
    drifted(0, 0) += std::is_same_v<S, float> ? S(1e-5) : S(1e-9);
    const Transform<S> pose(drifted, Vec3<S>(S(0.5), 0, 0));
    CHECK(pose_is_usable(pose));
    const auto res = collide(m, Transform<S>(), m, pose);
    CHECK(res.status == QueryStatus::ok);
    CHECK(res.colliding);
}

// pose_is_usable (Transform::is_valid(√ε)) is written for speed (six dot products, a triple product, no
// finiteness pass over R): it must refuse a NaN or an infinity in any of the twelve entries, and decide as the
// plain statement of the test does (all entries finite, |RᵀR − I| ≤ tol, |det R − 1| ≤ tol) elsewhere.
TEMPLATE_TEST_CASE("pose_is_usable refuses every non-finite entry and agrees with the plain test", "[robustness]",
                   float, double) {
    using S = TestType;
    const S tol = std::sqrt(std::numeric_limits<S>::epsilon());
    const auto plain = [&](const Transform<S>& p) {
        return p.R.allFinite() && p.t.allFinite() &&
               ((p.R.transpose() * p.R) - Mat3<S>::Identity()).cwiseAbs().maxCoeff() <= tol &&
               std::abs(p.R.determinant() - S(1)) <= tol;
    };
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    int refused = 0, accepted = 0;
    for (int i = 0; i < 2000; ++i) {
        Transform<S> p(test::random_rotation<S>(rng), Vec3<S>(S(u(rng)), S(u(rng)), S(u(rng))));
        for (const S bad : {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                            -std::numeric_limits<S>::infinity()}) {
            for (int k = 0; k < 12; ++k) {
                Transform<S> q = p;
                (k < 9 ? q.R(k / 3, k % 3) : q.t[k - 9]) = bad;
                REQUIRE_FALSE(pose_is_usable(q));
            }
        }
        // Perturbations around the tolerance: both tests decide alike.
        Transform<S> q = p;
        q.R(int(i % 3), int(i / 3 % 3)) += S(u(rng)) * S(3) * tol;
        REQUIRE(pose_is_usable(q) == plain(q));
        pose_is_usable(q) ? ++accepted : ++refused;
    }
    CHECK(accepted > 100);
    CHECK(refused > 100);
}
