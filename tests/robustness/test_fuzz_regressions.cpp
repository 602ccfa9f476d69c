// Every fuzz_load_mesh reproducer kept in fuzz/regressions/ replayed through load_mesh_from_memory, the way
// the harness calls it: the outcome must be a valid mesh or cdkit::Error (no hang, no other exception).
// The sanitizer CI job turns this into a memory check too. See fuzz/regressions/README.md.
#include "test_common.hpp"

#include "cdkit/io/load_mesh.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace cdkit;

TEST_CASE("fuzz_load_mesh regressions load or raise cdkit::Error", "[robustness][io]") {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(CDKIT_TEST_DATA_DIR) / ".." / ".." / "fuzz" / "regressions";
    REQUIRE(fs::is_directory(dir));
    int replayed = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("fuzz_load_mesh-", 0) != 0) continue;
        std::ifstream in(entry.path(), std::ios::binary);
        const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        REQUIRE(!bytes.empty());
        static const char* const hints[] = {"obj", "stl", "ply", "off", "gltf", "dae", "3ds"};
        const auto first = static_cast<unsigned char>(bytes[0]);
        LoadOptions options;
        options.join_vertices = (first & 0x80) == 0;
        INFO(name);
        try {
            const TriangleMesh<double> m =
                load_mesh_from_memory(bytes.data() + 1, bytes.size() - 1, hints[first % 7], options, name);
            CHECK_NOTHROW(validate(m));
        } catch (const Error& e) {
            CHECK(std::string(e.what()).rfind(name, 0) == 0);  // the error names its source
        }
        ++replayed;
    }
    CHECK(replayed >= 2);
}

TEST_CASE("A PLY header without end_header raises cdkit::Error", "[robustness][io]") {
    // assimp 5.2.5 never returns on this input; load_mesh's PLY check rejects it first.
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n1\n";
    try {
        (void)load_mesh_from_memory(ply.data(), ply.size(), "ply");
        FAIL("no exception");
    } catch (const Error& e) {
        CHECK(e.reason() == "PLY header has no 'end_header' line (truncated, or not a PLY file)");
    }
}
