#pragma once
// Two convex shapes posed at a chosen gap near contact by long-double GJK, for the tests of the cold boolean's
// certificates (containment, candidate axes, certified separation).
#include <cdkit/narrowphase/gjk.hpp>

#include "mesh_factory.hpp"

#include <cmath>
#include <random>

namespace cdkit::test {

/// A uniformly random unit vector (a normalised Gaussian triple).
inline Vec3<double> random_unit(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    return Vec3<double>(g(rng), g(rng), g(rng)).normalized();
}

/// Poses pa, pb placing B at gap·size from A (gap < 0: overlapping by that much along the normal): random
/// rotations, A up to 100 sizes from the origin (10^k · size, k ∈ {−1, 0, 1, 2}), B moved along long-double GJK's
/// closest-point normal, first to 1e-3 of the size and then to the gap (twice for a gap > 0, refining on the
/// distance; once otherwise, as overlapping pairs have no distance to refine on). `a_l`, `b_l`: the shapes in long
/// double. False when long double gives no normal on the way: the case is to be skipped.
template <class AL, class BL>
bool place_near_contact(const AL& a_l, const BL& b_l, double size, double gap, std::mt19937_64& rng,
                        Transform<double>& pa, Transform<double>& pb) {
    using L = long double;
    GjkSettings<L> exact;
    exact.rel_tolerance = L(1e-16);
    const double offset_scale = size * std::pow(10.0, std::uniform_int_distribution<int>(-1, 2)(rng));
    const Vec3<double> offset = random_unit(rng) * offset_scale;
    pa = Transform<double>(random_rotation(rng), offset);
    const Mat3<double> rb = random_rotation(rng);
    pb = Transform<double>(rb, offset + random_unit(rng) * (1.5 * size));
    const Transform<L> pa_l(pa.R.template cast<L>(), pa.t.template cast<L>());
    for (const double target : {1e-3 * size, gap * size, gap * size}) {
        const Transform<L> pb_l(pb.R.template cast<L>(), pb.t.template cast<L>());
        const auto d = gjk_distance(a_l, pa_l, b_l, pb_l, nullptr, exact);
        if (d.status != GjkStatus::separated) return false;  // needs a normal
        pb.t = (pb_l.t + (L(target) - d.distance) * d.normal).template cast<double>();
        if (target == gap * size && gap <= 0) break;
    }
    return true;
}

}  // namespace cdkit::test
