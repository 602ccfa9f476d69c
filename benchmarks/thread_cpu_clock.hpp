#pragma once
/// \file ThreadCpuClock: a std::chrono clock of the calling thread's CPU time. The benchmark machine may be
/// shared, and wall time would count the time a single-threaded measurement spends descheduled; every cdkit
/// method and its peer are timed with the same clock in the same run.

#include <chrono>
#include <cstdint>
#include <ctime>

namespace cdbench {

struct ThreadCpuClock {
    using duration = std::chrono::nanoseconds;
    using rep = duration::rep;
    using period = duration::period;
    using time_point = std::chrono::time_point<ThreadCpuClock>;
    static constexpr bool is_steady = true;
    static time_point now() noexcept {
        timespec ts;
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return time_point(duration(std::int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec));
    }
};

/// The calling thread's CPU time in seconds, for code that wants a plain number.
[[nodiscard]] inline double thread_cpu_seconds() noexcept {
    return std::chrono::duration<double>(ThreadCpuClock::now().time_since_epoch()).count();
}

/// Milliseconds of `Clock` since t0.
template <class Clock> [[nodiscard]] double ms_since(typename Clock::time_point t0) noexcept {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace cdbench
