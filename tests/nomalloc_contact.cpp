// constrained_forward_dynamics, impulse_dynamics, contact_inverse_dynamics (contact.hpp) and the ZMP and CoP
// (zmp.hpp) never allocate once their ContactData is built:
// calls on the HOAP-3's floating model (compile-time and run-time trees, both feet welded, then point contacts) and
// on a fixed-base run-time chain with an end-effector constraint, inside the guarded region. Guarded by Eigen's
// run-time check and by the counting global operator new of nomalloc_algorithms.cpp (same executable).

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>

#include "support/no_allocation.hpp"
#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <random>
#include <type_traits>
#include <vector>

namespace {

using namespace spatial;
namespace st = spatial::testing;
using spatial::testing::NoAllocationRegion;

volatile double g_sink = 0.0;

template <class M, class D, class Q, class V>
void exercise(const M& model, D& data, ContactData<M>& cd, const Q& q, const V& v, const V& tau) {
  NoAllocationRegion guard;
  constrained_forward_dynamics(model, data, cd, q, v, tau);
  g_sink = g_sink + cd.qdd.sum() + cd.lambda.sum();
  impulse_dynamics(model, data, cd, q, v, 0.2);
  g_sink = g_sink + cd.v_after.sum() + cd.lambda.sum();
  set_contact_targets(model, data, cd, q);
  cd.contacts[0].kp = 10.0;
  constrained_forward_dynamics(model, data, cd, q, v, tau);
  g_sink = g_sink + cd.qdd.sum();
  EXPECT_TRUE(cd.ok);
  g_sink = g_sink + center_of_pressure(model, data, cd).sum() + multibody_zmp(model, data, q, v, cd.qdd).sum();
  if constexpr (std::is_same_v<M, FloatingModel<typename M::Scalar, typename M::tree_type>>) {
    for (auto& c : cd.contacts) c.sole_x_min = -0.05, c.sole_x_max = 0.05, c.sole_y_min = -0.03, c.sole_y_max = 0.03;
    contact_inverse_dynamics(model, data, cd, q, v, cd.qdd);
    g_sink = g_sink + cd.tau.sum() + cd.lambda.sum();
  }
  EXPECT_EQ(guard.new_calls(), 0);
}

TEST(NoMallocContact, Hoap3FeetCompileTimeAndRunTime) {
  namespace hf = models::hoap3_floating;
  std::mt19937 rng(5);
  const auto ct = hf::floating_model();
  const auto rt = ct.to_runtime();
  const int l = hf::frame_index("L_SOLE"), r = hf::frame_index("R_SOLE");
  const Eigen::VectorXd q = neutral(rt), v = st::random_vector(rt.nv(), rng), tau = st::random_vector(rt.nv(), rng);
  for (const auto& contacts : {std::vector<RigidContact<double>>{contact_6d(l), contact_6d(r)},
                               std::vector<RigidContact<double>>{contact_3d(l), contact_3d(r, ReferenceFrame::Local)}}) {
    FloatingData<double> d(rt);
    ContactData<FloatingModel<double>> cd(rt, contacts);
    exercise(rt, d, cd, q, v, tau);
    FloatingData<double, hf::Tree> dc(ct);
    ContactData<std::decay_t<decltype(ct)>> cdc(ct, contacts);
    const Eigen::Matrix<double, hf::nq, 1> qc = q;
    const Eigen::Matrix<double, hf::nv, 1> vc = v, tc = tau;
    exercise(ct, dc, cdc, qc, vc, tc);
  }
}

TEST(NoMallocContact, FixedBaseChain) {
  std::mt19937 rng(6);
  const Model<double> model = st::build_model_with_frames(st::random_bodies(8, st::Shape::Chain, 6), 6);
  Data<double> d(model);
  ContactData<Model<double>> cd(model, {contact_3d(1)});
  const Eigen::VectorXd q = st::random_vector(8, rng), v = st::random_vector(8, rng), tau = st::random_vector(8, rng);
  exercise(model, d, cd, q, v, tau);
}

}  // namespace
