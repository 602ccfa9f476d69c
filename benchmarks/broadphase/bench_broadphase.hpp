#pragma once
// P4 broad-phase benchmark: the interface every measured method implements, so FCL stays in one TU.
#include "cdkit/broadphase/box.hpp"

#include <memory>
#include <string>
#include <vector>

namespace cdbench_bp {

using V3 = cdkit::Vec3<double>;

/// One broad-phase method under test. init() is untimed; step() is one frame: move every object to its new
/// centre (sizes are fixed), then find all overlapping pairs into `out` (cleared by the caller).
struct Method {
    virtual ~Method() = default;
    virtual std::string name() const = 0;
    virtual bool is_fcl() const { return false; }
    virtual void init(const std::vector<V3>& centers, const std::vector<V3>& halves) = 0;
    virtual void step(const std::vector<V3>& centers, std::vector<cdkit::ObjectPair>& out) = 0;
};

/// Scene bounds and the cell size given to FCL's spatial hash (the same rule as cdkit's automatic grid).
struct FclOptions {
    V3 scene_min, scene_max;
    double cell_size = 1.0;
    bool naive = true;  ///< include NaiveCollisionManager (O(n^2))
};

/// FCL 0.7 broad-phase managers (peers_fcl.cpp).
std::vector<std::unique_ptr<Method>> make_fcl_methods(const FclOptions& opt);

}  // namespace cdbench_bp
