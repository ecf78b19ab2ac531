// Paying only for what a scene uses: each option of include/spatial/options.hpp and each reduced model of
// include/spatial/reduce.hpp against the full computation, on the 21-DoF HOAP-3 stance model (generated header,
// compile-time tree "static", and its run-time twin "runtime"). Inputs come from a pre-generated pool of random
// states with q within the joint limits (stance::lower/upper) and q̇, q̈, τ in [−1, 1]; each call takes the next one.
//
// Names: "scene/<ALGORITHM>.<Variant>/hoap3_stance21/double/<tree>"; tools/report.py pairs every variant with
// "<ALGORITHM>.Full" of the same tree (Savings table). The arm-gesture scene ("ArmsOnly") keeps only the two arms
// (8 DoF) moving, with the legs, waist and chest held at a fixed pose (keep_branches), and is paired with the whole
// body; "ArmsOnlyStatic" is its static RNEA.
#include "bench_common.hpp"

#include <spatial/models/hoap3_stance_right.hpp>

namespace {
using namespace spatial;
using namespace spatial::bench;
namespace stance = spatial::models::hoap3_stance_right;

// The arms of the stance model as a compile-time tree: bodies 7–10 (right arm) and 11–14 (left arm).
using ArmsTree = Tree<Parents<-1, 0, 1, 2, -1, 4, 5, 6>,
                      Joints<JointType::RevoluteZ, JointType::RevoluteZ, JointType::RevoluteZ, JointType::RevoluteZ,
                             JointType::RevoluteZ, JointType::RevoluteZ, JointType::RevoluteZ, JointType::RevoluteZ>>;

const std::string kModel = "hoap3_stance21";

InputRange stance_range() {
  InputRange r{Eigen::VectorXd(stance::dof), Eigen::VectorXd(stance::dof)};
  for (int i = 0; i < stance::dof; ++i) {
    r.lower[i] = stance::lower[static_cast<std::size_t>(i)];
    r.upper[i] = stance::upper[static_cast<std::size_t>(i)];
  }
  return r;
}

/// The held pose of the arm-gesture scene: the middle of every joint's range.
Eigen::VectorXd held_pose() {
  const InputRange r = stance_range();
  return (r.lower + r.upper) / 2.0;
}

template <class TreeT>
struct SceneFixture {
  using VectorN = typename Data<double, TreeT>::VectorN;
  Model<double, TreeT> model;
  Data<double, TreeT> data;
  InputPool<double, Model<double, TreeT>::NB> pool;
  SceneFixture(const Model<double, TreeT>& m, const InputPool<double>& p)
      : model(m), data(model), pool(p.template cast<double, Model<double, TreeT>::NB>()) {}
};

/// The pool of the reduced model: the kept joints' entries of every state of the whole-body pool.
InputPool<double> reduce_pool(const InputPool<double>& full, const ReducedModel<double>& red) {
  InputPool<double> out;
  const int n = red.model.size();
  for (int k = 0; k < full.size(); ++k) {
    const auto kk = static_cast<std::size_t>(k);
    Eigen::VectorXd q(n), qd(n), u(n);
    red.gather(full.q[kk], q);
    red.gather(full.qd[kk], qd);
    red.gather(full.u[kk], u);
    out.q.push_back(q);
    out.qd.push_back(qd);
    out.u.push_back(u);
  }
  return out;
}

#define SCENE_CALL(expr) benchmark::DoNotOptimize((expr).data())

template <class Fx>
void register_whole_body(const std::string& tree, const std::shared_ptr<Fx>& fx) {
  const auto name = [&](const char* algorithm) { return bench_name("scene", algorithm, kModel, "double", tree); };
  const auto at = [](const auto& v, int k) -> const auto& { return v[static_cast<std::size_t>(k)]; };
  // RNEA
  register_one(name("RNEA.Full"), fx, [at](Fx& f, int k) {
    SCENE_CALL(rnea(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)));
  });
  register_one(name("RNEA.Static"), fx, [at](Fx& f, int k) {
    SCENE_CALL(rnea<Dyn::Static>(f.model, f.data, at(f.pool.q, k), at(f.pool.q, k), at(f.pool.q, k)));
  });
  register_one(name("RNEA.QuasiStatic"), fx, [at](Fx& f, int k) {
    SCENE_CALL(rnea<Dyn::QuasiStatic>(f.model, f.data, at(f.pool.q, k), at(f.pool.q, k), at(f.pool.u, k)));
  });
  register_one(name("RNEA.NoGravity"), fx, [at](Fx& f, int k) {
    SCENE_CALL(rnea<Dyn::NoGravity>(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)));
  });
  register_one(name("RNEA.BiasForces"), fx, [at](Fx& f, int k) {
    SCENE_CALL(rnea<Dyn::Gravity | Dyn::Velocity>(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k),
                                                  at(f.pool.q, k)));
  });
  register_one(name("RNEA.FullBaseForces"), fx, [at](Fx& f, int k) {
    SCENE_CALL(rnea<Dyn::Full | Dyn::BaseForces>(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k),
                                                  at(f.pool.u, k)));
  });
  register_one(name("RNEA.StaticBaseForces"), fx, [at](Fx& f, int k) {
    SCENE_CALL(rnea<Dyn::Static | Dyn::BaseForces>(f.model, f.data, at(f.pool.q, k), at(f.pool.q, k),
                                                    at(f.pool.q, k)));
  });
  // ABA
  register_one(name("ABA.Full"), fx, [at](Fx& f, int k) {
    SCENE_CALL(aba(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)));
  });
  register_one(name("ABA.Static"), fx, [at](Fx& f, int k) {
    SCENE_CALL(aba<Dyn::Static>(f.model, f.data, at(f.pool.q, k), at(f.pool.q, k), at(f.pool.u, k)));
  });
  register_one(name("ABA.NoGravity"), fx, [at](Fx& f, int k) {
    SCENE_CALL(aba<Dyn::Velocity>(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)));
  });
  // Forward dynamics by CRBA + LTDL
  register_one(name("FD_CRBA.Full"), fx, [at](Fx& f, int k) {
    SCENE_CALL(forward_dynamics_crba(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)));
  });
  register_one(name("FD_CRBA.Static"), fx, [at](Fx& f, int k) {
    SCENE_CALL(forward_dynamics_crba<Dyn::Static>(f.model, f.data, at(f.pool.q, k), at(f.pool.q, k),
                                                  at(f.pool.u, k)));
  });
  register_one(name("FD_CRBA.NoGravity"), fx, [at](Fx& f, int k) {
    SCENE_CALL(forward_dynamics_crba<Dyn::Velocity>(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k),
                                                    at(f.pool.u, k)));
  });
  // CRBA alone (the baseline of the arms-only CRBA)
  register_one(name("CRBA.Full"), fx, [at](Fx& f, int k) { SCENE_CALL(crba(f.model, f.data, at(f.pool.q, k))); });
}

template <class Fx>
void register_arms(const std::string& tree, const std::shared_ptr<Fx>& fx) {
  const auto name = [&](const char* algorithm) { return bench_name("scene", algorithm, kModel, "double", tree); };
  const auto at = [](const auto& v, int k) -> const auto& { return v[static_cast<std::size_t>(k)]; };
  register_one(name("RNEA.ArmsOnly"), fx, [at](Fx& f, int k) {
    SCENE_CALL(rnea(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)));
  });
  register_one(name("RNEA.ArmsOnlyStatic"), fx, [at](Fx& f, int k) {
    SCENE_CALL(rnea<Dyn::Static>(f.model, f.data, at(f.pool.q, k), at(f.pool.q, k), at(f.pool.q, k)));
  });
  register_one(name("ABA.ArmsOnly"), fx, [at](Fx& f, int k) {
    SCENE_CALL(aba(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)));
  });
  register_one(name("FD_CRBA.ArmsOnly"), fx, [at](Fx& f, int k) {
    SCENE_CALL(forward_dynamics_crba(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)));
  });
  register_one(name("CRBA.ArmsOnly"), fx, [at](Fx& f, int k) { SCENE_CALL(crba(f.model, f.data, at(f.pool.q, k))); });
}

const bool registered = [] {
  add_build_context();
  const auto whole = stance::model();
  const InputPool<double> pool(stance_range());
  const ReducedModel<double> arms = keep_branches(whole, {"R_SFE", "L_SFE"}, held_pose());
  const InputPool<double> arms_pool = reduce_pool(pool, arms);
  register_whole_body("static", std::make_shared<SceneFixture<stance::Tree>>(whole, pool));
  register_whole_body("runtime", std::make_shared<SceneFixture<DynamicTree>>(whole.to_runtime(), pool));
  register_arms("static",
                std::make_shared<SceneFixture<ArmsTree>>(Model<double, ArmsTree>::from(arms.model), arms_pool));
  register_arms("runtime", std::make_shared<SceneFixture<DynamicTree>>(arms.model, arms_pool));
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
