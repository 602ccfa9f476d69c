/// \file cdkit_bench_accuracy: how often each triangle test disagrees with CGAL's exact kernel on a seeded
/// hard-case corpus (hard_cases.hpp), per family; then mesh-level cases (coincident copies, copies moved by
/// one ulp, mirrored copies touching or one ulp apart) for cdkit collide, FCL's mesh collide and the exact
/// brute force. Prints tables and writes CSV. See docs/robustness.md.
///
/// Usage: cdkit_bench_accuracy [--cases N] [--seed S] [--csv FILE] [--mesh-csv FILE] [--speed-csv FILE]
///        [--no-mesh] [--max-mesh-triangles N]
/// --cases is the total number of triangle-pair cases over all families (default 200000). P6: each method
/// is also timed on one stored sample of the corpus (all families), and time per test is written beside its
/// disagreement rate (--speed-csv, default accuracy_speed.csv) for the time-against-error plot.

#include "../cli_args.hpp"
#include "../provenance.hpp"
#include "hard_cases.hpp"
#include "mesh_factory.hpp"
#include "oracles.hpp"

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/narrowphase/triangle.hpp"
#include "cdkit/query.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

using namespace cdkit;
using namespace cdkit::accuracy;

namespace {

struct Options {
    long long cases = 200000;
    std::uint64_t seed = 20261122;
    std::string csv = "accuracy_triangles.csv";
    std::string mesh_csv = "accuracy_meshes.csv";
    std::string speed_csv = "accuracy_speed.csv";
    bool mesh = true;
    std::size_t max_mesh_triangles = 4000;
    std::string provenance;  ///< comment lines first in each CSV (provenance.hpp)
};

Options parse(int argc, char** argv) {
    Options o;
    for (cdbench::ArgCursor args(argc, argv); args.next();) {
        const std::string a = args.flag();
        if (a == "--cases") o.cases = std::atoll(args.value().c_str());
        else if (a == "--seed") o.seed = std::strtoull(args.value().c_str(), nullptr, 10);
        else if (a == "--csv") o.csv = args.value();
        else if (a == "--mesh-csv") o.mesh_csv = args.value();
        else if (a == "--speed-csv") o.speed_csv = args.value();
        else if (a == "--no-mesh") o.mesh = false;
        else if (a == "--max-mesh-triangles") o.max_mesh_triangles = std::strtoull(args.value().c_str(), nullptr, 10);
        else {
            std::cerr << "usage: cdkit_bench_accuracy [--cases N] [--seed S] [--csv FILE] [--mesh-csv FILE]"
                         " [--speed-csv FILE] [--no-mesh]"
                         " [--max-mesh-triangles N]\n";
            std::exit(a == "--help" || a == "-h" ? 0 : 2);
        }
    }
    o.provenance = cdbench::provenance_lines(argc, argv);
    return o;
}

// ---- triangle pairs ---------------------------------------------------------------------------------

enum Method { exact_double, exact_float, fp_double, fp_float, fcl_double, kMethods };
const char* method_name(int m) {
    static const char* n[] = {"cdkit_exact_double", "cdkit_exact_float", "cdkit_fp_double", "cdkit_fp_float",
                              "fcl_double"};
    return n[m];
}

struct Tally {
    long long cases = 0, hits = 0, hits_float = 0;
    long long wrong[kMethods] = {};
    long long false_pos[kMethods] = {};  // said "intersect" where the exact answer is "no"
};

Tri3 tri3(const std::array<Vec3<double>, 3>& t) { return {t[0], t[1], t[2]}; }
template <class S> Tri3 widen(const std::array<Vec3<S>, 3>& t) {
    return {t[0].template cast<double>(), t[1].template cast<double>(), t[2].template cast<double>()};
}

/// Whether every nonzero coordinate lies in the range [2^-280, 2^280] of the predicates' floating-point
/// stages (cdkit/core/predicates.hpp). The corpus has cases outside it: a ±1 ulp step from a zero
/// coordinate is a subnormal number. cdkit decides those in its wide-integer stage; they are tallied
/// apart, in the row "outside_range*", to show what floating point alone does there.
bool in_range(const Pair& x) {
    for (const Tri* t : {&x.p, &x.q})
        for (const V& v : *t)
            for (int k = 0; k < 3; ++k) {
                const double a = std::abs(v[k]);
                if (a != 0 && (a < 0x1p-280 || a > 0x1p280)) return false;
            }
    return true;
}

void run_case(const Pair& x, Tally& t) {
    const Tri3 p = tri3(x.p), q = tri3(x.q);
    const bool truth = exact_triangles_intersect(p, q);
    // Float methods see the pair rounded to float, and are judged against the exact answer for that input.
    const auto xf = tri::as<float>(x);
    const Tri3 pf = widen(xf.p), qf = widen(xf.q);
    const bool same = pf == p && qf == q;
    const bool truth_f = same ? truth : exact_triangles_intersect(pf, qf);
    ++t.cases;
    t.hits += truth;
    t.hits_float += truth_f;
    bool got[kMethods];
    got[exact_double] = triangles_intersect(p[0], p[1], p[2], q[0], q[1], q[2]);
    got[fp_double] = triangles_intersect(p[0], p[1], p[2], q[0], q[1], q[2], PredicateMode::floating_point);
    got[exact_float] = triangles_intersect(xf.p[0], xf.p[1], xf.p[2], xf.q[0], xf.q[1], xf.q[2]);
    got[fp_float] = triangles_intersect(xf.p[0], xf.p[1], xf.p[2], xf.q[0], xf.q[1], xf.q[2], PredicateMode::floating_point);
    got[fcl_double] = fcl_triangles_intersect(p, q);
    for (int m = 0; m < kMethods; ++m) {
        const bool want = (m == exact_float || m == fp_float) ? truth_f : truth;
        if (got[m] != want) {
            ++t.wrong[m];
            t.false_pos[m] += got[m];
            if (m == exact_double || m == exact_float) {  // the target is zero: print a reproducer
                std::printf("DISAGREEMENT %s exact=%d got=%d\n", method_name(m), int(want), int(got[m]));
                const Tri3& a = m == exact_double ? p : pf;
                const Tri3& b = m == exact_double ? q : qf;
                for (int i = 0; i < 3; ++i)
                    std::printf("  p%d %.17g %.17g %.17g   q%d %.17g %.17g %.17g\n", i, a[i].x(), a[i].y(), a[i].z(), i,
                                b[i].x(), b[i].y(), b[i].z());
            }
        }
    }
}

/// One tally per family, then the out-of-range cases of all families (index kFamilies).
std::vector<Tally> run_triangles(const Options& o) {
    std::vector<Tally> tallies(kFamilies + 1);
    auto run = [&](const Pair& x, Tally& t) { run_case(x, in_range(x) ? t : tallies[kFamilies]); };
    const long long per_family = std::max<long long>(72, o.cases / kFamilies);
    for (int f = 0; f < kFamilies; ++f) {
        Rng rng(o.seed * 1000003ull + std::uint64_t(f));
        Tally& t = tallies[f];
        if (f == static_cast<int>(Family::orders36)) {
            for (long long i = 0; i < per_family; i += 72) {
                const Pair base = orders36_base(rng);
                for (int k = 0; k < 72; ++k) run(reorder(base, k), t);
            }
        } else {
            for (long long i = 0; i < per_family; ++i) run(generate(f, rng), t);
        }
        std::fprintf(stderr, "  %-20s %lld cases done\n", family_name(f).c_str(), t.cases);
    }
    return tallies;
}

void print_triangles(const std::vector<Tally>& tallies, const Options& o) {
    std::printf("\nTriangle pairs: disagreements with CGAL's exact kernel (count, and rate in %%)\n");
    std::printf("%-20s %10s %6s", "family", "cases", "hit%");
    for (int m = 0; m < kMethods; ++m) std::printf(" %22s", method_name(m));
    std::printf("\n");
    Tally all;
    auto row = [&](const std::string& name, const Tally& t) {
        std::printf("%-20s %10lld %6.1f", name.c_str(), t.cases, 100.0 * double(t.hits) / double(std::max(1LL, t.cases)));
        for (int m = 0; m < kMethods; ++m) {
            char cell[64];
            std::snprintf(cell, sizeof cell, "%lld (%.3g%%)", t.wrong[m], 100.0 * double(t.wrong[m]) / double(std::max(1LL, t.cases)));
            std::printf(" %22s", cell);
        }
        std::printf("\n");
    };
    for (int f = 0; f < kFamilies; ++f) {
        const Tally& t = tallies[f];
        row(family_name(f), t);
        all.cases += t.cases;
        all.hits += t.hits;
        all.hits_float += t.hits_float;
        for (int m = 0; m < kMethods; ++m) all.wrong[m] += t.wrong[m], all.false_pos[m] += t.false_pos[m];
    }
    row("ALL (in range)", all);
    row("outside_range*", tallies[kFamilies]);
    std::printf("* a subnormal coordinate (outside the floating-point stages' range: cdkit's wide-integer stage decides),"
                " from any family; not in ALL\n");
    std::ofstream csv(o.csv);
    csv << o.provenance << "family,method,cases,oracle_hits,disagreements,false_positives,false_negatives,rate\n";
    auto csv_rows = [&](const std::string& name, const Tally& t) {
        for (int m = 0; m < kMethods; ++m) {
            const long long hits = (m == exact_float || m == fp_float) ? t.hits_float : t.hits;
            csv << name << ',' << method_name(m) << ',' << t.cases << ',' << hits << ',' << t.wrong[m] << ','
                << t.false_pos[m] << ',' << t.wrong[m] - t.false_pos[m] << ','
                << double(t.wrong[m]) / double(std::max(1LL, t.cases)) << '\n';
        }
    };
    for (int f = 0; f < kFamilies; ++f) csv_rows(family_name(f), tallies[f]);
    csv_rows("ALL", all);
    csv_rows("outside_range", tallies[kFamilies]);
    std::printf("(seed %llu; CSV: %s)\n", static_cast<unsigned long long>(o.seed), o.csv.c_str());
}

// ---- P6: time per test against the disagreement rate --------------------------------------------------

/// Times every method on one sample of the corpus (the same pairs for all, every family, float methods on
/// the float-rounded pairs): nanoseconds per test as the median of 7 passes, each pass the whole sample.
void time_methods(const std::vector<Tally>& tallies, const Options& o) {
    constexpr int kPerFamily = 4000, kPasses = 7;
    std::vector<Tri3> ps, qs;
    std::vector<std::array<Vec3<float>, 3>> pf, qf;
    for (int f = 0; f < kFamilies; ++f) {
        Rng rng(o.seed * 7919ull + std::uint64_t(f));
        for (int i = 0; i < kPerFamily; ++i) {
            const Pair x = f == static_cast<int>(Family::orders36) ? reorder(orders36_base(rng), i % 72) : generate(f, rng);
            const auto xf = tri::as<float>(x);
            ps.push_back(tri3(x.p)), qs.push_back(tri3(x.q)), pf.push_back(xf.p), qf.push_back(xf.q);
        }
    }
    auto test = [&](int m, std::size_t i) {
        const Tri3 &p = ps[i], &q = qs[i];
        const auto &a = pf[i], &b = qf[i];
        switch (m) {
        case exact_double: return triangles_intersect(p[0], p[1], p[2], q[0], q[1], q[2]);
        case fp_double: return triangles_intersect(p[0], p[1], p[2], q[0], q[1], q[2], PredicateMode::floating_point);
        case exact_float: return triangles_intersect(a[0], a[1], a[2], b[0], b[1], b[2]);
        case fp_float: return triangles_intersect(a[0], a[1], a[2], b[0], b[1], b[2], PredicateMode::floating_point);
        default: return fcl_triangles_intersect(p, q);
        }
    };
    Tally all;
    for (const Tally& t : tallies) {
        all.cases += t.cases;
        for (int m = 0; m < kMethods; ++m) all.wrong[m] += t.wrong[m];
    }
    std::printf("\nP6 time against error: %zu sampled pairs, median of %d passes\n", ps.size(), kPasses);
    std::printf("%-22s %10s %16s\n", "method", "ns/test", "disagreement %");
    std::ofstream csv(o.speed_csv);
    csv << o.provenance << "method,ns_per_test,cases,disagreements,rate\n";
    long long sink = 0;
    for (int m = 0; m < kMethods; ++m) {
        std::vector<double> ns;
        for (int pass = 0; pass < kPasses; ++pass) {
            const auto t0 = std::chrono::steady_clock::now();
            for (std::size_t i = 0; i < ps.size(); ++i) sink += test(m, i);
            ns.push_back(std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() /
                         double(ps.size()));
        }
        std::nth_element(ns.begin(), ns.begin() + kPasses / 2, ns.end());
        const double rate = double(all.wrong[m]) / double(std::max(1LL, all.cases));
        std::printf("%-22s %10.1f %16.4g\n", method_name(m), ns[kPasses / 2], 100 * rate);
        csv << method_name(m) << ',' << ns[kPasses / 2] << ',' << all.cases << ',' << all.wrong[m] << ',' << rate << '\n';
    }
    std::printf("(all %lld corpus cases, out-of-range ones included; %lld hits in the timing passes; CSV: %s)\n",
                all.cases, sink, o.speed_csv.c_str());
}

// ---- meshes -----------------------------------------------------------------------------------------

/// A scaled and moved into [1, 3]^3 (this defines A; no later step rounds): no coordinate is zero, so
/// one-ulp moves stay normal numbers, and x -> 2 - x is exact on [1, 3] (Sterbenz).
TriangleMesh<double> normalized(TriangleMesh<double> m) {
    Vec3<double> lo = m.vertices.front(), hi = lo;
    for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double s = 2.0 / (hi - lo).maxCoeff();
    for (auto& v : m.vertices) v = Vec3<double>::Ones() + s * (v - lo);
    for (auto& v : m.vertices) v.x() = std::clamp(v.x(), 1.0, 3.0);
    return m;
}

/// Both meshes in one frame: every method sees the same doubles, and the poses are identity.
struct MeshCase {
    std::string name;
    TriangleMesh<double> a, b;
};

std::vector<MeshCase> mesh_cases(const TriangleMesh<double>& a) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    std::vector<MeshCase> out;
    out.push_back({"coincident", a, a});
    TriangleMesh<double> up = a;
    for (auto& v : up.vertices)
        for (int k = 0; k < 3; ++k) v[k] = std::nextafter(v[k], inf);
    out.push_back({"shifted_1ulp", a, up});
    // Mirrored in the plane x = 1 (exact): the copies touch exactly at A's vertices with x = 1.
    TriangleMesh<double> mirror = a;
    for (auto& v : mirror.vertices) v.x() = 2.0 - v.x();
    for (auto& t : mirror.triangles) std::swap(t[1], t[2]);
    out.push_back({"mirrored_touching", a, mirror});
    TriangleMesh<double> apart = mirror;  // then 1 ulp apart: B's x <= 1 - 2^-53 < 1 <= A's x
    for (auto& v : apart.vertices) v.x() = std::nextafter(v.x(), -inf);
    out.push_back({"mirrored_1ulp_apart", a, apart});
    // Outside the floating-point stages' range (the wide-integer stage decides): mirrored in x = 0, one subnormal apart.
    TriangleMesh<double> a0 = a, sub = a;
    for (auto& v : a0.vertices) v.x() -= 1.0;  // exact on [1, 3]: A moved to x in [0, 2]
    for (auto& v : sub.vertices) v.x() = std::nextafter(-(v.x() - 1.0), -inf);
    for (auto& t : sub.triangles) std::swap(t[1], t[2]);
    out.push_back({"subnormal_apart*", a0, sub});
    return out;
}

template <class BV> PairList cdkit_pairs(const MeshModel<BV>& a, const MeshModel<BV>& b) {
    CollisionRequest req;
    req.mode = ContactMode::all;
    const auto r = collide(a, Transform<typename BV::Scalar>(), b, Transform<typename BV::Scalar>(), req);
    PairList out;
    for (const auto& c : r.contacts) out.emplace_back(c.triangle_a, c.triangle_b);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

struct MeshRow {
    std::string mesh, config, method;
    std::size_t exact = 0, reported = 0, missed = 0, extra = 0;
    bool exact_colliding = false, colliding = false;
    double ms = 0;
};

MeshRow compare(const std::string& mesh, const std::string& config, const std::string& method, const PairList& exact,
                const PairList& got, double ms) {
    MeshRow r{mesh, config, method};
    r.exact = exact.size();
    r.reported = got.size();
    PairList d;
    std::set_difference(exact.begin(), exact.end(), got.begin(), got.end(), std::back_inserter(d));
    r.missed = d.size();
    d.clear();
    std::set_difference(got.begin(), got.end(), exact.begin(), exact.end(), std::back_inserter(d));
    r.extra = d.size();
    r.exact_colliding = !exact.empty();
    r.colliding = !got.empty();
    r.ms = ms;
    return r;
}

void run_meshes(const Options& o) {
    std::vector<TriangleMesh<double>> meshes;
    meshes.push_back(test::uv_sphere<double>(1.0, 16, 32));
    meshes.back().source = "uv_sphere_16x32";
    for (const char* f : {"teapot.obj", "bunny.obj"}) {
        try {
            TriangleMesh<double> m = load_mesh(std::string(CDKIT_BENCH_SOURCE_DIR) + "/data/" + f);
            m.source = f;
            if (m.triangles.size() <= o.max_mesh_triangles) meshes.push_back(std::move(m));
        } catch (const Error& e) {
            std::fprintf(stderr, "skipping %s: %s\n", f, e.what());
        }
    }
    std::vector<MeshRow> rows;
    using Clock = std::chrono::steady_clock;
    auto ms_since = [](Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); };
    for (const auto& m0 : meshes) {
        for (const MeshCase& c : mesh_cases(normalized(m0))) {
            const TriangleMesh<double>& a = c.a;
            auto t0 = Clock::now();
            const PairList exact = exact_intersecting_pairs(a, c.b);
            const double exact_ms = ms_since(t0);
            rows.push_back(compare(m0.source, c.name, "exact_cgal", exact, exact, exact_ms));
            t0 = Clock::now();
            const PairList obb = cdkit_pairs(MeshModel<Obb<double>>(a), MeshModel<Obb<double>>(c.b));
            rows.push_back(compare(m0.source, c.name, "cdkit_obb_double", exact, obb, ms_since(t0)));
            t0 = Clock::now();
            const PairList aabb = cdkit_pairs(MeshModel<Aabb<double>>(a), MeshModel<Aabb<double>>(c.b));
            rows.push_back(compare(m0.source, c.name, "cdkit_aabb_double", exact, aabb, ms_since(t0)));
            t0 = Clock::now();
            const PairList fcl = fcl_intersecting_pairs(a, c.b, std::size_t(1) << 26);
            rows.push_back(compare(m0.source, c.name, "fcl_obbrss", exact, fcl, ms_since(t0)));
        }
    }
    std::printf("\nMesh pairs (B given in A's frame, identity poses): intersecting triangle pairs vs the exact brute force\n");
    std::printf("%-16s %-20s %-18s %8s %9s %8s %8s %6s %9s\n", "mesh", "config", "method", "exact", "reported",
                "missed", "extra", "bool", "ms");
    std::ofstream csv(o.mesh_csv);
    csv << o.provenance << "mesh,triangles_a,config,method,exact_pairs,reported_pairs,missed,extra,exact_colliding,colliding,ms\n";
    for (const auto& r : rows) {
        std::printf("%-16s %-20s %-18s %8zu %9zu %8zu %8zu %6s %9.1f\n", r.mesh.c_str(), r.config.c_str(), r.method.c_str(),
                    r.exact, r.reported, r.missed, r.extra, r.colliding == r.exact_colliding ? "ok" : "WRONG", r.ms);
        std::size_t tris = 0;
        for (const auto& m : meshes)
            if (m.source == r.mesh) tris = m.triangles.size();
        csv << r.mesh << ',' << tris << ',' << r.config << ',' << r.method << ',' << r.exact << ',' << r.reported << ','
            << r.missed << ',' << r.extra << ',' << r.exact_colliding << ',' << r.colliding << ',' << r.ms << '\n';
    }
    std::printf("(* outside the floating-point stages' range [2^-280, 2^280]: a subnormal coordinate; CSV: %s)\n",
                o.mesh_csv.c_str());
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    const auto t0 = std::chrono::steady_clock::now();
    std::printf("cdkit_bench_accuracy: %lld triangle-pair cases over %d families, seed %llu\n", o.cases, kFamilies,
                static_cast<unsigned long long>(o.seed));
    const auto tallies = run_triangles(o);
    print_triangles(tallies, o);
    time_methods(tallies, o);
    if (o.mesh) run_meshes(o);
    std::printf("\ntotal %.1f s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    long long wrong = 0;
    for (int f = 0; f <= kFamilies; ++f) wrong += tallies[f].wrong[exact_double] + tallies[f].wrong[exact_float];
    return wrong == 0 ? 0 : 1;  // cdkit's default (exact) test must never disagree
}
