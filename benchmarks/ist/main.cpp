// cdkit_bench_ist: inner sphere trees on a closed mesh (default: the bundled bunny, scaled into [-1, 1]^3).
//
//  1. Coverage (sphere volume / mesh volume) and build time (packing + hierarchy) against the sphere count.
//  2. Penetration volume at P2 proximity poses (BENCHMARKS.md): R random rotations and directions u, bisection
//     to contact with cdkit::collide on the meshes, then B moved towards A by 5% of the bounding-box diagonal
//     (δ = −0.05). Per sphere count and out-degree (4, 8): median / p99 µs per query (thread CPU time,
//     batches of repetitions), node tests, overlapping pairs.
//  3. Error of the volume against a reference of vol(A ∩ B) of the meshes (mesh_intersection_volume: exact
//     lengths along jittered lines), checked by Monte Carlo (uniform samples in the intersection of the two
//     bounding boxes, exact inside tests): raw Σ lens volumes and the calibrated estimate (cell spheres),
//     median and max relative error over the poses; the time-critical mode's error, interval width and
//     bracketing against the node budget.
//  4. ist_query()'s one descent against the two traversals it replaced (penetration_volume, then
//     sphere_distance when no inner spheres overlap) at those poses and at separated ones (B moved 5% of the
//     diagonal away from contact, δ = +0.05): median µs, node tests, and whether the answers are bit for bit equal.
//
// Usage: cdkit_bench_ist [--quick] [--mesh PATH] [--poses N] [--samples N] [--lines N] [--csv PATH] [--plots DIR] [--gaps]
//   --quick: 1k and 10k spheres, 8 poses, 300k Monte Carlo samples, reference on a 128² line grid (under a
//   minute); default adds 100k spheres, 24 poses, 2M samples, a 256² line grid (8 jittered passes each).
//   --counts N,M,...: sphere counts instead of the mode's.
//   --depth-calibration, --no-depth-calibration, --calibration-iterations N, --calibration-strength A: set
//   PackingOptions::depth_calibration(_iterations, _strength) (default: the library's defaults; a negative
//   strength derives it from self-contacts); --contact-depth F sets PackingOptions::depth_calibration_contact_depth.
//   --plots DIR: instead, write the CSV files that benchmarks/ist/plot_ist.py draws (docs/images/ist_*.png):
//   the packing's cross-section at 1k and 10k spheres, the tree's levels 1-3, force and torque along a path.
//   --gaps: instead, where the packing leaves the mesh empty: per sphere count, uniform samples in the mesh
//   (--samples N in the bounding box, exact inside test) by depth below the surface in units of the packing's
//   sample spacing h, with the fraction of each depth layer that no sphere covers.
//   --lookahead K: PackingOptions::lookahead (default: the library's).
//   --packing: instead, per sphere count, the packing with the look-ahead (K) against without (0), in one
//   run: coverage, its first 1k spheres, and process CPU time (depth calibration off: it does not move the
//   spheres), with the ratios.
//   --out-of-sample: instead, the calibrated error where α was not derived (out_of_sample.cpp): per mesh (every
//   --mesh given; default the bunny, the Armadillo and, when fetched, the 871k dragon), sphere count (--counts,
//   default 1k and 10k) and δ ∈ −(--depths, default 0.01,0.05,0.2), α derived at the same depth (in-sample),
//   at the other depths, and on the other meshes; --poses (default 8) per δ, --lines (default 256), --csv.
#include "../thread_cpu_clock.hpp"
#include "out_of_sample.hpp"
#include "oracles/contact_poses.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/ist/inner_sphere_tree.hpp"
#include "cdkit/ist/inside_test.hpp"
#include "cdkit/ist/intersection_volume.hpp"
#include "cdkit/ist/ist_query.hpp"
#include "cdkit/ist/penalty_force.hpp"
#include "cdkit/ist/point_mesh_distance.hpp"
#include "cdkit/query.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

using namespace cdkit;

namespace {

double thread_seconds() { return cdbench::thread_cpu_seconds(); }
// CPU time of the whole process (the packing's TBB workers included): unlike wall time, it does not count
// the time spent descheduled on a shared machine.
double process_seconds() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}
double wall_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Median thread-CPU µs of f() over batches long enough for the clock.
template <class F> double time_us(F&& f) {
    int reps = 1;
    double elapsed = 0;
    while (true) {
        const double s = thread_seconds();
        for (int k = 0; k < reps; ++k) f();
        elapsed = thread_seconds() - s;
        if (elapsed > 2e-3 || reps >= 1 << 14) break;
        reps *= 4;
    }
    return 1e6 * elapsed / reps;
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5))];
}

struct Row {
    std::size_t spheres = 0;
    int degree = 0;
    double coverage = 0, pack_s = 0, pack_cpu_s = 0, tree_s = 0;
    std::size_t depth = 0, nodes = 0;
    double q_median = 0, q_p99 = 0, tests_median = 0, pairs_median = 0;
    double raw_err_median = 0, cal_err_median = 0, cal_err_max = 0, cal_bias = 0, alpha = 0;
};

// ist_query's one descent against the two traversals it replaces (penetration_volume, then sphere_distance
// when no inner spheres overlap), at the overlapping (δ = −0.05) and separated (δ = +0.05) poses.
struct TraversalRow {
    std::size_t spheres = 0;
    const char* poses = "";
    double one_median = 0, two_median = 0, one_tests = 0, two_tests = 0;
    int same = 0, total = 0;
};

/// Time-critical mode at one node budget (out-degree of the default tree), medians over the poses.
struct BudgetRow {
    std::size_t spheres = 0;
    std::uint64_t budget = 0;  // 0: unlimited (the exact query)
    double us = 0, node_tests = 0, cal_err = 0, width = 0;  // width: (upper − lower) / exact volume
    int bracketed = 0, complete = 0, total = 0;             // exact volume in [lower, upper]; finished
};

std::ofstream open_csv(const std::string& path) {
    std::ofstream f(path);
    if (!f) throw Error(path, "", "cannot open for writing");
    f.precision(9);
    return f;
}

// Cross-section of the mesh with the plane z = z0: one segment per crossing triangle.
void write_mesh_section(std::ofstream& f, const TriangleMesh<double>& mesh, double z0) {
    for (const Triangle& t : mesh.triangles) {
        Vec3<double> p[2];
        int n = 0;
        for (int k = 0; k < 3 && n < 2; ++k) {
            const Vec3<double>& u = mesh.vertices[t[k]];
            const Vec3<double>& v = mesh.vertices[t[(k + 1) % 3]];
            if ((u.z() < z0) == (v.z() < z0)) continue;
            p[n++] = u + (v - u) * ((z0 - u.z()) / (v.z() - u.z()));
        }
        if (n == 2) f << "segment," << p[0].x() << ',' << p[0].y() << ',' << p[1].x() << ',' << p[1].y() << '\n';
    }
}

// The plot data (see the file comment). The path is examples/ist_forces.cpp's: B comes in along -x from
// outside contact to x = 1.1, turning 0.5 rad about y, sampled at 1000 and at 250 steps.
void write_plot_data(const TriangleMesh<double>& mesh, const std::string& dir) {
    const double z0 = 0;
    InnerSphereTree tree10k;
    for (std::size_t count : {std::size_t(1000), std::size_t(10000)}) {
        PackingOptions po;
        po.max_spheres = count;
        IstBuildOptions bo;
        bo.out_degree = 8;
        InnerSphereTree tree(pack_spheres(mesh, po), bo);
        std::ofstream f = open_csv(dir + "/ist_section_" + std::to_string(count) + ".csv");
        f << "kind,x0,y0,x1_or_r,y1\n";
        for (const InnerSphere& s : tree.spheres()) {
            const double dz = s.center.z() - z0;
            if (std::abs(dz) < s.radius)
                f << "circle," << s.center.x() << ',' << s.center.y() << ',' << std::sqrt(s.radius * s.radius - dz * dz) << ",0\n";
        }
        write_mesh_section(f, mesh, z0);
        std::printf("%s: %zu spheres, coverage %.1f%%\n", (dir + "/ist_section_" + std::to_string(count) + ".csv").c_str(),
                    tree.spheres().size(), 100 * tree.coverage());
        if (count == 10000) tree10k = std::move(tree);
    }
    {   // Levels 1-3 (the root is level 0) of the 10k tree, projected onto the xy plane, over the mesh's projection.
        std::ofstream f = open_csv(dir + "/ist_levels.csv");
        f << "kind,level,x0,y0,x1_or_r,y1,x2,y2\n";
        const auto& nodes = tree10k.nodes();
        std::function<void(std::uint32_t, int)> walk = [&](std::uint32_t i, int level) {
            const IstNode& n = nodes[i];
            if (level >= 1) f << "sphere," << level << ',' << n.center.x() << ',' << n.center.y() << ',' << n.radius << ",0,0,0\n";
            if (level < 3)
                for (std::uint32_t j = n.first; j < n.first + n.count; ++j) walk(j, level + 1);
        };
        walk(0, 0);
        for (const Triangle& t : mesh.triangles) {
            f << "triangle,0";
            for (Index v : t) f << ',' << mesh.vertices[v].x() << ',' << mesh.vertices[v].y();
            f << '\n';
        }
    }
    {   // Force and torque on B along the path, 10k-sphere trees, stiffness 1.
        std::ofstream f = open_csv(dir + "/ist_path.csv");
        f << "steps,s,x,volume,pairs,force,torque,fx,fy,fz\n";
        for (int steps : {250, 1000}) {
            for (int i = 0; i <= steps; ++i) {
                const double s = double(i) / steps;
                const Transform<double> pb(Eigen::AngleAxisd(0.5 * s, Vec3<double>::UnitY()).toRotationMatrix(),
                                           Vec3<double>(1.8 - 0.7 * s, 0.1, 0.0));
                const auto v = penetration_volume(tree10k, {}, tree10k, pb);
                const auto w = penalty_wrench(v, tree10k, {}, tree10k, pb, 1.0, Vec3<double>::Zero(), pb.t);
                f << steps << ',' << s << ',' << pb.t.x() << ',' << v.volume << ',' << v.pairs.size() << ','
                  << w.on_b.force.norm() << ',' << w.on_b.torque.norm() << ',' << w.on_b.force.x() << ','
                  << w.on_b.force.y() << ',' << w.on_b.force.z() << '\n';
            }
        }
    }
}

}  // namespace

/// The --gaps table: the empty part of the mesh by depth (see the usage comment). Samples in the bounding
/// box, uniform (fixed seed); a sample is covered when it lies in a sphere (found through a hash grid of the
/// spheres' boxes, cells 2h wide); its depth is its exact distance to the surface.
/// The --packing table: look-ahead against none, same process, same counts (see the usage comment).
void print_packing_comparison(const TriangleMesh<double>& mesh, const std::vector<std::size_t>& counts, double lookahead) {
    std::printf("| spheres | look-ahead | coverage | first 1k | pack cpu s | spheres/s | coverage gain (points) | cpu ratio |\n"
                "|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (std::size_t count : counts) {
        double cov0 = 0, cpu0 = 0;
        for (double look : {0.0, lookahead}) {
            PackingOptions po;
            po.max_spheres = count;
            po.depth_calibration = false;
            po.lookahead = look;
            const double c0 = process_seconds();
            const SpherePacking p = pack_spheres(mesh, po);
            const double cpu = process_seconds() - c0;
            if (look == 0) cov0 = p.coverage(), cpu0 = cpu;
            std::printf("| %zu | %.2f | %.2f%% | %.2f%% | %.2f | %.0f | %+.2f | %.2f |\n", count, look, 100 * p.coverage(),
                        100 * p.coverage_of_first(1000), cpu, double(p.spheres.size()) / cpu, 100 * (p.coverage() - cov0),
                        cpu / cpu0);
            std::fflush(stdout);
        }
    }
}

void print_gap_profile(const TriangleMesh<double>& mesh, const std::vector<std::size_t>& counts, long samples,
                       const PackingOptions& base) {
    Vec3<double> lo = mesh.vertices[0], hi = lo;
    for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const InsideTest inside(mesh);
    const PointMeshDistance surface(mesh);
    constexpr int layers = 6;
    const double edges[layers] = {0.5, 1, 2, 4, 8, std::numeric_limits<double>::infinity()};
    const char* names[layers] = {"< 0.5h", "0.5–1h", "1–2h", "2–4h", "4–8h", "≥ 8h"};
    std::printf("| spheres | coverage | depth below the surface | share of the mesh volume | of it empty | empty, share of the mesh volume | share of all empty volume |\n"
                "|---:|---:|---|---:|---:|---:|---:|\n");
    for (std::size_t n : counts) {
        PackingOptions po = base;
        po.max_spheres = n;
        const SpherePacking p = pack_spheres(mesh, po);
        const double h = p.stats.grid_spacing, cell = 2 * h;
        auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
            return std::uint64_t(x & 0x1fffff) | (std::uint64_t(y & 0x1fffff) << 21) | (std::uint64_t(z & 0x1fffff) << 42);
        };
        auto cell_of = [&](double v, int k) { return std::int64_t(std::floor((v - lo[k]) / cell)); };
        std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
        for (std::size_t i = 0; i < p.spheres.size(); ++i) {
            const InnerSphere& s = p.spheres[i];
            for (std::int64_t z = cell_of(s.center.z() - s.radius, 2); z <= cell_of(s.center.z() + s.radius, 2); ++z)
                for (std::int64_t y = cell_of(s.center.y() - s.radius, 1); y <= cell_of(s.center.y() + s.radius, 1); ++y)
                    for (std::int64_t x = cell_of(s.center.x() - s.radius, 0); x <= cell_of(s.center.x() + s.radius, 0); ++x)
                        grid[key(x, y, z)].push_back(std::uint32_t(i));
        }
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> unit(0, 1);
        long in = 0, count[layers] = {}, empty[layers] = {};
        for (long k = 0; k < samples; ++k) {
            const Vec3<double> q(lo.x() + unit(rng) * (hi.x() - lo.x()), lo.y() + unit(rng) * (hi.y() - lo.y()),
                                 lo.z() + unit(rng) * (hi.z() - lo.z()));
            if (!inside.inside(q)) continue;
            ++in;
            const double depth = surface.query(q).distance / h;
            int layer = 0;
            while (depth >= edges[layer]) ++layer;
            ++count[layer];
            bool covered = false;
            const auto it = grid.find(key(cell_of(q.x(), 0), cell_of(q.y(), 1), cell_of(q.z(), 2)));
            if (it != grid.end())
                for (std::uint32_t i : it->second)
                    if ((q - p.spheres[i].center).squaredNorm() < p.spheres[i].radius * p.spheres[i].radius) { covered = true; break; }
            if (!covered) ++empty[layer];
        }
        long all_empty = 0;
        for (long e : empty) all_empty += e;
        for (int l = 0; l < layers; ++l)
            std::printf("| %zu | %.1f%% | %s | %.1f%% | %.1f%% | %.2f%% | %.0f%% |\n", n, 100 * p.coverage(), names[l],
                        100.0 * double(count[l]) / double(std::max(in, 1L)), count[l] ? 100.0 * double(empty[l]) / double(count[l]) : 0.0,
                        100.0 * double(empty[l]) / double(std::max(in, 1L)), 100.0 * double(empty[l]) / double(std::max(all_empty, 1L)));
        std::printf("| %zu | | all (%ld samples in the mesh, h = %.4g) | 100%% | %.1f%% | %.2f%% | 100%% |\n", n, in,
                    h, 100.0 * double(all_empty) / double(std::max(in, 1L)), 100.0 * double(all_empty) / double(std::max(in, 1L)));
        std::fflush(stdout);
    }
}

int main(int argc, char** argv) {
    bool quick = false;
    std::string mesh_path = std::string(CDKIT_BENCH_SOURCE_DIR) + "/data/bunny.obj", csv, plots;
    int poses = -1;
    bool depth_calibration = PackingOptions{}.depth_calibration;
    std::vector<std::size_t> user_counts;
    int calibration_iterations = PackingOptions{}.depth_calibration_iterations;
    double calibration_strength = PackingOptions{}.depth_calibration_strength;
    double contact_depth = 0;
    long samples = -1;
    int line_grid = -1;
    bool gaps = false, packing_only = false, out_of_sample = false;
    std::vector<std::string> meshes;
    std::vector<double> depths;
    double lookahead = PackingOptions{}.lookahead;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--quick") quick = true;
        else if (a == "--mesh" && i + 1 < argc) mesh_path = argv[++i], meshes.push_back(mesh_path);
        else if (a == "--poses" && i + 1 < argc) poses = std::atoi(argv[++i]);
        else if (a == "--samples" && i + 1 < argc) samples = std::atol(argv[++i]);
        else if (a == "--lines" && i + 1 < argc) line_grid = std::atoi(argv[++i]);
        else if (a == "--csv" && i + 1 < argc) csv = argv[++i];
        else if (a == "--plots" && i + 1 < argc) plots = argv[++i];
        else if (a == "--gaps") gaps = true;
        else if (a == "--no-depth-calibration") depth_calibration = false;
        else if (a == "--depth-calibration") depth_calibration = true;
        else if (a == "--counts" && i + 1 < argc) {
            for (const char* p = argv[++i]; *p;) {
                char* end = nullptr;
                user_counts.push_back(std::size_t(std::strtoul(p, &end, 10)));
                p = *end == ',' ? end + 1 : end;
                if (end == p && *p) break;
            }
        }
        else if (a == "--calibration-iterations" && i + 1 < argc) calibration_iterations = std::atoi(argv[++i]);
        else if (a == "--calibration-strength" && i + 1 < argc) calibration_strength = std::atof(argv[++i]);
        else if (a == "--contact-depth" && i + 1 < argc) contact_depth = std::atof(argv[++i]);
        else if (a == "--lookahead" && i + 1 < argc) lookahead = std::atof(argv[++i]);
        else if (a == "--packing") packing_only = true;
        else if (a == "--out-of-sample") out_of_sample = true;
        else if (a == "--depths" && i + 1 < argc) {
            for (const char* p = argv[++i]; *p;) {
                char* end = nullptr;
                depths.push_back(std::strtod(p, &end));
                if (end == p) break;
                p = *end == ',' ? end + 1 : end;
            }
        }
        else {
            std::fprintf(stderr, "usage: cdkit_bench_ist [--quick] [--mesh PATH] [--poses N] [--samples N] [--lines N] [--csv PATH] [--plots DIR] [--gaps]\n"
                         "                       [--counts N,M,...] [--[no-]depth-calibration] [--calibration-iterations N]\n"
                         "                       [--calibration-strength A] [--contact-depth F] [--lookahead K] [--packing]\n"
                         "                       [--out-of-sample [--depths F,G,...]]\n");
            return 2;
        }
    }
    if (out_of_sample) {
        cdbench::OutOfSampleOptions o;
        o.meshes = meshes;
        if (o.meshes.empty()) {
            const std::string data = std::string(CDKIT_BENCH_SOURCE_DIR) + "/data/";
            o.meshes = {data + "bunny.obj", data + "armadillo.obj"};
            if (std::ifstream(data + "dragon/dragon_871k.ply")) o.meshes.push_back(data + "dragon/dragon_871k.ply");
        }
        o.counts = !user_counts.empty() ? user_counts : std::vector<std::size_t>{1000, 10000};
        if (!depths.empty()) o.depths = depths;
        if (poses > 0) o.poses = poses;
        if (line_grid > 0) o.line_grid = line_grid;
        o.csv = csv;
        try {
            return cdbench::run_out_of_sample(o, argc, argv);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "cdkit_bench_ist: %s\n", e.what());
            return 1;
        }
    }
    if (poses < 0) poses = quick ? 8 : 24;
    if (samples < 0) samples = quick ? 300000 : 2000000;
    if (line_grid < 0) line_grid = quick ? 128 : 256;
    const std::vector<std::size_t> counts = !user_counts.empty() ? user_counts
                                            : quick ? std::vector<std::size_t>{1000, 10000}
                                                    : std::vector<std::size_t>{1000, 10000, 100000};
    try {
        TriangleMesh<double> mesh = load_mesh(mesh_path);
        Vec3<double> lo = mesh.vertices[0], hi = lo;
        for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
        for (auto& v : mesh.vertices) v = (v - (lo + hi) / 2) * (2 / (hi - lo).maxCoeff());
        lo = hi = mesh.vertices[0];
        for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
        const double diag = (hi - lo).norm();
        if (!plots.empty()) {
            write_plot_data(mesh, plots);
            return 0;
        }
        if (packing_only) {
            std::printf("# cdkit_bench_ist --packing: %s (%zu triangles)\n\n", mesh_path.c_str(), mesh.triangles.size());
            print_packing_comparison(mesh, counts, lookahead);
            return 0;
        }
        if (gaps) {
            PackingOptions po;
            po.lookahead = lookahead;
            po.depth_calibration = false;  // the spheres do not depend on it
            std::printf("# cdkit_bench_ist --gaps: %s (%zu triangles), %ld samples in the bounding box\n\n", mesh_path.c_str(),
                        mesh.triangles.size(), samples);
            print_gap_profile(mesh, counts, samples, po);
            return 0;
        }
        std::printf("# cdkit_bench_ist: %s (%zu triangles), %d poses at δ = -0.05 (depth %.4f), %ld MC samples (check), %d² reference lines%s\n\n",
                    mesh_path.c_str(), mesh.triangles.size(), poses, 0.05 * diag, samples, line_grid, quick ? " (--quick)" : "");

        // Poses: bisection to contact on the meshes, then 5% of the diagonal deeper (oracles/contact_poses.hpp).
        const InsideTest inside(mesh);
        std::mt19937_64 rng(2024);  // the poses, then the Monte Carlo check's samples
        std::vector<Transform<double>> pose_b, pose_apart;
        for (const test::ContactPose& p : test::contact_poses(mesh, diag, poses, rng)) {
            pose_b.push_back(test::pose_past_contact(p, diag, 0.05));
            pose_apart.push_back(test::pose_past_contact(p, diag, -0.05));
        }
        // Reference of vol(A ∩ B) per pose: integration along lines (ist/intersection_volume.hpp), checked
        // against plain Monte Carlo (uniform samples in the boxes' overlap, exact inside tests).
        std::vector<double> reference(poses), ref_err(poses), mc_err(poses), mc_z(poses);
        double t_lines = 0, t_mc = 0;
        for (int i = 0; i < poses; ++i) {
            double t0 = wall_seconds();
            TriangleMesh<double> moved = mesh;
            for (auto& v : moved.vertices) v = pose_b[i] * v;
            const InsideTest inside_b(std::move(moved));
            const IntersectionVolume lines =
                mesh_intersection_volume(inside, inside_b, {.grid = line_grid, .passes = 8, .seed = std::uint64_t(i + 1)});
            reference[i] = lines.volume;
            ref_err[i] = lines.volume > 0 ? lines.standard_error / lines.volume : 1.0;  // relative standard error
            t_lines += wall_seconds() - t0;

            t0 = wall_seconds();
            Vec3<double> blo = Vec3<double>::Constant(1e300), bhi = -blo;
            for (const auto& v : inside_b.mesh().vertices) blo = blo.cwiseMin(v), bhi = bhi.cwiseMax(v);
            blo = blo.cwiseMax(lo), bhi = bhi.cwiseMin(hi);
            const Vec3<double> ext = (bhi - blo).cwiseMax(0.0);
            std::uniform_real_distribution<double> u01(0, 1);
            long hits = 0;
            for (long k = 0; k < samples; ++k) {
                const Vec3<double> p = blo + Vec3<double>(u01(rng), u01(rng), u01(rng)).cwiseProduct(ext);
                hits += inside.inside(p) && inside_b.inside(p);
            }
            const double f = double(hits) / double(samples), mc = f * ext.prod();
            const double sigma = std::sqrt(f * (1 - f) / double(samples)) * ext.prod();
            mc_err[i] = hits ? sigma / mc : 1.0;
            mc_z[i] = std::abs(mc - lines.volume) / std::hypot(sigma, lines.standard_error);
            t_mc += wall_seconds() - t0;
        }
        std::printf("Reference (lines along x, %d × %d grid, 8 jittered passes): %.1f s, median relative standard "
                    "error %.3f%%, max %.3f%%\n",
                    line_grid, line_grid, t_lines, 100 * quantile(ref_err, 0.5), 100 * quantile(ref_err, 1.0));
        std::printf("Monte Carlo check (%ld samples): %.1f s, median relative standard error %.2f%%; |MC − reference| "
                    "/ σ: median %.2f (0.67 expected), max %.2f\n\n",
                    samples, t_mc, 100 * quantile(mc_err, 0.5), quantile(mc_z, 0.5), quantile(mc_z, 1.0));

        std::vector<Row> rows;
        std::vector<TraversalRow> traversal_rows;
        std::vector<BudgetRow> budget_rows;
        struct CurvePoint { std::size_t packing, spheres; double coverage; };
        std::vector<CurvePoint> curve;
        for (std::size_t count : counts) {
            PackingOptions po;
            po.max_spheres = count;
            po.lookahead = lookahead;
            po.depth_calibration = depth_calibration;
            po.depth_calibration_iterations = calibration_iterations;
            po.depth_calibration_strength = calibration_strength;
            if (contact_depth > 0) po.depth_calibration_contact_depth = contact_depth;
            const double t0 = wall_seconds(), c0 = process_seconds();
            const SpherePacking packing = pack_spheres(mesh, po);
            const double pack_s = wall_seconds() - t0, pack_cpu_s = process_seconds() - c0;
            for (std::size_t n = 100; n < count; n *= 10) {
                curve.push_back({count, n, packing.coverage_of_first(n)});
                if (3 * n < count) curve.push_back({count, 3 * n, packing.coverage_of_first(3 * n)});
            }
            curve.push_back({count, count, packing.coverage()});
            for (int degree : {4, 8}) {
                IstBuildOptions bo;
                bo.out_degree = degree;
                const double t1 = wall_seconds();
                const InnerSphereTree tree(packing, bo);
                Row row;
                row.tree_s = wall_seconds() - t1;
                row.pack_s = pack_s;
                row.pack_cpu_s = pack_cpu_s;
                row.spheres = tree.spheres().size();
                row.degree = degree;
                row.coverage = tree.coverage();
                row.alpha = packing.calibration_strength;
                row.depth = tree.stats().depth;
                row.nodes = tree.nodes().size();
                std::vector<double> times, tests, pairs, raw_err, cal_err;
                double bias = 0;
                for (int i = 0; i < poses; ++i) {
                    PenetrationVolumeResult r = penetration_volume(tree, {}, tree, pose_b[i]);
                    int reps = 1;
                    double elapsed = 0;
                    while (true) {  // batches long enough for the clock
                        const double s = thread_seconds();
                        for (int k = 0; k < reps; ++k) r = penetration_volume(tree, {}, tree, pose_b[i]);
                        elapsed = thread_seconds() - s;
                        if (elapsed > 2e-3 || reps >= 1 << 14) break;
                        reps *= 4;
                    }
                    times.push_back(1e6 * elapsed / reps);
                    tests.push_back(double(r.stats.node_tests));
                    pairs.push_back(double(r.pairs.size()));
                    if (reference[i] > 0) {
                        raw_err.push_back(std::abs(r.volume - reference[i]) / reference[i]);
                        cal_err.push_back(std::abs(r.calibrated - reference[i]) / reference[i]);
                        bias += (r.calibrated - reference[i]) / reference[i];
                    }
                }
                row.q_median = quantile(times, 0.5);
                row.q_p99 = quantile(times, 0.99);
                row.tests_median = quantile(tests, 0.5);
                row.pairs_median = quantile(pairs, 0.5);
                row.raw_err_median = quantile(raw_err, 0.5);
                row.cal_err_median = quantile(cal_err, 0.5);
                row.cal_err_max = quantile(cal_err, 1.0);
                row.cal_bias = cal_err.empty() ? 0 : bias / double(cal_err.size());
                rows.push_back(row);
                if (degree != IstBuildOptions{}.out_degree) continue;
                std::vector<double> exact_volume(static_cast<std::size_t>(poses));
                for (int i = 0; i < poses; ++i) exact_volume[std::size_t(i)] = penetration_volume(tree, {}, tree, pose_b[i]).volume;
                for (std::uint64_t budget : {std::uint64_t(100), std::uint64_t(300), std::uint64_t(1000),
                                             std::uint64_t(3000), std::uint64_t(10000), std::uint64_t(0)}) {
                    BudgetRow br;
                    br.spheres = row.spheres;
                    br.budget = budget;
                    std::vector<double> us, nt, err, width;
                    for (int i = 0; i < poses; ++i) {
                        const double exact = exact_volume[std::size_t(i)];
                        PenetrationVolumeResult r;
                        IstRequest req;
                        req.max_node_tests = budget;
                        req.collect_pairs = false;
                        us.push_back(time_us([&] { r = penetration_volume(tree, {}, tree, pose_b[i], req); }));
                        nt.push_back(double(r.stats.node_tests));
                        if (reference[i] > 0) err.push_back(std::abs(r.calibrated - reference[i]) / reference[i]);
                        if (exact > 0) width.push_back((r.volume_upper - r.volume_lower) / exact);
                        // The exact query sums in another order: allow its rounding.
                        const double slack = 1e-12 * exact;
                        br.bracketed += r.volume_lower <= exact + slack && exact - slack <= r.volume_upper;
                        br.complete += r.complete;
                        ++br.total;
                    }
                    br.us = quantile(us, 0.5);
                    br.node_tests = quantile(nt, 0.5);
                    br.cal_err = quantile(err, 0.5);
                    br.width = quantile(width, 0.5);
                    budget_rows.push_back(br);
                }
                for (const auto* set : {&pose_b, &pose_apart}) {
                    TraversalRow tr;
                    tr.spheres = row.spheres;
                    tr.poses = set == &pose_b ? "overlapping (δ = -0.05)" : "separated (δ = +0.05)";
                    std::vector<double> one, two, one_tests, two_tests;
                    for (const auto& pb : *set) {
                        IstQueryResult q1, q2;
                        one.push_back(time_us([&] { q1 = ist_query(tree, {}, tree, pb); }));
                        two.push_back(time_us([&] {  // the former ist_query: volume, then distance if apart
                            q2 = {};
                            q2.volume = penetration_volume(tree, {}, tree, pb);
                            q2.stats = q2.volume.stats;
                            if (q2.volume.volume_lower == 0) {
                                q2.distance = sphere_distance(tree, {}, tree, pb);
                                q2.stats.node_tests += q2.distance.stats.node_tests;
                            }
                        }));
                        one_tests.push_back(double(q1.stats.node_tests));
                        two_tests.push_back(double(q2.stats.node_tests));
                        tr.same += q1.volume.volume == q2.volume.volume && q1.volume.calibrated == q2.volume.calibrated &&
                                   (q1.volume.volume > 0 || q1.distance.distance == q2.distance.distance);
                        ++tr.total;
                    }
                    tr.one_median = quantile(one, 0.5);
                    tr.two_median = quantile(two, 0.5);
                    tr.one_tests = quantile(one_tests, 0.5);
                    tr.two_tests = quantile(two_tests, 0.5);
                    traversal_rows.push_back(tr);
                }
            }
        }

        std::printf("## Coverage against sphere count\n\nA packing for max_spheres = N; its first n spheres (the greedy "
                    "prefix) cover the fraction shown.\n\n| packing N | first n spheres | coverage |\n|---:|---:|---:|\n");
        for (const auto& c : curve) std::printf("| %zu | %zu | %.1f%% |\n", c.packing, c.spheres, 100 * c.coverage);
        std::printf("\n## Build, volume query at δ = -0.05, error against the line reference\n\n");
        std::printf("| spheres | out-degree | coverage | pack s | pack cpu s | tree s | depth | nodes | query median µs | p99 µs | "
                    "node tests | pairs | raw error (median) | calibrated error (median) | calibrated error (max) | calibrated bias (mean signed) | α |\n");
        std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for (const Row& r : rows)
            std::printf("| %zu | %d | %.1f%% | %.2f | %.2f | %.3f | %zu | %zu | %.1f | %.1f | %.0f | %.0f | %.1f%% | %.1f%% | %.1f%% | %+.1f%% | %.2f |\n",
                        r.spheres, r.degree, 100 * r.coverage, r.pack_s, r.pack_cpu_s, r.tree_s, r.depth, r.nodes, r.q_median, r.q_p99,
                        r.tests_median, r.pairs_median, 100 * r.raw_err_median, 100 * r.cal_err_median, 100 * r.cal_err_max, 100 * r.cal_bias, r.alpha);
        std::printf("\n## Time-critical mode at δ = -0.05 (out-degree %d)\n\n"
                    "penetration_volume() with IstRequest::max_node_tests = budget (0: unlimited), no pair list; medians over "
                    "the poses: thread-CPU µs, node tests, |calibrated − reference| / reference, the guaranteed interval's "
                    "width (upper − lower) / exact volume; \"bracketed\": poses whose exact volume lies in [lower, upper].\n\n"
                    "| spheres | budget | µs | node tests | calibrated error | interval width | bracketed | complete |\n"
                    "|---:|---:|---:|---:|---:|---:|---:|---:|\n", IstBuildOptions{}.out_degree);
        for (const BudgetRow& b : budget_rows)
            std::printf("| %zu | %s | %.1f | %.0f | %.1f%% | %.1f%% | %d/%d | %d/%d |\n", b.spheres,
                        b.budget ? std::to_string(b.budget).c_str() : "∞", b.us, b.node_tests, 100 * b.cal_err,
                        100 * b.width, b.bracketed, b.total, b.complete, b.total);
        std::printf("\n## ist_query: one descent against the two traversals (out-degree %d)\n\n"
                    "Median thread-CPU µs per query over the poses; \"same\": poses where volume, calibrated volume and "
                    "(when apart) distance are bit for bit equal.\n\n"
                    "| spheres | poses | one descent µs | two traversals µs | ratio (one / two) | node tests (one) | node tests (two) | same |\n"
                    "|---:|---|---:|---:|---:|---:|---:|---:|\n", IstBuildOptions{}.out_degree);
        for (const TraversalRow& t : traversal_rows)
            std::printf("| %zu | %s | %.1f | %.1f | %.2f | %.0f | %.0f | %d/%d |\n", t.spheres, t.poses, t.one_median,
                        t.two_median, t.one_median / t.two_median, t.one_tests, t.two_tests, t.same, t.total);
        if (!csv.empty()) {
            std::ofstream f(csv);
            if (!f) throw Error(csv, "", "cannot open for writing");
            f << "spheres,out_degree,coverage,pack_s,pack_cpu_s,tree_s,depth,nodes,query_median_us,query_p99_us,node_tests_median,"
                 "pairs_median,raw_rel_err_median,cal_rel_err_median,cal_rel_err_max,cal_rel_bias,alpha\n";
            for (const Row& r : rows)
                f << r.spheres << ',' << r.degree << ',' << r.coverage << ',' << r.pack_s << ',' << r.pack_cpu_s << ',' << r.tree_s << ','
                  << r.depth << ',' << r.nodes << ',' << r.q_median << ',' << r.q_p99 << ',' << r.tests_median << ','
                  << r.pairs_median << ',' << r.raw_err_median << ',' << r.cal_err_median << ',' << r.cal_err_max << ',' << r.cal_bias << ',' << r.alpha << '\n';
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cdkit_bench_ist: %s\n", e.what());
        return 1;
    }
}
