// Coherent motion (issue 5): two convex polytopes (~20 and ~200 hull vertices) moving a little each frame,
// timed per frame for cold GJK (distance and boolean), warm-started GJK, the separating-plane test with its
// cache, closest-feature tracking with its cache, and libccd's GJK and MPR, all in one process on the same
// precomputed poses, and libccd's GJK with the hulls' hinted support, the hint kept from frame to frame as warm
// GJK's cache keeps it. Each row is compared with its own kind: distances with the cold distance, booleans with
// the cold boolean and with libccd's GJK (plain and with the kept hint). Error rates against a long-double
// reference (cdkit's GJK in long double, tight tolerance, on the shapes placed in the world frame).
// Usage: cdkit_bench_coherent [frames=2000] [repetitions=5] [csv_path]
#include "../provenance.hpp"
#include <cdkit/narrowphase/closest_features.hpp>
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/gjk.hpp>
#include <cdkit/narrowphase/separating_plane.hpp>

#include "ccd_adapter.hpp"
#include "coherent_scene.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace cdkit;
using LD = long double;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int batch = 25;  // consecutive frames per timed batch (a per-query clock read costs 20–30 ns)
using Scene = cdbench::CoherentScene;
using Frame = cdbench::CoherentFrame;

/// One method's per-frame answers and timing.
struct Outcome {
    std::vector<double> batch_ns;  // ns per frame, one entry per batch
    std::vector<char> hit;
    std::vector<double> distance;  // NaN when the method has no distance
    long iterations = 0, fallbacks = 0;
    [[nodiscard]] double median() {
        std::sort(batch_ns.begin(), batch_ns.end());
        return batch_ns.empty() ? 0.0 : batch_ns[batch_ns.size() / 2];
    }
};

volatile double g_sink = 0;

/// One method of the table: its per-frame query and the reset of its caches before each repetition.
template <class Reset, class Query> struct Method {
    const char* name;
    bool distance;  // the method reports a distance
    Reset reset;
    Query query;
};
template <class Reset, class Query> Method(const char*, bool, Reset, Query) -> Method<Reset, Query>;

/// One repetition of one method: all frames, timed in batches of consecutive frames.
template <class M> void run_once(const Scene& s, M& method, Outcome& o) {
    const std::size_t n = s.frames.size();
    method.reset();
    o.iterations = 0;
    o.fallbacks = 0;
    for (std::size_t b = 0; b < n; b += batch) {
        const std::size_t e = std::min(n, b + batch);
        auto t0 = Clock::now();
        for (std::size_t f = b; f < e; ++f) method.query(f, o);
        auto t1 = Clock::now();
        o.batch_ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / double(e - b));
    }
}

/// Runs every method over all frames `reps` times. The repetitions interleave the methods (repetition r runs
/// them all, starting at method r mod count), so that a slow phase of the machine (a neighbour's load, a
/// frequency change) falls on all of them alike instead of on whichever method ran then: the ratios between
/// rows are what the table is for. Each repetition starts with fresh caches (`reset`); answers are kept from the
/// last one. The methods stay separate types (no std::function): their queries are inlined into the timed loop.
template <class... M> std::vector<Outcome> run(const Scene& s, int reps, M&... methods) {
    constexpr std::size_t m = sizeof...(M);
    std::vector<Outcome> out(m);
    for (Outcome& o : out) {
        o.hit.assign(s.frames.size(), 0);
        o.distance.assign(s.frames.size(), std::nan(""));
    }
    for (int r = 0; r < reps; ++r)
        for (std::size_t k = 0; k < m; ++k) {
            const std::size_t i = (std::size_t(r) + k) % m;
            std::size_t j = 0;
            ((j++ == i ? run_once(s, methods, out[i]) : void()), ...);
        }
    return out;
}

struct Errors {
    long wrong_bool = 0, bool_checked = 0, wrong_dist = 0, dist_checked = 0;
    double worst_rel = 0;
};

Errors errors(const Scene& s, const Outcome& o, double scale) {
    Errors e;
    for (std::size_t f = 0; f < s.frames.size(); ++f) {
        const Frame& fr = s.frames[f];
        // Booleans are judged where the reference is clear of contact by 1e-9·scale.
        if (fr.ref_hit || fr.ref_distance > 1e-9 * scale) {
            ++e.bool_checked;
            e.wrong_bool += bool(o.hit[f]) != fr.ref_hit;
        }
        if (!fr.ref_hit && fr.ref_distance > 1e-9 * scale && !std::isnan(o.distance[f])) {
            ++e.dist_checked;
            const double rel = std::abs(o.distance[f] - fr.ref_distance) / fr.ref_distance;
            e.worst_rel = std::max(e.worst_rel, rel);
            e.wrong_dist += rel > 1e-9;
        }
    }
    return e;
}

}  // namespace

int main(int argc, char** argv) {
    const int frames = argc > 1 ? std::max(batch, std::atoi(argv[1])) : 2000;
    const int reps = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
    std::FILE* csv = argc > 3 ? std::fopen(argv[3], "w") : nullptr;
    if (csv) cdbench::write_provenance(csv, argc, argv);
    std::mt19937_64 rng(cdbench::coherent_seed);
    const cdbench::CoherentPoints pts = cdbench::coherent_points(rng);
    const ConvexPolyhedron<double> a(pts.a), b(pts.b);
    const ConvexPolyhedron<LD> al(cdbench::to_ld(pts.a)), bl(cdbench::to_ld(pts.b));
    const double scale = 1.0;
    std::printf("Coherent motion: A = hull of %zu vertices, B = hull of %zu vertices (size ~1); %d frames x %d "
                "repetitions; per-frame motion: spins 0.5 and 0.7 deg, orbit 0.3 deg\n",
                a.vertices().size(), b.vertices().size(), frames, reps);

    const std::vector<Scene> scenes = cdbench::coherent_scenes(frames, al, bl, rng);
    // vs_cold: the cold query of the row's kind (cold GJK distance for distance rows, cold GJK boolean for boolean
    // rows) over the row; vs_libccd, vs_libccd_hint (boolean rows): libccd's GJK, plain and with the kept hint,
    // over the row. > 1: the row is that many times cheaper per frame.
    if (csv) std::fprintf(csv, "scene,method,kind,median_ns,vs_cold,vs_libccd,vs_libccd_hint,mean_iterations,fallbacks,"
                               "wrong_bool,bool_checked,wrong_dist,dist_checked,worst_rel\n");

    for (const Scene& s : scenes) {
        long ref_hits = 0;
        for (const auto& fr : s.frames) ref_hits += fr.ref_hit;
        std::printf("\nscene %s: %zu frames, %ld colliding (reference)\n", s.name.c_str(), s.frames.size(), ref_hits);
        auto noop = [] {};
        GjkCache<double> gc;
        auto reset_gjk = [&] { gc.size = 0; };
        SeparatingPlaneCache<double> sc;
        auto reset_plane = [&] { sc.valid = false; sc.gjk.size = 0; };
        ClosestFeatureCache<double> cc;
        auto reset_features = [&] { cc.valid = false; cc.gjk.size = 0; };
        ccd_t ccd = bench::make_ccd();
        // A GJK result's answers into the row's outcome (distance rows keep the distance too).
        auto keep = [](Outcome& o, std::size_t f, const GjkResult<double>& r, bool with_distance) {
            o.hit[f] = r.colliding;
            if (with_distance) o.distance[f] = r.distance;
            o.iterations += r.iterations;
        };
        Method cold_distance{"cold GJK distance", true, noop, [&](std::size_t f, Outcome& o) {
                                 keep(o, f, gjk_distance(a, s.frames[f].pa, b, s.frames[f].pb), true);
                             }};
        Method cold_boolean{"cold GJK boolean", false, noop, [&](std::size_t f, Outcome& o) {
                                keep(o, f, gjk_intersect(a, s.frames[f].pa, b, s.frames[f].pb), false);
                            }};
        Method warm_distance{"warm GJK distance", true, reset_gjk, [&](std::size_t f, Outcome& o) {
                                 keep(o, f, gjk_distance(a, s.frames[f].pa, b, s.frames[f].pb, &gc), true);
                             }};
        Method warm_boolean{"warm GJK boolean", false, reset_gjk, [&](std::size_t f, Outcome& o) {
                                keep(o, f, gjk_intersect(a, s.frames[f].pa, b, s.frames[f].pb, &gc), false);
                            }};
        Method plane{"separating plane", false, reset_plane, [&](std::size_t f, Outcome& o) {
                         auto r = separating_plane_intersect(a, s.frames[f].pa, b, s.frames[f].pb, &sc);
                         o.hit[f] = r.colliding;
                         o.iterations += r.iterations;
                         o.fallbacks += r.used_gjk;
                     }};
        // The same without the lecture's repair of a failing plane (straight to warm GJK): the feature-off row.
        SeparatingPlaneCache<double> sc0;
        auto reset_plane0 = [&] { sc0.valid = false; sc0.gjk.size = 0; };
        SeparatingPlaneSettings no_repair;
        no_repair.repair_iterations = 0;
        Method plane0{"plane without repair", false, reset_plane0, [&](std::size_t f, Outcome& o) {
                          auto r = separating_plane_intersect(a, s.frames[f].pa, b, s.frames[f].pb, &sc0, no_repair);
                          o.hit[f] = r.colliding;
                          o.iterations += r.iterations;
                          o.fallbacks += r.used_gjk;
                      }};
        Method features{"closest features", true, reset_features, [&](std::size_t f, Outcome& o) {
                            auto r = closest_features(a, s.frames[f].pa, b, s.frames[f].pb, &cc);
                            o.hit[f] = r.colliding;
                            o.distance[f] = r.distance;
                            o.iterations += r.iterations;
                            o.fallbacks += r.used_gjk;
                        }};
        Method ccd_gjk{"libccd GJK", false, noop, [&](std::size_t f, Outcome& o) {
                           bench::CcdObject oa = bench::make_ccd_object(a, s.frames[f].pa);
                           bench::CcdObject ob = bench::make_ccd_object(b, s.frames[f].pb);
                           o.hit[f] = char(ccdGJKIntersect(&oa, &ob, &ccd) != 0);
                       }};
        Method ccd_mpr{"libccd MPR", false, noop, [&](std::size_t f, Outcome& o) {
                           bench::CcdObject oa = bench::make_ccd_object(a, s.frames[f].pa);
                           bench::CcdObject ob = bench::make_ccd_object(b, s.frames[f].pb);
                           o.hit[f] = char(ccdMPRIntersect(&oa, &ob, &ccd) != 0);
                       }};
        // libccd's GJK given the hint slot that warm GJK keeps in its cache (issue 37): the hulls' hinted support,
        // each hull's last support vertex carried from frame to frame (reset with the repetition, as the cache is).
        std::uint32_t kept_hint[2] = {std::uint32_t(-1), std::uint32_t(-1)};
        auto reset_hint = [&] { kept_hint[0] = kept_hint[1] = std::uint32_t(-1); };
        Method ccd_hint{"libccd GJK kept hint", false, reset_hint, [&](std::size_t f, Outcome& o) {
                            bench::CcdObject oa = bench::make_ccd_object(a, s.frames[f].pa, true);
                            bench::CcdObject ob = bench::make_ccd_object(b, s.frames[f].pb, true);
                            oa.hint = kept_hint[0];
                            ob.hint = kept_hint[1];
                            o.hit[f] = char(ccdGJKIntersect(&oa, &ob, &ccd) != 0);
                            kept_hint[0] = oa.hint;
                            kept_hint[1] = ob.hint;
                        }};
        std::vector<Outcome> outcomes = run(s, reps, cold_distance, cold_boolean, warm_distance, warm_boolean, plane,
                                            features, ccd_gjk, ccd_mpr, plane0, ccd_hint);
        struct Named {
            const char* name;
            Outcome& o;
            bool distance;
        };
        const std::vector<Named> rows = {
            {cold_distance.name, outcomes[0], cold_distance.distance},
            {cold_boolean.name, outcomes[1], cold_boolean.distance},
            {warm_distance.name, outcomes[2], warm_distance.distance},
            {warm_boolean.name, outcomes[3], warm_boolean.distance},
            {plane.name, outcomes[4], plane.distance},
            {features.name, outcomes[5], features.distance},
            {ccd_gjk.name, outcomes[6], ccd_gjk.distance},
            {ccd_mpr.name, outcomes[7], ccd_mpr.distance},
            {plane0.name, outcomes[8], plane0.distance},
            {ccd_hint.name, outcomes[9], ccd_hint.distance}};
        // Each row against its own kind (issue 37): a distance row against the cold distance, a boolean row
        // against the cold boolean and against libccd's GJK (plain, and with the kept hint).
        const double cold_dist = rows[0].o.median(), cold_bool = rows[1].o.median();
        const double ccd_plain = rows[6].o.median(), ccd_kept = rows[9].o.median();
        std::printf("  %-20s | %-8s | %9s | %8s %9s %9s | %7s | %9s | %-22s | %s\n", "method", "kind", "median ns",
                    "cold/x", "libccd/x", "hint/x", "mean it", "GJK used", "wrong booleans",
                    "distance rel.err > 1e-9 (max)");
        for (const Named& row : rows) {
            const double med = row.o.median();
            const char* kind = row.distance ? "distance" : "boolean";
            const double vs_cold = (row.distance ? cold_dist : cold_bool) / med;
            char vs_ccd[16] = "-", vs_kept[16] = "-";
            if (!row.distance) {
                std::snprintf(vs_ccd, sizeof vs_ccd, "%.3f", ccd_plain / med);
                std::snprintf(vs_kept, sizeof vs_kept, "%.3f", ccd_kept / med);
            }
            const Errors e = errors(s, row.o, scale);
            char dist[64] = "-";
            if (row.distance)
                std::snprintf(dist, sizeof dist, "%ld / %ld (%.1e)", e.wrong_dist, e.dist_checked, e.worst_rel);
            char fb[32] = "-";
            if (row.o.fallbacks || std::string(row.name).find("plane") != std::string::npos ||
                std::string(row.name) == "closest features")
                std::snprintf(fb, sizeof fb, "%ld", row.o.fallbacks);
            std::printf("  %-20s | %-8s | %9.0f | %8.2f %9s %9s | %7.2f | %9s | %6ld / %-13ld | %s\n", row.name, kind,
                        med, vs_cold, vs_ccd, vs_kept, double(row.o.iterations) / double(s.frames.size()), fb,
                        e.wrong_bool, e.bool_checked, dist);
            if (csv)
                std::fprintf(csv, "%s,%s,%s,%.1f,%.3f,%s,%s,%.3f,%ld,%ld,%ld,%ld,%ld,%.3e\n", s.name.c_str(), row.name,
                             kind, med, vs_cold, vs_ccd, vs_kept, double(row.o.iterations) / double(s.frames.size()),
                             row.o.fallbacks, e.wrong_bool, e.bool_checked, row.distance ? e.wrong_dist : 0L,
                             row.distance ? e.dist_checked : 0L, row.distance ? e.worst_rel : 0.0);
        }
        g_sink = g_sink + rows[0].o.distance[0];
    }
    std::printf("\n(x = the row's median; cold/x: the cold GJK query of the row's kind (distance or boolean), libccd/x and\n"
                " hint/x (boolean rows): libccd's GJK plain and with the kept hint; ratios > 1: the row is that many\n"
                " times cheaper per frame. Booleans judged\n"
                " where the reference is colliding or > 1e-9 away; GJK used = frames answered by the GJK fallback in\n"
                " the last repetition; mean it = GJK iterations, plane updates or feature-walk steps per frame.)\n");
    if (csv) std::fclose(csv);
    return 0;
}
