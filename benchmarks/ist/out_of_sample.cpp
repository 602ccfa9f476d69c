// cdkit_bench_ist --out-of-sample (issue 37, item 3): the error of the calibrated penetration volume where the
// depth calibration's strength α was not derived.
//
// By default α comes from the object's own self-contacts pushed depth_calibration_contact_depth = 0.05 of the
// box diagonal past first contact, the depth at which the main run reports the error (δ = −0.05): that error
// is in-sample. Here, per closed mesh (scaled into [-1, 1]^3) and sphere count:
//
//   * α is derived (PackingOptions::derived_strength) at each contact depth c of --depths (default 0.01,
//     0.05, 0.2): one packing per c, the same spheres, only the weights differ;
//   * P2 poses as in the main run (the same generator: seed 2024, random rotation and direction u, bisection
//     to contact with collide() on the meshes), each evaluated at every δ = −c: B moved c·diagonal past contact;
//   * reference: mesh_intersection_volume (lines along x, a --lines² grid (default 256²), 8 jittered passes);
//   * the calibrated estimate of penetration_volume() (out-degree 8) with α from:
//       in-sample    this mesh, derived at c = |δ|;
//       other depth  this mesh, derived at another c (the default c = 0.05 evaluated at δ = −0.01 and −0.2 is
//                    what a user of the defaults gets there);
//       other mesh   another mesh of the run, derived at c = |δ| and the same sphere count, given to this mesh
//                    as a fixed α (PackingOptions::depth_calibration_strength = α: one more packing).
//
// Per row: median and max |relative error|, mean signed and mean |relative error| over the poses; beside it the
// in-sample row's median and mean signed, and those of the plain cell weights (no depth calibration, α = 0:
// one more packing) at the same mesh, count and δ.
#include "out_of_sample.hpp"

#include "oracles/contact_poses.hpp"

#include "../provenance.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/ist/inner_sphere_tree.hpp"
#include "cdkit/ist/inside_test.hpp"
#include "cdkit/ist/intersection_volume.hpp"
#include "cdkit/ist/ist_query.hpp"
#include "cdkit/query.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace cdbench {

using namespace cdkit;

namespace {

double wall_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median_of(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

/// One mesh: scaled into [-1, 1]^3 as the main run does, its poses and references per δ.
struct MeshCase {
    std::string label;  // the file's stem (no commas: it is a CSV field)
    TriangleMesh<double> mesh;
    double diag = 0;
    std::vector<std::vector<Transform<double>>> pose;  // [depth][pose]
    std::vector<std::vector<double>> reference;        // [depth][pose]
    std::vector<double> ref_rel_se_max;                // [depth]: largest relative standard error of the reference
};

MeshCase load_case(const std::string& path, const std::vector<double>& depths, int pose_count, int line_grid) {
    MeshCase m;
    m.label = std::filesystem::path(path).stem().string();
    m.mesh = load_mesh(path);
    Vec3<double> lo = m.mesh.vertices[0], hi = lo;
    for (const auto& v : m.mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    for (auto& v : m.mesh.vertices) v = (v - (lo + hi) / 2) * (2 / (hi - lo).maxCoeff());
    lo = hi = m.mesh.vertices[0];
    for (const auto& v : m.mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    m.diag = (hi - lo).norm();

    // The main run's pose generator (benchmarks/ist/main.cpp): the same seed, the same draws; the test that bounds
    // these figures (tests/ist/test_ist_accuracy.cpp) draws them through the same header.
    const std::vector<test::ContactPose> poses = test::contact_poses(m.mesh, m.diag, pose_count);
    const InsideTest inside(m.mesh);
    m.pose.resize(depths.size());
    m.reference.resize(depths.size());
    m.ref_rel_se_max.assign(depths.size(), 0.0);
    for (std::size_t k = 0; k < depths.size(); ++k)
        for (int i = 0; i < pose_count; ++i) {
            const Transform<double> pb = test::pose_past_contact(poses[std::size_t(i)], m.diag, depths[k]);
            TriangleMesh<double> moved = m.mesh;
            for (auto& v : moved.vertices) v = pb * v;
            const IntersectionVolume r = mesh_intersection_volume(
                inside, InsideTest(std::move(moved)), {.grid = line_grid, .passes = 8, .seed = std::uint64_t(1000 * k + std::size_t(i) + 1)});
            m.pose[k].push_back(pb);
            m.reference[k].push_back(r.volume);
            if (r.volume > 0) m.ref_rel_se_max[k] = std::max(m.ref_rel_se_max[k], r.standard_error / r.volume);
        }
    return m;
}

struct Errors {
    int poses = 0;
    double median_abs = 0, max_abs = 0, mean_signed = 0, mean_abs = 0;
};

Errors evaluate(const InnerSphereTree& tree, const std::vector<Transform<double>>& poses, const std::vector<double>& reference) {
    std::vector<double> abs_err;
    Errors e;
    for (std::size_t i = 0; i < poses.size(); ++i) {
        if (!(reference[i] > 0)) continue;
        const double rel = (penetration_volume(tree, {}, tree, poses[i]).calibrated - reference[i]) / reference[i];
        abs_err.push_back(std::abs(rel));
        e.mean_signed += rel;
        e.mean_abs += std::abs(rel);
        e.max_abs = std::max(e.max_abs, std::abs(rel));
    }
    e.poses = int(abs_err.size());
    if (e.poses) e.mean_signed /= e.poses, e.mean_abs /= e.poses;
    e.median_abs = median_of(abs_err);
    return e;
}

struct Row {
    std::string mesh;
    std::size_t spheres = 0;
    double delta = 0;
    std::string kind, alpha_mesh;
    double alpha_depth = 0, alpha = 0;
    Errors err;
    Errors in_sample;  // the in-sample row of the same mesh, count and δ
    Errors plain;      // the plain cell weights (α = 0) at the same mesh, count and δ
};

InnerSphereTree tree_of(const TriangleMesh<double>& mesh, std::size_t count, double strength, double contact_depth, double* alpha) {
    PackingOptions po;
    po.max_spheres = count;
    po.depth_calibration_strength = strength;
    po.depth_calibration_contact_depth = contact_depth;
    SpherePacking packing = pack_spheres(mesh, po);
    if (alpha) *alpha = packing.calibration_strength;
    return InnerSphereTree(std::move(packing), IstBuildOptions{});
}

}  // namespace

int run_out_of_sample(const OutOfSampleOptions& o, int argc, char** argv) {
    const std::size_t D = o.depths.size();
    std::printf("# cdkit_bench_ist --out-of-sample: %zu meshes, %d poses per δ, reference on %d² lines × 8 passes\n\n",
                o.meshes.size(), o.poses, o.line_grid);
    std::vector<MeshCase> cases;
    for (const std::string& path : o.meshes) {
        const double t0 = wall_seconds();
        cases.push_back(load_case(path, o.depths, o.poses, o.line_grid));
        std::printf("%s: %zu triangles, poses and references %.1f s; largest relative standard error of the reference per δ:",
                    cases.back().label.c_str(), cases.back().mesh.triangles.size(), wall_seconds() - t0);
        for (std::size_t k = 0; k < D; ++k) std::printf(" %.3f%% (δ = -%g)", 100 * cases.back().ref_rel_se_max[k], o.depths[k]);
        std::printf("\n");
        std::fflush(stdout);
    }

    std::vector<Row> rows;
    std::map<std::tuple<std::string, std::size_t, double>, Errors> plain;  // (mesh, spheres, δ)
    std::printf("\n## Derived α per contact depth c\n\n| mesh | spheres |");
    for (double c : o.depths) std::printf(" α (c = %g) |", c);
    std::printf(" pack s (all) |\n|---|---:|");
    for (std::size_t k = 0; k < D; ++k) std::printf("---:|");
    std::printf("---:|\n");
    for (std::size_t count : o.counts) {
        // alpha[m][c]: mesh m's α derived at contact depth c.
        std::vector<std::vector<double>> alpha(cases.size(), std::vector<double>(D));
        for (std::size_t m = 0; m < cases.size(); ++m) {
            const MeshCase& mc = cases[m];
            const double t0 = wall_seconds();
            std::vector<InnerSphereTree> own(D);
            for (std::size_t c = 0; c < D; ++c)
                own[c] = tree_of(mc.mesh, count, PackingOptions::derived_strength, o.depths[c], &alpha[m][c]);
            std::printf("| %s | %zu |", mc.label.c_str(), own[0].spheres().size());
            for (std::size_t c = 0; c < D; ++c) std::printf(" %.3f |", alpha[m][c]);
            std::printf(" %.1f |\n", wall_seconds() - t0);
            std::fflush(stdout);
            const InnerSphereTree zero = tree_of(mc.mesh, count, 0.0, o.depths[0], nullptr);
            for (std::size_t k = 0; k < D; ++k)
                plain[{mc.label, zero.spheres().size(), -o.depths[k]}] = evaluate(zero, mc.pose[k], mc.reference[k]);
            for (std::size_t k = 0; k < D; ++k)
                for (std::size_t c = 0; c < D; ++c) {
                    Row r{mc.label, own[c].spheres().size(), -o.depths[k], c == k ? "in-sample" : "other depth", mc.label,
                          o.depths[c], alpha[m][c], evaluate(own[c], mc.pose[k], mc.reference[k]), {}, {}};
                    rows.push_back(r);
                }
        }
        // Other meshes' α, derived at the evaluated depth, given as a fixed strength.
        for (std::size_t m = 0; m < cases.size(); ++m)
            for (std::size_t src = 0; src < cases.size(); ++src) {
                if (src == m) continue;
                for (std::size_t k = 0; k < D; ++k) {
                    const InnerSphereTree t = tree_of(cases[m].mesh, count, alpha[src][k], o.depths[k], nullptr);
                    rows.push_back({cases[m].label, t.spheres().size(), -o.depths[k], "other mesh", cases[src].label,
                                    o.depths[k], alpha[src][k], evaluate(t, cases[m].pose[k], cases[m].reference[k]), {}, {}});
                }
            }
    }
    for (Row& r : rows)
        for (const Row& s : rows)
            if (s.kind == "in-sample" && s.mesh == r.mesh && s.spheres == r.spheres && s.delta == r.delta) r.in_sample = s.err;
    for (Row& r : rows) r.plain = plain.at({r.mesh, r.spheres, r.delta});
    std::stable_sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) {
        auto rank = [](const std::string& k) { return k == "in-sample" ? 0 : k == "other depth" ? 1 : 2; };
        return std::make_tuple(a.mesh, a.spheres, -a.delta, rank(a.kind)) < std::make_tuple(b.mesh, b.spheres, -b.delta, rank(b.kind));
    });

    std::printf("\n## Calibrated error against the line reference, by the source of α\n\n"
                "|relative error| median / max, mean signed, mean |error| over the poses; the in-sample row's and the plain "
                "cell weights' (α = 0) median and mean signed beside.\n\n"
                "| mesh | spheres | δ | α from | α mesh | α depth c | α | poses | median | max | mean signed | mean abs | in-sample median | in-sample mean signed | plain median | plain mean signed |\n"
                "|---|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const Row& r : rows)
        std::printf("| %s | %zu | %g | %s | %s | %g | %.3f | %d | %.1f%% | %.1f%% | %+.1f%% | %.1f%% | %.1f%% | %+.1f%% | %.1f%% | %+.1f%% |\n",
                    r.mesh.c_str(), r.spheres, r.delta, r.kind.c_str(), r.alpha_mesh.c_str(), r.alpha_depth, r.alpha, r.err.poses,
                    100 * r.err.median_abs, 100 * r.err.max_abs, 100 * r.err.mean_signed, 100 * r.err.mean_abs,
                    100 * r.in_sample.median_abs, 100 * r.in_sample.mean_signed, 100 * r.plain.median_abs, 100 * r.plain.mean_signed);
    if (!o.csv.empty()) {
        std::FILE* f = std::fopen(o.csv.c_str(), "w");
        if (!f) throw Error(o.csv, "", "cannot open for writing");
        write_provenance(f, argc, argv);
        std::fprintf(f, "mesh,spheres,delta,alpha_from,alpha_mesh,alpha_depth,alpha,poses,median_pct,max_pct,mean_signed_pct,"
                        "mean_abs_pct,in_sample_median_pct,in_sample_mean_signed_pct,plain_median_pct,plain_mean_signed_pct\n");
        for (const Row& r : rows)
            std::fprintf(f, "%s,%zu,%g,%s,%s,%g,%.3f,%d,%.1f,%.1f,%+.1f,%.1f,%.1f,%+.1f,%.1f,%+.1f\n", r.mesh.c_str(), r.spheres, r.delta,
                         r.kind.c_str(), r.alpha_mesh.c_str(), r.alpha_depth, r.alpha, r.err.poses, 100 * r.err.median_abs,
                         100 * r.err.max_abs, 100 * r.err.mean_signed, 100 * r.err.mean_abs, 100 * r.in_sample.median_abs,
                         100 * r.in_sample.mean_signed, 100 * r.plain.median_abs, 100 * r.plain.mean_signed);
        std::fclose(f);
    }
    return 0;
}

}  // namespace cdbench
