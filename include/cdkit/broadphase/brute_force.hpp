#pragma once
/// \file The reference broad phase: every pair of live objects is tested, O(n^2) per frame. It is the oracle
/// the other methods are checked against, and the fastest choice for a few dozen objects.

#include "cdkit/broadphase/detail/object_slots.hpp"

#include <vector>

namespace cdkit {

/// All-pairs broad phase. Thread safety: const members may run concurrently; insert / remove / move /
/// for_each_pair must not run concurrently with anything else on the same object.
template <class S = double> class BruteForceBroadPhase : public detail::SlotBroadPhase<S, BruteForceBroadPhase<S>> {
    using Base = detail::SlotBroadPhase<S, BruteForceBroadPhase<S>>;
    using Base::slots_;

public:
    static constexpr const char* name = "brute_force";

    /// Calls f(a, b) with a < b once for every overlapping pair of live objects.
    template <class F> void for_each_pair(F&& f) {
        flat_.clear();
        for (ObjectId id = 0; id < slots_.capacity(); ++id)
            if (slots_.alive(id)) {
                const auto& b = slots_.box(id);
                flat_.push_back({{b.lo.x(), b.lo.y(), b.lo.z()}, {b.hi.x(), b.hi.y(), b.hi.z()}, id});
            }
        const std::size_t n = flat_.size();
        for (std::size_t i = 0; i < n; ++i) {
            const Flat& p = flat_[i];
            for (std::size_t j = i + 1; j < n; ++j) {
                const Flat& q = flat_[j];
                // Non-short-circuit '&' keeps the inner loop branch-free; the compiler vectorises it.
                const bool hit = (p.lo[0] <= q.hi[0]) & (q.lo[0] <= p.hi[0]) & (p.lo[1] <= q.hi[1]) &
                                 (q.lo[1] <= p.hi[1]) & (p.lo[2] <= q.hi[2]) & (q.lo[2] <= p.hi[2]);
                if (hit) f(p.id, q.id);  // ids ascend with the index: p.id < q.id
            }
        }
    }

private:
    struct Flat {
        S lo[3], hi[3];
        ObjectId id;
    };
    std::vector<Flat> flat_;
};

}  // namespace cdkit
