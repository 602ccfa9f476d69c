#pragma once
// Per-call time of a query in thread CPU time (the VM is shared; a descheduled thread is not charged), for
// bench_convex.cpp and peer_fcl.cpp alike. Reading CLOCK_THREAD_CPUTIME_ID is a system call (~0.5 µs here),
// so one configuration is timed as a batch long enough (≥ 20 µs, at least `min_reps` calls) that the reading
// is a small share, and the clock's own cost, measured once, is subtracted.
#include "../thread_cpu_clock.hpp"

#include <algorithm>
#include <chrono>
#include <vector>

namespace cdkit::bench {

/// Median cost of one pair of thread-CPU clock readings, in ns.
inline double thread_clock_overhead_ns() {
    static const double overhead = [] {
        std::vector<double> d;
        for (int i = 0; i < 201; ++i) {
            const auto t0 = cdbench::ThreadCpuClock::now();
            const auto t1 = cdbench::ThreadCpuClock::now();
            d.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
        }
        std::nth_element(d.begin(), d.begin() + 100, d.end());
        return d[100];
    }();
    return overhead;
}

/// Mean thread-CPU ns per call of `f` over a batch after one untimed call (without it the method timed first
/// for a configuration paid that configuration's cache misses). The batch size is chosen from a 16-call
/// steady-clock estimate so that the batch takes ≥ 20 µs. The empty asm with a memory clobber before each
/// call keeps the compiler from hoisting an inlined, side-effect-free query out of the loop.
template <class F> double time_ns(F&& f, int min_reps = 16) {
    f();
    using Steady = std::chrono::steady_clock;
    const auto e0 = Steady::now();
    for (int r = 0; r < 16; ++r) {
        asm volatile("" ::: "memory");
        f();
    }
    const double est = std::chrono::duration<double, std::nano>(Steady::now() - e0).count() / 16;
    const int reps = std::clamp(int(20000.0 / std::max(est, 1.0)), min_reps, 4096);
    const auto t0 = cdbench::ThreadCpuClock::now();
    for (int r = 0; r < reps; ++r) {
        asm volatile("" ::: "memory");
        f();
    }
    const auto t1 = cdbench::ThreadCpuClock::now();
    const double total = std::chrono::duration<double, std::nano>(t1 - t0).count() - thread_clock_overhead_ns();
    return std::max(total, 0.0) / reps;
}

}  // namespace cdkit::bench
