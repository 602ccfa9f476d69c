#pragma once
// The fair boolean table of issue 37 (cdkit_bench_convex --p3-csv, results/p3.csv): per cell the booleans of
// cdkit by default, with each pre-test off and plain, and of libccd's GJK plain, with cdkit's hinted support and
// with cdkit's bounding-ball pre-test in front; a median row per distance class; ratios. Printed and written as CSV.
#include "p3_cells.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace cdbench::p3 {

/// One cell of the fair boolean table (issue 37): its columns in order, NaN where a variant did not run.
struct FairCell {
    std::string family, cls;
    long configs = 0, cdkit_wrong = 0, libccd_wrong = 0;
    std::vector<double> v;  // the numeric columns of fair_columns, in order
};
constexpr const char* fair_columns[] = {
    "balls_decide", "cdkit_ns", "cdkit_it", "no_balls_ns", "no_containment_ns", "no_axes_ns", "no_momentum_ns",
    "plain_ns", "plain_it", "libccd_gjk_ns", "libccd_hint_ns", "libccd_ball_ns", "libccd_mpr_ns", "default_vs_libccd",
    "default_vs_libccd_ball", "plain_vs_libccd_hint"};
constexpr int fair_n = int(sizeof fair_columns / sizeof fair_columns[0]);

inline FairCell fair_cell(Row& r) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    auto med = [&](Stats& s) { return s.n ? s.pct(0.5) : nan; };
    auto it = [&](Stats& s) { return s.n ? s.it / double(s.n) : nan; };
    FairCell c{r.family, r.cls, r.cd_bool.n, r.cd_bool.wrong, r.ccd_gjk.wrong, {}};
    for (Stats& s : r.cd_bool_off) c.cdkit_wrong += s.wrong;
    const double cd = med(r.cd_bool), plain = med(r.cd_bool_off[off_all]);
    c.v = {double(r.cd_bool_balls) / double(std::max(r.cd_bool.n, 1L)), cd, it(r.cd_bool),
           med(r.cd_bool_off[off_balls]), med(r.cd_bool_off[off_containment]), med(r.cd_bool_off[off_axes]),
           med(r.cd_bool_off[off_momentum]), plain, it(r.cd_bool_off[off_all]), med(r.ccd_gjk), med(r.ccd_gjk_hint),
           med(r.ccd_gjk_ball), med(r.ccd_mpr), med(r.ccd_gjk) / cd, med(r.ccd_gjk_ball) / cd,
           med(r.ccd_gjk_hint) / plain};
    return c;
}

/// The cells and, per distance class, a `median` row: each column's median over the shape families.
inline std::vector<FairCell> fair_cells(std::vector<Row>& rows) {
    std::vector<FairCell> cells;
    for (Row& r : rows) cells.push_back(fair_cell(r));
    for (const char* cls : {"distant", "close", "overlapping"}) {
        FairCell m{"median", cls, 0, 0, 0, std::vector<double>(fair_n, std::numeric_limits<double>::quiet_NaN())};
        for (int j = 0; j < fair_n; ++j) {
            std::vector<double> x;
            for (const FairCell& c : cells)
                if (c.cls == cls && c.family != "median" && !std::isnan(c.v[std::size_t(j)])) x.push_back(c.v[std::size_t(j)]);
            if (x.empty()) continue;
            std::sort(x.begin(), x.end());
            const std::size_t h = x.size() / 2;
            m.v[std::size_t(j)] = x.size() % 2 ? x[h] : (x[h - 1] + x[h]) / 2;
        }
        for (const FairCell& c : cells)
            if (c.cls == cls && c.family != "median") {
                m.configs += c.configs;
                m.cdkit_wrong += c.cdkit_wrong;
                m.libccd_wrong += c.libccd_wrong;
            }
        if (m.configs) cells.push_back(std::move(m));
    }
    return cells;
}

/// A column's value as the CSV and the table print it: ns to 0.1, fractions and ratios to 0.01, "" for NaN.
inline std::string fair_value(int j, double x) {
    if (std::isnan(x)) return "";
    char buf[32];
    const std::string name = fair_columns[j];
    std::snprintf(buf, sizeof buf, name.ends_with("_ns") ? "%.1f" : "%.2f", x);
    return buf;
}

inline void print_fair_table(std::vector<Row>& rows) {
    std::printf("\nFair booleans (issue 37): median ns per call over the cell's configurations, each the fastest of 3 "
                "interleaved batches;\n cdkit by default, with one pre-test off, and plain (all off, no momentum); "
                "libccd GJK plain, with cdkit's hinted support (hint),\n and with that and cdkit's bounding-ball "
                "pre-test (ball); balls = share the ball pre-test decided; ratios: libccd / cdkit\n");
    std::printf("%-10s %-11s %5s | %7s %5s | %7s %7s %7s %7s | %7s %5s | %7s %7s %7s %7s | %7s %7s %7s | wrong\n",
                "family", "class", "balls", "cdkit", "it", "-balls", "-contn", "-axes", "-momnt", "plain", "it",
                "ccdGJK", "hint", "ball", "ccdMPR", "def/GJK", "def/bal", "pln/hnt");
    for (const FairCell& c : fair_cells(rows)) {
        std::printf("%-10s %-11s", c.family.c_str(), c.cls.c_str());
        for (int j = 0; j < fair_n; ++j) {
            const std::string v = fair_value(j, c.v[std::size_t(j)]);
            std::printf(j == 0 ? " %5s" : (j == 1 || j == 3 || j == 7 || j == 9 || j == 13) ? " | %7s" : " %7s",
                        v.empty() ? "-" : v.c_str());
        }
        std::printf(" | %ld %ld\n", c.cdkit_wrong, c.libccd_wrong);
    }
}

inline void write_fair_csv(std::FILE* f, std::vector<Row>& rows) {
    std::fprintf(f, "family,class,configs");
    for (const char* name : fair_columns) std::fprintf(f, ",%s", name);
    std::fprintf(f, ",cdkit_wrong,libccd_wrong\n");
    for (const FairCell& c : fair_cells(rows)) {
        std::fprintf(f, "%s,%s,%ld", c.family.c_str(), c.cls.c_str(), c.configs);
        for (int j = 0; j < fair_n; ++j) std::fprintf(f, ",%s", fair_value(j, c.v[std::size_t(j)]).c_str());
        std::fprintf(f, ",%ld,%ld\n", c.cdkit_wrong, c.libccd_wrong);
    }
}

}  // namespace cdbench::p3
