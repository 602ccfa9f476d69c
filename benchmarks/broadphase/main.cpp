// cdkit_bench_broadphase: P4 of BENCHMARKS.md (after Serpa & Rodrigues, "Broadmark: A Testing Framework for
// Broad-Phase Collision Detection Algorithms", CGF 2020). Scenes: Brownian, free fall into a bin, teleport.
// Per frame: move every object + find all pairs, for cdkit's broad phases and FCL's managers on identical
// boxes in one process. Every method's pair set is compared with the reference in every frame (untimed):
// brute force's own pair set at N <= 10k, a stateless full-sort sweep at 100k.
//
// Usage: cdkit_bench_broadphase [--full] [--n N] [--frames F] [--csv FILE] [--skip METHOD]...
//   default N in {1000, 10000}; --full adds N = 100000. --skip leaves a method out (repeatable), e.g.
//   --skip fcl_sap for a lone --n 100000 run, where nothing tells the budget rule that FCL's SaP takes
//   minutes per frame.
#include "../provenance.hpp"
#include "../thread_cpu_clock.hpp"
#include "bench_broadphase.hpp"

#include "cdkit/broadphase/brute_force.hpp"
#include "cdkit/broadphase/dynamic_aabb_tree.hpp"
#include "cdkit/broadphase/sorted_cell_grid.hpp"
#include "cdkit/broadphase/sweep_and_prune.hpp"
#include "cdkit/broadphase/uniform_grid.hpp"

#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <string>

using namespace cdbench_bp;
using cdkit::ObjectPair;

namespace {

template <class BP> class CdkitMethod final : public Method {
public:
    explicit CdkitMethod(std::string n) : name_(std::move(n)) {}
    std::string name() const override { return name_; }
    void init(const std::vector<V3>& c, const std::vector<V3>& h) override {
        bp_ = BP();
        halves_ = h;
        for (std::size_t i = 0; i < c.size(); ++i) bp_.insert(cdkit::BroadBox<double>::from_center_half(c[i], h[i]));
    }
    void step(const std::vector<V3>& c, std::vector<ObjectPair>& out) override {
        for (std::size_t i = 0; i < c.size(); ++i)
            bp_.move(cdkit::ObjectId(i), cdkit::BroadBox<double>::from_center_half(c[i], halves_[i]));
        bp_.for_each_pair([&](cdkit::ObjectId a, cdkit::ObjectId b) { out.push_back({a, b}); });
    }

private:
    std::string name_;
    BP bp_;
    std::vector<V3> halves_;
};

/// CPU time of the calling thread in ms: on a shared, loaded machine it leaves out the time the scheduler
/// gives to other processes (wall-clock times there vary 2-3x from run to run).
double thread_cpu_ms() { return 1e3 * cdbench::thread_cpu_seconds(); }

/// Reference for N > 10k, where brute force would take seconds per frame: a stateless full-sort sweep
/// (sort by min x, scan while min x <= max x, test y and z). Exact; cross-checked against brute force in
/// tests/broadphase (as the SAP batch path) and here at N <= 10k.
std::vector<ObjectPair> reference_sweep(const std::vector<V3>& c, const std::vector<V3>& h) {
    std::vector<std::uint32_t> order(c.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::vector<V3> lo(c.size()), hi(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) { lo[i] = c[i] - h[i]; hi[i] = c[i] + h[i]; }
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return lo[a].x() < lo[b].x(); });
    std::vector<ObjectPair> out;
    for (std::size_t i = 0; i < order.size(); ++i)
        for (std::size_t j = i + 1; j < order.size() && lo[order[j]].x() <= hi[order[i]].x(); ++j) {
            const auto a = order[i], b = order[j];
            if (lo[a].y() <= hi[b].y() && lo[b].y() <= hi[a].y() && lo[a].z() <= hi[b].z() && lo[b].z() <= hi[a].z())
                out.push_back(ObjectPair::make(a, b));
        }
    return out;
}

/// A scene: fixed half extents, centres advanced one frame at a time.
struct Scene {
    std::string name;
    std::vector<V3> c, h, v;
    V3 lo, hi;  // bounds for FCL's spatial hash
    std::mt19937_64 rng;
    int kind = 0;  // 0 Brownian, 1 free fall, 2 teleport
    double L = 1, W = 1, H = 1, g = 9.81, dt = 1.0 / 60;

    Scene(int k, std::size_t n, int frames, std::uint64_t seed) : rng(seed), kind(k) {
        static const char* names[] = {"brownian", "free_fall", "teleport"};
        name = names[k];
        // Box edges spread over one order of magnitude, [0.2, 2]; mean Minkowski volume ~ 10.6.
        std::uniform_real_distribution<double> edge(0.2, 2.0), u(0, 1);
        h.resize(n);
        for (auto& x : h) x = V3(edge(rng), edge(rng), edge(rng)) * 0.5;
        L = 1.75 * std::cbrt(double(n));      // ~2 neighbours per object
        W = 0.95 * std::sqrt(double(n));      // free fall: ~8 neighbours on the floor at the end
        H = 10.6 * double(n) / (W * W * 2.0);  // sparse column at the start
        // All objects land by 80% of the frames: H = g t^2 / 2.
        const double t = 0.8 * frames * dt;
        g = 2 * H / (t * t);
        c.resize(n);
        v.assign(n, V3::Zero());
        for (std::size_t i = 0; i < n; ++i) {
            if (kind == 1) c[i] = V3(W * u(rng), W * u(rng), h[i].z() + H * u(rng));
            else c[i] = V3(L * u(rng), L * u(rng), L * u(rng));
        }
        if (kind == 1) { lo = V3(-1, -1, -1); hi = V3(W + 1, W + 1, H + 2); }
        else { lo = V3(-1, -1, -1); hi = V3::Constant(L + 1); }
    }
    void advance() {
        std::normal_distribution<double> step(0, 0.05);
        std::uniform_real_distribution<double> u(0, 1);
        for (std::size_t i = 0; i < c.size(); ++i) {
            if (kind == 0) {
                for (int a = 0; a < 3; ++a) {
                    double x = c[i][a] + step(rng);
                    if (x < 0) x = -x;  // reflect at the walls
                    if (x > L) x = 2 * L - x;
                    c[i][a] = x;
                }
            } else if (kind == 1) {
                v[i].z() -= g * dt;
                c[i].z() += v[i].z() * dt;
                if (c[i].z() < h[i].z()) { c[i].z() = h[i].z(); v[i].z() = 0; }  // rests on the floor
            } else {
                c[i] = V3(L * u(rng), L * u(rng), L * u(rng));
            }
        }
    }
};

struct Result {
    std::vector<double> ms;
    std::size_t wrong_frames = 0;
    double total_ms = 0;
    bool stopped = false;      // over the per-scene time budget: not run for the remaining frames
    std::string first_diff;    // missing / extra / duplicate pairs in the first wrong frame
    double median() const { auto s = ms; std::sort(s.begin(), s.end()); return s[s.size() / 2]; }
    double p99() const {
        auto s = ms;
        std::sort(s.begin(), s.end());
        return s[std::min(s.size() - 1, std::size_t(std::ceil(0.99 * double(s.size()))) - 1)];
    }
};

/// "missing M, extra E, duplicates D" between a method's sorted pair list and the sorted reference.
std::string describe_diff(const std::vector<ObjectPair>& got, const std::vector<ObjectPair>& ref) {
    std::size_t dup = 0;
    for (std::size_t i = 1; i < got.size(); ++i) dup += got[i] == got[i - 1];
    std::vector<ObjectPair> u = got;
    u.erase(std::unique(u.begin(), u.end()), u.end());
    std::vector<ObjectPair> miss, extra;
    std::set_difference(ref.begin(), ref.end(), u.begin(), u.end(), std::back_inserter(miss));
    std::set_difference(u.begin(), u.end(), ref.begin(), ref.end(), std::back_inserter(extra));
    return "missing " + std::to_string(miss.size()) + ", extra " + std::to_string(extra.size()) + ", duplicates " +
           std::to_string(dup) + " (of " + std::to_string(ref.size()) + ")";
}

}  // namespace

int main(int argc, char** argv) {
    bool full = false;
    int frames_override = 0, only_n = 0;
    std::string csv;
    std::vector<std::string> skip;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--full")) full = true;
        else if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) frames_override = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) csv = argv[++i];
        else if (!std::strcmp(argv[i], "--n") && i + 1 < argc) only_n = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--skip") && i + 1 < argc) skip.push_back(argv[++i]);
        else { std::fprintf(stderr, "usage: %s [--full] [--n N] [--frames F] [--csv FILE] [--skip METHOD]...\n", argv[0]); return 2; }
    }
    std::vector<std::size_t> sizes = {1000, 10000};
    if (full) sizes.push_back(100000);
    if (only_n > 0) sizes = {std::size_t(only_n)};
    // Methods stopped for the time budget at a smaller N are skipped at the larger N of the same scene
    // (FCL's SaP takes ~0.5 s per teleport frame at 1k and grows quadratically).
    std::map<std::pair<int, std::string>, bool> over_budget;
    std::ofstream out_csv;
    if (!csv.empty()) out_csv.open(csv), out_csv << cdbench::provenance_lines(argc, argv) << "scene,n,method,median_ms,p99_ms,frames,wrong_frames,pairs_last,frames_run\n";
    std::size_t total_wrong_cdkit = 0;
    // A method stops for the rest of a scene once it has used this much time (FCL's SaP and interval tree
    // take seconds per frame at 10k in the dense scenes); its row says how many frames it ran.
    const double budget_ms = full ? 20000.0 : 3000.0;

    for (std::size_t n : sizes) {
        const int frames = frames_override > 0 ? frames_override : (n <= 1000 ? 40 : n <= 10000 ? 10 : 10);
        for (int kind = 0; kind < 3; ++kind) {
            Scene scene(kind, n, frames, 1234 + kind);
            std::vector<std::unique_ptr<Method>> methods;
            // Brute force comes first: at N <= 10k its pair set is the reference of the frame.
            const bool bf_ref = n <= 10000;
            if (bf_ref) methods.push_back(std::make_unique<CdkitMethod<cdkit::BruteForceBroadPhase<double>>>("cdkit_brute_force"));
            methods.push_back(std::make_unique<CdkitMethod<cdkit::SweepAndPrune<double>>>("cdkit_sap"));
            methods.push_back(std::make_unique<CdkitMethod<cdkit::UniformGrid<double>>>("cdkit_grid"));
            methods.push_back(std::make_unique<CdkitMethod<cdkit::DynamicAabbTree<double>>>("cdkit_dbvt"));
            methods.push_back(std::make_unique<CdkitMethod<cdkit::SortedCellGrid<double>>>("cdkit_sorted_grid"));
            std::erase_if(methods, [&](const auto& m) {
                return !(bf_ref && m->name() == "cdkit_brute_force") &&
                       std::find(skip.begin(), skip.end(), m->name()) != skip.end();
            });
            FclOptions fo;
            fo.scene_min = scene.lo;
            fo.scene_max = scene.hi;
            double mean_d = 0;
            for (const auto& x : scene.h) mean_d += 2 * x.maxCoeff();
            fo.cell_size = mean_d / double(n);
            fo.naive = n <= 1000 || (full && n <= 10000);  // ~2-6 s per frame at 10k
            for (auto& m : make_fcl_methods(fo))
                if (std::find(skip.begin(), skip.end(), m->name()) != skip.end()) continue;
                else if (!over_budget[{kind, m->name()}]) methods.push_back(std::move(m));
                else std::printf("(skipping %s in %s at N = %zu: over budget at a smaller N)\n", m->name().c_str(), scene.name.c_str(), n);
            for (auto& m : methods) m->init(scene.c, scene.h);

            std::vector<Result> res(methods.size());
            std::vector<ObjectPair> pairs;
            pairs.reserve(16 * n);
            std::size_t last_pairs = 0;
            for (int f = 0; f < frames; ++f) {
                scene.advance();
                std::vector<ObjectPair> ref;
                if (!bf_ref) {
                    ref = reference_sweep(scene.c, scene.h);
                    std::sort(ref.begin(), ref.end());
                    last_pairs = ref.size();
                }
                for (std::size_t k = 0; k < methods.size(); ++k) {
                    if (res[k].stopped) continue;
                    pairs.clear();
                    const double t0 = thread_cpu_ms();
                    methods[k]->step(scene.c, pairs);
                    res[k].ms.push_back(thread_cpu_ms() - t0);
                    res[k].total_ms += res[k].ms.back();
                    // The reference (brute force at N <= 10k) always runs.
                    if (!(bf_ref && k == 0) && res[k].total_ms > budget_ms && f + 1 < frames) res[k].stopped = true;
                    std::sort(pairs.begin(), pairs.end());
                    if (bf_ref && k == 0) {
                        ref = pairs;
                        last_pairs = ref.size();
                        continue;
                    }
                    if (pairs != ref) {
                        if (res[k].wrong_frames++ == 0) res[k].first_diff = describe_diff(pairs, ref);
                        if (!methods[k]->is_fcl()) ++total_wrong_cdkit;
                    }
                }
            }
            for (std::size_t k = 0; k < methods.size(); ++k)
                if (res[k].stopped) over_budget[{kind, methods[k]->name()}] = true;
            // FCL's best manager: lowest median among those with exact pair sets in every frame.
            double best_fcl = 0;
            std::string best_name = "-";
            for (std::size_t k = 0; k < methods.size(); ++k)
                if (methods[k]->is_fcl() && res[k].wrong_frames == 0 && !res[k].stopped && (best_fcl == 0 || res[k].median() < best_fcl)) {
                    best_fcl = res[k].median();
                    best_name = methods[k]->name();
                }
            std::printf("\n## %s, N = %zu, %d frames, %zu pairs in the last frame (reference: %s); best FCL: %s\n",
                        scene.name.c_str(), n, frames, last_pairs, n <= 10000 ? "brute force" : "full-sort sweep",
                        best_name.c_str());
            std::printf("| method | median ms | p99 ms | frames run | wrong frames | median / best FCL |\n"
                        "|---|---:|---:|---:|---:|---:|\n");
            for (std::size_t k = 0; k < methods.size(); ++k) {
                std::printf("| %s | %.3f | %.3f | %zu%s | %zu | %.3f |\n", methods[k]->name().c_str(), res[k].median(),
                            res[k].p99(), res[k].ms.size(), res[k].stopped ? " (stopped: over budget)" : "",
                            res[k].wrong_frames, best_fcl > 0 ? res[k].median() / best_fcl : 0.0);
                if (!res[k].first_diff.empty())
                    std::printf("|   first wrong frame of %s: %s | | | | | |\n", methods[k]->name().c_str(), res[k].first_diff.c_str());
                if (out_csv)
                    out_csv << scene.name << ',' << n << ',' << methods[k]->name() << ',' << res[k].median() << ','
                            << res[k].p99() << ',' << frames << ',' << res[k].wrong_frames << ',' << last_pairs << ',' << res[k].ms.size() << '\n';
            }
            std::fflush(stdout);
        }
    }
    std::printf("\ncdkit frames with a pair set different from the reference: %zu\n", total_wrong_cdkit);
    return total_wrong_cdkit == 0 ? 0 : 1;
}
