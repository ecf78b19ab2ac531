// Temporary: only here to validate the build infrastructure. Deleted when the library lands.
#include <spatial/spatial.hpp>

#include <gtest/gtest.h>

TEST(Placeholder, EigenVector3dWorks) {
  const Eigen::Vector3d a(1.0, 2.0, 3.0);
  const Eigen::Vector3d b(4.0, 5.0, 6.0);
  EXPECT_DOUBLE_EQ(a.dot(b), 32.0);
  EXPECT_TRUE((a + b).isApprox(Eigen::Vector3d(5.0, 7.0, 9.0)));
}
