// TriangleMesh: validate(), compute_stats() and join_identical_vertices() on small hand-built meshes whose
// answers can be counted by hand.
#include "cdkit/core/mesh.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

namespace {

using cdkit::Index;
using cdkit::Triangle;
using cdkit::TriangleMesh;

/// The unit cube [0,1]^3: 8 vertices, 12 triangles, counter-clockwise seen from outside.
template <class S> TriangleMesh<S> unit_cube() {
    TriangleMesh<S> m;
    for (int i = 0; i < 8; ++i) m.vertices.emplace_back(S(i & 1 ? 1 : 0), S(i & 2 ? 1 : 0), S(i & 4 ? 1 : 0));
    // Vertex i has x = bit 0, y = bit 1, z = bit 2. Quads wound outward, split along one diagonal.
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.triangles.push_back({Index(q[0]), Index(q[1]), Index(q[2])});
        m.triangles.push_back({Index(q[0]), Index(q[2]), Index(q[3])});
    }
    m.source = "<cube>";
    return m;
}

template <class S> S signed_volume(const TriangleMesh<S>& m) {
    S v = 0;
    for (std::size_t i = 0; i < m.num_triangles(); ++i) {
        const auto t = m.triangle(i);
        v += t[0].dot(t[1].cross(t[2])) / S(6);
    }
    return v;
}

/// Runs f and returns the cdkit::Error it throws (fails the test when it throws nothing or another type).
template <class F> cdkit::Error error_of(F&& f) {
    try {
        f();
    } catch (const cdkit::Error& e) {
        return e;
    }
    FAIL("expected cdkit::Error");
    return cdkit::Error("", "", "");
}

}  // namespace

TEMPLATE_TEST_CASE("compute_stats: closed, consistently oriented cube", "[mesh]", float, double) {
    const auto m = unit_cube<TestType>();
    REQUIRE_NOTHROW(cdkit::validate(m));
    REQUIRE(signed_volume(m) == Approx(1.0));  // outward winding, so the checks below mean what they say
    const cdkit::MeshStats s = cdkit::compute_stats(m);
    CHECK(s.vertices == 8);
    CHECK(s.triangles == 12);
    CHECK(s.edges == 18);
    CHECK(s.boundary_edges == 0);
    CHECK(s.non_manifold_edges == 0);
    CHECK(s.inconsistent_edges == 0);
    CHECK(s.degenerate_triangles == 0);
    CHECK(s.duplicate_triangles == 0);
    CHECK(s.closed);
    CHECK(s.consistently_oriented);
}

TEMPLATE_TEST_CASE("compute_stats: open cube has boundary edges", "[mesh]", float, double) {
    SECTION("one triangle removed: its three edges become boundary") {
        auto m = unit_cube<TestType>();
        m.triangles.pop_back();
        const auto s = cdkit::compute_stats(m);
        CHECK(s.triangles == 11);
        CHECK(s.edges == 18);
        CHECK(s.boundary_edges == 3);
        CHECK_FALSE(s.closed);
        CHECK_FALSE(s.consistently_oriented);
        CHECK(s.inconsistent_edges == 0);
    }
    SECTION("one square face removed: a 4-edge hole, and its diagonal is gone") {
        auto m = unit_cube<TestType>();
        m.triangles.resize(10);
        const auto s = cdkit::compute_stats(m);
        CHECK(s.edges == 17);
        CHECK(s.boundary_edges == 4);
        CHECK(s.non_manifold_edges == 0);
        CHECK_FALSE(s.closed);
    }
}

TEMPLATE_TEST_CASE("compute_stats: one flipped triangle gives three inconsistent edges", "[mesh]", float, double) {
    auto m = unit_cube<TestType>();
    std::swap(m.triangles[5][1], m.triangles[5][2]);
    const auto s = cdkit::compute_stats(m);
    CHECK(s.closed);  // closedness does not depend on orientation
    CHECK(s.inconsistent_edges == 3);
    CHECK_FALSE(s.consistently_oriented);
    CHECK(s.boundary_edges == 0);
}

TEMPLATE_TEST_CASE("compute_stats: a fin makes a non-manifold edge", "[mesh]", float, double) {
    auto m = unit_cube<TestType>();
    // A third triangle on the cube edge 0-1 (y = z = 0), sticking out below the cube.
    m.vertices.emplace_back(TestType(0.5), TestType(-1), TestType(-1));
    m.triangles.push_back({0, 1, 8});
    const auto s = cdkit::compute_stats(m);
    CHECK(s.non_manifold_edges == 1);
    CHECK(s.boundary_edges == 2);  // the fin's two free edges
    CHECK(s.edges == 20);
    CHECK_FALSE(s.closed);
    CHECK_FALSE(s.consistently_oriented);
}

TEMPLATE_TEST_CASE("compute_stats: duplicate and degenerate triangles are counted", "[mesh]", float, double) {
    SECTION("duplicates in any vertex order") {
        auto m = unit_cube<TestType>();
        const Triangle t = m.triangles[0];
        m.triangles.push_back({t[1], t[2], t[0]});  // same orientation, rotated
        m.triangles.push_back({t[0], t[2], t[1]});  // opposite orientation
        const auto s = cdkit::compute_stats(m);
        CHECK(s.duplicate_triangles == 2);
        CHECK(s.degenerate_triangles == 0);
        CHECK(s.non_manifold_edges == 3);  // each edge of t is now used four times
        CHECK_FALSE(s.closed);
    }
    SECTION("repeated index and zero area") {
        auto m = unit_cube<TestType>();
        m.triangles.push_back({0, 0, 1});  // repeated index: its edges bound nothing and are not counted
        m.vertices.emplace_back(TestType(2), TestType(0), TestType(0));  // collinear with vertices 0 and 1
        m.triangles.push_back({0, 1, 8});
        const auto s = cdkit::compute_stats(m);
        CHECK(s.degenerate_triangles == 2);
        CHECK(s.duplicate_triangles == 0);
        CHECK(s.non_manifold_edges == 1);  // edge 0-1 of the collinear triangle is a third use
        CHECK(s.boundary_edges == 2);
    }
}

TEST_CASE("validate: rejects what queries cannot handle and names the element", "[mesh]") {
    SECTION("a valid mesh passes, degenerate triangles included") {
        auto m = unit_cube<double>();
        m.triangles.push_back({3, 3, 3});
        REQUIRE_NOTHROW(cdkit::validate(m));
    }
    SECTION("no triangles") {
        TriangleMesh<double> m;
        m.vertices.emplace_back(0, 0, 0);
        m.source = "empty.stl";
        const auto e = error_of([&] { cdkit::validate(m); });
        CHECK(e.source() == "empty.stl");
        CHECK_THAT(e.what(), Catch::Contains("empty.stl") && Catch::Contains("no triangles"));
    }
    SECTION("NaN coordinate") {
        auto m = unit_cube<double>();
        m.vertices[5].y() = std::numeric_limits<double>::quiet_NaN();
        const auto e = error_of([&] { cdkit::validate(m); });
        CHECK(e.element() == "vertex 5");
        CHECK_THAT(e.what(), Catch::Contains("<cube>") && Catch::Contains("NaN"));
    }
    SECTION("infinite coordinate, in float") {
        auto m = unit_cube<float>();
        m.vertices[2].z() = -std::numeric_limits<float>::infinity();
        const auto e = error_of([&] { cdkit::validate(m); });
        CHECK(e.element() == "vertex 2");
    }
    SECTION("index out of range") {
        auto m = unit_cube<double>();
        m.triangles[7][2] = 8;
        const auto e = error_of([&] { cdkit::validate(m); });
        CHECK(e.element() == "triangle 7");
        CHECK_THAT(e.reason(), Catch::Contains("out of range") && Catch::Contains("8 vertices"));
    }
}

TEST_CASE("join_identical_vertices: rebuilds shared indices from a triangle soup", "[mesh]") {
    const auto cube = unit_cube<double>();
    TriangleMesh<double> soup;  // three vertices per triangle, as an STL file gives them
    for (std::size_t i = 0; i < cube.num_triangles(); ++i) {
        const auto t = cube.triangle(i);
        const Index b = Index(soup.vertices.size());
        soup.vertices.insert(soup.vertices.end(), t.begin(), t.end());
        soup.triangles.push_back({b, Index(b + 1), Index(b + 2)});
    }
    REQUIRE_FALSE(cdkit::compute_stats(soup).closed);
    cdkit::join_identical_vertices(soup);
    const auto s = cdkit::compute_stats(soup);
    CHECK(s.vertices == 8);
    CHECK(s.closed);
    CHECK(s.consistently_oriented);
    // First-occurrence order: the first triangle keeps indices 0, 1, 2.
    CHECK(soup.triangles[0] == Triangle{0, 1, 2});
    CHECK(soup.vertices[0] == cube.vertices[cube.triangles[0][0]]);

    SECTION("+0 and -0 are the same point; nearly equal points are not") {
        TriangleMesh<double> m;
        m.vertices = {{0.0, 1, 1}, {-0.0, 1, 1}, {std::nextafter(0.0, 1.0), 1, 1}};
        m.triangles = {{0, 1, 2}};
        cdkit::join_identical_vertices(m);
        CHECK(m.num_vertices() == 2);
        CHECK(m.triangles[0] == Triangle{0, 0, 1});
    }
}

TEST_CASE("TriangleMesh: accessors and cast", "[mesh]") {
    const auto m = unit_cube<double>();
    CHECK_FALSE(m.empty());
    CHECK(m.memory_bytes() == 8 * sizeof(cdkit::Vec3<double>) + 12 * sizeof(Triangle));
    const auto f = m.cast<float>();
    CHECK(f.source == m.source);
    CHECK(f.triangles == m.triangles);
    CHECK(f.vertices[7] == cdkit::Vec3<float>(1, 1, 1));
    CHECK(TriangleMesh<float>{}.empty());
}
