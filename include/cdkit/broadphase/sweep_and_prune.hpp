#pragma once
/// \file Incremental sweep and prune (sort and sweep).
///
/// Based on: D. Baraff, "Dynamic simulation of non-penetrating rigid bodies", PhD thesis, Cornell 1992, and
/// J. Cohen, M. Lin, D. Manocha, M. Ponamgari, "I-COLLIDE", Symposium on Interactive 3D Graphics 1995:
/// keep the boxes sorted along an axis from frame to frame; with temporal coherence an insertion sort of the
/// nearly sorted list costs O(n + swaps).
///
/// Design choice: the list holds one entry per object sorted by its *min* endpoint on the sweep axis (max
/// endpoints ride along in the entry), and the overlapping pairs are found by a sweep of that coherent
/// list each frame rather than by maintaining a pair set through the swaps. Per frame the cost is
/// O(n + swaps + k), k the number of pairs overlapping on the sweep axis. The swap-maintained variant needs a
/// hash set of pairs touched on every swap and a second pass to read it out; the sweep does the same work
/// with sequential memory access, no hash table, and is exact by construction (no state to drift).
/// Batch path: when the insertion sort exceeds a swap budget (teleports, mass insertion), it falls back to a
/// full std::sort, so an incoherent frame costs O(n log n + k) instead of O(n^2). A full sort also re-picks
/// the sweep axis (largest variance of the centres), which keeps k small.

#include "cdkit/broadphase/detail/object_slots.hpp"

#include <algorithm>
#include <vector>

namespace cdkit {

/// Sweep-and-prune broad phase. Thread safety: const members may run concurrently; insert / remove / move /
/// for_each_pair / rebuild must not run concurrently with anything else on the same object.
template <class S = double> class SweepAndPrune : public detail::SlotBroadPhase<S, SweepAndPrune<S>> {
    using Base = detail::SlotBroadPhase<S, SweepAndPrune<S>>;
    using Base::slots_;

public:
    static constexpr const char* name = "sweep_and_prune";

    /// Statistics of the last for_each_pair.
    struct Stats {
        std::size_t swaps = 0;          ///< element moves of the insertion sort
        bool full_sort = false;         ///< the batch path ran (std::sort)
        std::size_t axis_overlaps = 0;  ///< pairs overlapping on the sweep axis (candidates)
        int axis = 0;                   ///< the sweep axis
    };

    /// Adds an object; throws cdkit::Error for a NaN/infinite box or min > max.
    ObjectId insert(const BroadBox<S>& b) {
        const ObjectId id = slots_.insert(b);
        if (id >= in_list_.size()) in_list_.resize(id + 1, 0);
        // A removed id that is reused before the next frame still has its entry in the list: keep it.
        if (!in_list_[id]) {
            in_list_[id] = 1;
            list_.push_back({S(0), S(0), S(0), S(0), S(0), S(0), id});
            ++appended_;
        }
        return id;
    }
    /// Removes an object; throws cdkit::Error for an unknown or already removed id. The entry leaves the
    /// sorted list at the next for_each_pair.
    void remove(ObjectId id) {
        slots_.remove(id);
        ++removed_;
    }
    /// Replaces an object's box; throws cdkit::Error for a bad id or box.
    void move(ObjectId id, const BroadBox<S>& b) { slots_.move(id, b); }
    /// Forces the next frame to take the batch path (full sort, sweep axis re-chosen). Use it after
    /// teleporting most objects; the swap budget would also detect it, but later.
    void rebuild() noexcept { force_full_ = true; }
    [[nodiscard]] const Stats& stats() const noexcept { return stats_; }

    /// Calls f(a, b) with a < b once for every overlapping pair of live objects.
    template <class F> void for_each_pair(F&& f) {
        stats_ = {};
        if (removed_ > 0) {
            // Compact: drop entries whose object is gone.
            std::size_t w = 0;
            for (std::size_t r = 0; r < list_.size(); ++r) {
                const ObjectId id = list_[r].id;
                if (slots_.alive(id)) list_[w++] = list_[r];
                else in_list_[id] = 0;
            }
            list_.resize(w);
            removed_ = 0;
        }
        const std::size_t n = list_.size();
        bool full = force_full_ || appended_ * 4 > n;
        if (full) axis_ = pick_axis();
        const int a0 = axis_, a1 = (axis_ + 1) % 3, a2 = (axis_ + 2) % 3;
        for (auto& e : list_) {
            const auto& b = slots_.box(e.id);
            e.lo0 = b.lo[a0]; e.hi0 = b.hi[a0];
            e.lo1 = b.lo[a1]; e.hi1 = b.hi[a1];
            e.lo2 = b.lo[a2]; e.hi2 = b.hi[a2];
        }
        if (!full) full = !insertion_sort();
        if (full) {
            std::sort(list_.begin(), list_.end(), [](const Entry& x, const Entry& y) { return x.lo0 < y.lo0; });
            stats_.full_sort = true;
        }
        force_full_ = false;
        appended_ = 0;
        stats_.axis = axis_;

        const Entry* e = list_.data();
        std::size_t cand = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const Entry& p = e[i];
            for (std::size_t j = i + 1; j < n && e[j].lo0 <= p.hi0; ++j) {
                const Entry& q = e[j];
                ++cand;
                if ((p.lo1 <= q.hi1) & (q.lo1 <= p.hi1) & (p.lo2 <= q.hi2) & (q.lo2 <= p.hi2))
                    p.id < q.id ? f(p.id, q.id) : f(q.id, p.id);
            }
        }
        stats_.axis_overlaps = cand;
    }

private:
    struct Entry {
        S lo0, hi0, lo1, hi1, lo2, hi2;  // sweep axis first
        ObjectId id;
    };

    /// Insertion sort by lo0; gives up (returns false, list still a permutation) past the swap budget.
    bool insertion_sort() noexcept {
        const std::size_t n = list_.size();
        const std::size_t budget = 8 * n + 256;
        std::size_t swaps = 0;
        Entry* e = list_.data();
        for (std::size_t i = 1; i < n; ++i) {
            if (!(e[i].lo0 < e[i - 1].lo0)) continue;
            const Entry x = e[i];
            std::size_t j = i;
            do {
                e[j] = e[j - 1];
                --j;
                ++swaps;
            } while (j > 0 && x.lo0 < e[j - 1].lo0);
            e[j] = x;
            if (swaps > budget) {
                stats_.swaps = swaps;
                return false;
            }
        }
        stats_.swaps = swaps;
        return true;
    }
    int pick_axis() const noexcept {
        S sum[3] = {0, 0, 0}, sq[3] = {0, 0, 0};
        for (const auto& e : list_) {
            const auto& b = slots_.box(e.id);
            for (int k = 0; k < 3; ++k) {
                const S c = (b.lo[k] + b.hi[k]) * S(0.5);
                sum[k] += c;
                sq[k] += c * c;
            }
        }
        const S n = std::max<S>(S(1), S(list_.size()));
        int best = 0;
        S best_var = -1;
        for (int k = 0; k < 3; ++k) {
            const S var = sq[k] / n - (sum[k] / n) * (sum[k] / n);
            if (var > best_var) { best_var = var; best = k; }  // NaN-free: boxes are checked on entry
        }
        return best;
    }

    std::vector<Entry> list_;
    std::vector<unsigned char> in_list_;
    std::size_t appended_ = 0, removed_ = 0;
    bool force_full_ = false;
    int axis_ = 0;
    Stats stats_;
};

}  // namespace cdkit
