// Differential tests of the broad phases against brute force over seeded scenes, edge-case boxes, errors.
#include <catch2/catch.hpp>

#include "broadphase_check.hpp"
#include "test_common.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

using namespace cdkit;
using B = BroadBox<double>;

using test::random_box;
using test::sorted_pairs;
using Quad = test::AllBroadPhases;

TEST_CASE("broad phases equal brute force over seeded dynamic scenes", "[broadphase][dbvt]") {
    for (unsigned seed = 1; seed <= 3; ++seed) {
        std::mt19937 rng(seed);
        Quad q;
        std::vector<ObjectId> ids;
        const int n = 300;
        const double world = 20;
        for (int i = 0; i < n; ++i) ids.push_back(q.insert(random_box(rng, world, 0.2, 2.0)));
        std::normal_distribution<double> step(0.0, 0.1);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        std::size_t total_pairs = 0, frames = 0;
        const int nframes = cdkit::test::scaled(60, 40);  // cheap: the hit-rate check needs the full count
        for (int f = 0; f < nframes; ++f) {
            for (ObjectId id : ids) {
                const double r = u(rng);
                if (r < 0.02) {
                    q.move(id, random_box(rng, world, 0.2, 2.0));  // teleport
                } else if (r < 0.04) {
                    const B b = q.bf.box(id);  // shrink to a point: a tree's fat box becomes too loose
                    q.move(id, {b.lo, b.lo});
                } else {
                    B b = q.bf.box(id);
                    const Vec3<double> d(step(rng), step(rng), step(rng));
                    q.move(id, {b.lo + d, b.hi + d});  // Brownian step
                }
            }
            if (f % 5 == 2) {  // removals and inserts (ids get reused)
                for (int k = 0; k < 10; ++k) {
                    const std::size_t at = std::size_t(u(rng) * double(ids.size())) % ids.size();
                    q.remove(ids[at]);
                    ids.erase(ids.begin() + std::ptrdiff_t(at));
                }
                for (int k = 0; k < 12; ++k) ids.push_back(q.insert(random_box(rng, world, 0.2, 2.0)));
            }
            if (f % 7 == 3) {  // remove and re-insert before the frame: the reused id is a new object
                const ObjectId victim = ids.front();
                q.remove(victim);
                ids.erase(ids.begin());
                const ObjectId again = q.insert(random_box(rng, world, 0.2, 2.0));
                CHECK(again == victim);
                ids.push_back(again);
            }
            if (f == 20) {  // mass teleport: SAP's batch path, the trees' rebuild path
                for (ObjectId id : ids) q.move(id, random_box(rng, world, 0.2, 2.0));
            }
            if (f == 30) q.tree.rebuild();  // explicit rebuild between frames
            total_pairs += q.check();
            ++frames;
        }
        // Hit rate: pairs exist, and far fewer than all pairs (culling is being exercised).
        CHECK(total_pairs > frames * 25);
        CHECK(total_pairs < frames * std::size_t(n) * n / 20);
    }
}

TEST_CASE("broad phases: remove then reuse an id before the next frame", "[broadphase]") {
    Quad q;
    const ObjectId a = q.insert({Vec3<double>(0, 0, 0), Vec3<double>(1, 1, 1)});
    const ObjectId b = q.insert({Vec3<double>(0.5, 0.5, 0.5), Vec3<double>(2, 2, 2)});
    CHECK(q.check() == 1);
    q.remove(a);
    const ObjectId c = q.insert({Vec3<double>(5, 5, 5), Vec3<double>(6, 6, 6)});
    CHECK(c == a);  // reused
    CHECK(q.check() == 0);
    q.move(b, {Vec3<double>(6, 6, 6), Vec3<double>(7, 7, 7)});  // touches c at a corner
    CHECK(q.check() == 1);
}

TEST_CASE("broad phases: touching, zero-size, identical, huge and tiny boxes", "[broadphase]") {
    std::mt19937 rng(7);
    Quad q;
    // A lattice of unit cubes sharing faces, edges and corners: 3x3x3 -> every neighbour pair touches.
    for (int x = 0; x < 3; ++x)
        for (int y = 0; y < 3; ++y)
            for (int z = 0; z < 3; ++z)
                q.insert({Vec3<double>(x, y, z), Vec3<double>(x + 1, y + 1, z + 1)});
    // 26-neighbourhood pairs in a 3x3x3 lattice: (3*3*3 with all offsets) = 158.
    CHECK(q.check() == 158);
    // Zero-size boxes: on a lattice corner (touches 8 cubes) and a point inside a face.
    q.insert({Vec3<double>(1, 1, 1), Vec3<double>(1, 1, 1)});
    q.insert({Vec3<double>(1, 1, 1), Vec3<double>(1, 1, 1)});  // identical point: pair with the first
    q.insert({Vec3<double>(1.5, 1.5, 3), Vec3<double>(1.5, 1.5, 3)});
    // Identical boxes.
    for (int k = 0; k < 5; ++k) q.insert({Vec3<double>(10, 10, 10), Vec3<double>(11, 12, 13)});
    // A huge box over everything and tiny boxes.
    q.insert({Vec3<double>(-1e6, -1e6, -1e6), Vec3<double>(1e6, 1e6, 1e6)});
    for (int k = 0; k < 50; ++k) {
        std::uniform_real_distribution<double> pos(0, 3);
        Vec3<double> c(pos(rng), pos(rng), pos(rng));
        q.insert({c, c + Vec3<double>::Constant(1e-9)});
    }
    // Far away, huge coordinates (cell index clamping).
    q.insert({Vec3<double>(1e300, 1e300, 1e300), Vec3<double>(1e300, 1e300, 1e300)});
    q.insert({Vec3<double>(-1e300, 1e299, 0), Vec3<double>(1e300, 1e300, 1)});
    const std::size_t pairs = q.check();
    CHECK(pairs > 158 + 10 + 50);
}

TEST_CASE("broad phases reject bad boxes and ids with cdkit::Error", "[broadphase]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    Quad q;
    const ObjectId a = q.insert({Vec3<double>(0, 0, 0), Vec3<double>(1, 1, 1)});
    const B bad_nan{Vec3<double>(nan, 0, 0), Vec3<double>(1, 1, 1)};
    const B bad_inf{Vec3<double>(0, 0, 0), Vec3<double>(inf, 1, 1)};
    const B bad_order{Vec3<double>(2, 0, 0), Vec3<double>(1, 1, 1)};
    CHECK_THROWS_AS(q.bf.insert(bad_nan), cdkit::Error);
    CHECK_THROWS_AS(q.sap.insert(bad_inf), cdkit::Error);
    CHECK_THROWS_AS(q.grid.insert(bad_order), cdkit::Error);
    CHECK_THROWS_AS(q.sap.move(a, bad_nan), cdkit::Error);
    CHECK_THROWS_AS(q.grid.move(a, bad_nan), cdkit::Error);
    CHECK_THROWS_AS(q.bf.move(99, {}), cdkit::Error);
    CHECK_THROWS_AS(q.sap.remove(99), cdkit::Error);
    q.remove(a);
    CHECK_THROWS_AS(q.bf.remove(a), cdkit::Error);    // double removal
    CHECK_THROWS_AS(q.sap.remove(a), cdkit::Error);
    CHECK_THROWS_AS(q.grid.move(a, {}), cdkit::Error);
    CHECK_THROWS_AS(UniformGrid<double>(nan), cdkit::Error);
    CHECK(q.check() == 0);
    CHECK(q.sap.size() == 0);
}

TEST_CASE("sweep and prune: coherent frames use the insertion sort, teleports the batch path", "[broadphase]") {
    std::mt19937 rng(11);
    SweepAndPrune<double> sap;
    std::vector<ObjectId> ids;
    for (int i = 0; i < 2000; ++i) ids.push_back(sap.insert(random_box(rng, 50, 0.2, 2)));
    (void)sap.find_pairs();
    CHECK(sap.stats().full_sort);  // mass insertion
    std::normal_distribution<double> step(0, 0.01);
    for (ObjectId id : ids) {
        B b = sap.box(id);
        const Vec3<double> d(step(rng), step(rng), step(rng));
        sap.move(id, {b.lo + d, b.hi + d});
    }
    (void)sap.find_pairs();
    CHECK_FALSE(sap.stats().full_sort);
    CHECK(sap.stats().swaps < 2000);
    for (ObjectId id : ids) sap.move(id, random_box(rng, 50, 0.2, 2));
    (void)sap.find_pairs();
    CHECK(sap.stats().full_sort);  // swap budget exceeded
}

TEST_CASE("float broad phases equal brute force", "[broadphase]") {
    std::mt19937 rng(5);
    BruteForceBroadPhase<float> bf;
    SweepAndPrune<float> sap;
    UniformGrid<float> grid;
    std::uniform_real_distribution<float> pos(0, 10), sz(0.1f, 1.f);
    for (int i = 0; i < 400; ++i) {
        Vec3<float> c(pos(rng), pos(rng), pos(rng));
        BroadBox<float> b{c, c + Vec3<float>(sz(rng), sz(rng), sz(rng))};
        bf.insert(b); sap.insert(b); grid.insert(b);
    }
    auto r = bf.find_pairs(), s = sap.find_pairs(), g = grid.find_pairs();
    std::sort(r.begin(), r.end()); std::sort(s.begin(), s.end()); std::sort(g.begin(), g.end());
    CHECK(!r.empty());
    CHECK(s == r);
    CHECK(g == r);
}
