// The AVX2 CRBA (simd.hpp) against the scalar path (crba_impl<false>), in a translation unit built with -mavx2
// -mfma: H and every per-body output (X_up, X_base, S_base, Iᶜ) on the HOAP-3 models and random compile-time trees
// of revolute joints about coordinate axes. No call may allocate (EIGEN_RUNTIME_NO_MALLOC).
#include "support/simd_compare.hpp"

namespace {
using namespace spatial;
using namespace spatial::testing::simd;

/// CRBA: H and every per-body output against the scalar path.
template <class TreeT, class S>
void compare_crba(const Model<S, TreeT>& model, unsigned seed, double angle_scale) {
  using VN = Eigen::Matrix<S, TreeT::size, 1>;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double tol = tolerance<TreeT, S>();
  for (int trial = 0; trial < 20; ++trial) {
    VN q;
    for (int i = 0; i < TreeT::size; ++i) q[i] = S(angle_scale * u(rng));
    Data<S, TreeT> ds(model), dr(model);
    Eigen::internal::set_is_malloc_allowed(false);
    detail::crba_inputs<true>(model, ds, q);
    detail::crba_impl<true>(model, ds);
    detail::crba_inputs<false>(model, dr, q);
    detail::crba_impl<false>(model, dr);
    Eigen::internal::set_is_malloc_allowed(true);
    const double sH = double(dr.H.cwiseAbs().maxCoeff());
    EXPECT_LE((ds.H - dr.H).cwiseAbs().maxCoeff(), tol * sH);
    EXPECT_EQ(ds.H.transpose(), ds.H) << "H is symmetric by construction";
    double sI = 0;
    for (int i = 0; i < TreeT::size; ++i)
      sI = std::max(sI, double(dr.Ic[static_cast<std::size_t>(i)].matrix().cwiseAbs().maxCoeff()));
    for (int i = 0; i < TreeT::size; ++i) {
      const auto k = static_cast<std::size_t>(i);
      EXPECT_LE((ds.X_up[k].E - dr.X_up[k].E).cwiseAbs().maxCoeff(), 4 * std::numeric_limits<S>::epsilon());
      EXPECT_EQ(ds.X_up[k].r, dr.X_up[k].r);
      // ⁱX_0 is a product of depth rotations; its r a sum of depth rotated offsets (|r_T| < 1 m in all models).
      EXPECT_LE((ds.X_base[k].E - dr.X_base[k].E).cwiseAbs().maxCoeff(), tol) << "body " << i;
      EXPECT_LE((ds.X_base[k].r - dr.X_base[k].r).cwiseAbs().maxCoeff(), tol * TreeT::size) << "body " << i;
      EXPECT_LE((ds.S_base[k].vector() - dr.S_base[k].vector()).cwiseAbs().maxCoeff(), tol * TreeT::size)
          << "body " << i;
      EXPECT_LE((ds.Ic[k].matrix() - dr.Ic[k].matrix()).cwiseAbs().maxCoeff(), tol * std::max(sI, 1.0))
          << "body " << i;
    }
  }
}

TEST(SimdCrba, HoapModels) {
  compare_crba(models::hoap3_stance_right::model(), 40, 3.2);
#if SPATIAL_SIMD_TEST_ALL_TREES
  compare_crba(models::hoap3_stance_left::model(), 41, 3.2);
  compare_crba(models::hoap3_torso::model(), 42, 3.2);
  compare_crba(models::hoap3_double_pendulum::model(), 43, 3.2);
#endif
}

TEST(SimdCrba, RandomTrees) {
  for (unsigned seed = 50; seed < 54; ++seed) {
    compare_crba(random_static<Rev9>(seed), seed, 3.2);
    compare_crba(random_static<RevChain24>(seed), seed, 3.2);
  }
  compare_crba(random_static<Rev9>(60), 60, 1e6);
}

TEST(SimdCrba, Float) {
  compare_crba(models::hoap3_stance_right::model().cast<float>(), 44, 3.2);
  compare_crba(random_static<Rev9>(61).cast<float>(), 61, 3.2);
}

}  // namespace
