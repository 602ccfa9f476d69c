// The sorted-cell grid against brute force: its dense (cell start table) and sparse (forward pointers) paths,
// crowded cells, the oversize list, boxes on cell boundaries, one-cell fallbacks for extreme coordinates, float.
#include <catch2/catch.hpp>

#include "broadphase_check.hpp"
#include "test_common.hpp"

#include <algorithm>
#include <functional>
#include <random>
#include <vector>

using namespace cdkit;
using B = BroadBox<double>;
using test::random_box;
using test::sorted_pairs;

namespace {

/// Brute force and the sorted-cell grid on one edit script.
struct Pair2 {
    BruteForceBroadPhase<double> bf;
    SortedCellGrid<double> g;
    ObjectId insert(const B& b) {
        const ObjectId id = bf.insert(b);
        REQUIRE(g.insert(b) == id);
        return id;
    }
    void move(ObjectId id, const B& b) { bf.move(id, b), g.move(id, b); }
    void remove(ObjectId id) { bf.remove(id), g.remove(id); }
    std::size_t check() {
        const auto ref = sorted_pairs(bf);
        CHECK(sorted_pairs(g) == ref);
        return ref.size();
    }
};

/// Random coherent frames with teleports, point boxes, removals and inserts; returns the pairs seen.
std::size_t run_frames(Pair2& p, std::vector<ObjectId>& ids, std::mt19937& rng, int frames,
                       const std::function<B(std::mt19937&)>& fresh) {
    std::normal_distribution<double> step(0.0, 0.1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::size_t pairs = 0;
    for (int f = 0; f < frames; ++f) {
        for (ObjectId id : ids) {
            const double r = u(rng);
            B b = p.bf.box(id);
            if (r < 0.02) p.move(id, fresh(rng));
            else if (r < 0.03) p.move(id, {b.lo, b.lo});
            else {
                const Vec3<double> d(step(rng), step(rng), step(rng));
                p.move(id, {b.lo + d, b.hi + d});
            }
        }
        if (f % 3 == 1) {
            for (int k = 0; k < 5 && !ids.empty(); ++k) {
                const std::size_t at = std::size_t(u(rng) * double(ids.size())) % ids.size();
                p.remove(ids[at]);
                ids.erase(ids.begin() + std::ptrdiff_t(at));
            }
            for (int k = 0; k < 6; ++k) ids.push_back(p.insert(fresh(rng)));
        }
        pairs += p.check();
    }
    return pairs;
}

}  // namespace

TEST_CASE("sorted-cell grid, dense path: coherent frames equal brute force", "[broadphase][cellgrid]") {
    std::mt19937 rng(21);
    Pair2 p;
    std::vector<ObjectId> ids;
    auto fresh = [](std::mt19937& r) { return random_box(r, 14, 0.2, 2.0); };
    for (int i = 0; i < 500; ++i) ids.push_back(p.insert(fresh(rng)));
    const int frames = test::scaled(40, 6);
    const std::size_t pairs = run_frames(p, ids, rng, frames, fresh);
    CHECK(p.g.stats().dense);
    CHECK(p.g.stats().oversized == 0);
    CHECK(pairs > std::size_t(frames) * 100);  // a dense scene: many pairs checked
    // Culling works: far fewer box tests than all pairs.
    CHECK(p.g.stats().candidates < ids.size() * ids.size() / 8);
}

TEST_CASE("sorted-cell grid, sparse path: far-apart clusters equal brute force", "[broadphase][cellgrid]") {
    std::mt19937 rng(22);
    Pair2 p;
    std::vector<ObjectId> ids;
    // Three clusters 1e4 apart along a diagonal: many more cells than objects, so no cell start table.
    auto fresh = [](std::mt19937& r) {
        std::uniform_int_distribution<int> which(0, 2);
        const double off = 1e4 * which(r);
        B b = random_box(r, 8, 0.2, 2.0);
        const Vec3<double> d(off, off, -off);
        return B{b.lo + d, b.hi + d};
    };
    for (int i = 0; i < 300; ++i) ids.push_back(p.insert(fresh(rng)));
    const int frames = test::scaled(30, 5);
    const std::size_t pairs = run_frames(p, ids, rng, frames, fresh);
    CHECK_FALSE(p.g.stats().dense);
    CHECK(pairs > std::size_t(frames) * 100);
}

TEST_CASE("sorted-cell grid: crowded cells equal brute force, dense and sparse", "[broadphase][cellgrid]") {
    // 2500 small boxes in a 0.3-wide cube, a few objects per cell: runs longer than the eight indices written
    // without a loop, candidate lists that outgrow their first buffer, and more pairs per frame than one
    // batch of the pair buffer. 200 more boxes spread over a wide scene make the grid sparse.
    for (const bool spread : {false, true}) {
        CAPTURE(spread);
        std::mt19937 rng(spread ? 26 : 25);
        Pair2 p;
        std::vector<ObjectId> ids;
        auto fresh = [](std::mt19937& r) { return random_box(r, 0.3, 0.02, 0.05); };
        for (int i = 0; i < 2500; ++i) ids.push_back(p.insert(fresh(rng)));
        if (spread)
            for (int i = 0; i < 200; ++i) ids.push_back(p.insert(random_box(rng, 50, 0.02, 0.05)));
        CHECK(p.check() > 4000);
        CHECK(p.g.stats().dense == !spread);
        CHECK(p.g.stats().oversized == 0);
        CHECK(p.g.stats().candidates > 40 * ids.size());  // longer lists than 5 runs x 8 indices
        CHECK(run_frames(p, ids, rng, test::scaled(3, 1), fresh) > 0);
    }
}

TEST_CASE("sorted-cell grid: one cell holding thousands of points", "[broadphase][cellgrid]") {
    // 2200 boxes of edge 0.5-1.5 set the cells (about 1 x 1 x 1, 0.5 on x), 2200 points lie in one cell near
    // the origin, away from the boxes: the first point's candidate list (the rest of its cell) is longer
    // than the whole pair buffer. The boxes alone give more pairs than one batch of that buffer.
    for (const bool spread : {false, true}) {
        CAPTURE(spread);
        std::mt19937 rng(spread ? 28 : 27);
        Pair2 p;
        p.insert({Vec3<double>(0, 0, 0), Vec3<double>(0, 0, 0)});  // the grid origin
        std::uniform_real_distribution<double> u(0.05, 0.45);
        for (int i = 0; i < 2200; ++i) {
            const Vec3<double> c(u(rng), u(rng), u(rng));
            p.insert({c, c});
        }
        const double world = spread ? 80 : 18;  // 80: far more cells than objects
        for (int i = 0; i < 2200; ++i) {
            B b = random_box(rng, world, 0.5, 1.5);
            p.insert({b.lo + Vec3<double>::Constant(2), b.hi + Vec3<double>::Constant(2)});
        }
        CHECK(p.check() > (spread ? 0u : 2500u));
        CHECK(p.g.stats().dense == !spread);
        CHECK(p.g.stats().oversized == 0);
        CHECK(p.g.stats().candidates > 2200 * 2199 / 2);  // every pair of points in the one cell is tested
    }
}

TEST_CASE("sorted-cell grid: boxes on cell boundaries and exactly as large as the cell", "[broadphase][cellgrid]") {
    Pair2 p;
    // Unit cubes on an integer lattice (faces, edges and corners touch across cells), a few cubes shifted by
    // half a cell, and points on lattice corners.
    for (int x = 0; x < 5; ++x)
        for (int y = 0; y < 4; ++y)
            for (int z = 0; z < 3; ++z) p.insert({Vec3<double>(x, y, z), Vec3<double>(x + 1, y + 1, z + 1)});
    for (int k = 0; k < 4; ++k) p.insert({Vec3<double>(k + 0.5, 0.5, 0.5), Vec3<double>(k + 1.5, 1.5, 1.5)});
    for (int k = 0; k < 4; ++k) p.insert({Vec3<double>(k, 2, 1), Vec3<double>(k, 2, 1)});
    // 26-neighbourhood pairs of a 5x4x3 lattice: 1 + 3*... counted by brute force; the check compares sets.
    CHECK(p.check() > 300);
    CHECK(p.g.stats().oversized == 0);
}

TEST_CASE("sorted-cell grid: oversized boxes and extreme coordinates", "[broadphase][cellgrid]") {
    std::mt19937 rng(23);
    Pair2 p;
    for (int i = 0; i < 400; ++i) p.insert(random_box(rng, 20, 0.1, 1.0));
    // Much larger than 4x the mean extent: kept off the grid, tested against everything.
    p.insert({Vec3<double>(-5, -5, -5), Vec3<double>(30, 2, 30)});
    p.insert({Vec3<double>(0, 0, 0), Vec3<double>(25, 25, 25)});
    p.check();
    CHECK(p.g.stats().oversized == 2);
    // Min corners 3e308 apart: the range overflows, so every grid object shares one cell (exact, slow).
    const ObjectId far1 = p.insert({Vec3<double>(-1.7e308, 0, 0), Vec3<double>(-1.7e308, 0, 0)});
    const ObjectId far2 = p.insert({Vec3<double>(1.7e308, 1, 1), Vec3<double>(1.7e308, 1, 1)});
    p.check();
    CHECK(p.g.stats().cells[0] == 1);
    // A box whose extent overflows to infinity: oversized, still exact.
    p.move(far1, {Vec3<double>(-1.7e308, 0, 0), Vec3<double>(1.7e308, 1, 1)});
    p.check();
    p.remove(far2);
    p.check();
    CHECK(p.g.stats().oversized == 3);
    // Everything removed, then a single point.
    Pair2 q;
    CHECK(q.check() == 0);
    const ObjectId a = q.insert({Vec3<double>(1, 2, 3), Vec3<double>(1, 2, 3)});
    CHECK(q.check() == 0);
    q.insert({Vec3<double>(1, 2, 3), Vec3<double>(1, 2, 3)});
    CHECK(q.check() == 1);
    q.remove(a);
    CHECK(q.check() == 0);
    CHECK_THROWS_AS(q.g.remove(a), cdkit::Error);
    CHECK_THROWS_AS(q.g.move(a, {}), cdkit::Error);
    CHECK_THROWS_AS(q.g.insert({Vec3<double>(1, 0, 0), Vec3<double>(0, 1, 1)}), cdkit::Error);
}

TEST_CASE("float sorted-cell grid equals brute force", "[broadphase][cellgrid]") {
    std::mt19937 rng(24);
    BruteForceBroadPhase<float> bf;
    SortedCellGrid<float> g;
    std::uniform_real_distribution<float> pos(0, 1000), sz(0.5f, 4.f);
    // A wide, sparse scene (float cell counts are capped lower) plus a dense block.
    for (int i = 0; i < 1500; ++i) {
        const float w = i < 500 ? 1.f : 0.03f;
        Vec3<float> c(pos(rng) * w, pos(rng) * w, pos(rng) * w);
        BroadBox<float> b{c, c + Vec3<float>(sz(rng), sz(rng), sz(rng))};
        bf.insert(b), g.insert(b);
    }
    auto r = bf.find_pairs(), s = g.find_pairs();
    std::sort(r.begin(), r.end()), std::sort(s.begin(), s.end());
    CHECK(r.size() > 500);
    CHECK(s == r);
}
