#include "peer_fcl.hpp"

#include "../thread_cpu_clock.hpp"

#include <fcl/math/bv/utility.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kDOP.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <stdexcept>

namespace cdbuild {

namespace {
using Clock = cdbench::ThreadCpuClock;  // FCL builds on one thread
double ms_since(Clock::time_point t0) { return cdbench::ms_since<Clock>(t0); }

std::vector<fcl::Vector3d> points(const cdkit::TriangleMesh<double>& m) {
    std::vector<fcl::Vector3d> p;
    p.reserve(m.vertices.size());
    for (const auto& v : m.vertices) p.emplace_back(v.x(), v.y(), v.z());
    return p;
}

template <class BV>
FclTimes run(const cdkit::TriangleMesh<double>& mesh, const cdkit::TriangleMesh<double>& moved, int reps) {
    const auto verts = points(mesh), moved_verts = points(moved);
    std::vector<fcl::Triangle> tris;
    tris.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) tris.emplace_back(t[0], t[1], t[2]);
    FclTimes out;
    std::vector<double> times;
    std::unique_ptr<fcl::BVHModel<BV>> last;
    for (int r = 0; r < reps; ++r) {
        auto m = std::make_unique<fcl::BVHModel<BV>>();
        const auto t0 = Clock::now();
        m->beginModel(int(tris.size()), int(verts.size()));
        m->addSubModel(verts, tris);
        m->endModel();
        times.push_back(ms_since(t0));
        last = std::move(m);
    }
    fcl::BVHModel<BV>& model = *last;
    std::nth_element(times.begin(), times.begin() + reps / 2, times.end());
    out.build_ms = times[reps / 2];
    out.bv_count = std::size_t(model.getNumBVs());
    out.bv_bytes = out.bv_count * sizeof(fcl::BVNode<BV>);
    const auto t0 = Clock::now();
    model.beginUpdateModel();
    model.updateSubModel(moved_verts);
    model.endUpdateModel(true, true);  // refit (not rebuild), bottom-up
    out.refit_ms = ms_since(t0);
    return out;
}
}  // namespace

const std::vector<std::string>& fcl_bv_kinds() {
    static const std::vector<std::string> kinds{"OBBRSS", "RSS", "OBB", "AABB", "KDOP24"};
    return kinds;
}

FclTimes fcl_build_and_refit(const std::string& kind, const cdkit::TriangleMesh<double>& mesh,
                             const cdkit::TriangleMesh<double>& moved, int reps) {
    if (kind == "OBBRSS") return run<fcl::OBBRSSd>(mesh, moved, reps);
    if (kind == "RSS") return run<fcl::RSSd>(mesh, moved, reps);
    if (kind == "OBB") return run<fcl::OBBd>(mesh, moved, reps);
    if (kind == "AABB") return run<fcl::AABBd>(mesh, moved, reps);
    if (kind == "KDOP24") return run<fcl::KDOPd<24>>(mesh, moved, reps);
    throw std::invalid_argument("unknown FCL BV kind " + kind);
}

}  // namespace cdbuild
