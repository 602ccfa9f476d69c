#pragma once
// Shared helpers of the inner sphere tree tests: small packed meshes and brute-force references.
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/ist/inner_sphere_tree.hpp"
#include "cdkit/ist/ist_query.hpp"
#include "mesh_factory.hpp"
#include "test_common.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace cdkit::test {

inline TriangleMesh<double> unit_bunny() { return unit_scaled(load_mesh(data_path("bunny.obj"))); }

/// A small IST of the unit-scaled bunny (built once per test binary; const afterwards).
inline const InnerSphereTree& small_bunny_tree() {
    static const InnerSphereTree tree = [] {
        PackingOptions p;
        p.max_spheres = 400;
        p.grid_resolution = 40;
        return build_inner_sphere_tree(unit_bunny(), p);
    }();
    return tree;
}

/// Σ lens volumes over all sphere pairs, and the overlapping pairs, by brute force.
struct BruteVolume {
    double volume = 0;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
};
inline BruteVolume brute_volume(const InnerSphereTree& a, const Transform<double>& pa, const InnerSphereTree& b,
                                const Transform<double>& pb) {
    BruteVolume out;
    std::vector<Vec3<double>> cb;
    for (const auto& s : b.spheres()) cb.push_back(pb * s.center);
    for (std::uint32_t i = 0; i < a.spheres().size(); ++i) {
        const Vec3<double> ca = pa * a.spheres()[i].center;
        for (std::uint32_t j = 0; j < b.spheres().size(); ++j) {
            const double v = sphere_intersection_volume(a.spheres()[i].radius, b.spheres()[j].radius, (ca - cb[j]).norm());
            if (v > 0) out.volume += v, out.pairs.emplace_back(i, j);
        }
    }
    return out;
}

/// min over all sphere pairs of |ca − cb| − ra − rb (may be negative).
inline double brute_distance(const InnerSphereTree& a, const Transform<double>& pa, const InnerSphereTree& b,
                             const Transform<double>& pb) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& x : a.spheres())
        for (const auto& y : b.spheres())
            best = std::min(best, (pa * x.center - pb * y.center).norm() - x.radius - y.radius);
    return best;
}

}  // namespace cdkit::test
