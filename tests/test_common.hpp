#pragma once
// Shared helpers for the tests: data paths, the size scale for reduced (sanitizer) runs, seeded RNG.
#include <cstdlib>
#include <random>
#include <string>

namespace cdkit::test {

/// CDKIT_TEST_SCALE (default 1) scales iteration counts; the sanitizer job sets it below 1.
inline double scale() {
    const char* s = std::getenv("CDKIT_TEST_SCALE");
    if (!s || !*s) return 1.0;
    double v = std::atof(s);
    return v > 0 ? v : 1.0;
}
/// n scaled by scale(), at least `min`.
inline int scaled(int n, int min = 1) {
    int v = static_cast<int>(n * scale());
    return v < min ? min : v;
}
/// dir + "/" + name, appended in place: GCC 12 warned (-Wstringop-overflow, a false positive) on the temporary
/// of std::string(dir) + "/" in every test that includes this header.
inline std::string joined_path(const char* dir, const std::string& name) {
    std::string path(dir);
    path.push_back('/');
    path.append(name);
    return path;
}
inline std::string data_path(const std::string& name) { return joined_path(CDKIT_DATA_DIR, name); }
inline std::string test_data_path(const std::string& name) { return joined_path(CDKIT_TEST_DATA_DIR, name); }

}  // namespace cdkit::test
