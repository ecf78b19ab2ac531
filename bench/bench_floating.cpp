// Run time of the floating-base algorithms on floating27 (the HOAP-3 free-flying at the pelvis, nv = 27;
// bench_floating.hpp): RNEA, CRBA, ABA and forward dynamics by CRBA + LTDL; all joint Jacobians (JointJacobians),
// the left sole's Jacobian from them (FrameJacobian) and in one walk (ComputeFrameJacobian), both
// LOCAL_WORLD_ALIGNED; the CoM Jacobian (ComJacobian) and the centroidal momentum matrix (CentroidalMatrix);
// compile-time and run-time trees, double. Names "spatial/<algorithm>/floating27/double/<static|runtime>";
// bench_pinocchio times Pinocchio's free-flyer model of the same robot on the same states (computeJointJacobians,
// getFrameJacobian, computeFrameJacobian, jacobianCenterOfMass, ccrba).
// IK_FeetCoM: inverse kinematics (ik.hpp) of both soles' poses and the centre of mass (15 rows, joint limits on)
// to 1e-12, targets from forward kinematics of a pool state, started from that state perturbed by 0.05 × a pool
// velocity on the manifold (one whole solve per call).
// Contacts (contact.hpp): ContactDynamics_6D (the left sole welded), ContactDynamics_2x6D (both soles) by
// constrained_forward_dynamics, ImpulseDynamics_2x6D (both soles, inelastic) by impulse_dynamics; τ from the pool,
// its root wrench zeroed; bench_pinocchio times constraintDynamics / impulseDynamics on the same states.
#include "bench_common.hpp"
#include "bench_derivatives.hpp"
#include "bench_floating.hpp"

namespace {
using namespace spatial;
using namespace spatial::bench;

template <class S, class TreeT>
struct FloatingFixture {
  FloatingModel<S, TreeT> model;
  FloatingData<S, TreeT> data;
  FloatingPool<S, FloatingModel<S, TreeT>::NQ, FloatingModel<S, TreeT>::NV> pool;
  Eigen::Matrix<S, 6, FloatingModel<S, TreeT>::NV> J, Ag;
  Eigen::Matrix<S, 3, FloatingModel<S, TreeT>::NV> Jc;
  int frame;
  explicit FloatingFixture(const FloatingModel<S, TreeT>& m)
      : model(m), data(model),
        pool(floating_pool().template cast<S, FloatingModel<S, TreeT>::NQ, FloatingModel<S, TreeT>::NV>()),
        J(6, model.nv()), Ag(6, model.nv()), Jc(3, model.nv()), frame(floating27_frame()) {}
};

template <class S, class TreeT>
void register_floating(const std::string& tree, const FloatingModel<S, TreeT>& model) {
  using Fx = FloatingFixture<S, TreeT>;
  auto fx = std::make_shared<Fx>(model);
  const auto name = [&](const char* algorithm) {
    return bench_name("spatial", algorithm, "floating27", scalar_name<S>(), tree);
  };
  const auto at = [](const auto& v, int k) -> const auto& { return v[static_cast<std::size_t>(k)]; };
  register_one(name("RNEA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(rnea(f.model, f.data, at(f.pool.q, k), at(f.pool.v, k), at(f.pool.u, k)).data());
  });
  register_one(name("CRBA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(crba(f.model, f.data, at(f.pool.q, k)).data());
  });
  register_one(name("ABA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(aba(f.model, f.data, at(f.pool.q, k), at(f.pool.v, k), at(f.pool.u, k)).data());
  });
  register_one(name("FD_CRBA_LTDL"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(
        forward_dynamics_crba(f.model, f.data, at(f.pool.q, k), at(f.pool.v, k), at(f.pool.u, k)).data());
  });
  register_one(name("JointJacobians"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(compute_joint_jacobians(f.model, f.data, at(f.pool.q, k)).data());
  });
  // From the joint Jacobians of the last state (Pinocchio's getFrameJacobian after computeJointJacobians).
  compute_joint_jacobians(fx->model, fx->data, fx->pool.q[0]);
  register_one(name("FrameJacobian"), fx, [](Fx& f, int) {
    frame_jacobian(f.model, f.data, f.frame, ReferenceFrame::LocalWorldAligned, f.J);
    benchmark::DoNotOptimize(f.J.data());
    benchmark::ClobberMemory();
  });
  register_one(name("ComputeFrameJacobian"), fx, [at](Fx& f, int k) {
    compute_frame_jacobian(f.model, f.data, at(f.pool.q, k), f.frame, ReferenceFrame::LocalWorldAligned, f.J);
    benchmark::DoNotOptimize(f.J.data());
    benchmark::ClobberMemory();
  });
  register_one(name("ComJacobian"), fx, [at](Fx& f, int k) {
    com_jacobian(f.model, f.data, at(f.pool.q, k), f.Jc);
    benchmark::DoNotOptimize(f.Jc.data());
    benchmark::ClobberMemory();
  });
  register_one(name("CentroidalMatrix"), fx, [at](Fx& f, int k) {
    centroidal_momentum_matrix(f.model, f.data, at(f.pool.q, k), f.Ag);
    benchmark::DoNotOptimize(f.Ag.data());
    benchmark::ClobberMemory();
  });
}

/// Targets (both soles, CoM) and perturbed starts for every pool state, and one solver.
template <class S, class TreeT>
struct IkFixture {
  using FM = FloatingModel<S, TreeT>;
  FM model;
  FloatingPool<S, FM::NQ, FM::NV> pool;
  std::vector<Eigen::Matrix<S, FM::NQ, 1>> start;
  std::vector<Eigen::Transform<S, 3, Eigen::Isometry>> right, left;
  std::vector<Vector3<S>> com;
  IkSolver<FM> ik;
  Eigen::Matrix<S, FM::NQ, 1> q;
  static IkOptions<S> options() {
    namespace fb = models::hoap3_floating;
    IkOptions<S> o;
    o.lower = ik_limits<S>(fb::lower), o.upper = ik_limits<S>(fb::upper);
    return o;
  }
  explicit IkFixture(const FM& m)
      : model(m), pool(floating_pool().template cast<S, FM::NQ, FM::NV>()),
        ik(model,
           {ik_pose(frame("R_SOLE"), Vector3<S>::Zero(), Matrix3<S>::Identity()),
            ik_pose(frame("L_SOLE"), Vector3<S>::Zero(), Matrix3<S>::Identity()),
            ik_center_of_mass(Vector3<S>::Zero())},
           options()) {
    FloatingData<S, TreeT> data(model);
    for (int k = 0; k < pool.size(); ++k) {
      const auto kk = static_cast<std::size_t>(k);
      forward_kinematics(model, data, pool.q[kk]);
      right.push_back(frame_pose(model, data, frame("R_SOLE")));
      left.push_back(frame_pose(model, data, frame("L_SOLE")));
      com.push_back(center_of_mass(model, data, pool.q[kk], pool.v[kk] * S(0)));
      start.push_back(integrate(model, pool.q[kk], pool.v[kk], S(0.05)));
    }
  }
  static int frame(const char* name) { return models::hoap3_floating::frame_index(name); }
};

template <class S, class TreeT>
void register_ik(const std::string& tree, const FloatingModel<S, TreeT>& model) {
  using Fx = IkFixture<S, TreeT>;
  auto fx = std::make_shared<Fx>(model);
  register_one(bench_name("spatial", "IK_FeetCoM", "floating27", scalar_name<S>(), tree), fx, [](Fx& f, int k) {
    const auto kk = static_cast<std::size_t>(k);
    f.ik.set_target(0, f.right[kk].translation(), f.right[kk].linear());
    f.ik.set_target(1, f.left[kk].translation(), f.left[kk].linear());
    f.ik.set_target(2, f.com[kk]);
    f.q = f.start[kk];
    benchmark::DoNotOptimize(f.ik.solve(f.q).residual);
  });
}

/// Contact dynamics on the soles: one ContactData per contact set.
template <class S, class TreeT>
struct ContactFixture {
  using FM = FloatingModel<S, TreeT>;
  FM model;
  FloatingData<S, TreeT> data;
  FloatingPool<S, FM::NQ, FM::NV> pool;
  ContactData<FM> left, feet;
  explicit ContactFixture(const FM& m)
      : model(m), data(model), pool(floating_pool().template cast<S, FM::NQ, FM::NV>()),
        left(model, {contact_6d<S>(frame("L_SOLE"))}),
        feet(model, {contact_6d<S>(frame("L_SOLE")), contact_6d<S>(frame("R_SOLE"))}) {
    for (auto& u : pool.u) u.template head<6>().setZero();
  }
  static int frame(const char* name) { return models::hoap3_floating::frame_index(name); }
};

template <class S, class TreeT>
void register_contacts(const std::string& tree, const FloatingModel<S, TreeT>& model) {
  using Fx = ContactFixture<S, TreeT>;
  auto fx = std::make_shared<Fx>(model);
  const auto name = [&](const char* algorithm) {
    return bench_name("spatial", algorithm, "floating27", scalar_name<S>(), tree);
  };
  const auto at = [](const auto& v, int k) -> const auto& { return v[static_cast<std::size_t>(k)]; };
  register_one(name("ContactDynamics_6D"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(
        constrained_forward_dynamics(f.model, f.data, f.left, at(f.pool.q, k), at(f.pool.v, k), at(f.pool.u, k)).data());
  });
  register_one(name("ContactDynamics_2x6D"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(
        constrained_forward_dynamics(f.model, f.data, f.feet, at(f.pool.q, k), at(f.pool.v, k), at(f.pool.u, k)).data());
  });
  register_one(name("ImpulseDynamics_2x6D"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(impulse_dynamics(f.model, f.data, f.feet, at(f.pool.q, k), at(f.pool.v, k)).data());
  });
}

const bool registered = [] {
  add_build_context();
  register_floating<double>("static", floating27());
  register_floating<double>("runtime", floating27().to_runtime());
  const auto derivatives = [](const std::string& tree, const auto& model) {
    using M = std::decay_t<decltype(model)>;
    using T = typename M::tree_type;
    const auto pool = floating_pool().template cast<double, M::NQ, M::NV>();
    register_derivatives<M, FloatingData<double, T>, FloatingDerivativeData<double, T>>(
        model, pool, [&](const char* algorithm) { return bench_name("spatial", algorithm, "floating27", "double", tree); });
  };
  derivatives("static", floating27());
  derivatives("runtime", floating27().to_runtime());
  register_ik<double>("static", floating27());
  register_ik<double>("runtime", floating27().to_runtime());
  register_contacts<double>("static", floating27());
  register_contacts<double>("runtime", floating27().to_runtime());
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
