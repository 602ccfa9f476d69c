/// \file The stdout summary and the CSV/JSON files of a run.

#include "output.hpp"

#include "peers_fcl.hpp"

#include <sched.h>
#include <sys/utsname.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#ifndef CDKIT_BENCH_BUILD_TYPE
#define CDKIT_BENCH_BUILD_TYPE "unknown"
#endif
#ifndef CDKIT_BENCH_CXX_FLAGS
#define CDKIT_BENCH_CXX_FLAGS ""
#endif

namespace cdbench {
namespace {

std::string first_line_with(const char* file, const std::string& key) {
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(key, 0) == 0) {
            const auto colon = line.find(':');
            std::string v = colon == std::string::npos ? line : line.substr(colon + 1);
            v.erase(0, v.find_first_not_of(" \t"));
            return v;
        }
    return "";
}

std::string read_all(const char* file) {
    std::ifstream in(file);
    std::string s;
    std::getline(in, s);
    return s;
}

/// Times in µs to 3–4 significant digits in 7 columns, whatever their magnitude.
std::string fmt_us(double x) {
    char b[32];
    if (!std::isfinite(x)) std::snprintf(b, sizeof b, "%7s", "-");
    else if (x < 10) std::snprintf(b, sizeof b, "%7.3f", x);
    else if (x < 100) std::snprintf(b, sizeof b, "%7.2f", x);
    else if (x < 1000) std::snprintf(b, sizeof b, "%7.1f", x);
    else std::snprintf(b, sizeof b, "%7.0f", x);
    return b;
}

std::string fmt_ratio(double r) {
    char b[32];
    if (r < 0 || !std::isfinite(r)) std::snprintf(b, sizeof b, "%6s", "-");
    else if (r < 100) std::snprintf(b, sizeof b, "x%5.2f", r);
    else std::snprintf(b, sizeof b, "x%5.0f", r);
    return b;
}

/// Rows of one table (mesh, protocol, mode), in run order.
struct Table {
    std::string mesh, protocol, mode, kind;
    std::size_t triangles = 0, poses = 0;
    std::vector<const ResultRow*> rows;
};

std::vector<Table> tables(const Report& r) {
    std::vector<Table> out;
    for (const ResultRow& row : r.rows) {
        if (out.empty() || out.back().mesh != row.mesh || out.back().protocol != row.protocol ||
            out.back().mode != row.mode)
            out.push_back({row.mesh, row.protocol, row.mode, row.distance_kind, row.triangles, row.poses, {}});
        out.back().rows.push_back(&row);
    }
    return out;
}

/// Correctness totals over all distance classes of one (mesh, protocol, mode, method).
struct Totals {
    std::string mesh, protocol, mode, method;
    std::size_t poses = 0, bool_dis = 0, count_mis = 0, probe_timed = 0, colliding_poses = 0;
};

std::vector<Totals> totals(const Report& r) {
    std::vector<Totals> out;
    for (const ResultRow& row : r.rows) {
        auto it = std::find_if(out.begin(), out.end(), [&](const Totals& t) {
            return t.mesh == row.mesh && t.protocol == row.protocol && t.mode == row.mode && t.method == row.method;
        });
        if (it == out.end()) it = out.insert(out.end(), Totals{row.mesh, row.protocol, row.mode, row.method});
        it->poses += row.poses;
        it->bool_dis += row.bool_disagreements;
        it->count_mis += row.contact_mismatches;
        it->probe_timed += row.probe_timed_mismatches;
        it->colliding_poses += std::size_t(std::lround(row.frac_colliding * double(row.poses)));
    }
    return out;
}

std::string csv_escape(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string o = "\"";
    for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
    return o + "\"";
}

std::string num(double x, const char* fmt = "%.6g") {
    if (!std::isfinite(x)) return "";
    char b[64];
    std::snprintf(b, sizeof b, fmt, x);
    return b;
}

/// −1 stands for "not available" in ResultRow; CSV leaves it empty, JSON writes null.
std::string opt_num(double x, const char* fmt = "%.6g") { return x < 0 ? "" : num(x, fmt); }

std::string json_str(const std::string& s) {
    std::string o = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') o += '\\', o += c;
        else if (static_cast<unsigned char>(c) < 0x20) {
            char b[8];
            std::snprintf(b, sizeof b, "\\u%04x", c);
            o += b;
        } else o += c;
    }
    return o + "\"";
}
std::string json_num(double x, const char* fmt = "%.6g") {
    const std::string s = num(x, fmt);
    return s.empty() ? "null" : s;
}
std::string json_opt(double x) { return x < 0 ? "null" : json_num(x); }

std::ofstream open(const std::filesystem::path& p, std::vector<std::string>& written) {
    std::ofstream f(p);
    if (!f) throw std::runtime_error("cannot write " + p.string());
    written.push_back(p.string());
    return f;
}

}  // namespace

std::map<std::string, std::string> machine_info() {
    std::map<std::string, std::string> m;
    m["cpu"] = first_line_with("/proc/cpuinfo", "model name");
    m["cores"] = std::to_string(std::thread::hardware_concurrency());
    m["loadavg_start"] = read_all("/proc/loadavg");
    // This VM's two vCPUs differ, and FCL slows more than cdkit on the slow one (docs/benchmarks.md).
    m["cpu_index_start"] = std::to_string(sched_getcpu());
#if defined(__clang__)
    m["compiler"] = std::string("Clang ") + __clang_version__;
#elif defined(__GNUC__)
    m["compiler"] = std::string("GCC ") + __VERSION__;
#else
    m["compiler"] = "unknown";
#endif
    m["build_type"] = CDKIT_BENCH_BUILD_TYPE;
    m["cxx_flags"] = CDKIT_BENCH_CXX_FLAGS;
#ifdef NDEBUG
    m["asserts"] = "off (NDEBUG)";
#else
    m["asserts"] = "on";
#endif
    m["fcl_version"] = fcl_version();
    struct utsname u {};
    if (uname(&u) == 0) m["os"] = std::string(u.sysname) + " " + u.release + " " + u.machine;
    const std::time_t now = std::time(nullptr);
    char b[64];
    std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    m["date"] = b;
    return m;
}

void print_summary(const Report& r) {
    const std::string& peer = r.peer;
    for (const Table& t : tables(r)) {
        const std::size_t nm = r.methods.size();
        std::printf("\n== %s %s (%zu triangles), %s, %zu poses per %s ==\n", t.protocol.c_str(), t.mesh.c_str(),
                    t.triangles, t.mode == "first" ? "first contact" : "all contacts", t.poses, t.kind.c_str());
        std::printf("   per method: median us, p99 us, xR with R = median(%s) / median(method): R > 1 means faster "
                    "than %s\n", peer.c_str(), peer.c_str());
        std::printf("%7s %5s", t.kind.c_str(), "coll");
        for (const auto& m : r.methods) std::printf(" | %-22s", m.c_str());
        std::printf("\n");
        std::vector<double> log_sum(nm, 0);
        std::vector<std::size_t> log_n(nm, 0);
        for (std::size_t i = 0; i + nm <= t.rows.size(); i += nm) {
            const ResultRow& ref = *t.rows[i];
            std::printf("%+7.3f %4.0f%%", ref.distance, 100 * ref.frac_colliding);
            for (std::size_t m = 0; m < nm; ++m) {
                const ResultRow& x = *t.rows[i + m];
                std::printf(" | %s %s %s", fmt_us(x.median_us).c_str(), fmt_us(x.p99_us).c_str(),
                            fmt_ratio(x.ratio_vs_peer).c_str());
                if (x.ratio_vs_peer > 0) log_sum[m] += std::log(x.ratio_vs_peer), ++log_n[m];
            }
            std::printf("\n");
        }
        std::printf("%13s", "geomean R");
        for (std::size_t m = 0; m < nm; ++m)
            std::printf(" | %15s %s", "", fmt_ratio(log_n[m] ? std::exp(log_sum[m] / double(log_n[m])) : -1).c_str());
        std::printf("\n");
    }

    std::printf("\n== models (built once per mesh; tree = nodes + index arrays, mesh = vertices + triangles) ==\n");
    std::printf("%-18s %-14s %10s %12s %10s %10s %9s\n", "mesh", "method", "build ms", "tree bytes", "B/tri",
                "mesh bytes", "tree/mesh");
    for (const MeshInfo& mi : r.meshes)
        for (const auto& b : mi.builds)
            std::printf("%-18s %-14s %10.2f %12zu %10.1f %10zu %9.2f%s\n", mi.name.c_str(), b.method.c_str(),
                        b.info.build_ms, b.info.tree_bytes, double(b.info.tree_bytes) / double(mi.triangles),
                        b.info.mesh_bytes, double(b.info.tree_bytes) / double(b.info.mesh_bytes),
                        b.family == "cdkit" ? "" : " (est.)");

    std::printf("\n== correctness: booleans against %s; pair counts (all-contacts mode) against it too ==\n",
                r.reference.c_str());
    std::printf("%-18s %-3s %-5s %-14s %8s %9s %10s %12s\n", "mesh", "P", "mode", "method", "poses", "colliding",
                "bool diff", "pairs diff");
    bool probe_timed = false;
    for (const Totals& t : totals(r)) {
        std::printf("%-18s %-3s %-5s %-14s %8zu %9zu %10zu %12s\n", t.mesh.c_str(), t.protocol.c_str(),
                    t.mode.c_str(), t.method.c_str(), t.poses, t.colliding_poses, t.bool_dis,
                    t.mode == "all" ? std::to_string(t.count_mis).c_str() : "-");
        probe_timed |= t.probe_timed != 0;
    }
    std::map<std::string, std::size_t> kinds;
    for (const Disagreement& d : r.disagreements) ++kinds[d.kind];
    std::printf("non-unanimous poses kept in disagreements.csv:");
    if (kinds.empty()) std::printf(" none");
    for (const auto& [k, n] : kinds) std::printf(" %s=%zu", k.c_str(), n);
    std::printf("\n");
    if (probe_timed)
        std::printf("WARNING: some timed batches answered unlike their untimed probe (see results.csv, "
                    "probe_timed_mismatches): those timings measured something else.\n");
    for (const MeshInfo& mi : r.meshes) {
        if (!mi.identity_collides) std::printf("WARNING: %s: triangle test never reports a hit: results meaningless\n", mi.name.c_str());
        if (mi.p2_skipped) std::printf("note: %s: %zu P2 rotations redrawn (no contact at s = 0)\n", mi.name.c_str(), mi.p2_skipped);
    }
    std::printf("total %.1f s\n", r.total_seconds);
}

std::vector<std::string> write_outputs(const Report& r) {
    namespace fs = std::filesystem;
    const fs::path dir = r.options.out_dir;
    fs::create_directories(dir);
    std::vector<std::string> written;

    {
        auto f = open(dir / "results.csv", written);
        f << r.provenance << "mesh,triangles,protocol,mode,distance_kind,distance,method,family,poses,mean_us,median_us,p99_us,"
             "max_us,min_us,frac_colliding,bv_tests_mean,tri_tests_mean,contacts_mean,bool_disagreements,"
             "contact_mismatches,probe_timed_mismatches,ratio_vs_"
          << r.peer << ",first_call_median_us\n";
        for (const ResultRow& x : r.rows)
            f << csv_escape(x.mesh) << ',' << x.triangles << ',' << x.protocol << ',' << x.mode << ','
              << x.distance_kind << ',' << num(x.distance, "%.4f") << ',' << x.method << ',' << x.family << ','
              << x.poses << ',' << num(x.mean_us) << ',' << num(x.median_us) << ',' << num(x.p99_us) << ','
              << num(x.max_us) << ',' << num(x.min_us) << ',' << num(x.frac_colliding, "%.4f") << ','
              << opt_num(x.bv_tests_mean, "%.1f") << ',' << opt_num(x.tri_tests_mean, "%.1f") << ','
              << num(x.contacts_mean, "%.2f") << ',' << x.bool_disagreements << ',' << x.contact_mismatches << ','
              << x.probe_timed_mismatches << ',' << opt_num(x.ratio_vs_peer, "%.4f") << ','
              << opt_num(x.first_call_median_us) << "\n";
    }
    {
        auto f = open(dir / "builds.csv", written);
        f << "mesh,path,triangles,vertices,method,family,build_ms,tree_bytes,tree_bytes_per_triangle,mesh_bytes,"
             "tree_to_mesh,nodes,tree_bytes_source\n";
        for (const MeshInfo& mi : r.meshes)
            for (const auto& b : mi.builds)
                f << csv_escape(mi.name) << ',' << csv_escape(mi.path) << ',' << mi.triangles << ',' << mi.vertices
                  << ',' << b.method << ',' << b.family << ',' << num(b.info.build_ms, "%.3f") << ','
                  << b.info.tree_bytes << ',' << num(double(b.info.tree_bytes) / double(mi.triangles), "%.2f") << ','
                  << b.info.mesh_bytes << ',' << num(double(b.info.tree_bytes) / double(b.info.mesh_bytes), "%.3f")
                  << ',' << b.info.nodes << ',' << csv_escape(b.info.tree_bytes_note) << "\n";
    }
    const std::vector<Totals> tot = totals(r);
    {
        auto f = open(dir / "correctness.csv", written);
        f << "mesh,protocol,mode,method,poses,colliding_poses,bool_disagreements,contact_mismatches,"
             "probe_timed_mismatches\n";
        for (const Totals& t : tot)
            f << csv_escape(t.mesh) << ',' << t.protocol << ',' << t.mode << ',' << t.method << ',' << t.poses << ','
              << t.colliding_poses << ',' << t.bool_dis << ',' << t.count_mis << ',' << t.probe_timed << "\n";
    }
    {
        // Poses in the normalised frame (see builds/meshes: scale and centre), full precision, so an exact
        // oracle can replay them: fixed copy at the identity, moving copy at x ↦ R·x + t.
        auto f = open(dir / "disagreements.csv", written);
        f << "mesh_path,protocol,mode,distance,pose_index,kind,R00,R01,R02,R10,R11,R12,R20,R21,R22,tx,ty,tz";
        for (const auto& m : r.methods) f << ',' << m;
        f << "\n";
        for (const Disagreement& d : r.disagreements) {
            f << csv_escape(d.mesh_path) << ',' << d.protocol << ',' << d.mode << ',' << num(d.distance, "%.4f")
              << ',' << d.pose_index << ',' << d.kind;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) f << ',' << num(d.pose.R(i, j), "%.17g");
            for (int i = 0; i < 3; ++i) f << ',' << num(d.pose.t(i), "%.17g");
            // "1" / "0" in first-contact mode; "1:17" (pairs after the colon) in all-contacts mode.
            for (const Outcome& o : d.answers) {
                f << ',' << int(o.colliding);
                if (d.mode == "all") f << ':' << o.contacts;
            }
            f << "\n";
        }
    }
    {
        auto f = open(dir / "results.json", written);
        const Options& o = r.options;
        f << "{\n  \"machine\": {";
        bool first = true;
        for (const auto& [k, v] : r.machine) f << (first ? "" : ",") << "\n    " << json_str(k) << ": " << json_str(v), first = false;
        f << "\n  },\n  \"config\": {\"size\": " << json_str(o.size) << ", \"steps\": " << o.steps
          << ", \"rotations\": " << o.rotations << ", \"min_batch_us\": " << json_num(o.min_batch_us) << ", \"batches\": " << o.batches
          << ", \"min_reps\": " << o.min_reps << ", \"warmup\": " << o.warmup
          << ", \"slow_query_us\": " << json_num(o.slow_query_us)
          << ", \"seed\": " << o.seed << ", \"split\": " << json_str(o.split) << ", \"protocols\": [";
        for (std::size_t i = 0; i < o.protocols.size(); ++i) f << (i ? ", " : "") << json_str(o.protocols[i]);
        f << "], \"modes\": [";
        for (std::size_t i = 0; i < o.modes.size(); ++i) f << (i ? ", " : "") << json_str(mode_name(o.modes[i]));
        f << "]},\n  \"reference\": " << json_str(r.reference) << ",\n  \"peer\": " << json_str(r.peer)
          << ",\n  \"total_seconds\": " << json_num(r.total_seconds, "%.2f") << ",\n  \"methods\": [";
        for (std::size_t i = 0; i < r.methods.size(); ++i) f << (i ? ", " : "") << json_str(r.methods[i]);
        f << "],\n  \"meshes\": [";
        for (std::size_t i = 0; i < r.meshes.size(); ++i) {
            const MeshInfo& mi = r.meshes[i];
            f << (i ? "," : "") << "\n    {\"name\": " << json_str(mi.name) << ", \"path\": " << json_str(mi.path)
              << ", \"triangles\": " << mi.triangles << ", \"vertices\": " << mi.vertices
              << ", \"closed\": " << (mi.closed ? "true" : "false")
              << ", \"degenerate_triangles\": " << mi.degenerate_triangles
              << ", \"duplicate_triangles\": " << mi.duplicate_triangles
              << ", \"non_manifold_edges\": " << mi.non_manifold_edges << ", \"scale\": " << json_num(mi.scale, "%.17g")
              << ", \"center\": [" << json_num(mi.center.x(), "%.17g") << ", " << json_num(mi.center.y(), "%.17g")
              << ", " << json_num(mi.center.z(), "%.17g") << "], \"radius\": " << json_num(mi.radius, "%.17g")
              << ", \"load_ms\": " << json_num(mi.load_ms, "%.2f")
              << ", \"identity_collides\": " << (mi.identity_collides ? "true" : "false")
              << ", \"p2_skipped\": " << mi.p2_skipped << ", \"builds\": [";
            for (std::size_t j = 0; j < mi.builds.size(); ++j) {
                const auto& b = mi.builds[j];
                f << (j ? "," : "") << "\n      {\"method\": " << json_str(b.method) << ", \"family\": "
                  << json_str(b.family) << ", \"build_ms\": " << json_num(b.info.build_ms, "%.3f")
                  << ", \"tree_bytes\": " << b.info.tree_bytes << ", \"mesh_bytes\": " << b.info.mesh_bytes
                  << ", \"nodes\": " << b.info.nodes << ", \"tree_bytes_source\": " << json_str(b.info.tree_bytes_note)
                  << "}";
            }
            f << "]}";
        }
        f << "\n  ],\n  \"results\": [";
        for (std::size_t i = 0; i < r.rows.size(); ++i) {
            const ResultRow& x = r.rows[i];
            f << (i ? "," : "") << "\n    {\"mesh\": " << json_str(x.mesh) << ", \"triangles\": " << x.triangles
              << ", \"protocol\": " << json_str(x.protocol) << ", \"mode\": " << json_str(x.mode)
              << ", \"distance_kind\": " << json_str(x.distance_kind) << ", \"distance\": " << json_num(x.distance, "%.4f")
              << ", \"method\": " << json_str(x.method) << ", \"family\": " << json_str(x.family)
              << ", \"poses\": " << x.poses << ", \"mean_us\": " << json_num(x.mean_us)
              << ", \"median_us\": " << json_num(x.median_us) << ", \"p99_us\": " << json_num(x.p99_us)
              << ", \"max_us\": " << json_num(x.max_us) << ", \"min_us\": " << json_num(x.min_us)
              << ", \"first_call_median_us\": " << json_opt(x.first_call_median_us)
              << ", \"frac_colliding\": " << json_num(x.frac_colliding, "%.4f")
              << ", \"bv_tests_mean\": " << json_opt(x.bv_tests_mean) << ", \"tri_tests_mean\": "
              << json_opt(x.tri_tests_mean) << ", \"contacts_mean\": " << json_num(x.contacts_mean)
              << ", \"bool_disagreements\": " << x.bool_disagreements
              << ", \"contact_mismatches\": " << x.contact_mismatches
              << ", \"probe_timed_mismatches\": " << x.probe_timed_mismatches
              << ", \"ratio_vs_peer\": " << json_opt(x.ratio_vs_peer) << "}";
        }
        f << "\n  ],\n  \"correctness\": [";
        for (std::size_t i = 0; i < tot.size(); ++i) {
            const Totals& t = tot[i];
            f << (i ? "," : "") << "\n    {\"mesh\": " << json_str(t.mesh) << ", \"protocol\": " << json_str(t.protocol)
              << ", \"mode\": " << json_str(t.mode) << ", \"method\": " << json_str(t.method) << ", \"poses\": " << t.poses
              << ", \"colliding_poses\": " << t.colliding_poses << ", \"bool_disagreements\": " << t.bool_dis
              << ", \"contact_mismatches\": " << t.count_mis << ", \"probe_timed_mismatches\": " << t.probe_timed << "}";
        }
        std::map<std::string, std::size_t> kinds;
        for (const Disagreement& d : r.disagreements) ++kinds[d.kind];
        f << "\n  ],\n  \"disagreement_kinds\": {";
        first = true;
        for (const auto& [k, n] : kinds) f << (first ? "" : ", ") << json_str(k) << ": " << n, first = false;
        f << "}\n}\n";
    }
    return written;
}

}  // namespace cdbench
