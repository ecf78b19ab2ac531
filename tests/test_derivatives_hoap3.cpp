// The analytical derivatives on the compile-time tree of the HOAP-3 stance model (21 DoF): against central finite
// differences and the forward-mode AD oracle with and without external forces, its run-time twin the same way,
// repeated calls, float against double (support/derivative_checks.hpp). Compile-time trees only: nothing here in the sanitizer build
// (support/compile_time_trees.hpp). The floating base is in test_derivatives_hoap3_floating.cpp.
#include <spatial/models/hoap3_stance_right.hpp>

#include "support/compile_time_trees.hpp"  // SPATIAL_TEST_COMPILE_TIME_TREES: 0 in the sanitizer build
#include "support/derivative_checks.hpp"

namespace {

using namespace spatial;
using namespace spatial::testing::derivative_checks;
using spatial::testing::random_vector;

#if SPATIAL_TEST_COMPILE_TIME_TREES
TEST(RneaDerivatives, Hoap3StanceCompileTimeTreeAgainstFiniteDifferencesAndAD) {
  const auto model = models::hoap3_stance_right::model();
  const int n = model.size();
  std::mt19937 rng(11);
  const Vec q = random_vector(n, rng, 1.0), v = random_vector(n, rng, 2.0), a = random_vector(n, rng, 2.0);
  const Forces f = random_forces(n, rng);
  check_fixed<true>(model, q, v, a, NoExternalForces{}, ForceFrame::Body, "no external forces");
  check_fixed<true>(model, q, v, a, f, ForceFrame::Body, "body-frame forces");
  check_fixed<true>(model, q, v, a, f, ForceFrame::Base, "base-frame forces");
}

// The run-time twin (revolute joints about coordinate axes, double) takes the AVX2 forward pass too, over per-body
// records in Data::work and a switch on each joint's axis instead of the unrolled tree; the AD oracle takes the
// scalar pass.
TEST(RneaDerivatives, Hoap3StanceRuntimeTwinAgainstFiniteDifferencesAndAD) {
  const Model<double> twin = models::hoap3_stance_right::model().to_runtime();
  const int n = twin.size();
  std::mt19937 rng(14);
  const Vec q = random_vector(n, rng, 1.0), v = random_vector(n, rng, 2.0), a = random_vector(n, rng, 2.0);
  check_fixed<true>(twin, q, v, a, NoExternalForces{}, ForceFrame::Body, "run-time twin, no external forces");
  check_fixed<true>(twin, q, v, a, random_forces(n, rng), ForceFrame::Base, "run-time twin, base-frame forces");
}

TEST(RneaDerivatives, RepeatedCallsAndOtherStatesLeaveNothingBehind) {
  const auto model = models::hoap3_stance_right::model();
  using T = models::hoap3_stance_right::Tree;
  const int n = model.size();
  std::mt19937 rng(12);
  Data<double, T> data(model);
  DerivativeData<double, T> dd(model);
  const Vec q1 = random_vector(n, rng), v1 = random_vector(n, rng), a1 = random_vector(n, rng);
  const Vec q2 = random_vector(n, rng), v2 = random_vector(n, rng), a2 = random_vector(n, rng);
  rnea_derivatives(model, data, dd, q1, v1, a1);
  const Mat first_q = dd.dtau_dq, first_v = dd.dtau_dv;
  rnea_derivatives(model, data, dd, q2, v2, a2, random_forces(n, rng), ForceFrame::Base);
  rnea_derivatives(model, data, dd, q1, v1, a1);
  EXPECT_EQ(Mat(dd.dtau_dq), first_q);
  EXPECT_EQ(Mat(dd.dtau_dv), first_v);
  // Entries between joints of different branches (neither an ancestor of the other) are structurally zero.
  const auto ancestor = [&](int i, int j) {  // j ⪯ i
    for (int k = i; k >= 0; k = model.parent(k))
      if (k == j) return true;
    return false;
  };
  int unrelated = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (!ancestor(i, j) && !ancestor(j, i)) {
        ++unrelated;
        EXPECT_EQ(dd.dtau_dq(i, j), 0.0) << i << ", " << j;
        EXPECT_EQ(dd.dtau_dv(i, j), 0.0) << i << ", " << j;
      }
  EXPECT_GT(unrelated, 0);
}

TEST(RneaDerivatives, FloatMatchesDouble) {
  const auto model = models::hoap3_stance_right::model();
  const auto mf = model.cast<float>();
  using T = models::hoap3_stance_right::Tree;
  const int n = model.size();
  std::mt19937 rng(13);
  const Vec q = random_vector(n, rng), v = random_vector(n, rng), a = random_vector(n, rng);
  Data<double, T> d(model);
  DerivativeData<double, T> dd(model);
  Data<float, T> df(mf);
  DerivativeData<float, T> ddf(mf);
  rnea_derivatives(model, d, dd, q, v, a);
  rnea_derivatives(mf, df, ddf, q.cast<float>(), v.cast<float>(), a.cast<float>());
  EXPECT_LT(rel_err(ddf.dtau_dq.cast<double>(), dd.dtau_dq), 1e-5);
  EXPECT_LT(rel_err(ddf.dtau_dv.cast<double>(), dd.dtau_dv), 1e-5);
}
#endif

}  // namespace
