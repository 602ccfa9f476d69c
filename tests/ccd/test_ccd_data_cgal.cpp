// Vertex–face and edge–edge CCD on every query of the public CCD data in ../shared/ccd-data (the handcrafted
// degenerate set of Wang et al. 2021, and the simulation steps of Belgrod et al. 2023 that come with queries),
// judged by the data's exact ground truth (computed in rational arithmetic by its authors, independent of cdkit).
// The data must be there: a missing folder fails the test. "_cgal": it needs GMP (through CGAL's link), which
// reads the files' rationals exactly.

#include "oracles/ccd_query_file.hpp"
#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <cdkit/ccd/edge_edge.hpp>
#include <cdkit/ccd/vertex_face.hpp>

namespace {

struct Counts {
    std::size_t queries = 0, positives = 0, false_negatives = 0, false_positives = 0, proven = 0, proven_wrong = 0;
    std::size_t toi_out_of_range = 0, capped = 0;
};

/// Runs every query under `root`; [0] vertex–face, [1] edge–edge.
std::array<Counts, 2> run_all(const std::string& root, const cdkit::CcdRequest& req) {
    std::array<Counts, 2> c;
    const auto files = cdkit::test::find_ccd_query_files(root);
    REQUIRE(!files.empty());
    for (const auto& path : files) {
        const auto file = cdkit::test::read_ccd_query_file(path);
        Counts& k = c[file.vertex_face ? 0 : 1];
        for (const auto& q : file.queries) {
            const auto& p = q.points;
            const cdkit::CcdResult r = file.vertex_face
                                           ? cdkit::vertex_face_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], req)
                                           : cdkit::edge_edge_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], req);
            REQUIRE(r.status == cdkit::QueryStatus::ok);
            ++k.queries;
            k.positives += q.truth;
            k.false_negatives += q.truth && !r.colliding;
            k.false_positives += !q.truth && r.colliding;
            k.proven += r.proven;
            k.proven_wrong += r.proven && !q.truth;  // a proof of contact where there is none: a wrong proof
            k.capped += r.stats.capped;
            k.toi_out_of_range += r.colliding && !(r.toi >= 0 && r.toi <= r.toi_upper && r.toi_upper <= req.t_max);
        }
    }
    return c;
}

}  // namespace

TEST_CASE("primitive CCD on the handcrafted queries: no false negative, fewer false positives than the anchor",
          "[ccd][data]") {
    const std::string root = cdkit::test::ccd_data_root(CDKIT_SOURCE_DIR) + "/sample-queries";
    const auto c = run_all(root, cdkit::CcdRequest{});
    // The data's own counts (its README): 3,085 vertex–face (248 colliding), 4,194 edge–edge (187 colliding).
    CHECK(c[0].queries == 3085);
    CHECK(c[0].positives == 248);
    CHECK(c[1].queries == 4194);
    CHECK(c[1].positives == 187);
    for (const auto& k : c) {
        CHECK(k.false_negatives == 0);
        CHECK(k.proven_wrong == 0);
        CHECK(k.toi_out_of_range == 0);
        CHECK(k.proven > k.positives / 2);  // Newton proves most contacts, so `proven` is exercised
    }
    // Tight-Inclusion at the same tolerance (1e-6), measured on this set (issue 34): 85 and 137 false positives.
    // The bounds are this method's counts as recorded in docs/ccd.md (85, 125): a change that adds one shows here.
    CHECK(c[0].false_positives <= 85);
    CHECK(c[1].false_positives <= 125);
    CHECK(c[0].capped + c[1].capped <= 2);
}

TEST_CASE("primitive CCD on the simulation steps' queries: no false negative", "[ccd][data]") {
    const std::string root = cdkit::test::ccd_data_root(CDKIT_SOURCE_DIR) + "/scalable-ccd";
    const auto c = run_all(root, cdkit::CcdRequest{});
    CHECK(c[0].queries > 9000);
    CHECK(c[1].queries > 200);
    for (const auto& k : c) {
        CHECK(k.false_negatives == 0);
        CHECK(k.proven_wrong == 0);
        CHECK(k.toi_out_of_range == 0);
    }
}

TEST_CASE("primitive CCD with a minimum separation keeps every contact of the data", "[ccd][data]") {
    // A contact at distance 0 is a contact at any separation d > 0, and the first one comes no later.
    const std::string root = cdkit::test::ccd_data_root(CDKIT_SOURCE_DIR) + "/sample-queries";
    cdkit::CcdRequest keep_gap;
    keep_gap.min_separation = 1e-4;
    const auto c = run_all(root, keep_gap);
    for (const auto& k : c) {
        CHECK(k.false_negatives == 0);
        CHECK(k.proven == 0);  // proofs are of zeros, which say nothing about the first approach to d
    }
}

TEST_CASE("the CCD query reader rejects malformed files with the file and line", "[ccd][io]") {
    const std::string dir = std::string(CDKIT_TEST_DATA_DIR) + "/bad/ccd/vertex-face";
    auto message = [](const std::string& path) {
        try {
            (void)cdkit::test::read_ccd_query_file(path);
        } catch (const std::runtime_error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK_THAT(message(dir + "/short.csv"), Catch::Contains("short.csv") && Catch::Contains("fewer than 8 rows"));
    CHECK_THAT(message(dir + "/not_double.csv"), Catch::Contains("not_double.csv:1") && Catch::Contains("not exactly a double"));
    CHECK_THAT(message(dir + "/zero_den.csv"), Catch::Contains("not a rational"));
}
