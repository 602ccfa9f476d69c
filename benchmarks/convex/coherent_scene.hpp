#pragma once
// The coherent-motion scenes of issue 5, shared by cdkit_bench_coherent and the in-process A/B of the queries on
// them (ab_driver/run.sh … coherent): two hulls of points on ellipsoids (20 and 200 vertices, size ~1); A spins
// in place, B spins and orbits A, and the gap along the closest-point normal follows a per-scene schedule, set
// each frame with a long-double reference.
#include <cdkit/narrowphase/convex_polyhedron.hpp>
#include <cdkit/narrowphase/gjk.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace cdbench {

using LD = long double;
inline constexpr double pi = 3.14159265358979323846;
inline constexpr std::uint64_t coherent_seed = 20261122;

/// Points on an ellipsoid surface: every one is a hull vertex.
inline std::vector<cdkit::Vec3<double>> ellipsoid_points(std::mt19937_64& rng, int n, const cdkit::Vec3<double>& radii) {
    std::normal_distribution<double> g;
    std::vector<cdkit::Vec3<double>> p;
    for (int i = 0; i < n; ++i) p.push_back(cdkit::Vec3<double>(g(rng), g(rng), g(rng)).normalized().cwiseProduct(radii));
    return p;
}
inline std::vector<cdkit::Vec3<LD>> to_ld(const std::vector<cdkit::Vec3<double>>& p) {
    std::vector<cdkit::Vec3<LD>> o;
    for (const auto& x : p) o.push_back(x.cast<LD>());
    return o;
}

/// The two shapes' points, drawn first from the scenes' generator.
struct CoherentPoints {
    std::vector<cdkit::Vec3<double>> a, b;
};
inline CoherentPoints coherent_points(std::mt19937_64& rng) {
    CoherentPoints p;
    p.a = ellipsoid_points(rng, 20, {1.0, 0.7, 0.5});
    p.b = ellipsoid_points(rng, 200, {0.9, 0.8, 0.6});
    return p;
}

struct CoherentFrame {
    cdkit::Transform<double> pa, pb;
    bool ref_hit = false;
    double ref_distance = 0;  // long-double reference, rounded
};

struct CoherentScene {
    std::string name;
    std::vector<CoherentFrame> frames;
};

/// One scene: A spins in place, B spins and orbits A; the gap along the closest-point normal follows `gap(frame)`
/// (set with the long-double reference).
template <class Gap>
CoherentScene make_coherent_scene(const char* name, int frames, const cdkit::ConvexPolyhedron<LD>& al,
                                  const cdkit::ConvexPolyhedron<LD>& bl, Gap gap, std::mt19937_64& rng) {
    using namespace cdkit;
    CoherentScene s{name, {}};
    std::normal_distribution<double> g;
    auto axis = [&] { return Vec3<double>(g(rng), g(rng), g(rng)).normalized(); };
    const Mat3<double> spin_a = Eigen::AngleAxisd(0.5 * pi / 180, axis()).toRotationMatrix();
    const Mat3<double> spin_b = Eigen::AngleAxisd(0.7 * pi / 180, axis()).toRotationMatrix();
    const Mat3<double> orbit = Eigen::AngleAxisd(0.3 * pi / 180, axis()).toRotationMatrix();
    Transform<double> pa(Mat3<double>::Identity(), Vec3<double>::Zero());
    Transform<double> pb(Mat3<double>::Identity(), Vec3<double>(3, 0, 0));
    Vec3<double> dir = axis().cross(Vec3<double>::UnitZ()).normalized();
    GjkSettings<LD> tight;
    tight.rel_tolerance = 1e-16L;
    for (int f = 0; f < frames; ++f) {
        // Re-orthonormalised each frame (through a unit quaternion): a product of thousands of rotations drifts
        // (2e-13 after 2000 frames), and GJK's frame of A takes R_aᵀ for R_a's inverse.
        pa.R = Eigen::Quaterniond(Mat3<double>(spin_a * pa.R)).normalized().toRotationMatrix();
        pb.R = Eigen::Quaterniond(Mat3<double>(spin_b * pb.R)).normalized().toRotationMatrix();
        dir = orbit * dir;
        pb.t = 3.0 * dir;
        const double target = gap(f);
        for (int k = 0; k < 4; ++k) {  // along the normal to the target gap (a few steps: the normal turns)
            auto d = gjk_distance(al, pa.cast<LD>(), bl, pb.cast<LD>(), nullptr, tight);
            if (d.status != GjkStatus::separated) break;
            pb.t += (target - double(d.distance)) * d.normal.cast<double>();
            if (target <= 0) break;
        }
        // The reference in the world frame, both shapes placed by their poses (as the near-contact refinement
        // measures; A's frame maps B by R_aᵀ, R_a's inverse only to its rounding: docs/convex.md, "Near contact").
        const Transformed<ConvexPolyhedron<LD>> ta{al, pa.cast<LD>()}, tb{bl, pb.cast<LD>()};
        auto ref = gjk_distance(ta, Transform<LD>(), tb, Transform<LD>(), nullptr, tight);
        s.frames.push_back({pa, pb, ref.colliding, double(ref.distance)});
    }
    return s;
}

/// The three scenes, drawn from `rng` after coherent_points: separated (gap 0.1–0.5), near-touching (1e-4–1e-2)
/// and in-and-out (−0.02…+0.03).
inline std::vector<CoherentScene> coherent_scenes(int frames, const cdkit::ConvexPolyhedron<LD>& al,
                                                  const cdkit::ConvexPolyhedron<LD>& bl, std::mt19937_64& rng) {
    std::vector<CoherentScene> scenes;
    scenes.push_back(make_coherent_scene("separated", frames, al, bl,
                                         [](int f) { return 0.3 + 0.2 * std::sin(2 * pi * f / 500.0); }, rng));
    scenes.push_back(make_coherent_scene("near-touching", frames, al, bl,
                                         [](int f) { return std::pow(10.0, -3.0 + std::sin(2 * pi * f / 400.0)); },
                                         rng));
    scenes.push_back(make_coherent_scene("in-and-out", frames, al, bl,
                                         [](int f) { return 0.005 + 0.025 * std::sin(2 * pi * f / 300.0); }, rng));
    return scenes;
}

}  // namespace cdbench
