// The rigid-contact simulator (walking/simulation.hpp): the HOAP-3 standing still on both feet under the torques of
// contact_inverse_dynamics and a joint PD stays still with the static split; a foot that touches down stops
// (impulse) and the kinetic energy drops; Baumgarte stabilisation pulls a displaced weld back critically damped
// (against e(t) = e₀ (1 + ωt) e^{−ωt}); a robot without contacts falls freely; bad settings are refused.

#include <spatial/spatial.hpp>
#include <spatial/walking/simulation.hpp>
#include <spatial/models/hoap3_floating.hpp>

#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <Eigen/SVD>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

using namespace spatial;
using spatial::walking::ContactSimulator;
using spatial::walking::SimulationSettings;
using Vec = Eigen::VectorXd;

std::vector<RigidContact<double>> soles(const FloatingModel<double>& model) {
  std::vector<RigidContact<double>> c;
  for (const char* name : {"L_SOLE", "R_SOLE"}) {
    RigidContact<double> k = contact_6d(model.frame_index(name), ReferenceFrame::LocalWorldAligned);
    k.sole_x_min = -0.054, k.sole_x_max = 0.054, k.sole_y_min = -0.0365, k.sole_y_max = 0.0365;
    c.push_back(k);
  }
  return c;
}

TEST(ContactSimulator, StandingStillStaysStill) {
  const auto model = models::hoap3_floating::floating_model<double>().to_runtime();
  FloatingData<double> data(model);
  ContactData<FloatingModel<double>> id(model, soles(model));
  const Vec q0 = neutral(model), zero = Vec::Zero(model.nv());
  contact_inverse_dynamics(model, data, id, q0, zero, zero);
  ASSERT_TRUE(id.ok);
  ContactSimulator<FloatingModel<double>> sim(model, soles(model));
  sim.reset(q0, zero, 3u);
  const int n = model.njoints();
  // Gains inside the explicit integrator's stability limit for the lightest joint (effective inertia ≈ 1.6e-4 kg m²:
  // kd dt / I < 2).
  const double kp = 20.0, kd = 0.1;
  for (int k = 0; k < 500; ++k) {
    Vec tau = id.tau;
    tau.tail(n) += kp * (q0.tail(n) - sim.q().tail(n)) - kd * sim.v().tail(n);
    tau.head<6>().setZero();
    sim.step(tau, 3u);
  }
  EXPECT_NEAR(sim.time(), 0.5, 1e-12);
  EXPECT_LT(Vec(difference(model, q0, sim.q())).norm(), 1e-9);
  EXPECT_LT(sim.v().norm(), 1e-8);
  // The simulator's forces are the static split (the same physics; LWA axes = the soles' axes here).
  ASSERT_NE(sim.active(), nullptr);
  EXPECT_LT((sim.active()->lambda - id.lambda).norm(), 1e-6 * model.total_mass() * 9.81);
  EXPECT_FALSE(sim.impact());
}

TEST(ContactSimulator, TouchdownStopsTheFootAndTakesEnergy) {
  // On the left foot, the robot moving so that the left sole stays still and the right sole moves; then the right
  // foot is put down: after the impact both soles are still, and the energy has dropped by what the impact reports.
  const auto model = models::hoap3_floating::floating_model<double>().to_runtime();
  const auto feet = soles(model);
  FloatingData<double> data(model);
  const Vec q = neutral(model);
  Eigen::MatrixXd JL = Eigen::MatrixXd::Zero(6, model.nv()), JR = JL;
  compute_frame_jacobian(model, data, q, feet[0].frame, ReferenceFrame::Local, JL);
  compute_frame_jacobian(model, data, q, feet[1].frame, ReferenceFrame::Local, JR);
  std::mt19937 rng(3);
  const Vec x = spatial::testing::random_vector(model.nv(), rng, 0.5);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(JL, Eigen::ComputeFullV);
  const Eigen::MatrixXd N = svd.matrixV().rightCols(model.nv() - 6);
  const Vec v = N * (N.transpose() * x);
  ASSERT_LT((JL * v).norm(), 1e-12);
  ASSERT_GT((JR * v).norm(), 1e-2);
  ContactSimulator<FloatingModel<double>> sim(model, feet);
  sim.reset(q, v, 1u);
  const double before = kinetic_energy(model, data, q, v);
  sim.step(Vec::Zero(model.nv()), 3u);
  EXPECT_TRUE(sim.impact());
  EXPECT_GT(sim.impact_energy_loss(), 0.0);
  // The impact's v⁺ is what the step integrated from: both soles still at the start of the step, so after one step
  // of 1 ms their velocity is of the order of dt J̇ v (the right sole moved at > 1e-2 before).
  const double right_before = (JR * v).norm();
  compute_frame_jacobian(model, data, sim.q(), feet[0].frame, ReferenceFrame::Local, JL);
  compute_frame_jacobian(model, data, sim.q(), feet[1].frame, ReferenceFrame::Local, JR);
  EXPECT_LT((JL * sim.v()).norm(), 0.01 * right_before);
  EXPECT_LT((JR * sim.v()).norm(), 0.01 * right_before);
  EXPECT_LT(kinetic_energy(model, data, sim.q(), sim.v()), before);
  sim.step(Vec::Zero(model.nv()), 3u);
  EXPECT_FALSE(sim.impact());
}

TEST(ContactSimulator, BaumgarteIsCriticallyDamped) {
  // A box welded by its bottom face, whose target is 1 mm above where the face is: the error follows
  // e(t) = e₀ (1 + ωt) e^{−ωt} (to the integrator's first-order error).
  ModelBuilder<double> b;
  b.add_fixed_body("bottom", -1, Transform<double>(Matrix3<double>::Identity(), Eigen::Vector3d(0, 0, -0.05)),
                   Inertia<double>::Zero());
  const FloatingModel<double> box(
      b.build(), Inertia<double>::from_com(2.0, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.03, 0.04).asDiagonal()),
      "box");
  SimulationSettings<double> settings;
  settings.contact_frequency = 20.0;
  settings.dt = 1e-4;
  ContactSimulator<FloatingModel<double>> sim(box, {contact_6d(0)}, settings);
  const Vec q = neutral(box), v = Vec::Zero(6);
  sim.reset(q, v, 1u);
  const double e0 = -1e-3, w = 20.0;  // the face is 1 mm below its target
  sim.set_target(0, Eigen::Vector3d(0, 0, -0.05 - e0), Matrix3<double>::Identity());
  double worst = 0.0;
  for (int k = 1; k <= 2000; ++k) {
    sim.step(Vec::Zero(6), 1u);
    // The face is at z − 0.05 and its target at −0.05 − e₀, so e = z + e₀.
    const double t = sim.time(), e = sim.q()[2] + e0;
    worst = std::max(worst, std::abs(e - e0 * (1 + w * t) * std::exp(-w * t)));
  }
  EXPECT_LT(worst, 0.01 * std::abs(e0)) << "largest departure from the critically damped decay";
  EXPECT_NEAR(sim.q()[2] + e0, e0 * 5 * std::exp(-4.0), 1e-6);  // after 0.2 s (ωt = 4): e₀ · 5 e⁻⁴
}

TEST(ContactSimulator, BadSettingsAreRefused) {
  const auto model = models::hoap3_floating::floating_model<double>().to_runtime();
  SimulationSettings<double> s;
  s.dt = 0.0;
  EXPECT_THROW((ContactSimulator<FloatingModel<double>>(model, soles(model), s)), std::invalid_argument);
  s = {};
  s.restitution = 1.5;
  EXPECT_THROW((ContactSimulator<FloatingModel<double>>(model, soles(model), s)), std::invalid_argument);
  auto five = soles(model);
  five.insert(five.end(), {five[0], five[1], five[0]});
  EXPECT_THROW((ContactSimulator<FloatingModel<double>>(model, five)), std::invalid_argument);
}

TEST(ContactSimulator, WithoutContactItFallsFreely) {
  const auto model = models::hoap3_floating::floating_model<double>().to_runtime();
  ContactSimulator<FloatingModel<double>> sim(model, soles(model));
  const Vec q = neutral(model), zero = Vec::Zero(model.nv());
  sim.reset(q, zero, 0u);
  FloatingData<double> data(model);
  const double z0 = center_of_mass(model, data, q, zero).z();
  for (int k = 0; k < 100; ++k) sim.step(zero, 0u);
  EXPECT_EQ(sim.active(), nullptr);
  const double z1 = center_of_mass(model, data, sim.q(), sim.v()).z();
  // Semi-implicit Euler: z drops by g dt² (1 + 2 + … + 100) = g dt² · 5050.
  EXPECT_NEAR(z0 - z1, 9.81 * 1e-6 * 5050, 1e-9);
}

}  // namespace
