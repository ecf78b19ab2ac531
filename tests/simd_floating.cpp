// The floating-base algorithms (floating.hpp) in a translation unit built with -mavx2 -mfma, where the tree passes
// take the AVX2 kernels (simd.hpp, minv.hpp) wherever the scalar path is not forced: CRBA with the free-flyer's
// columns, RNEA, ABA, CRBA + LTDL forward dynamics and H⁻¹ (fixed base too) against the same calls with the scalar
// path (`<false>`), on the HOAP-3 models and random trees, with no allocation (EIGEN_RUNTIME_NO_MALLOC).
#include "support/simd_compare.hpp"

#include <spatial/models/hoap3_floating.hpp>

namespace {
using namespace spatial;
using namespace spatial::testing::simd;

template <class TreeT, class S>
void compare_floating(const FloatingModel<S, TreeT>& model, unsigned seed) {
  using FM = FloatingModel<S, TreeT>;
  using VQ = Eigen::Matrix<S, FM::NQ, 1>;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Matrix<S, Eigen::Dynamic, 1> lo = Eigen::Matrix<S, Eigen::Dynamic, 1>::Constant(TreeT::size, S(-3.2));
  const Eigen::Matrix<S, Eigen::Dynamic, 1> hi = -lo;
  const double tol = tolerance<TreeT, S>();
  for (int trial = 0; trial < 20; ++trial) {
    const VQ q = random_configuration(model, lo, hi, rng);
    FloatingData<S, TreeT> ds(model), dr(model);
    Eigen::internal::set_is_malloc_allowed(false);
    const auto qj = q.template tail<TreeT::size>();
    detail::crba_inputs<true>(model.tree(), ds.tree, qj);
    detail::crba_floating<true>(model, ds);
    detail::crba_inputs<false>(model.tree(), dr.tree, qj);
    detail::crba_floating<false>(model, dr);
    Eigen::internal::set_is_malloc_allowed(true);
    const double sH = double(dr.H.cwiseAbs().maxCoeff());
    EXPECT_LE((ds.H - dr.H).cwiseAbs().maxCoeff(), tol * sH);
    EXPECT_EQ(ds.H.transpose(), ds.H) << "H is symmetric by construction";
    // The public entry point takes the AVX2 CRBA and gives the same H.
    EXPECT_LE((crba(model, dr, q) - ds.H).cwiseAbs().maxCoeff(), tol * sH);
  }
}

TEST(SimdFloating, CrbaHoap3) { compare_floating(models::hoap3_floating::floating_model(), 70); }

TEST(SimdFloating, CrbaRandomTrees) {
  std::mt19937 rng(71);
  for (unsigned seed = 72; seed < 75; ++seed) {
    const Inertia<double> I0 = test_root_inertia();
    compare_floating(FloatingModel<double, Rev9>(random_static<Rev9>(seed), I0), seed);
#if SPATIAL_SIMD_TEST_ALL_TREES
    compare_floating(FloatingModel<double, RevChain24>(random_static<RevChain24>(seed), I0), seed);
#endif
  }
}

}  // namespace

namespace {
using namespace spatial;
using namespace spatial::testing::simd;

/// RNEA (every term combination) and ABA on a floating base: the AVX2 tree passes against the scalar ones.
template <class TreeT, class S>
void compare_floating_dynamics(const FloatingModel<S, TreeT>& model, unsigned seed) {
  using FM = FloatingModel<S, TreeT>;
  using VQ = Eigen::Matrix<S, FM::NQ, 1>;
  using VV = Eigen::Matrix<S, FM::NV, 1>;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Matrix<S, Eigen::Dynamic, 1> lo = Eigen::Matrix<S, Eigen::Dynamic, 1>::Constant(TreeT::size, S(-3.2));
  const Eigen::Matrix<S, Eigen::Dynamic, 1> hi = -lo;
  const double tol = tolerance<TreeT, S>();
  for (int trial = 0; trial < 20; ++trial) {
    const VQ q = random_configuration(model, lo, hi, rng);
    VV v, a;
    for (int i = 0; i < FM::NV; ++i) v[i] = S(2 * u(rng)), a[i] = S(2 * u(rng));
    FloatingData<S, TreeT> ds(model), dr(model);
    VV ts, tr;
    Eigen::internal::set_is_malloc_allowed(false);
    auto both = [&](auto terms) {
      constexpr unsigned Terms = decltype(terms)::value;
      detail::rnea_floating<Terms, true>(model, ds, q, v, a, NoExternalForces{}, ForceFrame::Body, ts);
      detail::rnea_floating<Terms, false>(model, dr, q, v, a, NoExternalForces{}, ForceFrame::Body, tr);
      Eigen::internal::set_is_malloc_allowed(true);
      EXPECT_LE((ts - tr).cwiseAbs().maxCoeff(), tol * std::max(1.0, double(tr.cwiseAbs().maxCoeff()))) << Terms;
      Eigen::internal::set_is_malloc_allowed(false);
    };
    both(std::integral_constant<unsigned, 7u>{});
    if constexpr (kEveryTermCombination<TreeT, S>) {
      both(std::integral_constant<unsigned, 3u>{});
      both(std::integral_constant<unsigned, 1u>{});
      both(std::integral_constant<unsigned, 6u>{});
    }
    detail::aba_floating<true>(model, ds, q, v, a, NoExternalForces{}, ForceFrame::Body);
    detail::aba_floating<false>(model, dr, q, v, a, NoExternalForces{}, ForceFrame::Body);
    Eigen::internal::set_is_malloc_allowed(true);
    EXPECT_LE((ds.qdd - dr.qdd).cwiseAbs().maxCoeff(), 1e3 * tol * std::max(1.0, double(dr.qdd.cwiseAbs().maxCoeff())));
    // The round trip through the public entry points (both AVX2): RNEA(ABA(τ)) = τ.
    const VV qdd = aba(model, ds, q, v, a);
    const VV back = rnea(model, ds, q, v, qdd);
    EXPECT_LE((back - a).cwiseAbs().maxCoeff(), 1e3 * tol * std::max(1.0, double(a.cwiseAbs().maxCoeff())));
  }
}

TEST(SimdFloating, DynamicsHoap3) { compare_floating_dynamics(models::hoap3_floating::floating_model(), 80); }

// float on Rev9 (the HOAP-3's fixed-base kernels run in float in simd_rnea.cpp, simd_crba.cpp and simd_aba.cpp; a
// 27-body floating model in float would be three more large unrolled instantiations).
TEST(SimdFloating, Float) {
  const Inertia<double> I0 = test_root_inertia();
  const auto model = FloatingModel<double, Rev9>(random_static<Rev9>(86), I0).cast<float>();
  compare_floating(model, 71);
  compare_floating_dynamics(model, 85);
}

TEST(SimdFloating, DynamicsRandomTrees) {
  for (unsigned seed = 81; seed < 84; ++seed) {
    const Inertia<double> I0 = test_root_inertia();
    compare_floating_dynamics(FloatingModel<double, Rev9>(random_static<Rev9>(seed), I0), seed);
#if SPATIAL_SIMD_TEST_ALL_TREES
    compare_floating_dynamics(FloatingModel<double, RevChain24>(random_static<RevChain24>(seed), I0), seed);
#endif
  }
}

}  // namespace

namespace {
using namespace spatial;
using namespace spatial::testing::simd;

/// H⁻¹ (minv.hpp): the AVX2 passes 1 and 2 against the scalar ones (`inverse_inertia_impl<false>`), H⁻¹ and pass 1's
/// per-body outputs (S⁰, U, 1/D), fixed and floating base, compile-time and run-time trees, without allocation.
template <class M, class MD, class Q>
void compare_minv_once(const M& model, const Q& q, double tol) {
  typename detail::ModelTraits<M>::DataType ds(model), dr(model);
  MD ms(model), mr(model);
  Eigen::internal::set_is_malloc_allowed(false);
  detail::inverse_inertia_impl<true>(model, ds, ms, q);
  detail::inverse_inertia_impl<false>(model, dr, mr, q);
  Eigen::internal::set_is_malloc_allowed(true);
  const double sM = double(mr.Minv.cwiseAbs().maxCoeff());
  EXPECT_LE(double((ms.Minv - mr.Minv).cwiseAbs().maxCoeff()), tol * sM);
  EXPECT_EQ(ms.Minv.transpose(), ms.Minv) << "H⁻¹ is symmetric by construction";
  // The public entry point takes the AVX2 passes.
  EXPECT_EQ(inverse_inertia(model, dr, mr, q), ms.Minv);
  for (std::size_t k = 0; k < ms.U.size(); ++k) {
    const double sU = std::max(1.0, double(mr.U[k].vector().cwiseAbs().maxCoeff()));
    EXPECT_LE(double((ms.S0[k].vector() - mr.S0[k].vector()).cwiseAbs().maxCoeff()), tol) << "S0 of body " << k;
    EXPECT_LE(double((ms.U[k].vector() - mr.U[k].vector()).cwiseAbs().maxCoeff()), tol * sU) << "U of body " << k;
    EXPECT_LE(double(std::abs(ms.Dinv[k] - mr.Dinv[k])), tol * double(std::abs(mr.Dinv[k]))) << "1/D of body " << k;
  }
}

/// The run-time kernels run the compile-time kernels' operations in the same order, so H⁻¹ is equal bit for bit.
/// On HOAP-3's trees this checks that pass 1's backward walk takes the bodies in interleaved_reverse_order on both
/// (on stance21 the pelvis's two children come in another order than n − 1 … 0 would give).
template <class MDS, class MDR, class MS, class MR, class Q>
void expect_twin_minv_equal(const MS& model, const MR& twin, const Q& q) {
  typename detail::ModelTraits<MS>::DataType ds(model);
  typename detail::ModelTraits<MR>::DataType dr(twin);
  MDS ms(model);
  MDR mr(twin);
  using X = Eigen::Matrix<typename Q::Scalar, Eigen::Dynamic, 1>;
  EXPECT_TRUE(inverse_inertia(model, ds, ms, q) == inverse_inertia(twin, dr, mr, X(q)))
      << "H⁻¹ of the run-time twin differs from the compile-time tree's";
}

template <class TreeT, class S>
void compare_minv(const Model<S, TreeT>& model, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.2, 3.2);
  // H⁻¹ is built by one division per body from D = Sᵀ Iᴬ S, whose differences grow with the tree's condition.
  const double tol = 64 * tolerance<TreeT, S>();
  const Model<S> twin = model.to_runtime();  // the run-time kernels (simd_applies)
  for (int trial = 0; trial < 10; ++trial) {
    Eigen::Matrix<S, TreeT::size, 1> q;
    for (int i = 0; i < TreeT::size; ++i) q[i] = S(u(rng));
    compare_minv_once<Model<S, TreeT>, MinvData<S, TreeT>>(model, q, tol);
    compare_minv_once<Model<S>, MinvData<S>>(twin, Eigen::Matrix<S, Eigen::Dynamic, 1>(q), tol);
    expect_twin_minv_equal<MinvData<S, TreeT>, MinvData<S>>(model, twin, q);
  }
}

template <class TreeT, class S>
void compare_minv(const FloatingModel<S, TreeT>& model, unsigned seed) {
  std::mt19937 rng(seed);
  const Eigen::Matrix<S, Eigen::Dynamic, 1> lo = Eigen::Matrix<S, Eigen::Dynamic, 1>::Constant(TreeT::size, S(-3.2));
  const Eigen::Matrix<S, Eigen::Dynamic, 1> hi = -lo;
  const double tol = 64 * tolerance<TreeT, S>();
  const FloatingModel<S> twin = model.to_runtime();
  for (int trial = 0; trial < 10; ++trial) {
    const auto q = random_configuration(model, lo, hi, rng);
    compare_minv_once<FloatingModel<S, TreeT>, FloatingMinvData<S, TreeT>>(model, q, tol);
    expect_twin_minv_equal<FloatingMinvData<S, TreeT>, FloatingMinvData<S>>(model, twin, q);
  }
}

TEST(SimdMinv, FixedBase) {
  compare_minv(models::hoap3_stance_right::model(), 80);
  for (unsigned seed = 81; seed < 84; ++seed) compare_minv(random_static<Rev9>(seed), seed);
  compare_minv(models::hoap3_stance_right::model().cast<float>(), 84);
}

TEST(SimdMinv, FloatingBase) {
  compare_minv(models::hoap3_floating::floating_model(), 85);
  compare_minv(FloatingModel<double, Rev9>(random_static<Rev9>(86), test_root_inertia()), 86);
}

/// spd_inverse (the floating root's D₀⁻¹) against Eigen's LLT on random positive definite matrices.
TEST(SimdMinv, SpdInverse) {
  std::mt19937 rng(87);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    Matrix6<double> B;
    for (int i = 0; i < 36; ++i) B(i) = u(rng);
    const Matrix6<double> A = B * B.transpose() + 0.1 * Matrix6<double>::Identity();
    const Matrix6<double> X = detail::spd_inverse(A);
    const Matrix6<double> ref = A.llt().solve(Matrix6<double>::Identity());
    EXPECT_LE((X - ref).cwiseAbs().maxCoeff(), 1e-10 * ref.cwiseAbs().maxCoeff());
    EXPECT_EQ(X, X.transpose());
    EXPECT_LE((A * X - Matrix6<double>::Identity()).cwiseAbs().maxCoeff(), 1e-10);
  }
  Matrix6<double> N = Matrix6<double>::Identity();
  N(3, 3) = -1.0;  // not positive definite: non-finite entries, no exception
  EXPECT_FALSE(detail::spd_inverse(N).allFinite());
}

}  // namespace
