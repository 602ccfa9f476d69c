#pragma once
// FCL's BVHModel of a cdkit mesh, for the FCL comparison tests (FCL headers: keep to few TUs).
#include "cdkit/core/math.hpp"
#include "cdkit/core/mesh.hpp"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/bvh/detail/BV_splitter.h>

#include <memory>
#include <vector>

namespace cdkit::test {

/// A cdkit pose as FCL's.
inline fcl::Transform3d fcl_pose(const Transform<double>& p) {
    fcl::Transform3d x = fcl::Transform3d::Identity();
    x.linear() = p.R;
    x.translation() = p.t;
    return x;
}

/// `split`: FCL's rule for dividing a node (its default, the mean, unless asked otherwise).
template <class BV>
std::shared_ptr<fcl::BVHModel<BV>> fcl_mesh(const TriangleMesh<double>& m,
                                            fcl::detail::SplitMethodType split = fcl::detail::SPLIT_METHOD_MEAN) {
    auto model = std::make_shared<fcl::BVHModel<BV>>();
    model->bv_splitter = std::make_shared<fcl::detail::BVSplitter<BV>>(split);
    std::vector<fcl::Vector3d> pts(m.vertices.begin(), m.vertices.end());
    std::vector<fcl::Triangle> tris;
    for (const auto& t : m.triangles) tris.emplace_back(t[0], t[1], t[2]);
    model->beginModel();
    model->addSubModel(pts, tris);
    model->endModel();
    return model;
}

}  // namespace cdkit::test
