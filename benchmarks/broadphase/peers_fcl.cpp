// FCL 0.7 broad-phase managers as P4 peers, used as an FCL user would: Boxd geometry in CollisionObjectd,
// per frame setTranslation + computeAABB, manager->update(), manager->collide(data, callback) with a callback
// that only records the pair (no narrow phase).
#include "bench_broadphase.hpp"

#include <fcl/broadphase/broadphase_SSaP.h>
#include <fcl/broadphase/broadphase_SaP.h>
#include <fcl/broadphase/broadphase_bruteforce.h>
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/broadphase/broadphase_interval_tree.h>
#include <fcl/broadphase/broadphase_spatialhash.h>
#include <fcl/geometry/shape/box.h>

#include <cstdint>
#include <functional>

namespace cdbench_bp {
namespace {

bool record_pair(fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
    auto* out = static_cast<std::vector<cdkit::ObjectPair>*>(data);
    const auto a = static_cast<cdkit::ObjectId>(reinterpret_cast<std::uintptr_t>(o1->getUserData()));
    const auto b = static_cast<cdkit::ObjectId>(reinterpret_cast<std::uintptr_t>(o2->getUserData()));
    out->push_back(cdkit::ObjectPair::make(a, b));
    return false;  // never stop early
}

class FclManager final : public Method {
public:
    FclManager(std::string name, std::function<std::unique_ptr<fcl::BroadPhaseCollisionManagerd>()> make)
        : name_(std::move(name)), make_(std::move(make)) {}
    std::string name() const override { return name_; }
    bool is_fcl() const override { return true; }
    void init(const std::vector<V3>& c, const std::vector<V3>& h) override {
        mgr_ = make_();
        objs_.clear();
        std::vector<fcl::CollisionObjectd*> ptrs;
        for (std::size_t i = 0; i < c.size(); ++i) {
            auto geom = std::make_shared<fcl::Boxd>(2 * h[i]);  // aabb_local = +-h exactly
            objs_.push_back(std::make_unique<fcl::CollisionObjectd>(geom));
            auto& o = *objs_.back();
            o.setTranslation(c[i]);
            o.computeAABB();
            o.setUserData(reinterpret_cast<void*>(static_cast<std::uintptr_t>(i)));
            ptrs.push_back(&o);
        }
        mgr_->registerObjects(ptrs);
        mgr_->setup();
    }
    void step(const std::vector<V3>& c, std::vector<cdkit::ObjectPair>& out) override {
        for (std::size_t i = 0; i < c.size(); ++i) {
            objs_[i]->setTranslation(c[i]);
            objs_[i]->computeAABB();
        }
        mgr_->update();
        mgr_->collide(&out, record_pair);
    }

private:
    std::string name_;
    std::function<std::unique_ptr<fcl::BroadPhaseCollisionManagerd>()> make_;
    std::unique_ptr<fcl::BroadPhaseCollisionManagerd> mgr_;
    std::vector<std::unique_ptr<fcl::CollisionObjectd>> objs_;
};

}  // namespace

std::vector<std::unique_ptr<Method>> make_fcl_methods(const FclOptions& opt) {
    std::vector<std::unique_ptr<Method>> v;
    v.push_back(std::make_unique<FclManager>("fcl_dynamic_aabb_tree", [] {
        return std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>();
    }));
    v.push_back(std::make_unique<FclManager>("fcl_sap", [] { return std::make_unique<fcl::SaPCollisionManagerd>(); }));
    v.push_back(std::make_unique<FclManager>("fcl_ssap", [] { return std::make_unique<fcl::SSaPCollisionManagerd>(); }));
    v.push_back(std::make_unique<FclManager>("fcl_interval_tree", [] {
        return std::make_unique<fcl::IntervalTreeCollisionManagerd>();
    }));
    v.push_back(std::make_unique<FclManager>("fcl_spatial_hash", [opt] {
        return std::make_unique<fcl::SpatialHashingCollisionManagerd<>>(opt.cell_size, opt.scene_min, opt.scene_max);
    }));
    if (opt.naive)
        v.push_back(std::make_unique<FclManager>("fcl_naive", [] { return std::make_unique<fcl::NaiveCollisionManagerd>(); }));
    return v;
}

}  // namespace cdbench_bp
