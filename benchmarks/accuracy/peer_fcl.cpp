/// \file FCL 0.7 as a peer of the accuracy benchmark (the only TU that includes FCL).

#include "oracles.hpp"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/detail/traversal/collision/intersect.h>

#include <algorithm>
#include <memory>

namespace cdkit::accuracy {

bool fcl_triangles_intersect(const Tri3& p, const Tri3& q) {
    return fcl::detail::Intersect<double>::intersect_Triangle(p[0], p[1], p[2], q[0], q[1], q[2]);
}

namespace {
std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl_model(const TriangleMesh<double>& m) {
    auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    std::vector<fcl::Vector3d> verts(m.vertices.begin(), m.vertices.end());
    std::vector<fcl::Triangle> tris;
    tris.reserve(m.triangles.size());
    for (const auto& t : m.triangles) tris.emplace_back(t[0], t[1], t[2]);
    model->beginModel(int(tris.size()), int(verts.size()));
    model->addSubModel(verts, tris);
    model->endModel();
    return model;
}
}  // namespace

PairList fcl_intersecting_pairs(const TriangleMesh<double>& a, const TriangleMesh<double>& b, std::size_t max_contacts) {
    fcl::CollisionObjectd oa(fcl_model(a)), ob(fcl_model(b));
    fcl::CollisionRequestd req(max_contacts, false);
    fcl::CollisionResultd res;
    fcl::collide(&oa, &ob, req, res);
    PairList out;
    for (std::size_t i = 0; i < res.numContacts(); ++i) {
        const auto& c = res.getContact(i);
        out.emplace_back(Index(c.b1), Index(c.b2));
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace cdkit::accuracy
