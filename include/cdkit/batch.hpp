#pragma once
/// \file Batches: one pair of mesh models at N pose pairs, N answers out — the planning-style loop (a robot
/// model against an obstacle at every configuration of a path, a sampler's candidate poses) as one call.
///
/// `collide_many` and `distance_many` run `collide()` / `distance()` for pose pair i = (poses_a[i], poses_b[i])
/// and return the N results in order, each exactly what the single call returns for that pair (same code, same
/// rounding). With TBB (CDKIT_HAS_TBB) the pairs run in parallel over the calling thread's task arena (all cores
/// unless the caller limits it with a `tbb::task_arena` or `tbb::global_control`); without it, in a loop. The
/// queries are const on the models, so one model pair serves every worker; distance()'s open-pair heap is
/// thread_local and reused. The Python module's `collide_many` / `distance_many` call these with the GIL released.

#include "cdkit/core/error.hpp"
#include "cdkit/distance.hpp"
#include "cdkit/query.hpp"

#include <span>
#include <string>
#include <vector>

#if defined(CDKIT_HAS_TBB)
#include <tbb/parallel_for.h>
#endif

namespace cdkit {

/// How a batch runs.
struct BatchRequest {
    /// Run the pairs in parallel with TBB where the library was built with it (false: in order, this thread).
    bool parallel = true;
    /// Pairs per TBB task at least: queries of a few microseconds need some work per task to amortise the
    /// scheduling (0 is taken as 1).
    std::size_t grain = 16;
};

namespace detail {
/// poses_a and poses_b must pair up one to one; a mismatch is a caller's error, named in the message.
inline void check_batch_sizes(std::size_t na, std::size_t nb, const char* what) {
    if (na != nb)
        throw Error("<batch>", what,
                    "poses_a has " + std::to_string(na) + " poses but poses_b has " + std::to_string(nb));
}

/// f(i) for i in [0, n): in parallel with TBB when asked and available.
template <class F> void for_each_index(std::size_t n, const BatchRequest& batch, F&& f) {
#if defined(CDKIT_HAS_TBB)
    if (batch.parallel && n > 1) {
        const std::size_t grain = batch.grain > 0 ? batch.grain : 1;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
        });
        return;
    }
#endif
    (void)batch;
    for (std::size_t i = 0; i < n; ++i) f(i);
}
}  // namespace detail

/// collide(a, poses_a[i], b, poses_b[i], request) for every i, in order. Throws cdkit::Error when the two pose
/// lists differ in length (nothing is computed); a pose that is not a rigid motion gives that entry's
/// `invalid_pose` status, as in the single call. Thread-safe (const on the models).
template <class BV, class M>
[[nodiscard]] std::vector<CollisionResult<M>> collide_many(const MeshModel<BV, M>& a,
                                                           std::span<const Transform<M>> poses_a,
                                                           const MeshModel<BV, M>& b,
                                                           std::span<const Transform<M>> poses_b,
                                                           const CollisionRequest& request = {},
                                                           const BatchRequest& batch = {}) {
    detail::check_batch_sizes(poses_a.size(), poses_b.size(), "collide_many");
    std::vector<CollisionResult<M>> out(poses_a.size());
    detail::for_each_index(out.size(), batch,
                           [&](std::size_t i) { out[i] = collide(a, poses_a[i], b, poses_b[i], request); });
    return out;
}

/// distance(a, poses_a[i], b, poses_b[i], request) for every i, in order; as collide_many otherwise.
template <class BV, class M>
[[nodiscard]] std::vector<DistanceResult<M>> distance_many(const MeshModel<BV, M>& a,
                                                           std::span<const Transform<M>> poses_a,
                                                           const MeshModel<BV, M>& b,
                                                           std::span<const Transform<M>> poses_b,
                                                           const DistanceRequest<M>& request = {},
                                                           const BatchRequest& batch = {}) {
    detail::check_batch_sizes(poses_a.size(), poses_b.size(), "distance_many");
    std::vector<DistanceResult<M>> out(poses_a.size());
    detail::for_each_index(out.size(), batch,
                           [&](std::size_t i) { out[i] = distance(a, poses_a[i], b, poses_b[i], request); });
    return out;
}

}  // namespace cdkit
