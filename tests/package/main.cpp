// Built against an installed spatial by the package_consumer test: the README's example, as an outside user
// would write it. It succeeds when the installed headers are found, C++17 is switched on by the target, Eigen
// comes along as a dependency, and the example's numbers are right (forward dynamics inverts inverse dynamics).
#include <spatial/spatial.hpp>

#include <cstdio>

static_assert(__cplusplus >= 201703L, "spatial::spatial must request C++17");

int main() {
  using namespace spatial;
  ModelBuilder<double> b;  // a two-link arm, joints about z
  auto link = Inertia<double>::from_com(1.0, {0.25, 0, 0}, Matrix3<double>::Identity() * 1e-3);
  int upper = b.add_body("upper", -1, JointType::RevoluteZ, Transform<double>::Identity(), link);
  b.add_body("fore", upper, JointType::RevoluteZ, xlt<double>({0.5, 0, 0}), link);
  Model<double> model = b.build();
  Data<double> data(model);
  Eigen::Vector2d q(0.3, -0.2), qd(1, 0), qdd(0, 2);
  Eigen::Vector2d tau = rnea(model, data, q, qd, qdd);
  Eigen::Vector2d acc = aba(model, data, q, qd, tau);

  using Arm = Tree<Parents<-1, 0>, Joints<JointType::RevoluteZ, JointType::RevoluteZ>>;
  Model<double, Arm> fixed = Model<double, Arm>::from(model);
  Data<double, Arm> fixed_data(fixed);
  Eigen::Vector2d tau_fixed = rnea(fixed, fixed_data, q, qd, qdd);

  if (!acc.isApprox(qdd, 1e-12) || !tau_fixed.isApprox(tau, 1e-14) || !(tau.norm() > 0)) {
    std::fprintf(stderr, "unexpected results: tau = (%g, %g), acc = (%g, %g)\n", tau[0], tau[1], acc[0], acc[1]);
    return 1;
  }
  std::printf("spatial package consumer: ok, tau = (%.6f, %.6f)\n", tau[0], tau[1]);
  return 0;
}
