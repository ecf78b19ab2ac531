// H⁻¹ computed directly (minv.hpp) against the inverse of CRBA's H, on random fixed and floating trees of every
// joint type and on the HOAP-3 compile-time models; exact symmetry, repeated calls, float against double, and the
// structural zeros between the base's branches on a fixed base.
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/models/hoap3_torso.hpp>

#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <random>

#include "support/compile_time_trees.hpp"  // SPATIAL_TEST_COMPILE_TIME_TREES: 0 in the sanitizer build

namespace {

using namespace spatial;
using spatial::testing::random_floating;
using spatial::testing::random_model;
using spatial::testing::random_vector;
using spatial::testing::Shape;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;

/// Checks md.Minv against H⁻¹ by LU of CRBA's H: the residuals H·M − 1 and M·H − 1 (scaled by H's size), and that
/// M is exactly symmetric. `Data`/`MinvData` of either base.
template <class Model, class Data, class MinvData>
void check_against_crba(const Model& model, Data& data, MinvData& md, const Vec& q, double tol = 1e-10) {
  const Mat M = inverse_inertia(model, data, md, q);
  Data ref(model);
  const Mat H = crba(model, ref, q);
  const int n = static_cast<int>(H.rows());
  ASSERT_EQ(M.rows(), n);
  ASSERT_EQ(M.cols(), n);
  const double cond = H.norm() * H.inverse().norm();
  EXPECT_LT((H * M - Mat::Identity(n, n)).cwiseAbs().maxCoeff(), tol * cond) << "H\n" << H << "\nM\n" << M;
  EXPECT_LT((M * H - Mat::Identity(n, n)).cwiseAbs().maxCoeff(), tol * cond);
  const Mat Hinv = H.inverse();
  EXPECT_LT((M - Hinv).cwiseAbs().maxCoeff(), tol * cond * Hinv.cwiseAbs().maxCoeff());
  EXPECT_TRUE(M == M.transpose()) << "not exactly symmetric";
}

TEST(InverseInertia, RandomFixedTreesEveryJointType) {
  struct Case {
    int n;
    Shape shape;
    unsigned seed;
  };
  for (const Case c : {Case{1, Shape::Chain, 1}, Case{2, Shape::Branched, 2}, Case{7, Shape::Chain, 3},
                       Case{12, Shape::Branched, 4}, Case{25, Shape::Branched, 5}}) {
    SCOPED_TRACE(c.n);
    const Model<double> model = random_model(c.n, c.shape, c.seed);
    std::mt19937 rng(c.seed);
    Data<double> data(model);
    MinvData<double> md(model);
    for (int k = 0; k < 3; ++k) check_against_crba(model, data, md, random_vector(c.n, rng, 3.0));
  }
}

TEST(InverseInertia, RandomFloatingTreesEveryJointType) {
  struct Case {
    int n;
    Shape shape;
    unsigned seed;
  };
  for (const Case c : {Case{0, Shape::Chain, 6}, Case{1, Shape::Chain, 7}, Case{6, Shape::Chain, 8},
                       Case{15, Shape::Branched, 9}}) {
    SCOPED_TRACE(c.n);
    const FloatingModel<double> model = random_floating(c.n, c.shape, c.seed);
    std::mt19937 rng(c.seed);
    FloatingData<double> data(model);
    FloatingMinvData<double> md(model);
    const Vec lo = Vec::Constant(c.n, -3.0), hi = Vec::Constant(c.n, 3.0);
    for (int k = 0; k < 3; ++k) check_against_crba(model, data, md, random_configuration(model, lo, hi, rng));
  }
}

TEST(InverseInertia, FixedBaseBranchesAreDecoupled) {
  // Two branches hanging from a fixed base do not couple: H is block-diagonal over them, so is H⁻¹, exactly.
  auto bodies = spatial::testing::random_bodies(12, Shape::Branched, 21);
  bodies[6].parent = -1;  // at least two branches at the base (bodies 0 and 6)
  const Model<double> model = spatial::testing::build_model(bodies);
  std::mt19937 rng(21);
  Data<double> data(model);
  MinvData<double> md(model);
  inverse_inertia(model, data, md, random_vector(12, rng, 3.0));
  const auto root_of = [&](int i) {
    while (model.parent(i) >= 0) i = model.parent(i);
    return i;
  };
  int decoupled = 0;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j)
      if (root_of(i) != root_of(j)) {
        ++decoupled;
        EXPECT_EQ(md.Minv(i, j), 0.0) << i << ", " << j;
      }
  EXPECT_GT(decoupled, 0);
  check_against_crba(model, data, md, random_vector(12, rng, 3.0));
}

TEST(InverseInertia, ReusedDataGivesTheSameResult) {
  const FloatingModel<double> model = random_floating(10, Shape::Branched, 22);
  std::mt19937 rng(22);
  const Vec lo = Vec::Constant(10, -3.0), hi = Vec::Constant(10, 3.0);
  const Vec q1 = random_configuration(model, lo, hi, rng), q2 = random_configuration(model, lo, hi, rng);
  FloatingData<double> data(model), fresh_data(model);
  FloatingMinvData<double> md(model), fresh(model);
  inverse_inertia(model, data, md, q2);
  inverse_inertia(model, data, md, q1);
  inverse_inertia(model, fresh_data, fresh, q1);
  EXPECT_TRUE(md.Minv == fresh.Minv);
}

#if SPATIAL_TEST_COMPILE_TIME_TREES
TEST(InverseInertia, Hoap3CompileTimeModels) {
  std::mt19937 rng(24);
  {
    const auto model = models::hoap3_stance_right::model();
    using T = models::hoap3_stance_right::Tree;
    Data<double, T> data(model);
    MinvData<double, T> md(model);
    for (int k = 0; k < 3; ++k) check_against_crba(model, data, md, random_vector(model.size(), rng, 1.5));
  }
  {
    const auto model = models::hoap3_torso::model();
    using T = models::hoap3_torso::Tree;
    Data<double, T> data(model);
    MinvData<double, T> md(model);
    check_against_crba(model, data, md, random_vector(model.size(), rng, 1.5));
  }
  {
    const auto model = models::hoap3_floating::floating_model();
    using T = models::hoap3_floating::Tree;
    FloatingData<double, T> data(model);
    FloatingMinvData<double, T> md(model);
    const Vec lo = Vec::Constant(model.njoints(), -1.0), hi = Vec::Constant(model.njoints(), 1.0);
    for (int k = 0; k < 3; ++k) check_against_crba(model, data, md, random_configuration(model, lo, hi, rng));
  }
}

TEST(InverseInertia, FloatMatchesDouble) {
  const auto model = models::hoap3_floating::floating_model();
  const auto mf = model.cast<float>();
  using T = models::hoap3_floating::Tree;
  std::mt19937 rng(25);
  const Vec lo = Vec::Constant(model.njoints(), -1.0), hi = Vec::Constant(model.njoints(), 1.0);
  const Vec q = random_configuration(model, lo, hi, rng);
  FloatingData<double, T> d(model);
  FloatingMinvData<double, T> md(model);
  FloatingData<float, T> df(mf);
  FloatingMinvData<float, T> mdf(mf);
  const Mat M = inverse_inertia(model, d, md, q);
  const Mat Mf = inverse_inertia(mf, df, mdf, q.cast<float>()).template cast<double>();
  // H of the HOAP-3 has a condition number of ~1e4 (light wrists against the whole body): float keeps ~3 digits.
  EXPECT_LT((Mf - M).cwiseAbs().maxCoeff(), 1e-2 * M.cwiseAbs().maxCoeff());
}
#endif

}  // namespace
