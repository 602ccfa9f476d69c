#pragma once
/// \file Turns fuzzer bytes into numbers for the harnesses: a little reader that never reads past the end
/// (missing bytes read as zero), and a coordinate decoding that mixes small dyadic values (so that shared
/// vertices, coplanar and touching configurations are common) with raw doubles (so that NaN, ±Inf, signed
/// zeros and full-precision values appear).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace cdkit::fuzz {

class Reader {
public:
    Reader(const std::uint8_t* data, std::size_t size) noexcept : p_(data), end_(data + size) {}
    [[nodiscard]] std::uint8_t byte() noexcept { return p_ < end_ ? *p_++ : 0; }
    [[nodiscard]] double raw_double() noexcept {
        unsigned char b[8] = {};
        for (unsigned char& c : b) c = byte();
        double x;
        std::memcpy(&x, b, sizeof x);
        return x;
    }
    /// One coordinate: a tag byte, then either nothing (the tag as k/8, k in [-64, 63]) or 8 raw bytes.
    /// Raw finite values are folded into [2^-100, 1e6] in magnitude (or zero): beyond that the predicates'
    /// documented range and the transform's overflow are what is exercised, not the code's logic.
    /// NaN and ±Inf pass through unchanged.
    [[nodiscard]] double coordinate() noexcept {
        const std::uint8_t tag = byte();
        if (tag < 0xF0) return double(int(tag % 128) - 64) / 8.0;
        double x = raw_double();
        if (!std::isfinite(x)) return x;
        if (std::abs(x) > 1e6) x = std::fmod(x, 1e6);
        if (std::abs(x) < 0x1p-100) x = 0;
        return x;
    }
    [[nodiscard]] bool empty() const noexcept { return p_ >= end_; }

private:
    const std::uint8_t* p_;
    const std::uint8_t* end_;
};

}  // namespace cdkit::fuzz
