#pragma once
/// \file simd.hpp
/// AVX2 kernels for RNEA, CRBA (also without H: the columns of A_G, centroidal.hpp), ABA, forward kinematics and the
/// world Jacobian columns (and, in minv.hpp on the same helpers, passes 1 and 2 of H⁻¹), in double and float, on
/// compile-time trees (unrolled per body) and on run-time trees (a loop that switches once per body on the joint's
/// axis; per-body records in `Data::work`; the same operations in the same order, so the same results bit for bit).
/// The one-walk Jacobian kernel is in kinematics.hpp.
///
/// The scalar algorithms (algorithms.hpp) spend about one instruction per flop on 3-vector arithmetic. Here every
/// 3-vector lives in one register (lanes x, y, z and a spare fourth lane: four doubles in 256 bits, four floats in
/// 128, the same kernels over either register type), so that
///  - E x (E by columns) and Eᵀ x (E by rows) are three broadcasts and three fused multiply–adds,
///  - a × b is three lane permutations and two arithmetic instructions: a × b = yzx(a ∘ yzx(b) − yzx(a) ∘ b),
///  - the joint rotation X_J X_T about coordinate axis K is one lane swap and one multiply–add per column.
/// The fourth lane is never broadcast into the others, so whatever it holds cannot reach a result; values are
/// written back to `Data` with three-lane stores (or four-lane stores that a later store overwrites).
///
/// Used when the translation unit is compiled with AVX2 and FMA (`-mavx2 -mfma`, `-march=x86-64-v3`, `-march=native`
/// on such a machine), the scalar is double or float, every joint of the tree is revolute about a coordinate axis
/// (RevoluteX/Y/Z: all reference models, and the HOAP-3 URDF loaded at run time), and no external force is given.
/// Everything else takes the scalar path. Define SPATIAL_NO_SIMD to always take it. Results agree with the scalar path to rounding
/// (tests/simd_*.cpp: every term combination, every per-body output, double and float).

#include "spatial/algebra.hpp"
#include "spatial/joints.hpp"
#include "spatial/model.hpp"
#include "spatial/sincos.hpp"

#include <cstddef>
#include <new>
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

/// True when RNEA (without external forces) and CRBA take the AVX2 path on every Model<S, T> (compile-time trees of
/// RevoluteX/Y/Z joints; see the file comment).
template <class S, class T>
constexpr bool simd_enabled() {
  if constexpr (!SPATIAL_SIMD_AVX2 || !(std::is_same_v<S, double> || std::is_same_v<S, float>) ||
                !is_static_tree_v<T>) {
    return false;
  } else {
    return all_revolute_axis_aligned<T>(std::make_index_sequence<std::size_t(T::size)>{});
  }
}
/// True when the AVX2 path may serve a Model<S, T>: always when `simd_enabled`, and for a run-time tree in double
/// or float when `simd_applies` (checked per call: one pass over the joint types).
template <class S, class T>
constexpr bool simd_candidate() {
  return simd_enabled<S, T>() || (SPATIAL_SIMD_AVX2 && (std::is_same_v<S, double> || std::is_same_v<S, float>) &&
                                  !is_static_tree_v<T>);
}
template <class S, class T>
bool simd_applies(const Model<S, T>& model) {
  if constexpr (simd_enabled<S, T>()) return (void)model, true;
  else if constexpr (simd_candidate<S, T>()) return model.revolute_axes_only();
  else return (void)model, false;
}

/// Whether the lane routines that write 6-row columns in place (Jacobians, A_G) may take an output of Eigen type M:
/// double or float entries, column-major, contiguous columns; the caller still checks at run time that M has 6 rows
/// and a column stride of 6.
template <class M>
constexpr bool lane_columns() {
  using S = typename M::Scalar;
  constexpr int flags = int(M::Flags);
  return SPATIAL_SIMD_AVX2 && (std::is_same_v<S, double> || std::is_same_v<S, float>) &&
         (flags & Eigen::DirectAccessBit) && !(flags & Eigen::RowMajorBit) && int(M::InnerStrideAtCompileTime) == 1 &&
         (int(M::RowsAtCompileTime) == 6 || int(M::RowsAtCompileTime) == int(Eigen::Dynamic));
}
template <class M>
bool lane_columns(const Eigen::MatrixBase<M>& x) {
  if constexpr (lane_columns<M>()) return x.rows() == 6 && x.derived().outerStride() == 6;
  else return (void)x, false;
}

#if SPATIAL_SIMD_AVX2

namespace simd {

// One 3-vector per register: four doubles in a 256-bit register (Vd), or four floats in a 128-bit one (Vf, the same
// lane layout with the same instruction count: float runs these kernels at double's speed rather than taking the
// scalar path). Each helper below exists for both; the kernels are written once, over V = Vec<S>.
using Vd = __m256d;
using Vf = __m128;
template <class S>
struct VecOf;
template <>
struct VecOf<double> {
  using type = Vd;
};
template <>
struct VecOf<float> {
  using type = Vf;
};
template <class S>
using Vec = typename VecOf<S>::type;
// (The helpers that need the register type as a template argument test its size: naming __m256d or __m128 as an
// argument of a class template such as std::is_same makes g++ warn that their attributes are ignored.)

SPATIAL_INLINE Vd add(Vd a, Vd b) { return _mm256_add_pd(a, b); }
SPATIAL_INLINE Vf add(Vf a, Vf b) { return _mm_add_ps(a, b); }
SPATIAL_INLINE Vd sub(Vd a, Vd b) { return _mm256_sub_pd(a, b); }
SPATIAL_INLINE Vf sub(Vf a, Vf b) { return _mm_sub_ps(a, b); }
SPATIAL_INLINE Vd mul(Vd a, Vd b) { return _mm256_mul_pd(a, b); }
SPATIAL_INLINE Vf mul(Vf a, Vf b) { return _mm_mul_ps(a, b); }
SPATIAL_INLINE Vd div(Vd a, Vd b) { return _mm256_div_pd(a, b); }
SPATIAL_INLINE Vf div(Vf a, Vf b) { return _mm_div_ps(a, b); }
/// a b + c
SPATIAL_INLINE Vd fmadd(Vd a, Vd b, Vd c) { return _mm256_fmadd_pd(a, b, c); }
SPATIAL_INLINE Vf fmadd(Vf a, Vf b, Vf c) { return _mm_fmadd_ps(a, b, c); }
/// a b − c
SPATIAL_INLINE Vd fmsub(Vd a, Vd b, Vd c) { return _mm256_fmsub_pd(a, b, c); }
SPATIAL_INLINE Vf fmsub(Vf a, Vf b, Vf c) { return _mm_fmsub_ps(a, b, c); }
/// c − a b
SPATIAL_INLINE Vd fnmadd(Vd a, Vd b, Vd c) { return _mm256_fnmadd_pd(a, b, c); }
SPATIAL_INLINE Vf fnmadd(Vf a, Vf b, Vf c) { return _mm_fnmadd_ps(a, b, c); }

/// (l0, l1, l2, l3), lane 0 first.
template <class W>
SPATIAL_INLINE W set(double l0, double l1, double l2, double l3) {
  if constexpr (sizeof(W) == sizeof(Vd)) return _mm256_set_pd(l3, l2, l1, l0);
  else return _mm_set_ps(float(l3), float(l2), float(l1), float(l0));
}
template <class W>
SPATIAL_INLINE W zero() {
  if constexpr (sizeof(W) == sizeof(Vd)) return _mm256_setzero_pd();
  else return _mm_setzero_ps();
}
/// Four scalars from p (the fourth lane is whatever follows the 3-vector in memory; p[3] must be readable).
SPATIAL_INLINE Vd load4(const double* p) { return _mm256_loadu_pd(p); }
SPATIAL_INLINE Vf load4(const float* p) { return _mm_loadu_ps(p); }
/// Three scalars from p, fourth lane 0 (nothing beyond p[2] is read).
SPATIAL_INLINE Vd load3(const double* p) { return _mm256_maskload_pd(p, _mm256_set_epi64x(0, -1, -1, -1)); }
SPATIAL_INLINE Vf load3(const float* p) { return _mm_maskload_ps(p, _mm_set_epi32(0, -1, -1, -1)); }
/// Lanes 0..3 to p[0..3] (p[3] is overwritten: a later store must put it right).
SPATIAL_INLINE void store4(double* p, Vd x) { _mm256_storeu_pd(p, x); }
SPATIAL_INLINE void store4(float* p, Vf x) { _mm_storeu_ps(p, x); }
/// Lanes 0..2 to p[0..2].
SPATIAL_INLINE void store3(double* p, Vd x) {
  _mm_storeu_pd(p, _mm256_castpd256_pd128(x));
  _mm_store_sd(p + 2, _mm256_extractf128_pd(x, 1));
}
SPATIAL_INLINE void store3(float* p, Vf x) {
  _mm_storel_pi(reinterpret_cast<__m64*>(p), x);
  _mm_store_ss(p + 2, _mm_movehl_ps(x, x));
}
SPATIAL_INLINE Vd bcast(double s) { return _mm256_set1_pd(s); }
SPATIAL_INLINE Vf bcast(float s) { return _mm_set1_ps(s); }
/// Lane L of x in all four lanes.
template <int L>
SPATIAL_INLINE Vd lane(Vd x) {
  return _mm256_permute4x64_pd(x, L * 0x55);
}
template <int L>
SPATIAL_INLINE Vf lane(Vf x) {
  return _mm_permute_ps(x, L * 0x55);
}
template <int L>
SPATIAL_INLINE double get(Vd x) {
  if constexpr (L == 0) return _mm256_cvtsd_f64(x);
  else return _mm256_cvtsd_f64(_mm256_permute4x64_pd(x, L));
}
template <int L>
SPATIAL_INLINE float get(Vf x) {
  if constexpr (L == 0) return _mm_cvtss_f32(x);
  else return _mm_cvtss_f32(_mm_permute_ps(x, L));
}
/// (x₀ + x₂) + (x₁ + x₃)
SPATIAL_INLINE double hsum(Vd x) {
  const __m128d t = _mm_add_pd(_mm256_castpd256_pd128(x), _mm256_extractf128_pd(x, 1));
  return _mm_cvtsd_f64(_mm_add_sd(t, _mm_unpackhi_pd(t, t)));
}
SPATIAL_INLINE float hsum(Vf x) {
  const __m128 t = _mm_add_ps(x, _mm_movehl_ps(x, x));
  return _mm_cvtss_f32(_mm_add_ss(t, _mm_movehdup_ps(t)));
}
/// hsum(x) in all four lanes, with the same additions in the same order: (x₀ + x₂) + (x₁ + x₃).
SPATIAL_INLINE Vd hsum_all(Vd x) {
  const Vd t = _mm256_add_pd(x, _mm256_permute2f128_pd(x, x, 1));  // (x₀ + x₂, x₁ + x₃, x₂ + x₀, x₃ + x₁)
  return _mm256_add_pd(t, _mm256_permute_pd(t, 0b0101));
}
SPATIAL_INLINE Vf hsum_all(Vf x) {
  const Vf t = _mm_add_ps(x, _mm_permute_ps(x, 0b01001110));
  return _mm_add_ps(t, _mm_permute_ps(t, 0b10110001));
}
/// s e_L (s in lane L, 0 elsewhere) from a register holding a finite s in every lane. A product with e_L rather
/// than a blend or mask: for L = 0 compilers turn those into a form of vmovq that valgrind cannot decode.
template <int L, class W>
SPATIAL_INLINE W only(W s) {
  return mul(s, set<W>(L == 0, L == 1, L == 2, L == 3));
}
/// Lanes 0, 1, 2 of a and lane 3 of b.
SPATIAL_INLINE Vd low3_high1(Vd a, Vd b) { return _mm256_blend_pd(a, b, 0x8); }
SPATIAL_INLINE Vf low3_high1(Vf a, Vf b) { return _mm_blend_ps(a, b, 0x8); }
/// x with lane L set to 0.
template <int L>
SPATIAL_INLINE Vd clear(Vd x) {
  return _mm256_and_pd(x, _mm256_castsi256_pd(_mm256_set_epi64x(L == 3 ? 0 : -1, L == 2 ? 0 : -1, L == 1 ? 0 : -1,
                                                                 L == 0 ? 0 : -1)));
}
template <int L>
SPATIAL_INLINE Vf clear(Vf x) {
  return _mm_and_ps(x, _mm_castsi128_ps(_mm_set_epi32(L == 3 ? 0 : -1, L == 2 ? 0 : -1, L == 1 ? 0 : -1,
                                                      L == 0 ? 0 : -1)));
}
/// Three scalars from p, fourth lane 0 (p[3] must be readable; it is read and discarded).
template <class P>
SPATIAL_INLINE auto load3z(const P* p) {
  return clear<3>(load4(p));
}
/// (x₁, x₂, x₀, x₃)
SPATIAL_INLINE Vd yzx(Vd x) { return _mm256_permute4x64_pd(x, 0xC9); }
SPATIAL_INLINE Vf yzx(Vf x) { return _mm_permute_ps(x, 0xC9); }
/// a × b in lanes 0..2; lane 3 is 0 for finite inputs.
template <class W>
SPATIAL_INLINE W cross(W a, W b) {
  return yzx(fmsub(a, yzx(b), mul(yzx(a), b)));
}
/// c0 x₀ + c1 x₁ + c2 x₂: E x when c0, c1, c2 are the columns of E, Eᵀ x when they are its rows.
template <class W>
SPATIAL_INLINE W comb(W c0, W c1, W c2, W x) {
  return fmadd(c2, lane<2>(x), fmadd(c1, lane<1>(x), mul(c0, lane<0>(x))));
}
/// comb without the term of index K (c_K or x_K known to be zero).
template <int K, class W>
SPATIAL_INLINE W comb_skip(W c0, W c1, W c2, W x) {
  if constexpr (K == 0) return fmadd(c2, lane<2>(x), mul(c1, lane<1>(x)));
  else if constexpr (K == 1) return fmadd(c2, lane<2>(x), mul(c0, lane<0>(x)));
  else return fmadd(c1, lane<1>(x), mul(c0, lane<0>(x)));
}
/// x with lanes (K+1) % 3 and (K+2) % 3 exchanged.
template <int K>
SPATIAL_INLINE Vd swap_other(Vd x) {
  if constexpr (K == 2) return _mm256_permute_pd(x, 0x9);               // (x₁, x₀, x₂, x₃)
  else if constexpr (K == 0) return _mm256_permute4x64_pd(x, 0xD8);     // (x₀, x₂, x₁, x₃)
  else return _mm256_permute4x64_pd(x, 0xC6);                          // (x₂, x₁, x₀, x₃)
}
template <int K>
SPATIAL_INLINE Vf swap_other(Vf x) {
  return _mm_permute_ps(x, K == 2 ? 0xE1 : K == 0 ? 0xD8 : 0xC6);
}
/// (+1 in lane (K+1) % 3, −1 in lane (K+2) % 3, 0 elsewhere): swap_other<K>(a) ∘ sign<K>() s = a × e_K s.
template <int K, class W>
SPATIAL_INLINE W sign() {
  constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
  return set<W>(i == 0 ? 1.0 : j == 0 ? -1.0 : 0.0, i == 1 ? 1.0 : j == 1 ? -1.0 : 0.0,
                i == 2 ? 1.0 : j == 2 ? -1.0 : 0.0, 0.0);
}
/// 1 in lanes (K+1) % 3 and (K+2) % 3, 0 elsewhere.
template <int K, class W>
SPATIAL_INLINE W other() {
  return set<W>(K == 0 ? 0.0 : 1.0, K == 1 ? 0.0 : 1.0, K == 2 ? 0.0 : 1.0, 0.0);
}
/// e_K s (s in lane K, 0 elsewhere for finite s). A product with e_K: inserting s into a zero register makes some
/// compilers emit a form of vmovq that valgrind cannot decode.
template <int K, class S>
SPATIAL_INLINE Vec<S> axis(S s) {
  return mul(bcast(s), set<Vec<S>>(K == 0, K == 1, K == 2, 0.0));
}
/// Rows 0, 1, 2 of the 3×3 matrix with columns c0, c1, c2 (fourth lanes 0); the rows' fourth lanes are 0.
SPATIAL_INLINE void transpose(Vd c0, Vd c1, Vd c2, Vd& r0, Vd& r1, Vd& r2) {
  const Vd t0 = _mm256_unpacklo_pd(c0, c1);          // c0₀ c1₀ c0₂ c1₂
  const Vd t1 = _mm256_unpackhi_pd(c0, c1);          // c0₁ c1₁ c0₃ c1₃
  const Vd t2 = _mm256_unpacklo_pd(c2, zero<Vd>());  // c2₀ 0 c2₂ 0
  const Vd t3 = _mm256_unpackhi_pd(c2, zero<Vd>());  // c2₁ 0 c2₃ 0
  r0 = _mm256_permute2f128_pd(t0, t2, 0x20);
  r1 = _mm256_permute2f128_pd(t1, t3, 0x20);
  r2 = _mm256_permute2f128_pd(t0, t2, 0x31);
}
SPATIAL_INLINE void transpose(Vf c0, Vf c1, Vf c2, Vf& r0, Vf& r1, Vf& r2) {
  const Vf t0 = _mm_unpacklo_ps(c0, c1);          // c0₀ c1₀ c0₁ c1₁
  const Vf t1 = _mm_unpackhi_ps(c0, c1);          // c0₂ c1₂ c0₃ c1₃
  const Vf t2 = _mm_unpacklo_ps(c2, zero<Vf>());  // c2₀ 0 c2₁ 0
  const Vf t3 = _mm_unpackhi_ps(c2, zero<Vf>());  // c2₂ 0 c2₃ 0
  r0 = _mm_movelh_ps(t0, t2);
  r1 = _mm_movehl_ps(t2, t0);
  r2 = _mm_movelh_ps(t1, t3);
}

/// ⁱX_λ = X_J(q) X_T for a revolute joint about axis K, from c = cos q and s = sin q: the columns c0, c1, c2 of E
/// (fourth lanes 0) and r (= r_T). Each column x of E_T turns into x ∘ (c in the two other lanes, 1 in lane K)
/// + swap(x) ∘ sign s.
template <int K, class S>
SPATIAL_INLINE void compose(const Transform<S>& XT, S c, S s, Vec<S>& c0, Vec<S>& c1, Vec<S>& c2, Vec<S>& r) {
  using V = Vec<S>;
  const S* e = XT.E.data();
  const V cvec = fmadd(bcast(c), other<K, V>(), axis<K>(S(1)));
  const V svec = mul(bcast(s), sign<K, V>());
  const V t0 = load4(e), t1 = load4(e + 3), t2 = load4(e + 6);
  c0 = fmadd(swap_other<K>(t0), svec, mul(t0, cvec));
  c1 = fmadd(swap_other<K>(t1), svec, mul(t1, cvec));
  c2 = fmadd(swap_other<K>(t2), svec, mul(t2, cvec));
  r = load3(XT.r.data());
}
/// Writes a transform given by the columns of E and r.
template <class S>
SPATIAL_INLINE void store_transform(Transform<S>& X, Vec<S> c0, Vec<S> c1, Vec<S> c2, Vec<S> r) {
  S* x = X.E.data();
  store4(x, c0);
  store4(x + 3, c1);
  store4(x + 6, c2);
  store3(x + 9, r);
}
/// Writes a rigid-body inertia held in lanes: m, h, the columns of Ī (h and Ī are contiguous in an Inertia, so each
/// four-lane store's fourth lane is overwritten by the next store).
template <class S>
SPATIAL_INLINE void store_inertia(S m, Vec<S> h, const Vec<S> (&ic)[3], Inertia<S>& out) {
  out.m = m;
  store4(out.h.data(), h);
  store4(out.I.data(), ic[0]);
  store4(out.I.data() + 3, ic[1]);
  store3(out.I.data() + 6, ic[2]);
}

/// ⁱX_λ of body i (compose<K>) into `data.X_up[i]`, and E by columns and by rows.
template <int K, class M, class D, class V>
SPATIAL_INLINE void joint_transform(const M& model, D& data, int i, V col[3], V row[3], V& r) {
  compose<K>(model.tree_transform(i), data.cos_q[i], data.sin_q[i], col[0], col[1], col[2], r);
  store_transform(data.X_up[static_cast<std::size_t>(i)], col[0], col[1], col[2], r);
  transpose(col[0], col[1], col[2], row[0], row[1], row[2]);
}

/// The first pass shared by CRBA, forward kinematics and H⁻¹ (minv.hpp): ⁱX_λ of body i (joint_transform, into
/// `data.X_up[i]` and `up`), ⁱX_0 = ⁱX_λ ᵏX_0 from the parent's record b[p] (p < 0, a root: ⁱX_0 = ⁱX_λ) into
/// `B` = b[i] (col, row, r) and `data.X_base[i]`, and the joint's motion subspace in base coordinates,
/// S⁰ = X⁻¹ [e_K; 0] = [Eᵀ e_K; r × Eᵀ e_K] (Eᵀ e_K: row K of E), into `sw`, `sv` and `data.S_base[i]`.
/// Rec: a kernel's per-body record with members `Vec<S> col[3], row[3], r`; p as parent_of gives it (a constant on
/// a compile-time tree).
template <class S>
struct LocalTransform {
  Vec<S> col[3], row[3], r;  // ⁱX_λ: columns and rows of E, r
};
template <int K, class M, class D, class P, class Rec, class S>
SPATIAL_INLINE void base_transform(const M& model, D& data, int i, P p, const Rec* b, LocalTransform<S>& up, Rec& B,
                                   Vec<S>& sw, Vec<S>& sv) {
  const auto k = static_cast<std::size_t>(i);
  joint_transform<K>(model, data, i, up.col, up.row, up.r);
  if (p >= 0) {
    // E = E_up E_λ (column by column), r = r_λ + E_λᵀ r_up.
    const Rec& Pa = b[p];
    for (int c = 0; c < 3; ++c) B.col[c] = comb(up.col[0], up.col[1], up.col[2], Pa.col[c]);
    B.r = add(Pa.r, comb(Pa.row[0], Pa.row[1], Pa.row[2], up.r));
    transpose(B.col[0], B.col[1], B.col[2], B.row[0], B.row[1], B.row[2]);
  } else {
    for (int c = 0; c < 3; ++c) B.col[c] = up.col[c], B.row[c] = up.row[c];
    B.r = up.r;
  }
  // S⁰ in registers and stored from them: `sw` and `sv` may be fields of B, which the stores through double*
  // below may alias (the vector types may alias anything), so the compiler would otherwise store them and read them
  // back, and read back the upper half of a four-lane store (`store3`), which is slow to forward.
  const Vec<S> w = B.row[K];
  const Vec<S> v = cross(B.r, w);
  store_transform(data.X_base[k], B.col[0], B.col[1], B.col[2], B.r);
  store4(data.S_base[k].w.data(), w);
  store3(data.S_base[k].v.data(), v);
  sw = w;
  sv = v;
}

/// A rigid-body inertia (m, h, Ī by columns) moved by Xᵀ I X, X = (E, r) given by E's columns and rows
/// (Inertia::transformed_inverse): h′ = Eᵀ h, Ī′ = Eᵀ Ī E, g = h′ + (m/2) r, Ī = Ī′ − (r gᵀ + g rᵀ) + 2 (g·r) 1,
/// h = h′ + m r. CRBA's composite-inertia step (by ⁱX_λ) and H⁻¹'s base-frame inertias (by ⁱX_0, minv.hpp).
template <class S>
SPATIAL_INLINE void transformed_inertia(const Vec<S> (&col)[3], const Vec<S> (&row)[3], Vec<S> r, S m, Vec<S> h,
                                        const Vec<S> (&ic)[3], Vec<S>& h_out, Vec<S> (&ic_out)[3]) {
  using V = Vec<S>;
  const V hp = comb(row[0], row[1], row[2], h);
  const V g = fmadd(bcast(S(0.5) * m), r, hp);
  const V d = bcast(S(2) * hsum(mul(g, r)));
  auto column = [&](auto C) SPATIAL_LAMBDA_INLINE {
    constexpr int c = decltype(C)::value;
    const V ie = comb(ic[0], ic[1], ic[2], col[c]);  // column c of Ī E
    V x = comb(row[0], row[1], row[2], ie);           // of Eᵀ Ī E
    x = fnmadd(r, lane<c>(g), fnmadd(g, lane<c>(r), x));
    ic_out[c] = add(x, only<c>(d));
  };
  column(std::integral_constant<int, 0>{});
  column(std::integral_constant<int, 1>{});
  column(std::integral_constant<int, 2>{});
  h_out = fmadd(bcast(m), r, hp);
}
/// X m = [E ω; E (v − r × ω)], E by columns.
template <class V>
SPATIAL_INLINE void apply_motion(const V col[3], V r, V mw, V mv, V& ow, V& ov) {
  ow = comb(col[0], col[1], col[2], mw);
  ov = comb(col[0], col[1], col[2], sub(mv, cross(r, mw)));
}
/// Xᵀ f = [Eᵀ n + r × Eᵀ f; Eᵀ f], E by rows.
template <class V>
SPATIAL_INLINE void apply_force_inverse(const V row[3], V r, V fn, V ff, V& on, V& of) {
  of = comb(row[0], row[1], row[2], ff);
  on = add(comb(row[0], row[1], row[2], fn), cross(r, of));
}

/// I x = [Ī ω + h × u; m u − h × ω] for a rigid-body inertia (m in every lane, h, Ī by columns i0, i1, i2) and a
/// motion x = (ω, u).
template <class V>
SPATIAL_INLINE void inertia_times(V i0, V i1, V i2, V h, V m, V xw, V xv, V& n, V& f) {
  n = add(comb(i0, i1, i2, xw), cross(h, xv));
  f = fmsub(m, xv, cross(h, xw));
}
/// x ×* (fn, ff) = [ω × fn + u × ff; ω × ff] for a motion x = (ω, u).
template <class V>
SPATIAL_INLINE void cross_force(V xw, V xv, V fn, V ff, V& n, V& f) {
  n = add(cross(xw, fn), cross(xv, ff));
  f = cross(xw, ff);
}

/// Keeps a per-body workspace in memory. Without this clang promotes every element of the (small, constant-indexed)
/// array to a register value for the whole call and then spills: in ABA on stance21, ~2 800 spill and reload
/// instructions and 10 % more time; with it, ~100. (An empty asm statement that may read and write the array.)
SPATIAL_INLINE void keep_in_memory(void* p) { __asm__ __volatile__("" : : "r"(p) : "memory"); }

/// Calls f(P) for every proper ancestor P of body J (compile-time indices).
template <class T, int J, class F>
SPATIAL_INLINE void for_each_ancestor(F& f) {
  constexpr int P = T::parent[J];
  if constexpr (P >= 0) {
    f(std::integral_constant<int, P>{});
    for_each_ancestor<T, P>(f);
  }
}

template <class F, int... I>
SPATIAL_INLINE void for_each_index(F& f, std::integer_sequence<int, I...>) {
  (f(std::integral_constant<int, I>{}), ...);
}

// The body loops of the kernels. On a compile-time tree they are unrolled: f(i, K) gets body i and its joint's axis
// K as std::integral_constants, so every parent index, axis and array offset is a constant. On a run-time tree
// (RevoluteX/Y/Z joints only, `simd_applies`) they loop and switch once per body on the joint type to the code
// for that axis: the same sequence of branches on every call, which the branch predictor learns.
template <int K>
using AxisK = std::integral_constant<int, K>;
template <class S, class T, class F>
SPATIAL_INLINE void with_axis(const Model<S, T>& model, int i, F& f) {
  switch (model.joint_type(i)) {
    case JointType::RevoluteX: f(i, AxisK<0>{}); break;
    case JointType::RevoluteY: f(i, AxisK<1>{}); break;
    default: f(i, AxisK<2>{}); break;
  }
}
template <class T, class F, int... I>
SPATIAL_INLINE void unrolled(F& f, std::integer_sequence<int, I...>) {
  (f(std::integral_constant<int, I>{}, AxisK<revolute_axis(T::joint[I])>{}), ...);
}
template <class T, class F, int... I>
SPATIAL_INLINE void unrolled_reverse(F& f, std::integer_sequence<int, I...>) {
  (f(std::integral_constant<int, T::size - 1 - I>{}, AxisK<revolute_axis(T::joint[T::size - 1 - I])>{}), ...);
}
/// interleaved_reverse_order (model.hpp) of a compile-time tree, at compile time.
template <class T>
struct InterleavedReverse {
  static constexpr std::array<int, T::size> order = [] {
    std::array<int, T::size> out{}, queue{}, pending{};
    interleaved_reverse_order(T::size, T::parent.data(), out.data(), queue.data(), pending.data());
    return out;
  }();
};
template <class T, class F, int... I>
SPATIAL_INLINE void unrolled_interleaved_reverse(F& f, std::integer_sequence<int, I...>) {
  using O = InterleavedReverse<T>;
  (f(std::integral_constant<int, O::order[I]>{}, AxisK<revolute_axis(T::joint[O::order[I]])>{}), ...);
}
/// f(i, K) for bodies 0 … n−1 (parents first).
template <class S, class T, class F>
SPATIAL_INLINE void bodies(const Model<S, T>& model, F& f) {
  if constexpr (is_static_tree_v<T>) unrolled<T>(f, std::make_integer_sequence<int, T::size>{});
  else for (int i = 0; i < model.size(); ++i) with_axis(model, i, f);
}
/// f(i, K) for bodies n−1 … 0 (children first).
template <class S, class T, class F>
SPATIAL_INLINE void bodies_reverse(const Model<S, T>& model, F& f) {
  if constexpr (is_static_tree_v<T>) unrolled_reverse<T>(f, std::make_integer_sequence<int, T::size>{});
  else for (int i = model.size() - 1; i >= 0; --i) with_axis(model, i, f);
}
/// f(i, K) for every body, children before parents, in interleaved_reverse_order (model.hpp): on a compile-time
/// tree unrolled in InterleavedReverse's order, on a run-time tree looping over `order` (that order, computed once
/// by the caller's buffers), so that both trees run the same operations in the same order.
template <class S, class T, class F>
SPATIAL_INLINE void bodies_reverse_interleaved(const Model<S, T>& model, const int* order, F& f) {
  if constexpr (is_static_tree_v<T>) {
    (void)order;
    unrolled_interleaved_reverse<T>(f, std::make_integer_sequence<int, T::size>{});
  } else {
    for (int t = 0; t < model.size(); ++t) with_axis(model, order[t], f);
  }
}
/// λ(i): a std::integral_constant for a compile-time index of a compile-time tree, else an int.
template <class S, class T, int I>
SPATIAL_INLINE constexpr auto parent_of(const Model<S, T>&, std::integral_constant<int, I>) {
  return std::integral_constant<int, T::parent[I]>{};
}
template <class S, class T>
SPATIAL_INLINE int parent_of(const Model<S, T>& model, int i) {
  return model.parent(i);
}
/// f(j) for every proper ancestor j of body i.
template <class S, class T, class I, class F>
SPATIAL_INLINE void ancestors(const Model<S, T>& model, I i, F& f) {
  if constexpr (is_static_tree_v<T>) {
    (void)model;
    for_each_ancestor<T, I::value>(f);
  } else {
    for (int j = model.parent(i); j >= 0; j = model.parent(j)) f(j);
  }
}

/// Per-body records of a kernel on a run-time tree: `Data::work` viewed as n records of type Rec.
template <class Rec, class S, class T>
SPATIAL_INLINE Rec* records(Data<S, T>& data, int n) {
  static_assert(sizeof(Rec) <= kWorkBlocksPerBody * sizeof(WorkBlock) && alignof(Rec) <= alignof(WorkBlock),
                "a kernel's per-body record outgrew Data::work");
  Rec* r = reinterpret_cast<Rec*>(data.work.data());
  for (int i = 0; i < n; ++i) new (r + i) Rec;  // trivial: begins the records' lifetimes, emits no code
  return r;
}

/// Per-body values of one RNEA call, kept in registers' form between the passes.
template <int NB, class S>
struct RneaWork {
  using V = Vec<S>;
  V vw[NB], vv[NB];    // velocity
  V aw[NB], av[NB];    // acceleration
  V fn[NB], ff[NB];    // force
  V row[NB][3];        // rows of E in ⁱX_λ
};
/// The same on a run-time tree, in `Data::work`.
template <class S>
struct RneaWorkView {
  using V = Vec<S>;
  V *vw, *vv, *aw, *av, *fn, *ff;
  V (*row)[3];
  template <class T>
  void attach(Data<S, T>& data, int n) {
    struct Body {
      V x[9];
    };
    V* base = records<Body>(data, n)->x;
    vw = base, vv = base + n, aw = base + 2 * n, av = base + 3 * n, fn = base + 4 * n, ff = base + 5 * n;
    row = reinterpret_cast<V(*)[3]>(base + 6 * n);
  }
};

/// rnea_impl's AVX2 path (the same equations, the same outputs in `data`).
template <unsigned Terms, class S, class T, class Q, class QD, class QDD, class Out, class Root>
void rnea(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
          const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<QDD>& qdd, Out& tau, const Root& root) {
  using V = Vec<S>;
  constexpr bool G = (Terms & 1u) != 0;
  constexpr bool Vel = (Terms & 2u) != 0;
  constexpr bool A = (Terms & 4u) != 0;
  constexpr bool R = Root::floating;  // a moving root (floating base): its v and a start the recursion
  constexpr bool Static = Model<S, T>::is_static;
  constexpr int NB = Static ? Model<S, T>::NB : 1;
  static_assert(sizeof(Transform<S>) == 12 * sizeof(S) && sizeof(Motion<S>) == 6 * sizeof(S) &&
                    sizeof(Force<S>) == 6 * sizeof(S) && sizeof(Inertia<S>) == 13 * sizeof(S),
                "the AVX2 kernels assume unpadded spatial types");
  sincos_all<S>(q, data.cos_q, data.sin_q, model.size());
  std::conditional_t<Static, RneaWork<NB, S>, RneaWorkView<S>> w;
  if constexpr (Static) keep_in_memory(&w);
  else w.attach(data, model.size());
  const V g0 = sub(zero<V>(), load3(model.gravity().data()));  // a₀ = −a_g = [0; −g]
  V rvw = zero<V>(), rvv = zero<V>(), raw = zero<V>(), rav = zero<V>(), rfn = zero<V>(), rff = zero<V>();
  if constexpr (R) {
    rvw = load3(root.v.w.data()), rvv = load3(root.v.v.data());
    raw = load3(root.a.w.data()), rav = load3(root.a.v.data());
  }

  auto forward = [&](auto I, auto KC) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    const auto p = parent_of(model, I);
    constexpr int K = decltype(KC)::value;
    V col[3], r;
    joint_transform<K>(model, data, i, col, w.row[i], r);

    V vw = zero<V>(), vv = zero<V>(), aw = zero<V>(), av = zero<V>();
    if constexpr (Vel) {
      if (p >= 0) apply_motion(col, r, w.vw[p], w.vv[p], vw, vv);
      else if constexpr (R) apply_motion(col, r, rvw, rvv, vw, vv);
      vw = add(vw, axis<K>(S(qd[i])));
      w.vw[i] = vw;
      w.vv[i] = vv;
    }
    if (p >= 0) {
      apply_motion(col, r, w.aw[p], w.av[p], aw, av);
    } else if constexpr (R) {
      apply_motion(col, r, raw, rav, aw, av);
    } else if constexpr (G) {
      av = comb(col[0], col[1], col[2], g0);
    }
    if constexpr (A) aw = add(aw, axis<K>(S(qdd[i])));
    if constexpr (Vel) {
      // + v × S q̇ = [ω × e_K; v × e_K] q̇
      const V sq = mul(sign<K, V>(), bcast(S(qd[i])));
      aw = fmadd(swap_other<K>(vw), sq, aw);
      av = fmadd(swap_other<K>(vv), sq, av);
    }
    w.aw[i] = aw;
    w.av[i] = av;

    // f = I a + v ×* (I v), I m = [Ī ω + h × v; m v − h × ω]
    const Inertia<S>& In = model.inertia(i);
    const V h = load4(In.h.data());
    const S* J = In.I.data();
    const V j0 = load4(J), j1 = load4(J + 3), j2 = load3(J + 6);
    const V m = bcast(In.m);
    V fn, ff;
    inertia_times(j0, j1, j2, h, m, aw, av, fn, ff);
    if constexpr (Vel) {
      V pn, pf, cn, cf;
      inertia_times(j0, j1, j2, h, m, vw, vv, pn, pf);
      cross_force(vw, vv, pn, pf, cn, cf);  // v ×* p
      fn = add(fn, cn);
      ff = add(ff, cf);
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

  auto backward = [&](auto I, auto KC) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    const auto p = parent_of(model, I);
    constexpr int K = decltype(KC)::value;
    const V fn = w.fn[i], ff = w.ff[i];
    const auto k = static_cast<std::size_t>(i);
    store4(data.f[k].n.data(), fn);
    store3(data.f[k].f.data(), ff);
    tau[i] = get<K>(fn);
    if (p >= 0) {
      V ang, lin;
      apply_force_inverse(w.row[i], load3(model.tree_transform(i).r.data()), fn, ff, ang, lin);
      w.fn[p] = add(w.fn[p], ang);
      w.ff[p] = add(w.ff[p], lin);
    } else if constexpr (R) {
      V ang, lin;
      apply_force_inverse(w.row[i], load3(model.tree_transform(i).r.data()), fn, ff, ang, lin);
      rfn = add(rfn, ang);
      rff = add(rff, lin);
    }
  };

  bodies(model, forward);
  bodies_reverse(model, backward);
  if constexpr (R) {
    Force<S> add;
    store4(add.n.data(), rfn);
    store3(add.f.data(), rff);
    *root.f += add;
  } else {
    (void)root;
  }
}


/// forward_kinematics' AVX2 path (after joint_sincos): ⁱX_λ into `data.X_up`, ⁱX_0 into `data.X_base` and the motion
/// subspaces in base coordinates into `data.S_base`, as crba's first pass computes them.
template <class S, class T>
void forward_kinematics(const Model<S, T>& model, Data<S, T>& data) {
  using V = Vec<S>;
  constexpr bool Static = Model<S, T>::is_static;
  constexpr int NB = Static ? Model<S, T>::NB : 1;
  struct Body {
    V col[3], row[3], r;  // ⁱX_0: columns and rows of E, r
  };
  Body local[NB];
  Body* b = local;
  if constexpr (Static) keep_in_memory(b);
  else b = records<Body>(data, model.size());
  auto forward = [&](auto I, auto KC) SPATIAL_LAMBDA_INLINE {
    const auto p = parent_of(model, I);
    LocalTransform<S> up;
    V sw, sv;
    base_transform<decltype(KC)::value>(model, data, I, p, b, up, b[int(I)], sw, sv);
  };
  bodies(model, forward);
}

/// Columns offset … offset + n − 1 of a 6-row column-major Jacobian (rows linear first) from n motion subspaces in
/// root coordinates, moved to world coordinates by X0 = ⁰X_w: ω = E0ᵀ s_ω, v = E0ᵀ s_v + r0 × ω; without `Move`
/// (a fixed base: X0 is the identity) copied as they are.
template <bool Move, class S>
SPATIAL_INLINE void world_jacobian_columns(const Motion<S>* s, int n, const Transform<S>& X0, S* J, int offset) {
  using V = Vec<S>;
  V row[3];
  transpose(load3z(X0.E.data()), load3z(X0.E.data() + 3), load3(X0.E.data() + 6), row[0], row[1], row[2]);
  // transpose gives the rows of E0, i.e. the columns of E0ᵀ: comb with them is E0ᵀ x.
  const V r0 = load3(X0.r.data());
  for (int c = 0; c < n; ++c) {
    // v is the last 3-vector of the Motion, and of the array: three lanes only (load3 reads nothing beyond).
    V w = load3z(s[c].w.data()), v = load3(s[c].v.data());
    if constexpr (Move) {
      w = comb(row[0], row[1], row[2], w);
      v = add(comb(row[0], row[1], row[2], v), cross(r0, w));
    }
    S* out = J + 6 * (offset + c);
    store4(out, v);
    store3(out + 3, w);
  }
}

/// Columns offset … offset + n − 1 of a 6-row column-major force matrix (rows linear first: f, then the moment n)
/// moved in place by the transform X: f′ = E f, n′ = E (n − r × f) (centroidal.hpp: A_G's joint columns).
template <class S>
SPATIAL_INLINE void move_force_columns(const Transform<S>& X, S* A, int offset, int n) {
  using V = Vec<S>;
  // E's storage is column-major: its three columns, and comb with them is E x.
  const V c0 = load3z(X.E.data()), c1 = load3z(X.E.data() + 3), c2 = load3(X.E.data() + 6);
  const V r = load3(X.r.data());
  for (int c = offset; c < offset + n; ++c) {
    S* col = A + 6 * c;
    // f is followed by n in the column: four lanes, the fourth cleared; n is the column's end: three lanes only.
    const V f = load3z(col), m = load3(col + 3);
    const V fo = comb(c0, c1, c2, f), no = comb(c0, c1, c2, sub(m, cross(r, f)));
    store4(col, fo);
    store3(col + 3, no);
  }
}

/// Column c of a 6-row column-major Jacobian (rows linear first) from column c of the world columns J0 (same
/// layout), moved to the point p (world coordinates, in lanes: `load3(p.data())`): [v + ω × p; ω] for [v; ω].
template <class S>
SPATIAL_INLINE void jacobian_column_at(const S* J0, Vec<S> p, S* J, int c) {
  using V = Vec<S>;
  const V w = load3(J0 + 6 * c + 3);
  const V v = add(load3z(J0 + 6 * c), cross(w, p));
  store4(J + 6 * c, v);  // its fourth lane (0) is overwritten by ω next
  store3(J + 6 * c + 3, w);
}

/// crba_impl's AVX2 path: the same three passes and the same outputs in `data` (X_up, X_base, S_base, Ic, H). The
/// transforms ⁱX_λ are composed again from data.cos_q and data.sin_q rather than read back from data.X_up: reading
/// a 4-lane value that two stores wrote moments ago stalls until they retire, which costs more than the rotation.
template <class S, class T, class Sink>
void crba(const Model<S, T>& model, Data<S, T>& data, Sink& sink) {
  using V = Vec<S>;
  constexpr bool Static = Model<S, T>::is_static;
  constexpr int NB = Static ? Model<S, T>::NB : 1;
  constexpr bool Out = std::decay_t<Sink>::active;
  constexpr bool Entries = std::decay_t<Sink>::entries;
  constexpr bool Roots = std::decay_t<Sink>::sums_roots;
  struct Body {
    LocalTransform<S> up;  // ⁱX_λ
    V col[3], row[3], r;   // ⁱX_0
    V sw, sv;              // Sᵢ in base coordinates
    V ih, ic[3];           // composite inertia: h and the columns of Ī
    S im;                  // and m
  };
  Body local[NB];
  Body* b = local;
  if constexpr (Static) keep_in_memory(b);
  else b = records<Body>(data, model.size());
  struct {
    V ih = zero<V>(), ic[3] = {zero<V>(), zero<V>(), zero<V>()};
    S im = S(0);
  } root;  // Roots: Σ over the roots of ⁱX_0ᵀ Iᶜᵢ ⁱX_0
  // ⁱX_λᵀ Iᶜᵢ ⁱX_λ added into another composite inertia's lanes (the parent's, or the roots' sum).
  auto add_moved = [](const Body& B, S& im, V& ih, V (&ic)[3]) SPATIAL_LAMBDA_INLINE {
    V h, c[3];
    transformed_inertia<S>(B.up.col, B.up.row, B.up.r, B.im, B.ih, B.ic, h, c);
    for (int k = 0; k < 3; ++k) ic[k] = add(ic[k], c[k]);
    ih = add(ih, h);
    im += B.im;
  };

  auto forward = [&](auto I, auto KC) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    const auto p = parent_of(model, I);
    Body& B = b[i];
    base_transform<decltype(KC)::value>(model, data, i, p, b, B.up, B, B.sw, B.sv);
    const Inertia<S>& In = model.inertia(i);
    B.im = In.m;
    B.ih = load3z(In.h.data());
    B.ic[0] = load3z(In.I.data());
    B.ic[1] = load3z(In.I.data() + 3);
    B.ic[2] = load3(In.I.data() + 6);
  };

  auto backward = [&](auto I, auto) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    const auto p = parent_of(model, I);
    const auto k = static_cast<std::size_t>(i);
    const Body& B = b[i];
    // Iᶜᵢ is complete: write it out.
    store_inertia(B.im, B.ih, B.ic, data.Ic[k]);
    if (p >= 0) {
      Body& P = b[p];
      add_moved(B, P.im, P.ih, P.ic);
    } else if constexpr (Roots) {
      // A root's ⁱX_λ is ⁱX_0: its composite inertia in base coordinates, summed over the roots for the sink.
      add_moved(B, root.im, root.ih, root.ic);
    }
  };

  auto entries = [&](auto I, auto KC) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    constexpr int K = decltype(KC)::value;
    const Body& B = b[i];
    // F = Iᶜ S = [Ī e_K; e_K × h]; Hᵢᵢ = Sᵀ F = Ī_KK.
    const V fn = B.ic[K];
    const V ff = mul(swap_other<K>(B.ih), sub(zero<V>(), sign<K, V>()));
    if constexpr (!Entries) {
      V n0, f0;
      apply_force_inverse(B.row, B.r, fn, ff, n0, f0);
      Force<S> F0;
      store4(F0.n.data(), n0);
      store3(F0.f.data(), f0);
      sink(i, F0);
    } else {
      if constexpr (Out) sink.entry(i, i, get<K>(fn));
      else data.H(i, i) = get<K>(fn);
      if (parent_of(model, I) >= 0 || Out) {
        // F⁰ = ⁱX_0ᵀ F = [Eᵀ n + r × Eᵀ f; Eᵀ f]; H_ij = S⁰ⱼ · F⁰ for every ancestor j.
        V n0, f0;
        apply_force_inverse(B.row, B.r, fn, ff, n0, f0);
        if constexpr (Out) {
          Force<S> F0;
          store4(F0.n.data(), n0);
          store3(F0.f.data(), f0);
          sink(i, F0);
        }
        auto entry = [&](auto J) SPATIAL_LAMBDA_INLINE {
          const int j = J;
          const S hij = hsum(fmadd(b[j].sw, n0, mul(b[j].sv, f0)));
          if constexpr (Out) {
            sink.entry(i, j, hij);
          } else {
            data.H(i, j) = hij;
            data.H(j, i) = hij;
          }
        };
        ancestors(model, I, entry);
      }
    }
  };

  bodies(model, forward);
  bodies_reverse(model, backward);
  if constexpr (Roots) {
    Inertia<S> total;
    store_inertia(root.im, root.ih, root.ic, total);
    // The lanes' congruences leave Ī symmetric only to rounding; H's root block must be exactly symmetric.
    const Matrix3<S> I = total.I;
    total.I = S(0.5) * (I + I.transpose());
    sink.roots(total);
  }
  bodies(model, entries);
}

/// Writes a motion or force vector from its two 3-vectors.
template <class S, class V>
SPATIAL_INLINE void store_pair(S* p, V x, V y) {
  store4(p, x);
  store3(p + 3, y);
}

/// aba_impl's AVX2 path (no external forces): the same three passes and the same outputs in `data` (X_up, v, c,
/// IA, pA, U, Dinv, u, a, qdd). The articulated inertia [A B; Bᵀ C] is kept as the columns of A, B and C; the
/// rows of B (for U = Iᴬ S = [A e_K; Bᵀ e_K] and Bᵀ c) by one transpose per body.
template <bool G, bool Vel, class S, class T, class Q, class QD, class Tau, class Root>
void aba(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
         const Eigen::MatrixBase<Tau>& tau, const Root& root) {
  using V = Vec<S>;
  constexpr bool Static = Model<S, T>::is_static;
  constexpr int NB = Static ? Model<S, T>::NB : 1;
  constexpr bool R = Root::floating;  // a moving root: pass 1 from its velocity, pass 2 into it, pass 3 from solve()
  static_assert(sizeof(ArticulatedInertia<S>) == 27 * sizeof(S), "unpadded articulated inertia");
  struct Body {
    V col[3], row[3], r;  // ⁱX_λ: columns and rows of E, r
    V vw, vv, cw, cv;     // velocity and c = v × S q̇
    V pn, pf;             // bias force pᴬ (children added in pass 2)
    V A[3], B[3], C[3];   // articulated inertia, by columns (children added in pass 2)
    V un, uf;             // U = Iᴬ S
    S dinv, u;
    V aw, av;             // acceleration
  };
  Body local[NB];
  Body* b = local;
  if constexpr (Static) keep_in_memory(b);
  else b = records<Body>(data, model.size());
  sincos_all<S>(q, data.cos_q, data.sin_q, model.size());
  (void)qd;
  Body rootb;  // the moving root: what its children pass to it in pass 2 (floating base only)
  V rvw = zero<V>(), rvv = zero<V>();
  if constexpr (R) {
    for (int j = 0; j < 3; ++j) rootb.A[j] = rootb.B[j] = rootb.C[j] = zero<V>();
    rootb.pn = rootb.pf = zero<V>();
    rvw = load3(root.v.w.data()), rvv = load3(root.v.v.data());
  }

  auto pass1 = [&](auto I, auto KC) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    const auto p = parent_of(model, I);
    constexpr int K = decltype(KC)::value;
    const auto k = static_cast<std::size_t>(i);
    Body& B = b[i];
    joint_transform<K>(model, data, i, B.col, B.row, B.r);
    const Inertia<S>& In = model.inertia(i);
    const V h = load3z(In.h.data());
    B.A[0] = load3z(In.I.data());
    B.A[1] = load3z(In.I.data() + 3);
    B.A[2] = load3(In.I.data() + 6);
    // B = h̃: column j is h × e_j.  C = m 1.
    B.B[0] = mul(swap_other<0>(h), sign<0, V>());
    B.B[1] = mul(swap_other<1>(h), sign<1, V>());
    B.B[2] = mul(swap_other<2>(h), sign<2, V>());
    const V m = bcast(In.m);
    B.C[0] = only<0>(m);
    B.C[1] = only<1>(m);
    B.C[2] = only<2>(m);
    if constexpr (Vel) {
      V vw = zero<V>(), vv = zero<V>();
      if (p >= 0) {
        const Body& P = b[p];
        apply_motion(B.col, B.r, P.vw, P.vv, vw, vv);
      } else if constexpr (R) {
        apply_motion(B.col, B.r, rvw, rvv, vw, vv);
      }
      const S qdi = S(qd[i]);
      vw = add(vw, axis<K>(qdi));
      const V sq = mul(sign<K, V>(), bcast(qdi));
      B.vw = vw;
      B.vv = vv;
      B.cw = mul(swap_other<K>(vw), sq);
      B.cv = mul(swap_other<K>(vv), sq);
      // pᴬ = v ×* I v, I v = [Ī ω + h × v; m v − h × ω]
      const V in = add(comb(B.A[0], B.A[1], B.A[2], vw), cross(h, vv));
      const V jf = fmsub(m, vv, cross(h, vw));
      B.pn = add(cross(vw, in), cross(vv, jf));
      B.pf = cross(vw, jf);
      store_pair(data.v[k].w.data(), vw, vv);
      store_pair(data.c[k].w.data(), B.cw, B.cv);
    } else {
      B.pn = zero<V>();
      B.pf = zero<V>();
    }
  };

  auto pass2 = [&](auto I, auto KC) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    const auto p = parent_of(model, I);
    constexpr int K = decltype(KC)::value;
    const auto k = static_cast<std::size_t>(i);
    Body& B = b[i];
    // Iᴬ and pᴬ of body i are complete.
    S* ia = data.IA[k].A.data();
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
    B.dinv = S(1) / get<K>(B.un);
    B.u = S(tau[i]) - get<K>(B.pn);
    store_pair(data.U[k].n.data(), B.un, B.uf);
    data.Dinv[k] = B.dinv;
    data.u[k] = B.u;
    if (p >= 0 || R) {
      // Iᵃ = Iᴬ − U Uᵀ / D
      const V d = bcast(B.dinv);
      const V wn = mul(B.un, d), wf = mul(B.uf, d);
      V a[3] = {B.A[0], B.A[1], B.A[2]}, bc[3] = {B.B[0], B.B[1], B.B[2]}, c[3] = {B.C[0], B.C[1], B.C[2]};
      V br[3] = {br0, br1, br2};
      auto rank1 = [&](auto J) SPATIAL_LAMBDA_INLINE {
        constexpr int j = decltype(J)::value;
        a[j] = fnmadd(B.un, lane<j>(wn), a[j]);
        bc[j] = fnmadd(B.un, lane<j>(wf), bc[j]);
        c[j] = fnmadd(B.uf, lane<j>(wf), c[j]);
        br[j] = fnmadd(B.uf, lane<j>(wn), br[j]);
      };
      rank1(std::integral_constant<int, 0>{});
      rank1(std::integral_constant<int, 1>{});
      rank1(std::integral_constant<int, 2>{});
      // Iᵃ maps e_K to zero: row and column K of A and row K of B are exactly zero, not round-off (as in
      // ArticulatedInertia::subtract_outer<K>; the round-off would otherwise reach the parent and cost digits).
      a[K] = zero<V>();
      br[K] = zero<V>();
      for (int j = 0; j < 3; ++j) {
        a[j] = clear<K>(a[j]);
        bc[j] = clear<K>(bc[j]);
      }
      // pᵃ = pᴬ + Iᵃ c + U u / D
      const V ud = bcast(B.u * B.dinv);
      V pan = fmadd(B.un, ud, B.pn);
      V paf = fmadd(B.uf, ud, B.pf);
      if constexpr (Vel) {
        // c = v × S q̇ has no component K in either half (ArticulatedInertia::mul_null<K>).
        pan = add(pan, add(comb_skip<K>(a[0], a[1], a[2], B.cw), comb_skip<K>(bc[0], bc[1], bc[2], B.cv)));
        paf = add(paf, add(comb_skip<K>(br[0], br[1], br[2], B.cw), comb_skip<K>(c[0], c[1], c[2], B.cv)));
      }
      // Xᵀ Iᵃ X (ArticulatedInertia::transformed_inverse): a = Eᵀ A E, b = Eᵀ B E, c = Eᵀ C E;
      // B′ = b + r̃ c, A′ = a − B′ r̃ + r̃ bᵀ, C′ = c.
      Body& P = p >= 0 ? b[p] : rootb;
      V rb[3], rbp[3];
      auto rotate = [&](auto J) SPATIAL_LAMBDA_INLINE {
        constexpr int j = decltype(J)::value;
        const V e = B.col[j];
        // A e and B e have no component K (column K of A, row K of A and B are zero).
        const V aj = comb_skip<K>(B.row[0], B.row[1], B.row[2], comb_skip<K>(a[0], a[1], a[2], e));
        rb[j] = comb_skip<K>(B.row[0], B.row[1], B.row[2], comb(bc[0], bc[1], bc[2], e));
        const V cj = comb(B.row[0], B.row[1], B.row[2], comb(c[0], c[1], c[2], e));
        rbp[j] = add(rb[j], cross(B.r, cj));
        P.A[j] = add(P.A[j], aj);
        P.B[j] = add(P.B[j], rbp[j]);
        P.C[j] = add(P.C[j], cj);
      };
      rotate(std::integral_constant<int, 0>{});
      rotate(std::integral_constant<int, 1>{});
      rotate(std::integral_constant<int, 2>{});
      V bt0, bt1, bt2;  // rows of b
      transpose(rb[0], rb[1], rb[2], bt0, bt1, bt2);
      const V r0 = lane<0>(B.r), r1 = lane<1>(B.r), r2 = lane<2>(B.r);
      // −B′ r̃ by columns: −(r₂ B′₁ − r₁ B′₂), −(r₀ B′₂ − r₂ B′₀), −(r₁ B′₀ − r₀ B′₁); + r × (row j of b).
      P.A[0] = add(P.A[0], sub(cross(B.r, bt0), fmsub(r2, rbp[1], mul(r1, rbp[2]))));
      P.A[1] = add(P.A[1], sub(cross(B.r, bt1), fmsub(r0, rbp[2], mul(r2, rbp[0]))));
      P.A[2] = add(P.A[2], sub(cross(B.r, bt2), fmsub(r1, rbp[0], mul(r0, rbp[1]))));
      // pᴬ_λ += ⁱX_λᵀ pᵃ = [Eᵀ n + r × Eᵀ f; Eᵀ f]
      V ang, lin;
      apply_force_inverse(B.row, B.r, pan, paf, ang, lin);
      P.pn = add(P.pn, ang);
      P.pf = add(P.pf, lin);
    }
  };

  const V g0 = sub(zero<V>(), load3(model.gravity().data()));
  V raw = zero<V>(), rav = zero<V>();
  auto pass3 = [&](auto I, auto KC) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    const auto p = parent_of(model, I);
    constexpr int K = decltype(KC)::value;
    const auto k = static_cast<std::size_t>(i);
    Body& B = b[i];
    V aw = zero<V>(), av = zero<V>();
    if (p >= 0) {
      const Body& P = b[p];
      apply_motion(B.col, B.r, P.aw, P.av, aw, av);
    } else if constexpr (R) {
      apply_motion(B.col, B.r, raw, rav, aw, av);
    } else if constexpr (G) {
      av = comb(B.col[0], B.col[1], B.col[2], g0);
    }
    if constexpr (Vel) {
      aw = add(aw, B.cw);
      av = add(av, B.cv);
    }
    const S qddi = (B.u - hsum(fmadd(B.un, aw, mul(B.uf, av)))) * B.dinv;
    data.qdd[i] = qddi;
    aw = add(aw, axis<K>(qddi));
    B.aw = aw;
    B.av = av;
    store_pair(data.a[k].w.data(), aw, av);
  };

  bodies(model, pass1);
  bodies_reverse(model, pass2);
  if constexpr (R) {
    // The root's articulated inertia and bias force are complete: add them in, solve for its acceleration.
    ArticulatedInertia<S> IA;
    S* ia = IA.A.data();
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
    Force<S> pA;
    store_pair(pA.n.data(), rootb.pn, rootb.pf);
    *root.pA += pA;
    const Motion<S> a0 = root.solve();
    raw = load3(a0.w.data());
    rav = load3(a0.v.data());
  } else {
    (void)root, (void)raw, (void)rav;
  }
  bodies(model, pass3);
}

}  // namespace simd
#endif  // SPATIAL_SIMD_AVX2

}  // namespace spatial::detail
