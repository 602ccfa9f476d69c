/// \file FCL 0.7 peers: BVHModel<BV> queried with fcl::collide, exactly as an FCL user calls it.
///
/// The timed path is the public fcl::collide(geometry, tf, geometry, tf, request, result). fcl::collide
/// offers no work counters, so the untimed probe re-runs the same traversal that fcl::collide dispatches to
/// (collision_func_matrix-inl.h: orientedMeshCollide for OBB/OBBRSS, BVHCollideImpl for the rest) with the
/// traversal node's `enable_statistics` switched on. The harness checks that probe and timed answers agree.

#include "peers_fcl.hpp"

#include <fcl/config.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>

#include <limits>
#include <utility>

namespace cdbench {
namespace {

/// Which traversal node fcl::collide uses for a BV type, and the method's name.
template <class BV> struct FclBv;
template <> struct FclBv<fcl::OBBRSS<double>> {
    static constexpr const char* name = "fcl_obbrss";
    using Node = fcl::detail::MeshCollisionTraversalNodeOBBRSS<double>;
    static constexpr bool oriented = true;
};
template <> struct FclBv<fcl::OBB<double>> {
    static constexpr const char* name = "fcl_obb";
    using Node = fcl::detail::MeshCollisionTraversalNodeOBB<double>;
    static constexpr bool oriented = true;
};
template <> struct FclBv<fcl::AABB<double>> {
    // fcl::collide copies both models and refits them in world coordinates on every query (BVHCollideImpl):
    // that cost is part of what an FCL user pays, so it is timed.
    static constexpr const char* name = "fcl_aabb";
    using Node = fcl::detail::MeshCollisionTraversalNode<fcl::AABB<double>>;
    static constexpr bool oriented = false;
};

template <> struct FclBv<fcl::RSS<double>> {
    // FCL 0.7 has no oriented RSS-RSS collision node: fcl::collide takes the same copy-and-refit path as for
    // AABB (only its distance() uses RSS oriented), so this is timed as an FCL user meets it.
    static constexpr const char* name = "fcl_rss";
    using Node = fcl::detail::MeshCollisionTraversalNode<fcl::RSS<double>>;
    static constexpr bool oriented = false;
};

/// Every FCL BV type measured, in output order: adding one is one entry here plus its FclBv traits.
using FclBvs = std::tuple<fcl::OBBRSS<double>, fcl::OBB<double>, fcl::RSS<double>, fcl::AABB<double>>;

template <class BV> class FclMethod final : public Method {
public:
    using Model = fcl::BVHModel<BV>;

    explicit FclMethod(const cdkit::TriangleMesh<double>& mesh) : name_(FclBv<BV>::name) {
        std::vector<fcl::Vector3d> verts(mesh.vertices.begin(), mesh.vertices.end());
        std::vector<fcl::Triangle> tris;
        tris.reserve(mesh.triangles.size());
        for (const auto& t : mesh.triangles) tris.emplace_back(t[0], t[1], t[2]);
        const auto t0 = Clock::now();
        model_ = std::make_shared<Model>();
        model_->beginModel(int(tris.size()), int(verts.size()));
        model_->addSubModel(verts, tris);
        model_->endModel();
        info_.build_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        // BVHModel has no memory API: count its node array and primitive index array.
        info_.nodes = std::size_t(model_->getNumBVs());
        info_.tree_bytes = info_.nodes * sizeof(fcl::BVNode<BV>) + std::size_t(model_->num_tris) * sizeof(unsigned int);
        info_.tree_bytes_note = "estimate: getNumBVs() * sizeof(BVNode) + num_tris * sizeof(unsigned)";
        info_.mesh_bytes = verts.size() * sizeof(fcl::Vector3d) + tris.size() * sizeof(fcl::Triangle);
    }

    const std::string& name() const noexcept override { return name_; }
    const std::string& family() const noexcept override { return family_; }
    const BuildInfo& build_info() const noexcept override { return info_; }

    Outcome probe(const Pose& pose, Mode mode) override {
        const fcl::CollisionRequestd req = request(mode);
        fcl::CollisionResultd res;
        fcl::Transform3d tf1 = fcl::Transform3d::Identity();
        fcl::Transform3d tf2 = to_fcl(pose);
        typename FclBv<BV>::Node node;
        if constexpr (FclBv<BV>::oriented) {
            // Const arguments select the oriented node's initialize(), as fcl::collide's dispatch does.
            const Model& m = *model_;
            fcl::detail::initialize(node, m, std::as_const(tf1), m, std::as_const(tf2), req, res);
            node.enable_statistics = true;
            fcl::detail::collide(&node);
        } else {
            Model a(*model_), b(*model_);  // as BVHCollideImpl does: initialize() refits these in place
            fcl::detail::initialize(node, a, tf1, b, tf2, req, res);
            node.enable_statistics = true;
            fcl::detail::collide(&node);
        }
        return {res.isCollision(), res.numContacts(), std::uint64_t(node.num_bv_tests),
                std::uint64_t(node.num_leaf_tests)};
    }

    Timed time(const Pose& pose, Mode mode, std::size_t reps) override {
        const fcl::CollisionRequestd req = request(mode);
        const fcl::Transform3d tf1 = fcl::Transform3d::Identity();
        const fcl::Transform3d tf2 = to_fcl(pose);
        const fcl::CollisionGeometryd* g = model_.get();
        return time_batch(reps, [&] {
            fcl::CollisionResultd res;  // a fresh result per query, as cdkit returns a fresh one
            fcl::collide(g, tf1, g, tf2, req, res);
            return std::pair<bool, std::size_t>(res.isCollision(), res.numContacts());
        });
    }

private:
    static fcl::CollisionRequestd request(Mode mode) {
        // enable_contact stays false: one contact per intersecting triangle pair, as cdkit reports them.
        return fcl::CollisionRequestd(mode == Mode::first ? 1 : std::numeric_limits<std::size_t>::max(), false);
    }
    static fcl::Transform3d to_fcl(const Pose& p) {
        fcl::Transform3d tf = fcl::Transform3d::Identity();
        tf.linear() = p.R;
        tf.translation() = p.t;
        return tf;
    }

    std::string name_;
    std::string family_ = "fcl";
    BuildInfo info_;
    std::shared_ptr<Model> model_;
};

}  // namespace

std::vector<std::string> fcl_method_names() {
    return std::apply([](auto... bv) { return std::vector<std::string>{FclBv<decltype(bv)>::name...}; }, FclBvs{});
}

std::vector<std::unique_ptr<Method>> make_fcl_methods(const cdkit::TriangleMesh<double>& mesh,
                                                      const std::function<bool(const std::string&)>& wanted) {
    std::vector<std::unique_ptr<Method>> out;
    auto add = [&]<class BV>(BV*) {
        if (wanted(FclBv<BV>::name)) out.push_back(std::make_unique<FclMethod<BV>>(mesh));
    };
    std::apply([&](auto... bv) { (add(static_cast<decltype(bv)*>(nullptr)), ...); }, FclBvs{});
    return out;
}

std::string fcl_version() { return FCL_VERSION; }

}  // namespace cdbench
