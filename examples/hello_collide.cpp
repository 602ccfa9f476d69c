// The README's usage example: load a mesh, build a tree, ask whether two posed copies collide.
// Usage: hello_collide [mesh file]   (default: data/bunny.obj)
#include <cdkit/cdkit.hpp>

#include <cstdio>

int main(int argc, char** argv) try {
    const char* path = argc > 1 ? argv[1] : CDKIT_DEFAULT_MESH;
    // --8<-- [readme]
    cdkit::MeshModel<cdkit::Obb<double>> bunny(cdkit::load_mesh(path));   // validate + build the BVH once

    cdkit::Transform<double> pose_a;                                      // identity
    cdkit::Transform<double> pose_b(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                                    Eigen::Vector3d(0.05, 0.0, 0.0));    // rotated and moved 5 cm

    cdkit::CollisionResult<double> hit = cdkit::collide(bunny, pose_a, bunny, pose_b);
    if (hit.colliding)
        std::printf("collide: triangles %u and %u touch at (%.4f %.4f %.4f)\n", hit.contacts[0].triangle_a,
                    hit.contacts[0].triangle_b, hit.contacts[0].point.x(), hit.contacts[0].point.y(),
                    hit.contacts[0].point.z());
    // --8<-- [readme]

    cdkit::CollisionRequest all{cdkit::ContactMode::all};
    const auto every = cdkit::collide(bunny, pose_a, bunny, pose_b, all);
    std::printf("all contacts: %zu triangle pairs; %llu BV tests, %llu triangle tests\n", every.contacts.size(),
                static_cast<unsigned long long>(every.stats.bv_tests),
                static_cast<unsigned long long>(every.stats.primitive_tests));
    return hit.colliding ? 0 : 1;  // two overlapping copies must collide
} catch (const cdkit::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
}
