#pragma once
/// \file sincos.hpp
/// Sines and cosines of all joint angles at once. Every revolute joint needs sin qᵢ and cos qᵢ; computed one by
/// one through the C library they cost about a fifth of RNEA on a 21-joint humanoid. Here they are computed in one
/// branch-free loop that the compiler vectorises: Cody–Waite reduction by π/2 (four-part constant, exact for
/// |q| < 2²⁰ π/2) and minimax polynomials on [−π/4, π/4], accurate to about one unit in the last place (tested
/// against the C library). Angles with |q| ≥ 10⁵ rad, and scalars other than float and double, go through
/// std::sin / std::cos.

#include "spatial/algebra.hpp"  // SPATIAL_INLINE

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

/// The arithmetic of `sincos_reduced`, for T = double or a SIMD batch of doubles (batch.hpp): k = nearest integer
/// to x·2/π (`kd`, and `t`, whose significand's low bits hold k in two's complement), the reduced argument
/// r = x − k·π/2 and the polynomials sr ≈ sin r, cr ≈ cos r. What is left to the caller is the quadrant fix-up,
/// which needs the bits of t (memcpy for double, a bit cast for batches).
template <class T>
SPATIAL_INLINE void sincos_reduce(const T& x, T& t, T& sr, T& cr) {
  // k by the 1.5·2⁵² rounding trick (round to nearest, no branch).
  const T two_over_pi(6.36619772367581382433e-01);
  const T round_magic(6755399441055744.0);  // 1.5 · 2⁵²
  t = x * two_over_pi + round_magic;
  const T kd = t - round_magic;
  // π/2 = p1 + p2 + p3 + p4, p1, p2 and p3 with 33 significant bits so that k·p1, k·p2 and k·p3 are exact for
  // |k| < 2²⁰; the fourth term keeps the relative accuracy of r when x is close to a multiple of π/2.
  const T p1(1.57079632673412561417e+00);
  const T p2(6.07710050630396597660e-11);
  const T p3(2.02226624871116645580e-21);
  const T p4(8.47842766036889956997e-32);
  const T r = (((x - kd * p1) - kd * p2) - kd * p3) - kd * p4;
  const T z = r * r;
  // sin r = r + r³ (S1 + z S2 + … + z⁵ S6); cos r = 1 − z/2 + z² (C1 + z C2 + … + z⁵ C6)  (minimax on [−π/4, π/4]).
  const T ps = T(-1.66666666666666324348e-01) +
               z * (T(8.33333333332248946124e-03) +
                    z * (T(-1.98412698298579493134e-04) +
                         z * (T(2.75573137070700676789e-06) +
                              z * (T(-2.50507602534068634195e-08) + z * T(1.58969099521155010221e-10)))));
  const T pc = T(4.16666666666666019037e-02) +
               z * (T(-1.38888888888741095749e-03) +
                    z * (T(2.48015872894767294178e-05) +
                         z * (T(-2.75573143513906633035e-07) +
                              z * (T(2.08757232129817482790e-09) + z * T(-1.13596475577881948265e-11)))));
  sr = r + r * z * ps;
  const T hz = T(0.5) * z;
  const T w = T(1.0) - hz;
  cr = w + (((T(1.0) - w) - hz) + z * z * pc);
}

/// `sincos_reduce` in float arithmetic throughout, for batches of floats (batch.hpp's float lanes; T = a batch):
/// k by the 1.5·2²³ rounding trick, a four-part Cody–Waite reduction by π/2 whose first three parts have 8, 12 and
/// 12 significant bits (so that k·p1, k·p2 and k·p3 are exact for |k| < 2¹², which |x| < kSincosFloatFastLimit
/// ensures; the fourth keeps the relative accuracy of r when x is close to a multiple of π/2), and minimax
/// polynomials of degrees 7 (sine) and 8 (cosine) on [−π/4, π/4] (the coefficients of Cephes' sinf and cosf). Within two float spacings of the correctly rounded sine and cosine for joint angles (tests/support/
/// batch_suite.hpp measures it); the quadrant fix-up is `sincos_quadrant<32>` on the bits of t.
template <class T>
SPATIAL_INLINE void sincos_reduce_float(const T& x, T& t, T& sr, T& cr) {
  const T two_over_pi(6.36619772e-01f);
  const T round_magic(12582912.0f);  // 1.5 · 2²³: t's low significand bits hold k in two's complement
  t = x * two_over_pi + round_magic;
  const T kd = t - round_magic;
  const T p1(1.5703125f);                  // 201 / 128
  const T p2(4.8387050628662109e-04f);     // 12 significant bits
  const T p3(-4.3713953346014023e-08f);    // 12 significant bits
  const T p4(2.5633440682570896e-12f);     // π/2 − p1 − p2 − p3, rounded to float
  const T r = (((x - kd * p1) - kd * p2) - kd * p3) - kd * p4;
  const T z = r * r;
  sr = r + r * z * (T(-1.6666654611e-1f) + z * (T(8.3321608736e-3f) + z * T(-1.9515295891e-4f)));
  cr = (T(1.0f) - T(0.5f) * z) +
       z * z * (T(4.166664568298827e-2f) + z * (T(-1.388731625493765e-3f) + z * T(2.443315711809948e-5f)));
}

/// |x| below which `sincos_reduce_float` applies (k·p2 and k·p3 exact); other lanes take the double kernel.
inline constexpr float kSincosFloatFastLimit = 4096.0f;

/// The quadrant fix-up on the bit patterns (U = std::uint64_t or a batch of them, or with Bits = 32 a batch of
/// std::uint32_t holding floats): quadrant k mod 4 gives (sin, cos) = (sr, cr), (cr, −sr), (−sr, −cr), (−cr, sr).
/// Selected and signed with bit operations rather than branches or floating-point comparisons, so that loops over
/// it vectorise.
template <int Bits = 64, class U>
SPATIAL_INLINE void sincos_quadrant(const U& kbits, const U& sbits, const U& cbits, U& sin_bits, U& cos_bits) {
  const U odd = U(0) - (kbits & U(1));  // all ones in quadrants 1 and 3
  sin_bits = (sbits & ~odd) | (cbits & odd);
  cos_bits = (cbits & ~odd) | (sbits & odd);
  sin_bits = sin_bits ^ ((kbits & U(2)) << (Bits - 2));        // negative in quadrants 2 and 3
  cos_bits = cos_bits ^ (((kbits + U(1)) & U(2)) << (Bits - 2));  // negative in quadrants 1 and 2
}

/// sin and cos of x for |x| < kSincosFastLimit (no branch: suitable for vectorised loops).
inline void sincos_reduced(double x, double& s_out, double& c_out) {
  double t, sr, cr;
  sincos_reduce(x, t, sr, cr);
  std::uint64_t kbits, sbits, cbits, sin_bits, cos_bits;
  std::memcpy(&kbits, &t, sizeof kbits);
  std::memcpy(&sbits, &sr, sizeof sbits);
  std::memcpy(&cbits, &cr, sizeof cbits);
  sincos_quadrant(kbits, sbits, cbits, sin_bits, cos_bits);
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
