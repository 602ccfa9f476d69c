/// \file cdkit_bench: cdkit's mesh–mesh collision against FCL, protocols P1 (tumbling) and P2 (proximity)
/// of shared/BENCHMARKS.md, all methods in one process on identical poses. See docs/benchmarks.md.

#include "cdkit_methods.hpp"
#include "harness.hpp"
#include "output.hpp"
#include "peers_fcl.hpp"
#include "provenance.hpp"

#include "cdkit/core/error.hpp"

#include <glob.h>
#include <sched.h>  // sched_getcpu
#include <string.h>  // strverscmp (GNU)

#include <algorithm>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#ifndef CDKIT_BENCH_SOURCE_DIR
#define CDKIT_BENCH_SOURCE_DIR "."
#endif

namespace {

using cdbench::Options;

/// Sizes: how many poses a run uses unless --steps / --rotations say otherwise.
struct Size { const char* name; std::size_t steps, rotations; };
constexpr Size kSizes[] = {{"quick", 36, 100}, {"full", 5000, 1000}};

void usage(std::FILE* f) {
    std::fprintf(f, R"(usage: cdkit_bench [options] [MESH...]

Times cdkit's mesh-mesh collision queries against FCL's, in one process on identical poses
(protocols P1 and P2 of shared/BENCHMARKS.md; docs/benchmarks.md explains every column).

  --mesh LIST         mesh files: comma-separated, repeatable, globs allowed ('data/dragon/*.ply');
                      extra arguments without an option are meshes too.
                      default: data/bunny.obj and data/teapot.obj (those that exist)
  --protocol LIST     p1 (tumbling), p2 (proximity, bisection to contact); default p1,p2
  --mode LIST         first (stop at the first contact), all (every intersecting pair); default first,all
  --size quick|full   quick: %zu tumbling steps, %zu P2 rotations (default);
                      full:  %zu steps, %zu rotations (BENCHMARKS.md's N)
  --steps N           P1: poses per distance (one tumbling turn in N steps); overrides --size
  --rotations R       P2: random rotations (each with a random direction); overrides --size
  --methods LIST      comma-separated glob patterns over method names (default '*'); a leading '-'
                      excludes ('-fcl_aabb,-fcl_rss' = all but those two, which copy and refit both
                      meshes on every query and dominate run time on big meshes); the reference %s
                      is always measured
  --list-methods      print the method names and exit
  --min-batch-us X    repeat each pose's query until the batch lasts X us (default 50)
  --min-reps N        ... and at least N times, for queries shorter than X us (default 8)
  --batches B         timed batches per pose, the fastest kept (default 3: filters preemption)
  --warmup W          untimed calls of the timed query before the batches, the last one sizing
                      them (default 1; with 0 the pose's cold first call sizes them; --warmup 0
                      --min-reps 1 --batches 1 is close to the measurement before issue 39)
  --slow-query-us X   a method whose last query took >= X us is timed by one call after the
                      probe, as before issue 39, and its first call is not timed (default 500)
  --seed S            P2's random rotations and directions (default 1)
  --split median|mean|sah|pca_volume  cdkit tree build split (default sah, the library's; FCL splits at the mean)
  --out DIR           output directory for results.{csv,json}, builds.csv, correctness.csv,
                      disagreements.csv (default build/report)
  --quiet             no progress on stderr
  --help

Ratios are median(fcl_obbrss) / median(method): above 1, the method is faster than FCL's OBBRSS.
Plots and report.md: /usr/bin/python3 benchmarks/report.py DIR
)",
                 kSizes[0].steps, kSizes[0].rotations, kSizes[1].steps, kSizes[1].rotations,
                 cdbench::cdkit_method_names().front().c_str());
}

std::vector<std::string> split(const std::string& s, char sep = ',') {
    std::vector<std::string> out;
    std::stringstream in(s);
    std::string item;
    while (std::getline(in, item, sep))
        if (!item.empty()) out.push_back(item);
    return out;
}

/// Expands a pattern with glob(3); a plain path is kept as is (load_mesh names it if it is missing).
std::vector<std::string> expand(const std::string& pattern) {
    if (pattern.find_first_of("*?[") == std::string::npos) return {pattern};
    glob_t g{};
    std::vector<std::string> out;
    if (glob(pattern.c_str(), 0, nullptr, &g) == 0)
        for (std::size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
    globfree(&g);
    if (out.empty()) throw std::runtime_error("--mesh: no file matches '" + pattern + "'");
    // Natural order (strverscmp), so that a ladder runs small to large: 11k, 48k, 203k, 871k.
    std::sort(out.begin(), out.end(), [](const std::string& a, const std::string& b) {
        return strverscmp(a.c_str(), b.c_str()) < 0;
    });
    return out;
}

/// The bundled meshes, found from the working directory or else from the source tree.
std::vector<std::string> default_meshes() {
    std::vector<std::string> out;
    for (const char* rel : {"data/bunny.obj", "data/teapot.obj"}) {
        if (std::filesystem::exists(rel)) out.emplace_back(rel);
        else if (auto p = std::filesystem::path(CDKIT_BENCH_SOURCE_DIR) / rel; std::filesystem::exists(p))
            out.push_back(p.string());
    }
    if (out.empty()) throw std::runtime_error("no default mesh found (data/bunny.obj); pass --mesh");
    return out;
}

std::size_t to_count(const std::string& opt, const std::string& v) {
    char* end = nullptr;
    const long long n = std::strtoll(v.c_str(), &end, 10);
    if (v.empty() || *end || n <= 0) throw std::runtime_error(opt + " needs a positive integer, got '" + v + "'");
    return std::size_t(n);
}

double to_number(const std::string& opt, const std::string& v) {
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (v.empty() || *end || !(x >= 0)) throw std::runtime_error(opt + " needs a number >= 0, got '" + v + "'");
    return x;
}

/// Parses argv; returns nullopt when the program should exit successfully (--help, --list-methods).
std::optional<Options> parse(int argc, char** argv) {
    Options o;
    std::optional<std::size_t> steps, rotations;
    std::vector<std::string> meshes;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        std::optional<std::string> inline_value;  // --option=value
        if (const auto eq = a.find('='); a.rfind("--", 0) == 0 && eq != std::string::npos) {
            inline_value = a.substr(eq + 1);
            a.resize(eq);
        }
        auto value = [&]() -> std::string {
            if (inline_value) return *std::exchange(inline_value, std::nullopt);
            if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
            return argv[++i];
        };
        if (a == "--help" || a == "-h") {
            usage(stdout);
            return std::nullopt;
        } else if (a == "--list-methods") {
            for (const auto& n : cdbench::cdkit_method_names()) std::printf("%s\n", n.c_str());
            for (const auto& n : cdbench::fcl_method_names()) std::printf("%s\n", n.c_str());
            return std::nullopt;
        } else if (a == "--mesh") {
            for (const auto& p : split(value())) meshes.push_back(p);
        } else if (a == "--protocol") {
            o.protocols.clear();
            for (auto p : split(value())) {
                for (auto& c : p) c = char(std::tolower(static_cast<unsigned char>(c)));
                if (p != "p1" && p != "p2") throw std::runtime_error("--protocol: unknown '" + p + "' (p1, p2)");
                o.protocols.push_back(p);
            }
        } else if (a == "--mode") {
            o.modes.clear();
            for (const auto& m : split(value())) {
                if (m == "first") o.modes.push_back(cdbench::Mode::first);
                else if (m == "all") o.modes.push_back(cdbench::Mode::all);
                else throw std::runtime_error("--mode: unknown '" + m + "' (first, all)");
            }
        } else if (a == "--size") {
            o.size = value();
        } else if (a == "--steps") {
            steps = to_count(a, value());
        } else if (a == "--rotations") {
            rotations = to_count(a, value());
        } else if (a == "--methods") {
            o.method_patterns = split(value());
        } else if (a == "--min-batch-us") {
            o.min_batch_us = to_number(a, value());
        } else if (a == "--min-reps") {
            o.min_reps = to_count(a, value());
        } else if (a == "--batches") {
            o.batches = to_count(a, value());
        } else if (a == "--warmup") {
            const std::string v = value();
            o.warmup = v == "0" ? 0 : to_count(a, v);
        } else if (a == "--slow-query-us") {
            o.slow_query_us = to_number(a, value());
        } else if (a == "--seed") {
            o.seed = to_count(a, value());
        } else if (a == "--split") {
            o.split = value();
        } else if (a == "--out") {
            o.out_dir = value();
        } else if (a == "--quiet") {
            o.quiet = true;
        } else if (!a.empty() && a[0] == '-') {
            throw std::runtime_error("unknown option '" + a + "' (see --help)");
        } else {
            meshes.push_back(a);  // e.g. the rest of a shell-expanded '--mesh data/dragon/*.ply'
        }
        if (inline_value) throw std::runtime_error(a + " takes no value");
    }
    const Size* size = nullptr;
    for (const Size& s : kSizes)
        if (o.size == s.name) size = &s;
    if (!size) throw std::runtime_error("--size must be quick or full, got '" + o.size + "'");
    o.steps = steps.value_or(size->steps);
    o.rotations = rotations.value_or(size->rotations);
    if (meshes.empty()) o.meshes = default_meshes();
    else
        for (const auto& m : meshes)
            for (auto& p : expand(m)) o.meshes.push_back(std::move(p));
    if (o.protocols.empty() || o.modes.empty()) throw std::runtime_error("nothing to run");
    return o;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const std::optional<Options> opt = parse(argc, argv);
        if (!opt) return 0;
        cdbench::Report report;
        report.options = *opt;
        report.machine = cdbench::machine_info();
        report.provenance = cdbench::provenance_lines(argc, argv);
        const auto& m = report.machine;
        std::printf("cdkit_bench: %s, %s cores (on CPU %s); %s; build %s; FCL %s; %s\n", m.at("cpu").c_str(),
                    m.at("cores").c_str(), m.at("cpu_index_start").c_str(), m.at("compiler").c_str(),
                    m.at("build_type").c_str(), m.at("fcl_version").c_str(), m.at("date").c_str());
        std::printf("size %s: P1 %zu steps per d, P2 %zu rotations; %zu warm-up call(s), then batches >= %.0f us "
                    "and >= %zu queries (%zu per pose, fastest kept; one call after the probe above %.0f us); seed %llu\n",
                    opt->size.c_str(), opt->steps, opt->rotations, opt->warmup, opt->min_batch_us, opt->min_reps,
                    opt->batches, opt->slow_query_us, static_cast<unsigned long long>(opt->seed));
#ifndef NDEBUG
        std::printf("WARNING: assertions are on (not a Release build): timings are not representative\n");
#endif
        std::fflush(stdout);
        cdbench::run_all(*opt, report);
        report.machine["cpu_index_end"] = std::to_string(sched_getcpu());
        report.machine["loadavg_end"] = [] {
            std::FILE* f = std::fopen("/proc/loadavg", "r");
            char b[128] = {};
            if (f) {
                if (!std::fgets(b, sizeof b, f)) b[0] = 0;
                std::fclose(f);
            }
            std::string s = b;
            while (!s.empty() && s.back() == '\n') s.pop_back();
            return s;
        }();
        cdbench::print_summary(report);
        for (const auto& p : cdbench::write_outputs(report)) std::printf("wrote %s\n", p.c_str());
        return 0;
    } catch (const cdkit::Error& e) {
        std::fprintf(stderr, "cdkit_bench: %s\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cdkit_bench: error: %s\n", e.what());
    }
    return 1;
}
