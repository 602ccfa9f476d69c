// One side of the in-process A/B of the queries on the coherent-motion scenes (run.sh … coherent): compiled twice,
// as ab_variant.cpp is, into one binary with ab_coherent_main.cpp. The scenes are cdkit_bench_coherent's
// (coherent_scene.hpp, 2000 frames each); every pass runs all frames of one scene with one method, the warm
// methods from an empty cache, thread CPU time over the passes.
#include "../coherent_scene.hpp"

#include <cdkit/narrowphase/closest_features.hpp>
#include <cdkit/narrowphase/separating_plane.hpp>

#include <time.h>
#define CAT2(a, b) a##b
#define CAT(a, b) CAT2(a, b)
using namespace cdkit;
namespace {
double tcpu() { timespec t; clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t); return t.tv_sec * 1e9 + t.tv_nsec; }
volatile double sink;
double checksum(const GjkResult<double>& r) {
    return r.distance + r.normal.sum() + r.point_a.sum() + 3 * r.point_b.sum() + int(r.status) * 7 + r.iterations * 11;
}
}  // namespace
/// ns per frame over `reps` passes; scene 0 separated, 1 near-touching, 2 in-and-out; method 0 cold distance,
/// 1 warm distance, 2 cold boolean, 3 warm boolean, 4 separating plane, 5 closest features. `sig`: a checksum of every result field of the last pass.
double CAT(coh_, VARIANT)(int scene, int method, int reps, double* sig) {
    struct Setup {
        std::mt19937_64 rng{cdbench::coherent_seed};
        cdbench::CoherentPoints pts = cdbench::coherent_points(rng);
        ConvexPolyhedron<double> a{pts.a}, b{pts.b};
        std::vector<cdbench::CoherentScene> scenes =
            cdbench::coherent_scenes(2000, ConvexPolyhedron<cdbench::LD>(cdbench::to_ld(pts.a)),
                                     ConvexPolyhedron<cdbench::LD>(cdbench::to_ld(pts.b)), rng);
    };
    static const Setup setup;
    const auto& frames = setup.scenes[std::size_t(scene)].frames;
    GjkCache<double> cache;
    double t0 = tcpu(), s = 0;
    for (int rep = 0; rep < reps; ++rep) {
        cache.size = 0;
        s = 0;
        if (method == 4) {
            SeparatingPlaneCache<double> plane;
            for (const auto& f : frames) {
                asm volatile("" ::: "memory");
                const auto r = separating_plane_intersect(setup.a, f.pa, setup.b, f.pb, &plane);
                s += r.colliding + 3 * r.used_gjk + 5 * r.iterations + plane.n.sum() + plane.c;
            }
            continue;
        }
        if (method == 5) {
            ClosestFeatureCache<double> features;
            for (const auto& f : frames) {
                asm volatile("" ::: "memory");
                const auto r = closest_features(setup.a, f.pa, setup.b, f.pb, &features);
                s += r.distance + r.normal.sum() + r.point_a.sum() + 3 * r.point_b.sum() + int(r.status) * 7 +
                     r.iterations * 11 + 13 * r.used_gjk;
            }
            continue;
        }
        for (const auto& f : frames) {
            asm volatile("" ::: "memory");
            const GjkResult<double> r =
                method == 0   ? gjk_distance(setup.a, f.pa, setup.b, f.pb)
                : method == 1 ? gjk_distance(setup.a, f.pa, setup.b, f.pb, &cache)
                : method == 2 ? gjk_intersect(setup.a, f.pa, setup.b, f.pb)
                              : gjk_intersect(setup.a, f.pa, setup.b, f.pb, &cache);
            s += checksum(r);
        }
    }
    const double ns = (tcpu() - t0) / (double(reps) * double(frames.size()));
    sink = sink + s;
    *sig = s;
    return ns;
}
