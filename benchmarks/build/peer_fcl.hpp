#pragma once
/// \file FCL's BVHModel build and refit behind plain declarations (FCL's headers are slow to compile: only
/// peer_fcl.cpp includes them).

#include "cdkit/core/mesh.hpp"

#include <string>
#include <vector>

namespace cdbuild {

/// The FCL BV types measured: "OBBRSS", "RSS", "OBB", "AABB", "KDOP24".
[[nodiscard]] const std::vector<std::string>& fcl_bv_kinds();

struct FclTimes {
    double build_ms = 0;  ///< beginModel / addSubModel / endModel (FCL's default split: mean)
    double refit_ms = 0;  ///< beginUpdateModel / updateSubModel(moved) / endUpdateModel (bottom-up refit)
    std::size_t bv_count = 0;
    std::size_t bv_bytes = 0;  ///< sizeof(BVNode<BV>) × count (FCL keeps more per model; a lower bound)
};

/// Builds `mesh` as an FCL BVHModel of the given kind `reps` times (median), then refits it to `moved`.
[[nodiscard]] FclTimes fcl_build_and_refit(const std::string& kind, const cdkit::TriangleMesh<double>& mesh,
                                           const cdkit::TriangleMesh<double>& moved, int reps);

}  // namespace cdbuild
