// Uses the installed cdkit package: load a mesh, build an AABB tree in float, collide two copies.
#include <cdkit/cdkit.hpp>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc < 2) return 2;
    const cdkit::MeshModel<cdkit::Aabb<float>> m(cdkit::load_mesh(argv[1]).cast<float>());
    const auto r = cdkit::collide(m, cdkit::Transform<float>(), m, cdkit::Transform<float>::translation({0.01f, 0, 0}));
    std::printf("consumer: %zu triangles, colliding=%d\n", m.mesh().num_triangles(), int(r.colliding));
    return r.colliding ? 0 : 1;
}
