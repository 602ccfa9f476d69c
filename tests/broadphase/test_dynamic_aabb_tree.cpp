// Dynamic AABB tree: stable handles, balance, coherence statistics, rebuilds, bad input, and concurrent const
// queries (its pair sets over seeded edit scripts are checked with the other broad phases in test_broadphase.cpp).
#include <catch2/catch.hpp>

#include "broadphase_check.hpp"
#include "test_common.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <thread>
#include <vector>

using namespace cdkit;
using B = BroadBox<double>;

using test::random_box;
using test::sorted_pairs;
using Pair3 = test::AllBroadPhases;  // the trees against brute force (and the other broad phases)

TEST_CASE("dynamic AABB tree: handles are stable and boxes are kept per handle", "[broadphase][dbvt]") {
    std::mt19937 rng(3);
    DynamicAabbTree<double> tree;
    std::vector<ObjectId> ids;
    std::vector<B> boxes;
    for (int i = 0; i < 200; ++i) {
        boxes.push_back(random_box(rng, 10, 0.1, 1));
        ids.push_back(tree.insert(boxes.back()));
    }
    for (int i = 0; i < 200; ++i) CHECK(ids[std::size_t(i)] == ObjectId(i));
    std::normal_distribution<double> step(0.0, 0.3);
    for (int f = 0; f < 20; ++f) {
        for (std::size_t i = 0; i < ids.size(); ++i) {
            const Vec3<double> d(step(rng), step(rng), step(rng));
            boxes[i] = {boxes[i].lo + d, boxes[i].hi + d};
            tree.move(ids[i], boxes[i]);
        }
        (void)tree.find_pairs();
    }
    std::size_t same = 0;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        same += tree.box(ids[i]).lo == boxes[i].lo && tree.box(ids[i]).hi == boxes[i].hi;
        const B fat = tree.fat_box(ids[i]);
        CHECK(((fat.lo.array() <= boxes[i].lo.array()).all() && (boxes[i].hi.array() <= fat.hi.array()).all()));
    }
    CHECK(same == ids.size());
    tree.remove(ids[17]);
    CHECK_FALSE(tree.contains(ids[17]));
    CHECK(tree.contains(ids[18]));
    CHECK(tree.size() == 199);
    CHECK(tree.insert(boxes[17]) == ids[17]);  // the freed id is handed out again
    CHECK_NOTHROW(tree.validate());
}

TEST_CASE("dynamic AABB tree: coherent moves skip re-insertion, teleports do not", "[broadphase][dbvt]") {
    std::mt19937 rng(11);
    DynamicAabbTree<double> tree;
    std::vector<ObjectId> ids;
    const int n = cdkit::test::scaled(2000, 200);
    for (int i = 0; i < n; ++i) ids.push_back(tree.insert(random_box(rng, 50, 0.2, 2)));
    (void)tree.find_pairs();
    CHECK(tree.stats().reinserted == std::size_t(n));
    CHECK(tree.stats().rebuilds == 1);  // mass insertion: one balanced rebuild instead of n queries
    CHECK(tree.height() <= int(std::ceil(std::log2(double(n)))));
    std::normal_distribution<double> step(0, 0.01);  // ~1% of the size per frame
    for (ObjectId id : ids) {
        const B b = tree.box(id);
        const Vec3<double> d(step(rng), step(rng), step(rng));
        tree.move(id, {b.lo + d, b.hi + d});
    }
    (void)tree.find_pairs();
    CHECK(tree.stats().reinserted < std::size_t(n) / 20);
    CHECK(tree.stats().rebuilds == 0);
    CHECK(tree.stats().fat_pairs > 0);
    for (ObjectId id : ids) tree.move(id, random_box(rng, 50, 0.2, 2));
    (void)tree.find_pairs();
    CHECK(tree.stats().reinserted > std::size_t(n) * 9 / 10);
    CHECK(tree.stats().rebuilds == 1);
    CHECK(tree.height() <= int(std::ceil(std::log2(double(n)))));  // the median rebuild is balanced
    CHECK_NOTHROW(tree.validate());
}

TEST_CASE("dynamic AABB tree: rebuild renumbers nodes, keeps fat boxes, pairs and later edits exact", "[broadphase][dbvt]") {
    std::mt19937 rng(23);
    Pair3 q;
    std::vector<ObjectId> ids;
    const int n = cdkit::test::scaled(1500, 150);
    for (int i = 0; i < n; ++i) ids.push_back(q.insert(random_box(rng, 30, 0.2, 2)));
    q.check();
    for (int i = 0; i < n; i += 7) q.remove(ids[std::size_t(i)]);  // holes in the id range and free nodes
    q.check();
    std::vector<B> fat;
    for (int i = 0; i < n; ++i)
        if (q.tree.contains(ids[std::size_t(i)])) fat.push_back(q.tree.fat_box(ids[std::size_t(i)]));
    const auto before = sorted_pairs(q.tree);
    q.tree.rebuild();  // the node array is rebuilt in depth-first order: every leaf gets a new node
    CHECK_NOTHROW(q.tree.validate());
    std::size_t k = 0;
    for (int i = 0; i < n; ++i)
        if (q.tree.contains(ids[std::size_t(i)])) {
            const B& f = q.tree.fat_box(ids[std::size_t(i)]);
            CHECK((f.lo == fat[k].lo && f.hi == fat[k].hi));
            ++k;
        }
    CHECK(sorted_pairs(q.tree) == before);
    // Edits after the rebuild: small moves (re-insertions in place), an insertion reusing a freed id, removals.
    std::normal_distribution<double> step(0, 0.3);
    for (int f = 0; f < 5; ++f) {
        for (int i = 1; i < n; i += 3)
            if (q.tree.contains(ids[std::size_t(i)])) {
                const B b = q.tree.box(ids[std::size_t(i)]);
                const Vec3<double> d(step(rng), step(rng), step(rng));
                q.move(ids[std::size_t(i)], {b.lo + d, b.hi + d});
            }
        const ObjectId again = q.insert(random_box(rng, 30, 0.2, 2));
        CHECK(again < ObjectId(n));  // a freed id is handed out again
        q.remove(ids[std::size_t(2 + 7 * f)]);
        CHECK(q.check() > 0);
    }
}

TEST_CASE("dynamic AABB tree stays balanced for sorted and clustered insertions", "[broadphase][dbvt]") {
    const int n = cdkit::test::scaled(4096, 512);
    const double log2n = std::log2(double(n));
    {
        // Boxes inserted in sorted order along a line: a plain greedy insertion degenerates to a list.
        DynamicAabbTree<double> tree;
        for (int i = 0; i < n; ++i) tree.insert({Vec3<double>(i, 0, 0), Vec3<double>(i + 0.5, 0.5, 0.5)});
        INFO("height " << tree.height() << " for n = " << n);
        CHECK(tree.height() <= int(4 * log2n));
        CHECK_NOTHROW(tree.validate());
    }
    {
        // A grid of identical boxes, then everything removed in insertion order and re-added.
        DynamicAabbTree<double> tree;
        std::vector<ObjectId> ids;
        const int side = int(std::cbrt(double(n)));
        for (int x = 0; x < side; ++x)
            for (int y = 0; y < side; ++y)
                for (int z = 0; z < side; ++z)
                    ids.push_back(tree.insert({Vec3<double>(x, y, z), Vec3<double>(x + 0.9, y + 0.9, z + 0.9)}));
        for (std::size_t i = 0; i < ids.size() / 2; ++i) tree.remove(ids[i]);
        INFO("height " << tree.height());
        CHECK(tree.height() <= int(4 * log2n));
        CHECK_NOTHROW(tree.validate());
    }
}

TEST_CASE("dynamic AABB tree: touching, zero-size, identical, huge and far boxes", "[broadphase][dbvt]") {
    std::mt19937 rng(7);
    Pair3 q;
    for (int x = 0; x < 3; ++x)
        for (int y = 0; y < 3; ++y)
            for (int z = 0; z < 3; ++z) q.insert({Vec3<double>(x, y, z), Vec3<double>(x + 1, y + 1, z + 1)});
    CHECK(q.check() == 158);  // 26-neighbourhood pairs of a 3x3x3 lattice of touching cubes
    q.insert({Vec3<double>(1, 1, 1), Vec3<double>(1, 1, 1)});
    q.insert({Vec3<double>(1, 1, 1), Vec3<double>(1, 1, 1)});
    for (int k = 0; k < 5; ++k) q.insert({Vec3<double>(10, 10, 10), Vec3<double>(11, 12, 13)});
    q.insert({Vec3<double>(-1e6, -1e6, -1e6), Vec3<double>(1e6, 1e6, 1e6)});
    for (int k = 0; k < 50; ++k) {
        std::uniform_real_distribution<double> pos(0, 3);
        const Vec3<double> c(pos(rng), pos(rng), pos(rng));
        q.insert({c, c + Vec3<double>::Constant(1e-9)});
    }
    // Huge coordinates: areas overflow to infinity; the tree must stay correct (and finite fat boxes).
    const ObjectId far1 = q.insert({Vec3<double>(1e300, 1e300, 1e300), Vec3<double>(1e300, 1e300, 1e300)});
    q.insert({Vec3<double>(-1e300, 1e299, 0), Vec3<double>(1e300, 1e300, 1)});
    q.insert({Vec3<double>::Constant(-1.7e308), Vec3<double>::Constant(1.7e308)});
    CHECK(q.tree.fat_box(far1).lo.allFinite());
    const std::size_t pairs = q.check();
    CHECK(pairs > 158 + 10 + 50);
    q.move(far1, {Vec3<double>(2, 2, 2), Vec3<double>(2.5, 2.5, 2.5)});
    q.check();
}

TEST_CASE("dynamic AABB tree rejects bad boxes, ids and options with cdkit::Error", "[broadphase][dbvt]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    DynamicAabbTree<double> tree;
    const ObjectId a = tree.insert({Vec3<double>(0, 0, 0), Vec3<double>(1, 1, 1)});
    const ObjectId b = tree.insert({Vec3<double>(0.5, 0, 0), Vec3<double>(1, 1, 1)});
    CHECK_THROWS_AS(tree.insert({Vec3<double>(nan, 0, 0), Vec3<double>(1, 1, 1)}), cdkit::Error);
    CHECK_THROWS_AS(tree.insert({Vec3<double>(0, 0, 0), Vec3<double>(inf, 1, 1)}), cdkit::Error);
    CHECK_THROWS_AS(tree.insert({Vec3<double>(2, 0, 0), Vec3<double>(1, 1, 1)}), cdkit::Error);
    CHECK_THROWS_AS(tree.move(a, {Vec3<double>(0, nan, 0), Vec3<double>(1, 1, 1)}), cdkit::Error);
    CHECK_THROWS_AS(tree.move(99, {}), cdkit::Error);
    CHECK_THROWS_AS(tree.remove(99), cdkit::Error);
    CHECK_THROWS_AS(DynamicAabbTree<double>({-1.0, 0.0}), cdkit::Error);
    CHECK_THROWS_AS(DynamicAabbTree<double>({0.0, nan}), cdkit::Error);
    CHECK_THROWS_AS(DynamicAabbTree<double>({inf, 0.0}), cdkit::Error);
    try {
        tree.move(a, {Vec3<double>(nan, 0, 0), Vec3<double>(1, 1, 1)});
    } catch (const cdkit::Error& e) {
        CHECK(std::string(e.what()).find("NaN") != std::string::npos);
    }
    // Failed calls left the tree intact.
    CHECK(tree.size() == 2);
    CHECK_NOTHROW(tree.validate());
    CHECK(tree.find_pairs().size() == 1);
    tree.remove(a);
    CHECK_THROWS_AS(tree.remove(a), cdkit::Error);  // double removal
    CHECK_THROWS_AS(tree.move(a, {}), cdkit::Error);
    CHECK(tree.find_pairs().empty());
    tree.remove(b);
    CHECK(tree.height() == -1);
    CHECK(tree.find_pairs().empty());
    CHECK_NOTHROW(tree.validate());
}

TEST_CASE("dynamic AABB tree: const queries from several threads", "[broadphase][dbvt]") {
    std::mt19937 rng(21);
    DynamicAabbTree<double> tree;
    BruteForceBroadPhase<double> bf;
    for (int i = 0; i < 1000; ++i) {
        const B b = random_box(rng, 30, 0.2, 2);
        tree.insert(b);
        bf.insert(b);
    }
    std::vector<B> queries;
    for (int i = 0; i < 200; ++i) queries.push_back(random_box(rng, 30, 0.5, 4));
    // Expected: tight-box hits by brute force.
    std::vector<std::size_t> expected(queries.size(), 0);
    for (std::size_t k = 0; k < queries.size(); ++k)
        for (ObjectId id = 0; id < 1000; ++id) expected[k] += overlap(bf.box(id), queries[k]);
    std::size_t total = 0;
    for (auto e : expected) total += e;
    CHECK(total > queries.size());  // the queries do hit
    std::vector<std::vector<std::size_t>> got(4, std::vector<std::size_t>(queries.size(), 0));
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (std::size_t k = 0; k < queries.size(); ++k)
                tree.query(queries[k], [&](ObjectId id) {
                    got[std::size_t(t)][k] += overlap(tree.box(id), queries[k]);
                    return true;
                });
        });
    for (auto& th : threads) th.join();
    for (int t = 0; t < 4; ++t) CHECK(got[std::size_t(t)] == expected);
}

TEST_CASE("float dynamic AABB tree equals brute force", "[broadphase][dbvt]") {
    std::mt19937 rng(5);
    BruteForceBroadPhase<float> bf;
    DynamicAabbTree<float> tree;
    std::uniform_real_distribution<float> pos(0, 10), sz(0.1f, 1.f), step(-0.05f, 0.05f);
    for (int i = 0; i < 400; ++i) {
        const Vec3<float> c(pos(rng), pos(rng), pos(rng));
        const BroadBox<float> b{c, c + Vec3<float>(sz(rng), sz(rng), sz(rng))};
        bf.insert(b);
        tree.insert(b);
    }
    for (int f = 0; f < 5; ++f) {
        for (ObjectId id = 0; id < 400; ++id) {
            const Vec3<float> d(step(rng), step(rng), step(rng));
            const BroadBox<float> b{bf.box(id).lo + d, bf.box(id).hi + d};
            bf.move(id, b);
            tree.move(id, b);
        }
        auto r = bf.find_pairs(), t = tree.find_pairs();
        std::sort(r.begin(), r.end());
        std::sort(t.begin(), t.end());
        CHECK(!r.empty());
        CHECK(t == r);
    }
}
