#pragma once
/// \file Grid of cells no smaller than the objects, rebuilt each frame by sorting the objects by cell.
///
/// Based on the linked-cell method of particle simulation (R. W. Hockney, J. W. Eastwood, "Computer Simulation
/// Using Particles", 1981; M. P. Allen, D. J. Tildesley, "Computer Simulation of Liquids", 1987): with cells at
/// least as large as every object, an object can only overlap objects whose min corner lies in its own cell or
/// in one of the 26 neighbours, and scanning only the "forward" half of that shell finds every pair once. The
/// objects are sorted by cell index every frame (as S. Green, "Particle Simulation using CUDA", NVIDIA 2010,
/// sorts particles), so each cell, and each row of cells along x, is a contiguous run of the sorted array:
/// no hash table and no per-cell lists.
///
/// Each object is stored once, at the cell of its min corner. Cell edge on y and z: 1.01 x the largest extent
/// on that axis (the 1% keeps "overlap => neighbouring cell" true under rounding); on x half of that, so a row
/// run spans from two cells before the object's cell to the cell of its max x and hugs the boxes more closely.
/// Only objects no larger than 4 x the mean extent count; larger ones (and boxes whose extent overflows) go on
/// an oversize list tested against everything. Cell coordinates are taken relative to the smallest min corner
/// and limited per axis (cells grow where the scene is wider), so keys fit in 64 bits for any input. A frame
/// costs one counting sort of n keys plus the candidate tests, the same for coherent and teleporting scenes.

#include "cdkit/broadphase/detail/object_slots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace cdkit {

/// Sorted-cell broad phase. Thread safety: const members may run concurrently; insert / remove / move /
/// for_each_pair must not run concurrently with anything else on the same object.
template <class S = double> class SortedCellGrid : public detail::SlotBroadPhase<S, SortedCellGrid<S>> {
    using Base = detail::SlotBroadPhase<S, SortedCellGrid<S>>;
    using Base::slots_;

public:
    static constexpr const char* name = "sorted_cell_grid";

    /// Statistics of the last for_each_pair.
    struct Stats {
        S cell_size[3] = {0, 0, 0};  ///< cell edge per axis
        std::size_t cells[3] = {0, 0, 0};  ///< cells per axis spanned by the min corners
        std::size_t oversized = 0;   ///< objects kept off the grid
        std::size_t candidates = 0;  ///< box tests done
        bool dense = false;          ///< the cell start table was used (at most 4 cells per object)
    };

    [[nodiscard]] const Stats& stats() const noexcept { return stats_; }

    /// Calls f(a, b) with a < b once for every overlapping pair of live objects.
    template <class F> void for_each_pair(F&& f) {
        stats_ = {};
        choose_cells();
        sort_by_cell();
        if (dense_) scan_pairs<true>(f);
        else scan_pairs<false>(f);
        // Oversized objects against everything (each oversized pair once).
        std::size_t cand = 0;
        for (std::size_t bi = 0; bi < big_.size(); ++bi) {
            const BroadBox<S>& a = slots_.box(big_[bi]);
            const Item q{{a.lo.x(), a.lo.y(), a.lo.z()}, {a.hi.x(), a.hi.y(), a.hi.z()}, big_[bi], 0, 0};
            for (std::size_t j = 0; j < grid_.size(); ++j) {
                const Item& it = items_[j];
                ++cand;
                if (overlaps(q, it)) q.id < it.id ? f(q.id, it.id) : f(it.id, q.id);
            }
            for (std::size_t bj = bi + 1; bj < big_.size(); ++bj) {
                ++cand;
                if (overlap(a, slots_.box(big_[bj]))) big_[bi] < big_[bj] ? f(big_[bi], big_[bj]) : f(big_[bj], big_[bi]);
            }
        }
        stats_.candidates += cand;
    }

private:
    /// An object on the grid in cell order: its box, id, flags and cell key (64 bytes at double precision).
    struct Item {
        S lo[3], hi[3];
        ObjectId id;
        // bits 0-1: cells along x after the own one that the box reaches (0..kSplitX); bit 2 / 3: reaches the
        // next cell on y / z; bits 4-5: min(ix, kSplitX); bit 6: iy > 0.
        std::uint32_t flags;
        std::uint64_t key;    // (iz * ny + iy) * nx + ix
    };
    static constexpr std::size_t kPad = 4;
    /// Cells along x are 1/kSplitX of the largest extent, so the runs along x hug the boxes more closely
    /// (20% fewer candidates than cells of the full extent in the P4 Brownian scene) at no cost in runs.
    static constexpr unsigned kSplitX = 2;
    static bool overlaps(const Item& p, const Item& q) noexcept {
        return (p.lo[0] <= q.hi[0]) & (q.lo[0] <= p.hi[0]) & (p.lo[1] <= q.hi[1]) & (q.lo[1] <= p.hi[1]) &
               (p.lo[2] <= q.hi[2]) & (q.lo[2] <= p.hi[2]);
    }

    /// The half-shell scan. Besides the own row (rest of the own cell, then the cells along x that the box
    /// reaches), four forward rows (dy, dz) = (-1,1), (0,1), (1,1), (1,0), each the run of keys
    /// [key(ix - kSplitX, iy+dy, iz+dz), key(cell of hi.x, iy+dy, iz+dz)]; rows the box cannot reach on y or
    /// z are skipped. Each pair is found once, by the object earlier in cell order. Dense grids look the runs up in the cell
    /// start table; sparse ones find their starts with one forward-moving pointer per row (a row's first key
    /// only grows with the key of the scanning object). Candidates are tested without branches into a
    /// buffer of hits, which keeps the mispredicted branches to about one per run.
    template <bool Dense, class F> void scan_pairs(F& f) {
        const std::size_t n = grid_.size();
        const std::uint64_t nx = nc_[0], nxy = nc_[0] * nc_[1];
        constexpr int row_dy[4] = {-1, 0, 1, 1}, row_dz[4] = {1, 1, 1, 0};
        std::size_t ptr[4] = {0, 0, 0, 0};
        std::size_t cand = 0;
        const Item* it = items_.data();
        const std::uint32_t* cs = cell_start_.data();
        hits_.resize(n + kPad);
        std::uint32_t* hits = hits_.data();
        // Runs are short (about 1.5 objects per cell), so they are tested in blocks of four with the tail
        // masked: one or two iterations per run instead of a loop exit that mispredicts. items_ carries
        // kPad sentinels (never overlapping) so a block may read past the last item.
        auto run = [&](const Item& a, std::size_t j, std::size_t end) {
            std::size_t m = 0;
            for (; j < end; j += kPad)
                for (std::size_t u = 0; u < kPad; ++u) {
                    hits[m] = std::uint32_t(j + u);
                    m += overlaps(a, it[j + u]) & (j + u < end);
                }
            for (std::size_t h = 0; h < m; ++h) {
                const ObjectId ib = it[hits[h]].id;
                a.id < ib ? f(a.id, ib) : f(ib, a.id);
            }
        };
        for (std::size_t i = 0; i < n; ++i) {
            const Item& a = it[i];
            const std::uint64_t k = a.key;
            const unsigned fl = a.flags;
            const std::uint64_t reach_x = fl & 3u;  // cells along x after the own cell that the box reaches
            std::size_t own_end;
            if constexpr (Dense) own_end = cs[k + reach_x + 1];
            else for (own_end = i + 1; own_end < n && it[own_end].key <= k + reach_x;) ++own_end;
            cand += own_end - (i + 1);
            run(a, i + 1, own_end);
            for (int r = 0; r < 4; ++r) {
                if (row_dz[r] == 1 && !(fl & 8u)) continue;    // box does not reach the next z cell
                if (row_dy[r] == 1 && !(fl & 4u)) continue;    // ... nor the next y cell
                if (row_dy[r] == -1 && !(fl & 64u)) continue;  // no row below y = 0
                const std::uint64_t base = k + std::uint64_t(row_dz[r]) * nxy + std::uint64_t(std::int64_t(row_dy[r])) * nx;
                const std::uint64_t first = base - ((fl >> 4) & 3u);  // cell ix - kSplitX, or the row start
                std::size_t b, e;
                if constexpr (Dense) {
                    b = cs[first], e = cs[base + reach_x + 1];
                } else {
                    std::size_t& p = ptr[r];
                    while (p < n && it[p].key < first) ++p;
                    for (b = e = p; e < n && it[e].key <= base + reach_x;) ++e;
                }
                cand += e - b;
                run(a, b, e);
            }
        }
        stats_.candidates = cand;
    }

    /// Cell edges, origin and counts of this frame; fills big_ with the objects kept off the grid.
    void choose_cells() {
        const std::size_t cap = slots_.capacity();
        S mean[3] = {0, 0, 0};
        std::size_t live = 0;
        for (ObjectId id = 0; id < cap; ++id)
            if (slots_.alive(id)) {
                const auto& b = slots_.box(id);
                for (int a = 0; a < 3; ++a) mean[a] += b.hi[a] - b.lo[a];  // may overflow to inf: handled below
                ++live;
            }
        S limit[3], ext[3] = {0, 0, 0};
        for (int a = 0; a < 3; ++a) {
            limit[a] = live ? S(4) * (mean[a] / S(live)) : S(0);
            org_[a] = std::numeric_limits<S>::infinity();
        }
        S top[3] = {-std::numeric_limits<S>::infinity(), -std::numeric_limits<S>::infinity(),
                    -std::numeric_limits<S>::infinity()};
        big_.clear();
        grid_.clear();
        for (ObjectId id = 0; id < cap; ++id) {
            if (!slots_.alive(id)) continue;
            const auto& b = slots_.box(id);
            const S e[3] = {b.hi.x() - b.lo.x(), b.hi.y() - b.lo.y(), b.hi.z() - b.lo.z()};
            bool regular = true;
            for (int a = 0; a < 3; ++a) regular &= std::isfinite(e[a]) && !(e[a] > limit[a]);
            if (!regular) { big_.push_back(id); continue; }
            grid_.push_back(id);
            for (int a = 0; a < 3; ++a) {
                ext[a] = std::max(ext[a], e[a]);
                org_[a] = std::min(org_[a], b.lo[a]);
                top[a] = std::max(top[a], b.lo[a]);
            }
        }
        // Per-axis cell count limit: keeps the rounding of (x - origin) / cell far below the 1% margin.
        constexpr S max_cells = sizeof(S) >= 8 ? S(1 << 20) : S(1 << 12);
        for (int a = 0; a < 3; ++a) {
            const S range = grid_.empty() ? S(0) : top[a] - org_[a];
            S c = std::max(S(1.01) * ext[a] / (a == 0 ? S(kSplitX) : S(1)), range / (max_cells - S(2)));
            if (!(c > S(0))) c = S(1);  // all points on one coordinate: one cell
            S inv = S(1) / c;
            // An infinite range (or a subnormal cell) puts everything in cell 0: exact, just not fast.
            if (!std::isfinite(c) || !std::isfinite(inv)) c = std::numeric_limits<S>::infinity(), inv = S(0);
            inv_[a] = inv;
            nc_[a] = grid_.empty() ? 1 : coord(top[a], a, max_cells - S(1)) + 1;
            stats_.cell_size[a] = c;
            stats_.cells[a] = std::size_t(nc_[a]);
        }
        stats_.oversized = big_.size();
    }
    /// Cell coordinate of x on axis a, in [0, last]; monotone in x (NaN from inf * 0 goes to 0).
    std::uint64_t coord(S x, int a, S last) const noexcept {
        const S t = std::min(std::max(S(0), (x - org_[a]) * inv_[a]), last);  // max(0, NaN) = 0
        return std::uint64_t(t);  // truncation = floor for t >= 0
    }
    /// Keys of the grid objects, then the objects in key order (stable, so by id within a cell). Dense grids
    /// (at most 4 cells per object) use one counting sort over the cells, which also gives the cell start
    /// table; sparse ones an LSD radix sort of the keys and a gather.
    void sort_by_cell() {
        const std::size_t n = grid_.size();
        recs_.resize(n);
        const S last[3] = {S(nc_[0] - 1), S(nc_[1] - 1), S(nc_[2] - 1)};
        for (std::size_t i = 0; i < n; ++i) {
            const auto& b = slots_.box(grid_[i]);
            std::uint64_t c[3];
            for (int a = 0; a < 3; ++a) c[a] = coord(b.lo[a], a, last[a]);
            const unsigned fl = unsigned(coord(b.hi[0], 0, last[0]) - c[0]) |
                                unsigned(coord(b.hi[1], 1, last[1]) > c[1]) << 2 |
                                unsigned(coord(b.hi[2], 2, last[2]) > c[2]) << 3 |
                                unsigned(std::min<std::uint64_t>(c[0], kSplitX)) << 4 | unsigned(c[1] > 0) << 6;
            recs_[i] = {(c[2] * nc_[1] + c[1]) * nc_[0] + c[0], std::uint32_t(i), fl};
        }
        const std::uint64_t cells = nc_[0] * nc_[1] * nc_[2];
        dense_ = cells <= 4 * std::uint64_t(n) + 64;
        stats_.dense = dense_;
        // kPad sentinels after the last item: +inf min and -inf max overlap nothing.
        constexpr S inf = std::numeric_limits<S>::infinity();
        items_.resize(n + kPad);
        std::fill(items_.begin() + std::ptrdiff_t(n), items_.end(), Item{{inf, inf, inf}, {-inf, -inf, -inf}, 0, 0, ~std::uint64_t(0)});
        auto item = [&](const Rec& r) {
            const ObjectId id = grid_[r.obj];
            const auto& b = slots_.box(id);
            return Item{{b.lo.x(), b.lo.y(), b.lo.z()}, {b.hi.x(), b.hi.y(), b.hi.z()}, id, r.flags, r.key};
        };
        if (dense_) {
            // Counting sort with the table shifted by one: the scatter advances entry key + 1 from the start
            // of cell key to its end, which leaves entry c holding the start of cell c (entry 0 stays 0).
            cell_start_.assign(std::size_t(cells) + 2, 0);
            for (const Rec& r : recs_) ++cell_start_[r.key + 2];
            for (std::size_t c = 1; c <= cells; ++c) cell_start_[c + 1] += cell_start_[c];
            for (const Rec& r : recs_) items_[cell_start_[r.key + 1]++] = item(r);
            return;
        }
        int bits = 1;
        while (bits < 64 && ((cells - 1) >> bits)) ++bits;
        const int passes = (bits + 11) / 12;  // digits of <= 12 bits: the histogram stays in L1
        const int digit = (bits + passes - 1) / passes;
        tmp_.resize(n);
        for (int p = 0; p < passes; ++p) {
            radix_pass(recs_, tmp_, p * digit, digit);
            recs_.swap(tmp_);
        }
        for (std::size_t i = 0; i < n; ++i) items_[i] = item(recs_[i]);
    }
    struct Rec {
        std::uint64_t key;
        std::uint32_t obj;    // index into grid_
        std::uint32_t flags;  // as Item::flags
    };
    void radix_pass(const std::vector<Rec>& src, std::vector<Rec>& dst, int shift, int nbits) {
        const std::uint64_t mask = (std::uint64_t(1) << nbits) - 1;
        count_.assign(std::size_t(mask) + 2, 0);
        for (const Rec& r : src) ++count_[((r.key >> shift) & mask) + 1];
        for (std::size_t d = 0; d + 1 < count_.size(); ++d) count_[d + 1] += count_[d];
        for (const Rec& r : src) dst[count_[(r.key >> shift) & mask]++] = r;
    }

    S org_[3] = {0, 0, 0}, inv_[3] = {1, 1, 1};
    std::uint64_t nc_[3] = {1, 1, 1};
    std::vector<ObjectId> grid_, big_;
    std::vector<Rec> recs_, tmp_;
    std::vector<std::uint32_t> count_, cell_start_, hits_;
    std::vector<Item> items_;
    bool dense_ = false;
    Stats stats_;
};

}  // namespace cdkit
