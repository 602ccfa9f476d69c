/// \file libFuzzer harness: bytes → two small meshes (≤ 16 triangles each) and a pose → collide() with all
/// contacts, checked against collide_brute_force() (same set of triangle pairs, same `colliding`), for
/// MeshModel<Obb<double>> and MeshModel<Aabb<float>>. A mesh with a NaN or infinite coordinate must be
/// rejected with cdkit::Error when the MeshModel is built, and a finite one must be accepted. Aborts on any
/// violation.

#include "fuzz_input.hpp"

#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/query.hpp"

#include <algorithm>
#include <optional>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>

namespace {

using Pairs = std::vector<std::pair<cdkit::Index, cdkit::Index>>;

[[noreturn]] void fail(const char* what) {
    std::fprintf(stderr, "fuzz_collide: %s\n", what);
    std::abort();
}

cdkit::TriangleMesh<double> read_mesh(cdkit::fuzz::Reader& in) {
    cdkit::TriangleMesh<double> m;
    const int nv = 3 + in.byte() % 14;  // 3 … 16 vertices
    const int nt = 1 + in.byte() % 16;  // 1 … 16 triangles
    for (int i = 0; i < nv; ++i) m.vertices.emplace_back(in.coordinate(), in.coordinate(), in.coordinate());
    for (int i = 0; i < nt; ++i)
        m.triangles.push_back({cdkit::Index(in.byte() % nv), cdkit::Index(in.byte() % nv), cdkit::Index(in.byte() % nv)});
    return m;
}

template <class S> Pairs pairs(const cdkit::CollisionResult<S>& r) {
    Pairs p;
    for (const auto& c : r.contacts) p.emplace_back(c.triangle_a, c.triangle_b);
    std::sort(p.begin(), p.end());
    return p;
}

template <class BV>
void check(const cdkit::TriangleMesh<typename BV::Scalar>& a, const cdkit::TriangleMesh<typename BV::Scalar>& b,
           const cdkit::Transform<typename BV::Scalar>& pose_b) {
    using S = typename BV::Scalar;
    const bool finite = [&] {
        for (const auto* m : {&a, &b})
            for (const auto& v : m->vertices)
                if (!v.allFinite()) return false;
        return true;
    }();
    std::optional<cdkit::MeshModel<BV>> ma, mb;
    try {
        ma.emplace(a);
        mb.emplace(b);
    } catch (const cdkit::Error&) {
        if (finite) fail("a finite mesh was rejected");
        return;
    }
    if (!finite) fail("a mesh with NaN/Inf was accepted");
    ma->validate();
    mb->validate();
    cdkit::CollisionRequest all;
    all.mode = cdkit::ContactMode::all;
    const cdkit::Transform<S> pose_a;
    const auto fast = cdkit::collide(*ma, pose_a, *mb, pose_b, all);
    const auto slow = cdkit::collide_brute_force(a, pose_a, b, pose_b, all);
    if (fast.colliding != slow.colliding) fail("collide().colliding differs from brute force");
    if (pairs(fast) != pairs(slow)) fail("collide() contact pairs differ from brute force");
    const auto first = cdkit::collide(*ma, pose_a, *mb, pose_b);
    if (first.colliding != slow.colliding) fail("ContactMode::first differs from brute force");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    cdkit::fuzz::Reader in(data, size);
    const auto a = read_mesh(in);
    const auto b = read_mesh(in);
    // Pose of B (A at identity): a normalised quaternion (identity when all zero) and a finite translation.
    Eigen::Quaterniond q(double(int(in.byte()) - 128), double(int(in.byte()) - 128), double(int(in.byte()) - 128),
                         double(int(in.byte()) - 128));
    if (q.squaredNorm() == 0) q = Eigen::Quaterniond::Identity();
    q.normalize();
    cdkit::Vec3<double> t(in.coordinate(), in.coordinate(), in.coordinate());
    if (!t.allFinite()) t.setZero();
    const cdkit::Transform<double> pose(q.toRotationMatrix(), t);
    check<cdkit::Obb<double>>(a, b, pose);
    check<cdkit::Aabb<float>>(a.cast<float>(), b.cast<float>(), pose.cast<float>());
    return 0;
}
