#pragma once
// Shared by the broad-phase tests: sorted pair sets, random boxes, and every broad phase run on one edit
// script against brute force.
#include <catch2/catch.hpp>

#include "cdkit/broadphase/brute_force.hpp"
#include "cdkit/broadphase/dynamic_aabb_tree.hpp"
#include "cdkit/broadphase/sorted_cell_grid.hpp"
#include "cdkit/broadphase/sweep_and_prune.hpp"
#include "cdkit/broadphase/uniform_grid.hpp"

#include <algorithm>
#include <random>
#include <vector>

namespace cdkit::test {

/// The pairs a broad phase reports, sorted; each must have a < b and appear once.
template <class BP> std::vector<ObjectPair> sorted_pairs(BP& bp) {
    auto v = bp.find_pairs();
    for (const auto& p : v) REQUIRE(p.a < p.b);
    std::sort(v.begin(), v.end());
    REQUIRE(std::adjacent_find(v.begin(), v.end()) == v.end());  // each pair once
    return v;
}

/// A box with its centre uniform in [0, world]^3 and side lengths uniform in [smin, smax].
inline BroadBox<double> random_box(std::mt19937& rng, double world, double smin, double smax) {
    std::uniform_real_distribution<double> pos(0.0, world), sz(smin, smax);
    const Vec3<double> c(pos(rng), pos(rng), pos(rng));
    const Vec3<double> h(sz(rng), sz(rng), sz(rng));
    return BroadBox<double>::from_center_half(c, h * 0.5);
}

/// The same edit script on brute force, SAP, two grids (automatic and fixed cell), two dynamic AABB trees
/// (default and zero margin) and the sorted-cell grid; check() compares every pair set with brute force's.
struct AllBroadPhases {
    BruteForceBroadPhase<double> bf;
    SweepAndPrune<double> sap;
    UniformGrid<double> grid;
    UniformGrid<double> grid_fixed{0.7, 8};
    DynamicAabbTree<double> tree;
    DynamicAabbTree<double> tight{{0.0, 0.0}};
    SortedCellGrid<double> cells;
    ObjectId insert(const BroadBox<double>& b) {
        const ObjectId id = bf.insert(b);
        // Same id policy everywhere: handles agree with brute force's.
        REQUIRE(sap.insert(b) == id);
        REQUIRE(grid.insert(b) == id);
        REQUIRE(grid_fixed.insert(b) == id);
        REQUIRE(tree.insert(b) == id);
        REQUIRE(tight.insert(b) == id);
        REQUIRE(cells.insert(b) == id);
        return id;
    }
    void remove(ObjectId id) {
        bf.remove(id), sap.remove(id), grid.remove(id), grid_fixed.remove(id), tree.remove(id), tight.remove(id), cells.remove(id);
    }
    void move(ObjectId id, const BroadBox<double>& b) {
        bf.move(id, b), sap.move(id, b), grid.move(id, b), grid_fixed.move(id, b), tree.move(id, b), tight.move(id, b), cells.move(id, b);
    }
    std::size_t check(bool validate_trees = true) {
        const auto ref = sorted_pairs(bf);
        CHECK(sorted_pairs(sap) == ref);
        CHECK(sorted_pairs(grid) == ref);
        CHECK(sorted_pairs(grid_fixed) == ref);
        CHECK(sorted_pairs(tree) == ref);
        CHECK(sorted_pairs(tight) == ref);
        CHECK(sorted_pairs(cells) == ref);
        if (validate_trees) {
            CHECK_NOTHROW(tree.validate());
            CHECK_NOTHROW(tight.validate());
        }
        return ref.size();
    }
};

}  // namespace cdkit::test
