// The AVX2 ABA (simd.hpp) against the scalar path (aba_impl<G, V, false>) and a long-double reference, in a
// translation unit built with -mavx2 -mfma: q̈ at least as accurate as the scalar path's, every per-body output
// (X_up, v, c, Iᴬ, pᴬ, U, D⁻¹, u, a), the entry points aba and aba<Dyn>, and the round trip through RNEA. No call
// may allocate (EIGEN_RUNTIME_NO_MALLOC).
#include "support/simd_compare.hpp"

namespace {
using namespace spatial;
using namespace spatial::testing::simd;

/// ABA: every per-body output against the scalar path, and q̈ against a long-double reference: the AVX2 path must
/// be as accurate as the scalar one.
template <class TreeT, bool G, bool V, class S>
void compare_aba_terms(const Model<S, TreeT>& model, const Model<long double, TreeT>& reference,
                       const Eigen::Matrix<S, TreeT::size, 1>& q, const Eigen::Matrix<S, TreeT::size, 1>& qd,
                       const Eigen::Matrix<S, TreeT::size, 1>& tau) {
  SCOPED_TRACE(::testing::Message() << "gravity " << G << ", velocity " << V);
  using VN = Eigen::Matrix<double, TreeT::size, 1>;
  Data<S, TreeT> ds(model), dr(model);
  Data<long double, TreeT> dl(reference);
  Eigen::internal::set_is_malloc_allowed(false);
  detail::aba_impl<G, V, true>(model, ds, q, qd, tau, NoExternalForces{}, ForceFrame::Body);
  detail::aba_impl<G, V, false>(model, dr, q, qd, tau, NoExternalForces{}, ForceFrame::Body);
  Eigen::internal::set_is_malloc_allowed(true);
  detail::aba_impl<G, V, false>(reference, dl, q.template cast<long double>(), qd.template cast<long double>(),
                                tau.template cast<long double>(), NoExternalForces{}, ForceFrame::Body);
  const VN ref = dl.qdd.template cast<double>();
  const double scale = std::max(ref.cwiseAbs().maxCoeff(), 1.0);
  const double err_simd = (ds.qdd.template cast<double>() - ref).cwiseAbs().maxCoeff();
  const double err_scalar = (dr.qdd.template cast<double>() - ref).cwiseAbs().maxCoeff();
  // The error of one state varies with the order of the roundings: the bound is twice the scalar path's error or
  // the comparison bound of this tree (16 (depth + 1) u |q̈|), whichever is larger. (Over 200 states of six random
  // 24-body chains both paths reach the same largest error, 2e-14 |q̈|.)
  EXPECT_LE(err_simd, std::max(2.0 * err_scalar, tolerance<TreeT, S>() * scale))
      << "simd error " << err_simd << ", scalar error " << err_scalar;
  // The other outputs: differences of a few roundings per level against the largest value of each kind, except
  // where the scalar error itself is large (ill-conditioned articulated inertias), which the q̈ check covers.
  const double tol =
      tolerance<TreeT, S>() * std::max(1.0, err_scalar / (double(std::numeric_limits<S>::epsilon()) * scale));
  double sIA = 0, sp = 0, sU = 0, sv = 0, sa = 0;
  for (int i = 0; i < TreeT::size; ++i) {
    const auto k = static_cast<std::size_t>(i);
    sIA = std::max(sIA, double(dr.IA[k].matrix().cwiseAbs().maxCoeff()));
    sp = std::max(sp, double(dr.pA[k].vector().cwiseAbs().maxCoeff()));
    sU = std::max(sU, double(dr.U[k].vector().cwiseAbs().maxCoeff()));
    sv = std::max({sv, double(dr.v[k].vector().cwiseAbs().maxCoeff()), double(dr.c[k].vector().cwiseAbs().maxCoeff())});
    sa = std::max(sa, double(dr.a[k].vector().cwiseAbs().maxCoeff()));
  }
  const Compare<TreeT, S> cmp{tol};
  for (int i = 0; i < TreeT::size; ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_LE((ds.X_up[k].E - dr.X_up[k].E).cwiseAbs().maxCoeff(), 4 * std::numeric_limits<S>::epsilon());
    EXPECT_EQ(ds.X_up[k].r, dr.X_up[k].r);
    if (V) {
      cmp("v", i, ds.v[k].vector(), dr.v[k].vector(), sv);
      cmp("c", i, ds.c[k].vector(), dr.c[k].vector(), sv);
    }
    cmp("IA", i, ds.IA[k].matrix(), dr.IA[k].matrix(), sIA);
    cmp("pA", i, ds.pA[k].vector(), dr.pA[k].vector(), sp);
    cmp("U", i, ds.U[k].vector(), dr.U[k].vector(), sU);
    cmp("a", i, ds.a[k].vector(), dr.a[k].vector(), sa);
    EXPECT_NEAR(ds.Dinv[k], dr.Dinv[k], tol * std::abs(dr.Dinv[k])) << "body " << i;
    EXPECT_NEAR(ds.u[k], dr.u[k], tol * std::max(sp, 1.0)) << "body " << i;
  }
}

/// All four term combinations when `AllTerms`, else only the full ABA (each combination of each tree is a large
/// unrolled instantiation: this keeps the file's compile time down).
template <bool AllTerms = false, class TreeT, class S>
void compare_aba(const Model<S, TreeT>& model, unsigned seed, double angle_scale) {
  using VN = Eigen::Matrix<S, TreeT::size, 1>;
  const auto reference = model.template cast<long double>();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 10; ++trial) {
    VN q, qd, tau;
    for (int i = 0; i < TreeT::size; ++i) {
      q[i] = S(angle_scale * u(rng));
      qd[i] = S(3.0 * u(rng));
      tau[i] = S(u(rng));
    }
    compare_aba_terms<TreeT, true, true>(model, reference, q, qd, tau);
    if constexpr (AllTerms && kEveryTermCombination<TreeT, S>) {
      compare_aba_terms<TreeT, true, false>(model, reference, q, qd, tau);
      compare_aba_terms<TreeT, false, true>(model, reference, q, qd, tau);
      compare_aba_terms<TreeT, false, false>(model, reference, q, qd, tau);
    }
  }
}

TEST(SimdAba, HoapModels) {
  compare_aba<true>(models::hoap3_stance_right::model(), 70, 3.2);
#if SPATIAL_SIMD_TEST_ALL_TREES
  compare_aba(models::hoap3_stance_left::model(), 71, 3.2);
  compare_aba(models::hoap3_torso::model(), 72, 3.2);
  compare_aba(models::hoap3_double_pendulum::model(), 73, 3.2);
#endif
}

TEST(SimdAba, RandomTrees) {
  for (unsigned seed = 80; seed < 84; ++seed) {
    compare_aba<true>(random_static<Rev9>(seed), seed, 3.2);
    compare_aba(random_static<RevChain24>(seed), seed, 3.2);
  }
  compare_aba(random_static<Rev9>(90), 90, 1e6);
}

TEST(SimdAba, Float) {
  compare_aba(models::hoap3_stance_right::model().cast<float>(), 74, 3.2);
  compare_aba<true>(random_static<Rev9>(91).cast<float>(), 91, 3.2);
}

// The public entry points reach the AVX2 ABA (aba, aba<Dyn>), and inverse dynamics undoes forward dynamics, both
// on the AVX2 paths: rnea(q, q̇, aba(q, q̇, τ)) = τ up to the rounding of each.
TEST(SimdAba, EntryPointsAndRoundTrip) {
  using Tree = models::hoap3_stance_right::Tree;
  const auto model = models::hoap3_stance_right::model();
  using VN = Eigen::Matrix<double, Tree::size, 1>;
  using MN = Eigen::Matrix<double, Tree::size, Tree::size>;
  std::mt19937 rng(91);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VN q, qd, tau;
  for (int i = 0; i < Tree::size; ++i) q[i] = 1.5 * u(rng), qd[i] = u(rng), tau[i] = u(rng);
  Data<double, Tree> ds(model), dr(model);
  Eigen::internal::set_is_malloc_allowed(false);
  const VN qdd = aba(model, ds, q, qd, tau);
  const VN qdd_static = aba<Dyn::Static>(model, ds, q, qd, tau);
  const VN back = rnea(model, ds, q, qd, qdd);
  Eigen::internal::set_is_malloc_allowed(true);
  detail::aba_impl<true, true, true>(model, dr, q, qd, tau, NoExternalForces{}, ForceFrame::Body);
  EXPECT_EQ(qdd, dr.qdd) << "aba runs aba_impl's AVX2 path";
  detail::aba_impl<true, false, true>(model, dr, q, qd, tau, NoExternalForces{}, ForceFrame::Body);
  EXPECT_EQ(qdd_static, dr.qdd) << "aba<Dyn::Static> runs aba_impl's AVX2 path";
  detail::aba_impl<true, true, false>(model, dr, q, qd, tau, NoExternalForces{}, ForceFrame::Body);
  EXPECT_NE(qdd, dr.qdd) << "the scalar path rounds differently, so equality would mean it ran instead";
  // |τ − rnea(aba(τ))| ≤ (rounding of the forces in RNEA) + ‖H‖ |Δq̈| with |Δq̈| ≤ κ(H) (rounding of ABA).
  crba(model, dr, q);
  const Eigen::SelfAdjointEigenSolver<MN> eig(dr.H);
  const double kappa = eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff();
  double sf = 0;
  for (const auto& f : ds.f) sf = std::max(sf, f.vector().cwiseAbs().maxCoeff());
  const double bound = tolerance<Tree>() * (std::max(sf, 1.0) + kappa * eig.eigenvalues().maxCoeff() *
                                                                     qdd.cwiseAbs().maxCoeff());
  EXPECT_LE((back - tau).cwiseAbs().maxCoeff(), bound) << "kappa " << kappa;
}

}  // namespace
