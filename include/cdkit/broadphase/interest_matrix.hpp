#pragma once
/// \file Collision interest matrix: which pairs are tested, the per-pair data that lives while a pair
/// overlaps, and begin / persist / end events.
///
/// Filtering is two-level: every object belongs to one of 64 groups and a 64x64 bit matrix says which group
/// pairs are tested (O(1), no per-pair storage); individual pairs can be switched off or on in a hash map that
/// is only consulted when it is non-empty. Filtered-out pairs stop at the bit test and never reach the pair
/// table or a callback. Only overlapping, tested pairs hold an entry (with the user's `PairData`, e.g. a
/// narrow-phase warm-start cache) and it is created on begin and destroyed after end.

#include "cdkit/broadphase/box.hpp"

#include <cstdint>
#include <array>
#include <functional>
#include <iterator>
#include <unordered_map>
#include <vector>

namespace cdkit {

/// Interest matrix over object ids; `PairData` is default-constructed when a pair begins overlapping.
/// Thread safety: const members may run concurrently; everything else must not run concurrently.
template <class PairData = std::uint8_t> class InterestMatrix {
public:
    using GroupId = std::uint8_t;
    static constexpr int max_groups = 64;
    using Callback = std::function<void(ObjectPair, PairData&)>;

    /// Called when a tested pair starts overlapping, keeps overlapping, and stops overlapping (or an object
    /// of the pair is forgotten). Each may be empty.
    Callback on_begin, on_persist, on_end;

    InterestMatrix() { groups_mask_.fill(~std::uint64_t(0)); }

    /// Puts an object in a group (default group 0). Throws cdkit::Error for a group >= 64.
    void set_group(ObjectId id, GroupId g) {
        if (g >= max_groups) throw Error("<interest matrix>", "group " + std::to_string(g), "must be < 64");
        if (id >= group_.size()) group_.resize(std::size_t(id) + 1, 0);
        group_[id] = g;
    }
    [[nodiscard]] GroupId group(ObjectId id) const noexcept { return id < group_.size() ? group_[id] : 0; }
    /// Whether objects of groups g and h are tested against each other (default: all are).
    void set_groups_tested(GroupId g, GroupId h, bool tested) {
        if (g >= max_groups || h >= max_groups) throw Error("<interest matrix>", "group pair", "groups must be < 64");
        set_bit(g, h, tested);
        set_bit(h, g, tested);
    }
    /// Overrides the group rule for one pair.
    void set_pair_tested(ObjectId a, ObjectId b, bool tested) { override_[ObjectPair::make(a, b).key()] = tested; }
    /// Removes a per-pair override.
    void clear_pair_override(ObjectId a, ObjectId b) { override_.erase(ObjectPair::make(a, b).key()); }

    /// Whether the pair is tested: the per-pair override if any, else the group matrix.
    [[nodiscard]] bool tested(ObjectId a, ObjectId b) const noexcept {
        if (a == b) return false;
        if (!override_.empty()) {
            const auto it = override_.find(ObjectPair::make(a, b).key());
            if (it != override_.end()) return it->second;
        }
        return (groups_mask_[group(a)] >> group(b)) & 1u;
    }

    /// Runs the broad phase's pair search (anything with for_each_pair(f)), filters the pairs, updates the
    /// pair table and fires the callbacks: begins and persists during the search, ends after it.
    template <class BroadPhase> void update(BroadPhase& bp) {
        ++frame_;
        bp.for_each_pair([&](ObjectId a, ObjectId b) { report(a, b); });
        finish_frame();
    }
    /// Manual feeding, for a pair list from elsewhere: begin_frame(), report() each pair once, finish_frame().
    void begin_frame() noexcept { ++frame_; }
    void report(ObjectId a, ObjectId b) {
        if (!tested(a, b)) return;
        const ObjectPair p = ObjectPair::make(a, b);
        auto [it, fresh] = active_.try_emplace(p.key());
        it->second.frame = frame_;
        if (fresh) {
            if (on_begin) on_begin(p, it->second.data);
        } else if (on_persist) {
            on_persist(p, it->second.data);
        }
    }
    void finish_frame() {
        for (auto it = active_.begin(); it != active_.end();) {
            if (it->second.frame != frame_) {
                if (on_end) on_end(unkey(it->first), it->second.data);
                it = active_.erase(it);
            } else {
                ++it;
            }
        }
    }
    /// Call when an object is removed from the broad phase (its id may be reused): ends its active pairs,
    /// drops its overrides and resets its group to 0. O(active pairs + overrides).
    void forget(ObjectId id) {
        for (auto it = active_.begin(); it != active_.end();) {
            const ObjectPair p = unkey(it->first);
            if (p.a == id || p.b == id) {
                if (on_end) on_end(p, it->second.data);
                it = active_.erase(it);
            } else {
                ++it;
            }
        }
        for (auto it = override_.begin(); it != override_.end();) {
            const ObjectPair p = unkey(it->first);
            it = (p.a == id || p.b == id) ? override_.erase(it) : std::next(it);
        }
        if (id < group_.size()) group_[id] = 0;
    }

    /// The data of an active pair, or nullptr.
    [[nodiscard]] PairData* data(ObjectId a, ObjectId b) noexcept {
        const auto it = active_.find(ObjectPair::make(a, b).key());
        return it == active_.end() ? nullptr : &it->second.data;
    }
    /// Number of tested pairs overlapping after the last frame.
    [[nodiscard]] std::size_t active_count() const noexcept { return active_.size(); }
    /// Calls f(pair, data) for every active pair.
    template <class F> void for_each_active(F&& f) {
        for (auto& [k, e] : active_) f(unkey(k), e.data);
    }

private:
    struct Entry {
        PairData data{};
        std::uint64_t frame = 0;
    };
    static ObjectPair unkey(std::uint64_t k) noexcept { return {ObjectId(k >> 32), ObjectId(k & 0xffffffffu)}; }
    void set_bit(GroupId g, GroupId h, bool on) noexcept {
        if (on) groups_mask_[g] |= std::uint64_t(1) << h;
        else groups_mask_[g] &= ~(std::uint64_t(1) << h);
    }

    std::array<std::uint64_t, max_groups> groups_mask_{};
    std::vector<GroupId> group_;
    std::unordered_map<std::uint64_t, bool> override_;
    std::unordered_map<std::uint64_t, Entry> active_;
    std::uint64_t frame_ = 0;
};

}  // namespace cdkit
