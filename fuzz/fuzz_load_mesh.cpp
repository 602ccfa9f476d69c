/// \file libFuzzer harness: bytes → load_mesh_from_memory. The first byte picks the format hint. The loader
/// must either return a valid mesh (validate() passes) or throw cdkit::Error; any other exception, crash,
/// sanitizer report or hang is a finding.

#include "cdkit/core/mesh.hpp"
#include "cdkit/io/load_mesh.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* const hints[] = {"obj", "stl", "ply", "off", "gltf", "dae", "3ds"};
    const char* hint = hints[data[0] % 7];
    cdkit::LoadOptions options;
    options.join_vertices = (data[0] & 0x80) == 0;
    cdkit::TriangleMesh<double> mesh;
    try {
        mesh = cdkit::load_mesh_from_memory(data + 1, size - 1, hint, options);
    } catch (const cdkit::Error&) {
        return 0;  // the documented outcome for bad bytes
    }
    // A mesh that was returned must be usable: an Error here escapes and libFuzzer reports it.
    cdkit::validate(mesh);
    (void)cdkit::compute_stats(mesh);
    return 0;
}
