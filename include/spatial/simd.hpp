#pragma once
/// \file simd.hpp
/// AVX2 kernels for the recursive Newton–Euler algorithm on compile-time trees in double precision.
///
/// The scalar algorithms (algorithms.hpp) spend about one instruction per flop on 3-vector arithmetic. Here every
/// 3-vector lives in one 256-bit register (lanes x, y, z and a spare fourth lane), so that
///  - E x (E by columns) and Eᵀ x (E by rows) are three broadcasts and three fused multiply–adds,
///  - a × b is three lane permutations and two arithmetic instructions: a × b = yzx(a ∘ yzx(b) − yzx(a) ∘ b),
///  - the joint rotation X_J X_T about coordinate axis K is one lane swap and one multiply–add per column.
/// The fourth lane is never broadcast into the others, so whatever it holds cannot reach a result; values are
/// written back to `Data` with three-lane stores (or four-lane stores that a later store overwrites).
///
/// Used when the translation unit is compiled with AVX2 and FMA (`-mavx2 -mfma`, `-march=x86-64-v3`,
/// `-march=native` on such a machine), the scalar is double, the tree is a compile-time tree of revolute joints
/// about coordinate axes (RevoluteX/Y/Z: all reference models), and no external force is given. Everything else
/// takes the scalar path. Define SPATIAL_NO_SIMD to always take it. Results agree with the scalar path to rounding
/// (tests/simd/: every term combination, every per-body output).

#include "spatial/algebra.hpp"
#include "spatial/joints.hpp"
#include "spatial/model.hpp"
#include "spatial/sincos.hpp"

#include <cstddef>
#include <type_traits>
#include <utility>

#if defined(__AVX2__) && defined(__FMA__) && !defined(SPATIAL_NO_SIMD)
#define SPATIAL_SIMD_AVX2 1
#include <immintrin.h>
#else
#define SPATIAL_SIMD_AVX2 0
#endif

namespace spatial::detail {

/// The coordinate axis K (0, 1, 2) of a revolute joint about x, y or z; −1 for every other joint type.
constexpr int revolute_axis(JointType t) {
  return t == JointType::RevoluteX ? 0 : t == JointType::RevoluteY ? 1 : t == JointType::RevoluteZ ? 2 : -1;
}

template <class Tree, std::size_t... I>
constexpr bool all_revolute_axis_aligned(std::index_sequence<I...>) {
  return ((revolute_axis(Tree::joint[I]) >= 0) && ...);
}

/// True when `rnea` without external forces takes the AVX2 path on a Model<S, T> (see the file comment).
template <class S, class T>
constexpr bool rnea_simd_enabled() {
  if constexpr (!SPATIAL_SIMD_AVX2 || !std::is_same_v<S, double> || !is_static_tree_v<T>) {
    return false;
  } else {
    return all_revolute_axis_aligned<T>(std::make_index_sequence<std::size_t(T::size)>{});
  }
}

#if SPATIAL_SIMD_AVX2
/// Forces inlining of a lambda's body into its caller (GCC otherwise keeps some per-body lambdas out of line).
#define SPATIAL_LAMBDA_INLINE __attribute__((always_inline))

namespace simd {

using V = __m256d;

SPATIAL_INLINE V zero() { return _mm256_setzero_pd(); }
/// Four doubles from p (the fourth lane is whatever follows the 3-vector in memory; p[3] must be readable).
SPATIAL_INLINE V load4(const double* p) { return _mm256_loadu_pd(p); }
/// Three doubles from p, fourth lane 0 (nothing beyond p[2] is read).
SPATIAL_INLINE V load3(const double* p) {
  return _mm256_maskload_pd(p, _mm256_set_epi64x(0, -1, -1, -1));
}
/// Lanes 0..3 to p[0..3] (p[3] is overwritten: a later store must put it right).
SPATIAL_INLINE void store4(double* p, V x) { _mm256_storeu_pd(p, x); }
/// Lanes 0..2 to p[0..2].
SPATIAL_INLINE void store3(double* p, V x) {
  _mm_storeu_pd(p, _mm256_castpd256_pd128(x));
  _mm_store_sd(p + 2, _mm256_extractf128_pd(x, 1));
}
SPATIAL_INLINE V bcast(double s) { return _mm256_set1_pd(s); }
/// Lane L of x in all four lanes.
template <int L>
SPATIAL_INLINE V lane(V x) {
  return _mm256_permute4x64_pd(x, L * 0x55);
}
template <int L>
SPATIAL_INLINE double get(V x) {
  if constexpr (L == 0) return _mm256_cvtsd_f64(x);
  else return _mm256_cvtsd_f64(_mm256_permute4x64_pd(x, L));
}
/// (x₁, x₂, x₀, x₃)
SPATIAL_INLINE V yzx(V x) { return _mm256_permute4x64_pd(x, 0xC9); }
/// a × b in lanes 0..2; lane 3 is 0 for finite inputs.
SPATIAL_INLINE V cross(V a, V b) {
  return yzx(_mm256_fmsub_pd(a, yzx(b), _mm256_mul_pd(yzx(a), b)));
}
/// c0 x₀ + c1 x₁ + c2 x₂: E x when c0, c1, c2 are the columns of E, Eᵀ x when they are its rows.
SPATIAL_INLINE V comb(V c0, V c1, V c2, V x) {
  return _mm256_fmadd_pd(c2, lane<2>(x), _mm256_fmadd_pd(c1, lane<1>(x), _mm256_mul_pd(c0, lane<0>(x))));
}
/// x with lanes (K+1) % 3 and (K+2) % 3 exchanged.
template <int K>
SPATIAL_INLINE V swap_other(V x) {
  if constexpr (K == 2) return _mm256_permute_pd(x, 0x9);               // (x₁, x₀, x₂, x₃)
  else if constexpr (K == 0) return _mm256_permute4x64_pd(x, 0xD8);     // (x₀, x₂, x₁, x₃)
  else return _mm256_permute4x64_pd(x, 0xC6);                          // (x₂, x₁, x₀, x₃)
}
/// (+1 in lane (K+1) % 3, −1 in lane (K+2) % 3, 0 elsewhere): swap_other<K>(a) ∘ sign<K>() s = a × e_K s.
template <int K>
SPATIAL_INLINE V sign() {
  constexpr int i = (K + 1) % 3;
  return _mm256_set_pd(0.0, i == 2 ? 1.0 : (K + 2) % 3 == 2 ? -1.0 : 0.0, i == 1 ? 1.0 : (K + 2) % 3 == 1 ? -1.0 : 0.0,
                       i == 0 ? 1.0 : (K + 2) % 3 == 0 ? -1.0 : 0.0);
}
/// 1 in lanes (K+1) % 3 and (K+2) % 3, 0 elsewhere.
template <int K>
SPATIAL_INLINE V other() {
  return _mm256_set_pd(0.0, K == 2 ? 0.0 : 1.0, K == 1 ? 0.0 : 1.0, K == 0 ? 0.0 : 1.0);
}
/// e_K s (s in lane K, 0 elsewhere).
template <int K>
SPATIAL_INLINE V axis(double s) {
  return _mm256_set_pd(0.0, K == 2 ? s : 0.0, K == 1 ? s : 0.0, K == 0 ? s : 0.0);
}
/// Rows 0, 1, 2 of the 3×3 matrix with columns c0, c1, c2 (fourth lanes 0); the rows' fourth lanes are 0.
SPATIAL_INLINE void transpose(V c0, V c1, V c2, V& r0, V& r1, V& r2) {
  const V t0 = _mm256_unpacklo_pd(c0, c1);          // c0₀ c1₀ c0₂ c1₂
  const V t1 = _mm256_unpackhi_pd(c0, c1);          // c0₁ c1₁ c0₃ c1₃
  const V t2 = _mm256_unpacklo_pd(c2, zero());      // c2₀ 0 c2₂ 0
  const V t3 = _mm256_unpackhi_pd(c2, zero());      // c2₁ 0 c2₃ 0
  r0 = _mm256_permute2f128_pd(t0, t2, 0x20);
  r1 = _mm256_permute2f128_pd(t1, t3, 0x20);
  r2 = _mm256_permute2f128_pd(t0, t2, 0x31);
}

template <class F, int... I>
SPATIAL_INLINE void for_each_index(F& f, std::integer_sequence<int, I...>) {
  (f(std::integral_constant<int, I>{}), ...);
}

/// Per-body values of one RNEA call, kept in registers' form between the passes.
template <int NB>
struct RneaWork {
  V vw[NB], vv[NB];    // velocity
  V aw[NB], av[NB];    // acceleration
  V fn[NB], ff[NB];    // force
  V row[NB][3];        // rows of E in ⁱX_λ
};

/// rnea_impl's AVX2 path (the same equations, the same outputs in `data`).
template <unsigned Terms, class S, class T, class Q, class QD, class QDD, class Out>
void rnea(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
          const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<QDD>& qdd, Out& tau) {
  constexpr bool G = (Terms & 1u) != 0;
  constexpr bool Vel = (Terms & 2u) != 0;
  constexpr bool A = (Terms & 4u) != 0;
  constexpr int NB = T::size;
  static_assert(sizeof(Transform<double>) == 12 * sizeof(double) && sizeof(Motion<double>) == 6 * sizeof(double) &&
                    sizeof(Force<double>) == 6 * sizeof(double) && sizeof(Inertia<double>) == 13 * sizeof(double),
                "the AVX2 kernels assume unpadded spatial types");
  sincos_all<S>(q, data.cos_q, data.sin_q, NB);
  RneaWork<NB> w;
  const V g0 = _mm256_sub_pd(zero(), load3(model.gravity().data()));  // a₀ = −a_g = [0; −g]

  auto forward = [&](auto I) SPATIAL_LAMBDA_INLINE {
    constexpr int i = decltype(I)::value;
    constexpr int p = T::parent[i];
    constexpr int K = revolute_axis(T::joint[i]);
    const Transform<double>& XT = model.tree_transform(i);
    const double* e = XT.E.data();
    // Columns of E = E_J(q) E_T: x′ = x ∘ (c in the two other lanes, 1 in lane K) + swap(x) ∘ sign s.
    const V cvec = _mm256_fmadd_pd(bcast(data.cos_q[i]), other<K>(), axis<K>(1.0));
    const V svec = _mm256_mul_pd(bcast(data.sin_q[i]), sign<K>());
    const V t0 = load4(e), t1 = load4(e + 3), t2 = load4(e + 6);
    const V c0 = _mm256_fmadd_pd(swap_other<K>(t0), svec, _mm256_mul_pd(t0, cvec));
    const V c1 = _mm256_fmadd_pd(swap_other<K>(t1), svec, _mm256_mul_pd(t1, cvec));
    const V c2 = _mm256_fmadd_pd(swap_other<K>(t2), svec, _mm256_mul_pd(t2, cvec));
    const V r = load3(XT.r.data());
    transpose(c0, c1, c2, w.row[i][0], w.row[i][1], w.row[i][2]);
    double* x = data.X_up[static_cast<std::size_t>(i)].E.data();
    store4(x, c0);
    store4(x + 3, c1);
    store4(x + 6, c2);
    store3(x + 9, r);

    // ⁱX_λ m = [E ω; E (v − r × ω)]
    auto apply = [&](V mw, V mv, V& ow, V& ov) {
      ow = comb(c0, c1, c2, mw);
      ov = comb(c0, c1, c2, _mm256_sub_pd(mv, cross(r, mw)));
    };
    V vw = zero(), vv = zero(), aw = zero(), av = zero();
    if constexpr (Vel) {
      if constexpr (p >= 0) apply(w.vw[p], w.vv[p], vw, vv);
      vw = _mm256_add_pd(vw, axis<K>(double(qd[i])));
      w.vw[i] = vw;
      w.vv[i] = vv;
    }
    if constexpr (p >= 0) {
      apply(w.aw[p], w.av[p], aw, av);
    } else if constexpr (G) {
      av = comb(c0, c1, c2, g0);
    }
    if constexpr (A) aw = _mm256_add_pd(aw, axis<K>(double(qdd[i])));
    if constexpr (Vel) {
      // + v × S q̇ = [ω × e_K; v × e_K] q̇
      const V sq = _mm256_mul_pd(sign<K>(), bcast(double(qd[i])));
      aw = _mm256_fmadd_pd(swap_other<K>(vw), sq, aw);
      av = _mm256_fmadd_pd(swap_other<K>(vv), sq, av);
    }
    w.aw[i] = aw;
    w.av[i] = av;

    // f = I a + v ×* (I v), I m = [Ī ω + h × v; m v − h × ω]
    const Inertia<double>& In = model.inertia(i);
    const V h = load4(In.h.data());
    const double* J = In.I.data();
    const V j0 = load4(J), j1 = load4(J + 3), j2 = load3(J + 6);
    const V m = bcast(In.m);
    auto inertia_times = [&](V mw, V mv, V& on, V& of) {
      on = _mm256_add_pd(comb(j0, j1, j2, mw), cross(h, mv));
      of = _mm256_fmsub_pd(m, mv, cross(h, mw));
    };
    V fn, ff;
    inertia_times(aw, av, fn, ff);
    if constexpr (Vel) {
      V pn, pf;
      inertia_times(vw, vv, pn, pf);
      // v ×* p = [ω × n + v × f; ω × f]
      fn = _mm256_add_pd(fn, _mm256_add_pd(cross(vw, pn), cross(vv, pf)));
      ff = _mm256_add_pd(ff, cross(vw, pf));
    }
    w.fn[i] = fn;
    w.ff[i] = ff;
    const auto k = static_cast<std::size_t>(i);
    if constexpr (Vel) {
      store4(data.v[k].w.data(), vw);
      store3(data.v[k].v.data(), vv);
    }
    store4(data.a[k].w.data(), aw);
    store3(data.a[k].v.data(), av);
  };

  auto backward = [&](auto I) SPATIAL_LAMBDA_INLINE {
    constexpr int i = NB - 1 - decltype(I)::value;
    constexpr int p = T::parent[i];
    constexpr int K = revolute_axis(T::joint[i]);
    const V fn = w.fn[i], ff = w.ff[i];
    const auto k = static_cast<std::size_t>(i);
    store4(data.f[k].n.data(), fn);
    store3(data.f[k].f.data(), ff);
    tau[i] = get<K>(fn);
    if constexpr (p >= 0) {
      // ⁱX_λᵀ f = [Eᵀ n + r × Eᵀ f; Eᵀ f]
      const V r = load3(model.tree_transform(i).r.data());
      const V lin = comb(w.row[i][0], w.row[i][1], w.row[i][2], ff);
      const V ang = _mm256_add_pd(comb(w.row[i][0], w.row[i][1], w.row[i][2], fn), cross(r, lin));
      w.fn[p] = _mm256_add_pd(w.fn[p], ang);
      w.ff[p] = _mm256_add_pd(w.ff[p], lin);
    }
  };

  for_each_index(forward, std::make_integer_sequence<int, NB>{});
  for_each_index(backward, std::make_integer_sequence<int, NB>{});
}

}  // namespace simd
#endif  // SPATIAL_SIMD_AVX2

}  // namespace spatial::detail
