#pragma once
/// \file sincos.hpp
/// Sines and cosines of all joint angles at once. Every revolute joint needs sin qᵢ and cos qᵢ; computed one by
/// one through the C library they cost about a fifth of RNEA on a 21-joint humanoid. Here they are computed in one
/// branch-free loop that the compiler vectorises: Cody–Waite reduction by π/2 (four-part constant, exact for
/// |q| < 2²⁰ π/2) and minimax polynomials on [−π/4, π/4], accurate to about one unit in the last place (tested
/// against the C library). Angles with |q| ≥ 10⁵ rad, and scalars other than float and double, go through
/// std::sin / std::cos.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace spatial::detail {

/// A customisation point for scalar types that compute sine and cosine together (batch.hpp's SIMD lanes, whose
/// `xsimd::sincos` shares one argument reduction between the two): specialise with `custom = true` and a static
/// `sincos(S x, S& s, S& c)`. The built-in floating-point types take `sincos_reduced` below; other scalars
/// std::sin and std::cos.
template <class S>
struct SincosTraits {
  static constexpr bool custom = false;
};

/// sin and cos of x for |x| < kSincosFastLimit (no branch: suitable for vectorised loops).
inline void sincos_reduced(double x, double& s_out, double& c_out) {
  // k = nearest integer to x·2/π, by the 1.5·2⁵² rounding trick (round to nearest, no branch); the low bits of
  // t's significand then hold k in two's complement.
  constexpr double two_over_pi = 6.36619772367581382433e-01;
  constexpr double round_magic = 6755399441055744.0;  // 1.5 · 2⁵²
  const double t = x * two_over_pi + round_magic;
  const double kd = t - round_magic;
  std::uint64_t kbits;
  std::memcpy(&kbits, &t, sizeof kbits);
  // π/2 = p1 + p2 + p3 + p4, p1, p2 and p3 with 33 significant bits so that k·p1, k·p2 and k·p3 are exact for
  // |k| < 2²⁰; the fourth term keeps the relative accuracy of r when x is close to a multiple of π/2.
  constexpr double p1 = 1.57079632673412561417e+00;
  constexpr double p2 = 6.07710050630396597660e-11;
  constexpr double p3 = 2.02226624871116645580e-21;
  constexpr double p4 = 8.47842766036889956997e-32;
  const double r = (((x - kd * p1) - kd * p2) - kd * p3) - kd * p4;
  const double z = r * r;
  // sin r = r + r³ (S1 + z S2 + … + z⁵ S6); cos r = 1 − z/2 + z² (C1 + z C2 + … + z⁵ C6)  (minimax on [−π/4, π/4]).
  const double ps = -1.66666666666666324348e-01 +
                    z * (8.33333333332248946124e-03 +
                         z * (-1.98412698298579493134e-04 +
                              z * (2.75573137070700676789e-06 +
                                   z * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10))));
  const double pc = 4.16666666666666019037e-02 +
                    z * (-1.38888888888741095749e-03 +
                         z * (2.48015872894767294178e-05 +
                              z * (-2.75573143513906633035e-07 +
                                   z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11))));
  const double sr = r + r * z * ps;
  const double hz = 0.5 * z;
  const double w = 1.0 - hz;
  const double cr = w + (((1.0 - w) - hz) + z * z * pc);
  // Quadrant k mod 4: (sin, cos) = (sr, cr), (cr, −sr), (−sr, −cr), (−cr, sr). Selected and signed with bit
  // operations rather than branches or floating-point comparisons, so that loops over this function vectorise.
  std::uint64_t sbits, cbits;
  std::memcpy(&sbits, &sr, sizeof sbits);
  std::memcpy(&cbits, &cr, sizeof cbits);
  const std::uint64_t odd = std::uint64_t(0) - (kbits & 1);  // all ones in quadrants 1 and 3
  std::uint64_t sin_bits = (sbits & ~odd) | (cbits & odd);
  std::uint64_t cos_bits = (cbits & ~odd) | (sbits & odd);
  sin_bits ^= (kbits & 2) << 62;        // negative in quadrants 2 and 3
  cos_bits ^= ((kbits + 1) & 2) << 62;  // negative in quadrants 1 and 2
  std::memcpy(&s_out, &sin_bits, sizeof s_out);
  std::memcpy(&c_out, &cos_bits, sizeof c_out);
}

inline constexpr double kSincosFastLimit = 1e5;
inline constexpr std::uint64_t kSincosFastLimitBits = 0x40F86A0000000000ULL;  // the bits of 1e5

/// c[i] = cos q[i], s[i] = sin q[i] for i < n.
template <class S, class Q, class C>
inline void sincos_all(const Q& q, C& c, C& s, int n) {
  using std::abs;
  if constexpr (std::is_same_v<S, double> || std::is_same_v<S, float>) {
    int slow = 0;
    for (int i = 0; i < n; ++i) {
      double si, ci;
      const double x = static_cast<double>(q[i]);
      sincos_reduced(x, si, ci);
      s[i] = static_cast<S>(si);
      c[i] = static_cast<S>(ci);
      // |x| ≥ limit (or NaN, Inf) by comparing the bit patterns of |x| and the limit as integers, which unlike a
      // floating-point comparison cannot trap, so the loop vectorises.
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      slow += (bits & 0x7fffffffffffffffULL) >= kSincosFastLimitBits ? 1 : 0;
    }
    if (slow != 0) {
      for (int i = 0; i < n; ++i) {
        const double x = static_cast<double>(q[i]);
        if (!(abs(x) < kSincosFastLimit)) {
          s[i] = static_cast<S>(std::sin(x));
          c[i] = static_cast<S>(std::cos(x));
        }
      }
    }
  } else if constexpr (SincosTraits<S>::custom) {
    for (int i = 0; i < n; ++i) SincosTraits<S>::sincos(S(q[i]), s[i], c[i]);
  } else {
    using std::cos;
    using std::sin;
    for (int i = 0; i < n; ++i) {
      s[i] = sin(S(q[i]));
      c[i] = cos(S(q[i]));
    }
  }
}

}  // namespace spatial::detail
