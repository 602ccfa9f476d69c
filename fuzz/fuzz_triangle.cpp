/// \file libFuzzer harness: 6 vertices → triangles_intersect, which must give one answer for all 36 vertex
/// orders and both argument orders, equal to triangle_intersection().intersect; in double and, for the
/// same points rounded to float, in float. Aborts on any difference.

#include "fuzz_input.hpp"

#include "cdkit/narrowphase/triangle.hpp"

#include <array>
#include <cstdio>
#include <cstdlib>

namespace {

constexpr int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};

template <class S> void check(const std::array<cdkit::Vec3<S>, 6>& v, const char* type) {
    const auto& p = v;
    const bool ref = cdkit::triangles_intersect(p[0], p[1], p[2], p[3], p[4], p[5]);
    auto fail = [&](const char* what, int i, int j) {
        std::fprintf(stderr, "fuzz_triangle (%s): %s differs (orders %d, %d); reference %d\n", type, what, i, j, int(ref));
        for (int k = 0; k < 6; ++k)
            std::fprintf(stderr, "  v%d %.17g %.17g %.17g\n", k, double(p[k].x()), double(p[k].y()), double(p[k].z()));
        std::abort();
    };
    if (cdkit::triangle_intersection(p[0], p[1], p[2], p[3], p[4], p[5]).intersect != ref) fail("triangle_intersection", 0, 0);
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) {
            const auto* a = kPerm[i];
            const auto* b = kPerm[j];
            if (cdkit::triangles_intersect(p[a[0]], p[a[1]], p[a[2]], p[3 + b[0]], p[3 + b[1]], p[3 + b[2]]) != ref)
                fail("vertex order", i, j);
            if (cdkit::triangles_intersect(p[3 + b[0]], p[3 + b[1]], p[3 + b[2]], p[a[0]], p[a[1]], p[a[2]]) != ref)
                fail("argument swap", i, j);
        }
    // The floating-point mode must at least be safe (no UB, no crash) on the same input.
    (void)cdkit::triangle_intersection(p[0], p[1], p[2], p[3], p[4], p[5], cdkit::PredicateMode::floating_point);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    cdkit::fuzz::Reader in(data, size);
    std::array<cdkit::Vec3<double>, 6> v;
    for (auto& x : v) x = {in.coordinate(), in.coordinate(), in.coordinate()};
    for (const auto& x : v)
        if (!x.allFinite()) return 0;  // outside the triangle test's domain (MeshModel rejects such meshes)
    check<double>(v, "double");
    std::array<cdkit::Vec3<float>, 6> f;
    for (int k = 0; k < 6; ++k) f[k] = v[k].cast<float>();
    check<float>(f, "float");
    return 0;
}
