#pragma once
/// \file minv.hpp
/// The inverse of the joint-space inertia matrix, H⁻¹(q), computed directly (without forming H and inverting it),
/// for fixed- and floating-base trees, compile-time and run-time, any scalar type:
///
///   inverse_inertia(model, data, md, q)  → md.Minv (n × n, or nv × nv on a floating base; both triangles filled)
///
/// **The algorithm.** Column j of H⁻¹ is the joint acceleration that a unit torque at joint j produces at rest
/// without gravity: forward dynamics by ABA with τ = eⱼ, run for all columns at once (the idea of Carpentier &
/// Mansard, RSS 2018; the formulation and the code are this library's). Everything is expressed in one frame, the
/// base frame (root coordinates on a floating base), so that columns never need transforming:
///   pass 1 (leaves to root): Iᴬᵢ = Iᵢ + Σ children (Iᴬ_c − U_c U_cᵀ / D_c),  Uᵢ = Iᴬᵢ Sᵢ,  Dᵢ = Sᵢᵀ Uᵢ;
///   pass 2 (per column j, up its ancestor chain): the force that the unit torque passes on, f = Uⱼ / Dⱼ, and at
///     each ancestor a:  H⁻¹(a, j) = −Sₐᵀ f / Dₐ,  f ← f + Uₐ H⁻¹(a, j)   (ABA's pass 2 for τ = eⱼ; a 6-vector in
///     registers, no 6 × n block);  H⁻¹(j, j) = 1 / Dⱼ;
///   pass 3 (root to leaves, rows i, columns j > i): H⁻¹(i, j) −= Uᵢᵀ A_λ(i)(:, j) / Dᵢ and
///     Aᵢ(:, j) = A_λ(i)(:, j) + Sᵢ H⁻¹(i, j), Aᵢ being body i's accelerations for the unit torques (ABA's pass 3).
/// Only one triangle is computed (stored as the lower one, H⁻¹(j, i) for j ≥ i, whose columns are contiguous); the
/// other is copied from it, so H⁻¹ is exactly symmetric.
/// Pass 1 is O(n), pass 2 O(n·depth), pass 3 O(n²) (H⁻¹ of a tree is dense within each branch of the base).
///
/// On a floating base the free-flyer is a 6-DoF joint with S = 1 at the root: D₀ = Iᴬ₀ (6 × 6, inverted by its
/// Cholesky factor), its rows H⁻¹(0…5, j) = −D₀⁻¹ f, and A₀ = H⁻¹(0…5, :). Rows and columns are ordered as v
/// (free-flyer linear first, then angular, both in root coordinates, then the joints), as Pinocchio's
/// `computeMinverse` on a free-flyer model: the matrices compare entry by entry.

#include "spatial/algorithms.hpp"
#include "spatial/floating.hpp"

#include <array>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace spatial {

namespace detail {
/// Buffers of `inverse_inertia`, allocated once here: the N × N result and per-body scratch (base coordinates).
template <class S, class T, int N>
struct MinvBuffers {
  using ModelType = Model<S, T>;
  template <class X>
  using Array = typename ModelType::template Array<X>;
  using Matrix = Eigen::Matrix<S, matrix_dim(N), matrix_dim(N)>;
  /// Accelerations of one body for every unit torque: rows angular then linear (as Motion), one column per joint;
  /// row-major, so that pass 3 runs along each row's contiguous columns several at a time (SIMD).
  using Block = Eigen::Matrix<S, 6, matrix_dim(N), matrix_dim(N) == 1 ? Eigen::ColMajor : Eigen::RowMajor>;

  MinvBuffers(const ModelType& tree, int n) : Minv(Matrix::Zero(n, n)) {
    if constexpr (!ModelType::is_static) {
      const auto k = static_cast<std::size_t>(tree.size());
      S0.resize(k);
      SD.resize(k);
      IA.resize(k);
      U.resize(k);
      Dinv.resize(k);
      A.resize(k);
      order.resize(k);
      std::vector<int> parent(k), scratch(2 * k);
      for (int i = 0; i < tree.size(); ++i) parent[static_cast<std::size_t>(i)] = tree.parent(i);
      interleaved_reverse_order(tree.size(), parent.data(), order.data(), scratch.data(), scratch.data() + k);
    }
    for (auto& a : A) a = Block::Zero(6, n);
  }

  Matrix Minv;                     ///< H⁻¹ (result)
  Array<Motion<S>> S0{};           ///< joint axes in base coordinates
  Array<Motion<S>> SD{};           ///< pass 2 (AVX2): −Sᵢ / Dᵢ, the axes scaled once per call
  Array<ArticulatedInertia<S>> IA{};  ///< articulated-body inertias in base coordinates
  Array<Force<S>> U{};             ///< Uᵢ = Iᴬᵢ Sᵢ
  Array<S> Dinv{};                 ///< 1 / Dᵢ
  Array<Block> A{};                ///< pass 3: body accelerations for the unit torques (columns ≥ the body's own)
  /// pass 1 (AVX2) on a run-time tree: the bodies in interleaved_reverse_order (compile-time trees have it as a
  /// constant)
  std::conditional_t<ModelType::is_static, std::array<int, 0>, std::vector<int>> order{};
};

/// Pass 1 of the tree (leaves to root): S, Iᴬ, U, 1/D in base coordinates. X_base of `data` must be up to date.
/// `root_IA`, if not null, receives what the root bodies pass to a free-flying root.
template <class S, class T, class Buffers>
void minv_articulated(const Model<S, T>& model, const Data<S, T>& data, Buffers& md,
                      ArticulatedInertia<S>* root_IA) {
  for_each_body(model, [&](auto I) {
    const auto k = static_cast<std::size_t>(int(I));
    const Transform<S>& X0 = data.X_base[k];
    md.S0[k] = model.joint(I).subspace_inverse(X0);
    md.IA[k] = ArticulatedInertia<S>(model.inertia(int(I)).transformed_inverse(X0));
  });
  for_each_body_reverse(model, [&](auto I) {
    const auto k = static_cast<std::size_t>(int(I));
    const int p = model.parent(I);
    md.U[k] = md.IA[k] * md.S0[k];
    md.Dinv[k] = S(1) / dot(md.S0[k], md.U[k]);
    if (p >= 0 || root_IA) {
      ArticulatedInertia<S> Ia = md.IA[k];
      Ia.subtract_outer(md.U[k], md.Dinv[k]);
      if (p >= 0) md.IA[static_cast<std::size_t>(p)] += Ia;
      else *root_IA += Ia;
    }
  });
}

/// Pass 2 of the tree: the columns `off + j` of the rows of j and its ancestors, stored transposed (lower triangle);
/// `root_force(j, f)` receives the force each column passes to a free-flying root (unused on a fixed base).
template <class S, class T, class Buffers, class RootForce>
void minv_columns(const Model<S, T>& model, Buffers& md, int off, RootForce&& root_force) {
  auto& M = md.Minv;
  // Plain loops over the bodies (also for compile-time trees: unrolled, the n columns' walks bloat the code and
  // run slower than the loop).
  for (int j = 0; j < model.size(); ++j) {
    const auto jk = static_cast<std::size_t>(j);
    const S dj = md.Dinv[jk];
    M(off + j, off + j) = dj;
    Force<S> f = md.U[jk] * dj;
    for (int a = model.parent(j); a >= 0; a = model.parent(a)) {
      const auto ak = static_cast<std::size_t>(a);
      const S m = -md.Dinv[ak] * dot(md.S0[ak], f);
      M(off + j, off + a) = m;
      f += md.U[ak] * m;
    }
    root_force(j, f);
  }
}

#if SPATIAL_SIMD_AVX2
namespace simd {
/// minv_articulated's AVX2 path (double or float, revolute joints about coordinate axes: `simd_applies`), which also
/// composes the transforms (base_transform: data.X_up, data.X_base, data.S_base, as forward_kinematics' kernel
/// leaves them), then each body's inertia moved to base
/// coordinates and the articulated inertias [A B; Bᵀ C] accumulated by columns, one register per column. The
/// results (md.S0, md.U, md.Dinv and *root_IA) agree with the scalar pass to rounding; md.IA is not written. With
/// `body_inertia`, each body's inertia in base coordinates goes there too (`aba_derivatives` gives it its
/// derivative buffers, whose forward pass then need not move the inertias again: `derivatives_forward`, Reuse).
template <class S, class T, class Buffers>
void minv_articulated(const Model<S, T>& model, Data<S, T>& data, Buffers& md, ArticulatedInertia<S>* root_IA,
                      Inertia<S>* body_inertia = nullptr) {
  using V = Vec<S>;
  constexpr bool Static = Model<S, T>::is_static;
  constexpr int NB = Static ? Model<S, T>::NB : 1;
  struct Body {
    V col[3], row[3], r;  // ⁱX_0: columns and rows of E, r
    V sw, sv;             // Sᵢ in base coordinates
    V A[3], B[3], C[3];   // Iᴬᵢ in base coordinates, by columns (children added in the second loop)
  };
  Body local[NB];
  Body* b = local;
  if constexpr (Static) keep_in_memory(b);
  else b = records<Body>(data, model.size());
  V root[9];  // what the root bodies pass to a free-flying root: the columns of A, B, C
  for (V& x : root) x = zero<V>();

  auto forward = [&](auto I, auto KC) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    const auto p = parent_of(model, I);
    const auto k = static_cast<std::size_t>(i);
    Body& B = b[i];
    LocalTransform<S> up;
    base_transform<decltype(KC)::value>(model, data, i, p, b, up, B, B.sw, B.sv);
    store4(md.S0[k].w.data(), B.sw);
    store3(md.S0[k].v.data(), B.sv);
    // Iᵢ in base coordinates, ⁱX_0ᵀ Iᵢ ⁱX_0, as an articulated inertia: A = Ī, B = h× (column c: h × e_c), C = m 1.
    const Inertia<S>& In = model.inertia(i);
    const V ic[3] = {load3z(In.I.data()), load3z(In.I.data() + 3), load3(In.I.data() + 6)};
    V h;
    transformed_inertia<S>(B.col, B.row, B.r, In.m, load3z(In.h.data()), ic, h, B.A);
    if (body_inertia) store_inertia(In.m, h, B.A, body_inertia[i]);
    auto column = [&](auto CC) SPATIAL_LAMBDA_INLINE {
      constexpr int c = decltype(CC)::value;
      B.B[c] = mul(swap_other<c>(h), sign<c, V>());
      B.C[c] = axis<c>(In.m);
    };
    column(std::integral_constant<int, 0>{});
    column(std::integral_constant<int, 1>{});
    column(std::integral_constant<int, 2>{});
  };

  auto backward = [&](auto I, auto) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    const auto p = parent_of(model, I);
    const auto k = static_cast<std::size_t>(i);
    const Body& B = b[i];
    // U = Iᴬ S = [A s_ω + B s_v; Bᵀ s_ω + C s_v], D = Sᵀ U.
    V brow[3];
    transpose(B.B[0], B.B[1], B.B[2], brow[0], brow[1], brow[2]);
    const V un = add(comb(B.A[0], B.A[1], B.A[2], B.sw), comb(B.B[0], B.B[1], B.B[2], B.sv));
    const V uf = add(comb(brow[0], brow[1], brow[2], B.sw), comb(B.C[0], B.C[1], B.C[2], B.sv));
    // The chain from one body's D to its parent's (leaves to root: the bodies of a branch wait on each other) runs
    // through D's sum, the division and one fused multiply-add per column: D is summed into all four lanes and
    // divided there (no scalar division, no broadcast), the outer products U Uᵀ are formed beside the division, and
    // each column of the parent is the column it has so far plus this body's, minus the product times 1 / D.
    const V bd = div(bcast(S(1)), hsum_all(fmadd(B.sw, un, mul(B.sv, uf))));
    store4(md.U[k].n.data(), un);
    store3(md.U[k].f.data(), uf);
    md.Dinv[k] = get<0>(bd);
    // The parent (or a free-flying root) gets Iᴬ − U Uᵀ / D: column c of A loses un un_c / D, of B un uf_c / D, of
    // C uf uf_c / D.
    auto give = [&](V* pa, V* pb, V* pc) SPATIAL_LAMBDA_INLINE {
      auto column = [&](auto CC) SPATIAL_LAMBDA_INLINE {
        constexpr int c = decltype(CC)::value;
        const V nc = lane<c>(un), fc = lane<c>(uf);
        pa[c] = fnmadd(mul(un, nc), bd, add(pa[c], B.A[c]));
        pb[c] = fnmadd(mul(un, fc), bd, add(pb[c], B.B[c]));
        pc[c] = fnmadd(mul(uf, fc), bd, add(pc[c], B.C[c]));
      };
      column(std::integral_constant<int, 0>{});
      column(std::integral_constant<int, 1>{});
      column(std::integral_constant<int, 2>{});
    };
    if (p >= 0) {
      Body& P = b[p];
      give(P.A, P.B, P.C);
    } else if (root_IA) {
      give(root, root + 3, root + 6);
    }
  };

  bodies(model, forward);
  bodies_reverse_interleaved(model, md.order.data(), backward);
  if (root_IA) {
    Matrix3<S>* blocks[3] = {&root_IA->A, &root_IA->B, &root_IA->C};
    for (int m = 0; m < 3; ++m)
      for (int c = 0; c < 3; ++c) {
        S x[4];
        store4(x, root[3 * m + c]);
        blocks[m]->col(c) += Vector3<S>(x[0], x[1], x[2]);
      }
  }
}

/// minv_columns' AVX2 path (double or float, any joint): the force f as two registers.
template <class S, class T, class Buffers, class RootForce>
void minv_columns(const Model<S, T>& model, Buffers& md, int off, RootForce&& root_force) {
  using V = Vec<S>;
  auto& M = md.Minv;
  // Each column's walk up its ancestors is a chain of dependent steps (m from f, then f from m): −Sₐ / Dₐ is
  // computed here, off that chain, and the dot product is summed into all four lanes (hsum_all), so that a step is
  // a product, a fused multiply-add, the sum, and the update of f (no scalar multiply, no broadcast).
  for (int a = 0; a < model.size(); ++a) {
    const auto ak = static_cast<std::size_t>(a);
    const V nd = bcast(-md.Dinv[ak]);
    store4(md.SD[ak].w.data(), mul(load3z(md.S0[ak].w.data()), nd));
    store3(md.SD[ak].v.data(), mul(load3(md.S0[ak].v.data()), nd));
  }
  for (int j = 0; j < model.size(); ++j) {
    const auto jk = static_cast<std::size_t>(j);
    const S dj = md.Dinv[jk];
    M(off + j, off + j) = dj;
    const V bj = bcast(dj);
    V fn = mul(load3z(md.U[jk].n.data()), bj), ff = mul(load3(md.U[jk].f.data()), bj);
    for (int a = model.parent(j); a >= 0; a = model.parent(a)) {
      const auto ak = static_cast<std::size_t>(a);
      const Motion<S>& s = md.SD[ak];
      const V bm = hsum_all(fmadd(load3z(s.w.data()), fn, mul(load3(s.v.data()), ff)));
      M(off + j, off + a) = get<0>(bm);
      fn = fmadd(load3z(md.U[ak].n.data()), bm, fn);
      ff = fmadd(load3(md.U[ak].f.data()), bm, ff);
    }
    Force<S> f;
    store4(f.n.data(), fn);
    store3(f.f.data(), ff);
    root_force(j, f);
  }
}
}  // namespace simd
#endif

/// The transforms and pass 1 (after joint_sincos): the AVX2 kernel when it applies (`Simd` false: never, for the
/// tests), else update_transform and the scalar pass. `body_inertia`: see simd::minv_articulated (the scalar pass
/// ignores it).
template <bool Simd, class S, class T, class Q, class Buffers>
void minv_first(const Model<S, T>& model, Data<S, T>& data, Buffers& md, const Eigen::MatrixBase<Q>& q,
                ArticulatedInertia<S>* root_IA, Inertia<S>* body_inertia = nullptr) {
#if SPATIAL_SIMD_AVX2
  if constexpr (Simd && simd_candidate<S, T>()) {
    if (simd_applies(model)) return simd::minv_articulated(model, data, md, root_IA, body_inertia);
  }
#endif
  (void)body_inertia;
  for_each_body(model, [&](auto I) { update_transform<true>(model, data, I, q); });
  minv_articulated(model, data, md, root_IA);
}

/// Pass 2: the AVX2 kernel for double and float (it needs no particular joint type), else the scalar pass.
template <bool Simd, class S, class T, class Buffers, class RootForce>
void minv_second(const Model<S, T>& model, Buffers& md, int off, RootForce&& root_force) {
#if SPATIAL_SIMD_AVX2
  if constexpr (Simd && (std::is_same_v<S, double> || std::is_same_v<S, float>)) {
    return simd::minv_columns(model, md, off, root_force);
  }
#endif
  minv_columns(model, md, off, root_force);
}

/// The inverse of a symmetric positive definite 6 × 6 matrix through its Cholesky factor L (A⁻¹ = L⁻ᵀ L⁻¹), in
/// fixed-size loops: the floating root's D₀⁻¹ once per call (Eigen's LLT solve against the identity took ~4 800
/// instructions under clang, mostly in its general triangular solver; this ~600). A matrix that is not positive
/// definite gives non-finite entries.
template <class S>
Matrix6<S> spd_inverse(const Matrix6<S>& A) {
  using std::sqrt;
  S L[6][6] = {}, W[6][6] = {};  // L, and W = L⁻¹ (both lower triangular)
  for (int j = 0; j < 6; ++j) {
    S d = A(j, j);
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    L[j][j] = sqrt(d);
    const S inv = S(1) / L[j][j];
    for (int i = j + 1; i < 6; ++i) {
      S x = A(i, j);
      for (int k = 0; k < j; ++k) x -= L[i][k] * L[j][k];
      L[i][j] = x * inv;
    }
  }
  for (int j = 0; j < 6; ++j) {
    W[j][j] = S(1) / L[j][j];
    for (int i = j + 1; i < 6; ++i) {
      S x = S(0);
      for (int k = j; k < i; ++k) x -= L[i][k] * W[k][j];
      W[i][j] = x / L[i][i];
    }
  }
  Matrix6<S> out;
  for (int c = 0; c < 6; ++c)
    for (int r = c; r < 6; ++r) {
      S x = S(0);
      for (int k = r; k < 6; ++k) x += W[k][r] * W[k][c];
      out(r, c) = x;
      out(c, r) = x;
    }
  return out;
}

/// Pass 3's inner loop over the columns c ≥ r: m = col[c] − u · ap(:, c), col[c] = m, a(:, c) = ap(:, c) + s m.
/// The columns are independent of each other, so they go four at a time (Eigen's packets: one AVX2 operation per
/// line, or two SSE2 or NEON ones), in blocks that end at nv and begin at or below r. The
/// columns below r that the first block also computes are harmless: col[c] for c < r is the upper triangle (pass 3
/// runs on the lower one; minv_symmetrize overwrites the upper one), and a body's accelerations below its own
/// column are read by nothing but the same harmless columns of its descendants. Without a block's worth of columns
/// above row 0 (nv − 4 · blocks < 0), a plain loop from r.
template <class S>
SPATIAL_INLINE void minv_row_update(S* col, S* const (&a)[6], const S* const (&ap)[6],
                                    const S (&u)[6], const S (&s)[6], int r, int nv) {
  constexpr int W = 4;
  const int blocks = (nv - r + W - 1) / W;
  int c = nv - W * blocks;
  const auto step = [&](int x) {
    const S x0 = ap[0][x], x1 = ap[1][x], x2 = ap[2][x], x3 = ap[3][x], x4 = ap[4][x], x5 = ap[5][x];
    const S m = col[x] - (u[0] * x0 + u[1] * x1 + u[2] * x2 + u[3] * x3 + u[4] * x4 + u[5] * x5);
    col[x] = m;
    a[0][x] = x0 + s[0] * m;
    a[1][x] = x1 + s[1] * m;
    a[2][x] = x2 + s[2] * m;
    a[3][x] = x3 + s[3] * m;
    a[4][x] = x4 + s[4] * m;
    a[5][x] = x5 + s[5] * m;
  };
  if (c < 0) {
    for (c = r; c < nv; ++c) step(c);
    return;
  }
  using Lanes = Eigen::Array<S, W, 1>;  // Eigen's packets: one AVX2 register, two SSE2 or NEON ones
  using In = Eigen::Map<const Lanes>;
  using Out = Eigen::Map<Lanes>;
  for (; c < nv; c += W) {
    const Lanes x0 = In(ap[0] + c), x1 = In(ap[1] + c), x2 = In(ap[2] + c);
    const Lanes x3 = In(ap[3] + c), x4 = In(ap[4] + c), x5 = In(ap[5] + c);
    const Lanes m = In(col + c) - (u[0] * x0 + u[1] * x1 + u[2] * x2 + u[3] * x3 + u[4] * x4 + u[5] * x5);
    Out(col + c) = m;
    Out(a[0] + c) = x0 + s[0] * m;
    Out(a[1] + c) = x1 + s[1] * m;
    Out(a[2] + c) = x2 + s[2] * m;
    Out(a[3] + c) = x3 + s[3] * m;
    Out(a[4] + c) = x4 + s[4] * m;
    Out(a[5] + c) = x5 + s[5] * m;
  }
}

/// Pass 3 of the tree: rows `off + i`, columns c ≥ off + i + 1 (and, with a free-flying root, A of the root in
/// `A_root`, whose columns ≥ off are used). Works on the transposed entries M(c, r), c ≥ r (the lower triangle,
/// contiguous in Eigen's column-major storage), and the accelerations row by row (row-major blocks), so that the
/// update of a row of H⁻¹ is one pass over contiguous arrays, four columns at a time (minv_row_update).
template <class S, class T, class Buffers, class RootBlock>
void minv_rows(const Model<S, T>& model, Buffers& md, int off, const RootBlock* A_root) {
  auto& M = md.Minv;
  const int nv = static_cast<int>(M.cols());
  // Rows of the accelerations: A(k, c) at a[k][c] (row-major blocks; see MinvBuffers::Block).
  const auto rows = [](auto& A, auto& a) {
    for (int k = 0; k < 6; ++k) a[k] = A.row(k).data();
  };
  for (int i = 0; i < model.size(); ++i) {  // a plain loop, as in minv_columns
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(i);
    const int r = off + i;
    S* a[6];
    rows(md.A[k], a);
    const Motion<S>& s0 = md.S0[k];
    const S s[6] = {s0.w[0], s0.w[1], s0.w[2], s0.v[0], s0.v[1], s0.v[2]};
    S* col = &M(0, r);
    if (p >= 0 || A_root) {
      const S* ap[6];
      rows(p >= 0 ? md.A[static_cast<std::size_t>(p)] : *A_root, ap);
      const Force<S>& U = md.U[k];
      const S dinv = md.Dinv[k];
      const S u[6] = {U.n[0] * dinv, U.n[1] * dinv, U.n[2] * dinv, U.f[0] * dinv, U.f[1] * dinv, U.f[2] * dinv};
      // One pass over the columns c ≥ r, independent of each other, four at a time: the entry
      // H⁻¹(i, c) −= Uᵢᵀ A_λ(:, c) / Dᵢ and the body's accelerations Aᵢ(:, c) = A_λ(:, c) + Sᵢ H⁻¹(i, c).
      minv_row_update(col, a, ap, u, s, r, nv);
    } else {
      for (int c = r; c < nv; ++c)
        for (int j = 0; j < 6; ++j) a[j][c] = s[j] * col[c];
    }
  }
}

/// Upper triangle ← lower triangle, in L × L blocks where whole blocks fit, element by element elsewhere. For
/// float and double each block below the diagonal is L loads of Eigen's packets of (at most) four (its contiguous
/// columns), Eigen's in-register transpose (`ptranspose`: shuffles on AVX, AVX-512 and NEON alike; L = 4, or 2 for
/// double on SSE2 and NEON) and L packet stores; other scalars copy 4 × 4 blocks entry by entry. (Wider blocks, 8 × 8
/// of AVX-512, would leave most of n = 21 to the element-wise tail, and GCC 12 warns inside their transpose.)
#if defined(__GNUC__)
#pragma GCC diagnostic push
// Packet types as template arguments (PacketBlock, unpacket_traits) lose their vector attributes, harmlessly: the
// same warning that Eigen silences in its own headers.
#pragma GCC diagnostic ignored "-Wignored-attributes"
#endif
template <class Matrix>
void minv_symmetrize(Matrix& M) {
  using S = typename Matrix::Scalar;
  using Packet = typename Eigen::internal::find_best_packet<S, 4>::type;
  constexpr bool Packets = std::is_floating_point_v<S> && Eigen::internal::packet_traits<S>::Vectorizable;
  constexpr int L = Packets ? Eigen::internal::unpacket_traits<Packet>::size : 4;
  const auto n = M.rows();
  const Eigen::Index whole = n - n % L;
  for (Eigen::Index jb = 0; jb < whole; jb += L) {
    for (Eigen::Index j = jb; j < jb + L; ++j)
      for (Eigen::Index i = j + 1; i < jb + L; ++i) M(j, i) = M(i, j);
    for (Eigen::Index ib = jb + L; ib < whole; ib += L) {
      if constexpr (Packets) {
        Eigen::internal::PacketBlock<Packet, L> b;
        for (int k = 0; k < L; ++k) b.packet[k] = Eigen::internal::ploadu<Packet>(&M(ib, jb + k));
        Eigen::internal::ptranspose(b);
        for (int l = 0; l < L; ++l) Eigen::internal::pstoreu(&M(jb, ib + l), b.packet[l]);
      } else {
        S b[L][L];
        for (int k = 0; k < L; ++k)
          for (int l = 0; l < L; ++l) b[k][l] = M(ib + l, jb + k);
        for (int l = 0; l < L; ++l)
          for (int k = 0; k < L; ++k) M(jb + k, ib + l) = b[k][l];
      }
    }
    for (Eigen::Index i = whole; i < n; ++i)
      for (Eigen::Index j = jb; j < jb + L; ++j) M(j, i) = M(i, j);
  }
  for (Eigen::Index j = whole; j < n; ++j)
    for (Eigen::Index i = j + 1; i < n; ++i) M(j, i) = M(i, j);
}
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
}  // namespace detail

/// Buffers and result (`Minv`, n × n) of the fixed-base `inverse_inertia`, allocated once here.
template <class S, class T = DynamicTree>
struct MinvData : detail::MinvBuffers<S, T, Model<S, T>::NB> {
  using ModelType = Model<S, T>;
  explicit MinvData(const ModelType& model) : detail::MinvBuffers<S, T, ModelType::NB>(model, model.size()) {}
};

/// Buffers and result (`Minv`, nv × nv, ordered as v) of the floating-base `inverse_inertia`.
template <class S, class T = DynamicTree>
struct FloatingMinvData : detail::MinvBuffers<S, T, FloatingModel<S, T>::NV> {
  using ModelType = FloatingModel<S, T>;
  using Base = detail::MinvBuffers<S, T, ModelType::NV>;
  explicit FloatingMinvData(const ModelType& model) : Base(model.tree(), model.nv()), A0(Base::Block::Zero(6, model.nv())) {}
  typename Base::Block A0;  ///< the root's accelerations for the unit torques
};

namespace detail {
/// inverse_inertia's three passes; `Simd` false keeps every pass on the scalar path (the tests compare both).
/// `body_inertia`: see minv_first.
template <bool Simd, class S, class T, class Q>
const typename MinvData<S, T>::Matrix& inverse_inertia_impl(const Model<S, T>& model, Data<S, T>& data,
                                                            MinvData<S, T>& md, const Eigen::MatrixBase<Q>& q,
                                                            Inertia<S>* body_inertia = nullptr) {
  joint_sincos(model, data, q);
  // Entries (j, i), j > i, where i is not an ancestor of j get no pass-2 term: start them from zero. (The whole
  // matrix: whole packets, cheaper than the strict lower triangle's ragged columns; the upper triangle is
  // overwritten by minv_symmetrize.)
  md.Minv.setZero();
  minv_first<Simd>(model, data, md, q, static_cast<ArticulatedInertia<S>*>(nullptr), body_inertia);
  minv_second<Simd>(model, md, 0, [](int, const Force<S>&) {});
  minv_rows(model, md, 0, static_cast<const typename MinvData<S, T>::Block*>(nullptr));
  minv_symmetrize(md.Minv);
  return md.Minv;
}

template <bool Simd, class S, class T, class Q>
const typename FloatingMinvData<S, T>::Matrix& inverse_inertia_impl(const FloatingModel<S, T>& model,
                                                                    FloatingData<S, T>& data,
                                                                    FloatingMinvData<S, T>& md,
                                                                    const Eigen::MatrixBase<Q>& q,
                                                                    Inertia<S>* body_inertia = nullptr) {
  const auto& tree = model.tree();
  auto& td = data.tree;
  const auto qj = joint_block<FloatingModel<S, T>::NJ>(q, 7, model.njoints());
  data.X0 = root_transform<S>(q);
  joint_sincos(tree, td, qj);
  auto& M = md.Minv;
  M.setZero();  // as in the fixed-base version
  // Pass 1, and the root's articulated inertia D₀ = Iᴬ₀ (angular first), inverted through its Cholesky factor.
  ArticulatedInertia<S> IA0(model.root_inertia());
  minv_first<Simd>(tree, td, md, qj, &IA0, body_inertia);
  // v's order is linear first: D₀ with its blocks swapped, [C Bᵀ; B A], and its inverse is H⁻¹'s 6 × 6 corner.
  Matrix6<S> D0;
  D0 << IA0.C, IA0.B.transpose(), IA0.B, IA0.A;
  const Matrix6<S> D0inv = spd_inverse(D0);
  M.template topLeftCorner<6, 6>() = D0inv;
  // Pass 2: tree columns, then the root's rows for them, −D₀⁻¹ f (f linear first).
  minv_second<Simd>(tree, md, 6, [&](int j, const Force<S>& f) {
    const Vector6<S> x = -(D0inv * linear_first(f));
    for (int r = 0; r < 6; ++r) M(6 + j, r) = x[r];
  });
  // Pass 3: the root's accelerations are its rows, i.e. its columns of the lower triangle.
  for (int r = 0; r < 6; ++r) md.A0.row(r) = M.col((r + 3) % 6).transpose();
  minv_rows(tree, md, 6, &md.A0);
  minv_symmetrize(M);
  return M;
}
}  // namespace detail

/// H⁻¹(q) into `md.Minv` (n × n, symmetric, both triangles written on every call) without forming H; see the file
/// comment. Uses `data` for the transforms (`data.X_base` is left as `forward_kinematics` leaves it). No
/// allocation; a joint whose subtree has no inertia gives non-finite entries (H is singular). Returns `md.Minv`.
template <class S, class T, class Q>
const typename MinvData<S, T>::Matrix& inverse_inertia(const Model<S, T>& model, Data<S, T>& data,
                                                       MinvData<S, T>& md, const Eigen::MatrixBase<Q>& q) {
  detail::check_sizes(model, "inverse_inertia", "q", q);
  return detail::inverse_inertia_impl<true>(model, data, md, q);
}

/// The floating-base version: nv × nv, rows and columns ordered as v (see the file comment).
template <class S, class T, class Q>
const typename FloatingMinvData<S, T>::Matrix& inverse_inertia(const FloatingModel<S, T>& model,
                                                               FloatingData<S, T>& data, FloatingMinvData<S, T>& md,
                                                               const Eigen::MatrixBase<Q>& q) {
  detail::check_q(model, q, "inverse_inertia");
  return detail::inverse_inertia_impl<true>(model, data, md, q);
}

}  // namespace spatial
