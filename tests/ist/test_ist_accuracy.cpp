// Calibrated penetration volume against the line-integral reference of the meshes' intersection at shallow
// contacts (P2 poses at δ = −0.05, as in cdkit_bench_ist, with fewer spheres, poses and lines): the
// calibration must beat the raw Σ lens volume by far, and the default depth calibration must move the
// plain cell weights' mean error (low: the surface layer's gaps) towards zero. Out of sample (issue 37): the
// default α at δ = −0.01 and −0.2, and another mesh's α, within 1.5× of the figures in
// results/ist_out_of_sample.csv.
#include "ist_test_util.hpp"
#include "oracles/contact_poses.hpp"

#include "cdkit/bv/obb.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/ist/inside_test.hpp"
#include "cdkit/ist/intersection_volume.hpp"
#include "cdkit/query.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace cdkit;
using cdkit::test::scaled;

TEST_CASE("calibrated volume against the line reference at shallow contacts; depth calibration reduces the bias", "[ist][accuracy]") {
    const auto mesh = test::unit_bunny();
    PackingOptions o;
    o.max_spheres = 1000;
    o.depth_calibration = false;
    const InnerSphereTree plain = build_inner_sphere_tree(mesh, o);
    const InnerSphereTree calibrated = build_inner_sphere_tree(mesh, PackingOptions{.max_spheres = 1000});
    REQUIRE(plain.spheres().size() == calibrated.spheres().size());

    const MeshModel<Obb<double>> model(mesh);
    const InsideTest inside(mesh);
    Vec3<double> lo = mesh.vertices[0], hi = lo;
    for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double diag = (hi - lo).norm();
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g;
    const int poses = scaled(16, 6);
    double raw_abs = 0, plain_abs = 0, cal_abs = 0, plain_signed = 0, cal_signed = 0;
    int used = 0, cal_above_plain = 0;
    for (int i = 0; i < poses; ++i) {
        const Mat3<double> R = test::random_rotation(rng);
        Vec3<double> u(g(rng), g(rng), g(rng));
        u.normalize();
        double in = 0, out = 2 * diag;  // bisection to contact on the meshes, then 5% of the diagonal deeper
        for (int it = 0; it < 30; ++it) {
            const double mid = (in + out) / 2;
            (collide(model, Transform<double>{}, model, Transform<double>(R, mid * u)).colliding ? in : out) = mid;
        }
        const Transform<double> pb(R, (out - 0.05 * diag) * u);
        TriangleMesh<double> moved = mesh;
        for (auto& v : moved.vertices) v = pb * v;
        const double reference =
            mesh_intersection_volume(inside, InsideTest(std::move(moved)), {.grid = 96, .passes = 2, .seed = std::uint64_t(i + 1)}).volume;
        if (!(reference > 1e-4)) continue;  // a pose whose meshes barely overlap
        ++used;
        const auto rp = penetration_volume(plain, {}, plain, pb);
        const auto rc = penetration_volume(calibrated, {}, calibrated, pb);
        CHECK(rp.volume == rc.volume);  // same spheres: only the weights differ
        raw_abs += std::abs(rp.volume - reference) / reference;
        plain_abs += std::abs(rp.calibrated - reference) / reference;
        cal_abs += std::abs(rc.calibrated - reference) / reference;
        plain_signed += (rp.calibrated - reference) / reference;
        cal_signed += (rc.calibrated - reference) / reference;
        cal_above_plain += rc.calibrated > rp.calibrated;
    }
    REQUIRE(used >= poses / 2);
    raw_abs /= used, plain_abs /= used, cal_abs /= used, plain_signed /= used, cal_signed /= used;
    INFO("mean |error|: raw " << raw_abs << ", plain weights " << plain_abs << ", default " << cal_abs
                              << "; mean signed: plain " << plain_signed << ", default " << cal_signed);
    CHECK(raw_abs > 0.5);               // the inner spheres alone miss most of a shallow overlap
    CHECK(cal_abs < 0.5 * raw_abs);     // the calibration recovers most of it
    CHECK(plain_signed < 0);            // plain cell weights are low at shallow contacts
    // The depth calibration raises most estimates here; not necessarily all: the fit also lowers the weights
    // of spheres in deep layers, and a pose reaching deep can come out slightly lower (one of 14 did).
    CHECK(cal_above_plain * 4 >= used * 3);
    CHECK(std::abs(cal_signed) < std::abs(plain_signed));
    // A regression bound (issue 37): the default's mean |error| measured 0.109 here (16 poses; 0.100 over the 6 of
    // the reduced run), so 1.5× that. Before this bound the test would have passed a 40% error.
    CHECK(cal_abs < 1.5 * 0.109);
}

namespace {

// Out of sample (issue 37): the default α is derived from self-contacts pushed 5% of the diagonal past first
// contact, the depth of the test above, so that test's error is in-sample. The cases below use the poses,
// references and trees of `cdkit_bench_ist --out-of-sample` (out_of_sample.cpp: the main run's P2 generator,
// oracles/contact_poses.hpp, seed 2024, one direction per pose evaluated at every δ; lines 256² × 8 passes, seed 1000·k + i + 1 for the
// k-th depth of 0.01, 0.05, 0.2), so at full size they measure the very figures of results/ist_out_of_sample.csv
// (rendered in docs/ist.md); the bounds are 1.5× those.
/// The benchmark's references of vol(A ∩ B) at δ = −depth (depth_index: its place in the benchmark's list
/// 0.01, 0.05, 0.2, which seeds the jitter).
std::vector<double> oos_references(const TriangleMesh<double>& mesh, double diag, const std::vector<test::ContactPose>& poses,
                                   double depth, int depth_index) {
    const InsideTest inside(mesh);
    std::vector<double> out;
    for (std::size_t i = 0; i < poses.size(); ++i) {
        const Transform<double> pb = test::pose_past_contact(poses[i], diag, depth);
        TriangleMesh<double> moved = mesh;
        for (auto& v : moved.vertices) v = pb * v;
        out.push_back(mesh_intersection_volume(inside, InsideTest(std::move(moved)),
                                               {.grid = 256, .passes = 8, .seed = std::uint64_t(1000 * depth_index) + i + 1})
                          .volume);
    }
    return out;
}

struct OosErrors {
    double median_abs = 0, mean_abs = 0, mean_signed = 0;
};

/// The calibrated estimate's relative errors over the poses at δ = −depth.
OosErrors oos_errors(const InnerSphereTree& tree, double diag, const std::vector<test::ContactPose>& poses, double depth,
                     const std::vector<double>& reference) {
    std::vector<double> abs_err;
    OosErrors e;
    for (std::size_t i = 0; i < poses.size(); ++i) {
        REQUIRE(reference[i] > 0);
        const double rel = (penetration_volume(tree, {}, tree, test::pose_past_contact(poses[i], diag, depth)).calibrated - reference[i]) / reference[i];
        abs_err.push_back(std::abs(rel));
        e.mean_abs += std::abs(rel) / double(poses.size());
        e.mean_signed += rel / double(poses.size());
    }
    std::sort(abs_err.begin(), abs_err.end());
    const std::size_t n = abs_err.size();
    e.median_abs = n % 2 ? abs_err[n / 2] : (abs_err[n / 2 - 1] + abs_err[n / 2]) / 2;
    return e;
}

}  // namespace

TEST_CASE("calibrated volume out of sample at other contact depths and with another mesh's α", "[ist][accuracy]") {
    const auto bunny = test::unit_bunny();
    Vec3<double> lo = bunny.vertices[0], hi = lo;
    for (const auto& v : bunny.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double diag = (hi - lo).norm();
    const int n = scaled(8, 4);  // the benchmark's 8 poses; a prefix of them in reduced runs
    const std::vector<test::ContactPose> poses = test::contact_poses(bunny, diag, n);
    const bool full = n == 8;

    struct Case {
        std::size_t spheres;
        double depth;
        int depth_index;
        bool armadillo_alpha;  // α derived on the Armadillo (same count, contact depth = |δ|) instead of the bunny's default
        double doc_median, doc_mean_abs, doc_mean_signed;  // results/ist_out_of_sample.csv (median_pct, mean_abs_pct,
                                                           // mean_signed_pct), in %
    };
    const Case cases[] = {
        // The default α (derived at c = 0.05) evaluated at δ = −0.01 and −0.2: the bunny's "other depth" rows with α
        // depth 0.05. At δ = −0.01 the estimate is far low whatever α (docs/ist.md, "Out of sample"): the bound
        // only catches it getting worse.
        {1000, 0.01, 0, false, 56.1, 65.2, -52.6},
        {1000, 0.2, 2, false, 3.2, 6.1, 4.7},
        {10000, 0.01, 0, false, 26.4, 27.0, -27.0},
        {10000, 0.2, 2, false, 0.7, 1.3, 0.9},
        // The Armadillo's α (derived at c = 0.05, 1k spheres) on the bunny at δ = −0.05: the "other mesh" row.
        {1000, 0.05, 1, true, 9.7, 11.6, -4.3},
    };
    std::vector<double> reference[3];  // per depth index, computed once
    for (const Case& c : cases) {
        if (!full && c.spheres > 1000) continue;  // reduced runs: the 1k cases only
        if (reference[c.depth_index].empty()) reference[c.depth_index] = oos_references(bunny, diag, poses, c.depth, c.depth_index);
        PackingOptions o;
        o.max_spheres = c.spheres;
        if (c.armadillo_alpha) {
            PackingOptions a;
            a.max_spheres = c.spheres;
            a.depth_calibration_contact_depth = c.depth;
            o.depth_calibration_strength = pack_spheres(test::unit_scaled(load_mesh(test::data_path("armadillo.obj"))), a).calibration_strength;
        }
        SpherePacking packing = pack_spheres(bunny, o);
        const double alpha = packing.calibration_strength;
        const InnerSphereTree tree(std::move(packing));
        const OosErrors e = oos_errors(tree, diag, poses, c.depth, reference[c.depth_index]);
        INFO(c.spheres << " spheres, δ = −" << c.depth << (c.armadillo_alpha ? ", the Armadillo's α " : ", default α ")
                       << alpha << ": median |error| " << 100 * e.median_abs << "%, mean |error| "
                       << 100 * e.mean_abs << "%, mean signed " << 100 * e.mean_signed << "% over " << n << " poses");
        CHECK(100 * e.mean_abs <= 1.5 * c.doc_mean_abs);
        if (full) {  // a prefix's median and bias are not the documented ones
            CHECK(100 * e.median_abs <= 1.5 * c.doc_median);
            // The bias: its size may not grow past 1.5× the documented one (one percentage point of slack for the
            // near-zero ones), which catches a calibration that trades a low estimate for a high one.
            CHECK(std::abs(100 * e.mean_signed) <= 1.5 * std::abs(c.doc_mean_signed) + 1);
        }
    }
}
