// P3 convex pairs (BENCHMARKS.md): cdkit GJK (boolean, distance) and EPA against libccd (GJK, MPR,
// GJK+EPA penetration) and FCL 0.7's two solvers (GJKSolver_indep, GJKSolver_libccd: boolean, distance,
// penetration; peer_fcl.cpp) on the same shapes and poses, in one process, fixed seeds.
// Usage: cdkit_bench_convex [configs_per_cell=100] [check_cases=1000000] [csv_path|-] [families] [real_csv_path]
//                           [--p3-csv PATH] [--off LIST]
// --p3-csv: the fair boolean table of issue 37 (results/p3.csv, provenance first): per cell the booleans of cdkit by
// default, with each pre-test off (GjkSettings: bounding_ball_test, containment_test, candidate_axes,
// momentum_iterations) and with all of them off (plain GJK); of libccd's GJK plain, with cdkit's hinted hull
// support (the hint slot cdkit's GJK keeps) and with that and cdkit's own bounding-ball pre-test in front
// (libccd + ball); the share of the cell the ball pre-test decides; ratios. --off: which pre-test-off rows run,
// a comma subset of balls,containment,axes,momentum,all (plain GJK), or none (default: all five). Every boolean
// is timed on the same pose in turn, the fastest of 3 interleaved batches. The docs' table:
//   cdkit_bench_convex 100 0 /tmp/convex.csv --p3-csv /tmp/p3.csv   (then copy /tmp/p3.csv to results/)
// families: comma-separated subset of ellipsoid,box,capsule,cylinder,cone,hull100,hull1000,real (default all); the
// other families still draw their shapes and poses, so a measured family gets the configurations of a full run.
// Quick A/B run of the slow boolean cells: cdkit_bench_convex 100 0 - box,cone,cylinder,hull100,hull1000
// With csv_path, also writes one row per (family, class, method): median and p99 ns, mean iterations, maximum
// error and the fraction of configurations in error (booleans: wrong answers; distances and depths: relative
// error > 1e-9), for plot_convex.py.
// `real` (issue 39): hulls of the bundled and fetched meshes (data/, data/dragon/ from scripts/fetch-data; pairs
// whose files are missing are skipped) and, measured the same way for comparison, pairs of hull100 / hull1000
// clouds; configs_per_cell poses per gap (+0.5, +1e-3, −1e-3), interleaved, fastest of 3 batches ≥ 200 µs,
// with work counters (iterations, support calls per query, ns per support call). Its rows go to real_csv_path.
// The table: cdkit_bench_convex 60 0 - real results/p3_real_hulls.csv
// Prints per (shape family, distance class): median / p99 thread-CPU time per call (batch_timer.hpp), mean
// iterations, the error against a long-double reference (cdkit's own GJK/EPA instantiated in long double with
// tight tolerances) and the share of booleans decided by the bounding-ball pre-test, then the checked counter
// (checked_counter.hpp; check_cases of them, 0 skips it): seeded hull and curved pairs whose answers are judged by
// CGAL's exact polytope distance and the MPFR curved referee, non-zero exit on a wrong answer.
#include "../bench_util.hpp"
#include "../provenance.hpp"
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/epa.hpp>
#include <cdkit/io/load_mesh.hpp>

#include "../../tests/narrowphase/convex_reference.hpp"  // certified distance bounds, shared with the tests
#include "batch_timer.hpp"
#include "checked_counter.hpp"
#include "ccd_adapter.hpp"
#include "peer_fcl.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

using namespace cdkit;
using LD = long double;
using Clock = std::chrono::steady_clock;

namespace {

using cdbench::random_rotation;
inline std::vector<Vec3<double>> cloud(std::mt19937_64& rng, int n, double r) { return cdbench::random_cloud(rng, n, r); }
template <class T> std::vector<T> castv(const std::vector<Vec3<double>>& p) {
    std::vector<T> o;
    for (const auto& x : p) o.push_back(x.template cast<typename T::Scalar>());
    return o;
}

struct Stats {
    std::vector<double> t;
    double it = 0, err = 0;
    long n = 0, wrong = 0;
    void add(double ns, int iters, double e) {
        t.push_back(ns);
        it += iters;
        err = std::max(err, e);
        wrong += e > 1e-9 ? 1 : 0;
        ++n;
    }
    double pct(double q) {
        if (t.empty()) return 0;
        std::sort(t.begin(), t.end());
        return t[std::min(t.size() - 1, std::size_t(q * double(t.size())))];
    }
};

using bench::time_ns;  // thread CPU time per call over a ≥ 20 µs batch (batch_timer.hpp)

/// The long-double reference `ref` clamped into its certified interval (test::certified_interval).
template <class A, class B, class R>
LD certified_reference(const A& a, const Transform<LD>& pa, const B& b, const Transform<LD>& pb, const R& ref,
                       const Vec3<double>& tested_normal) {
    const auto [lower, upper] = test::certified_interval(a, pa, b, pb, ref, tested_normal);
    return std::clamp(ref.distance, lower, upper);
}

volatile double g_sink = 0;
constexpr int reps = 16;  // calls per timed batch (one configuration)

/// The boolean variants of the fair table (issue 37): cdkit with one pre-test off, then with all of them off.
enum Off { off_balls, off_containment, off_axes, off_momentum, off_all, off_count };
constexpr const char* off_names[off_count] = {"balls", "containment", "axes", "momentum", "all"};
/// Which of them run (`--off LIST`; all by default).
bool g_off_enabled[off_count] = {true, true, true, true, true};
/// The settings of variant `k`: GjkSettings with that pre-test off (all of them, and momentum, for off_all).
GjkSettings<double> off_settings(int k) {
    GjkSettings<double> s;
    if (k == off_balls || k == off_all) s.bounding_ball_test = false;
    if (k == off_containment || k == off_all) s.containment_test = false;
    if (k == off_axes || k == off_all) s.candidate_axes = false;
    if (k == off_momentum || k == off_all) s.momentum_iterations = 0;
    return s;
}

struct Row {
    std::string family, cls;
    Stats cd_bool, cd_dist, cd_epa, ccd_gjk, ccd_mpr, ccd_pen;
    Stats fcl_indep_bool, fcl_indep_dist, fcl_indep_pen, fcl_ccd_bool, fcl_ccd_dist, fcl_ccd_pen;
    long cd_bool_balls = 0;  ///< configurations the boolean decided by the bounding-ball pre-test (0 iterations)
    Stats cd_epa_bracket{};  ///< EPA's own bracket (depth − depth_lower)/depth as its "error" (cd_epa's times)
    Stats cd_bool_off[off_count];    ///< cdkit's boolean with a pre-test off (Off), and plain GJK (off_all)
    Stats ccd_gjk_hint{};            ///< libccd's GJK with cdkit's hinted hull support (a cold hint per query)
    Stats ccd_gjk_ball{};            ///< the same after cdkit's bounding-ball pre-test ("libccd + ball")
};

/// ns per call of each query, interleaved: three rounds, each timing every enabled query once in turn
/// (time_ns: an untimed call, then a batch of ≥ 20 µs), the fastest of its three batches kept.
template <std::size_t I, std::size_t N> void time_each(const std::array<bool, N>&, std::array<double, N>&) {}
template <std::size_t I, std::size_t N, class F, class... R>
void time_each(const std::array<bool, N>& enabled, std::array<double, N>& best, F& f, R&... rest) {
    if (enabled[I]) best[I] = std::min(best[I], time_ns(f, reps));
    time_each<I + 1>(enabled, best, rest...);
}
template <std::size_t N, class... F> std::array<double, N> fastest_of_3(const std::array<bool, N>& enabled, F&&... f) {
    static_assert(sizeof...(F) == N);
    std::array<double, N> best;
    best.fill(std::numeric_limits<double>::infinity());
    for (int round = 0; round < 3; ++round) time_each<0>(enabled, best, f...);
    return best;
}

/// One family: `make(rng)` returns {shape<double>, shape<long double>} pairs; scale = size of the shapes.
template <class Make> void run_family(const char* name, Make make, double scale, int configs, std::vector<Row>& rows,
                                      std::mt19937_64& rng, bool measure = true) {
    const double targets[3][4] = {{5, 2.5, 1, 0.5}, {1e-1, 1e-2, 1e-3, 1e-4}, {-1e-1, -1e-2, -1e-3, -1e-4}};
    const char* cls[3] = {"distant", "close", "overlapping"};
    for (int c = 0; c < 3; ++c) {
        Row row;
        row.family = name;
        row.cls = cls[c];
        for (int k = 0; k < configs; ++k) {
            // Pairs unpacked by reference, not structured bindings: clang 14 cannot capture those in lambdas.
            auto shapes_a = make(rng);
            auto shapes_b = make(rng);
            auto& a = shapes_a.first;
            auto& al = shapes_a.second;
            auto& b = shapes_b.first;
            auto& bl = shapes_b.second;
            Transform<double> pa(random_rotation(rng), Vec3<double>::Zero());
            std::normal_distribution<double> g;
            Transform<double> pb(random_rotation(rng), Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 4 * scale);
            if (!measure) continue;  // the draws of a measured family are made; nothing else uses the generator
            GjkSettings<LD> tight;
            tight.rel_tolerance = 1e-16L;
            auto d0 = gjk_distance(al, pa.cast<LD>(), bl, pb.cast<LD>(), nullptr, tight);
            double target = targets[c][k % 4] * scale;
            pb.t += (target - double(d0.distance)) * d0.normal.template cast<double>();
            const Transform<LD> pal = pa.cast<LD>(), pbl = pb.cast<LD>();
            // Reference in long double.
            EpaSettings<LD> es;
            es.rel_tolerance = 1e-14L;
            es.gjk = tight;
            es.max_iterations = 150;
            auto ref = penetration(al, pal, bl, pbl, es);
            const bool ref_hit = ref.status == GjkStatus::intersecting ||
                                 ((ref.status == GjkStatus::max_iterations || ref.status == GjkStatus::degenerate) &&
                                  ref.depth > 0);
            const double ref_val = double(ref_hit ? ref.depth : ref.distance);

            GjkResult<double> rb, rd;
            double ref_c = ref_val;  // the distance reference (certified-clamped) on separated pairs
            auto bool_err = [&](bool hit) { return (hit != ref_hit && std::abs(ref_val) > 1e-6 * scale) ? 1.0 : 0.0; };
            bench::CcdObject oa = bench::make_ccd_object(a, pa), ob = bench::make_ccd_object(b, pb);
            ccd_t ccd = bench::make_ccd();
            {
                // The booleans (issue 37's fair table): cdkit by default, with each pre-test off and as plain GJK;
                // libccd's GJK plain, with cdkit's hinted hull support (the hint slot cdkit's GJK keeps, reset
                // per query as cdkit's cold boolean resets it), and with that and cdkit's bounding-ball pre-test
                // in front (libccd + ball); libccd's MPR. All on this pose, interleaved, fastest of 3 batches.
                // Each cdkit result is constructed in place (as `auto r = gjk_intersect(...)` would be) and only a
                // scalar leaves the timed call; assigning the ~600-byte GjkResult to an outer variable in the
                // loop cost more than the one-iteration query itself. Untimed calls give the answers.
                const GjkSettings<double> so[off_count] = {off_settings(0), off_settings(1), off_settings(2),
                                                           off_settings(3), off_settings(4)};
                bench::CcdObject oah = bench::make_ccd_object(a, pa, true), obh = bench::make_ccd_object(b, pb, true);
                const double tf = GjkSettings<double>{}.touch_factor * std::numeric_limits<double>::epsilon();
                int hg = 0, hh = 0, hbl = 0, hm = 0;
                auto ccd_ball = [&] {
                    // cdkit's own pre-test (detail::bounding_ball_decides, its slack and all), then libccd.
                    GjkResult<double> br;
                    const Vec3<double> ca = detail::world_center(a, pa), cb = detail::world_center(b, pb);
                    const Vec3<double> delta = ca - cb;
                    if (detail::bounding_ball_decides(a, pa, b, pb, ca, cb, delta, delta.squaredNorm(), tf, br))
                        return int(br.status == GjkStatus::intersecting);
                    oah.hint = obh.hint = std::uint32_t(-1);
                    return ccdGJKIntersect(&oah, &obh, &ccd);
                };
                std::array<bool, 10> on{true, g_off_enabled[0], g_off_enabled[1], g_off_enabled[2], g_off_enabled[3],
                                        g_off_enabled[4], true, true, true, true};
                const auto t = fastest_of_3(
                    on, [&] { const auto r = gjk_intersect(a, pa, b, pb); g_sink = g_sink + r.distance; },
                    [&] { const auto r = gjk_intersect(a, pa, b, pb, nullptr, so[0]); g_sink = g_sink + r.distance; },
                    [&] { const auto r = gjk_intersect(a, pa, b, pb, nullptr, so[1]); g_sink = g_sink + r.distance; },
                    [&] { const auto r = gjk_intersect(a, pa, b, pb, nullptr, so[2]); g_sink = g_sink + r.distance; },
                    [&] { const auto r = gjk_intersect(a, pa, b, pb, nullptr, so[3]); g_sink = g_sink + r.distance; },
                    [&] { const auto r = gjk_intersect(a, pa, b, pb, nullptr, so[4]); g_sink = g_sink + r.distance; },
                    [&] { hg = ccdGJKIntersect(&oa, &ob, &ccd); g_sink = g_sink + hg; },
                    [&] {
                        oah.hint = obh.hint = std::uint32_t(-1);
                        hh = ccdGJKIntersect(&oah, &obh, &ccd);
                        g_sink = g_sink + hh;
                    },
                    [&] { hbl = ccd_ball(); g_sink = g_sink + hbl; },
                    [&] { hm = ccdMPRIntersect(&oa, &ob, &ccd); g_sink = g_sink + hm; });
                rb = gjk_intersect(a, pa, b, pb);
                row.cd_bool_balls += rb.iterations == 0;
                row.cd_bool.add(t[0], rb.iterations, bool_err(rb.colliding));
                for (int k = 0; k < off_count; ++k) {
                    if (!on[std::size_t(k) + 1]) continue;
                    const auto ro = gjk_intersect(a, pa, b, pb, nullptr, so[k]);
                    row.cd_bool_off[k].add(t[std::size_t(k) + 1], ro.iterations, bool_err(ro.colliding));
                }
                row.ccd_gjk.add(t[6], 0, bool_err(hg != 0));
                row.ccd_gjk_hint.add(t[7], 0, bool_err(hh != 0));
                row.ccd_gjk_ball.add(t[8], 0, bool_err(hbl != 0));
                row.ccd_mpr.add(t[9], 0, bool_err(hm != 0));
            }
            {
                const double ns_ = time_ns([&] { const auto r = gjk_distance(a, pa, b, pb); g_sink = g_sink + r.distance; }, reps);
                rd = gjk_distance(a, pa, b, pb);
                ref_c = ref_hit ? ref_val : double(certified_reference(al, pal, bl, pbl, ref, rd.normal));
                row.cd_dist.add(ns_,
                            rd.iterations, ref_hit ? 0 : std::abs(rd.distance - ref_c) / std::max(ref_c, 1e-12));
            }
            if (c == 2 && ref_hit) {
                PenetrationResult<double> rp;
                {
                    const double ns_ = time_ns([&] { const auto r = penetration(a, pa, b, pb); g_sink = g_sink + r.depth; }, reps);
                    rp = penetration(a, pa, b, pb);
                    row.cd_epa.add(ns_,
                               rp.epa_iterations, std::abs(rp.depth - ref_val) / std::max(ref_val, 1e-12));
                    row.cd_epa_bracket.add(ns_, rp.epa_iterations,
                                           (rp.depth - rp.depth_lower) / std::max(rp.depth, 1e-300));
                }
                ccd_real_t depth = 0;
                ccd_vec3_t dir, pos;
                int ok = 0;
                {
                    const double ns_ = time_ns([&] { ok = ccdGJKPenetration(&oa, &ob, &ccd, &depth, &dir, &pos); g_sink = g_sink + depth; }, reps);
                    row.ccd_pen.add(ns_,
                                0, ok == 0 ? std::abs(double(depth) - ref_val) / std::max(ref_val, 1e-12) : 1.0);
                }
            }
            {
                // FCL: its shapes are built from the same descriptions inside fcl_measure, before its timing.
                const bool pen = c == 2 && ref_hit;
                const auto fr = bench::fcl_measure(bench::fcl_desc(a), pa, bench::fcl_desc(b), pb, reps, pen);
                auto fcl_bool_err = [&](const bench::FclQuery& q) { return bool_err(q.hit); };
                // Distances are judged on separated pairs only, as cdkit's (a failed call counts as error 1).
                auto dist_err = [&](const bench::FclQuery& q) {
                    return ref_hit ? 0.0 : q.ok ? std::abs(q.value - ref_c) / std::max(ref_c, 1e-12) : 1.0;
                };
                auto pen_err = [&](const bench::FclQuery& q) {
                    return q.ok ? std::abs(q.value - ref_val) / std::max(ref_val, 1e-12) : 1.0;
                };
                row.fcl_indep_bool.add(fr.indep_bool.ns, 0, fcl_bool_err(fr.indep_bool));
                row.fcl_ccd_bool.add(fr.ccd_bool.ns, 0, fcl_bool_err(fr.ccd_bool));
                row.fcl_indep_dist.add(fr.indep_dist.ns, 0, dist_err(fr.indep_dist));
                row.fcl_ccd_dist.add(fr.ccd_dist.ns, 0, dist_err(fr.ccd_dist));
                if (pen) {
                    row.fcl_indep_pen.add(fr.indep_pen.ns, 0, pen_err(fr.indep_pen));
                    row.fcl_ccd_pen.add(fr.ccd_pen.ns, 0, pen_err(fr.ccd_pen));
                }
            }
        }
        if (measure) rows.push_back(std::move(row));
    }
}

}  // namespace

// ---- P3 hulls of real meshes (issue 39) -------------------------------------------------------------------
// Hulls of the bundled and fetched meshes, each scaled uniformly into [-1, 1]³ about its bounding-box centre,
// paired and posed like P3 (random rotations, B moved along the separating normal to gap +0.5, +1e-3 or −1e-3),
// every method timed on the same pose in turn (interleaved), warm, the fastest of 3 batches of ≥ 200 µs each;
// medians over the poses. Work counters from untimed runs: GJK iterations, support calls per query (a logging
// wrapper around the hull), and ns per support call (the logged (direction, hint) calls replayed and timed).
namespace real_hulls {

/// A hull that logs its support calls (direction, hint; hint −1 for an unhinted call) and otherwise forwards
/// everything the boolean GJK asks of a ConvexPolyhedron, so that the query takes the same path.
template <class H> struct Logged {
    using Scalar = typename H::Scalar;
    static constexpr bool polytope_core = true;
    const H* h = nullptr;
    std::vector<std::pair<Vec3<Scalar>, std::uint32_t>>* log = nullptr;
    std::uint32_t tag = 0;  ///< 0 for A, 1 for B: stored in the hint's top bit of the log
    [[nodiscard]] Vec3<Scalar> support(const Vec3<Scalar>& d) const noexcept {
        log->emplace_back(d, (tag << 31) | 0x7fffffffu);
        return h->support(d);
    }
    [[nodiscard]] Vec3<Scalar> support(const Vec3<Scalar>& d, std::uint32_t& hint) const noexcept {
        log->emplace_back(d, (tag << 31) | (hint & 0x7fffffffu));
        return h->support(d, hint);
    }
    [[nodiscard]] Vec3<Scalar> center() const noexcept { return h->center(); }
    [[nodiscard]] Scalar bounding_radius() const noexcept { return h->bounding_radius(); }
    [[nodiscard]] Scalar inner_radius() const noexcept { return h->inner_radius(); }
    [[nodiscard]] bool contains_strictly(const Vec3<Scalar>& p, Scalar slack) const noexcept {
        return h->contains_strictly(p, slack);
    }
    [[nodiscard]] PointLocation<Scalar> locate(const Vec3<Scalar>& p, Scalar slack, std::uint32_t near) const noexcept {
        return h->locate(p, slack, near);
    }
};

/// Thread-CPU ns per call of `f` over one batch of at least `min_ns` (the call count calibrated once per
/// method and pose by `calibrate`).
template <class F> int calibrate(F&& f, double min_ns) {
    using Steady = std::chrono::steady_clock;
    f();
    int n = 16;
    for (;;) {
        const auto t0 = Steady::now();
        for (int r = 0; r < n; ++r) {
            asm volatile("" ::: "memory");
            f();
        }
        const double ns = std::chrono::duration<double, std::nano>(Steady::now() - t0).count();
        if (ns >= min_ns / 4 || n >= (1 << 22)) return std::max(16, int(double(n) * min_ns / std::max(ns, 1.0)) + 1);
        n *= 8;
    }
}
template <class F> double batch_ns(F&& f, int reps) {
    const auto t0 = cdbench::ThreadCpuClock::now();
    for (int r = 0; r < reps; ++r) {
        asm volatile("" ::: "memory");
        f();
    }
    const auto t1 = cdbench::ThreadCpuClock::now();
    const double total = std::chrono::duration<double, std::nano>(t1 - t0).count() - bench::thread_clock_overhead_ns();
    return std::max(total, 0.0) / reps;
}

/// The mesh's vertices scaled uniformly into [-1, 1]³ about its bounding-box centre.
inline std::vector<Vec3<double>> scaled_mesh_points(const std::string& path) {
    const TriangleMesh<double> m = load_mesh(path);
    Vec3<double> lo = Vec3<double>::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& v : m.vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
    const Vec3<double> c = (lo + hi) / 2;
    const double s = 2.0 / (hi - lo).maxCoeff();
    std::vector<Vec3<double>> p;
    p.reserve(m.vertices.size());
    for (const auto& v : m.vertices) p.push_back((v - c) * s);
    return p;
}

struct Method {
    const char* name;
    std::vector<double> ns;
    double iterations = 0, support_calls = 0, support_ns = 0;  // sums over poses
    long wrong = 0, n = 0;
    double median() {
        if (ns.empty()) return 0;
        std::vector<double> t = ns;
        std::nth_element(t.begin(), t.begin() + long(t.size() / 2), t.end());
        return t[t.size() / 2];
    }
};
struct Cell {
    std::string pair;
    std::size_t va = 0, vb = 0;
    double gap = 0;
    std::vector<Method> m;
};

/// Counting libccd support callback (the counter behind the object's pointer).
struct CountedCcdObject {
    bench::CcdObject o;
    long* calls;
};
inline void ccd_support_counted(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
    const auto* c = static_cast<const CountedCcdObject*>(obj);
    ++*c->calls;
    bench::ccd_support(&c->o, dir, out);
}
inline void ccd_center_counted(const void* obj, ccd_vec3_t* out) {
    bench::ccd_center(&static_cast<const CountedCcdObject*>(obj)->o, out);
}

/// Measures one hull pair at the three gaps. `H` is the hull type under test (ConvexPolyhedron<double>, or a
/// variant for an A/B), `HL` its long-double twin for the reference. Appends one Cell per gap.
template <class H, class HL>
void measure_pair(const std::string& name, const H& a, const HL& al, const H& b, const HL& bl, int poses,
                  std::uint64_t seed, std::vector<Cell>& cells) {
    const double gaps[3] = {0.5, 1e-3, -1e-3};
    GjkSettings<double> off;  // every pre-test and momentum off: plain GJK
    off.bounding_ball_test = false;
    off.containment_test = false;
    off.candidate_axes = false;
    off.momentum_iterations = 0;
    GjkSettings<LD> tight;
    tight.rel_tolerance = 1e-16L;
    std::mt19937_64 rng(seed);
    for (double gap : gaps) {
        Cell cell{name, a.vertices().size(), b.vertices().size(), gap,
                  {{"cdkit GJK boolean", {}}, {"cdkit GJK boolean (pre-tests off)", {}}, {"libccd GJK boolean", {}},
                   {"libccd MPR boolean", {}}}};
        for (int k = 0; k < poses; ++k) {
            Transform<double> pa(random_rotation(rng), Vec3<double>::Zero());
            std::normal_distribution<double> g;
            Transform<double> pb(random_rotation(rng), Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 4);
            const auto d0 = gjk_distance(al, pa.cast<LD>(), bl, pb.cast<LD>(), nullptr, tight);
            pb.t += (gap - double(d0.distance)) * d0.normal.template cast<double>();
            // The placement's answer, confirmed by the long-double GJK (its distance for the separated gaps).
            const auto ref = gjk_distance(al, pa.cast<LD>(), bl, pb.cast<LD>(), nullptr, tight);
            const bool hit = gap < 0;
            if (ref.colliding != hit || (!hit && std::abs(double(ref.distance) - gap) > 1e-9))
                std::printf("  reference disagrees with the placement: %s gap %g pose %d: distance %.17Lg\n",
                            name.c_str(), gap, k, ref.distance);
            bench::CcdObject oa = bench::make_ccd_object(a, pa), ob = bench::make_ccd_object(b, pb);
            ccd_t ccd = bench::make_ccd();
            int answer[4] = {};
            auto q0 = [&] { const auto r = gjk_intersect(a, pa, b, pb); answer[0] = r.colliding; g_sink = g_sink + r.distance; };
            auto q1 = [&] { const auto r = gjk_intersect(a, pa, b, pb, nullptr, off); answer[1] = r.colliding; g_sink = g_sink + r.distance; };
            auto q2 = [&] { answer[2] = ccdGJKIntersect(&oa, &ob, &ccd); g_sink = g_sink + answer[2]; };
            auto q3 = [&] { answer[3] = ccdMPRIntersect(&oa, &ob, &ccd); g_sink = g_sink + answer[3]; };
            const int r0 = calibrate(q0, 2e5), r1 = calibrate(q1, 2e5), r2 = calibrate(q2, 2e5), r3 = calibrate(q3, 2e5);
            double best[4] = {1e300, 1e300, 1e300, 1e300};
            for (int round = 0; round < 3; ++round) {  // interleaved: each method once per round
                best[0] = std::min(best[0], batch_ns(q0, r0));
                best[1] = std::min(best[1], batch_ns(q1, r1));
                best[2] = std::min(best[2], batch_ns(q2, r2));
                best[3] = std::min(best[3], batch_ns(q3, r3));
            }
            // Work counters (untimed): iterations, support calls, and the logged support calls replayed.
            std::vector<std::pair<Vec3<double>, std::uint32_t>> log;
            const Logged<H> la{&a, &log, 0}, lb{&b, &log, 1};
            int iters[2];
            double calls[2], per_call[2];
            for (int s = 0; s < 2; ++s) {
                log.clear();
                const auto r = gjk_intersect(la, pa, lb, pb, nullptr, s == 0 ? GjkSettings<double>{} : off);
                iters[s] = r.iterations;
                calls[s] = double(log.size());
                // Replay: each logged call, with its hint, on the hull it was made on.
                auto replay = [&] {
                    std::uint32_t acc = 0;
                    for (const auto& [d, tagged] : log) {
                        const H& h = tagged >> 31 ? b : a;
                        const std::uint32_t hint = tagged & 0x7fffffffu;
                        acc += hint == 0x7fffffffu ? h.support_index(d) : h.support_index(d, hint);
                    }
                    g_sink = g_sink + acc;
                };
                per_call[s] = log.empty() ? 0 : batch_ns(replay, calibrate(replay, 2e5)) / double(log.size());
            }
            long ccd_calls[2] = {0, 0};
            {
                CountedCcdObject ca{oa, &ccd_calls[0]}, cb{ob, &ccd_calls[0]};
                ccd_t c = bench::make_ccd();
                c.support1 = c.support2 = ccd_support_counted;
                c.center1 = c.center2 = ccd_center_counted;
                (void)ccdGJKIntersect(&ca, &cb, &c);
                ca.calls = cb.calls = &ccd_calls[1];
                (void)ccdMPRIntersect(&ca, &cb, &c);
            }
            for (int i = 0; i < 4; ++i) {
                Method& m = cell.m[std::size_t(i)];
                m.ns.push_back(best[i]);
                m.wrong += bool(answer[i]) != hit;
                ++m.n;
            }
            for (int s = 0; s < 2; ++s) {
                cell.m[std::size_t(s)].iterations += iters[s];
                cell.m[std::size_t(s)].support_calls += calls[s];
                cell.m[std::size_t(s)].support_ns += per_call[s];
            }
            cell.m[2].support_calls += double(ccd_calls[0]);
            cell.m[3].support_calls += double(ccd_calls[1]);
        }
        cells.push_back(std::move(cell));
    }
}

}  // namespace real_hulls

namespace real_hulls {
/// Prints the cells as a table: per method the median ns, and for cdkit the mean iterations, support calls per
/// query and ns per support call; then the ratios libccd / cdkit.
inline void print_cells(std::vector<Cell>& cells, const char* title) {
    std::printf("%s\n", title);
    std::printf("%-22s %-12s %6s | %-34s | %-34s | %-15s | %-15s | ccdGJK/cd ccdMPR/cd (pre-tests off: GJK MPR) | wrong\n",
                "pair", "hull verts", "gap", "cdkit ns (it, supports, ns/support)",
                "cdkit pre-tests off (same)", "libccd GJK (sup)", "libccd MPR (sup)");
    for (auto& c : cells) {
        auto cd = [](Method& m) {
            char buf[80];
            const double n = double(std::max(m.n, 1L));
            std::snprintf(buf, sizeof buf, "%7.0f (%5.1f, %5.1f, %5.1f)", m.median(), m.iterations / n,
                          m.support_calls / n, m.support_ns / n);
            return std::string(buf);
        };
        auto peer = [](Method& m) {
            char buf[48];
            std::snprintf(buf, sizeof buf, "%7.0f (%5.1f)", m.median(), m.support_calls / double(std::max(m.n, 1L)));
            return std::string(buf);
        };
        char verts[32];
        std::snprintf(verts, sizeof verts, "%zu/%zu", c.va, c.vb);
        const double c0 = c.m[0].median(), c1 = c.m[1].median();
        std::printf("%-22s %-12s %6g | %-34s | %-34s | %-15s | %-15s | %5.2f %5.2f (%5.2f %5.2f) | %ld %ld %ld %ld\n",
                    c.pair.c_str(), verts, c.gap, cd(c.m[0]).c_str(), cd(c.m[1]).c_str(), peer(c.m[2]).c_str(),
                    peer(c.m[3]).c_str(), c.m[2].median() / c0, c.m[3].median() / c0, c.m[2].median() / c1,
                    c.m[3].median() / c1, c.m[0].wrong, c.m[1].wrong, c.m[2].wrong, c.m[3].wrong);
    }
}
}  // namespace real_hulls

namespace {

/// One cell of the fair boolean table (issue 37): its columns in order, NaN where a variant did not run.
struct FairCell {
    std::string family, cls;
    long configs = 0, cdkit_wrong = 0, libccd_wrong = 0;
    std::vector<double> v;  // the numeric columns of fair_columns, in order
};
constexpr const char* fair_columns[] = {
    "balls_decide", "cdkit_ns", "cdkit_it", "no_balls_ns", "no_containment_ns", "no_axes_ns", "no_momentum_ns",
    "plain_ns", "plain_it", "libccd_gjk_ns", "libccd_hint_ns", "libccd_ball_ns", "libccd_mpr_ns", "default_vs_libccd",
    "default_vs_libccd_ball", "plain_vs_libccd_hint"};
constexpr int fair_n = int(sizeof fair_columns / sizeof fair_columns[0]);

FairCell fair_cell(Row& r) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    auto med = [&](Stats& s) { return s.n ? s.pct(0.5) : nan; };
    auto it = [&](Stats& s) { return s.n ? s.it / double(s.n) : nan; };
    FairCell c{r.family, r.cls, r.cd_bool.n, r.cd_bool.wrong, r.ccd_gjk.wrong, {}};
    for (Stats& s : r.cd_bool_off) c.cdkit_wrong += s.wrong;
    const double cd = med(r.cd_bool), plain = med(r.cd_bool_off[off_all]);
    c.v = {double(r.cd_bool_balls) / double(std::max(r.cd_bool.n, 1L)), cd, it(r.cd_bool),
           med(r.cd_bool_off[off_balls]), med(r.cd_bool_off[off_containment]), med(r.cd_bool_off[off_axes]),
           med(r.cd_bool_off[off_momentum]), plain, it(r.cd_bool_off[off_all]), med(r.ccd_gjk), med(r.ccd_gjk_hint),
           med(r.ccd_gjk_ball), med(r.ccd_mpr), med(r.ccd_gjk) / cd, med(r.ccd_gjk_ball) / cd,
           med(r.ccd_gjk_hint) / plain};
    return c;
}

/// The cells and, per distance class, a `median` row: each column's median over the shape families.
std::vector<FairCell> fair_cells(std::vector<Row>& rows) {
    std::vector<FairCell> cells;
    for (Row& r : rows) cells.push_back(fair_cell(r));
    for (const char* cls : {"distant", "close", "overlapping"}) {
        FairCell m{"median", cls, 0, 0, 0, std::vector<double>(fair_n, std::numeric_limits<double>::quiet_NaN())};
        for (int j = 0; j < fair_n; ++j) {
            std::vector<double> x;
            for (const FairCell& c : cells)
                if (c.cls == cls && c.family != "median" && !std::isnan(c.v[std::size_t(j)])) x.push_back(c.v[std::size_t(j)]);
            if (x.empty()) continue;
            std::sort(x.begin(), x.end());
            const std::size_t h = x.size() / 2;
            m.v[std::size_t(j)] = x.size() % 2 ? x[h] : (x[h - 1] + x[h]) / 2;
        }
        for (const FairCell& c : cells)
            if (c.cls == cls && c.family != "median") {
                m.configs += c.configs;
                m.cdkit_wrong += c.cdkit_wrong;
                m.libccd_wrong += c.libccd_wrong;
            }
        if (m.configs) cells.push_back(std::move(m));
    }
    return cells;
}

/// A column's value as the CSV and the table print it: ns to 0.1, fractions and ratios to 0.01, "" for NaN.
std::string fair_value(int j, double x) {
    if (std::isnan(x)) return "";
    char buf[32];
    const std::string name = fair_columns[j];
    std::snprintf(buf, sizeof buf, name.ends_with("_ns") ? "%.1f" : "%.2f", x);
    return buf;
}

void print_fair_table(std::vector<Row>& rows) {
    std::printf("\nFair booleans (issue 37): median ns per call over the cell's configurations, each the fastest of 3 "
                "interleaved batches;\n cdkit by default, with one pre-test off, and plain (all off, no momentum); "
                "libccd GJK plain, with cdkit's hinted support (hint),\n and with that and cdkit's bounding-ball "
                "pre-test (ball); balls = share the ball pre-test decided; ratios: libccd / cdkit\n");
    std::printf("%-10s %-11s %5s | %7s %5s | %7s %7s %7s %7s | %7s %5s | %7s %7s %7s %7s | %7s %7s %7s | wrong\n",
                "family", "class", "balls", "cdkit", "it", "-balls", "-contn", "-axes", "-momnt", "plain", "it",
                "ccdGJK", "hint", "ball", "ccdMPR", "def/GJK", "def/bal", "pln/hnt");
    for (const FairCell& c : fair_cells(rows)) {
        std::printf("%-10s %-11s", c.family.c_str(), c.cls.c_str());
        for (int j = 0; j < fair_n; ++j) {
            const std::string v = fair_value(j, c.v[std::size_t(j)]);
            std::printf(j == 0 ? " %5s" : (j == 1 || j == 3 || j == 7 || j == 9 || j == 13) ? " | %7s" : " %7s",
                        v.empty() ? "-" : v.c_str());
        }
        std::printf(" | %ld %ld\n", c.cdkit_wrong, c.libccd_wrong);
    }
}

void write_fair_csv(std::FILE* f, std::vector<Row>& rows) {
    std::fprintf(f, "family,class,configs");
    for (const char* name : fair_columns) std::fprintf(f, ",%s", name);
    std::fprintf(f, ",cdkit_wrong,libccd_wrong\n");
    for (const FairCell& c : fair_cells(rows)) {
        std::fprintf(f, "%s,%s,%ld", c.family.c_str(), c.cls.c_str(), c.configs);
        for (int j = 0; j < fair_n; ++j) std::fprintf(f, ",%s", fair_value(j, c.v[std::size_t(j)]).c_str());
        std::fprintf(f, ",%ld,%ld\n", c.cdkit_wrong, c.libccd_wrong);
    }
}

}  // namespace

int main(int argc_all, char** argv_all) {
    // Flags (anywhere): --p3-csv PATH (the fair boolean table, with provenance: results/p3.csv), --off LIST (the
    // pre-test-off rows to time: a comma subset of balls,containment,axes,momentum,all, or none; default all of
    // them). The other arguments are the positional ones of the usage line.
    const char* p3_csv = nullptr;
    std::vector<char*> positional{argv_all[0]};
    for (int i = 1; i < argc_all; ++i) {
        const std::string arg = argv_all[i];
        if (arg == "--p3-csv" && i + 1 < argc_all) {
            p3_csv = argv_all[++i];
        } else if (arg == "--off" && i + 1 < argc_all) {
            const std::string list = "," + std::string(argv_all[++i]) + ",";
            for (int k = 0; k < off_count; ++k)
                g_off_enabled[k] = list.find("," + std::string(off_names[k]) + ",") != std::string::npos;
        } else {
            positional.push_back(argv_all[i]);
        }
    }
    const int argc = int(positional.size());
    char** argv = positional.data();
    int configs = argc > 1 ? std::atoi(argv[1]) : 100;
    long checks = argc > 2 ? std::atol(argv[2]) : 1000000;
    const char* csv_path = argc > 3 && std::string(argv[3]) != "-" ? argv[3] : nullptr;
    const std::string families = argc > 4 ? "," + std::string(argv[4]) + "," : std::string();
    auto wanted = [&](const char* f) { return families.empty() || families.find("," + std::string(f) + ",") != std::string::npos; };
    std::mt19937_64 rng(20261122);
    std::vector<Row> rows;
    std::uniform_real_distribution<double> u(0.5, 1.0);
    auto ell = [&](std::mt19937_64& r) {
        std::normal_distribution<double> g(0.1, 0.025);
        Vec3<double> rad(std::abs(g(r)) + 0.01, std::abs(g(r)) + 0.01, std::abs(g(r)) + 0.01);
        return std::pair{Ellipsoid<double>(rad), Ellipsoid<LD>(rad.cast<LD>())};
    };
    auto box = [&](std::mt19937_64& r) {
        Vec3<double> h(0.1 * u(r), 0.1 * u(r), 0.1 * u(r));
        return std::pair{Box<double>(h), Box<LD>(h.cast<LD>())};
    };
    auto cap = [&](std::mt19937_64& r) {
        double a = 0.05 * u(r), b = 0.1 * u(r);
        return std::pair{Capsule<double>(a, b), Capsule<LD>(a, b)};
    };
    auto cyl = [&](std::mt19937_64& r) {
        double a = 0.1 * u(r), b = 0.1 * u(r);
        return std::pair{Cylinder<double>(a, b), Cylinder<LD>(a, b)};
    };
    auto cone = [&](std::mt19937_64& r) {
        double a = 0.1 * u(r), b = 0.1 * u(r);
        return std::pair{Cone<double>(a, b), Cone<LD>(a, b)};
    };
    auto hull = [&](int n) {
        return [n](std::mt19937_64& r) {
            auto p = cloud(r, n, 0.1);
            return std::pair{ConvexPolyhedron<double>(p), ConvexPolyhedron<LD>(castv<Vec3<LD>>(p))};
        };
    };
    run_family("ellipsoid", ell, 0.1, configs, rows, rng, wanted("ellipsoid"));
    run_family("box", box, 0.1, configs, rows, rng, wanted("box"));
    run_family("capsule", cap, 0.1, configs, rows, rng, wanted("capsule"));
    run_family("cylinder", cyl, 0.1, configs, rows, rng, wanted("cylinder"));
    run_family("cone", cone, 0.1, configs, rows, rng, wanted("cone"));
    run_family("hull100", hull(100), 0.1, configs, rows, rng, wanted("hull100"));
    run_family("hull1000", hull(1000), 0.1, configs, rows, rng, wanted("hull1000"));
    if (wanted("real")) {
        // Hulls of real meshes, scaled into [-1, 1]³; the data directory next to this source file's repository.
        const std::filesystem::path data = std::filesystem::path(__FILE__).parent_path() / "../../data";
        struct RealPair { const char* name; const char* a; const char* b; };
        const RealPair pairs[] = {{"bunny-teapot", "bunny.obj", "teapot.obj"},
                                  {"dragon48k-armadillo", "dragon/dragon_48k.ply", "armadillo.obj"},
                                  {"dragon203k-bunny", "dragon/dragon_203k.ply", "bunny.obj"},
                                  {"dragon871k-dragon48k", "dragon/dragon_871k.ply", "dragon/dragon_48k.ply"}};
        std::vector<real_hulls::Cell> cells;
        for (const RealPair& p : pairs) {
            if (!std::filesystem::exists(data / p.a) || !std::filesystem::exists(data / p.b)) {
                std::printf("real hulls: %s skipped (run scripts/fetch-data for data/dragon/)\n", p.name);
                continue;
            }
            const ConvexPolyhedron<double> a(real_hulls::scaled_mesh_points((data / p.a).string()));
            const ConvexPolyhedron<double> b(real_hulls::scaled_mesh_points((data / p.b).string()));
            const ConvexPolyhedron<LD> al(castv<Vec3<LD>>(a.vertices())), bl(castv<Vec3<LD>>(b.vertices()));
            real_hulls::measure_pair(p.name, a, al, b, bl, configs, 39, cells);
        }
        // Random-cloud hulls (P3's hull100 / hull1000 clouds), scaled to the same size and measured the same way.
        for (int n : {100, 1000}) {
            std::mt19937_64 r(39 + std::uint64_t(n));
            const auto pa = cloud(r, n, 1.0), pb = cloud(r, n, 1.0);
            const ConvexPolyhedron<double> a(pa), b(pb);
            const ConvexPolyhedron<LD> al(castv<Vec3<LD>>(pa)), bl(castv<Vec3<LD>>(pb));
            real_hulls::measure_pair(n == 100 ? "cloud100-cloud100" : "cloud1000-cloud1000", a, al, b, bl, configs,
                                     39, cells);
        }
        real_hulls::print_cells(cells, "\nP3 hulls of real meshes (scaled into [-1,1]^3) and of random clouds: median ns per "
                                       "boolean query, fastest of 3 interleaved batches >= 200 us per pose");
        if (argc > 5) {
            if (FILE* f = std::fopen(argv[5], "w")) {
                std::fprintf(f, "pair,hull_vertices,gap,method,poses,median_ns,mean_iterations,support_calls,"
                                "ns_per_support,ratio_ccd_gjk,ratio_ccd_mpr,wrong\n");
                for (auto& c : cells)
                    for (auto& m : c.m) {
                        const double n = double(std::max(m.n, 1L));
                        const bool cd = &m == &c.m[0] || &m == &c.m[1];
                        std::fprintf(f, "%s,%zu/%zu,%g,%s,%ld,%.0f,%s,%.1f,%s,%.2f,%.2f,%ld\n", c.pair.c_str(), c.va, c.vb,
                                     c.gap, m.name, m.n, m.median(), cd ? std::to_string(m.iterations / n).substr(0, 4).c_str() : "",
                                     m.support_calls / n, cd ? std::to_string(m.support_ns / n).substr(0, 4).c_str() : "",
                                     c.m[2].median() / m.median(), c.m[3].median() / m.median(), m.wrong);
                    }
                std::fclose(f);
                std::printf("wrote %s\n", argv[5]);
            }
        }
    }

    std::printf("P3 convex pairs: %d configurations per cell, each timed as a batch of >= %d calls and >= 20 us "
                "of thread CPU time (clock cost %.0f ns subtracted); times in ns per call\n",
                configs, reps, bench::thread_clock_overhead_ns());
    std::printf("%-10s %-11s | %-26s | %-26s | %-26s | %-17s | %-17s | %-17s | bool ratio ccdGJK/cd, ccdMPR/cd; pen ratio | balls | EPA bracket\n",
                "family", "class", "cd bool med/p99 it err", "cd dist med/p99 it relerr", "cd EPA med/p99 it relerr",
                "ccd GJK med err", "ccd MPR med err", "ccd pen med relerr");
    for (auto& r : rows) {
        auto cell = [](Stats& s, bool with_it) {
            char buf[96];
            if (s.n == 0) std::snprintf(buf, sizeof buf, "%26s", "-");
            else if (with_it)
                std::snprintf(buf, sizeof buf, "%7.0f/%7.0f %4.1f %.1e", s.pct(0.5), s.pct(0.99), s.it / double(s.n), s.err);
            else std::snprintf(buf, sizeof buf, "%7.0f %.1e", s.pct(0.5), s.err);
            return std::string(buf);
        };
        double cb = r.cd_bool.pct(0.5);
        char bracket[32] = "-";
        if (r.cd_epa_bracket.n) std::snprintf(bracket, sizeof bracket, "%.1e", r.cd_epa_bracket.err);
        std::printf("%-10s %-11s | %s | %s | %s | %17s | %17s | %17s | %5.2f %5.2f %5.2f | %3.0f%% | %s\n", r.family.c_str(),
                    r.cls.c_str(), cell(r.cd_bool, true).c_str(), cell(r.cd_dist, true).c_str(),
                    cell(r.cd_epa, true).c_str(), cell(r.ccd_gjk, false).c_str(), cell(r.ccd_mpr, false).c_str(),
                    cell(r.ccd_pen, false).c_str(), r.ccd_gjk.pct(0.5) / cb, r.ccd_mpr.pct(0.5) / cb,
                    r.cd_epa.n ? r.ccd_pen.pct(0.5) / r.cd_epa.pct(0.5) : 0.0,
                    100.0 * double(r.cd_bool_balls) / double(std::max(r.cd_bool.n, 1L)), bracket);
    }
    std::printf("(err for booleans: max over cells of a wrong answer where |reference| > 1e-6·scale, 1 = some wrong; "
                "balls: share of the cell's configurations the cdkit boolean decided by its bounding-ball pre-test;\n"
                " EPA bracket: the largest (depth - depth_lower)/depth EPA itself reported in the cell, the width of its\n"
                " certified interval, which needs no reference)\n");
    // FCL 0.7 on the same configurations (see peer_fcl.hpp for the code each column runs); ratios are FCL's
    // median over cdkit's median of the same query (boolean: cd GJK boolean; distance: cd GJK distance;
    // penetration: cd EPA).
    std::printf("\nFCL 0.7, same configurations: median ns and error (booleans: wrong fraction; distance, depth: "
                "max relative error); ratio = FCL median / cdkit median\n");
    std::printf("%-10s %-11s | %-17s | %-17s | %-17s | %-17s | %-17s | %-17s | %-35s\n", "family", "class",
                "indep bool", "libccd(MPR) bool", "indep dist", "libccd dist", "indep pen (EPA)", "libccd pen (MPR)",
                "ratio bool i/l  dist i/l  pen i/l");
    for (auto& r : rows) {
        auto cell = [](Stats& s, bool fraction) {
            char buf[64];
            if (s.n == 0) std::snprintf(buf, sizeof buf, "%17s", "-");
            else std::snprintf(buf, sizeof buf, "%7.0f %9.1e", s.pct(0.5),
                               fraction ? double(s.wrong) / double(s.n) : s.err);
            return std::string(buf);
        };
        auto ratio = [](Stats& f, Stats& cd) { return f.n && cd.n ? f.pct(0.5) / cd.pct(0.5) : 0.0; };
        std::printf("%-10s %-11s | %s | %s | %s | %s | %s | %s | %5.2f %5.2f  %5.2f %5.2f  %5.2f %5.2f\n",
                    r.family.c_str(), r.cls.c_str(), cell(r.fcl_indep_bool, true).c_str(),
                    cell(r.fcl_ccd_bool, true).c_str(), cell(r.fcl_indep_dist, false).c_str(),
                    cell(r.fcl_ccd_dist, false).c_str(), cell(r.fcl_indep_pen, false).c_str(),
                    cell(r.fcl_ccd_pen, false).c_str(), ratio(r.fcl_indep_bool, r.cd_bool),
                    ratio(r.fcl_ccd_bool, r.cd_bool), ratio(r.fcl_indep_dist, r.cd_dist),
                    ratio(r.fcl_ccd_dist, r.cd_dist), ratio(r.fcl_indep_pen, r.cd_epa), ratio(r.fcl_ccd_pen, r.cd_epa));
    }
    std::printf("(FCL booleans: box/box runs FCL's boxBoxIntersect (SAT) in both solvers, capsule/capsule distance its "
                "closed form; indep boolean includes FCL's EPA on overlapping pairs)\n");
    print_fair_table(rows);
    if (p3_csv) {
        if (std::FILE* f = std::fopen(p3_csv, "w")) {
            cdbench::write_provenance(f, argc_all, argv_all);
            write_fair_csv(f, rows);
            std::fclose(f);
            std::printf("wrote %s\n", p3_csv);
        } else {
            std::printf("cannot write %s\n", p3_csv);
        }
    }
    if (csv_path) {
        if (FILE* f = std::fopen(csv_path, "w")) {
            std::fprintf(f, "family,class,method,median_ns,p99_ns,mean_iterations,max_error,fraction_in_error,n\n");
            for (auto& r : rows) {
                auto put = [&](const char* method, Stats& st) {
                    if (st.n == 0) return;
                    std::fprintf(f, "%s,%s,%s,%.1f,%.1f,%.3f,%.3e,%.5f,%ld\n", r.family.c_str(), r.cls.c_str(), method,
                                 st.pct(0.5), st.pct(0.99), st.it / double(st.n), st.err,
                                 double(st.wrong) / double(st.n), st.n);
                };
                put("cdkit GJK boolean", r.cd_bool);
                put("cdkit GJK distance", r.cd_dist);
                put("cdkit EPA", r.cd_epa);
                put("cdkit EPA bracket", r.cd_epa_bracket);  // max_error: the largest (depth - depth_lower)/depth
                put("libccd GJK boolean", r.ccd_gjk);
                put("libccd MPR boolean", r.ccd_mpr);
                put("libccd GJK+EPA penetration", r.ccd_pen);
                put("FCL indep GJK boolean", r.fcl_indep_bool);
                put("FCL indep GJK distance", r.fcl_indep_dist);
                put("FCL indep GJK+EPA penetration", r.fcl_indep_pen);
                put("FCL libccd MPR boolean", r.fcl_ccd_bool);
                put("FCL libccd GJK distance", r.fcl_ccd_dist);
                put("FCL libccd MPR penetration", r.fcl_ccd_pen);
            }
            std::fclose(f);
            std::printf("wrote %s\n", csv_path);
        } else {
            std::printf("cannot write %s\n", csv_path);
        }
    }

    // The checked counter (checked_counter.hpp): every class judged by an oracle independent of cdkit's GJK.
    if (checks > 0 && cdbench::run_checked_counter(checks) != 0) return 1;
    return 0;
}
