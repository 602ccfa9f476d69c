// cdkit_distance_expansion_cost: where the time of an Rss distance() query goes, per expansion. A
// diagnostic for issue #3's "cost per expansion" (docs/distance.md), not a peer benchmark: its ratios compare
// cdkit with itself in one process.
//
// Part 1, queries (P2 poses of cdkit_bench_distance: same seed, rotations and δ classes). Each pose is
// queried three times: first (after the previous pose's queries, as the first repetition of the benchmark),
// repeat (the same query again: same branches, data in cache), evicted (a third time, after streaming through
// --evict-mb MiB, which pushes the tree out of the core's L2 but not out of L3). First − repeat is what a
// pose's first run pays for mispredicted branches and cold cache; if evicted is not slower than repeat, the
// cache is not that cost (the branch predictor, trained by the runs before, is).
// Per δ class: medians over poses (median over --rounds rounds), bound evaluations, µs per expansion.
//
// Part 2, the bound alone: the two-lane Rss bound of distance() (transformed() of the other node, then
// detail::rss_pair_lower_bounds for both children) on random (inner node, node) pairs of the tree under a
// fixed rigid motion, in ns per call: "independent" calls (the next call's inputs do not wait for this one),
// "chained" calls (the next call's slack depends on this result, so calls cannot overlap: the latency), and
// the scalar bound (distance_lower_bound_same_frame, no cutoff) for both children for comparison.
//
// Usage: cdkit_distance_expansion_cost [--mesh PATH] [--rotations N] [--rounds N] [--evict-mb N] [--calls N]
//                                      [--csv PATH]   (both parts as rows: part "query" per δ, part "bound")
// Times are thread CPU time.
#include "distance_poses.hpp"
#include "../provenance.hpp"
#include "../thread_cpu_clock.hpp"
#include "cdkit/cdkit.hpp"
#include "cdkit/distance.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace cdkit;
using Clock = cdbench::ThreadCpuClock;

namespace {

using cdbench::random_rotation;
using cdbench::unit_scaled;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

double us_since(Clock::time_point t0) { return std::chrono::duration<double, std::micro>(Clock::now() - t0).count(); }

}  // namespace

int main(int argc, char** argv) {
    std::string path = std::string(CDKIT_BENCH_SOURCE_DIR) + "/data/bunny.obj";
    int rotations = 20, rounds = 5, evict_mb = 2, calls = 4096;
    std::string csv_path;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
        if (a == "--mesh") path = next();
        else if (a == "--rotations") rotations = std::max(1, std::atoi(next().c_str()));
        else if (a == "--rounds") rounds = std::max(1, std::atoi(next().c_str()));
        else if (a == "--evict-mb") evict_mb = std::max(0, std::atoi(next().c_str()));
        else if (a == "--calls") calls = std::max(16, std::atoi(next().c_str()));
        else if (a == "--csv") csv_path = next();
        else {
            std::fprintf(stderr, "usage: %s [--mesh PATH] [--rotations N] [--rounds N] [--evict-mb N] [--calls N] [--csv PATH]\n",
                         argv[0]);
            return 2;
        }
    }
    const auto mesh = std::make_shared<const TriangleMesh<double>>(unit_scaled(load_mesh(path)));
    double r = 0;
    for (const auto& v : mesh->vertices) r = std::max(r, v.norm());
    const MeshModel<Obb<double>> m_obb(mesh);  // for the bisection to contact, as cdkit_bench_distance
    BuildOptions sah;
    sah.split = SplitStrategy::sah;
    const MeshModel<Rss<double>> m_rss(mesh, sah);
    std::printf("cdkit_distance_expansion_cost: %s, %zu triangles, %zu Rss nodes (%zu bytes each); thread CPU time\n",
                path.c_str(), mesh->num_triangles(), m_rss.bvh().nodes().size(), sizeof(BvhNode<Rss<double>>));

    // P2 poses, exactly as cdkit_bench_distance builds them.
    const double deltas[] = {0.005, 0.01, 0.05, 0.2};
    std::mt19937_64 rng(20240611);
    std::vector<std::vector<Transform<double>>> poses(std::size(deltas));
    for (int k = 0; k < rotations; ++k) {
        const Mat3<double> R = random_rotation(rng);
        std::normal_distribution<double> g;
        const Vec3<double> u = Vec3<double>(g(rng), g(rng), g(rng)).normalized();
        auto hits = [&](double s) { return collide(m_obb, Transform<double>(), m_obb, Transform<double>(R, s * u)).colliding; };
        double lo = 0, hi = 2 * r * 1.01;
        if (!hits(lo)) continue;
        for (int it = 0; it < 50; ++it) {
            const double mid = 0.5 * (lo + hi);
            (hits(mid) ? lo : hi) = mid;
        }
        for (std::size_t d = 0; d < std::size(deltas); ++d) poses[d].push_back(Transform<double>(R, (hi + deltas[d] * r) * u));
    }

    std::FILE* csv = nullptr;
    if (!csv_path.empty()) {
        csv = std::fopen(csv_path.c_str(), "w");
        if (!csv) {
            std::fprintf(stderr, "cannot write %s\n", csv_path.c_str());
            return 1;
        }
        cdbench::write_provenance(csv, argc, argv);
        std::fprintf(csv, "part,delta,poses,bv_tests,first_us,repeat_us,evicted_us,first_over_repeat,ns_per_expansion_first,"
                          "ns_per_expansion_repeat,two_lane_ns,two_lane_chained_ns,scalar_pair_ns\n");
    }
    std::vector<double> evict(std::size_t(evict_mb) * 131072, 1.0);
    double sink = 0;
    std::printf("\n%-7s %6s %9s %10s %10s %11s %12s %13s %10s\n", "delta", "poses", "bv_tests", "first_us", "repeat_us",
                "evicted_us", "first/repeat", "ns/exp first", "ns/exp rep");
    for (std::size_t d = 0; d < std::size(deltas); ++d) {
        const auto& P = poses[d];
        std::vector<double> first, repeat, evicted;
        double bv = 0;
        for (int round = 0; round < rounds; ++round) {
            std::vector<double> f(P.size()), s(P.size()), e(P.size());
            for (std::size_t i = 0; i < P.size(); ++i) {
                auto t0 = Clock::now();
                const auto a = distance(m_rss, Transform<double>(), m_rss, P[i]);
                f[i] = us_since(t0);
                t0 = Clock::now();
                const auto b = distance(m_rss, Transform<double>(), m_rss, P[i]);
                s[i] = us_since(t0);
                for (std::size_t k = 0; k < evict.size(); k += 8) evict[k] += 1.0;  // one store per cache line
                t0 = Clock::now();
                const auto c = distance(m_rss, Transform<double>(), m_rss, P[i]);
                e[i] = us_since(t0);
                if (a.distance != b.distance || b.distance != c.distance) std::printf("nondeterministic answer!\n");
                if (round == 0) bv += double(a.stats.bv_tests);
                sink += a.distance;
            }
            first.push_back(median(f)), repeat.push_back(median(s)), evicted.push_back(median(e));
        }
        const double n = double(P.size()), fm = median(first), rm = median(repeat), em = median(evicted);
        const double expansions = bv / n / 2;  // two bound evaluations per expansion
        std::printf("%-7.3f %6zu %9.0f %10.1f %10.1f %11.1f %12.2f %13.0f %10.0f\n", deltas[d], P.size(), bv / n, fm, rm, em,
                    fm / rm, 1e3 * fm / expansions, 1e3 * rm / expansions);
        if (csv)
            std::fprintf(csv, "query,%g,%zu,%.0f,%.2f,%.2f,%.2f,%.3f,%.1f,%.1f,,,\n", deltas[d], P.size(), bv / n, fm, rm, em,
                         fm / rm, 1e3 * fm / expansions, 1e3 * rm / expansions);
    }

    // Part 2: the bound alone, on random (inner node, node) pairs under one rigid motion.
    const auto& nodes = m_rss.bvh().nodes();
    std::vector<std::uint32_t> inner;
    for (std::uint32_t i = 0; i < nodes.size(); ++i)
        if (!nodes[i].is_leaf()) inner.push_back(i);
    if (inner.empty()) {
        std::printf("\n(no inner nodes: no bound timings)\n");
        if (csv) std::fclose(csv);
        return 0;
    }
    std::mt19937 pick(7);
    std::vector<std::uint32_t> xs(std::size_t(calls), 0), ys(std::size_t(calls), 0);
    for (int i = 0; i < calls; ++i) xs[i] = inner[pick() % inner.size()], ys[i] = std::uint32_t(pick() % nodes.size());
    const Transform<double> motion(Eigen::AngleAxisd(0.7, Vec3<double>(1, 2, 3).normalized()).toRotationMatrix(),
                                   Vec3<double>(0.3, 0.1, 0.05));
    const auto rel = Rss<double>::relative(motion);
    const int passes = 50;
    std::vector<double> indep, chained, scalar;
    for (int round = 0; round < 5; ++round) {
        auto t0 = Clock::now();
        for (int p = 0; p < passes; ++p)
            for (int i = 0; i < calls; ++i) {
                const auto& x = nodes[xs[i]];
                const Rss<double> moved = transformed(nodes[ys[i]].bv, rel.R, rel.t);
                double out[2];
                detail::rss_pair_lower_bounds(nodes[x.first].bv, nodes[x.first + 1].bv, moved, rel.slack, out);
                sink += out[0] + out[1];
            }
        indep.push_back(1e3 * us_since(t0) / (double(passes) * calls));
        t0 = Clock::now();
        double dep = 0;
        for (int p = 0; p < passes; ++p)
            for (int i = 0; i < calls; ++i) {
                const auto& x = nodes[xs[i]];
                const Rss<double> moved = transformed(nodes[ys[i]].bv, rel.R, rel.t);
                double out[2];
                // dep is 0 (or subnormal) but the compiler cannot know: each call waits for the one before.
                detail::rss_pair_lower_bounds(nodes[x.first].bv, nodes[x.first + 1].bv, moved, rel.slack + dep, out);
                dep = (out[0] + out[1]) * 1e-300;
            }
        chained.push_back(1e3 * us_since(t0) / (double(passes) * calls));
        sink += dep;
        t0 = Clock::now();
        for (int p = 0; p < passes; ++p)
            for (int i = 0; i < calls; ++i) {
                const auto& x = nodes[xs[i]];
                const Rss<double> moved = transformed(nodes[ys[i]].bv, rel.R, rel.t);
                sink += distance_lower_bound_same_frame(nodes[x.first].bv, moved, rel.slack) +
                        distance_lower_bound_same_frame(nodes[x.first + 1].bv, moved, rel.slack);
            }
        scalar.push_back(1e3 * us_since(t0) / (double(passes) * calls));
    }
    std::printf("\nbound of both children of a node against one other node (transformed + bound), %d random pairs:\n", calls);
    std::printf("  two-lane, independent calls %.1f ns/call; chained %.1f ns/call; scalar bound x2 %.1f ns (%.2fx the two-lane)\n",
                median(indep), median(chained), median(scalar), median(scalar) / median(indep));
    if (csv) {
        std::fprintf(csv, "bound,,%d,,,,,,,,%.2f,%.2f,%.2f\n", calls, median(indep), median(chained), median(scalar));
        std::fclose(csv);
    }
    std::printf("\n(checksum %g)\n", sink);
    return 0;
}
