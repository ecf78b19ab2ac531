// Built against an installed spatial by the package_consumer test: the batched algorithms (<spatial/batch.hpp>,
// component batch: spatial::batch brings xsimd and threads) on a generated model, against the single-state call.
#include <spatial/batch.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include <cmath>
#include <cstdio>

int main() {
  namespace stance = spatial::models::hoap3_stance_right;
  const auto model = stance::model();
  spatial::Batch<double, stance::Tree> batch(model, 2);
  const int B = 2 * spatial::Batch<double, stance::Tree>::lanes + 1;
  const Eigen::MatrixXd Q = Eigen::MatrixXd::Random(stance::dof, B);
  const Eigen::MatrixXd V = Eigen::MatrixXd::Random(stance::dof, B);
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(stance::dof, B);
  Eigen::MatrixXd tau(stance::dof, B);
  batch.rnea(Q, V, A, tau);
  spatial::Data<double, stance::Tree> data(model);
  double worst = 0;
  for (int j = 0; j < B; ++j) {
    const Eigen::Matrix<double, stance::dof, 1> q = Q.col(j), v = V.col(j), a = A.col(j);
    worst = std::fmax(worst, (spatial::rnea(model, data, q, v, a) - tau.col(j)).cwiseAbs().maxCoeff());
  }
  if (!(worst < 1e-10)) {
    std::fprintf(stderr, "batched RNEA differs from the single-state call by %g\n", worst);
    return 1;
  }
  std::printf("spatial batch consumer: ok, %d states in groups of %d lanes, max difference %.1e\n", B,
              spatial::Batch<double, stance::Tree>::lanes, worst);
  return 0;
}
