// Argument sizes (include/spatial/sizes.hpp, checks.hpp): the `*_checked` entry points refuse a q, q̇, q̈ or τ of
// the wrong size without computing, on compile-time and run-time models, and `InputCheck` prints what is wrong.
// The debug assertion of the plain entry points is tested by debug_sizes.cpp (built without NDEBUG), the
// static_assert of fixed-size arguments by the compile-fail tests in tests/compile_fail/.

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace {

using namespace spatial;
namespace stance = spatial::models::hoap3_stance_right;
using Vec = Eigen::VectorXd;

template <class M>
void expect_checked_entry_points_refuse_wrong_sizes(const M& model) {
  using D = Data<double, typename M::tree_type>;
  D data(model);
  const int n = model.size();
  const Vec good = Vec::Constant(n, 0.1), short_q = Vec::Zero(n - 1), long_q = Vec::Zero(n + 1);
  data.tau.setConstant(42.0);
  data.qdd.setConstant(42.0);

  InputCheck r = rnea_checked(model, data, short_q, good, good);
  EXPECT_FALSE(r.ok());
  EXPECT_STREQ(r.argument, "q");
  EXPECT_EQ(r.index, n - 1);
  EXPECT_EQ(r.expected, n);
  EXPECT_EQ(to_string(r), "q: wrong size: " + std::to_string(n - 1) + " entries, the model has " +
                              std::to_string(n) + " joints");
  EXPECT_TRUE((data.tau.array() == 42.0).all()) << "rnea_checked computed with a wrong size";

  r = rnea_checked(model, data, good, good, long_q);
  EXPECT_STREQ(r.argument, "qdd");
  EXPECT_EQ(r.index, n + 1);
  r = aba_checked(model, data, good, long_q, good);
  EXPECT_STREQ(r.argument, "qd");
  EXPECT_EQ(r.expected, n);
  r = aba_checked(model, data, good, good, short_q);
  EXPECT_STREQ(r.argument, "tau");
  r = forward_dynamics_crba_checked(model, data, good, good, short_q);
  EXPECT_STREQ(r.argument, "tau");
  EXPECT_EQ(r.index, n - 1);
  EXPECT_TRUE((data.qdd.array() == 42.0).all()) << "a checked forward dynamics computed with a wrong size";
  EXPECT_EQ(check_finite(model, short_q).expected, n);

  // Right sizes still compute.
  r = rnea_checked(model, data, good, good, good);
  EXPECT_TRUE(r.ok()) << r;
  EXPECT_EQ(to_string(r), "ok");
  EXPECT_FALSE((data.tau.array() == 42.0).all());
}

TEST(Sizes, CheckedEntryPointsRefuseWrongSizesCompileTimeModel) {
  expect_checked_entry_points_refuse_wrong_sizes(stance::model());
}

TEST(Sizes, CheckedEntryPointsRefuseWrongSizesRunTimeModel) {
  // A run-time copy of the same model (lock_joints with no lock builds a Model<double>).
  expect_checked_entry_points_refuse_wrong_sizes(lock_joints(stance::model(), {}).model);
}

TEST(Sizes, InputCheckPrintsNonFiniteEntries) {
  const auto model = stance::model();
  Data<double, stance::Tree> data(model);
  Vec q = Vec::Zero(stance::dof), qd = q;
  qd[2] = std::numeric_limits<double>::quiet_NaN();
  const InputCheck r = rnea_checked(model, data, q, qd, q);
  std::ostringstream os;
  os << r;
  EXPECT_EQ(os.str(), "qd[2] (joint 'R_LFE_R_KN_joint'): NaN (value nan)");
  EXPECT_EQ(r.expected, -1);
  q[0] = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(to_string(check_finite(model, q)), "q[0] (joint 'R_AFE_R_AAA_joint'): -Inf (value -inf)");
}

}  // namespace
