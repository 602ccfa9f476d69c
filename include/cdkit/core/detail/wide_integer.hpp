#pragma once
/// \file A fixed-capacity signed integer: the predicates' last resort for input outside the range where
/// floating-point expansions stay exact (subnormal or huge coordinates, see cdkit/core/predicates.hpp).
///
/// Every finite double is an integer multiple of 2^-1074, so the coordinates of one predicate call, divided
/// by 2^base (base: the smallest exponent among them), are integers of at most 2,151 bits; orient3d's
/// determinant of their differences needs at most 6,456 bits. Schoolbook arithmetic on 64-bit limbs is
/// slow but exact, and runs only for input no floating-point stage can handle.

#include <cmath>
#include <cstdint>
#include <limits>

namespace cdkit::detail {

__extension__ using WideLimbProduct = unsigned __int128;  // GCC/Clang; __extension__ keeps -Wpedantic quiet

class WideInt {
public:
    /// 102 × 64 = 6,528 bits: orient3d's determinant of any finite doubles (6,456 bits) fits.
    static constexpr int kLimbs = 102;

    /// The exponent of x's lowest set bit: x is an odd integer times 2^lowest_exponent(x). x finite, nonzero.
    [[nodiscard]] static int lowest_exponent(double x) noexcept {
        int e;
        const double f = std::frexp(std::abs(x), &e);  // |x| = f·2^e, f in [0.5, 1)
        const auto m = static_cast<std::uint64_t>(std::ldexp(f, 53));
        return e - 53 + __builtin_ctzll(m);
    }
    /// x / 2^base, exactly; x must be finite and 0 or a multiple of 2^base (base <= lowest_exponent(x)).
    [[nodiscard]] static WideInt from_double(double x, int base) noexcept {
        WideInt r;
        if (x == 0.0) return r;
        int e;
        const double f = std::frexp(std::abs(x), &e);
        auto m = static_cast<std::uint64_t>(std::ldexp(f, 53));  // |x| = m·2^(e-53), m < 2^53
        const int zeros = __builtin_ctzll(m);
        m >>= zeros;                                  // |x| = m·2^lowest_exponent(x), m odd
        const int shift = e - 53 + zeros - base;      // >= 0 by the precondition
        const int limb = shift / 64, bit = shift % 64;
        for (int i = 0; i <= limb + 1; ++i) r.limb_[i] = 0;
        r.limb_[limb] = m << bit;
        if (bit != 0) r.limb_[limb + 1] = m >> (64 - bit);
        r.n_ = limb + 2;
        r.negative_ = x < 0.0;
        r.trim();
        return r;
    }

    [[nodiscard]] int sign() const noexcept { return n_ == 0 ? 0 : (negative_ ? -1 : 1); }

    /// The value times 2^scale rounded to double (relative error about 2^-52 while in double's range;
    /// 0 or ±inf beyond it).
    [[nodiscard]] double to_double(int scale) const noexcept {
        if (n_ == 0) return 0.0;
        double v = static_cast<double>(limb_[n_ - 1]);
        if (n_ >= 2) v = v * 0x1p64 + static_cast<double>(limb_[n_ - 2]);
        const int low_limbs = n_ >= 2 ? n_ - 2 : 0;
        v = std::ldexp(v, 64 * low_limbs + scale);
        return negative_ ? -v : v;
    }

    friend WideInt operator+(const WideInt& a, const WideInt& b) noexcept { return add(a, b, b.negative_); }
    friend WideInt operator-(const WideInt& a, const WideInt& b) noexcept { return add(a, b, !b.negative_); }
    friend WideInt operator*(const WideInt& a, const WideInt& b) noexcept {
        WideInt r;
        if (a.n_ == 0 || b.n_ == 0) return r;
        const int n = a.n_ + b.n_ < kLimbs ? a.n_ + b.n_ : kLimbs;
        for (int k = 0; k < n; ++k) r.limb_[k] = 0;
        for (int i = 0; i < a.n_; ++i) {
            WideLimbProduct carry = 0;
            for (int j = 0; j < b.n_; ++j) {
                const int k = i + j;
                if (k >= kLimbs) break;  // unreachable for predicate input (see kLimbs)
                const WideLimbProduct t =
                    static_cast<WideLimbProduct>(a.limb_[i]) * b.limb_[j] + r.limb_[k] + carry;
                r.limb_[k] = static_cast<std::uint64_t>(t);
                carry = t >> 64;
            }
            if (i + b.n_ < kLimbs) r.limb_[i + b.n_] = static_cast<std::uint64_t>(carry);
        }
        r.n_ = n;
        r.negative_ = a.negative_ != b.negative_;
        r.trim();
        return r;
    }

private:
    /// a + (±|b|), the sign of b's term given by b_negative.
    static WideInt add(const WideInt& a, const WideInt& b, bool b_negative) noexcept {
        if (a.negative_ == b_negative) {
            WideInt r = add_magnitudes(a, b);
            r.negative_ = a.negative_;
            r.trim();
            return r;
        }
        const int c = compare_magnitudes(a, b);
        if (c == 0) return WideInt{};
        WideInt r = c > 0 ? subtract_magnitudes(a, b) : subtract_magnitudes(b, a);
        r.negative_ = c > 0 ? a.negative_ : b_negative;
        r.trim();
        return r;
    }
    static WideInt add_magnitudes(const WideInt& a, const WideInt& b) noexcept {
        WideInt r;
        const int n = a.n_ > b.n_ ? a.n_ : b.n_;
        std::uint64_t carry = 0;
        for (int i = 0; i < n; ++i) {
            const std::uint64_t ai = i < a.n_ ? a.limb_[i] : 0, bi = i < b.n_ ? b.limb_[i] : 0;
            const WideLimbProduct t = static_cast<WideLimbProduct>(ai) + bi + carry;
            r.limb_[i] = static_cast<std::uint64_t>(t);
            carry = static_cast<std::uint64_t>(t >> 64);
        }
        r.n_ = n;
        if (carry != 0 && n < kLimbs) r.limb_[r.n_++] = carry;
        return r;
    }
    /// |a| − |b| for |a| > |b|.
    static WideInt subtract_magnitudes(const WideInt& a, const WideInt& b) noexcept {
        WideInt r;
        std::uint64_t borrow = 0;
        for (int i = 0; i < a.n_; ++i) {
            const std::uint64_t bi = i < b.n_ ? b.limb_[i] : 0;
            const std::uint64_t d = a.limb_[i] - bi - borrow;
            borrow = (a.limb_[i] < bi) || (a.limb_[i] - bi < borrow) ? 1 : 0;
            r.limb_[i] = d;
        }
        r.n_ = a.n_;
        return r;
    }
    static int compare_magnitudes(const WideInt& a, const WideInt& b) noexcept {
        if (a.n_ != b.n_) return a.n_ > b.n_ ? 1 : -1;
        for (int i = a.n_ - 1; i >= 0; --i)
            if (a.limb_[i] != b.limb_[i]) return a.limb_[i] > b.limb_[i] ? 1 : -1;
        return 0;
    }
    void trim() noexcept {
        while (n_ > 0 && limb_[n_ - 1] == 0) --n_;
        if (n_ == 0) negative_ = false;
    }

    // Little-endian magnitude; only limbs below n_ are meaningful (the rest is left uninitialised: an
    // orient3d builds dozens of these, and zeroing 816 bytes each dominated its cost).
    std::uint64_t limb_[kLimbs];
    int n_ = 0;
    bool negative_ = false;
};

}  // namespace cdkit::detail
