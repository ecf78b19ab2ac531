// The batched algorithms (batch.hpp) never allocate after construction, on one thread and on two (the worker pool
// is woken, not started, per call): a run-time tree of every joint type, a floating one (FloatingBatch) and the
// compile-time HOAP-3 stance model, double and float, every method, B not a multiple of the lane count.
// Guards: tests/support/no_allocation.hpp.
#include <spatial/batch.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include "support/no_allocation.hpp"
#include "support/random_model.hpp"

#include <gtest/gtest.h>

namespace {

using namespace spatial;
namespace st = spatial::testing;
using spatial::testing::NoAllocationRegion;

/// Every method of the batch of `model`: Batch for a `Model`, FloatingBatch for a `FloatingModel` (q with nq = nv + 1
/// rows, its quaternion normalised).
template <class MT>
void expect_no_allocation(const MT& model, int threads) {
  using S = typename MT::Scalar;
  using Traits = detail::ModelTraits<MT>;
  constexpr bool floating = Traits::voff != 0;
  using BatchT = BasicBatch<S, typename MT::tree_type, floating>;
  using M = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  BatchT batch(model, threads);
  const int nq = Traits::nq(model), n = Traits::nv(model), B = 3 * BatchT::lanes + 1;
  M Q = M::Random(nq, B);
  if constexpr (floating)
    for (int j = 0; j < B; ++j) Q.col(j).template segment<4>(3).normalize();
  const M V = M::Random(n, B), A = M::Random(n, B);
  M tau(n, B), qdd(n, B), H(n, n * B), P = M::Zero(3, 4 * B), J = M::Zero(6, n * B);
  long news = -1;
  {
    NoAllocationRegion guard;
    batch.rnea(Q, V, A, tau);
    batch.gravity(Q, tau);
    batch.bias(Q, V, tau);
    batch.aba(Q, V, A, qdd);
    batch.forward_dynamics_crba(Q, V, A, qdd);
    batch.crba(Q, H);
    batch.frame_placement(Q, 0, P);
    batch.frame_jacobian(Q, 0, ReferenceFrame::LocalWorldAligned, J);
    batch.body_placement(Q, 1, P);
    batch.body_jacobian(Q, 1, ReferenceFrame::Local, J);
    news = guard.new_calls();
  }
  EXPECT_EQ(news, 0) << threads << " thread(s)";
  EXPECT_TRUE(tau.allFinite() && qdd.allFinite() && H.allFinite() && P.allFinite() && J.allFinite());
}

TEST(NoMallocBatch, RunTimeFloatingTreeOfEveryJointType) {
  std::mt19937 rng(7);
  const FloatingModel<double> model(st::build_model_with_frames(st::random_bodies(9, st::Shape::Branched, 7, true), 7),
                                    st::random_root_inertia(rng), "root");
  for (const int threads : {1, 2}) {
    expect_no_allocation(model, threads);
    expect_no_allocation(model.cast<float>(), threads);
  }
}

TEST(NoMallocBatch, RunTimeTreeOfEveryJointType) {
  const Model<double> model =
      st::build_model_with_frames(st::random_bodies(11, st::Shape::Branched, 5, true), 5);
  for (const int threads : {1, 2}) {
    expect_no_allocation(model, threads);
    expect_no_allocation(model.cast<float>(), threads);
  }
}

TEST(NoMallocBatch, CompileTimeStanceModel) {
  // double only here: float takes the same code over the same tree (and is checked on the run-time tree above).
  const auto model = models::hoap3_stance_right::model();
  for (const int threads : {1, 2}) expect_no_allocation(model, threads);
}

}  // namespace
