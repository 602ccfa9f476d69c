#pragma once
// cdkit's rigid transform as FCL's, for the benchmarks that run FCL in the same process on the same poses.
#include <cdkit/core/math.hpp>

#include <fcl/common/types.h>

namespace cdbench {

inline fcl::Transform3d to_fcl(const cdkit::Transform<double>& t) {
    fcl::Transform3d x = fcl::Transform3d::Identity();
    x.linear() = t.R;
    x.translation() = t.t;
    return x;
}

}  // namespace cdbench
