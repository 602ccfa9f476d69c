// cdkit_bench_distance: separation distance between two copies of a mesh at P2 proximity poses
// (BENCHMARKS.md): random rotation and direction, bisection to contact with cdkit::collide, then queries at
// s* + δ·r for δ ∈ {0.005, 0.01, 0.05, 0.2}. cdkit distance() (Aabb, Obb, Rss and Rss<float> over the double
// mesh with SAH splits, Rss with 4-triangle leaves, Rss with median splits, the restricted boxtree, the Obb tree
// against the Rss tree (mixed trees, cdkit_obb_x_rss); rel_err 0
// and 0.01) against FCL's fcl::distance (BVHModel<RSS> with each of FCL's three split rules, BVHModel<OBBRSS>;
// rel_err 0 and 0.01) in one process, fixed seeds.
//
// Timing as the collision harness does it (docs/benchmarks.md, "Warm batches"): methods interleaved per pose, in
// an order rotated from pose to pose; per pose and method one cold call (first_us), one untimed warm-up that sizes
// the batch (≥ 50 µs and ≥ 8 calls), and the fastest of 3 batches (thread CPU time). Per δ class and method:
// median / p99 / max µs, the first call's median, ratios of medians to FCL RSS (its default split) and to the
// fastest FCL row of the same rel_err ("best FCL"), work counters.
// Reference: on `--brute N` poses per class of EVERY mesh, the all-pairs distance over a uniform grid
// (tests/oracles/grid_reference.hpp: no tree, its own triangle distance), up to --brute-pairs candidate pairs a
// pose (a pose over the cap is counted as unchecked, not dropped). A cdkit answer off the reference (rel_err 0:
// by more than 1e-9·r; rel_err 0.01: below it or above it by more than 1%) exits with status 1.
//
// Usage: cdkit_bench_distance [--mesh PATH]... [--full] [--rotations N] [--brute N] [--brute-pairs N] [--csv PATH]
//                             [--filter NAME]   (only cdkit methods whose name contains NAME; FCL always)
//   default: data/bunny.obj and data/dragon/dragon_48k.ply (when present), 100 rotations, 10 brute poses;
//   --full: bunny + every dragon.
#include "distance_poses.hpp"
#include "../thread_cpu_clock.hpp"
#include "cdkit/bvh/boxtree.hpp"
#include "cdkit/cdkit.hpp"
#include "cdkit/distance.hpp"

#include "../../tests/oracles/fcl_mesh.hpp"        // the FCL model builder the FCL tests use
#include "../../tests/oracles/grid_reference.hpp"  // the all-pairs reference the dragon tests use
#include "../provenance.hpp"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

using namespace cdkit;

// Thread CPU time (shared machine); cdkit and FCL are timed with this same clock, single-threaded.
using Clock = cdbench::ThreadCpuClock;

namespace {

struct Options {
    std::vector<std::string> meshes;
    bool full = false;
    int rotations = 100;
    int brute = 10;                       // poses per δ class checked against the all-pairs reference
    double brute_pairs = 3e8;             // candidate pairs a pose may take (more: counted as unchecked)
    std::string csv;
    std::string filter;  // run only the cdkit methods whose name contains it (FCL peers always run)
};

using cdbench::random_rotation;
using cdbench::unit_scaled;

struct Answer {
    double distance;
    std::uint64_t bv_tests, tri_tests, tri_skips;
};

struct Method {
    std::string name;
    std::string peer;   // the FCL method it is compared with
    std::string peer2;  // a second FCL peer (OBBRSS)
    std::function<Answer(std::size_t pose)> run;
    double rel = 0;     // the rel_err it was asked for
};

double percentile(std::vector<double> v, double p) {
    std::sort(v.begin(), v.end());
    const std::size_t i = std::min(v.size() - 1, std::size_t(p * double(v.size() - 1) + 0.5));
    return v[i];
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// One pose of one method, warm: a cold call (its time returned in `first_us`), an untimed warm-up that sizes the
/// batch (≥ 50 µs and ≥ 8 calls for shorter queries), then the fastest of 3 batches' mean, in µs.
double time_warm(const Method& m, std::size_t pose, double& first_us, Answer& ans) {
    auto t0 = Clock::now();
    ans = m.run(pose);
    first_us = seconds_since(t0) * 1e6;
    t0 = Clock::now();
    (void)m.run(pose);
    const double warm_us = std::max(seconds_since(t0) * 1e6, 1e-3);
    const int k = warm_us >= 50 ? 1 : std::max(8, int(std::ceil(50 / warm_us)));
    double best = 1e300;
    for (int b = 0; b < 3; ++b) {
        t0 = Clock::now();
        for (int i = 0; i < k; ++i) ans = m.run(pose);
        best = std::min(best, seconds_since(t0) * 1e6 / k);
    }
    return best;
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
        if (a == "--mesh") opt.meshes.push_back(next());
        else if (a == "--full") opt.full = true;
        else if (a == "--rotations") opt.rotations = std::max(1, std::atoi(next().c_str()));
        else if (a == "--brute") opt.brute = std::max(0, std::atoi(next().c_str()));
        else if (a == "--brute-pairs") opt.brute_pairs = std::atof(next().c_str());
        else if (a == "--csv") opt.csv = next();
        else if (a == "--filter") opt.filter = next();
        else {
            std::fprintf(stderr, "usage: %s [--mesh PATH]... [--full] [--rotations N] [--brute N] [--brute-pairs N] [--csv PATH] [--filter NAME]\n", argv[0]);
            return 2;
        }
    }
    const std::string root = CDKIT_BENCH_SOURCE_DIR;
    if (opt.meshes.empty()) {
        opt.meshes.push_back(root + "/data/bunny.obj");
        const std::vector<std::string> dragons =
            opt.full ? std::vector<std::string>{"11k", "48k", "203k", "871k"} : std::vector<std::string>{"48k"};
        for (const auto& d : dragons) {
            const std::string p = root + "/data/dragon/dragon_" + d + ".ply";
            if (std::filesystem::exists(p)) opt.meshes.push_back(p);
        }
    }
    std::FILE* csv = opt.csv.empty() ? nullptr : std::fopen(opt.csv.c_str(), "w");
    if (csv) {
        cdbench::write_provenance(csv, argc, argv);
        std::fprintf(csv, "mesh,triangles,delta,method,poses,median_us,p99_us,max_us,first_call_median_us,ratio_vs_fcl_rss,"
                          "ratio_vs_fcl_obbrss,ratio_vs_best_fcl,bv_tests,tri_tests,tri_skips,brute_poses,brute_unchecked,"
                          "max_err_vs_brute,wrong_vs_brute\n");
    }
    std::printf("cdkit_bench_distance: P2 poses, %d rotations; methods interleaved per pose, warm, fastest of 3 batches "
                "(thread CPU time)\n", opt.rotations);
    int cdkit_wrong = 0;
    const double deltas[] = {0.005, 0.01, 0.05, 0.2};

    for (const std::string& path : opt.meshes) {
        const auto mesh = std::make_shared<const TriangleMesh<double>>(unit_scaled(load_mesh(path)));
        const std::string name = std::filesystem::path(path).stem().string();
        double r = 0;
        for (const auto& v : mesh->vertices) r = std::max(r, v.norm());
        auto t0 = Clock::now();
        const MeshModel<Aabb<double>> m_aabb(mesh);
        const double build_aabb = seconds_since(t0);
        t0 = Clock::now();
        const MeshModel<Obb<double>> m_obb(mesh);
        const double build_obb = seconds_since(t0);
        t0 = Clock::now();
        // RSS trees with SAH splits: 20-30% fewer BV tests than median splits on the bunny (the
        // cdkit_rss_median row shows the difference).
        BuildOptions rss_opt;
        rss_opt.split = SplitStrategy::sah;
        const MeshModel<Rss<double>> m_rss(mesh, rss_opt);
        const double build_rss_ck = seconds_since(t0);
        const MeshModel<Rss<float>, double> m_rssf(mesh, rss_opt);
        BuildOptions leaf4;
        leaf4.max_leaf_triangles = 4;
        leaf4.split = rss_opt.split;
        BuildOptions median;  // the default is SAH now: the median row must ask for it
        median.split = SplitStrategy::median;
        const MeshModel<Rss<double>> m_rss_median(mesh, median);
        const RestrictedBoxtree<double> m_boxtree(mesh);
        const MeshModel<Rss<double>> m_rss4(mesh, leaf4);
        t0 = Clock::now();
        const auto f_rss = test::fcl_mesh<fcl::RSSd>(*mesh);  // FCL's default split: the mean
        const double build_rss = seconds_since(t0);
        const auto f_rss_median = test::fcl_mesh<fcl::RSSd>(*mesh, fcl::detail::SPLIT_METHOD_MEDIAN);
        const auto f_rss_center = test::fcl_mesh<fcl::RSSd>(*mesh, fcl::detail::SPLIT_METHOD_BV_CENTER);
        t0 = Clock::now();
        const auto f_obbrss = test::fcl_mesh<fcl::OBBRSSd>(*mesh);
        const double build_obbrss = seconds_since(t0);
        std::printf("\n== %s: %zu triangles, bounding-sphere radius r = %.4f; build s: aabb %.3f obb %.3f rss %.3f fcl_rss %.3f fcl_obbrss %.3f\n",
                    name.c_str(), mesh->num_triangles(), r, build_aabb, build_obb, build_rss_ck, build_rss, build_obbrss);

        // P2 poses: A at the identity, B rotated, bisection along u to the contact distance s*.
        std::mt19937_64 rng(20240611);
        std::vector<std::vector<Transform<double>>> poses(std::size(deltas));
        for (int k = 0; k < opt.rotations; ++k) {
            const Mat3<double> R = random_rotation(rng);
            std::normal_distribution<double> g;
            const Vec3<double> u = Vec3<double>(g(rng), g(rng), g(rng)).normalized();
            auto hits = [&](double s) { return collide(m_obb, Transform<double>(), m_obb, Transform<double>(R, s * u)).colliding; };
            double lo = 0, hi = 2 * r * 1.01;
            if (!hits(lo)) continue;  // the copies do not overlap at s = 0: no contact to bisect to
            for (int it = 0; it < 50; ++it) {
                const double mid = 0.5 * (lo + hi);
                (hits(mid) ? lo : hi) = mid;
            }
            for (std::size_t d = 0; d < std::size(deltas); ++d) poses[d].push_back(Transform<double>(R, (hi + deltas[d] * r) * u));
        }

        for (std::size_t d = 0; d < std::size(deltas); ++d) {
            const auto& P = poses[d];
            std::vector<fcl::CollisionObjectd> fa_rss, fb_rss, fa_or, fb_or, fa_med, fb_med, fa_cen, fb_cen;
            for (const auto& p : P) {
                fa_rss.emplace_back(f_rss, fcl::Transform3d::Identity());
                fb_rss.emplace_back(f_rss, p.to_isometry());
                fa_or.emplace_back(f_obbrss, fcl::Transform3d::Identity());
                fb_or.emplace_back(f_obbrss, p.to_isometry());
                fa_med.emplace_back(f_rss_median, fcl::Transform3d::Identity());
                fb_med.emplace_back(f_rss_median, p.to_isometry());
                fa_cen.emplace_back(f_rss_center, fcl::Transform3d::Identity());
                fb_cen.emplace_back(f_rss_center, p.to_isometry());
            }
            auto cd = [&](const auto& model, double rel) {
                return [&, rel](std::size_t i) {
                    const auto res = distance(model, Transform<double>(), model, P[i], {rel, 0.0});
                    return Answer{res.distance, res.stats.bv_tests, res.stats.primitive_tests, res.stats.primitive_skips};
                };
            };
            // Mixed trees (bvh/mixed_descent.hpp): A's tree of one volume against B's of another.
            auto cd_mixed = [&](const auto& model_a, const auto& model_b) {
                return [&](std::size_t i) {
                    const auto res = distance(model_a, Transform<double>(), model_b, P[i]);
                    return Answer{res.distance, res.stats.bv_tests, res.stats.primitive_tests, res.stats.primitive_skips};
                };
            };
            auto fd = [&](std::vector<fcl::CollisionObjectd>& A, std::vector<fcl::CollisionObjectd>& B, double rel) {
                return [&, rel](std::size_t i) {
                    fcl::DistanceRequestd req(true, false, rel, 0.0);
                    fcl::DistanceResultd res;
                    fcl::distance(&A[i], &B[i], req, res);
                    return Answer{res.min_distance, 0, 0, 0};
                };
            };
            std::vector<Method> methods = {
                {"fcl_rss", "", "", fd(fa_rss, fb_rss, 0.0)},
                {"fcl_rss_median", "", "", fd(fa_med, fb_med, 0.0)},
                {"fcl_rss_bv_center", "", "", fd(fa_cen, fb_cen, 0.0)},
                {"fcl_obbrss", "", "", fd(fa_or, fb_or, 0.0)},
                {"cdkit_aabb", "fcl_rss", "fcl_obbrss", cd(m_aabb, 0.0)},
                {"cdkit_obb", "fcl_rss", "fcl_obbrss", cd(m_obb, 0.0)},
                {"cdkit_rss", "fcl_rss", "fcl_obbrss", cd(m_rss, 0.0)},
                {"cdkit_rss_f32", "fcl_rss", "fcl_obbrss", cd(m_rssf, 0.0)},
                {"cdkit_rss_leaf4", "fcl_rss", "fcl_obbrss", cd(m_rss4, 0.0)},
                {"cdkit_rss_median", "fcl_rss", "fcl_obbrss", cd(m_rss_median, 0.0)},
                {"cdkit_boxtree", "fcl_rss", "fcl_obbrss", cd(m_boxtree, 0.0)},
                {"cdkit_obb_x_rss", "fcl_rss", "fcl_obbrss", cd_mixed(m_obb, m_rss)},
                {"fcl_rss_rel0.01", "", "", fd(fa_rss, fb_rss, 0.01), 0.01},
                {"fcl_rss_median_rel0.01", "", "", fd(fa_med, fb_med, 0.01), 0.01},
                {"fcl_obbrss_rel0.01", "", "", fd(fa_or, fb_or, 0.01), 0.01},
                {"cdkit_aabb_rel0.01", "fcl_rss_rel0.01", "fcl_obbrss_rel0.01", cd(m_aabb, 0.01), 0.01},
                {"cdkit_obb_rel0.01", "fcl_rss_rel0.01", "fcl_obbrss_rel0.01", cd(m_obb, 0.01), 0.01},
                {"cdkit_rss_rel0.01", "fcl_rss_rel0.01", "fcl_obbrss_rel0.01", cd(m_rss, 0.01), 0.01},
                {"cdkit_rss_f32_rel0.01", "fcl_rss_rel0.01", "fcl_obbrss_rel0.01", cd(m_rssf, 0.01), 0.01},
            };
            if (!opt.filter.empty())  // keep the FCL peers and the methods named by --filter
                std::erase_if(methods, [&](const Method& m) {
                    return m.name.rfind("fcl_", 0) != 0 && m.name.find(opt.filter) == std::string::npos;
                });
            // The all-pairs reference on the first `brute` poses (NaN: over the candidate cap, unchecked).
            const std::size_t nb = std::min<std::size_t>(opt.brute, P.size());
            std::vector<double> brute(nb, std::nan(""));
            std::size_t unchecked = 0;
            for (std::size_t i = 0; i < nb; ++i) {
                const double reach = cd(m_rss, 0.0)(i).distance * (1 + 1e-6) + 1e-12 * r;
                const test::grid::PosedPair pp = test::grid::posed(*mesh, Transform<double>(), *mesh, P[i]);
                std::atomic<double> candidates{0};
                test::grid::grid_pairs(pp, reach, [&](Index, Index) { candidates.fetch_add(1, std::memory_order_relaxed); });
                if (candidates.load() > opt.brute_pairs) ++unchecked;
                else brute[i] = test::grid::grid_distance(pp, reach);
            }

            std::printf("\n-- %s  delta = %+.3f  (%zu poses, %zu checked against the all-pairs reference, %zu over its cap)\n",
                        name.c_str(), deltas[d], P.size(), nb - unchecked, unchecked);
            std::printf("%-24s %10s %10s %10s %10s %9s %9s %9s %10s %10s %12s %6s\n", "method", "median_us", "p99_us", "max_us",
                        "first_us", "R_rss", "R_obbrss", "R_best", "bv_tests", "tri_tests", "maxerr_brute", "wrong");
            const std::size_t M = methods.size();
            std::vector<std::vector<double>> us(M, std::vector<double>(P.size())), first(M, std::vector<double>(P.size()));
            std::vector<double> err(M, 0), bv(M, 0), tri(M, 0), skips(M, 0);
            std::vector<int> wrong(M, 0);
            for (std::size_t i = 0; i < P.size(); ++i)
                for (std::size_t j = 0; j < M; ++j) {
                    const std::size_t m = (j + i) % M;  // interleaved, in an order rotated from pose to pose
                    Answer ans{};
                    us[m][i] = time_warm(methods[m], i, first[m][i], ans);
                    bv[m] += double(ans.bv_tests), tri[m] += double(ans.tri_tests), skips[m] += double(ans.tri_skips);
                    if (i < nb && !std::isnan(brute[i])) {
                        const double e = ans.distance - brute[i];
                        err[m] = std::max(err[m], std::abs(e));
                        const double slack = 1e-9 * r;
                        wrong[m] += methods[m].rel == 0 ? std::abs(e) > slack
                                                        : (e < -slack || e > methods[m].rel * brute[i] + slack);
                    }
                }
            std::vector<double> medians(M);
            for (std::size_t m = 0; m < M; ++m) medians[m] = percentile(us[m], 0.5);
            for (std::size_t m = 0; m < M; ++m) {
                double ratio = 0, ratio2 = 0, best_fcl = 1e300;
                for (std::size_t q = 0; q < M; ++q) {
                    if (methods[q].name == methods[m].peer) ratio = medians[q] / medians[m];
                    if (methods[q].name == methods[m].peer2) ratio2 = medians[q] / medians[m];
                    if (methods[q].name.rfind("fcl_", 0) == 0 && methods[q].rel == methods[m].rel)
                        best_fcl = std::min(best_fcl, medians[q]);
                }
                const bool is_cdkit = methods[m].name.rfind("cdkit_", 0) == 0;
                const double ratio_best = is_cdkit ? best_fcl / medians[m] : 0;
                if (is_cdkit) cdkit_wrong += wrong[m];
                auto fmt = [](double x) { return x > 0 ? std::to_string(x).substr(0, 5) + "x" : std::string("-"); };
                const double n = double(P.size());
                const double first_med = percentile(first[m], 0.5);
                const double e = nb > unchecked ? err[m] : std::nan("");
                std::printf("%-24s %10.1f %10.1f %10.1f %10.1f %9s %9s %9s %10.0f %10.0f %12.3g %6d\n", methods[m].name.c_str(),
                            medians[m], percentile(us[m], 0.99), percentile(us[m], 1.0), first_med, fmt(ratio).c_str(),
                            fmt(ratio2).c_str(), fmt(ratio_best).c_str(), bv[m] / n, tri[m] / n, e, wrong[m]);
                if (csv)
                    std::fprintf(csv, "%s,%zu,%g,%s,%zu,%.3f,%.3f,%.3f,%.3f,%.4f,%.4f,%.4f,%.0f,%.0f,%.1f,%zu,%zu,%.3g,%d\n",
                                 name.c_str(), mesh->num_triangles(), deltas[d], methods[m].name.c_str(), P.size(), medians[m],
                                 percentile(us[m], 0.99), percentile(us[m], 1.0), first_med, ratio, ratio2, ratio_best,
                                 bv[m] / n, tri[m] / n, skips[m] / n, nb - unchecked, unchecked, e, wrong[m]);
            }
        }
    }
    if (csv) std::fclose(csv);
    std::printf("\nR_rss, R_obbrss = the FCL peer's median (RSS with FCL's default split, OBBRSS; same rel_err) / this "
                "method's median (> 1: cdkit faster); R_best against the fastest FCL row of the same rel_err. maxerr_brute: "
                "largest |distance - all-pairs reference|; wrong: answers off it.\n");
    if (cdkit_wrong > 0) std::printf("FAILED: %d cdkit answers off the all-pairs reference\n", cdkit_wrong);
    return cdkit_wrong > 0 ? 1 : 0;
}
