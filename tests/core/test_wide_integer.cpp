// WideInt, the predicates' last resort: its arithmetic against __int128 on values that fit, and its
// conversions at the ends of the double range. (Exactness of the predicates built on it is tested against
// GMP in tests/narrowphase/test_triangle_cgal.cpp.)
#include "test_common.hpp"

#include "cdkit/core/detail/wide_integer.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

using cdkit::detail::WideInt;

namespace {
int sign128(__int128 v) { return (v > 0) - (v < 0); }
}  // namespace

TEST_CASE("WideInt: sums and products of three equal __int128 arithmetic", "[predicates][wide]") {
    std::mt19937_64 rng(99);
    const int n = cdkit::test::scaled(20000, 500);
    for (int i = 0; i < n; ++i) {
        // Integers below 2^40 (exact in double); a product of three stays below 2^122.
        double v[6];
        __int128 w[6];
        for (int k = 0; k < 6; ++k) {
            const auto bits = static_cast<std::int64_t>(rng() >> 24) - (std::int64_t(1) << 39);
            v[k] = static_cast<double>(bits);
            w[k] = bits;
        }
        WideInt x[6];
        for (int k = 0; k < 6; ++k) x[k] = WideInt::from_double(v[k], 0);
        const WideInt got = (x[0] - x[1]) * (x[2] + x[3]) * x[4] - x[5] * x[5] * x[0];
        const __int128 expected = (w[0] - w[1]) * (w[2] + w[3]) * w[4] - w[5] * w[5] * w[0];
        REQUIRE(got.sign() == sign128(expected));
        const double e = static_cast<double>(expected);
        REQUIRE(std::abs(got.to_double(0) - e) <= 0x1p-51 * std::abs(e));  // to_double rounds twice
        REQUIRE((x[0] - x[0]).sign() == 0);
    }
}

TEST_CASE("WideInt: the ends of the double range", "[predicates][wide]") {
    const double tiny = std::numeric_limits<double>::denorm_min(), huge = std::numeric_limits<double>::max();
    const int base = WideInt::lowest_exponent(tiny);
    CHECK(base == -1074);
    CHECK(WideInt::lowest_exponent(huge) == 1024 - 53);
    CHECK(WideInt::lowest_exponent(3.0) == 0);
    CHECK(WideInt::lowest_exponent(0.75) == -2);
    const WideInt t = WideInt::from_double(tiny, base), h = WideInt::from_double(huge, base);
    CHECK(t.to_double(base) == tiny);
    CHECK(h.to_double(base) == huge);
    CHECK(WideInt::from_double(-huge, base).to_double(base) == -huge);
    // huge³ and (huge + tiny) − huge: far outside double, exact here.
    const WideInt cube = h * h * h;
    CHECK(cube.sign() == 1);
    CHECK(std::isinf(cube.to_double(3 * base)));
    CHECK(((h + t) - h).to_double(base) == tiny);
    CHECK((t * t * t).to_double(3 * base) == 0.0);  // 2^-3222 underflows as a double ...
    CHECK((t * t * t).sign() == 1);                 // ... but not as a WideInt
    CHECK(((t - h) * (t + h)).sign() == -1);
}
