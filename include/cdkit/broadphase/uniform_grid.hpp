#pragma once
/// \file Uniform grid as a spatial hash.
///
/// Based on: M. Teschner, B. Heidelberger, M. Müller, D. Pomeranets, M. Gross, "Optimized Spatial Hashing for
/// Collision Detection of Deformable Objects", VMV 2003: an unbounded grid whose cells live in a hash table
/// (hash of the integer cell coordinates with three large primes), each object registered in every cell its
/// box touches. Cell size: the average object diameter (largest box edge) unless the user sets one.
///
/// The table is rebuilt every frame by a radix sort on the bucket index, O(n) and the same cost for coherent
/// and teleporting scenes. A pair is reported only in the cell that holds the min corner of the two boxes'
/// intersection, so each pair appears once without a hash set of reported pairs (both boxes touch that cell,
/// because floor() is monotone). Objects that would touch more than `max_cells_per_object` cells (huge
/// boxes) are kept off the grid and tested against everything, which bounds memory for any input.

#include "cdkit/broadphase/detail/object_slots.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace cdkit {

/// Spatial-hash broad phase. Thread safety: const members may run concurrently; insert / remove / move /
/// for_each_pair / set_cell_size must not run concurrently with anything else on the same object.
template <class S = double> class UniformGrid : public detail::SlotBroadPhase<S, UniformGrid<S>> {
    using Base = detail::SlotBroadPhase<S, UniformGrid<S>>;
    using Base::slots_;

public:
    static constexpr const char* name = "uniform_grid";

    struct Stats {
        S cell_size = 0;              ///< cell edge used in the last frame
        std::size_t registrations = 0;  ///< (object, cell) entries
        std::size_t oversized = 0;    ///< objects kept off the grid
        std::size_t candidates = 0;   ///< box tests done
    };

    /// cell_size <= 0 (default): automatic, the average largest box edge, recomputed every frame.
    explicit UniformGrid(S cell_size = S(0), std::size_t max_cells_per_object = 64)
        : user_cell_(cell_size), max_cells_(std::max<std::size_t>(1, max_cells_per_object)) {
        if (!(cell_size <= S(0)) && !std::isfinite(cell_size))
            throw Error("<broadphase>", "uniform grid", "cell size must be finite");
    }

    /// Sets the cell edge; <= 0 returns to the automatic size. Throws cdkit::Error for NaN/infinity.
    void set_cell_size(S c) {
        if (!(c <= S(0)) && !std::isfinite(c)) throw Error("<broadphase>", "uniform grid", "cell size must be finite");
        user_cell_ = c;
    }
    [[nodiscard]] const Stats& stats() const noexcept { return stats_; }

    /// Calls f(a, b) with a < b once for every overlapping pair of live objects.
    template <class F> void for_each_pair(F&& f) {
        stats_ = {};
        objs_.clear();
        for (ObjectId id = 0; id < slots_.capacity(); ++id)
            if (slots_.alive(id)) {
                const auto& b = slots_.box(id);
                objs_.push_back({{b.lo.x(), b.lo.y(), b.lo.z()}, {b.hi.x(), b.hi.y(), b.hi.z()}, id});
            }
        const S cell = cell_size_for_frame();
        stats_.cell_size = cell;
        const S inv = S(1) / cell;

        // Register objects in cells.
        cells_.clear();
        big_.clear();
        for (std::uint32_t k = 0; k < objs_.size(); ++k) {
            const Obj& o = objs_[k];
            int lo[3], hi[3];
            std::size_t count = 1;
            for (int a = 0; a < 3; ++a) {
                lo[a] = coord(o.lo[a], inv);
                hi[a] = coord(o.hi[a], inv);
                count *= std::size_t(std::int64_t(hi[a]) - lo[a] + 1);
                if (count > max_cells_) break;
            }
            if (count > max_cells_) { big_.push_back(k); continue; }
            for (int x = lo[0]; x <= hi[0]; ++x)
                for (int y = lo[1]; y <= hi[1]; ++y)
                    for (int z = lo[2]; z <= hi[2]; ++z) cells_.push_back({x, y, z, k, 0});
        }
        stats_.registrations = cells_.size();
        stats_.oversized = big_.size();

        // Group the registrations by hash bucket (the hash table, rebuilt in O(m)): a two-pass LSD radix sort
        // on the bucket index. Each pass counts at most 2^13 digits (in L1) and scatters into that many
        // sequential streams; one counting sort over all 2m buckets would miss the cache on every counter
        // and every store at 100k objects.
        std::size_t buckets = 16;
        int bits = 4;
        while (buckets < 2 * cells_.size()) buckets *= 2, ++bits;
        for (auto& c : cells_) c.key = std::uint32_t(bucket(c, buckets));
        radix_pass(cells_, sorted_, 0, bits / 2);
        radix_pass(sorted_, cells_, bits / 2, bits - bits / 2);  // cells_ is now sorted by key (stable)
        // The boxes in registration order: one random read per registration here, then the pair loops below
        // read consecutive entries instead of a random object per candidate.
        const std::size_t m = cells_.size();
        boxes_.resize(m);
        for (std::size_t i = 0; i < m; ++i) boxes_[i] = objs_[cells_[i].obj];

        std::size_t cand = 0;
        for (std::size_t s = 0; s < m;) {
            std::size_t e = s + 1;
            while (e < m && cells_[e].key == cells_[s].key) ++e;
            for (std::size_t i = s; i < e; ++i) {
                const Cell& ci = cells_[i];
                const Obj& p = boxes_[i];
                for (std::size_t j = i + 1; j < e; ++j) {
                    const Cell& cj = cells_[j];
                    if ((ci.x != cj.x) | (ci.y != cj.y) | (ci.z != cj.z)) continue;  // hash collision
                    const Obj& q = boxes_[j];
                    ++cand;
                    if (!overlaps(p, q)) continue;
                    // Report only in the cell of the intersection's min corner.
                    if (coord(std::max(p.lo[0], q.lo[0]), inv) != ci.x || coord(std::max(p.lo[1], q.lo[1]), inv) != ci.y ||
                        coord(std::max(p.lo[2], q.lo[2]), inv) != ci.z)
                        continue;
                    p.id < q.id ? f(p.id, q.id) : f(q.id, p.id);
                }
            }
            s = e;
        }
        // Oversized objects against everything (each big-big pair once).
        if (!big_.empty()) {
            is_big_.assign(objs_.size(), 0);
            for (auto k : big_) is_big_[k] = 1;
            for (std::size_t bi = 0; bi < big_.size(); ++bi) {
                const Obj& p = objs_[big_[bi]];
                for (std::uint32_t k = 0; k < objs_.size(); ++k) {
                    if (is_big_[k] && k <= big_[bi]) continue;
                    const Obj& q = objs_[k];
                    ++cand;
                    if (overlaps(p, q)) p.id < q.id ? f(p.id, q.id) : f(q.id, p.id);
                }
            }
        }
        stats_.candidates = cand;
    }

private:
    struct Obj {
        S lo[3], hi[3];
        ObjectId id;
    };
    struct Cell {
        int x, y, z;
        std::uint32_t obj;  // index into objs_
        std::uint32_t key;  // hash bucket
    };
    /// One stable counting-sort pass of src into dst by the digit (key >> shift) & (2^nbits - 1).
    void radix_pass(const std::vector<Cell>& src, std::vector<Cell>& dst, int shift, int nbits) {
        const std::uint32_t mask = (std::uint32_t(1) << nbits) - 1;
        count_.assign(std::size_t(mask) + 2, 0);
        for (const Cell& c : src) ++count_[((c.key >> shift) & mask) + 1];
        for (std::size_t d = 0; d + 1 < count_.size(); ++d) count_[d + 1] += count_[d];
        dst.resize(src.size());
        for (const Cell& c : src) dst[count_[(c.key >> shift) & mask]++] = c;
    }
    static bool overlaps(const Obj& p, const Obj& q) noexcept {
        return (p.lo[0] <= q.hi[0]) & (q.lo[0] <= p.hi[0]) & (p.lo[1] <= q.hi[1]) & (q.lo[1] <= p.hi[1]) &
               (p.lo[2] <= q.hi[2]) & (q.lo[2] <= p.hi[2]);
    }
    /// Cell coordinate, clamped so far-away boxes share a border cell instead of overflowing an int; the
    /// clamp is monotone, which is all the once-per-pair rule needs.
    static int coord(S x, S inv) noexcept {
        constexpr S lim = S(1 << 29);
        const S c = std::floor(x * inv);
        return static_cast<int>(std::clamp(c, -lim, lim));
    }
    static std::size_t bucket(const Cell& c, std::size_t buckets) noexcept {
        const std::uint32_t h = (std::uint32_t(c.x) * 73856093u) ^ (std::uint32_t(c.y) * 19349663u) ^
                                (std::uint32_t(c.z) * 83492791u);
        return h & (buckets - 1);
    }
    S cell_size_for_frame() const noexcept {
        if (user_cell_ > S(0)) return user_cell_;
        // Rule of thumb: cell edge = average object diameter (largest edge of its box).
        S sum = 0;
        std::size_t n = 0;
        for (const auto& o : objs_) {
            const S d = std::max({o.hi[0] - o.lo[0], o.hi[1] - o.lo[1], o.hi[2] - o.lo[2]});
            if (std::isfinite(d)) { sum += d; ++n; }  // hi - lo can overflow for huge boxes
        }
        const S c = n ? sum / S(n) : S(0);
        return (c > S(0) && std::isfinite(c) && S(1) / c > S(0) && std::isfinite(S(1) / c)) ? c : S(1);
    }

    S user_cell_;
    std::size_t max_cells_;
    std::vector<Obj> objs_;
    std::vector<Obj> boxes_;  // objs_[sorted_[i].obj] for every registration i
    std::vector<Cell> cells_, sorted_;
    std::vector<std::uint32_t> count_, big_;
    std::vector<unsigned char> is_big_;
    Stats stats_;
};

}  // namespace cdkit
