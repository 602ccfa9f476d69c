// Ray casts through the tree against every triangle tested one by one (the same watertight test, no tree), and
// rays aimed exactly at the shared edges and vertices of a closed mesh, which must never slip through.

#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <cdkit/bv/aabb.hpp>
#include <cdkit/bv/obb.hpp>
#include <cdkit/bv/rss.hpp>
#include <cdkit/ccd/ray_cast.hpp>
#include <cdkit/io/load_mesh.hpp>

#include <map>

namespace {

using V = cdkit::Vec3<double>;
using T = cdkit::Transform<double>;

V random_unit(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    const double x = g(rng), y = g(rng), z = g(rng);
    return V(x, y, z).normalized();
}

/// Every triangle, no tree: (t, triangle) of each hit, in the mesh frame.
std::vector<std::pair<double, cdkit::Index>> brute_hits(const cdkit::TriangleMesh<double>& m, const T& pose,
                                                        const cdkit::Ray& ray) {
    cdkit::Ray local = ray;
    local.origin = pose.inverse() * ray.origin;
    local.direction = pose.inverse().R * ray.direction;  // as ray_cast computes it
    const cdkit::detail::RayFrame f(local);
    std::vector<std::pair<double, cdkit::Index>> out;
    for (cdkit::Index i = 0; i < m.triangles.size(); ++i) {
        const auto& t = m.triangles[i];
        double h, u, v;
        if (cdkit::detail::ray_triangle(f, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], ray.t_min, ray.t_max, h,
                                        u, v))
            out.push_back({h, i});
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEMPLATE_TEST_CASE("ray casts on trees equal every triangle tested", "[ccd][ray]", cdkit::Obb<double>,
                   cdkit::Aabb<double>, cdkit::Rss<double>) {
    const auto mesh = cdkit::load_mesh(cdkit::test::data_path("bunny.obj"));
    const cdkit::MeshModel<TestType> model(mesh);
    std::mt19937_64 rng(34);
    const T pose(Eigen::AngleAxisd(0.7, V(1, 2, 3).normalized()).toRotationMatrix(), V(0.3, -0.2, 0.1));
    V lo = mesh.vertices[0], hi = lo;
    for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double size = (hi - lo).norm();
    const V centre = pose * (0.5 * (lo + hi));
    const int n = cdkit::test::scaled(300, 30);
    int hits = 0;
    std::vector<cdkit::Ray> rays;
    for (int i = 0; i < n; ++i) {
        cdkit::Ray ray;
        ray.origin = centre + 1.5 * size * random_unit(rng);
        ray.direction = (centre + 0.3 * size * random_unit(rng) - ray.origin);
        rays.push_back(ray);
        const auto brute = brute_hits(mesh, pose, ray);
        const auto closest = cdkit::ray_cast(model, pose, ray);
        REQUIRE(closest.status == cdkit::QueryStatus::ok);
        REQUIRE(closest.hit == !brute.empty());
        hits += closest.hit;
        if (closest.hit) {
            CHECK(closest.hits[0].t == brute[0].first);
            CHECK(closest.hits[0].triangle == brute[0].second);
        }
        const auto all = cdkit::ray_cast(model, pose, ray, cdkit::RayMode::all);
        CHECK(all.hits.size() == brute.size());
        CHECK(cdkit::ray_cast(model, pose, ray, cdkit::RayMode::any).hit == !brute.empty());
        CHECK(closest.triangle_tests < mesh.triangles.size());
    }
    CHECK(hits > n / 4);
    const auto many = cdkit::ray_cast_many(model, pose, rays);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const auto one = cdkit::ray_cast(model, pose, rays[i]);
        REQUIRE(many[i].hit == one.hit);
        if (one.hit) CHECK(many[i].hits[0].t == one.hits[0].t);
    }
}

TEST_CASE("ray casts aimed exactly at shared edges and vertices: the tree equals every triangle tested",
          "[ccd][ray]") {
    const auto mesh = cdkit::load_mesh(cdkit::test::data_path("bunny.obj"));
    const cdkit::MeshModel<cdkit::Obb<double>> model(mesh);
    std::mt19937_64 rng(35);
    const T pose;
    int rays = 0, hits = 0;
    const int step = std::max(1, int(mesh.triangles.size()) / cdkit::test::scaled(600, 60));
    for (std::size_t i = 0; i < mesh.triangles.size(); i += std::size_t(step)) {
        const auto& t = mesh.triangles[i];
        for (int k = 0; k < 3; ++k)
            for (const V& target : {mesh.vertices[t[k]], V(0.5 * (mesh.vertices[t[k]] + mesh.vertices[t[(k + 1) % 3]]))}) {
                cdkit::Ray ray;
                ray.origin = target + 0.5 * random_unit(rng);
                ray.direction = target - ray.origin;
                const auto brute = brute_hits(mesh, pose, ray);
                const auto r = cdkit::ray_cast(model, pose, ray);
                ++rays;
                REQUIRE(r.hit == !brute.empty());
                if (r.hit) CHECK(r.hits[0].t == brute[0].first);
                hits += r.hit;
            }
    }
    CHECK(rays > 3000 * cdkit::test::scale());
    CHECK(hits > rays / 2);
}

TEST_CASE("ray casts through the shared edges of a closed mesh never slip between the two triangles",
          "[ccd][ray]") {
    // A line through a point of an edge along the bisector of its two faces' normals crosses the surface there
    // (it enters the wedge of both faces), so the first hit lies at or before that point: a ray that slipped
    // between the two triangles would find a later hit, or none.
    const auto mesh = cdkit::load_mesh(cdkit::test::data_path("bunny.obj"));
    const cdkit::MeshModel<cdkit::Obb<double>> model(mesh);
    std::map<std::pair<cdkit::Index, cdkit::Index>, std::vector<cdkit::Index>> faces_of_edge;
    for (cdkit::Index f = 0; f < mesh.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const cdkit::Index a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
            faces_of_edge[{std::min(a, b), std::max(a, b)}].push_back(f);
        }
    auto normal = [&](cdkit::Index f) {
        const auto& t = mesh.triangles[f];
        return V((mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).normalized());
    };
    std::mt19937_64 rng(36);
    std::uniform_real_distribution<double> along(0.05, 0.95);
    int rays = 0, slipped = 0;
    for (const auto& [edge, faces] : faces_of_edge) {
        REQUIRE(faces.size() == 2);  // closed and manifold
        const V bisector = normal(faces[0]) + normal(faces[1]);
        if (bisector.norm() < 1e-6) continue;  // a knife edge: no wedge to enter
        const double s = along(rng);
        const V target = (1 - s) * mesh.vertices[edge.first] + s * mesh.vertices[edge.second];
        for (double side : {1.0, -1.0}) {
            cdkit::Ray ray;
            ray.origin = target + side * 0.3 * bisector.normalized();
            ray.direction = target - ray.origin;  // reaches the edge at t = 1
            ++rays;
            const auto r = cdkit::ray_cast(model, T(), ray);
            slipped += !r.hit || r.hits[0].t > 1 + 1e-9;
        }
    }
    CHECK(rays > 10000);
    CHECK(slipped == 0);
}

TEST_CASE("ray casts: bad rays and poses", "[ccd][ray]") {
    const auto mesh = cdkit::load_mesh(cdkit::test::data_path("bunny.obj"));
    const cdkit::MeshModel<cdkit::Obb<double>> model(mesh);
    cdkit::Ray zero;
    zero.direction = V::Zero();
    CHECK(cdkit::ray_cast(model, T(), zero).status == cdkit::QueryStatus::invalid_input);
    cdkit::Ray nan;
    nan.origin.x() = std::numeric_limits<double>::quiet_NaN();
    CHECK(cdkit::ray_cast(model, T(), nan).status == cdkit::QueryStatus::invalid_input);
    T bad;
    bad.R *= 2;
    CHECK(cdkit::ray_cast(model, bad, cdkit::Ray{}).status == cdkit::QueryStatus::invalid_pose);
}
