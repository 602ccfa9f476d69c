#pragma once
// P3 hulls of real meshes (issue 39), cdkit_bench_convex's `real` family.
// Hulls of the bundled and fetched meshes, each scaled uniformly into [-1, 1]³ about its bounding-box centre,
// paired and posed like P3 (random rotations, B moved along the separating normal to gap +0.5, +1e-3 or −1e-3),
// every method timed on the same pose in turn (interleaved), warm, the fastest of 3 batches of ≥ 200 µs each;
// medians over the poses. Work counters from untimed runs: GJK iterations, support calls per query (a logging
// wrapper around the hull), and ns per support call (the logged (direction, hint) calls replayed and timed).
#include "p3_cells.hpp"  // the timers, the sink, the libccd adapter
#include <cdkit/io/load_mesh.hpp>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace cdbench::real_hulls {

using namespace cdkit;
using p3::g_sink;
using p3::LD;

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

}  // namespace cdbench::real_hulls
