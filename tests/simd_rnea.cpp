// The AVX2 RNEA (simd.hpp) against the scalar path (rnea_impl<Terms, /*Simd=*/false>), in a translation unit built
// with -mavx2 -mfma: every term combination, τ and every per-body output (X_up, v, a, f), on the HOAP-3 models and
// on random compile-time trees of revolute joints about coordinate axes (several roots, branches, a 24-body chain),
// configurations beyond the fast sine range, NaN inputs, and the public entry points
// that dispatch to it (rnea, bias_forces, gravity_torques, rnea<Dyn>, forward dynamics by CRBA, which reuses the
// sines and cosines of its bias-force pass). No call may allocate (EIGEN_RUNTIME_NO_MALLOC).
#include "support/simd_compare.hpp"

namespace {
using namespace spatial;
using namespace spatial::testing::simd;

template <class TreeT, unsigned Terms, class S>
void compare_terms(const Model<S, TreeT>& model, const Eigen::Matrix<S, TreeT::size, 1>& q,
                   const Eigen::Matrix<S, TreeT::size, 1>& qd, const Eigen::Matrix<S, TreeT::size, 1>& qdd) {
  SCOPED_TRACE(::testing::Message() << "terms " << Terms);
  Data<S, TreeT> ds(model), dr(model);
  Eigen::internal::set_is_malloc_allowed(false);
  detail::rnea_impl<Terms, true>(model, ds, q, qd, qdd, NoExternalForces{}, ForceFrame::Body, ds.tau);
  detail::rnea_impl<Terms, false>(model, dr, q, qd, qdd, NoExternalForces{}, ForceFrame::Body, dr.tau);
  Eigen::internal::set_is_malloc_allowed(true);
  const Compare<TreeT, S> cmp{};
  constexpr bool V = (Terms & 2u) != 0;
  double sv = 0, sa = 0, sf = 0;
  for (int i = 0; i < TreeT::size; ++i) {
    const auto k = static_cast<std::size_t>(i);
    sv = std::max(sv, double(dr.v[k].vector().cwiseAbs().maxCoeff()));
    sa = std::max(sa, double(dr.a[k].vector().cwiseAbs().maxCoeff()));
    sf = std::max(sf, double(dr.f[k].vector().cwiseAbs().maxCoeff()));
  }
  cmp("tau", -1, ds.tau, dr.tau, sf);
  for (int i = 0; i < TreeT::size; ++i) {
    const auto k = static_cast<std::size_t>(i);
    // The transforms are one rotation by (cos q, sin q) of the tree transform: a rounding or two per entry.
    EXPECT_LE((ds.X_up[k].E - dr.X_up[k].E).cwiseAbs().maxCoeff(), 4 * std::numeric_limits<S>::epsilon());
    EXPECT_EQ(ds.X_up[k].r, dr.X_up[k].r);
    if (V) cmp("v", i, ds.v[k].vector(), dr.v[k].vector(), sv);
    cmp("a", i, ds.a[k].vector(), dr.a[k].vector(), sa);
    cmp("f", i, ds.f[k].vector(), dr.f[k].vector(), sf);
  }
}

template <class TreeT, class S>
void compare_all_terms(const Model<S, TreeT>& model, unsigned seed, double angle_scale) {
  using VN = Eigen::Matrix<S, TreeT::size, 1>;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    VN q, qd, qdd;
    for (int i = 0; i < TreeT::size; ++i) {
      q[i] = S(angle_scale * u(rng));
      qd[i] = S(3.0 * u(rng));
      qdd[i] = S(10.0 * u(rng));
    }
    if constexpr (kEveryTermCombination<TreeT, S>) {
      compare_terms<TreeT, 1u>(model, q, qd, qdd);
      compare_terms<TreeT, 2u>(model, q, qd, qdd);
      compare_terms<TreeT, 3u>(model, q, qd, qdd);
      compare_terms<TreeT, 4u>(model, q, qd, qdd);
      compare_terms<TreeT, 5u>(model, q, qd, qdd);
      compare_terms<TreeT, 6u>(model, q, qd, qdd);
    }
    compare_terms<TreeT, 7u>(model, q, qd, qdd);
  }
}

TEST(SimdRnea, HoapModelsAllTerms) {
  compare_all_terms(models::hoap3_stance_right::model(), 1, 3.2);
#if SPATIAL_SIMD_TEST_ALL_TREES
  compare_all_terms(models::hoap3_stance_left::model(), 2, 3.2);
  compare_all_terms(models::hoap3_torso::model(), 3, 3.2);
  compare_all_terms(models::hoap3_double_pendulum::model(), 4, 3.2);
#endif
}

TEST(SimdRnea, RandomTreesAllTerms) {
  for (unsigned seed = 10; seed < 14; ++seed) {
    compare_all_terms(random_static<Rev9>(seed), seed, 3.2);
    compare_all_terms(random_static<RevChain24>(seed), seed, 3.2);
  }
}

// float runs the same kernels on four floats per 128-bit register.
TEST(SimdRnea, FloatAllTerms) {
  compare_all_terms(models::hoap3_stance_right::model().cast<float>(), 7, 3.2);
  compare_all_terms(random_static<Rev9>(31).cast<float>(), 31, 3.2);
}

TEST(SimdRnea, LargeAnglesTakeTheLibraryPath) {
  // |q| up to 10⁶ rad: beyond the vectorised sine's range (10⁵), where sincos_all falls back to std::sin/cos.
  compare_all_terms(models::hoap3_stance_right::model(), 5, 1e6);
  compare_all_terms(random_static<Rev9>(20), 20, 1e6);
}

TEST(SimdRnea, OtherGravity) {
#if SPATIAL_SIMD_TEST_ALL_TREES
  compare_all_terms(models::hoap3_torso::model().with_gravity(Vector3<double>(1.5, -2.0, 9.0)), 6, 3.2);
#else
  compare_all_terms(models::hoap3_stance_right::model().with_gravity(Vector3<double>(1.5, -2.0, 9.0)), 6, 3.2);
#endif
}

// A NaN in q, q̇ or q̈ of body k must reach τ of k and of every ancestor of k, as on the scalar path.
TEST(SimdRnea, NanReachesTheSameTorques) {
  using Tree = models::hoap3_stance_right::Tree;
  const auto model = models::hoap3_stance_right::model();
  using VN = Eigen::Matrix<double, Tree::size, 1>;
  for (int input = 0; input < 3; ++input) {
    for (int k = 0; k < Tree::size; ++k) {
      VN q = VN::Constant(0.3), qd = VN::Constant(-0.2), qdd = VN::Constant(0.5);
      (input == 0 ? q : input == 1 ? qd : qdd)[k] = std::numeric_limits<double>::quiet_NaN();
      Data<double, Tree> ds(model), dr(model);
      detail::rnea_impl<7u, true>(model, ds, q, qd, qdd, NoExternalForces{}, ForceFrame::Body, ds.tau);
      detail::rnea_impl<7u, false>(model, dr, q, qd, qdd, NoExternalForces{}, ForceFrame::Body, dr.tau);
      for (int i = 0; i < Tree::size; ++i) {
        EXPECT_EQ(std::isnan(ds.tau[i]), std::isnan(dr.tau[i])) << "input " << input << ", NaN at " << k << ", tau " << i;
        if (model.is_ancestor_or_self(i, k)) {
          EXPECT_TRUE(std::isnan(ds.tau[i]));
        }
      }
    }
  }
}

// The public entry points reach the AVX2 path and agree with the scalar one.
TEST(SimdRnea, EntryPoints) {
  using Tree = models::hoap3_stance_right::Tree;
  const auto model = models::hoap3_stance_right::model();
  using VN = Eigen::Matrix<double, Tree::size, 1>;
  std::mt19937 rng(30);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VN q, qd, qdd, tau;
  for (int i = 0; i < Tree::size; ++i) q[i] = 1.5 * u(rng), qd[i] = u(rng), qdd[i] = u(rng), tau[i] = u(rng);
  Data<double, Tree> ds(model), dr(model);
  const double tol = tolerance<Tree>() * 100.0;  // τ of the HOAP-3 is below 100 N m at these inputs
  auto scalar = [&](auto terms, const VN& a, const VN& b) {
    detail::rnea_impl<decltype(terms)::value, false>(model, dr, q, a, b, NoExternalForces{}, ForceFrame::Body,
                                                     dr.tau);
    return VN(dr.tau);
  };
  Eigen::internal::set_is_malloc_allowed(false);
  const VN t_full = rnea(model, ds, q, qd, qdd);
  const VN t_bias = bias_forces(model, ds, q, qd);
  const VN t_grav = gravity_torques(model, ds, q);
  const VN t_novel = rnea<Dyn::QuasiStatic>(model, ds, q, qd, qdd);
  const VN t_nograv = rnea<Dyn::NoGravity>(model, ds, q, qd, qdd);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_LE((t_full - scalar(std::integral_constant<unsigned, 7u>{}, qd, qdd)).cwiseAbs().maxCoeff(), tol);
  EXPECT_LE((t_bias - scalar(std::integral_constant<unsigned, 3u>{}, qd, qdd)).cwiseAbs().maxCoeff(), tol);
  EXPECT_LE((t_grav - scalar(std::integral_constant<unsigned, 1u>{}, qd, qdd)).cwiseAbs().maxCoeff(), tol);
  EXPECT_LE((t_novel - scalar(std::integral_constant<unsigned, 5u>{}, qd, qdd)).cwiseAbs().maxCoeff(), tol);
  EXPECT_LE((t_nograv - scalar(std::integral_constant<unsigned, 6u>{}, qd, qdd)).cwiseAbs().maxCoeff(), tol);

  // Forward dynamics by CRBA takes the transforms of its AVX2 bias pass: H and τ − C as from the scalar pieces.
  Eigen::internal::set_is_malloc_allowed(false);
  const VN qdd_crba = forward_dynamics_crba(model, ds, q, qd, tau);
  Eigen::internal::set_is_malloc_allowed(true);
  crba(model, dr, q);
  const VN rhs = tau - scalar(std::integral_constant<unsigned, 3u>{}, qd, qd);
  EXPECT_LE((ds.H - dr.H).cwiseAbs().maxCoeff(), tolerance<Tree>() * dr.H.cwiseAbs().maxCoeff());
  EXPECT_LE((ds.tmp - rhs).cwiseAbs().maxCoeff(), tol);
  // q̈ against a dense solve of the scalar pieces: the difference in H and τ − C is amplified at most by κ(H).
  const VN qdd_ref = dr.H.ldlt().solve(rhs);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, Tree::size, Tree::size>> eig(dr.H);
  const double kappa = eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff();
  EXPECT_LE((qdd_crba - qdd_ref).norm(), 100.0 * tolerance<Tree>() * kappa * qdd_ref.norm()) << "kappa " << kappa;
}

// float reaches the kernels through every public entry point (bit for bit the kernel's result, not the scalar
// path's), and the kernels' float results are the double ones to float's precision.
TEST(SimdRnea, FloatEntryPointsTakeTheKernels) {
  using Tree = models::hoap3_stance_right::Tree;
  const auto md = models::hoap3_stance_right::model();
  const auto model = md.cast<float>();
  using VN = Eigen::Matrix<float, Tree::size, 1>;
  using VD = Eigen::Matrix<double, Tree::size, 1>;
  std::mt19937 rng(33);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  VN q, qd, qdd, tau;
  for (int i = 0; i < Tree::size; ++i) q[i] = 1.5f * u(rng), qd[i] = u(rng), qdd[i] = u(rng), tau[i] = u(rng);
  Data<float, Tree> d(model), ds(model), dr(model);
  Eigen::internal::set_is_malloc_allowed(false);
  const VN t = rnea(model, d, q, qd, qdd);
  detail::rnea_impl<7u, true>(model, ds, q, qd, qdd, NoExternalForces{}, ForceFrame::Body, ds.tau);
  detail::rnea_impl<7u, false>(model, dr, q, qd, qdd, NoExternalForces{}, ForceFrame::Body, dr.tau);
  crba(model, d, q);
  detail::crba_inputs<true>(model, ds, q);
  detail::crba_impl<true>(model, ds);
  detail::crba_inputs<false>(model, dr, q);
  detail::crba_impl<false>(model, dr);
  const VN a = aba(model, d, q, qd, tau);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(t, ds.tau);
  EXPECT_NE(t, dr.tau) << "the scalar path rounds differently, so equality would mean it ran instead";
  EXPECT_EQ(d.H, ds.H);
  EXPECT_NE(d.H, dr.H);
  detail::aba_impl<true, true, true>(model, ds, q, qd, tau, NoExternalForces{}, ForceFrame::Body);
  EXPECT_EQ(a, ds.qdd);
  detail::aba_impl<true, true, false>(model, dr, q, qd, tau, NoExternalForces{}, ForceFrame::Body);
  EXPECT_NE(a, dr.qdd);
  // Against double at the same (float) inputs: τ and H to a few float roundings per level, q̈ to κ(H) of them.
  Data<double, Tree> dd(md);
  const VD td = rnea(md, dd, q.cast<double>(), qd.cast<double>(), qdd.cast<double>());
  const double tol = tolerance<Tree, float>();
  EXPECT_LE((t.cast<double>() - td).cwiseAbs().maxCoeff(), tol * std::max(1.0, td.cwiseAbs().maxCoeff()));
  crba(md, dd, q.cast<double>());
  EXPECT_LE((d.H.cast<double>() - dd.H).cwiseAbs().maxCoeff(), tol * dd.H.cwiseAbs().maxCoeff());
  const VD ad = aba(md, dd, q.cast<double>(), qd.cast<double>(), tau.cast<double>());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, Tree::size, Tree::size>> eig(dd.H);
  const double kappa = eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff();
  EXPECT_LE((a.cast<double>() - ad).norm(), tol * kappa * ad.norm()) << "kappa " << kappa;
}

}  // namespace
