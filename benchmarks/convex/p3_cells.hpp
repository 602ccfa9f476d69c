#pragma once
// P3's cells (BENCHMARKS.md): per shape family and distance class (distant, close, overlapping), seeded
// configurations placed along the long-double GJK normal, every query of cdkit, libccd and FCL timed on the same
// pose (thread-CPU time, batch_timer.hpp) and its error taken against a long-double reference (cdkit's own
// GJK/EPA in long double, tight tolerances, distances clamped into their certified interval). Also the pre-test-off
// variants of the fair boolean table (fair_table.hpp). Included by bench_convex.cpp only.
#include "../bench_util.hpp"
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/epa.hpp>

#include "../../tests/narrowphase/convex_reference.hpp"  // certified distance bounds, shared with the tests
#include "batch_timer.hpp"
#include "ccd_adapter.hpp"
#include "peer_fcl.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace cdbench::p3 {

using namespace cdkit;
using LD = long double;

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

inline volatile double g_sink = 0;
constexpr int reps = 16;  // calls per timed batch (one configuration)

/// The boolean variants of the fair table (issue 37): cdkit with one pre-test off, then with all of them off.
enum Off { off_balls, off_containment, off_axes, off_momentum, off_all, off_count };
constexpr const char* off_names[off_count] = {"balls", "containment", "axes", "momentum", "all"};
/// Which of them run (`--off LIST`; all by default).
inline bool g_off_enabled[off_count] = {true, true, true, true, true};
/// The settings of variant `k`: GjkSettings with that pre-test off (all of them, and momentum, for off_all).
inline GjkSettings<double> off_settings(int k) {
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

}  // namespace cdbench::p3
