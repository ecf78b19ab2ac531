// Part of bench_pinocchio (pinocchio_bench.hpp): floating27, Pinocchio's free-flyer model of the HOAP-3, on the
// same states as bench_floating: rnea, crba, aba, the joint and frame Jacobians, the centre of mass's Jacobian, the
// centroidal momentum matrix, constraint and impulse dynamics with the soles welded, and the frame velocity and
// acceleration derivatives; checked against spatial on the first 32 states, then timed.
#include "pinocchio_bench.hpp"

// constraintDynamics and impulseDynamics are marked "unsupported" (their API may change): no warning for using them.
#define PINOCCHIO_DISABLE_UNSUPPORTED_WARNINGS
#include <pinocchio/algorithm/constrained-dynamics.hpp>
#include <pinocchio/algorithm/impulse-dynamics.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/center-of-mass.hpp>
#include <pinocchio/algorithm/centroidal.hpp>
#include <pinocchio/algorithm/frames-derivatives.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/kinematics-derivatives.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea.hpp>

#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace {
using namespace spatial;
using namespace spatial::bench;
using namespace spatial::peers;

struct FloatingPinFixture : FloatingPinStates {
  pinocchio::Data::Matrix6x J;      // frame Jacobian output
  pinocchio::FrameIndex frame = 0;  // the left sole (bench_floating.hpp's floating27_frame)
  // Contacts (bench_floating's ContactDynamics_*): the left sole welded, both soles welded (6D, LOCAL); one data
  // per set (initConstraintDynamics sizes it); τ = u with a zero root wrench.
  // (std::vector with Eigen's aligned allocator: Pinocchio 3 deprecates its PINOCCHIO_ALIGNED_STD_VECTOR for it.)
  template <class T>
  using Aligned = std::vector<T, Eigen::aligned_allocator<T>>;
  Aligned<pinocchio::RigidConstraintModel> left_c, feet_c;
  Aligned<pinocchio::RigidConstraintData> left_d, feet_d;
  pinocchio::DataTpl<double> data_left, data_feet;
  pinocchio::ProximalSettings prox;
  std::vector<Eigen::VectorXd> tau;
  explicit FloatingPinFixture(FloatingPinocchioPeer<double> p)
      : FloatingPinStates(std::move(p)), J(6, peer.tree.model.nv), data_left(peer.tree.model),
        data_feet(peer.tree.model) {
    J.setZero();
    const auto& pm = peer.tree.model;
    const auto weld = [&](const char* name) {
      const pinocchio::Frame& f = pm.frames[pm.getFrameId(name)];
      return pinocchio::RigidConstraintModel(pinocchio::CONTACT_6D, pm, f.parentJoint, f.placement, pinocchio::LOCAL);
    };
    left_c.push_back(weld("L_SOLE"));
    feet_c.push_back(weld("L_SOLE"));
    feet_c.push_back(weld("R_SOLE"));
    for (const auto& c : left_c) left_d.emplace_back(c);
    for (const auto& c : feet_c) feet_d.emplace_back(c);
    pinocchio::initConstraintDynamics(pm, data_left, left_c, left_d);
    pinocchio::initConstraintDynamics(pm, data_feet, feet_c, feet_d);
    const auto& pool = floating_pool();
    for (int k = 0; k < pool.size(); ++k) {
      // fixed size: on a VectorXd, head(6).setZero() made g++ 12 warn -Wstringop-overflow (a size it cannot see)
      Eigen::Matrix<double, FloatingModel<double, Floating27Tree>::NV, 1> t = pool.u[static_cast<std::size_t>(k)];
      t.head<6>().setZero();
      tau.push_back(peer.to_pinocchio(t, 6));
    }
  }
};

const bool registered = [] {
  const auto& model = floating27();
  auto fx = std::make_shared<FloatingPinFixture>(make_pinocchio_floating_peer(model));
  const auto& pool = floating_pool();
  const auto& pm = fx->peer.tree.model;
  const int frame = floating27_frame();
  fx->frame = pm.getFrameId(std::string(models::hoap3_floating::frame_names[static_cast<std::size_t>(frame)]));
  // The check: RNEA τ (root wrench included), CRBA H, ABA v̇, the sole's Jacobian in the three frames (from the
  // joint Jacobians and in one walk), the CoM Jacobian and A_G on the first 32 states.
  FloatingData<double, Floating27Tree> data(model);
  PeerCheck tau{"Pinocchio rnea tau (double) on floating27", 1e-12},
      mass{"Pinocchio crba H (upper triangle) (double) on floating27", 1e-12},
      fd{"Pinocchio aba qdd (double) on floating27", 1e-10},
      jac{"Pinocchio getFrameJacobian L_SOLE LOCAL/WORLD/LOCAL_WORLD_ALIGNED (double) on floating27", 1e-12},
      cjac{"Pinocchio computeFrameJacobian L_SOLE LOCAL/WORLD/LOCAL_WORLD_ALIGNED (double) on floating27", 1e-12},
      jcom{"Pinocchio jacobianCenterOfMass (double) on floating27", 1e-12},
      ag{"Pinocchio ccrba A_G (double) on floating27", 1e-12},
      cfd{"Pinocchio constraintDynamics L_SOLE / both soles 6D LOCAL ddq (double) on floating27", 1e-10},
      clam{"Pinocchio constraintDynamics L_SOLE / both soles 6D LOCAL lambda_c (double) on floating27", 1e-10},
      imp{"Pinocchio impulseDynamics both soles 6D LOCAL dq_after (double) on floating27", 1e-10},
      ilam{"Pinocchio impulseDynamics both soles 6D LOCAL impulse_c (double) on floating27", 1e-10};
  ContactData<std::decay_t<decltype(model)>> left(model, {contact_6d(models::hoap3_floating::frame_index("L_SOLE"))}),
      feet(model, {contact_6d(models::hoap3_floating::frame_index("L_SOLE")),
                   contact_6d(models::hoap3_floating::frame_index("R_SOLE"))});
  const char* const rf_names[3] = {"LOCAL", "WORLD", "LOCAL_WORLD_ALIGNED"};
  const char* const partials[5] = {"v_partial_dq", "a_partial_dq", "a_partial_dv", "a_partial_da", "v_partial_dv"};
  std::vector<PeerCheck> fkd;
  for (const char* rfn : rf_names)
    for (const char* part : partials)
      fkd.push_back({std::string("Pinocchio getFrame{Velocity,Acceleration}Derivatives L_SOLE ") + part + " " + rfn +
                         " (double) on floating27",
                     1e-12});
  FrameKinematicsDerivatives<double, 27> kd(model);
  const std::pair<pinocchio::ReferenceFrame, ReferenceFrame> frames[] = {
      {pinocchio::LOCAL, ReferenceFrame::Local},
      {pinocchio::WORLD, ReferenceFrame::World},
      {pinocchio::LOCAL_WORLD_ALIGNED, ReferenceFrame::LocalWorldAligned}};
  Eigen::Matrix<double, 6, 27> J, Ag;
  Eigen::Matrix<double, 3, 27> Jc;
  using VQ = Eigen::Matrix<double, 28, 1>;
  using VV = Eigen::Matrix<double, 27, 1>;
  for (int k = 0; k < 32; ++k) {
    const auto s = static_cast<std::size_t>(k);
    const VQ q = pool.q[s];
    const VV v = pool.v[s], u = pool.u[s];
    tau.compare(fx->peer.from_pinocchio(pinocchio::rnea(pm, fx->data, fx->q[s], fx->v[s], fx->u[s])),
                rnea(model, data, q, v, u));
    Eigen::MatrixXd M = pinocchio::crba(pm, fx->data, fx->q[s]);
    M.triangularView<Eigen::StrictlyLower>() = M.transpose().triangularView<Eigen::StrictlyLower>();
    mass.compare(fx->peer.from_pinocchio_matrix(M), crba(model, data, q));
    fd.compare(fx->peer.from_pinocchio(pinocchio::aba(pm, fx->data, fx->q[s], fx->v[s], fx->u[s])),
               aba(model, data, q, v, u));
    pinocchio::computeJointJacobians(pm, fx->data, fx->q[s]);
    compute_joint_jacobians(model, data, q);
    for (const auto& [prf, rf] : frames) {
      Eigen::MatrixXd Jp = Eigen::MatrixXd::Zero(6, pm.nv);
      pinocchio::getFrameJacobian(pm, fx->data, fx->frame, prf, Jp);
      frame_jacobian(model, data, frame, rf, J);
      jac.compare(fx->peer.from_pinocchio_columns(Jp), J);
    }
    for (const auto& [prf, rf] : frames) {
      Eigen::MatrixXd Jp = Eigen::MatrixXd::Zero(6, pm.nv);
      pinocchio::computeFrameJacobian(pm, fx->data, fx->q[s], fx->frame, prf, Jp);
      compute_frame_jacobian(model, data, q, frame, rf, J);
      cjac.compare(fx->peer.from_pinocchio_columns(Jp), J);
    }
    com_jacobian(model, data, q, Jc);
    jcom.compare(fx->peer.from_pinocchio_columns(pinocchio::jacobianCenterOfMass(pm, fx->data, fx->q[s])), Jc);
    centroidal_momentum_matrix(model, data, q, Ag);
    ag.compare(fx->peer.from_pinocchio_columns(pinocchio::ccrba(pm, fx->data, fx->q[s], fx->v[s])), Ag);
    // Contacts: the same τ (zero root wrench), no Baumgarte terms, no proximal damping.
    VV t = u;
    t.head<6>().setZero();
    cfd.compare(fx->peer.from_pinocchio(pinocchio::constraintDynamics(pm, fx->data_left, fx->q[s], fx->v[s], fx->tau[s],
                                                                      fx->left_c, fx->left_d, fx->prox)),
                constrained_forward_dynamics(model, data, left, q, v, t));
    clam.compare(Eigen::VectorXd(fx->data_left.lambda_c), left.lambda);
    cfd.compare(fx->peer.from_pinocchio(pinocchio::constraintDynamics(pm, fx->data_feet, fx->q[s], fx->v[s], fx->tau[s],
                                                                      fx->feet_c, fx->feet_d, fx->prox)),
                constrained_forward_dynamics(model, data, feet, q, v, t));
    clam.compare(Eigen::VectorXd(fx->data_feet.lambda_c), feet.lambda);
    imp.compare(fx->peer.from_pinocchio(pinocchio::impulseDynamics(pm, fx->data_feet, fx->q[s], fx->v[s], fx->feet_c,
                                                                   fx->feet_d, 0.0, fx->prox)),
                impulse_dynamics(model, data, feet, q, v));
    ilam.compare(Eigen::VectorXd(fx->data_feet.impulse_c), feet.lambda);
    // Frame velocity and acceleration derivatives (the state's u as the acceleration).
    pinocchio::computeForwardKinematicsDerivatives(pm, fx->data, fx->q[s], fx->v[s], fx->u[s]);
    for (std::size_t f = 0; f < 3; ++f) {
      const auto& [prf, rf] = frames[f];
      Eigen::MatrixXd p[5];
      for (auto& x : p) x = Eigen::MatrixXd::Zero(6, pm.nv);
      pinocchio::getFrameAccelerationDerivatives(pm, fx->data, fx->frame, prf, p[0], p[1], p[2], p[3]);
      pinocchio::getFrameVelocityDerivatives(pm, fx->data, fx->frame, prf, p[0], p[4]);
      frame_kinematics_derivatives(model, data, kd, q, v, u, frame, rf);
      const Eigen::Matrix<double, 6, 27>* ours[5] = {&kd.v_dq, &kd.a_dq, &kd.a_dv, &kd.a_da, &kd.v_dv};
      // LOCAL_WORLD_ALIGNED ∂/∂q: Pinocchio shifts the joint's derivative to the frame by the joint-to-frame offset
      // held constant (its frames-derivatives.hxx), which is not the derivative of getFrameVelocity/Acceleration in
      // LOCAL_WORLD_ALIGNED when the body turns (pinocchio#2702); ours is (tests/test_frame_derivatives.cpp checks
      // it by finite differences). Those two are not compared; everything else is.
      for (std::size_t m = 0; m < 5; ++m)
        if (!(rf == ReferenceFrame::LocalWorldAligned && m < 2))
          fkd[5 * f + m].compare(fx->peer.from_pinocchio_columns(p[m]), *ours[m]);
    }
  }
  for (const PeerCheck* c : {&tau, &mass, &fd, &jac, &cjac, &jcom, &ag, &cfd, &clam, &imp, &ilam}) c->report();
  for (std::size_t k = 0; k < fkd.size(); ++k)
    if (k != 10 && k != 11) fkd[k].report();  // LOCAL_WORLD_ALIGNED v_partial_dq, a_partial_dq: see above

  using Fx = FloatingPinFixture;
  const auto reg = [&](const char* algorithm, auto body) {
    register_pinocchio_call(fx, "floating27", "double", algorithm, body);
  };
  reg("RNEA", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::rnea(f.peer.tree.model, f.data, f.q[k], f.v[k], f.u[k]).data());
  });
  reg("CRBA", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::crba(f.peer.tree.model, f.data, f.q[k]).data());
  });
  reg("ABA", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::aba(f.peer.tree.model, f.data, f.q[k], f.v[k], f.u[k]).data());
  });
  reg("JointJacobians", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::computeJointJacobians(f.peer.tree.model, f.data, f.q[k]).data());
  });
  // getFrameJacobian after computeJointJacobians (bench_floating: frame_jacobian after compute_joint_jacobians).
  pinocchio::computeJointJacobians(pm, fx->data, fx->q[0]);
  reg("FrameJacobian", [](Fx& f, std::size_t) {
    pinocchio::getFrameJacobian(f.peer.tree.model, f.data, f.frame, pinocchio::LOCAL_WORLD_ALIGNED, f.J);
    benchmark::DoNotOptimize(f.J.data());
    benchmark::ClobberMemory();
  });
  reg("ComputeFrameJacobian", [](Fx& f, std::size_t k) {
    pinocchio::computeFrameJacobian(f.peer.tree.model, f.data, f.q[k], f.frame, pinocchio::LOCAL_WORLD_ALIGNED, f.J);
    benchmark::DoNotOptimize(f.J.data());
    benchmark::ClobberMemory();
  });
  reg("ComJacobian", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::jacobianCenterOfMass(f.peer.tree.model, f.data, f.q[k], false).data());
  });
  reg("CentroidalMatrix", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::ccrba(f.peer.tree.model, f.data, f.q[k], f.v[k]).data());
  });
  reg("ContactDynamics_6D", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::constraintDynamics(f.peer.tree.model, f.data_left, f.q[k], f.v[k], f.tau[k],
                                                           f.left_c, f.left_d, f.prox).data());
  });
  reg("ContactDynamics_2x6D", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::constraintDynamics(f.peer.tree.model, f.data_feet, f.q[k], f.v[k], f.tau[k],
                                                           f.feet_c, f.feet_d, f.prox).data());
  });
  reg("ImpulseDynamics_2x6D", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::impulseDynamics(f.peer.tree.model, f.data_feet, f.q[k], f.v[k], f.feet_c,
                                                        f.feet_d, 0.0, f.prox).data());
  });
  return true;
}();

}  // namespace
