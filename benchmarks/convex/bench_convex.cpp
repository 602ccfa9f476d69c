// P3 convex pairs (BENCHMARKS.md): cdkit GJK (boolean, distance) and EPA against libccd (GJK, MPR,
// GJK+EPA penetration) and FCL 0.7's two solvers (GJKSolver_indep, GJKSolver_libccd: boolean, distance,
// penetration; peer_fcl.cpp) on the same shapes and poses, in one process, fixed seeds.
// Usage: cdkit_bench_convex [configs_per_cell=100] [check_cases=1000000] [csv_path|-] [families] [real_csv_path]
//                           [--p3-csv PATH] [--off LIST]
// --p3-csv: the fair boolean table of issue 37 (results/p3.csv, provenance first): per cell the booleans of cdkit by
// default, with each pre-test off (GjkSettings: bounding_ball_test, containment_test, candidate_axes,
// momentum_iterations) and with all of them off (plain GJK); of libccd's GJK plain, with cdkit's hinted hull
// support (the hint slot cdkit's GJK keeps) and with that and cdkit's own bounding-ball pre-test in front
// (libccd + ball); the share of the cell the ball pre-test decides; ratios. --off: which pre-test-off rows run,
// a comma subset of balls,containment,axes,momentum,all (plain GJK), or none (default: all five). Every boolean
// is timed on the same pose in turn, the fastest of 3 interleaved batches. The docs' table:
//   cdkit_bench_convex 100 0 /tmp/convex.csv --p3-csv /tmp/p3.csv   (then copy /tmp/p3.csv to results/)
// families: comma-separated subset of ellipsoid,box,capsule,cylinder,cone,hull100,hull1000,real (default all); the
// other families still draw their shapes and poses, so a measured family gets the configurations of a full run.
// Quick A/B run of the slow boolean cells: cdkit_bench_convex 100 0 - box,cone,cylinder,hull100,hull1000
// With csv_path, also writes one row per (family, class, method): median and p99 ns, mean iterations, maximum
// error and the fraction of configurations in error (booleans: wrong answers; distances and depths: relative
// error > 1e-9), for plot_convex.py.
// `real` (issue 39): hulls of the bundled and fetched meshes (data/, data/dragon/ from scripts/fetch-data; pairs
// whose files are missing are skipped) and, measured the same way for comparison, pairs of hull100 / hull1000
// clouds; configs_per_cell poses per gap (+0.5, +1e-3, −1e-3), interleaved, fastest of 3 batches ≥ 200 µs,
// with work counters (iterations, support calls per query, ns per support call). Its rows go to real_csv_path.
// The table: cdkit_bench_convex 60 0 - real results/p3_real_hulls.csv
// Prints per (shape family, distance class): median / p99 thread-CPU time per call (batch_timer.hpp), mean
// iterations, the error against a long-double reference (cdkit's own GJK/EPA instantiated in long double with
// tight tolerances) and the share of booleans decided by the bounding-ball pre-test, then the checked counter
// (checked_counter.hpp; check_cases of them, 0 skips it): seeded hull and curved pairs whose answers are judged by
// CGAL's exact polytope distance and the MPFR curved referee, non-zero exit on a wrong answer.
// This file holds the command line and the output; the pieces: p3_cells.hpp (the cells: draws, placements, timed
// queries, errors), fair_table.hpp (--p3-csv), real_hulls.hpp (`real`), checked_counter.hpp (the counter).
#include "../provenance.hpp"
#include "checked_counter.hpp"
#include "fair_table.hpp"
#include "p3_cells.hpp"
#include "real_hulls.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

using namespace cdkit;
using namespace cdbench::p3;
namespace real_hulls = cdbench::real_hulls;

int main(int argc_all, char** argv_all) {
    // Flags (anywhere): --p3-csv PATH (the fair boolean table, with provenance: results/p3.csv), --off LIST (the
    // pre-test-off rows to time: a comma subset of balls,containment,axes,momentum,all, or none; default all of
    // them). The other arguments are the positional ones of the usage line.
    const char* p3_csv = nullptr;
    std::vector<char*> positional{argv_all[0]};
    for (int i = 1; i < argc_all; ++i) {
        const std::string arg = argv_all[i];
        if (arg == "--p3-csv" && i + 1 < argc_all) {
            p3_csv = argv_all[++i];
        } else if (arg == "--off" && i + 1 < argc_all) {
            const std::string list = "," + std::string(argv_all[++i]) + ",";
            for (int k = 0; k < off_count; ++k)
                g_off_enabled[k] = list.find("," + std::string(off_names[k]) + ",") != std::string::npos;
        } else {
            positional.push_back(argv_all[i]);
        }
    }
    const int argc = int(positional.size());
    char** argv = positional.data();
    int configs = argc > 1 ? std::atoi(argv[1]) : 100;
    long checks = argc > 2 ? std::atol(argv[2]) : 1000000;
    const char* csv_path = argc > 3 && std::string(argv[3]) != "-" ? argv[3] : nullptr;
    const std::string families = argc > 4 ? "," + std::string(argv[4]) + "," : std::string();
    auto wanted = [&](const char* f) { return families.empty() || families.find("," + std::string(f) + ",") != std::string::npos; };
    std::mt19937_64 rng(20261122);
    std::vector<Row> rows;
    std::uniform_real_distribution<double> u(0.5, 1.0);
    auto ell = [&](std::mt19937_64& r) {
        std::normal_distribution<double> g(0.1, 0.025);
        Vec3<double> rad(std::abs(g(r)) + 0.01, std::abs(g(r)) + 0.01, std::abs(g(r)) + 0.01);
        return std::pair{Ellipsoid<double>(rad), Ellipsoid<LD>(rad.cast<LD>())};
    };
    auto box = [&](std::mt19937_64& r) {
        Vec3<double> h(0.1 * u(r), 0.1 * u(r), 0.1 * u(r));
        return std::pair{Box<double>(h), Box<LD>(h.cast<LD>())};
    };
    auto cap = [&](std::mt19937_64& r) {
        double a = 0.05 * u(r), b = 0.1 * u(r);
        return std::pair{Capsule<double>(a, b), Capsule<LD>(a, b)};
    };
    auto cyl = [&](std::mt19937_64& r) {
        double a = 0.1 * u(r), b = 0.1 * u(r);
        return std::pair{Cylinder<double>(a, b), Cylinder<LD>(a, b)};
    };
    auto cone = [&](std::mt19937_64& r) {
        double a = 0.1 * u(r), b = 0.1 * u(r);
        return std::pair{Cone<double>(a, b), Cone<LD>(a, b)};
    };
    auto hull = [&](int n) {
        return [n](std::mt19937_64& r) {
            auto p = cloud(r, n, 0.1);
            return std::pair{ConvexPolyhedron<double>(p), ConvexPolyhedron<LD>(castv<Vec3<LD>>(p))};
        };
    };
    run_family("ellipsoid", ell, 0.1, configs, rows, rng, wanted("ellipsoid"));
    run_family("box", box, 0.1, configs, rows, rng, wanted("box"));
    run_family("capsule", cap, 0.1, configs, rows, rng, wanted("capsule"));
    run_family("cylinder", cyl, 0.1, configs, rows, rng, wanted("cylinder"));
    run_family("cone", cone, 0.1, configs, rows, rng, wanted("cone"));
    run_family("hull100", hull(100), 0.1, configs, rows, rng, wanted("hull100"));
    run_family("hull1000", hull(1000), 0.1, configs, rows, rng, wanted("hull1000"));
    if (wanted("real")) {
        // Hulls of real meshes, scaled into [-1, 1]³; the data directory next to this source file's repository.
        const std::filesystem::path data = std::filesystem::path(__FILE__).parent_path() / "../../data";
        struct RealPair { const char* name; const char* a; const char* b; };
        const RealPair pairs[] = {{"bunny-teapot", "bunny.obj", "teapot.obj"},
                                  {"dragon48k-armadillo", "dragon/dragon_48k.ply", "armadillo.obj"},
                                  {"dragon203k-bunny", "dragon/dragon_203k.ply", "bunny.obj"},
                                  {"dragon871k-dragon48k", "dragon/dragon_871k.ply", "dragon/dragon_48k.ply"}};
        std::vector<real_hulls::Cell> cells;
        for (const RealPair& p : pairs) {
            if (!std::filesystem::exists(data / p.a) || !std::filesystem::exists(data / p.b)) {
                std::printf("real hulls: %s skipped (run scripts/fetch-data for data/dragon/)\n", p.name);
                continue;
            }
            const ConvexPolyhedron<double> a(real_hulls::scaled_mesh_points((data / p.a).string()));
            const ConvexPolyhedron<double> b(real_hulls::scaled_mesh_points((data / p.b).string()));
            const ConvexPolyhedron<LD> al(castv<Vec3<LD>>(a.vertices())), bl(castv<Vec3<LD>>(b.vertices()));
            real_hulls::measure_pair(p.name, a, al, b, bl, configs, 39, cells);
        }
        // Random-cloud hulls (P3's hull100 / hull1000 clouds), scaled to the same size and measured the same way.
        for (int n : {100, 1000}) {
            std::mt19937_64 r(39 + std::uint64_t(n));
            const auto pa = cloud(r, n, 1.0), pb = cloud(r, n, 1.0);
            const ConvexPolyhedron<double> a(pa), b(pb);
            const ConvexPolyhedron<LD> al(castv<Vec3<LD>>(pa)), bl(castv<Vec3<LD>>(pb));
            real_hulls::measure_pair(n == 100 ? "cloud100-cloud100" : "cloud1000-cloud1000", a, al, b, bl, configs,
                                     39, cells);
        }
        real_hulls::print_cells(cells, "\nP3 hulls of real meshes (scaled into [-1,1]^3) and of random clouds: median ns per "
                                       "boolean query, fastest of 3 interleaved batches >= 200 us per pose");
        if (argc > 5) {
            if (FILE* f = std::fopen(argv[5], "w")) {
                std::fprintf(f, "pair,hull_vertices,gap,method,poses,median_ns,mean_iterations,support_calls,"
                                "ns_per_support,ratio_ccd_gjk,ratio_ccd_mpr,wrong\n");
                for (auto& c : cells)
                    for (auto& m : c.m) {
                        const double n = double(std::max(m.n, 1L));
                        const bool cd = &m == &c.m[0] || &m == &c.m[1];
                        std::fprintf(f, "%s,%zu/%zu,%g,%s,%ld,%.0f,%s,%.1f,%s,%.2f,%.2f,%ld\n", c.pair.c_str(), c.va, c.vb,
                                     c.gap, m.name, m.n, m.median(), cd ? std::to_string(m.iterations / n).substr(0, 4).c_str() : "",
                                     m.support_calls / n, cd ? std::to_string(m.support_ns / n).substr(0, 4).c_str() : "",
                                     c.m[2].median() / m.median(), c.m[3].median() / m.median(), m.wrong);
                    }
                std::fclose(f);
                std::printf("wrote %s\n", argv[5]);
            }
        }
    }

    std::printf("P3 convex pairs: %d configurations per cell, each timed as a batch of >= %d calls and >= 20 us "
                "of thread CPU time (clock cost %.0f ns subtracted); times in ns per call\n",
                configs, reps, bench::thread_clock_overhead_ns());
    std::printf("%-10s %-11s | %-26s | %-26s | %-26s | %-17s | %-17s | %-17s | bool ratio ccdGJK/cd, ccdMPR/cd; pen ratio | balls | EPA bracket\n",
                "family", "class", "cd bool med/p99 it err", "cd dist med/p99 it relerr", "cd EPA med/p99 it relerr",
                "ccd GJK med err", "ccd MPR med err", "ccd pen med relerr");
    for (auto& r : rows) {
        auto cell = [](Stats& s, bool with_it) {
            char buf[96];
            if (s.n == 0) std::snprintf(buf, sizeof buf, "%26s", "-");
            else if (with_it)
                std::snprintf(buf, sizeof buf, "%7.0f/%7.0f %4.1f %.1e", s.pct(0.5), s.pct(0.99), s.it / double(s.n), s.err);
            else std::snprintf(buf, sizeof buf, "%7.0f %.1e", s.pct(0.5), s.err);
            return std::string(buf);
        };
        double cb = r.cd_bool.pct(0.5);
        char bracket[32] = "-";
        if (r.cd_epa_bracket.n) std::snprintf(bracket, sizeof bracket, "%.1e", r.cd_epa_bracket.err);
        std::printf("%-10s %-11s | %s | %s | %s | %17s | %17s | %17s | %5.2f %5.2f %5.2f | %3.0f%% | %s\n", r.family.c_str(),
                    r.cls.c_str(), cell(r.cd_bool, true).c_str(), cell(r.cd_dist, true).c_str(),
                    cell(r.cd_epa, true).c_str(), cell(r.ccd_gjk, false).c_str(), cell(r.ccd_mpr, false).c_str(),
                    cell(r.ccd_pen, false).c_str(), r.ccd_gjk.pct(0.5) / cb, r.ccd_mpr.pct(0.5) / cb,
                    r.cd_epa.n ? r.ccd_pen.pct(0.5) / r.cd_epa.pct(0.5) : 0.0,
                    100.0 * double(r.cd_bool_balls) / double(std::max(r.cd_bool.n, 1L)), bracket);
    }
    std::printf("(err for booleans: max over cells of a wrong answer where |reference| > 1e-6·scale, 1 = some wrong; "
                "balls: share of the cell's configurations the cdkit boolean decided by its bounding-ball pre-test;\n"
                " EPA bracket: the largest (depth - depth_lower)/depth EPA itself reported in the cell, the width of its\n"
                " certified interval, which needs no reference)\n");
    // FCL 0.7 on the same configurations (see peer_fcl.hpp for the code each column runs); ratios are FCL's
    // median over cdkit's median of the same query (boolean: cd GJK boolean; distance: cd GJK distance;
    // penetration: cd EPA).
    std::printf("\nFCL 0.7, same configurations: median ns and error (booleans: wrong fraction; distance, depth: "
                "max relative error); ratio = FCL median / cdkit median\n");
    std::printf("%-10s %-11s | %-17s | %-17s | %-17s | %-17s | %-17s | %-17s | %-35s\n", "family", "class",
                "indep bool", "libccd(MPR) bool", "indep dist", "libccd dist", "indep pen (EPA)", "libccd pen (MPR)",
                "ratio bool i/l  dist i/l  pen i/l");
    for (auto& r : rows) {
        auto cell = [](Stats& s, bool fraction) {
            char buf[64];
            if (s.n == 0) std::snprintf(buf, sizeof buf, "%17s", "-");
            else std::snprintf(buf, sizeof buf, "%7.0f %9.1e", s.pct(0.5),
                               fraction ? double(s.wrong) / double(s.n) : s.err);
            return std::string(buf);
        };
        auto ratio = [](Stats& f, Stats& cd) { return f.n && cd.n ? f.pct(0.5) / cd.pct(0.5) : 0.0; };
        std::printf("%-10s %-11s | %s | %s | %s | %s | %s | %s | %5.2f %5.2f  %5.2f %5.2f  %5.2f %5.2f\n",
                    r.family.c_str(), r.cls.c_str(), cell(r.fcl_indep_bool, true).c_str(),
                    cell(r.fcl_ccd_bool, true).c_str(), cell(r.fcl_indep_dist, false).c_str(),
                    cell(r.fcl_ccd_dist, false).c_str(), cell(r.fcl_indep_pen, false).c_str(),
                    cell(r.fcl_ccd_pen, false).c_str(), ratio(r.fcl_indep_bool, r.cd_bool),
                    ratio(r.fcl_ccd_bool, r.cd_bool), ratio(r.fcl_indep_dist, r.cd_dist),
                    ratio(r.fcl_ccd_dist, r.cd_dist), ratio(r.fcl_indep_pen, r.cd_epa), ratio(r.fcl_ccd_pen, r.cd_epa));
    }
    std::printf("(FCL booleans: box/box runs FCL's boxBoxIntersect (SAT) in both solvers, capsule/capsule distance its "
                "closed form; indep boolean includes FCL's EPA on overlapping pairs)\n");
    print_fair_table(rows);
    if (p3_csv) {
        if (std::FILE* f = std::fopen(p3_csv, "w")) {
            cdbench::write_provenance(f, argc_all, argv_all);
            write_fair_csv(f, rows);
            std::fclose(f);
            std::printf("wrote %s\n", p3_csv);
        } else {
            std::printf("cannot write %s\n", p3_csv);
        }
    }
    if (csv_path) {
        if (FILE* f = std::fopen(csv_path, "w")) {
            std::fprintf(f, "family,class,method,median_ns,p99_ns,mean_iterations,max_error,fraction_in_error,n\n");
            for (auto& r : rows) {
                auto put = [&](const char* method, Stats& st) {
                    if (st.n == 0) return;
                    std::fprintf(f, "%s,%s,%s,%.1f,%.1f,%.3f,%.3e,%.5f,%ld\n", r.family.c_str(), r.cls.c_str(), method,
                                 st.pct(0.5), st.pct(0.99), st.it / double(st.n), st.err,
                                 double(st.wrong) / double(st.n), st.n);
                };
                put("cdkit GJK boolean", r.cd_bool);
                put("cdkit GJK distance", r.cd_dist);
                put("cdkit EPA", r.cd_epa);
                put("cdkit EPA bracket", r.cd_epa_bracket);  // max_error: the largest (depth - depth_lower)/depth
                put("libccd GJK boolean", r.ccd_gjk);
                put("libccd MPR boolean", r.ccd_mpr);
                put("libccd GJK+EPA penetration", r.ccd_pen);
                put("FCL indep GJK boolean", r.fcl_indep_bool);
                put("FCL indep GJK distance", r.fcl_indep_dist);
                put("FCL indep GJK+EPA penetration", r.fcl_indep_pen);
                put("FCL libccd MPR boolean", r.fcl_ccd_bool);
                put("FCL libccd GJK distance", r.fcl_ccd_dist);
                put("FCL libccd MPR penetration", r.fcl_ccd_pen);
            }
            std::fclose(f);
            std::printf("wrote %s\n", csv_path);
        } else {
            std::printf("cannot write %s\n", csv_path);
        }
    }

    // The checked counter (checked_counter.hpp): every class judged by an oracle independent of cdkit's GJK.
    if (checks > 0 && cdbench::run_checked_counter(checks) != 0) return 1;
    return 0;
}
