// Robustness over third-party corpora: every file of Debian's assimp-testmodels (assimp's own test suite:
// valid models, deliberately broken ones, textures, READMEs) and the mesh files of openscad-testing-data must
// either load or raise cdkit::Error. Anything else (another exception type, a crash, a hang) is a bug.
// With assimp 5.2.5 the whole walk takes a few seconds in Release, so no size limit is applied, and no file
// needs to be skipped.
#include "cdkit/io/load_mesh.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Corpus {
    const char* dir;
    /// Lower-case extensions to take (with the dot); empty: every regular file.
    std::vector<std::string> extensions;
};

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::vector<fs::path> files_of(const Corpus& c) {
    std::vector<fs::path> out;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(c.dir, fs::directory_options::skip_permission_denied, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (!it->is_regular_file(ec)) continue;
        const std::string ext = lower(it->path().extension().string());
        if (c.extensions.empty() || std::find(c.extensions.begin(), c.extensions.end(), ext) != c.extensions.end())
            out.push_back(it->path());
    }
    std::sort(out.begin(), out.end());  // a stable order, so a failure is reproducible
    return out;
}

}  // namespace

TEST_CASE("load_mesh over the assimp and OpenSCAD test corpora: loads or raises cdkit::Error", "[corpus]") {
    const Corpus corpora[] = {
        // Debian package assimp-testmodels.
        {"/usr/share/assimp/models", {}},
        // Debian package openscad-testing-data: its mesh files (the rest is .scad sources and PNG images).
        {"/usr/share/openscad", {".stl", ".off", ".obj", ".amf", ".3mf", ".ply", ".dxf"}},
    };
    for (const Corpus& c : corpora) {
        std::error_code ec;
        INFO("corpus " << c.dir << " is not installed: scripts/install-deps installs it (scripts/test runs it)");
        REQUIRE(fs::is_directory(c.dir, ec));
        const std::vector<fs::path> files = files_of(c);
        std::size_t loaded = 0, rejected = 0, triangles = 0;
        const auto t0 = std::chrono::steady_clock::now();
        for (const fs::path& f : files) {
            try {
                const auto m = cdkit::load_mesh(f.string());
                // A loaded mesh is valid by contract; re-check, since the corpus is the place bad data shows.
                CHECK_NOTHROW(cdkit::validate(m));
                CHECK(m.source == f.string());
                triangles += m.num_triangles();
                ++loaded;
            } catch (const cdkit::Error& e) {
                // Every message names the file (Error::source is the path).
                CHECK(e.source() == f.string());
                ++rejected;
            } catch (const std::exception& e) {
                FAIL_CHECK(f.string() << ": threw a non-cdkit exception: " << e.what());
            } catch (...) {
                FAIL_CHECK(f.string() << ": threw a non-std exception");
            }
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        WARN(c.dir << ": " << files.size() << " files, " << loaded << " loaded (" << triangles << " triangles), "
                   << rejected << " rejected, in " << seconds << " s");
        CHECK(loaded > 0);  // the corpus is not all rejects: a loader that rejects everything must not pass
    }
}
