/// \file Protocols P1 and P2 of shared/BENCHMARKS.md, and the loop that times every method on the same poses.

#include "harness.hpp"

#include "cdkit_methods.hpp"
#include "peers_fcl.hpp"

#include "cdkit/io/load_mesh.hpp"

#include <fnmatch.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

namespace cdbench {
namespace {

using Vec3 = cdkit::Vec3<double>;
using Mat3 = cdkit::Mat3<double>;

/// One distance class: all poses share the distance (P1's d, P2's δ).
struct PoseClass {
    double distance = 0;
    std::vector<Pose> poses;
};

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Linear interpolation between order statistics (numpy's default): q in [0, 1], `v` sorted.
double quantile(const std::vector<double>& v, double q) {
    if (v.empty()) return std::nan("");
    const double pos = q * double(v.size() - 1);
    const std::size_t i = std::size_t(pos);
    if (i + 1 >= v.size()) return v.back();
    return v[i] + (pos - double(i)) * (v[i + 1] - v[i]);
}

// ---- meshes ---------------------------------------------------------------------------------------

/// Scales uniformly into [-1, 1]³ about the bounding-box centre (longest side → 2), in place.
void normalise(cdkit::TriangleMesh<double>& mesh, MeshInfo& info) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Vec3& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    info.center = (lo + hi) * 0.5;
    const double extent = (hi - lo).maxCoeff();
    info.scale = extent > 0 ? 2.0 / extent : 1.0;
    info.radius = 0;
    for (Vec3& v : mesh.vertices) {
        v = (v - info.center) * info.scale;
        info.radius = std::max(info.radius, v.norm());
    }
}

// ---- poses ----------------------------------------------------------------------------------------

Mat3 rot_x(double a) { return Eigen::AngleAxisd(a, Vec3::UnitX()).toRotationMatrix(); }
Mat3 rot_z(double a) { return Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix(); }

/// P1: for each d, one full tumbling turn of N steps, step i rotated by Rz(iΔ)·Rx(iΔ), Δ = 2π/N.
std::vector<PoseClass> p1_classes(std::size_t steps) {
    std::vector<PoseClass> out;
    for (double d : p1_distances()) {
        PoseClass c;
        c.distance = d;
        c.poses.reserve(steps);
        for (std::size_t i = 0; i < steps; ++i) {
            const double a = double(i) * 2.0 * std::numbers::pi / double(steps);
            c.poses.push_back({rot_z(a) * rot_x(a), Vec3(d, 0, 0)});
        }
        out.push_back(std::move(c));
    }
    return out;
}

/// Uniform doubles in [0, 1) from 53 random bits: unlike std::uniform_real_distribution, the same on
/// every standard library, so a seed names the same poses everywhere.
struct Uniform {
    std::mt19937_64 rng;
    double operator()() { return double(rng() >> 11) * 0x1.0p-53; }
};

/// Uniform random rotation (Shoemake, "Uniform random rotations", Graphics Gems III, 1992).
Mat3 random_rotation(Uniform& u) {
    const double u1 = u(), u2 = 2 * std::numbers::pi * u(), u3 = 2 * std::numbers::pi * u();
    const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
    const Eigen::Quaterniond q(b * std::cos(u3), a * std::sin(u2), a * std::cos(u2), b * std::sin(u3));
    return q.normalized().toRotationMatrix();
}

/// Uniform random unit vector.
Vec3 random_direction(Uniform& u) {
    const double z = 2 * u() - 1, phi = 2 * std::numbers::pi * u();
    const double s = std::sqrt(std::max(0.0, 1 - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
}

/// P2: R random rotations with a random direction u each; bisection on s (pose (Q, s·u)) to the contact
/// translation s*, keeping the colliding end, then one pose per δ at s* + δ·r.
std::vector<PoseClass> p2_classes(Method& reference, const MeshInfo& mesh, std::size_t rotations,
                                  std::uint64_t seed, std::size_t& skipped) {
    Uniform u{std::mt19937_64(seed)};
    const std::vector<double> deltas = p2_deltas();
    std::vector<PoseClass> out(deltas.size());
    for (std::size_t k = 0; k < deltas.size(); ++k) out[k].distance = deltas[k];
    auto collides = [&](const Mat3& R, const Vec3& dir, double s) {
        return reference.probe({R, s * dir}, Mode::first).colliding;
    };
    skipped = 0;
    std::size_t made = 0;
    while (made < rotations) {
        const Mat3 R = random_rotation(u);
        const Vec3 dir = random_direction(u);
        // Beyond 2r the bounding spheres are apart; at 0 the copies share their centre and, being the same
        // surface turned, cross each other (redraw in the rare case they do not).
        double lo = 0, hi = 2.0 * mesh.radius * 1.001 + 1e-9;
        if (!collides(R, dir, lo) || collides(R, dir, hi)) {
            if (++skipped > 100 * rotations + 100) throw std::runtime_error("P2: no usable rotation found");
            continue;
        }
        for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (lo + hi);
            (collides(R, dir, mid) ? lo : hi) = mid;
        }
        for (std::size_t k = 0; k < deltas.size(); ++k)
            out[k].poses.push_back({R, (lo + deltas[k] * mesh.radius) * dir});
        ++made;
    }
    return out;
}

// ---- measurement ----------------------------------------------------------------------------------

struct Accumulator {
    std::vector<double> us, first_us;
    std::size_t colliding = 0, contacts = 0, bool_dis = 0, count_mis = 0, probe_timed_mis = 0;
    std::uint64_t bv = 0, tri = 0;
    bool has_bv = true, has_tri = true;
};

/// Times one pose of one method: the fastest batch's mean per query, in µs (a batch hit by preemption is
/// discarded). `first_s` was the pose's first call, and the untimed probe ran after it; neither warms FCL up
/// (its first call at a pose takes 2.3× its steady time, its probe is another code path, and it settles
/// after 3–4 repeats: docs/benchmarks.md, "Warm batches"). So `warmup` untimed calls come next, the last
/// sizing the batches: ≥ `min_batch_us` and, for queries that are shorter when warm, ≥ `min_reps` calls. This
/// holds whatever the cold first call took: a query whose first call took 100 µs may settle at 30 µs (FCL did
/// at the bunny's P2 δ = 0.005), and timing it as single calls, as an earlier rule for first calls ≥
/// `min_batch_us` did, kept it 27 % slower than plain_bench's. A slow query (`slow`: this method's last sample
/// took ≥ `slow_query_us`; `first_s` < 0 then, as its first call was skipped) gets one call after the probe, as
/// before issue 39: cold misses are a small share of it, and repeats would dominate the run time.
double time_pose(Method& m, const Pose& pose, Mode mode, const Options& opt, double first_s, const Outcome& probe,
                 Accumulator& acc, bool& slow) {
    const double target_s = opt.min_batch_us * 1e-6, slow_s = opt.slow_query_us * 1e-6;
    std::size_t k = 1, batches = std::max<std::size_t>(opt.batches, 1);
    if (slow || first_s >= slow_s) {
        batches = 1;
    } else {
        double est = first_s;
        for (std::size_t w = 0; w < opt.warmup; ++w) est = m.time(pose, mode, 1).seconds;
        est = std::max(est, 1e-9);
        k = std::size_t(std::clamp(std::ceil(target_s / est), 1.0, double(1 << 22)));
        if (est < target_s) k = std::max(k, opt.min_reps);
    }
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t b = 0; b < batches; ++b) {
        const Timed t = m.time(pose, mode, k);
        if (t.colliding != probe.colliding || t.contacts != probe.contacts) ++acc.probe_timed_mis;
        best = std::min(best, t.seconds);
    }
    slow = best / double(k) >= slow_s;
    return best / double(k) * 1e6;
}

bool is_cdkit(const Method& m) { return m.family() == "cdkit"; }

/// Classifies a non-unanimous pose; "" when there is nothing to keep. Answers are compared only between
/// methods of equal precision, except for "float_vs_double": a float query near contact may round either way.
std::string disagreement_kind(const std::vector<std::unique_ptr<Method>>& methods, const std::vector<Outcome>& ans,
                              Mode mode) {
    bool cross = false, cdkit_internal = false, peer_internal = false, precision = false;
    for (std::size_t i = 0; i < methods.size(); ++i)
        for (std::size_t j = i + 1; j < methods.size(); ++j) {
            if (ans[i].colliding == ans[j].colliding) continue;
            if (methods[i]->build_info().single_precision != methods[j]->build_info().single_precision) {
                precision = true;
                continue;
            }
            const bool ci = is_cdkit(*methods[i]), cj = is_cdkit(*methods[j]);
            if (ci != cj) cross = true;
            else if (ci) cdkit_internal = true;
            else peer_internal = true;
        }
    if (cross) return "cdkit_vs_fcl";
    if (cdkit_internal) return "cdkit_internal";
    if (peer_internal) return "fcl_internal";
    if (precision) return "float_vs_double";
    // Pair counts must agree exactly between cdkit trees of one precision (the tree only prunes; the same
    // triangle test decides); across precisions they may differ.
    if (mode == Mode::all)
        for (std::size_t i = 0; i < methods.size(); ++i)
            for (std::size_t j = i + 1; j < methods.size(); ++j)
                if (is_cdkit(*methods[i]) && is_cdkit(*methods[j]) && ans[i].contacts != ans[j].contacts)
                    return methods[i]->build_info().single_precision == methods[j]->build_info().single_precision
                               ? "cdkit_contact_count"
                               : "float_vs_double_contact_count";
    // FCL may count differently (its triangle test is not exact, and coplanar pairs are its own business):
    // kept so that an oracle can tell who is right.
    if (mode == Mode::all)
        for (std::size_t i = 1; i < methods.size(); ++i)
            if (!is_cdkit(*methods[i]) && ans[i].contacts != ans[0].contacts) return "fcl_contact_count";
    return "";
}

void measure(const Options& opt, const MeshInfo& mesh, std::vector<std::unique_ptr<Method>>& methods,
             const std::string& protocol, const std::string& distance_kind, const std::vector<PoseClass>& classes,
             Report& report) {
    const bool tty = isatty(fileno(stderr));
    std::size_t peer = methods.size();
    for (std::size_t i = 0; i < methods.size(); ++i)
        if (methods[i]->name() == report.peer) peer = i;
    for (Mode mode : opt.modes) {
        const auto t_mode = Clock::now();
        std::vector<bool> slow(methods.size(), false);  // the method's last sample took >= slow_query_us
        for (std::size_t ci = 0; ci < classes.size(); ++ci) {
            const PoseClass& cls = classes[ci];
            if (!opt.quiet && tty)
                std::fprintf(stderr, "\r  %s %s %-5s %s=%+.3f (%zu/%zu) %.0fs   ", mesh.name.c_str(), protocol.c_str(),
                             mode_name(mode), distance_kind.c_str(), cls.distance, ci + 1, classes.size(),
                             seconds_since(t_mode));
            std::vector<Accumulator> acc(methods.size());
            std::vector<Outcome> ans(methods.size());
            for (std::size_t pi = 0; pi < cls.poses.size(); ++pi) {
                const Pose& pose = cls.poses[pi];
                // Methods interleaved pose by pose, so that a burst of noise on a shared machine hits all alike.
                for (std::size_t m = 0; m < methods.size(); ++m) {
                    Accumulator& a = acc[m];
                    // The pose's first call, cold; skipped for slow methods (it would be a third call of ms).
                    const bool was_slow = slow[m];
                    const Timed first = was_slow ? Timed{-1} : methods[m]->time(pose, mode, 1);
                    ans[m] = methods[m]->probe(pose, mode);
                    if (!was_slow) {
                        if (first.colliding != ans[m].colliding || first.contacts != ans[m].contacts) ++a.probe_timed_mis;
                        a.first_us.push_back(first.seconds * 1e6);
                    }
                    bool is_slow = was_slow;
                    a.us.push_back(time_pose(*methods[m], pose, mode, opt, first.seconds, ans[m], a, is_slow));
                    slow[m] = is_slow;
                    a.colliding += ans[m].colliding;
                    a.contacts += ans[m].contacts;
                    if (ans[m].bv_tests) a.bv += *ans[m].bv_tests; else a.has_bv = false;
                    if (ans[m].tri_tests) a.tri += *ans[m].tri_tests; else a.has_tri = false;
                    a.bool_dis += ans[m].colliding != ans[0].colliding;
                    a.count_mis += mode == Mode::all && ans[m].contacts != ans[0].contacts;
                }
                if (std::string kind = disagreement_kind(methods, ans, mode); !kind.empty())
                    report.disagreements.push_back({mesh.path, protocol, mode_name(mode), kind, cls.distance, pi, pose, ans});
            }
            const std::size_t first_row = report.rows.size();
            for (std::size_t m = 0; m < methods.size(); ++m) {
                Accumulator& a = acc[m];
                const double n = double(a.us.size());
                std::sort(a.us.begin(), a.us.end());
                std::sort(a.first_us.begin(), a.first_us.end());
                ResultRow r;
                r.mesh = mesh.name;
                r.triangles = mesh.triangles;
                r.protocol = protocol;
                r.mode = mode_name(mode);
                r.distance_kind = distance_kind;
                r.distance = cls.distance;
                r.method = methods[m]->name();
                r.family = methods[m]->family();
                r.poses = a.us.size();
                double sum = 0;
                for (double x : a.us) sum += x;
                r.mean_us = sum / n;
                r.median_us = quantile(a.us, 0.5);
                r.p99_us = quantile(a.us, 0.99);
                r.max_us = a.us.back();
                r.min_us = a.us.front();
                r.first_call_median_us = a.first_us.empty() ? -1 : quantile(a.first_us, 0.5);
                r.frac_colliding = double(a.colliding) / n;
                r.bv_tests_mean = a.has_bv ? double(a.bv) / n : -1;
                r.tri_tests_mean = a.has_tri ? double(a.tri) / n : -1;
                r.contacts_mean = double(a.contacts) / n;
                r.bool_disagreements = a.bool_dis;
                r.contact_mismatches = a.count_mis;
                r.probe_timed_mismatches = a.probe_timed_mis;
                report.rows.push_back(r);
            }
            if (peer < methods.size())
                for (std::size_t m = 0; m < methods.size(); ++m) {
                    ResultRow& r = report.rows[first_row + m];
                    r.ratio_vs_peer = report.rows[first_row + peer].median_us / r.median_us;
                }
        }
        if (!opt.quiet)
            std::fprintf(stderr, "%s  %s %s %-5s: %zu classes x %zu poses x %zu methods in %.1fs\n", tty ? "\r" : "",
                         mesh.name.c_str(), protocol.c_str(), mode_name(mode), classes.size(),
                         classes.empty() ? 0 : classes.front().poses.size(), methods.size(), seconds_since(t_mode));
    }
}

/// A method is measured when it matches a pattern and no "-pattern"; only "-pattern"s mean "all but".
bool wanted(const Options& opt, const std::string& reference, const std::string& name) {
    if (name == reference) return true;  // always measured: the correctness reference and P2's bisection
    bool any_positive = false, matched = false;
    for (const std::string& p : opt.method_patterns) {
        if (!p.empty() && p[0] == '-') {
            if (fnmatch(p.c_str() + 1, name.c_str(), 0) == 0) return false;
        } else {
            any_positive = true;
            matched |= fnmatch(p.c_str(), name.c_str(), 0) == 0;
        }
    }
    return matched || !any_positive;
}

}  // namespace

std::vector<double> p1_distances() {
    std::vector<double> d;
    for (int k = 15; k >= 10; --k) d.push_back(k / 10.0);  // integers, so that no step accumulates rounding
    for (int k = 49; k >= 0; --k) d.push_back(k / 50.0);
    return d;
}

std::vector<double> p2_deltas() { return {-0.2, -0.05, -0.01, 0.0, 0.005, 0.01, 0.05, 0.2}; }

void run_all(const Options& opt, Report& report) {
    const auto t_all = Clock::now();
    const std::vector<std::string> cd_names = cdkit_method_names();
    report.reference = cd_names.front();
    report.peer = fcl_method_names().front();
    cdkit::BuildOptions build;
    if (opt.split == "median") build.split = cdkit::SplitStrategy::median;
    else if (opt.split == "mean") build.split = cdkit::SplitStrategy::mean;
    else if (opt.split == "sah") build.split = cdkit::SplitStrategy::sah;
    else if (opt.split == "pca_volume") build.split = cdkit::SplitStrategy::pca_volume;
    else throw std::runtime_error("--split must be median, mean, sah or pca_volume");
    auto want = [&](const std::string& n) { return wanted(opt, report.reference, n); };

    for (const std::string& path : opt.meshes) {
        MeshInfo info;
        info.path = path;
        info.name = std::filesystem::path(path).filename().string();
        const auto t_load = Clock::now();
        cdkit::TriangleMesh<double> mesh = cdkit::load_mesh(path);
        info.load_ms = seconds_since(t_load) * 1e3;
        normalise(mesh, info);
        const cdkit::MeshStats st = cdkit::compute_stats(mesh);
        info.vertices = st.vertices;
        info.triangles = st.triangles;
        info.closed = st.closed;
        info.degenerate_triangles = st.degenerate_triangles;
        info.duplicate_triangles = st.duplicate_triangles;
        info.non_manifold_edges = st.non_manifold_edges;
        if (!opt.quiet)
            std::fprintf(stderr, "%s: %zu triangles, %zu vertices, %s; building models...\n", path.c_str(),
                         info.triangles, info.vertices, info.closed ? "closed" : "open");

        std::vector<std::unique_ptr<Method>> methods = make_cdkit_methods(mesh, build, want);
        for (auto& m : make_fcl_methods(mesh, want)) methods.push_back(std::move(m));
        if (report.methods.empty())
            for (const auto& m : methods) report.methods.push_back(m->name());
        for (const auto& m : methods) info.builds.push_back({m->name(), m->family(), m->build_info()});

        // Two coincident copies must collide: a triangle test that never reports anything would make every
        // timing below meaningless (a stub narrow phase, for instance).
        info.identity_collides = methods.front()->probe(Pose{}, Mode::first).colliding;
        if (!info.identity_collides)
            std::fprintf(stderr, "WARNING: %s: two coincident copies do not collide: the triangle test never "
                                 "reports an intersection (stub?). Results are meaningless.\n", path.c_str());

        for (const std::string& p : opt.protocols) {
            if (p == "p1") {
                measure(opt, info, methods, "P1", "d", p1_classes(opt.steps), report);
            } else if (p == "p2") {
                if (!info.identity_collides) continue;  // bisection needs a colliding start
                const auto classes = p2_classes(*methods.front(), info, opt.rotations, opt.seed, info.p2_skipped);
                measure(opt, info, methods, "P2", "delta", classes, report);
            }
        }
        report.meshes.push_back(std::move(info));
    }
    report.total_seconds = seconds_since(t_all);
}

}  // namespace cdbench
