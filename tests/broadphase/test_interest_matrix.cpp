// Interest matrix: filtering by groups and pairs, begin/persist/end events, per-pair data kept while active.
#include <catch2/catch.hpp>

#include "cdkit/broadphase/brute_force.hpp"
#include "cdkit/broadphase/interest_matrix.hpp"
#include "cdkit/broadphase/sweep_and_prune.hpp"
#include "test_common.hpp"

#include <map>
#include <random>
#include <set>

using namespace cdkit;
using B = BroadBox<double>;

namespace {
B unit_at(double x) { return {Vec3<double>(x, 0, 0), Vec3<double>(x + 1, 1, 1)}; }
}  // namespace

TEST_CASE("interest matrix: events and persistent pair data", "[broadphase]") {
    SweepAndPrune<double> sap;
    struct Cache { int frames = 0; };
    InterestMatrix<Cache> im;
    std::vector<std::pair<char, ObjectPair>> log;
    im.on_begin = [&](ObjectPair p, Cache& c) { log.push_back({'b', p}); c.frames = 1; };
    im.on_persist = [&](ObjectPair p, Cache& c) { log.push_back({'p', p}); ++c.frames; };
    im.on_end = [&](ObjectPair p, Cache& c) { log.push_back({'e', p}); CHECK(c.frames > 0); };

    const ObjectId a = sap.insert(unit_at(0)), b = sap.insert(unit_at(0.5)), c = sap.insert(unit_at(10));
    im.update(sap);
    REQUIRE(log.size() == 1);
    CHECK(log[0].first == 'b');
    CHECK(log[0].second == ObjectPair{a, b});
    log.clear();
    im.update(sap);
    im.update(sap);
    REQUIRE(im.data(a, b) != nullptr);
    CHECK(im.data(b, a)->frames == 3);  // persisted, data kept
    CHECK(log.size() == 2);
    log.clear();
    sap.move(b, unit_at(5));
    im.update(sap);
    REQUIRE(log.size() == 1);
    CHECK(log[0].first == 'e');
    CHECK(im.data(a, b) == nullptr);
    CHECK(im.active_count() == 0);
    log.clear();
    // Filtering: put c in group 1 and switch off groups 0-1; move c onto a: no event.
    im.set_group(c, 1);
    im.set_groups_tested(0, 1, false);
    sap.move(c, unit_at(0.2));
    im.update(sap);
    CHECK(log.empty());
    // A per-pair override turns it back on.
    im.set_pair_tested(a, c, true);
    im.update(sap);
    REQUIRE(log.size() == 1);
    CHECK(log[0] == std::pair<char, ObjectPair>{'b', ObjectPair{a, c}});
    log.clear();
    // Forgetting an object ends its pairs.
    sap.remove(c);
    im.forget(c);
    REQUIRE(log.size() == 1);
    CHECK(log[0].first == 'e');
    CHECK_FALSE(im.tested(a, a));
    CHECK_THROWS_AS(im.set_group(a, 64), cdkit::Error);
}

TEST_CASE("interest matrix: active set equals filtered brute force over a random scene", "[broadphase]") {
    std::mt19937 rng(3);
    BruteForceBroadPhase<double> bf;
    SweepAndPrune<double> sap;
    InterestMatrix<int> im;
    std::uniform_real_distribution<double> pos(0, 10), u(0, 1);
    std::normal_distribution<double> step(0, 0.2);
    const int n = 200;
    for (int i = 0; i < n; ++i) {
        const Vec3<double> c(pos(rng), pos(rng), pos(rng));
        const B box{c, c + Vec3<double>::Constant(1.0)};
        const ObjectId id = bf.insert(box);
        sap.insert(box);
        im.set_group(id, ObjectId(i % 3));
    }
    im.set_groups_tested(1, 2, false);
    im.set_groups_tested(2, 2, false);
    std::size_t begins = 0, ends = 0;
    im.on_begin = [&](ObjectPair, int& d) { d = 1; ++begins; };
    im.on_persist = [&](ObjectPair, int& d) { ++d; };
    im.on_end = [&](ObjectPair, int&) { ++ends; };
    for (int f = 0; f < cdkit::test::scaled(30, 3); ++f) {
        for (ObjectId id = 0; id < ObjectId(n); ++id) {
            B b = bf.box(id);
            const Vec3<double> d(step(rng), step(rng), step(rng));
            bf.move(id, {b.lo + d, b.hi + d});
            sap.move(id, {b.lo + d, b.hi + d});
        }
        im.update(sap);
        std::set<std::uint64_t> want, got;
        bf.for_each_pair([&](ObjectId a, ObjectId b) {
            if (im.tested(a, b)) want.insert(ObjectPair{a, b}.key());
        });
        im.for_each_active([&](ObjectPair p, int&) { got.insert(p.key()); });
        CHECK(got == want);
    }
    CHECK(begins > 0);
    CHECK(ends > 0);
}
