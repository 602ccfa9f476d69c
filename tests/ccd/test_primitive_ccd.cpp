// Vertex–face and edge–edge CCD on cases whose answer is known by construction: dyadic coordinates, so every
// position the construction relies on is exact in double, and truths that follow from geometry (a point that
// lies on the face at a known t; a plane that separates the features at both ends of the step, hence at every t).

#include "test_common.hpp"

#include <catch2/catch.hpp>

#include <cdkit/ccd/edge_edge.hpp>
#include <cdkit/ccd/vertex_face.hpp>

#include <array>
#include <thread>

namespace {

using V = cdkit::Vec3<double>;
using Points = std::array<V, 8>;  // four at t = 0, the same four at t = 1

cdkit::CcdResult vf(const Points& p, const cdkit::CcdRequest& r = {}) {
    return cdkit::vertex_face_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], r);
}
cdkit::CcdResult ee(const Points& p, const cdkit::CcdRequest& r = {}) {
    return cdkit::edge_edge_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], r);
}
Points moved(Points p, const V& offset) {
    for (auto& q : p) q += offset;
    return p;
}
/// A point with coordinates drawn in a fixed order (arguments of one call are evaluated in no fixed order).
template <class Rng, class Dist> V random_point(Rng& rng, Dist& coord, double unit) {
    const double x = coord(rng), y = coord(rng), z = coord(rng);
    return V(x, y, z) / unit;
}
Points still(const V& a, const V& b, const V& c, const V& d) { return {a, b, c, d, a, b, c, d}; }

const V A(0, 0, 0), B(1, 0, 0), C(0, 1, 0);  // the face of the vertex–face cases, in z = 0

}  // namespace

TEST_CASE("vertex-face CCD: cases with a known answer", "[ccd]") {
    // The offset 1e6 in every axis keeps the dyadic coordinates exact and tests the error bound at large magnitude.
    for (const V& offset : {V(0, 0, 0), V(1e6, -1e6, 1e6)}) {
        CAPTURE(offset.transpose());
        SECTION("through the face at t = 1/2") {
            const auto r = vf(moved({V(0.25, 0.25, 1), A, B, C, V(0.25, 0.25, -1), A, B, C}, offset));
            REQUIRE(r.status == cdkit::QueryStatus::ok);
            REQUIRE(r.colliding);
            CHECK(r.toi <= 0.5);
            CHECK(r.toi >= 0.5 - 1e-5);
            CHECK((r.point - (V(0.25, 0.25, 0) + offset)).norm() < 1e-5);
            CHECK(r.normal.isApprox(V(0, 0, 1), 1e-9));
        }
        SECTION("beside the face") {
            CHECK_FALSE(vf(moved({V(1, 1, 1), A, B, C, V(1, 1, -1), A, B, C}, offset)).colliding);
        }
        SECTION("coplanar motion into the face through an edge, t* = 1/2") {
            const auto r = vf(moved({V(-1, 0.25, 0), A, B, C, V(1, 0.25, 0), A, B, C}, offset));
            REQUIRE(r.colliding);
            CHECK(r.toi <= 0.5);
            CHECK(r.toi >= 0.5 - 1e-5);
        }
        SECTION("coplanar motion that stays outside") {
            CHECK_FALSE(vf(moved({V(-1, 2, 0), A, B, C, V(2, 2, 0), A, B, C}, offset)).colliding);
        }
        SECTION("sliding along an edge: contact throughout") {
            const auto r = vf(moved({V(0.5, 0, 0), A, B, C, V(0.25, 0, 0), A, B, C}, offset));
            REQUIRE(r.colliding);
            CHECK(r.toi == 0);
        }
        SECTION("contact exactly at t = 0 and exactly at t = 1") {
            const auto at0 = vf(moved({V(0.25, 0.25, 0), A, B, C, V(0.25, 0.25, 1), A, B, C}, offset));
            REQUIRE(at0.colliding);
            CHECK(at0.toi == 0);
            const auto at1 = vf(moved({V(0.25, 0.25, 1), A, B, C, V(0.25, 0.25, 0), A, B, C}, offset));
            REQUIRE(at1.colliding);
            CHECK(at1.toi >= 1 - 1e-5);
        }
        SECTION("zero-length motion") {
            CHECK_FALSE(vf(moved(still(V(0.25, 0.25, 0.5), A, B, C), offset)).colliding);
            const auto on = vf(moved(still(V(0.25, 0.25, 0), A, B, C), offset));
            REQUIRE(on.colliding);
            CHECK(on.toi == 0);
        }
        SECTION("degenerate (zero-area) face: a segment") {
            const V D(2, 0, 0);
            const auto r = vf(moved({V(0.5, 0, 1), A, B, D, V(0.5, 0, -1), A, B, D}, offset));
            REQUIRE(r.colliding);
            CHECK(r.toi <= 0.5);
            CHECK_FALSE(vf(moved({V(0.5, 0.5, 1), A, B, D, V(0.5, 0.5, -1), A, B, D}, offset)).colliding);
        }
    }
}

TEST_CASE("vertex-face CCD: gaps of 1e-12 to 1e-6 are not contacts", "[ccd]") {
    for (double gap : {1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6}) {
        CAPTURE(gap);
        // Sliding over the face at height `gap`, and approaching it to stop at `gap`: z ≥ gap > 0 at every t.
        CHECK_FALSE(vf({V(-0.5, 0.25, gap), A, B, C, V(1.5, 0.25, gap), A, B, C}).colliding);
        CHECK_FALSE(vf({V(0.25, 0.25, 1), A, B, C, V(0.25, 0.25, gap), A, B, C}).colliding);
        // The face moves instead, rotating about the x axis towards the vertex and stopping short of it.
        CHECK_FALSE(vf({V(0.25, 0.25, gap), A, B, V(0, 1, -1), V(0.25, 0.25, gap), A, B, C}).colliding);
        // With a minimum separation above the gap, the same passes are contacts.
        cdkit::CcdRequest keep_gap;
        keep_gap.min_separation = 2 * gap;
        CHECK(vf({V(-0.5, 0.25, gap), A, B, C, V(1.5, 0.25, gap), A, B, C}, keep_gap).colliding);
        CHECK(vf({V(0.25, 0.25, 1), A, B, C, V(0.25, 0.25, gap), A, B, C}, keep_gap).colliding);
    }
}

TEST_CASE("edge-edge CCD: cases with a known answer", "[ccd]") {
    for (const V& offset : {V(0, 0, 0), V(-1e6, 1e6, 1e6)}) {
        CAPTURE(offset.transpose());
        SECTION("crossing edges, t* = 1/2") {
            const Points p{V(-1, 0, 1), V(1, 0, 1), V(0, -1, 0), V(0, 1, 0),
                           V(-1, 0, -1), V(1, 0, -1), V(0, -1, 0), V(0, 1, 0)};
            const auto r = ee(moved(p, offset));
            REQUIRE(r.colliding);
            CHECK(r.toi <= 0.5);
            CHECK(r.toi >= 0.5 - 1e-5);
            CHECK(r.normal.isApprox(V(0, 0, 1), 1e-9));
        }
        SECTION("parallel edges overlapping at t* = 1/2") {
            const Points p{V(0, 0, 1), V(1, 0, 1), V(0.5, 0, 0), V(1.5, 0, 0),
                           V(0, 0, -1), V(1, 0, -1), V(0.5, 0, 0), V(1.5, 0, 0)};
            const auto r = ee(moved(p, offset));
            REQUIRE(r.colliding);
            CHECK(r.toi <= 0.5);
            CHECK(r.toi >= 0.5 - 1e-5);
        }
        SECTION("parallel edges passing end to end without overlap") {
            const Points p{V(0, 0, 1), V(1, 0, 1), V(1.5, 0, 0), V(2.5, 0, 0),
                           V(0, 0, -1), V(1, 0, -1), V(1.5, 0, 0), V(2.5, 0, 0)};
            CHECK_FALSE(ee(moved(p, offset)).colliding);
        }
        SECTION("collinear edges sliding into each other") {
            // A's end reaches B's start (x = 2) at t = 2/3.
            const Points p{V(0, 0, 0), V(1, 0, 0), V(2, 0, 0), V(3, 0, 0),
                           V(1.5, 0, 0), V(2.5, 0, 0), V(2, 0, 0), V(3, 0, 0)};
            const auto r = ee(moved(p, offset));
            REQUIRE(r.colliding);
            CHECK(r.toi <= 2.0 / 3.0);
            CHECK(r.toi >= 2.0 / 3.0 - 1e-5);
        }
        SECTION("an end point sliding along the other edge") {
            const Points p{V(0.25, 0, 0), V(0.25, 1, 0), V(0, 0, 0), V(1, 0, 0),
                           V(0.75, 0, 0), V(0.75, 1, 0), V(0, 0, 0), V(1, 0, 0)};
            const auto r = ee(moved(p, offset));
            REQUIRE(r.colliding);
            CHECK(r.toi == 0);
        }
        SECTION("zero-length edge (a point) through an edge") {
            const Points p{V(0.5, 0, 1), V(0.5, 0, 1), V(0, 0, 0), V(1, 0, 0),
                           V(0.5, 0, -1), V(0.5, 0, -1), V(0, 0, 0), V(1, 0, 0)};
            REQUIRE(ee(moved(p, offset)).colliding);
        }
    }
}

TEST_CASE("edge-edge CCD: gaps of 1e-12 to 1e-6 are not contacts", "[ccd]") {
    for (double gap : {1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6}) {
        CAPTURE(gap);
        // Skew edges: A slides over B at height `gap`.
        CHECK_FALSE(ee({V(-1, -0.5, gap), V(1, -0.5, gap), V(0, -1, 0), V(0, 1, 0),
                        V(-1, 0.5, gap), V(1, 0.5, gap), V(0, -1, 0), V(0, 1, 0)}).colliding);
        // Parallel edges: A slides along B at height `gap` (the edges' cross product vanishes).
        CHECK_FALSE(ee({V(-1, 0, gap), V(0.5, 0, gap), V(0, 0, 0), V(1, 0, 0),
                        V(0.5, 0, gap), V(2, 0, gap), V(0, 0, 0), V(1, 0, 0)}).colliding);
        // A approaches B head-on and stops `gap` short.
        CHECK_FALSE(ee({V(-1, 0, 1), V(1, 0, 1), V(0, -1, 0), V(0, 1, 0),
                        V(-1, 0, gap), V(1, 0, gap), V(0, -1, 0), V(0, 1, 0)}).colliding);
    }
}

TEST_CASE("primitive CCD: random contacts at t = 1/2 are found, separated pairs are not", "[ccd]") {
    std::mt19937_64 rng(34);
    // Multiples of 2^-8 in [-4, 4]: every lerp to t = 1/2 and every barycentric combination below is exact.
    std::uniform_int_distribution<int> coord(-1024, 1024), param(0, 16);
    auto point = [&] { return random_point(rng, coord, 256.0); };
    const int n = cdkit::test::scaled(4000);
    int found = 0, separated_ok = 0;
    for (int i = 0; i < n; ++i) {
        // Vertex–face: p(1/2) = a(1/2) + u·(b − a)(1/2) + v·(c − a)(1/2), u, v multiples of 1/16 with u + v ≤ 1.
        Points p;
        for (int k = 1; k < 4; ++k) p[k] = point(), p[k + 4] = point();
        int iu = param(rng), iv = param(rng);
        if (iu + iv > 16) iu = 16 - iu, iv = 16 - iv;
        const double u = iu / 16.0, v = iv / 16.0;
        auto mid = [&](int k) -> V { return 0.5 * (p[k] + p[k + 4]); };
        const V hit = mid(1) + u * (mid(2) - mid(1)) + v * (mid(3) - mid(1));
        const V w = point();
        p[0] = hit + w, p[4] = hit - w;
        const auto r = vf(p);
        found += r.colliding && r.toi <= 0.5;
        // Edge–edge: the points at parameters u, v of the two edges coincide at t = 1/2.
        Points q;
        for (int k = 0; k < 4; ++k) q[k] = point();
        for (int k = 4; k < 8; ++k) q[k] = point();
        auto qmid = [&](int k) -> V { return 0.5 * (q[k] + q[k + 4]); };
        const V a_mid = qmid(0) + u * (qmid(1) - qmid(0));
        const V b_mid = qmid(2) + v * (qmid(3) - qmid(2));
        const V shift = a_mid - b_mid;  // move edge B by a constant: exact for these dyadics
        for (int k : {2, 3, 6, 7}) q[k] += shift;
        const auto s = ee(q);
        found += s.colliding && s.toi <= 0.5;
        // Separated: the vertex (edge A) stays in z ≥ 1/256, the face (edge B) in z ≤ −1/256, at both ends of the
        // step and so at every t. Contacts are impossible, with any tolerance.
        Points sp = p, sq = q;
        for (int k = 0; k < 8; ++k) {
            const bool upper = (k % 4) == 0 || ((k % 4) == 1);
            const double z = std::abs(sp[k].z()) + 1.0 / 256;
            sp[k].z() = (k % 4) == 0 ? z : -z;
            const double zq = std::abs(sq[k].z()) + 1.0 / 256;
            sq[k].z() = upper ? zq : -zq;
        }
        separated_ok += !vf(sp).colliding;
        separated_ok += !ee(sq).colliding;
    }
    CHECK(found == 2 * n);
    CHECK(separated_ok == 2 * n);
}

TEST_CASE("primitive CCD: the answer does not depend on the order of the points", "[ccd]") {
    std::mt19937_64 rng(35);
    std::uniform_int_distribution<int> coord(-256, 256);
    auto point = [&] { return random_point(rng, coord, 64.0); };
    const int n = cdkit::test::scaled(500);
    int hits = 0;
    for (int i = 0; i < n; ++i) {
        Points p;
        for (auto& q : p) q = point();
        const auto base = vf(p);
        hits += base.colliding;
        // The face's three vertices in every order, and the edges swapped or reversed.
        const std::array<std::array<int, 3>, 5> orders{{{1, 3, 2}, {2, 1, 3}, {2, 3, 1}, {3, 1, 2}, {3, 2, 1}}};
        for (const auto& o : orders) {
            const Points q{p[0], p[o[0]], p[o[1]], p[o[2]], p[4], p[o[0] + 4], p[o[1] + 4], p[o[2] + 4]};
            const auto r = vf(q);
            REQUIRE(r.colliding == base.colliding);
            if (r.colliding) CHECK(std::abs(r.toi - base.toi) <= 1e-4);
        }
        const auto e = ee(p);
        const Points swapped{p[2], p[3], p[0], p[1], p[6], p[7], p[4], p[5]};
        const Points reversed{p[1], p[0], p[3], p[2], p[5], p[4], p[7], p[6]};
        for (const auto& q : {swapped, reversed}) {
            const auto r = ee(q);
            REQUIRE(r.colliding == e.colliding);
            if (r.colliding) CHECK(std::abs(r.toi - e.toi) <= 1e-4);
        }
    }
    CHECK(hits > n / 20);  // the random cases do contain contacts
}

TEST_CASE("primitive CCD: t_max, the work cap and bad input", "[ccd]") {
    const Points through{V(0.25, 0.25, 1), A, B, C, V(0.25, 0.25, -1), A, B, C};
    cdkit::CcdRequest r;
    r.t_max = 0.25;
    CHECK_FALSE(vf(through, r).colliding);
    r.t_max = 0.75;
    CHECK(vf(through, r).colliding);

    cdkit::CcdRequest capped;
    capped.max_boxes = 1;
    const auto c = vf(through, capped);
    CHECK(c.stats.capped);
    CHECK(c.colliding);  // conservative: undecided is reported as a contact
    CHECK(c.toi == 0);

    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (double bad : {nan, inf, -inf}) {
        Points p = through;
        p[6].y() = bad;
        const auto a = vf(p);
        CHECK(a.status == cdkit::QueryStatus::invalid_input);
        CHECK_FALSE(a.colliding);
        CHECK(ee(p).status == cdkit::QueryStatus::invalid_input);
    }
    for (auto set : std::initializer_list<void (*)(cdkit::CcdRequest&)>{
             [](cdkit::CcdRequest& q) { q.tolerance = 0; }, [](cdkit::CcdRequest& q) { q.tolerance = -1; },
             [](cdkit::CcdRequest& q) { q.min_separation = -1e-9; },
             [](cdkit::CcdRequest& q) { q.t_max = 1.5; }, [](cdkit::CcdRequest& q) { q.t_max = -0.1; },
             [](cdkit::CcdRequest& q) { q.max_boxes = 0; },
             [](cdkit::CcdRequest& q) { q.tolerance = std::numeric_limits<double>::quiet_NaN(); }}) {
        cdkit::CcdRequest q;
        set(q);
        CHECK(vf(through, q).status == cdkit::QueryStatus::invalid_input);
        CHECK(ee(through, q).status == cdkit::QueryStatus::invalid_input);
    }
}

TEST_CASE("primitive CCD: concurrent queries give the sequential answers", "[ccd][threads]") {
    std::mt19937_64 rng(36);
    std::uniform_int_distribution<int> coord(-256, 256);
    std::vector<Points> cases(cdkit::test::scaled(400));
    for (auto& p : cases)
        for (auto& q : p) q = random_point(rng, coord, 64.0);
    std::vector<double> expected;
    for (const auto& p : cases) expected.push_back(vf(p).colliding ? vf(p).toi : -1);
    std::vector<int> wrong(4, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (std::size_t i = 0; i < cases.size(); ++i) {
                const auto r = vf(cases[i]);
                wrong[t] += (r.colliding ? r.toi : -1) != expected[i];
            }
        });
    for (auto& th : threads) th.join();
    for (int w : wrong) CHECK(w == 0);
}
