// The C++ side of python/bench/bench_python.py: the same queries on the same inputs, timed in C++.
//   cdkit_python_bench_cpp <mesh> <poses.bin> <repeats>
// poses.bin: N pairs of row-major 4x4 float64 poses (pose_a then pose_b), written by the Python script.
// Prints JSON: the median µs per call of a distant-pair collide and distance (the per-call floor the Python call adds
// to), and µs per pose of a sequential loop and of collide_many on 1 and 2 TBB threads over the file's poses.
#include <cdkit/batch.hpp>
#include <cdkit/io/load_mesh.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <vector>

#if defined(CDKIT_HAS_TBB)
#include <tbb/task_arena.h>
#endif

using namespace cdkit;
using P = Transform<double>;
using Clock = std::chrono::steady_clock;

namespace {
template <class F> double median_us(int repeats, int calls, F&& f) {
    std::vector<double> t;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = Clock::now();
        for (int i = 0; i < calls; ++i) f();
        t.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / calls);
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}
volatile bool sink;
volatile double dsink;
}  // namespace

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: %s mesh poses.bin repeats\n", argv[0]);
        return 2;
    }
    const auto mesh = load_mesh(argv[1]);
    const MeshModel<Obb<double>> obb(mesh);
    const MeshModel<Rss<double>> rss(mesh);
    const int repeats = std::atoi(argv[3]);
    std::vector<double> buf;
    std::vector<P> pa, pb;
    {
        std::ifstream f(argv[2], std::ios::binary | std::ios::ate);
        const std::size_t bytes = std::size_t(f.tellg());
        f.seekg(0);
        buf.resize(bytes / sizeof(double));
        f.read(reinterpret_cast<char*>(buf.data()), std::streamsize(bytes));
    }
    for (std::size_t k = 0; k + 32 <= buf.size(); k += 32)
        for (int side = 0; side < 2; ++side) {
            P p;
            const double* m = buf.data() + k + 16 * side;
            for (int r = 0; r < 3; ++r) {
                for (int c = 0; c < 3; ++c) p.R(r, c) = m[4 * r + c];
                p.t[r] = m[4 * r + 3];
            }
            (side ? pb : pa).push_back(p);
        }
    const P far = P::translation(Vec3<double>(100, 0, 0));  // the bunny is ~10 across
    const double collide_us = median_us(repeats, 20000, [&] { sink = collide(obb, P{}, obb, far).colliding; });
    const double distance_us = median_us(repeats, 20000, [&] { dsink = distance(rss, P{}, rss, far).distance; });
    const double loop_us = median_us(repeats, 1, [&] {
        for (std::size_t i = 0; i < pa.size(); ++i) sink = collide(obb, pa[i], obb, pb[i]).colliding;
    }) / double(pa.size());
    auto batch_us = [&](int threads) {
        return median_us(repeats, 1, [&] {
#if defined(CDKIT_HAS_TBB)
            tbb::task_arena arena(threads);
            arena.execute([&] { sink = collide_many(obb, std::span<const P>(pa), obb, std::span<const P>(pb)).size() > 0; });
#else
            (void)threads;
            sink = collide_many(obb, std::span<const P>(pa), obb, std::span<const P>(pb)).size() > 0;
#endif
        }) / double(pa.size());
    };
    const double b1 = batch_us(1), b2 = batch_us(2);
    std::size_t hits = 0;
    for (const auto& r : collide_many(obb, std::span<const P>(pa), obb, std::span<const P>(pb))) hits += r.colliding;
    std::printf("{\"collide_distant_us\": %.6g, \"distance_distant_us\": %.6g, \"loop_us\": %.6g, \"batch1_us\": %.6g, "
                "\"batch2_us\": %.6g, \"poses\": %zu, \"hits\": %zu}\n",
                collide_us, distance_us, loop_us, b1, b2, pa.size(), hits);
    return 0;
}
