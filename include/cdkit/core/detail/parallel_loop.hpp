#pragma once
/// \file for_each_index(n, body, parallel): body(i) for every i in [0, n), in parallel blocks with TBB
/// (CDKIT_HAS_TBB) when `parallel` and n is large enough to pay for the threads, else in order. For loops whose iterations write only
/// their own element: the result is the same either way.
#include <cstddef>

#if defined(CDKIT_HAS_TBB)
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#endif

namespace cdkit::detail {

/// Below this many iterations the loop runs on the calling thread (a per-triangle precomputation of a
/// mesh this small takes well under a millisecond).
inline constexpr std::size_t kParallelLoopMin = std::size_t(1) << 15;

template <class Body> void for_each_index(std::size_t n, const Body& body, bool parallel = true) {
#if defined(CDKIT_HAS_TBB)
    if (parallel && n >= kParallelLoopMin) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
        });
        return;
    }
#else
    (void)parallel;
#endif
    for (std::size_t i = 0; i < n; ++i) body(i);
}

}  // namespace cdkit::detail
