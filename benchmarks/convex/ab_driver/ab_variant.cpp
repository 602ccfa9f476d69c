// One side of the in-process A/B of the cold boolean GJK (run.sh): compiled twice, with -Dcdkit=cdkit_old and the
// headers of a git revision, and with -Dcdkit=cdkit_new and the working tree's, into one binary, so that both are
// timed in one process, alternating, under the same load. P3-like pairs (box, hull100, cylinder, cone; 200 per
// distance class, seeded, the same on both sides) placed by double GJK at the P3 target distances (× 0.1).
// Each configuration is called 16 times in a row (as the P3 batches do), thread CPU time over the whole cell.
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/convex_shapes.hpp>
#include <cdkit/narrowphase/gjk.hpp>
#include <random>
#include <vector>
#include <time.h>
#define CAT2(a, b) a##b
#define CAT(a, b) CAT2(a, b)
using namespace cdkit;
namespace {
Mat3<double> rrot(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    q.normalize();
    return q.toRotationMatrix();
}
double tcpu() { timespec t; clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t); return t.tv_sec * 1e9 + t.tv_nsec; }
volatile double sink;
template <class Sh> struct Set {
    std::vector<Sh> A, B; std::vector<Transform<double>> PA, PB;
};
template <class Sh, class Make> Set<Sh> make_set(Make make, int cls, int n) {
    std::mt19937_64 rng(7 + cls);
    const double targets[3][4] = {{5, 2.5, 1, 0.5}, {1e-1, 1e-2, 1e-3, 1e-4}, {-1e-1, -1e-2, -1e-3, -1e-4}};
    Set<Sh> s;
    for (int k = 0; k < n; ++k) {
        Sh a = make(rng), b = make(rng);
        Transform<double> pa(rrot(rng), Vec3<double>::Zero());
        std::normal_distribution<double> g;
        Transform<double> pb(rrot(rng), Vec3<double>(g(rng), g(rng), g(rng)).normalized() * 0.4);
        auto d0 = gjk_distance(a, pa, b, pb);
        pb.t += (targets[cls][k % 4] * 0.1 - d0.distance) * d0.normal;
        s.A.push_back(a); s.B.push_back(b); s.PA.push_back(pa); s.PB.push_back(pb);
    }
    return s;
}
template <class Sh> double time_set(const Set<Sh>& s, int reps, double* it, long* hits, double* sig) {
    double t0 = tcpu();
    for (int rr = 0; rr < reps; ++rr)
        for (std::size_t k = 0; k < s.A.size(); ++k)
            for (int q = 0; q < 16; ++q) {
                asm volatile("" ::: "memory");
                const auto r = gjk_intersect(s.A[k], s.PA[k], s.B[k], s.PB[k]);
                sink = sink + r.distance;
            }
    double t1 = tcpu();
    *it = 0; *hits = 0; *sig = 0;
    for (std::size_t k = 0; k < s.A.size(); ++k) {
        auto r = gjk_intersect(s.A[k], s.PA[k], s.B[k], s.PB[k]);
        *it += r.iterations; *hits += r.colliding;
        *sig += r.distance + r.normal.sum() + r.point_a.sum() + 3 * r.point_b.sum() + int(r.status) * 7;
    }
    return (t1 - t0) / (double(reps) * s.A.size() * 16);
}
}  // namespace
/// ns per query over `reps` passes of the cell; fam 0 box, 1 hull100, 2 cylinder, 3 cone; cls 0 distant, 1 close,
/// 2 overlapping. `it`, `hits`, `sig`: mean iterations, colliding answers and a checksum of every result field.
double CAT(run_, VARIANT)(int fam, int cls, int reps, double* it, long* hits, double* sig) {
    std::uniform_real_distribution<double> u(0.5, 1.0);
    static std::vector<Set<Box<double>>> boxes;
    static std::vector<Set<ConvexPolyhedron<double>>> hulls;
    static std::vector<Set<Cylinder<double>>> cyls;
    static std::vector<Set<Cone<double>>> cones;
    if (boxes.empty()) {
        for (int c = 0; c < 3; ++c) {
            boxes.push_back(make_set<Box<double>>([&](std::mt19937_64& r) { return Box<double>(Vec3<double>(0.1 * u(r), 0.1 * u(r), 0.1 * u(r))); }, c, 200));
            hulls.push_back(make_set<ConvexPolyhedron<double>>([&](std::mt19937_64& r) {
                std::normal_distribution<double> g; std::vector<Vec3<double>> p;
                for (int i = 0; i < 100; ++i) p.push_back(Vec3<double>(g(r), g(r), g(r)).normalized() * 0.1 * u(r));
                return ConvexPolyhedron<double>(p); }, c, 200));
            cyls.push_back(make_set<Cylinder<double>>([&](std::mt19937_64& r) { return Cylinder<double>(0.1 * u(r), 0.1 * u(r)); }, c, 200));
            cones.push_back(make_set<Cone<double>>([&](std::mt19937_64& r) { return Cone<double>(0.1 * u(r), 0.1 * u(r)); }, c, 200));
        }
    }
    if (fam == 0) return time_set(boxes[cls], reps, it, hits, sig);
    if (fam == 1) return time_set(hulls[cls], reps, it, hits, sig);
    if (fam == 2) return time_set(cyls[cls], reps, it, hits, sig);
    return time_set(cones[cls], reps, it, hits, sig);
}
