// The batched sine/cosine of the joint angles (include/spatial/sincos.hpp) against the C library, in long double.
#include <spatial/spatial.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

// Error of `value` against `reference` in units of the double spacing at |reference| (at least 2⁻¹⁰²²).
double ulps(double value, long double reference) {
  const long double spacing =
      std::ldexp(1.0L, std::max(std::ilogb(static_cast<double>(reference)), -1022) - 52);
  return static_cast<double>(std::fabs(static_cast<long double>(value) - reference) / spacing);
}

void check_range(double range, double max_ulps) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-range, range);
  std::vector<double> q(997), c(997), s(997);
  double worst_s = 0, worst_c = 0;
  for (int trial = 0; trial < 200; ++trial) {
    for (double& x : q) x = u(rng);
    spatial::detail::sincos_all<double>(q, c, s, static_cast<int>(q.size()));
    for (std::size_t i = 0; i < q.size(); ++i) {
      const long double x = q[i];
      worst_s = std::max(worst_s, ulps(s[i], std::sin(x)));
      worst_c = std::max(worst_c, ulps(c[i], std::cos(x)));
    }
  }
  ::testing::Test::RecordProperty("worst_sin_ulps", std::to_string(worst_s));
  ::testing::Test::RecordProperty("worst_cos_ulps", std::to_string(worst_c));
  EXPECT_LE(worst_s, max_ulps) << "range ±" << range;
  EXPECT_LE(worst_c, max_ulps) << "range ±" << range;
}

TEST(Sincos, WithinOneAndAHalfUlpsForJointAngles) { check_range(4.0, 1.5); }
TEST(Sincos, WithinTwoAndAHalfUlpsUpTo1e5) { check_range(99999.0, 2.5); }

TEST(Sincos, QuadrantBoundariesAndSpecialValues) {
  const double pi = 3.14159265358979323846;
  std::vector<double> q = {0.0, pi / 4, pi / 2, 3 * pi / 4, pi, -pi / 2, -pi, 2 * pi, 1e-300, -1e-300,
                           1e5,        // first value through the C library
                           -2.5e7, 1e300,
                           std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()};
  std::vector<double> c(q.size()), s(q.size());
  spatial::detail::sincos_all<double>(q, c, s, static_cast<int>(q.size()));
  for (std::size_t i = 0; i + 2 < q.size(); ++i) {
    EXPECT_LE(ulps(s[i], std::sin(static_cast<long double>(q[i]))), 2.5) << "sin " << q[i];
    EXPECT_LE(ulps(c[i], std::cos(static_cast<long double>(q[i]))), 2.5) << "cos " << q[i];
  }
  for (std::size_t i = q.size() - 2; i < q.size(); ++i) {
    EXPECT_TRUE(std::isnan(s[i])) << q[i];
    EXPECT_TRUE(std::isnan(c[i])) << q[i];
  }
}

TEST(Sincos, FloatAndLongDoubleFollowTheirOwnPrecision) {
  std::vector<float> qf = {0.1f, -2.0f, 3.0f, 1000.5f}, cf(4), sf(4);
  spatial::detail::sincos_all<float>(qf, cf, sf, 4);
  std::vector<long double> ql = {0.1L, -2.0L, 3.0L, 1000.5L}, cl(4), sl(4);
  spatial::detail::sincos_all<long double>(ql, cl, sl, 4);
  for (int i = 0; i < 4; ++i) {
    // float goes through the double kernel: at most one float spacing from the correctly rounded value.
    const float s_ref = static_cast<float>(std::sin(static_cast<double>(qf[i])));
    const float c_ref = static_cast<float>(std::cos(static_cast<double>(qf[i])));
    EXPECT_LE(std::fabs(sf[i] - s_ref), std::nextafter(std::fabs(s_ref), 2.0f) - std::fabs(s_ref));
    EXPECT_LE(std::fabs(cf[i] - c_ref), std::nextafter(std::fabs(c_ref), 2.0f) - std::fabs(c_ref));
    EXPECT_EQ(sl[i], std::sin(ql[i]));
    EXPECT_EQ(cl[i], std::cos(ql[i]));
  }
}

}  // namespace
