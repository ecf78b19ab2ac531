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

/// True when RNEA (without external forces) and CRBA take the AVX2 path on a Model<S, T> (see the file comment).
template <class S, class T>
constexpr bool simd_enabled() {
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
/// x₀ + x₁ + x₂ + x₃
SPATIAL_INLINE double hsum(V x) {
  const __m128d t = _mm_add_pd(_mm256_castpd256_pd128(x), _mm256_extractf128_pd(x, 1));
  return _mm_cvtsd_f64(_mm_add_sd(t, _mm_unpackhi_pd(t, t)));
}
/// s e_L (s in lane L, 0 elsewhere) from a register holding a finite s in every lane. A product with e_L rather
/// than a blend or mask: for L = 0 compilers turn those into a form of vmovq that valgrind cannot decode.
template <int L>
SPATIAL_INLINE V only(V s) {
  return _mm256_mul_pd(s, _mm256_set_pd(L == 3 ? 1.0 : 0.0, L == 2 ? 1.0 : 0.0, L == 1 ? 1.0 : 0.0, L == 0 ? 1.0 : 0.0));
}
/// x with lane L set to 0.
template <int L>
SPATIAL_INLINE V clear(V x) {
  return _mm256_and_pd(x, _mm256_castsi256_pd(_mm256_set_epi64x(L == 3 ? 0 : -1, L == 2 ? 0 : -1, L == 1 ? 0 : -1,
                                                                 L == 0 ? 0 : -1)));
}
/// Three doubles from p, fourth lane 0 (p[3] must be readable; it is read and discarded).
SPATIAL_INLINE V load3z(const double* p) { return clear<3>(_mm256_loadu_pd(p)); }
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
/// comb without the term of index K (c_K or x_K known to be zero).
template <int K>
SPATIAL_INLINE V comb_skip(V c0, V c1, V c2, V x) {
  if constexpr (K == 0) return _mm256_fmadd_pd(c2, lane<2>(x), _mm256_mul_pd(c1, lane<1>(x)));
  else if constexpr (K == 1) return _mm256_fmadd_pd(c2, lane<2>(x), _mm256_mul_pd(c0, lane<0>(x)));
  else return _mm256_fmadd_pd(c1, lane<1>(x), _mm256_mul_pd(c0, lane<0>(x)));
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
/// e_K s (s in lane K, 0 elsewhere for finite s). A product with e_K: inserting s into a zero register makes some
/// compilers emit a form of vmovq that valgrind cannot decode.
template <int K>
SPATIAL_INLINE V axis(double s) {
  return _mm256_mul_pd(bcast(s), _mm256_set_pd(0.0, K == 2 ? 1.0 : 0.0, K == 1 ? 1.0 : 0.0, K == 0 ? 1.0 : 0.0));
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

/// ⁱX_λ = X_J(q) X_T for a revolute joint about axis K, from c = cos q and s = sin q: the columns c0, c1, c2 of E
/// (fourth lanes 0) and r (= r_T). Each column x of E_T turns into x ∘ (c in the two other lanes, 1 in lane K)
/// + swap(x) ∘ sign s.
template <int K>
SPATIAL_INLINE void compose(const Transform<double>& XT, double c, double s, V& c0, V& c1, V& c2, V& r) {
  const double* e = XT.E.data();
  const V cvec = _mm256_fmadd_pd(bcast(c), other<K>(), axis<K>(1.0));
  const V svec = _mm256_mul_pd(bcast(s), sign<K>());
  const V t0 = load4(e), t1 = load4(e + 3), t2 = load4(e + 6);
  c0 = _mm256_fmadd_pd(swap_other<K>(t0), svec, _mm256_mul_pd(t0, cvec));
  c1 = _mm256_fmadd_pd(swap_other<K>(t1), svec, _mm256_mul_pd(t1, cvec));
  c2 = _mm256_fmadd_pd(swap_other<K>(t2), svec, _mm256_mul_pd(t2, cvec));
  r = load3(XT.r.data());
}
/// Writes a transform given by the columns of E and r.
SPATIAL_INLINE void store_transform(Transform<double>& X, V c0, V c1, V c2, V r) {
  double* x = X.E.data();
  store4(x, c0);
  store4(x + 3, c1);
  store4(x + 6, c2);
  store3(x + 9, r);
}

/// ⁱX_λ of body i (compose<K>) into `data.X_up[i]`, and E by columns and by rows.
template <int K, class M, class D>
SPATIAL_INLINE void joint_transform(const M& model, D& data, int i, V col[3], V row[3], V& r) {
  compose<K>(model.tree_transform(i), data.cos_q[i], data.sin_q[i], col[0], col[1], col[2], r);
  store_transform(data.X_up[static_cast<std::size_t>(i)], col[0], col[1], col[2], r);
  transpose(col[0], col[1], col[2], row[0], row[1], row[2]);
}
/// X m = [E ω; E (v − r × ω)], E by columns.
SPATIAL_INLINE void apply_motion(const V col[3], V r, V mw, V mv, V& ow, V& ov) {
  ow = comb(col[0], col[1], col[2], mw);
  ov = comb(col[0], col[1], col[2], _mm256_sub_pd(mv, cross(r, mw)));
}
/// Xᵀ f = [Eᵀ n + r × Eᵀ f; Eᵀ f], E by rows.
SPATIAL_INLINE void apply_force_inverse(const V row[3], V r, V fn, V ff, V& on, V& of) {
  of = comb(row[0], row[1], row[2], ff);
  on = _mm256_add_pd(comb(row[0], row[1], row[2], fn), cross(r, of));
}

/// Keeps a per-body workspace in memory. Without this clang promotes every element of the (small, constant-indexed)
/// array to a register value for the whole call and then spills: in ABA on stance21, ~2 800 spill and reload
/// instructions and 10 % more time; with it, ~100. (An empty asm statement that may read and write the array.)
SPATIAL_INLINE void keep_in_memory(void* p) { __asm__ __volatile__("" : : "r"(p) : "memory"); }

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
template <unsigned Terms, class S, class T, class Q, class QD, class QDD, class Out, class Root>
void rnea(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
          const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<QDD>& qdd, Out& tau, const Root& root) {
  constexpr bool G = (Terms & 1u) != 0;
  constexpr bool Vel = (Terms & 2u) != 0;
  constexpr bool A = (Terms & 4u) != 0;
  constexpr bool R = Root::floating;  // a moving root (floating base): its v and a start the recursion
  constexpr int NB = T::size;
  static_assert(sizeof(Transform<double>) == 12 * sizeof(double) && sizeof(Motion<double>) == 6 * sizeof(double) &&
                    sizeof(Force<double>) == 6 * sizeof(double) && sizeof(Inertia<double>) == 13 * sizeof(double),
                "the AVX2 kernels assume unpadded spatial types");
  sincos_all<S>(q, data.cos_q, data.sin_q, NB);
  RneaWork<NB> w;
  keep_in_memory(&w);
  const V g0 = _mm256_sub_pd(zero(), load3(model.gravity().data()));  // a₀ = −a_g = [0; −g]
  V rvw = zero(), rvv = zero(), raw = zero(), rav = zero(), rfn = zero(), rff = zero();
  if constexpr (R) {
    rvw = load3(root.v.w.data()), rvv = load3(root.v.v.data());
    raw = load3(root.a.w.data()), rav = load3(root.a.v.data());
  }

  auto forward = [&](auto I) SPATIAL_LAMBDA_INLINE {
    constexpr int i = decltype(I)::value;
    constexpr int p = T::parent[i];
    constexpr int K = revolute_axis(T::joint[i]);
    V col[3], r;
    joint_transform<K>(model, data, i, col, w.row[i], r);

    V vw = zero(), vv = zero(), aw = zero(), av = zero();
    if constexpr (Vel) {
      if constexpr (p >= 0) apply_motion(col, r, w.vw[p], w.vv[p], vw, vv);
      else if constexpr (R) apply_motion(col, r, rvw, rvv, vw, vv);
      vw = _mm256_add_pd(vw, axis<K>(double(qd[i])));
      w.vw[i] = vw;
      w.vv[i] = vv;
    }
    if constexpr (p >= 0) {
      apply_motion(col, r, w.aw[p], w.av[p], aw, av);
    } else if constexpr (R) {
      apply_motion(col, r, raw, rav, aw, av);
    } else if constexpr (G) {
      av = comb(col[0], col[1], col[2], g0);
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
      V ang, lin;
      apply_force_inverse(w.row[i], load3(model.tree_transform(i).r.data()), fn, ff, ang, lin);
      w.fn[p] = _mm256_add_pd(w.fn[p], ang);
      w.ff[p] = _mm256_add_pd(w.ff[p], lin);
    } else if constexpr (R) {
      V ang, lin;
      apply_force_inverse(w.row[i], load3(model.tree_transform(i).r.data()), fn, ff, ang, lin);
      rfn = _mm256_add_pd(rfn, ang);
      rff = _mm256_add_pd(rff, lin);
    }
  };

  for_each_index(forward, std::make_integer_sequence<int, NB>{});
  for_each_index(backward, std::make_integer_sequence<int, NB>{});
  if constexpr (R) {
    Force<double> add;
    store4(add.n.data(), rfn);
    store3(add.f.data(), rff);
    *root.f += add;
  } else {
    (void)root;
  }
}


/// Calls f(P) for every proper ancestor P of body J (compile-time indices).
template <class T, int J, class F>
SPATIAL_INLINE void for_each_ancestor(F& f) {
  constexpr int P = T::parent[J];
  if constexpr (P >= 0) {
    f(std::integral_constant<int, P>{});
    for_each_ancestor<T, P>(f);
  }
}

/// crba_impl's AVX2 path: the same three passes and the same outputs in `data` (X_up, X_base, S_base, Ic, H). The
/// transforms ⁱX_λ are composed again from data.cos_q and data.sin_q rather than read back from data.X_up: reading
/// a 4-lane value that two stores wrote moments ago stalls until they retire, which costs more than the rotation.
template <class S, class T, class Sink>
void crba(const Model<S, T>& model, Data<S, T>& data, Sink& sink) {
  constexpr int NB = T::size;
  constexpr bool Out = std::decay_t<Sink>::active;
  struct Body {
    V ucol[3], urow[3], ur;  // ⁱX_λ: columns and rows of E, r
    V col[3], row[3], r;     // ⁱX_0
    V sw, sv;                // Sᵢ in base coordinates
    V ih, ic[3];             // composite inertia: h and the columns of Ī
    double im;               // and m
  };
  Body b[NB];
  keep_in_memory(b);

  auto forward = [&](auto I) SPATIAL_LAMBDA_INLINE {
    constexpr int i = decltype(I)::value;
    constexpr int p = T::parent[i];
    constexpr int K = revolute_axis(T::joint[i]);
    const auto k = static_cast<std::size_t>(i);
    Body& B = b[i];
    joint_transform<K>(model, data, i, B.ucol, B.urow, B.ur);
    // ⁱX_0 = ⁱX_λ ᵏX_0: E = E_up E_λ (column by column), r = r_λ + E_λᵀ r_up.
    if constexpr (p >= 0) {
      const Body& P = b[p];
      for (int c = 0; c < 3; ++c) B.col[c] = comb(B.ucol[0], B.ucol[1], B.ucol[2], P.col[c]);
      B.r = _mm256_add_pd(P.r, comb(P.row[0], P.row[1], P.row[2], B.ur));
      transpose(B.col[0], B.col[1], B.col[2], B.row[0], B.row[1], B.row[2]);
    } else {
      for (int c = 0; c < 3; ++c) B.col[c] = B.ucol[c], B.row[c] = B.urow[c];
      B.r = B.ur;
    }
    store_transform(data.X_base[k], B.col[0], B.col[1], B.col[2], B.r);
    // S⁰ = X⁻¹ [e_K; 0] = [Eᵀ e_K; r × Eᵀ e_K] (Eᵀ e_K: row K of E).
    B.sw = B.row[K];
    B.sv = cross(B.r, B.sw);
    store4(data.S_base[k].w.data(), B.sw);
    store3(data.S_base[k].v.data(), B.sv);
    const Inertia<double>& In = model.inertia(i);
    B.im = In.m;
    B.ih = load3z(In.h.data());
    B.ic[0] = load3z(In.I.data());
    B.ic[1] = load3z(In.I.data() + 3);
    B.ic[2] = load3(In.I.data() + 6);
  };

  auto backward = [&](auto I) SPATIAL_LAMBDA_INLINE {
    constexpr int i = NB - 1 - decltype(I)::value;
    constexpr int p = T::parent[i];
    const auto k = static_cast<std::size_t>(i);
    const Body& B = b[i];
    // Iᶜᵢ is complete: write it out.
    Inertia<double>& out = data.Ic[k];
    out.m = B.im;
    store4(out.h.data(), B.ih);
    store4(out.I.data(), B.ic[0]);
    store4(out.I.data() + 3, B.ic[1]);
    store3(out.I.data() + 6, B.ic[2]);
    if constexpr (p >= 0) {
      // ⁱX_λᵀ Iᶜ ⁱX_λ (Inertia::transformed_inverse): h′ = Eᵀ h, Ī′ = Eᵀ Ī E, g = h′ + (m/2) r,
      // Ī = Ī′ − (r gᵀ + g rᵀ) + 2 (g·r) 1, h = h′ + m r.
      const V hp = comb(B.urow[0], B.urow[1], B.urow[2], B.ih);
      const V g = _mm256_fmadd_pd(bcast(0.5 * B.im), B.ur, hp);
      const V d = bcast(2.0 * hsum(_mm256_mul_pd(g, B.ur)));
      Body& P = b[p];
      auto column = [&](auto C) SPATIAL_LAMBDA_INLINE {
        constexpr int c = decltype(C)::value;
        const V ie = comb(B.ic[0], B.ic[1], B.ic[2], B.ucol[c]);  // column c of Ī E
        V col = comb(B.urow[0], B.urow[1], B.urow[2], ie);         // of Eᵀ Ī E
        col = _mm256_fnmadd_pd(B.ur, lane<c>(g), _mm256_fnmadd_pd(g, lane<c>(B.ur), col));
        P.ic[c] = _mm256_add_pd(P.ic[c], _mm256_add_pd(col, only<c>(d)));
      };
      column(std::integral_constant<int, 0>{});
      column(std::integral_constant<int, 1>{});
      column(std::integral_constant<int, 2>{});
      P.ih = _mm256_add_pd(P.ih, _mm256_fmadd_pd(bcast(B.im), B.ur, hp));
      P.im += B.im;
    }
  };

  auto entries = [&](auto I) SPATIAL_LAMBDA_INLINE {
    constexpr int i = decltype(I)::value;
    constexpr int K = revolute_axis(T::joint[i]);
    const Body& B = b[i];
    // F = Iᶜ S = [Ī e_K; e_K × h]; Hᵢᵢ = Sᵀ F = Ī_KK.
    const V fn = B.ic[K];
    const V ff = _mm256_mul_pd(swap_other<K>(B.ih), _mm256_sub_pd(zero(), sign<K>()));
    if constexpr (Out) sink.entry(i, i, get<K>(fn));
    else data.H(i, i) = get<K>(fn);
    if constexpr (T::parent[i] >= 0 || Out) {
      // F⁰ = ⁱX_0ᵀ F = [Eᵀ n + r × Eᵀ f; Eᵀ f]; H_ij = S⁰ⱼ · F⁰ for every ancestor j.
      V n0, f0;
      apply_force_inverse(B.row, B.r, fn, ff, n0, f0);
      if constexpr (Out) {
        Force<double> F0;
        store4(F0.n.data(), n0);
        store3(F0.f.data(), f0);
        sink(i, F0);
      }
      auto entry = [&](auto J) SPATIAL_LAMBDA_INLINE {
        constexpr int j = decltype(J)::value;
        const double hij = hsum(_mm256_fmadd_pd(b[j].sw, n0, _mm256_mul_pd(b[j].sv, f0)));
        if constexpr (Out) {
          sink.entry(i, j, hij);
        } else {
          data.H(i, j) = hij;
          data.H(j, i) = hij;
        }
      };
      for_each_ancestor<T, i>(entry);
    }
  };

  for_each_index(forward, std::make_integer_sequence<int, NB>{});
  for_each_index(backward, std::make_integer_sequence<int, NB>{});
  for_each_index(entries, std::make_integer_sequence<int, NB>{});
}

/// Writes a motion or force vector from its two 3-vectors.
SPATIAL_INLINE void store_pair(double* p, V x, V y) {
  store4(p, x);
  store3(p + 3, y);
}

/// aba_impl's AVX2 path (no external forces): the same three passes and the same outputs in `data` (X_up, v, c,
/// IA, pA, U, Dinv, u, a, qdd). The articulated inertia [A B; Bᵀ C] is kept as the columns of A, B and C; the
/// rows of B (for U = Iᴬ S = [A e_K; Bᵀ e_K] and Bᵀ c) by one transpose per body.
template <bool G, bool Vel, class S, class T, class Q, class QD, class Tau, class Root>
void aba(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
         const Eigen::MatrixBase<Tau>& tau, const Root& root) {
  constexpr int NB = T::size;
  constexpr bool R = Root::floating;  // a moving root: pass 1 from its velocity, pass 2 into it, pass 3 from solve()
  static_assert(sizeof(ArticulatedInertia<double>) == 27 * sizeof(double), "unpadded articulated inertia");
  struct Body {
    V col[3], row[3], r;  // ⁱX_λ: columns and rows of E, r
    V vw, vv, cw, cv;     // velocity and c = v × S q̇
    V pn, pf;             // bias force pᴬ (children added in pass 2)
    V A[3], B[3], C[3];   // articulated inertia, by columns (children added in pass 2)
    V un, uf;             // U = Iᴬ S
    double dinv, u;
    V aw, av;             // acceleration
  };
  Body b[NB];
  keep_in_memory(b);
  sincos_all<S>(q, data.cos_q, data.sin_q, NB);
  (void)qd;
  Body rootb;  // the moving root: what its children pass to it in pass 2 (floating base only)
  V rvw = zero(), rvv = zero();
  if constexpr (R) {
    for (int j = 0; j < 3; ++j) rootb.A[j] = rootb.B[j] = rootb.C[j] = zero();
    rootb.pn = rootb.pf = zero();
    rvw = load3(root.v.w.data()), rvv = load3(root.v.v.data());
  }

  auto pass1 = [&](auto I) SPATIAL_LAMBDA_INLINE {
    constexpr int i = decltype(I)::value;
    constexpr int p = T::parent[i];
    constexpr int K = revolute_axis(T::joint[i]);
    const auto k = static_cast<std::size_t>(i);
    Body& B = b[i];
    joint_transform<K>(model, data, i, B.col, B.row, B.r);
    const Inertia<double>& In = model.inertia(i);
    const V h = load3z(In.h.data());
    B.A[0] = load3z(In.I.data());
    B.A[1] = load3z(In.I.data() + 3);
    B.A[2] = load3(In.I.data() + 6);
    // B = h̃: column j is h × e_j.  C = m 1.
    B.B[0] = _mm256_mul_pd(swap_other<0>(h), sign<0>());
    B.B[1] = _mm256_mul_pd(swap_other<1>(h), sign<1>());
    B.B[2] = _mm256_mul_pd(swap_other<2>(h), sign<2>());
    const V m = bcast(In.m);
    B.C[0] = only<0>(m);
    B.C[1] = only<1>(m);
    B.C[2] = only<2>(m);
    if constexpr (Vel) {
      V vw = zero(), vv = zero();
      if constexpr (p >= 0) {
        const Body& P = b[p];
        apply_motion(B.col, B.r, P.vw, P.vv, vw, vv);
      } else if constexpr (R) {
        apply_motion(B.col, B.r, rvw, rvv, vw, vv);
      }
      const double qdi = double(qd[i]);
      vw = _mm256_add_pd(vw, axis<K>(qdi));
      const V sq = _mm256_mul_pd(sign<K>(), bcast(qdi));
      B.vw = vw;
      B.vv = vv;
      B.cw = _mm256_mul_pd(swap_other<K>(vw), sq);
      B.cv = _mm256_mul_pd(swap_other<K>(vv), sq);
      // pᴬ = v ×* I v, I v = [Ī ω + h × v; m v − h × ω]
      const V in = _mm256_add_pd(comb(B.A[0], B.A[1], B.A[2], vw), cross(h, vv));
      const V jf = _mm256_fmsub_pd(m, vv, cross(h, vw));
      B.pn = _mm256_add_pd(cross(vw, in), cross(vv, jf));
      B.pf = cross(vw, jf);
      store_pair(data.v[k].w.data(), vw, vv);
      store_pair(data.c[k].w.data(), B.cw, B.cv);
    } else {
      B.pn = zero();
      B.pf = zero();
    }
  };

  auto pass2 = [&](auto I) SPATIAL_LAMBDA_INLINE {
    constexpr int i = NB - 1 - decltype(I)::value;
    constexpr int p = T::parent[i];
    constexpr int K = revolute_axis(T::joint[i]);
    const auto k = static_cast<std::size_t>(i);
    Body& B = b[i];
    // Iᴬ and pᴬ of body i are complete.
    double* ia = data.IA[k].A.data();
    store4(ia, B.A[0]);
    store4(ia + 3, B.A[1]);
    store4(ia + 6, B.A[2]);
    store4(ia + 9, B.B[0]);
    store4(ia + 12, B.B[1]);
    store4(ia + 15, B.B[2]);
    store4(ia + 18, B.C[0]);
    store4(ia + 21, B.C[1]);
    store3(ia + 24, B.C[2]);
    store_pair(data.pA[k].n.data(), B.pn, B.pf);
    V br0, br1, br2;  // rows of B
    transpose(B.B[0], B.B[1], B.B[2], br0, br1, br2);
    const V brow[3] = {br0, br1, br2};
    B.un = B.A[K];
    B.uf = brow[K];
    B.dinv = 1.0 / get<K>(B.un);
    B.u = double(tau[i]) - get<K>(B.pn);
    store_pair(data.U[k].n.data(), B.un, B.uf);
    data.Dinv[k] = B.dinv;
    data.u[k] = B.u;
    if constexpr (p >= 0 || R) {
      // Iᵃ = Iᴬ − U Uᵀ / D
      const V d = bcast(B.dinv);
      const V wn = _mm256_mul_pd(B.un, d), wf = _mm256_mul_pd(B.uf, d);
      V a[3] = {B.A[0], B.A[1], B.A[2]}, bc[3] = {B.B[0], B.B[1], B.B[2]}, c[3] = {B.C[0], B.C[1], B.C[2]};
      V br[3] = {br0, br1, br2};
      auto rank1 = [&](auto J) SPATIAL_LAMBDA_INLINE {
        constexpr int j = decltype(J)::value;
        a[j] = _mm256_fnmadd_pd(B.un, lane<j>(wn), a[j]);
        bc[j] = _mm256_fnmadd_pd(B.un, lane<j>(wf), bc[j]);
        c[j] = _mm256_fnmadd_pd(B.uf, lane<j>(wf), c[j]);
        br[j] = _mm256_fnmadd_pd(B.uf, lane<j>(wn), br[j]);
      };
      rank1(std::integral_constant<int, 0>{});
      rank1(std::integral_constant<int, 1>{});
      rank1(std::integral_constant<int, 2>{});
      // Iᵃ maps e_K to zero: row and column K of A and row K of B are exactly zero, not round-off (as in
      // ArticulatedInertia::subtract_outer<K>; the round-off would otherwise reach the parent and cost digits).
      a[K] = zero();
      br[K] = zero();
      for (int j = 0; j < 3; ++j) {
        a[j] = clear<K>(a[j]);
        bc[j] = clear<K>(bc[j]);
      }
      // pᵃ = pᴬ + Iᵃ c + U u / D
      const V ud = bcast(B.u * B.dinv);
      V pan = _mm256_fmadd_pd(B.un, ud, B.pn);
      V paf = _mm256_fmadd_pd(B.uf, ud, B.pf);
      if constexpr (Vel) {
        // c = v × S q̇ has no component K in either half (ArticulatedInertia::mul_null<K>).
        pan = _mm256_add_pd(pan, _mm256_add_pd(comb_skip<K>(a[0], a[1], a[2], B.cw), comb_skip<K>(bc[0], bc[1], bc[2], B.cv)));
        paf = _mm256_add_pd(paf, _mm256_add_pd(comb_skip<K>(br[0], br[1], br[2], B.cw), comb_skip<K>(c[0], c[1], c[2], B.cv)));
      }
      // Xᵀ Iᵃ X (ArticulatedInertia::transformed_inverse): a = Eᵀ A E, b = Eᵀ B E, c = Eᵀ C E;
      // B′ = b + r̃ c, A′ = a − B′ r̃ + r̃ bᵀ, C′ = c.
      Body& P = [&]() -> Body& {
        if constexpr (p >= 0) return b[p];
        else return rootb;
      }();
      V rb[3], rbp[3];
      auto rotate = [&](auto J) SPATIAL_LAMBDA_INLINE {
        constexpr int j = decltype(J)::value;
        const V e = B.col[j];
        // A e and B e have no component K (column K of A, row K of A and B are zero).
        const V aj = comb_skip<K>(B.row[0], B.row[1], B.row[2], comb_skip<K>(a[0], a[1], a[2], e));
        rb[j] = comb_skip<K>(B.row[0], B.row[1], B.row[2], comb(bc[0], bc[1], bc[2], e));
        const V cj = comb(B.row[0], B.row[1], B.row[2], comb(c[0], c[1], c[2], e));
        rbp[j] = _mm256_add_pd(rb[j], cross(B.r, cj));
        P.A[j] = _mm256_add_pd(P.A[j], aj);
        P.B[j] = _mm256_add_pd(P.B[j], rbp[j]);
        P.C[j] = _mm256_add_pd(P.C[j], cj);
      };
      rotate(std::integral_constant<int, 0>{});
      rotate(std::integral_constant<int, 1>{});
      rotate(std::integral_constant<int, 2>{});
      V bt0, bt1, bt2;  // rows of b
      transpose(rb[0], rb[1], rb[2], bt0, bt1, bt2);
      const V r0 = lane<0>(B.r), r1 = lane<1>(B.r), r2 = lane<2>(B.r);
      // −B′ r̃ by columns: −(r₂ B′₁ − r₁ B′₂), −(r₀ B′₂ − r₂ B′₀), −(r₁ B′₀ − r₀ B′₁); + r × (row j of b).
      P.A[0] = _mm256_add_pd(P.A[0], _mm256_sub_pd(cross(B.r, bt0), _mm256_fmsub_pd(r2, rbp[1], _mm256_mul_pd(r1, rbp[2]))));
      P.A[1] = _mm256_add_pd(P.A[1], _mm256_sub_pd(cross(B.r, bt1), _mm256_fmsub_pd(r0, rbp[2], _mm256_mul_pd(r2, rbp[0]))));
      P.A[2] = _mm256_add_pd(P.A[2], _mm256_sub_pd(cross(B.r, bt2), _mm256_fmsub_pd(r1, rbp[0], _mm256_mul_pd(r0, rbp[1]))));
      // pᴬ_λ += ⁱX_λᵀ pᵃ = [Eᵀ n + r × Eᵀ f; Eᵀ f]
      V ang, lin;
      apply_force_inverse(B.row, B.r, pan, paf, ang, lin);
      P.pn = _mm256_add_pd(P.pn, ang);
      P.pf = _mm256_add_pd(P.pf, lin);
    }
  };

  const V g0 = _mm256_sub_pd(zero(), load3(model.gravity().data()));
  V raw = zero(), rav = zero();
  auto pass3 = [&](auto I) SPATIAL_LAMBDA_INLINE {
    constexpr int i = decltype(I)::value;
    constexpr int p = T::parent[i];
    constexpr int K = revolute_axis(T::joint[i]);
    const auto k = static_cast<std::size_t>(i);
    Body& B = b[i];
    V aw = zero(), av = zero();
    if constexpr (p >= 0) {
      const Body& P = b[p];
      apply_motion(B.col, B.r, P.aw, P.av, aw, av);
    } else if constexpr (R) {
      apply_motion(B.col, B.r, raw, rav, aw, av);
    } else if constexpr (G) {
      av = comb(B.col[0], B.col[1], B.col[2], g0);
    }
    if constexpr (Vel) {
      aw = _mm256_add_pd(aw, B.cw);
      av = _mm256_add_pd(av, B.cv);
    }
    const double qddi = (B.u - hsum(_mm256_fmadd_pd(B.un, aw, _mm256_mul_pd(B.uf, av)))) * B.dinv;
    data.qdd[i] = qddi;
    aw = _mm256_add_pd(aw, axis<K>(qddi));
    B.aw = aw;
    B.av = av;
    store_pair(data.a[k].w.data(), aw, av);
  };

  for_each_index(pass1, std::make_integer_sequence<int, NB>{});
  for_each_index(pass2, std::make_integer_sequence<int, NB>{});
  if constexpr (R) {
    // The root's articulated inertia and bias force are complete: add them in, solve for its acceleration.
    ArticulatedInertia<double> IA;
    double* ia = IA.A.data();
    store4(ia, rootb.A[0]);
    store4(ia + 3, rootb.A[1]);
    store4(ia + 6, rootb.A[2]);
    store4(ia + 9, rootb.B[0]);
    store4(ia + 12, rootb.B[1]);
    store4(ia + 15, rootb.B[2]);
    store4(ia + 18, rootb.C[0]);
    store4(ia + 21, rootb.C[1]);
    store3(ia + 24, rootb.C[2]);
    *root.IA += IA;
    Force<double> pA;
    store_pair(pA.n.data(), rootb.pn, rootb.pf);
    *root.pA += pA;
    const Motion<double> a0 = root.solve();
    raw = load3(a0.w.data());
    rav = load3(a0.v.data());
  } else {
    (void)root, (void)raw, (void)rav;
  }
  for_each_index(pass3, std::make_integer_sequence<int, NB>{});
}

}  // namespace simd
#endif  // SPATIAL_SIMD_AVX2

}  // namespace spatial::detail
