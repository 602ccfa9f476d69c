/// \file plain_bench: cdkit against FCL as a user measures it. A program of its own, linking the installed
/// cdkit (find_package) and FCL 0.7, times first-contact collision of two copies of each mesh given:
/// cdkit MeshModel<Obb<double>> (default build) against FCL BVHModel<OBBRSS<double>> (fcl::collide, one
/// contact), on the poses of protocols P1 and P2 of shared/BENCHMARKS.md, made as cdkit_bench makes them
/// (same normalisation, same seed: the same poses). Per pose, cdkit then FCL: one cold call (the pose's first,
/// after the other library's queries), one untimed warm-up, then the fastest of 3 batches of ≥ 50 µs and ≥ 8
/// calls, with steady_clock. Prints per d (P1) and per δ (P2) the median µs and FCL/cdkit; exits 1 if the two
/// ever disagree on a boolean. Usage: plain_bench [--steps N] [--rotations R] [--seed S] [--csv FILE]
/// [--summary FILE] [--commit REV] MESH...
#include <cdkit/cdkit.hpp>

#include <sched.h>  // sched_getcpu: this VM's two vCPUs differ (docs/benchmarks.md)

#include <fcl/config.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/collision.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Clock = std::chrono::steady_clock;

struct Pose { Mat3 R; Vec3 t; };
struct Class { double distance; std::vector<Pose> poses; };

constexpr double kMinBatchSeconds = 50e-6;
constexpr int kMinReps = 8, kBatches = 3;
volatile std::uint64_t g_sink = 0;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// A query's per-call times at one pose: `first` the cold call, `warm` the fastest batch's mean.
struct Sample { double first_us, warm_us; bool colliding; bool stable; };

template <class Query> Sample time_query(Query&& query) {
    auto t0 = Clock::now();
    const bool hit = query();
    const double first = seconds_since(t0);
    t0 = Clock::now();
    query();  // warm-up; sizes the batches
    const double est = std::max(seconds_since(t0), 1e-9);
    const int k = std::max(kMinReps, int(std::ceil(kMinBatchSeconds / est)));
    double best = std::numeric_limits<double>::infinity();
    int hits = 0;
    for (int b = 0; b < kBatches; ++b) {
        t0 = Clock::now();
        for (int i = 0; i < k; ++i) {
            asm volatile("" ::: "memory");  // no merging or hoisting of repeated queries
            hits += query();
        }
        best = std::min(best, seconds_since(t0) / k);
    }
    g_sink = g_sink + std::uint64_t(hits);
    return {first * 1e6, best * 1e6, hit, hits == (hit ? kBatches * k : 0)};
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// ---- poses: as cdkit_bench makes them (benchmarks/harness.cpp) ----------------------------------------

std::vector<double> p1_distances() {  // 1.5 … 1.0 by 0.1, then 0.98 … 0 by 0.02
    std::vector<double> d;
    for (int k = 15; k >= 10; --k) d.push_back(k / 10.0);
    for (int k = 49; k >= 0; --k) d.push_back(k / 50.0);
    return d;
}

std::vector<Class> p1_classes(int steps) {  // t = (d, 0, 0), R = Rz(iΔ)·Rx(iΔ), Δ = 2π/steps
    std::vector<Class> out;
    for (double d : p1_distances()) {
        Class c{d, {}};
        for (int i = 0; i < steps; ++i) {
            const double a = double(i) * 2.0 * std::numbers::pi / double(steps);
            const Mat3 R = Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix() *
                           Eigen::AngleAxisd(a, Vec3::UnitX()).toRotationMatrix();
            c.poses.push_back({R, Vec3(d, 0, 0)});
        }
        out.push_back(std::move(c));
    }
    return out;
}

struct Uniform {  // 53 random bits: the same doubles on every standard library
    std::mt19937_64 rng;
    double operator()() { return double(rng() >> 11) * 0x1.0p-53; }
};

/// P2: uniform rotation (Shoemake) and direction u per draw; bisection (40 steps, cdkit first contact, keeping
/// the colliding end) from s = 0 to 2r·1.001 for the touching s*; one pose per δ at (s* + δ·r)·u.
template <class Collides>
std::vector<Class> p2_classes(int rotations, std::uint64_t seed, double r, Collides&& collides) {
    const std::vector<double> deltas = {-0.2, -0.05, -0.01, 0.0, 0.005, 0.01, 0.05, 0.2};
    std::vector<Class> out;
    for (double d : deltas) out.push_back({d, {}});
    Uniform u{std::mt19937_64(seed)};
    for (int made = 0, skipped = 0; made < rotations;) {
        const double u1 = u(), u2 = 2 * std::numbers::pi * u(), u3 = 2 * std::numbers::pi * u();
        const double qa = std::sqrt(1 - u1), qb = std::sqrt(u1);
        const Mat3 R = Eigen::Quaterniond(qb * std::cos(u3), qa * std::sin(u2), qa * std::cos(u2), qb * std::sin(u3))
                           .normalized().toRotationMatrix();
        const double z = 2 * u() - 1, phi = 2 * std::numbers::pi * u(), s = std::sqrt(std::max(0.0, 1 - z * z));
        const Vec3 dir(s * std::cos(phi), s * std::sin(phi), z);
        double lo = 0, hi = 2.0 * r * 1.001 + 1e-9;
        if (!collides({R, lo * dir}) || collides({R, hi * dir})) {
            if (++skipped > 100 * rotations + 100) throw std::runtime_error("P2: no usable rotation");
            continue;
        }
        for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (lo + hi);
            (collides({R, mid * dir}) ? lo : hi) = mid;
        }
        for (Class& c : out) c.poses.push_back({R, (lo + c.distance * r) * dir});
        ++made;
    }
    return out;
}

// ---- one mesh -------------------------------------------------------------------------------------

struct Options {
    int steps = 36, rotations = 100;
    std::uint64_t seed = 1;
    std::string csv, summary, commit = "?";
    std::vector<std::string> meshes;
};

/// Runs P1 and P2 on one mesh; prints the tables, appends CSV rows (per d or δ to `csv`, per protocol to
/// `summary`: the smallest, geometric mean and largest ratio); returns the boolean disagreements.
std::size_t run_mesh(const std::string& path, const Options& opt, std::FILE* csv, std::FILE* summary) {
    cdkit::TriangleMesh<double> mesh = cdkit::load_mesh(path);
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;  // into [-1, 1]³ about the
    for (const Vec3& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);  // bounding-box centre
    const Vec3 centre = 0.5 * (lo + hi);
    const double extent = (hi - lo).maxCoeff(), scale = extent > 0 ? 2.0 / extent : 1.0;
    double radius = 0;
    for (Vec3& v : mesh.vertices) v = (v - centre) * scale, radius = std::max(radius, v.norm());
    const std::string name = std::filesystem::path(path).filename().string();

    const cdkit::MeshModel<cdkit::Obb<double>> cd(mesh);
    std::vector<fcl::Vector3d> verts(mesh.vertices.begin(), mesh.vertices.end());
    std::vector<fcl::Triangle> tris;
    for (const auto& t : mesh.triangles) tris.emplace_back(t[0], t[1], t[2]);
    auto fm = std::make_shared<fcl::BVHModel<fcl::OBBRSS<double>>>();
    fm->beginModel(int(tris.size()), int(verts.size()));
    fm->addSubModel(verts, tris);
    fm->endModel();
    const cdkit::CollisionRequest cd_req{cdkit::ContactMode::first};
    const fcl::CollisionRequestd fcl_req(1, false);  // one contact; enable_contact off, as cdkit_bench
    const auto cd_collides = [&](const Pose& p) {
        return cdkit::collide(cd, cdkit::Transform<double>::identity(), cd, cdkit::Transform<double>(p.R, p.t), cd_req)
            .colliding;
    };
    std::printf("\n%s: %zu triangles (normalised into [-1, 1]^3, r = %.4f), on CPU %d\n", name.c_str(),
                mesh.triangles.size(), radius, sched_getcpu());

    std::size_t disagreements = 0;
    for (const char* protocol : {"P1", "P2"}) {
        const bool p1 = protocol[1] == '1';
        const std::vector<Class> classes =
            p1 ? p1_classes(opt.steps) : p2_classes(opt.rotations, opt.seed, radius, cd_collides);
        std::printf("\n%s first contact, median us per query (%zu poses per %s); warm: fastest of %d batches "
                    ">= %.0f us and >= %d calls; first: the pose's first call\n",
                    protocol, classes.front().poses.size(), p1 ? "d" : "delta", kBatches, kMinBatchSeconds * 1e6, kMinReps);
        std::printf("%8s %6s | %9s %9s %6s | %9s %9s %6s | %s\n", p1 ? "d" : "delta", "coll", "cdkit", "fcl", "ratio",
                    "cdkit 1st", "fcl 1st", "ratio", "disagree");
        std::vector<double> ratios;
        std::size_t protocol_disagreements = 0;
        for (const Class& c : classes) {
            std::vector<double> cw, fw, cf, ff;
            std::size_t hits = 0, dis = 0, unstable = 0;
            for (std::size_t i = 0; i < c.poses.size(); ++i) {
                const Pose& p = c.poses[i];
                const cdkit::Transform<double> pa = cdkit::Transform<double>::identity(), pb(p.R, p.t);
                fcl::Transform3d tf1 = fcl::Transform3d::Identity(), tf2 = tf1;
                tf2.linear() = p.R;
                tf2.translation() = p.t;
                const Sample a = time_query([&] { return cdkit::collide(cd, pa, cd, pb, cd_req).colliding; });
                const Sample b = time_query([&] {
                    fcl::CollisionResultd res;
                    fcl::collide(fm.get(), tf1, fm.get(), tf2, fcl_req, res);
                    return res.isCollision();
                });
                cw.push_back(a.warm_us), fw.push_back(b.warm_us), cf.push_back(a.first_us), ff.push_back(b.first_us);
                hits += a.colliding;
                unstable += !a.stable + !b.stable;
                if (a.colliding != b.colliding) {
                    ++dis;
                    std::printf("DISAGREEMENT %s %s %g pose %zu: cdkit %d fcl %d; R = [%.17g %.17g %.17g; %.17g %.17g %.17g; "
                                "%.17g %.17g %.17g], t = [%.17g %.17g %.17g]\n", name.c_str(), protocol, c.distance, i,
                                int(a.colliding), int(b.colliding), p.R(0, 0), p.R(0, 1), p.R(0, 2), p.R(1, 0), p.R(1, 1),
                                p.R(1, 2), p.R(2, 0), p.R(2, 1), p.R(2, 2), p.t.x(), p.t.y(), p.t.z());
                }
            }
            if (unstable) std::printf("WARNING: %zu batches answered unlike their first call\n", unstable);
            disagreements += dis + unstable;
            protocol_disagreements += dis + unstable;
            const double mc = median(cw), mf = median(fw), mc1 = median(cf), mf1 = median(ff);
            const double coll = double(hits) / double(c.poses.size());
            ratios.push_back(mf / mc);
            std::printf("%8.3f %5.0f%% | %9.2f %9.2f %6.2f | %9.2f %9.2f %6.2f | %zu\n", c.distance, 100 * coll, mc, mf,
                        mf / mc, mc1, mf1, mf1 / mc1, dis);
            if (csv)
                std::fprintf(csv, "%s,%zu,%s,%g,%zu,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%zu\n", name.c_str(),
                             mesh.triangles.size(), protocol, c.distance, c.poses.size(), coll, mc, mf, mf / mc, mc1,
                             mf1, mf1 / mc1, dis);
        }
        double log_sum = 0;
        for (double r : ratios) log_sum += std::log(r);
        const double lo = *std::min_element(ratios.begin(), ratios.end()), geo = std::exp(log_sum / double(ratios.size())),
                     hi = *std::max_element(ratios.begin(), ratios.end());
        std::printf("%s %s: FCL/cdkit (warm) min %.2f, geomean %.2f, max %.2f (now on CPU %d)\n", name.c_str(),
                    protocol, lo, geo, hi, sched_getcpu());
        if (summary)
            std::fprintf(summary, "%s,%zu,%s,%zu,%.4f,%.4f,%.4f,%zu\n", name.c_str(), mesh.triangles.size(), protocol,
                         classes.size(), lo, geo, hi, protocol_disagreements);
    }
    return disagreements;
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has_value = i + 1 < argc;
        if (a == "--steps" && has_value) opt.steps = std::max(1, std::atoi(argv[++i]));
        else if (a == "--rotations" && has_value) opt.rotations = std::max(1, std::atoi(argv[++i]));
        else if (a == "--seed" && has_value) opt.seed = std::strtoull(argv[++i], nullptr, 10);
        else if (a == "--csv" && has_value) opt.csv = argv[++i];
        else if (a == "--summary" && has_value) opt.summary = argv[++i];
        else if (a == "--commit" && has_value) opt.commit = argv[++i];
        else if (!a.empty() && a[0] != '-') opt.meshes.push_back(a);
        else {
            std::fprintf(stderr, "usage: plain_bench [--steps N] [--rotations R] [--seed S] [--csv FILE] "
                                 "[--summary FILE] [--commit REV] MESH...\n");
            return 2;
        }
    }
    if (opt.meshes.empty()) {
        std::fprintf(stderr, "plain_bench: no mesh given\n");
        return 2;
    }
    std::FILE* csv = opt.csv.empty() ? nullptr : std::fopen(opt.csv.c_str(), "w");
    std::FILE* summary = opt.summary.empty() ? nullptr : std::fopen(opt.summary.c_str(), "w");
    // Provenance as comment lines (scripts/render-results prints them under the tables it renders).
    std::string command;
    for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(argv[i]);
    // `--commit`: the installed package's source revision (scripts/bench passes it; a program that links an
    // installed package cannot ask git).
    char date[32];
    const std::time_t now = std::time(nullptr);
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    for (std::FILE* f : {csv, summary})
        if (f)
            std::fprintf(f, "# command: %s\n# machine: CPU %d of %u\n# compiler: %s\n# fcl: %s\n# commit: %s\n# date: %s\n",
                         command.c_str(), sched_getcpu(), std::thread::hardware_concurrency(), __VERSION__, FCL_VERSION,
                         opt.commit.c_str(), date);
    if (summary)
        std::fprintf(summary, "mesh,triangles,protocol,classes,min_ratio,geomean_ratio,max_ratio,disagreements\n");
    if (csv)
        std::fprintf(csv, "mesh,triangles,protocol,distance,poses,frac_colliding,cdkit_median_us,fcl_median_us,"
                          "ratio,cdkit_first_call_median_us,fcl_first_call_median_us,first_call_ratio,disagreements\n");
    std::printf("plain_bench: cdkit MeshModel<Obb<double>> vs FCL %s BVHModel<OBBRSS<double>>, first contact; "
                "P1 %d steps per d, P2 %d rotations (seed %llu); ratio = FCL / cdkit (> 1: cdkit faster)\n",
                FCL_VERSION, opt.steps, opt.rotations, static_cast<unsigned long long>(opt.seed));
    std::size_t disagreements = 0;
    try {
        for (const std::string& m : opt.meshes) disagreements += run_mesh(m, opt, csv, summary);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "plain_bench: %s\n", e.what());
        return 2;
    }
    for (std::FILE* f : {csv, summary})
        if (f) std::fclose(f);
    std::printf("\nboolean disagreements between cdkit and FCL: %zu\n", disagreements);
    return disagreements == 0 ? 0 : 1;
}
