// The inner-sphere-tree out-of-sample poses (issue 37), drawn once for the benchmark
// (benchmarks/ist/out_of_sample.cpp) and the test that bounds its figures (tests/ist/test_ist_accuracy.cpp), so both
// evaluate the very same poses: a random rotation of B and a random direction of approach, per pose, and the
// translation along that direction at which the two copies of the mesh first touch.
#pragma once

#include "cdkit/bv/obb.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/query.hpp"

#include <Eigen/Geometry>

#include <random>
#include <vector>

namespace cdkit::test {

struct ContactPose {
    Mat3<double> rotation;
    Vec3<double> direction;  // unit
    double contact = 0;      // translation along direction at first contact of the meshes
};

/// n poses of B = the mesh against A = the same mesh at the identity; the rotations and directions come from one
/// normal distribution over `rng` (the IST benchmark's P2 generator seeds it with 2024 and goes on drawing its
/// Monte Carlo samples from it), the first contact from 40 steps of bisection on collide() over [0, 2·diag].
inline std::vector<ContactPose> contact_poses(const TriangleMesh<double>& mesh, double diag, int n, std::mt19937_64& rng) {
    const MeshModel<Obb<double>> model(mesh);
    std::normal_distribution<double> g;
    std::vector<ContactPose> poses;
    poses.reserve(std::size_t(n));
    for (int i = 0; i < n; ++i) {
        Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
        q.normalize();
        Vec3<double> u(g(rng), g(rng), g(rng));
        u.normalize();
        ContactPose p{q.toRotationMatrix(), u, 0};
        double in = 0, out = 2 * diag;
        for (int it = 0; it < 40; ++it) {
            const double mid = (in + out) / 2;
            (collide(model, Transform<double>{}, model, Transform<double>(p.rotation, mid * u)).colliding ? in : out) = mid;
        }
        p.contact = out;
        poses.push_back(p);
    }
    return poses;
}

inline std::vector<ContactPose> contact_poses(const TriangleMesh<double>& mesh, double diag, int n) {
    std::mt19937_64 rng(2024);
    return contact_poses(mesh, diag, n, rng);
}

/// B's pose moved depth·diag past first contact (δ = −depth).
inline Transform<double> pose_past_contact(const ContactPose& p, double diag, double depth) {
    return Transform<double>(p.rotation, (p.contact - depth * diag) * p.direction);
}

}  // namespace cdkit::test
