#pragma once
/// \file Dynamic AABB tree with fattened leaves: the incremental broad phase for coherent scenes.
///
/// Based on: G. van den Bergen, "Efficient Collision Detection of Complex Deformable Models using AABB
/// Trees", J. Graphics Tools 2(4), 1997, and "Collision Detection in Interactive 3D Environments", 2003 (a
/// binary AABB tree updated incrementally instead of rebuilt); E. Catto, "Dynamic Bounding Volume
/// Hierarchies", GDC 2019 (Box2D's b2DynamicTree: leaves hold *fattened* boxes, so an object that moves a
/// little stays inside its leaf and costs nothing; insertion descends greedily by surface-area cost);
/// D. Kopta, T. Ize, J. Spjut, E. Brunvand, A. Davis, A. Kensler, "Fast, Effective BVH Updates for
/// Animated Scenes", I3D 2012 (local tree rotations that swap a child with a grandchild when that lowers
/// the surface area, applied on the path above every insertion and removal to keep the tree balanced).
///
/// Pair finding is incremental too: the tree keeps the set of pairs whose *fat* boxes overlap. Only objects
/// whose fat box changed since the last frame ("moved" objects) can change that set, so each frame
/// (0) re-inserts the leaves that left their fat boxes (move() only enlarged their ancestors, which keeps the
/// tree valid between frames), (1) drops the stored pairs that involve a moved or removed object and reports
/// the other stored pairs whose *tight* boxes overlap, (2) queries the tree with each moved object's fat box
/// and adds what it finds, and (3) reports the new pairs whose tight boxes overlap. Tight ⊆ fat, so the report
/// is exactly the overlapping pairs (checked against brute force in the tests); a coherent frame costs
/// O(moved · log n + fat pairs). When more than half of the objects moved or are new (teleports, mass
/// insertion), the frame instead rebuilds the tree top-down (median splits) and finds all fat pairs with one
/// self-traversal of the tree.
///
/// Fat margin per object: `Options::margin + Options::relative_margin · (largest edge of its box)`. Larger
/// margins mean fewer re-insertions but more fat pairs to filter; the defaults suit objects that move a few
/// percent of their size per frame.

#include "cdkit/broadphase/detail/object_slots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace cdkit {

/// Dynamic AABB tree broad phase, same interface as SweepAndPrune / UniformGrid.
/// Thread safety: const members (contains, size, box, fat_box, query, height, stats, validate) may run
/// concurrently with each other; insert / remove / move / for_each_pair / rebuild must not run concurrently
/// with anything else on the same object.
template <class S = double> class DynamicAabbTree : public detail::SlotBroadPhase<S, DynamicAabbTree<S>> {
    using Base = detail::SlotBroadPhase<S, DynamicAabbTree<S>>;
    using Base::slots_;

public:
    static constexpr const char* name = "dynamic_aabb_tree";

    struct Options {
        S margin = S(0);              ///< absolute fat margin added on every side (world units, >= 0)
        S relative_margin = S(0.25);  ///< plus this fraction of the box's largest edge (>= 0)
    };
    /// Statistics of the last for_each_pair (reinsertions and rotations counted since the one before).
    struct Stats {
        std::size_t reinserted = 0;  ///< objects that left their fat box (or were added) since the last frame
        std::size_t rotations = 0;   ///< tree rotations applied
        std::size_t queried = 0;     ///< tree queries run for moved objects
        std::size_t fat_pairs = 0;   ///< stored pairs whose fat boxes overlap (tight-box tests done)
        int height = 0;              ///< tree height after the frame (a leaf has height 0)
        std::size_t rebuilds = 0;    ///< 1 when the frame rebuilt the whole tree (most objects had moved out)
    };

    DynamicAabbTree() = default;
    /// Throws cdkit::Error when a margin is negative, NaN or infinite.
    explicit DynamicAabbTree(const Options& options) : options_(options) {
        if (!(options.margin >= S(0)) || !std::isfinite(options.margin) || !(options.relative_margin >= S(0)) ||
            !std::isfinite(options.relative_margin))
            throw Error("<broadphase>", "dynamic AABB tree options", "margins must be finite and >= 0");
    }

    /// Adds an object; throws cdkit::Error for a NaN/infinite box or min > max.
    ObjectId insert(const BroadBox<S>& b) {
        const ObjectId id = slots_.insert(b);
        if (id >= leaf_.size()) {
            leaf_.resize(std::size_t(id) + 1, null);
            fat_.resize(std::size_t(id) + 1);
            moved_.resize(std::size_t(id) + 1, 0);
        }
        fat_[id] = fatten(b);
        leaf_[id] = insert_leaf(fat_[id], id);
        mark_moved(id, fat_changed);
        return id;
    }
    /// Removes an object; throws cdkit::Error for an unknown or already removed id.
    void remove(ObjectId id) {
        slots_.remove(id);
        remove_leaf(leaf_[id]);
        free_node(leaf_[id]);
        leaf_[id] = null;
    }
    /// Replaces an object's box; throws cdkit::Error for a bad id or box. O(1) while the box stays inside its
    /// fat box (and the fat box is not much too large). Otherwise the leaf gets a new fat box and its
    /// ancestors are enlarged to hold it (the tree stays valid, only looser); the leaf is re-inserted at the
    /// next for_each_pair, or the whole tree is rebuilt there when most objects left their fat boxes.
    void move(ObjectId id, const BroadBox<S>& b) {
        slots_.move(id, b);
        const BroadBox<S>& fat = fat_[id];  // by id: the loop over all objects reads it sequentially
        if (contains_box(fat, b) && !too_loose(fat, b)) return;
        const BroadBox<S> nf = fatten(b);
        fat_[id] = nf;
        const std::int32_t leaf = leaf_[id];
        nodes_[std::size_t(leaf)].box = nf;
        for (std::int32_t i = nodes_[std::size_t(leaf)].parent; i != null; i = nodes_[std::size_t(i)].parent) {
            Node& n = nodes_[std::size_t(i)];
            if (contains_box(n.box, nf)) break;
            n.box = merge(n.box, nf);
        }
        mark_moved(id, needs_reinsert);
    }
    /// Rebuilds the tree top-down from the current fat boxes (median splits on the longest axis of the
    /// centres: depth ⌈log2 n⌉). for_each_pair does this by itself when most objects moved out of their
    /// fat boxes; the ids and pair results do not change.
    void rebuild() {
        items_.clear();
        for (ObjectId id = 0; id < slots_.capacity(); ++id)
            if (slots_.alive(id)) {
                const BroadBox<S>& b = fat_[id];
                items_.push_back({b.lo / S(2) + b.hi / S(2), leaf_[id]});  // halves first: no overflow
                if (moved_[id] == needs_reinsert) moved_[id] = fat_changed;
            }
        // Build a fresh node array in depth-first order (each subtree is one contiguous run of nodes, so the
        // queries and insertions of the next frames walk nearby memory), then drop the old one.
        built_.clear();
        built_.reserve(items_.empty() ? 0 : 2 * items_.size() - 1);
        if (!items_.empty()) build_top_down(0, items_.size(), null);
        nodes_.swap(built_);
        built_.clear();
        free_list_ = null;
        root_ = nodes_.empty() ? null : 0;
    }
    /// The fattened box stored in the tree for a live object (precondition: contains(id)).
    [[nodiscard]] const BroadBox<S>& fat_box(ObjectId id) const noexcept { return fat_[id]; }
    /// Tree height (0 for a single leaf, -1 when empty).
    [[nodiscard]] int height() const noexcept { return root_ == null ? -1 : nodes_[std::size_t(root_)].height; }
    [[nodiscard]] const Stats& stats() const noexcept { return stats_; }

    /// Calls f(id) for every live object whose *fat* box overlaps `query` (a superset of the tight-box
    /// hits; test box(id) for the exact answer); f returns false to stop early. Const and thread-safe.
    template <class F> void query(const BroadBox<S>& q, F&& f) const {
        std::vector<std::int32_t> stack;
        stack.reserve(64);
        query_with(q, stack, [&](std::int32_t node) { return f(nodes_[std::size_t(node)].object); });
    }

    /// Calls f(a, b) with a < b once for every overlapping pair of live objects (tight boxes). f must not
    /// modify this broad phase.
    template <class F> void for_each_pair(F&& f) {
        // 0. Moved leaves go to their proper place: one by one, or by a rebuild when most objects moved or are
        //    new (teleports, mass insertion), which then finds all fat pairs by one self-traversal instead of
        //    n queries (and replaces the tree grown by many incremental insertions with a balanced one).
        std::size_t pending = 0;
        for (const ObjectId id : move_buffer_) pending += slots_.alive(id) && moved_[id] != 0;
        if (pending > 64 && pending * 2 > slots_.size()) {
            rebuild();
            ++counters_.rebuilds;
            self_pairs();
            for (const ObjectId id : move_buffer_)
                if (id < moved_.size()) moved_[id] = 0;
            move_buffer_.clear();
            for (const ObjectPair& p : pairs_)
                if (overlap_branch_free(slots_.box(p.a), slots_.box(p.b))) f(p.a, p.b);
            finish_stats();
            return;
        }
        // Work through the moved objects in the order of their leaves in the node array: after a rebuild that
        // is depth-first order, so consecutive re-insertions and queries walk the same inner nodes (in cache).
        // Removed objects (leaf null) sort first and are skipped below.
        std::sort(move_buffer_.begin(), move_buffer_.end(), [this](ObjectId x, ObjectId y) {
            return std::make_pair(leaf_[x], x) < std::make_pair(leaf_[y], y);
        });
        for (const ObjectId id : move_buffer_)
            if (slots_.alive(id) && moved_[id] == needs_reinsert) {
                remove_leaf(leaf_[id]);
                insert_node(leaf_[id]);
                moved_[id] = fat_changed;
            }
        // 1. Keep the stored pairs of objects that did not move (their fat boxes, hence their fat overlap, are
        //    unchanged) and report those whose tight boxes overlap; drop the pairs of moved or removed objects.
        std::size_t w = 0;
        for (std::size_t r = 0; r < pairs_.size(); ++r) {
            const ObjectPair p = pairs_[r];
            // A sum, not ||: one branch for four unpredictable conditions.
            if (int(!slots_.alive(p.a)) + int(!slots_.alive(p.b)) + int(moved_[p.a] != 0) + int(moved_[p.b] != 0) != 0) continue;
            pairs_[w++] = p;
            if (overlap_branch_free(slots_.box(p.a), slots_.box(p.b))) f(p.a, p.b);
        }
        pairs_.resize(w);
        // 2. Re-query the moved objects. A pair of two moved objects is added by the query of the larger id.
        for (const ObjectId id : move_buffer_) {
            if (!slots_.alive(id) || !moved_[id]) continue;
            ++counters_.queried;
            query_with(fat_[id], stack_, [&](std::int32_t node) {
                const ObjectId other = nodes_[std::size_t(node)].object;
                if (other != id && !(moved_[other] && other < id)) pairs_.push_back(ObjectPair::make(id, other));
                return true;
            });
        }
        for (const ObjectId id : move_buffer_)
            if (id < moved_.size()) moved_[id] = 0;
        move_buffer_.clear();
        // 3. Report the new fat pairs whose tight boxes overlap.
        for (std::size_t r = w; r < pairs_.size(); ++r) {
            const ObjectPair p = pairs_[r];
            if (overlap_branch_free(slots_.box(p.a), slots_.box(p.b))) f(p.a, p.b);
        }
        finish_stats();
    }

    /// Checks every invariant (parent links, child boxes inside parents, heights, one leaf per live object
    /// whose fat box holds its tight box); throws cdkit::Error naming the broken one. O(n).
    void validate() const {
        auto fail = [](const std::string& what) { throw Error("<broadphase>", "dynamic AABB tree", what); };
        std::size_t leaves = 0;
        if (root_ != null) {
            if (nodes_[std::size_t(root_)].parent != null) fail("root has a parent");
            std::vector<std::int32_t> stack{root_};
            while (!stack.empty()) {
                const std::int32_t i = stack.back();
                stack.pop_back();
                const Node& n = nodes_[std::size_t(i)];
                if (n.is_leaf()) {
                    ++leaves;
                    if (n.height != 0) fail("leaf height != 0");
                    if (!slots_.contains(n.object) || leaf_[n.object] != i) fail("leaf of a dead object or stale leaf link");
                    if (!contains_box(n.box, slots_.box(n.object))) fail("fat box does not contain the object's box");
                    if (!(n.box.lo == fat_[n.object].lo && n.box.hi == fat_[n.object].hi)) fail("leaf box differs from the fat box");
                    continue;
                }
                const Node& c0 = nodes_[std::size_t(n.child[0])];
                const Node& c1 = nodes_[std::size_t(n.child[1])];
                if (c0.parent != i || c1.parent != i) fail("child's parent link is wrong");
                if (n.height != 1 + std::max(c0.height, c1.height)) fail("wrong height");
                if (!contains_box(n.box, c0.box) || !contains_box(n.box, c1.box)) fail("child box outside its parent");
                stack.push_back(n.child[0]);
                stack.push_back(n.child[1]);
            }
        }
        if (leaves != slots_.size()) fail("leaf count differs from the object count");
    }

private:
    static constexpr std::int32_t null = -1;
    /// 6 S box + 4 links/height + object id; leaves have child[0] == null.
    struct Node {
        BroadBox<S> box;
        std::int32_t parent = null;
        std::int32_t child[2] = {null, null};
        std::int32_t height = 0;
        ObjectId object = 0;
        [[nodiscard]] bool is_leaf() const noexcept { return child[0] == null; }
    };
    static_assert(sizeof(Node) <= 6 * sizeof(S) + 24, "dynamic AABB tree node should stay compact");

    /// overlap() without short-circuits: in the pair scans the outcome is unpredictable (about one fat pair
    /// in five overlaps), so six compares and one branch beat up to six mispredictable branches.
    [[nodiscard]] static bool overlap_branch_free(const BroadBox<S>& a, const BroadBox<S>& b) noexcept {
        return int(a.lo.x() <= b.hi.x()) + int(b.lo.x() <= a.hi.x()) + int(a.lo.y() <= b.hi.y()) + int(b.lo.y() <= a.hi.y()) +
                   int(a.lo.z() <= b.hi.z()) + int(b.lo.z() <= a.hi.z()) == 6;
    }
    [[nodiscard]] static BroadBox<S> merge(const BroadBox<S>& a, const BroadBox<S>& b) noexcept {
        return {a.lo.cwiseMin(b.lo), a.hi.cwiseMax(b.hi)};
    }
    /// Surface area / 2: the SAH cost of a box (a probability of being hit, up to a constant).
    [[nodiscard]] static S area(const BroadBox<S>& b) noexcept {
        const Vec3<S> e = b.hi - b.lo;
        return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
    }
    [[nodiscard]] static bool contains_box(const BroadBox<S>& outer, const BroadBox<S>& inner) noexcept {
        return (outer.lo.array() <= inner.lo.array()).all() && (inner.hi.array() <= outer.hi.array()).all();
    }
    [[nodiscard]] S margin_for(const BroadBox<S>& b) const noexcept {
        const S edge = (b.hi - b.lo).maxCoeff();
        const S m = options_.margin + options_.relative_margin * edge;
        return std::isfinite(m) ? m : S(0);  // hi - lo overflows for boxes spanning ±1e308
    }
    [[nodiscard]] BroadBox<S> fatten(const BroadBox<S>& b) const noexcept {
        const S m = margin_for(b);
        BroadBox<S> f{b.lo.array() - m, b.hi.array() + m};
        for (int k = 0; k < 3; ++k) {  // keep fat boxes finite near the end of the range
            if (!std::isfinite(f.lo[k])) f.lo[k] = b.lo[k];
            if (!std::isfinite(f.hi[k])) f.hi[k] = b.hi[k];
        }
        return f;
    }
    /// A fat box much larger than the object needs (it shrank): re-insert to keep the fat pairs few.
    [[nodiscard]] bool too_loose(const BroadBox<S>& fat, const BroadBox<S>& b) const noexcept {
        const S need = (b.hi - b.lo).maxCoeff() + S(4) * margin_for(b);
        return (fat.hi - fat.lo).maxCoeff() > S(2) * need + options_.margin;
    }
    void finish_stats() noexcept {
        counters_.fat_pairs = pairs_.size();
        counters_.height = height();
        stats_ = counters_;  // stats() shows this frame; the counters restart for the next one
        counters_ = {};
    }
    static constexpr unsigned char fat_changed = 1;     // new fat box, leaf already in its right place
    static constexpr unsigned char needs_reinsert = 2;  // new fat box set in place, ancestors only enlarged
    void mark_moved(ObjectId id, unsigned char how) {
        ++counters_.reinserted;
        if (!moved_[id]) move_buffer_.push_back(id);
        moved_[id] = std::max(moved_[id], how);
    }
    /// Builds a subtree over items_[first, last) into built_ (pre-order: the node, then its left subtree,
    /// then its right one) and returns its index there. Works on the compact items (centre, old leaf) rather
    /// than the nodes, so the median splits stay in cache.
    std::int32_t build_top_down(std::size_t first, std::size_t last, std::int32_t parent) {
        const std::int32_t node = std::int32_t(built_.size());
        built_.emplace_back();
        built_.back().parent = parent;
        if (last - first == 1) {
            const Node& old = nodes_[std::size_t(items_[first].leaf)];
            Node& n = built_.back();
            n.box = old.box;
            n.object = old.object;
            leaf_[old.object] = node;
            return node;
        }
        Vec3<S> lo = items_[first].c, hi = lo;
        for (std::size_t k = first + 1; k < last; ++k) lo = lo.cwiseMin(items_[k].c), hi = hi.cwiseMax(items_[k].c);
        int axis;
        (hi - lo).maxCoeff(&axis);
        const std::size_t mid = first + (last - first) / 2;
        std::nth_element(items_.begin() + std::ptrdiff_t(first), items_.begin() + std::ptrdiff_t(mid),
                         items_.begin() + std::ptrdiff_t(last),
                         [axis](const Item& x, const Item& y) { return x.c[axis] < y.c[axis]; });
        const std::int32_t left = build_top_down(first, mid, node);
        const std::int32_t right = build_top_down(mid, last, node);
        Node& n = built_[std::size_t(node)];
        n.child[0] = left;
        n.child[1] = right;
        n.box = merge(built_[std::size_t(left)].box, built_[std::size_t(right)].box);
        n.height = 1 + std::max(built_[std::size_t(left)].height, built_[std::size_t(right)].height);
        return node;
    }
    /// All pairs of leaves whose fat boxes overlap, by a simultaneous descent of the tree with itself.
    void self_pairs() {
        pairs_.clear();
        if (root_ == null) return;
        std::vector<std::pair<std::int32_t, std::int32_t>>& st = pair_stack_;
        st.clear();
        st.push_back({root_, root_});
        while (!st.empty()) {
            const auto [x, y] = st.back();
            st.pop_back();
            const Node& a = nodes_[std::size_t(x)];
            if (x == y) {
                if (a.is_leaf()) continue;
                st.push_back({a.child[0], a.child[0]});
                st.push_back({a.child[1], a.child[1]});
                st.push_back({a.child[0], a.child[1]});
                continue;
            }
            const Node& b = nodes_[std::size_t(y)];
            if (!overlap(a.box, b.box)) continue;
            if (a.is_leaf() && b.is_leaf()) {
                pairs_.push_back(ObjectPair::make(a.object, b.object));
            } else if (b.is_leaf() || (!a.is_leaf() && area(a.box) >= area(b.box))) {
                st.push_back({a.child[0], y});
                st.push_back({a.child[1], y});
            } else {
                st.push_back({x, b.child[0]});
                st.push_back({x, b.child[1]});
            }
        }
    }

    std::int32_t allocate_node() {
        if (free_list_ != null) {
            const std::int32_t i = free_list_;
            free_list_ = nodes_[std::size_t(i)].parent;
            nodes_[std::size_t(i)] = Node{};
            return i;
        }
        nodes_.emplace_back();
        return std::int32_t(nodes_.size() - 1);
    }
    void free_node(std::int32_t i) noexcept {
        nodes_[std::size_t(i)].parent = free_list_;
        nodes_[std::size_t(i)].height = -1;
        free_list_ = i;
    }
    std::int32_t insert_leaf(const BroadBox<S>& fat, ObjectId id) {
        const std::int32_t leaf = allocate_node();
        nodes_[std::size_t(leaf)].box = fat;
        nodes_[std::size_t(leaf)].object = id;
        insert_node(leaf);
        return leaf;
    }

    /// Greedy surface-area descent for the best sibling (Catto's b2DynamicTree cost: the new parent's area
    /// plus the growth it causes in every ancestor), then a new parent and a refit + rotate walk to the root.
    void insert_node(std::int32_t leaf) {
        nodes_[std::size_t(leaf)].child[0] = nodes_[std::size_t(leaf)].child[1] = null;
        nodes_[std::size_t(leaf)].height = 0;
        if (root_ == null) {
            root_ = leaf;
            nodes_[std::size_t(leaf)].parent = null;
            return;
        }
        const BroadBox<S> box = nodes_[std::size_t(leaf)].box;
        std::int32_t index = root_;
        while (!nodes_[std::size_t(index)].is_leaf()) {
            const Node& n = nodes_[std::size_t(index)];
            const S combined = area(merge(n.box, box));
            const S here = S(2) * combined;                         // make `index` the sibling
            const S inherited = S(2) * (combined - area(n.box));    // growth of `index` if we descend
            S child_cost[2];
            for (int k = 0; k < 2; ++k) {
                const Node& c = nodes_[std::size_t(n.child[k])];
                const S grown = area(merge(c.box, box));
                child_cost[k] = (c.is_leaf() ? grown : grown - area(c.box)) + inherited;
            }
            // NaN-safe: with overflowing areas every comparison is false and we stop here.
            if (!(child_cost[0] < here) && !(child_cost[1] < here)) break;
            index = n.child[child_cost[1] < child_cost[0] ? 1 : 0];
        }
        const std::int32_t sibling = index;
        const std::int32_t old_parent = nodes_[std::size_t(sibling)].parent;
        const std::int32_t parent = allocate_node();
        Node& p = nodes_[std::size_t(parent)];
        p.parent = old_parent;
        p.box = merge(box, nodes_[std::size_t(sibling)].box);
        p.height = nodes_[std::size_t(sibling)].height + 1;
        p.child[0] = sibling;
        p.child[1] = leaf;
        p.object = 0;
        if (old_parent == null) {
            root_ = parent;
        } else {
            Node& op = nodes_[std::size_t(old_parent)];
            op.child[op.child[0] == sibling ? 0 : 1] = parent;
        }
        nodes_[std::size_t(sibling)].parent = parent;
        nodes_[std::size_t(leaf)].parent = parent;
        refit_to_root(old_parent);
    }
    /// Unlinks a leaf (the node itself is kept, for re-insertion or freeing by the caller).
    void remove_leaf(std::int32_t leaf) {
        if (leaf == root_) {
            root_ = null;
            return;
        }
        const std::int32_t parent = nodes_[std::size_t(leaf)].parent;
        const std::int32_t grand = nodes_[std::size_t(parent)].parent;
        const Node& pn = nodes_[std::size_t(parent)];
        const std::int32_t sibling = pn.child[0] == leaf ? pn.child[1] : pn.child[0];
        if (grand == null) {
            root_ = sibling;
            nodes_[std::size_t(sibling)].parent = null;
        } else {
            Node& g = nodes_[std::size_t(grand)];
            g.child[g.child[0] == parent ? 0 : 1] = sibling;
            nodes_[std::size_t(sibling)].parent = grand;
        }
        free_node(parent);
        refit_to_root(grand);
    }
    /// Refits boxes and heights from node i up, rotating on the way. Stops early once two consecutive
    /// ancestors kept their box and height and were not rotated: nothing above can change then (a node's box
    /// and height depend only on its children), and a rotation looks at most two levels down, so the
    /// ancestors further up would see exactly the boxes they saw before. In a coherent scene a re-inserted
    /// object lands near where it was, so the walk usually ends a few levels above the leaf instead of at the
    /// root (fewer cache misses in a large tree).
    void refit_to_root(std::int32_t i) {
        int unchanged = 0;
        while (i != null) {
            Node& n = nodes_[std::size_t(i)];
            const Node& c0 = nodes_[std::size_t(n.child[0])];
            const Node& c1 = nodes_[std::size_t(n.child[1])];
            const BroadBox<S> box = merge(c0.box, c1.box);
            const std::int32_t height = 1 + std::max(c0.height, c1.height);
            const bool same = box.lo == n.box.lo && box.hi == n.box.hi && height == n.height;
            n.box = box;
            n.height = height;
            const bool rotated = rotate(i);
            unchanged = (same && !rotated) ? unchanged + 1 : 0;
            if (unchanged == 2) break;
            i = nodes_[std::size_t(i)].parent;
        }
    }
    /// Kopta et al.'s rotation at node a (children b, c): swap one child with a grandchild on the other side
    /// when that shrinks the area of the grandchild's parent; a's own box is unchanged by any swap.
    bool rotate(std::int32_t a) {
        Node& an = nodes_[std::size_t(a)];
        S best = S(0);
        int best_side = -1, best_grand = -1;  // swap an.child[1 - side] with grandchild child[grand] of an.child[side]
        for (int side = 0; side < 2; ++side) {
            const Node& inner = nodes_[std::size_t(an.child[side])];
            if (inner.is_leaf()) continue;
            const BroadBox<S>& other = nodes_[std::size_t(an.child[1 - side])].box;
            const S before = area(inner.box);
            for (int g = 0; g < 2; ++g) {
                // After the swap `inner` holds `other` and its grandchild 1 - g.
                const S after = area(merge(other, nodes_[std::size_t(inner.child[1 - g])].box));
                const S gain = after - before;
                if (gain < best) {
                    best = gain;
                    best_side = side;
                    best_grand = g;
                }
            }
        }
        if (best_side < 0) return false;
        const std::int32_t inner_i = an.child[best_side];
        const std::int32_t moved_up = nodes_[std::size_t(inner_i)].child[best_grand];
        const std::int32_t moved_down = an.child[1 - best_side];
        an.child[1 - best_side] = moved_up;
        nodes_[std::size_t(moved_up)].parent = a;
        Node& in = nodes_[std::size_t(inner_i)];
        in.child[best_grand] = moved_down;
        nodes_[std::size_t(moved_down)].parent = inner_i;
        const Node& k0 = nodes_[std::size_t(in.child[0])];
        const Node& k1 = nodes_[std::size_t(in.child[1])];
        in.box = merge(k0.box, k1.box);
        in.height = 1 + std::max(k0.height, k1.height);
        Node& an2 = nodes_[std::size_t(a)];
        an2.height = 1 + std::max(nodes_[std::size_t(an2.child[0])].height, nodes_[std::size_t(an2.child[1])].height);
        ++counters_.rotations;
        return true;
    }

    void prefetch(std::int32_t i) const noexcept {
#if defined(__GNUC__) || defined(__clang__)
        __builtin_prefetch(&nodes_[std::size_t(i)]);
#else
        (void)i;
#endif
    }
    /// Visits the leaves whose box overlaps q; `visit(node)` returns false to stop.
    template <class F> void query_with(const BroadBox<S>& q, std::vector<std::int32_t>& stack, F&& visit) const {
        if (root_ == null) return;
        stack.clear();
        stack.push_back(root_);
        while (!stack.empty()) {
            const std::int32_t i = stack.back();
            stack.pop_back();
            const Node& n = nodes_[std::size_t(i)];
            if (!overlap(n.box, q)) continue;
            if (n.is_leaf()) {
                if (!visit(i)) return;
            } else {
                // Start loading both children now: the second is popped only after the first's subtree.
                prefetch(n.child[0]);
                prefetch(n.child[1]);
                stack.push_back(n.child[0]);
                stack.push_back(n.child[1]);
            }
        }
    }

    Options options_{};
    std::vector<Node> nodes_;
    std::vector<Node> built_;  // the new node array during rebuild() (kept for its capacity)
    std::int32_t root_ = null, free_list_ = null;
    std::vector<std::int32_t> leaf_;         // object id -> leaf node
    std::vector<BroadBox<S>> fat_;           // object id -> fat box (a copy of its leaf's box, read by move())
    std::vector<unsigned char> moved_;       // fat box changed since the last frame
    std::vector<ObjectId> move_buffer_;      // ids with moved_ set
    std::vector<ObjectPair> pairs_;          // pairs whose fat boxes overlap (as of the last frame)
    struct Item {
        Vec3<S> c;  // centre of the fat box
        std::int32_t leaf;
    };
    std::vector<Item> items_;
    std::vector<std::int32_t> stack_;
    std::vector<std::pair<std::int32_t, std::int32_t>> pair_stack_;
    Stats stats_{}, counters_{};  // last frame's statistics; the ones being counted for the next frame
};

}  // namespace cdkit
