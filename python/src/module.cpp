// The extension module cdkit._cdkit; python/cdkit/__init__.py re-exports it as `cdkit`.
#include "common.hpp"

PYBIND11_MODULE(_cdkit, m) {
    m.doc() = "cdkit: collision detection (meshes with BVHs, convex shapes, World, inner sphere trees, continuous "
              "collision, ray casts) with numpy at the boundary. Every query releases the GIL.";
    using namespace cdkit::python;
    init_core(m);
    init_mesh(m);
    init_batch(m);
    init_convex(m);
    init_convex_cached(m);
    init_manifold(m);  // before the World: WorldContact.points returns ManifoldPoints
    init_world(m);
    init_ist(m);
    init_mesh_depth(m);
    init_ccd(m);
    init_mesh_convex(m);
    init_mesh_convex_ccd(m);
}
