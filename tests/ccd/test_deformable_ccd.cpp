// Continuous self-collision of whole simulation steps (the "Scalable CCD" data of Belgrod et al. 2023: cloth on a
// ball, cloth in a funnel, 16 bouncing balls): every pair the data's exact ground truth says collides must be
// among the contacts found. The data must be there: a missing file fails the test.

#include "oracles/ccd_scene.hpp"
#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <cdkit/ccd/deformable_ccd.hpp>

#include <set>
#include <utility>

namespace {

struct SceneFiles {
    const char* dir;
    const char* step;
    const char* start;
    const char* end;
};

std::string scene_root() {
    if (const char* env = std::getenv("CDKIT_CCD_DATA")) return std::string(env) + "/scalable-ccd/";
    return std::string(CDKIT_SOURCE_DIR) + "/../shared/ccd-data/scalable-ccd/";
}

}  // namespace

TEST_CASE("self CCD of whole simulation steps finds every ground-truth contact", "[ccd][data]") {
    const SceneFiles scenes[] = {{"cloth-ball", "92", "cloth_ball92.ply", "cloth_ball93.ply"},
                                 {"cloth-funnel", "227", "227.ply", "228.ply"},
                                 {"n-body-simulation", "18", "balls16_18.ply", "balls16_19.ply"}};
    for (const auto& sc : scenes) {
        CAPTURE(sc.dir);
        const auto frames = cdkit::test::read_binary_ply(scene_root() + sc.dir + "/frames/" + sc.start);
        const std::size_t edges = cdkit::mesh_edges(frames.triangles).size();
        const auto step = cdkit::test::read_ccd_scene_step(scene_root() + sc.dir, sc.step, sc.start, sc.end, edges);
        REQUIRE(step.start.triangles == step.end.triangles);

        cdkit::DeformableCcdRequest all;
        all.mode = cdkit::ContactMode::all;
        const auto r = cdkit::self_ccd(step.start.vertices, step.end.vertices, step.start.triangles, all, sc.dir);
        REQUIRE(r.status == cdkit::QueryStatus::ok);
        std::set<std::pair<cdkit::Index, cdkit::Index>> vf, ee;
        for (const auto& c : r.contacts) {
            if (c.vertex_face) vf.insert({c.a, c.b});
            else ee.insert({std::min(c.a, c.b), std::max(c.a, c.b)});
        }
        std::size_t positives = 0, missed = 0;
        for (const auto& p : step.vertex_face) {
            positives += p.truth;
            missed += p.truth && !vf.count({p.a, p.b});
        }
        for (const auto& p : step.edge_edge) {
            positives += p.truth;
            missed += p.truth && !ee.count({std::min(p.a, p.b), std::max(p.a, p.b)});
        }
        CHECK(positives > 0);
        CHECK(missed == 0);
        CHECK(r.stats.vertex_face_candidates + r.stats.edge_edge_candidates >= positives);

        // The earliest contact alone: no later than any contact of the full list (on the smallest scene: the others
        // take seconds a run).
        if (std::string(sc.dir) != "cloth-funnel") continue;
        const auto first = cdkit::self_ccd(step.start.vertices, step.end.vertices, step.start.triangles, {}, sc.dir);
        REQUIRE(first.colliding);
        REQUIRE(first.contacts.size() == 1);
        double earliest = 1;
        for (const auto& c : r.contacts) earliest = std::min(earliest, c.ccd.toi_upper);
        CHECK(first.toi <= earliest);
    }
}

TEST_CASE("self CCD: a triangle swept through another, neighbours left alone, bad input", "[ccd]") {
    using V = cdkit::Vec3<double>;
    // Two triangles sharing an edge (a hinge: never candidates of each other), and a third one falling through
    // the first between t = 1/4 and t = 3/4.
    std::vector<V> start{V(0, 0, 0), V(1, 0, 0), V(0, 1, 0), V(1, 1, 0), V(0.2, 0.2, 1), V(0.4, 0.2, 1), V(0.2, 0.4, 1)};
    std::vector<V> end = start;
    for (int i = 4; i < 7; ++i) end[i].z() = -1;
    const std::vector<cdkit::Triangle> tris{{0, 1, 2}, {1, 3, 2}, {4, 5, 6}};
    const auto r = cdkit::self_ccd(start, end, tris);
    REQUIRE(r.colliding);
    CHECK(r.toi <= 0.5);
    CHECK(r.toi >= 0.5 - 1e-5);
    cdkit::DeformableCcdRequest all;
    all.mode = cdkit::ContactMode::all;
    const auto every = cdkit::self_ccd(start, end, tris, all);
    for (const auto& c : every.contacts) CHECK((c.vertex_face ? c.a >= 4 || c.b == 2 : true));
    // Only the falling triangle moves: with it still, nothing touches.
    CHECK_FALSE(cdkit::self_ccd(start, start, tris).colliding);
    CHECK_FALSE(cdkit::self_ccd({}, {}, {}).colliding);

    std::vector<V> short_end(end.begin(), end.end() - 1);
    CHECK_THROWS_WITH(cdkit::self_ccd(start, short_end, tris, {}, "cloth.ply"),
                      Catch::Contains("cloth.ply") && Catch::Contains("7 vertices"));
    auto bad = end;
    bad[3].y() = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_WITH(cdkit::self_ccd(start, bad, tris), Catch::Contains("vertex 3") && Catch::Contains("end"));
    CHECK_THROWS_WITH(cdkit::self_ccd(start, end, {{0, 1, 9}}), Catch::Contains("triangle 0"));
    cdkit::DeformableCcdRequest bad_request;
    bad_request.primitive.tolerance = -1;
    CHECK(cdkit::self_ccd(start, end, tris, bad_request).status == cdkit::QueryStatus::invalid_input);
}
