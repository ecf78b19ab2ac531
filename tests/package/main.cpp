// Built against an installed spatial by the package_consumer test. It succeeds when the installed headers are
// found, C++17 is switched on by the target, and Eigen comes along as a dependency.
#include <spatial/spatial.hpp>

#include <Eigen/Core>

#include <cstdio>
#include <optional>

static_assert(__cplusplus >= 201703L, "spatial::spatial must request C++17");

int main() {
  const Eigen::Matrix3d a = Eigen::Matrix3d::Identity() * 2.0;
  const Eigen::Vector3d b(1.0, 2.0, 3.0);
  const std::optional<Eigen::Vector3d> c = a * b;  // std::optional: a C++17 feature
  if (!c || !c->isApprox(Eigen::Vector3d(2.0, 4.0, 6.0))) {
    std::fprintf(stderr, "unexpected result from Eigen\n");
    return 1;
  }
  std::printf("spatial package consumer: ok\n");
  return 0;
}
