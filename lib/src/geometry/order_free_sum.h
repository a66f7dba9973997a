// A sum of doubles that does not depend on the order of its terms: each term is kept exactly, by
// exponent, and the whole is rounded once at the end. Negating every term negates the sum and
// scaling every term by a power of two scales it, bit for bit; a plain running sum gives other last
// bits for the same terms in another order (vertices of one mesh numbered otherwise). CGAL's Mpzf
// (detect/orientation.cpp) sums exactly too, but its to_double rounds at 64-bit limb boundaries,
// which a power-of-two scale moves, so the scaled scene's sum could differ in its last bit.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>

namespace untangle {

class OrderFreeSum {
 public:
  OrderFreeSum() : buckets_(std::make_unique<std::array<__int128, 2048>>()) {}

  void add(double x) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    const int exponent = static_cast<int>((bits >> 52) & 0x7ff);
    if (exponent == 0x7ff) {  // infinity or NaN: they decide the sum
      special_ += x;
      return;
    }
    __int128 mantissa = static_cast<__int128>(bits & ((std::uint64_t(1) << 52) - 1));
    if (exponent != 0) mantissa += __int128(1) << 52;  // normal: the hidden bit
    (*buckets_)[exponent == 0 ? 1 : exponent] += bits >> 63 ? -mantissa : mantissa;
    highest_ = std::max(highest_, exponent == 0 ? 1 : exponent);
    ++count_;
  }

  // The sum, rounded to nearest once: every bucket is brought to units of 2^-40 of the largest
  // term's last bit (terms below that are cut toward zero, alike for a term and its negation), and
  // the 128-bit total is converted.
  double value() const {
    if (special_ != 0.0 || std::isnan(special_)) return special_;
    if (count_ == 0) return 0.0;
    constexpr int kBelow = 40;  // 2^(53 + 40) * 2^31 terms stays under 2^127
    __int128 total = 0;
    for (int e = 1; e <= highest_; ++e) {
      const __int128 b = (*buckets_)[e];
      if (b == 0) continue;
      const int shift = e - (highest_ - kBelow);
      if (shift >= 0)
        total += b * (__int128(1) << shift);
      else if (shift > -120)
        total += b / (__int128(1) << -shift);
    }
    return std::ldexp(static_cast<double>(total), highest_ - kBelow - 1075);
  }

 private:
  std::unique_ptr<std::array<__int128, 2048>> buckets_;
  int highest_ = 1;
  std::size_t count_ = 0;
  double special_ = 0.0;
};

}  // namespace untangle
