// Uses the installed cdkit package: load a mesh, build an AABB tree in float, collide two copies; a GJK distance.
#include <cdkit/cdkit.hpp>

#include <cmath>
#include <cstdio>

int main(int argc, char** argv) {
    if (argc < 2) return 2;
    const cdkit::MeshModel<cdkit::Aabb<float>> m(cdkit::load_mesh(argv[1]).cast<float>());
    const auto r = cdkit::collide(m, cdkit::Transform<float>(), m, cdkit::Transform<float>::translation({0.01f, 0, 0}));
    // GJK on two built-in shapes links the installed library's precompiled instance (precompiled_queries.hpp):
    // a unit sphere 1.5 from a box of half extent 0.25 along x, 0.25 apart.
    const auto d = cdkit::gjk_distance(cdkit::Sphere<double>(1.0), cdkit::Transform<double>(),
                                       cdkit::Box<double>(cdkit::Vec3<double>(0.25, 0.25, 0.25)),
                                       cdkit::Transform<double>::translation({1.5, 0, 0}));
    std::printf("consumer: %zu triangles, colliding=%d; sphere-box distance %.6f\n", m.mesh().num_triangles(),
                int(r.colliding), d.distance);
    return r.colliding && std::abs(d.distance - 0.25) < 1e-12 ? 0 : 1;
}
