// Driver for scripts/callgrind.sh: each scene option of bench_scenes.cpp as one extern "C" function that makes
// `reps` calls over a pre-generated pool of states (q within the joint limits of the HOAP-3 stance model, q̇, q̈, τ
// in [−1, 1]), so that callgrind's inclusive instruction count of the function divided by `reps` is the cost per
// call. Not a Google Benchmark binary (it is not globbed by bench/CMakeLists.txt); the script compiles it by hand.
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include "bench_models.hpp"

#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

namespace {
using namespace spatial;
namespace stance = spatial::models::hoap3_stance_right;
using ArmsTree = Tree<Parents<-1, 0, 1, 2, -1, 4, 5, 6>,
                      Joints<JointType::RevoluteZ, JointType::RevoluteZ, JointType::RevoluteZ, JointType::RevoluteZ,
                             JointType::RevoluteZ, JointType::RevoluteZ, JointType::RevoluteZ, JointType::RevoluteZ>>;

template <class T>
struct Fx {
  using V = typename Data<double, T>::VectorN;
  Model<double, T> model;
  Data<double, T> data;
  std::vector<V> q, qd, u;
  explicit Fx(const Model<double, T>& m) : model(m), data(model) {}
};

constexpr int kPool = 256;
}  // namespace

// Built at start-up, outside the measured functions.
static Fx<stance::Tree>* g_whole;
static Fx<ArmsTree>* g_arms;
static Fx<DynamicTree>* g_whole_rt;
static Fx<DynamicTree>* g_arms_rt;
volatile double g_sink;

#define SCENE(NAME, FX, EXPR)                                        \
  extern "C" [[gnu::noinline]] void NAME(int reps) {                 \
    auto& f = *FX;                                                   \
    double s = 0;                                                    \
    for (int r = 0; r < reps; ++r) {                                 \
      const int k = r % kPool;                                       \
      const auto& q = f.q[k];                                        \
      const auto& qd = f.qd[k];                                      \
      const auto& u = f.u[k];                                        \
      (void)qd;                                                      \
      (void)u;                                                       \
      s += (EXPR)(0, 0);                                               \
    }                                                                \
    g_sink = s;                                                      \
  }

#define SCENES(SUFFIX, WHOLE, ARMS)                                                                              \
  SCENE(scene_RNEA_Full_##SUFFIX, WHOLE, rnea(f.model, f.data, q, qd, u))                                      \
  SCENE(scene_RNEA_Static_##SUFFIX, WHOLE, rnea<Dyn::Static>(f.model, f.data, q, q, q))                       \
  SCENE(scene_RNEA_QuasiStatic_##SUFFIX, WHOLE, rnea<Dyn::QuasiStatic>(f.model, f.data, q, q, u))            \
  SCENE(scene_RNEA_NoGravity_##SUFFIX, WHOLE, rnea<Dyn::NoGravity>(f.model, f.data, q, qd, u))               \
  SCENE(scene_RNEA_BiasForces_##SUFFIX, WHOLE, rnea<Dyn::Gravity | Dyn::Velocity>(f.model, f.data, q, qd, q)) \
  SCENE(scene_RNEA_FullBaseForces_##SUFFIX, WHOLE, rnea<Dyn::Full | Dyn::BaseForces>(f.model, f.data, q, qd, u)) \
  SCENE(scene_RNEA_ArmsOnly_##SUFFIX, ARMS, rnea(f.model, f.data, q, qd, u))                                  \
  SCENE(scene_RNEA_ArmsOnlyStatic_##SUFFIX, ARMS, rnea<Dyn::Static>(f.model, f.data, q, q, q))                \
  SCENE(scene_ABA_Full_##SUFFIX, WHOLE, aba(f.model, f.data, q, qd, u))                                        \
  SCENE(scene_ABA_Static_##SUFFIX, WHOLE, aba<Dyn::Static>(f.model, f.data, q, q, u))                         \
  SCENE(scene_ABA_NoGravity_##SUFFIX, WHOLE, aba<Dyn::Velocity>(f.model, f.data, q, qd, u))                   \
  SCENE(scene_ABA_ArmsOnly_##SUFFIX, ARMS, aba(f.model, f.data, q, qd, u))                                     \
  SCENE(scene_FD_CRBA_Full_##SUFFIX, WHOLE, forward_dynamics_crba(f.model, f.data, q, qd, u))                  \
  SCENE(scene_FD_CRBA_Static_##SUFFIX, WHOLE, forward_dynamics_crba<Dyn::Static>(f.model, f.data, q, q, u))   \
  SCENE(scene_FD_CRBA_NoGravity_##SUFFIX, WHOLE, forward_dynamics_crba<Dyn::Velocity>(f.model, f.data, q, qd, u)) \
  SCENE(scene_FD_CRBA_ArmsOnly_##SUFFIX, ARMS, forward_dynamics_crba(f.model, f.data, q, qd, u))               \
  SCENE(scene_CRBA_Full_##SUFFIX, WHOLE, crba(f.model, f.data, q))                                              \
  SCENE(scene_CRBA_ArmsOnly_##SUFFIX, ARMS, crba(f.model, f.data, q))

SCENES(static, g_whole, g_arms)
SCENES(runtime, g_whole_rt, g_arms_rt)

namespace {

template <class T>
void fill(Fx<T>& f, const std::vector<Eigen::VectorXd>& q, const std::vector<Eigen::VectorXd>& qd,
          const std::vector<Eigen::VectorXd>& u, const ReducedModel<double>* red) {
  for (std::size_t k = 0; k < q.size(); ++k) {
    const int n = f.model.size();
    Eigen::VectorXd a(n), b(n), c(n);
    if (red) {
      red->gather(q[k], a);
      red->gather(qd[k], b);
      red->gather(u[k], c);
    } else {
      a = q[k];
      b = qd[k];
      c = u[k];
    }
    f.q.push_back(a);
    f.qd.push_back(b);
    f.u.push_back(c);
  }
}
}  // namespace

int main(int argc, char** argv) {
  const int reps = argc > 1 ? std::atoi(argv[1]) : 2000;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::VectorXd> q, qd, u;
  for (int k = 0; k < kPool; ++k) {
    Eigen::VectorXd a(stance::dof), b(stance::dof), c(stance::dof);
    for (int i = 0; i < stance::dof; ++i) {
      const auto j = static_cast<std::size_t>(i);
      a[i] = stance::lower[j] + (stance::upper[j] - stance::lower[j]) * unit(rng);
      b[i] = 2.0 * unit(rng) - 1.0;
      c[i] = 2.0 * unit(rng) - 1.0;
    }
    q.push_back(a);
    qd.push_back(b);
    u.push_back(c);
  }
  Eigen::VectorXd held(stance::dof);
  for (int i = 0; i < stance::dof; ++i)
    held[i] = (stance::lower[static_cast<std::size_t>(i)] + stance::upper[static_cast<std::size_t>(i)]) / 2.0;
  const auto whole = stance::model();
  const ReducedModel<double> arms = keep_branches(whole, {"R_SFE", "L_SFE"}, held);
  g_whole = new Fx<stance::Tree>(whole);
  g_arms = new Fx<ArmsTree>(Model<double, ArmsTree>::from(arms.model));
  g_whole_rt = new Fx<DynamicTree>(whole.to_runtime());
  g_arms_rt = new Fx<DynamicTree>(arms.model);
  fill(*g_whole, q, qd, u, nullptr);
  fill(*g_whole_rt, q, qd, u, nullptr);
  fill(*g_arms, q, qd, u, &arms);
  fill(*g_arms_rt, q, qd, u, &arms);

  using Fn = void (*)(int);
#define ENTRY(S) scene_RNEA_Full_##S, scene_RNEA_Static_##S, scene_RNEA_QuasiStatic_##S, scene_RNEA_NoGravity_##S, \
                 scene_RNEA_BiasForces_##S, scene_RNEA_FullBaseForces_##S, scene_RNEA_ArmsOnly_##S,                \
                 scene_RNEA_ArmsOnlyStatic_##S, scene_ABA_Full_##S, scene_ABA_Static_##S, scene_ABA_NoGravity_##S,   \
                 scene_ABA_ArmsOnly_##S, scene_FD_CRBA_Full_##S, scene_FD_CRBA_Static_##S,                          \
                 scene_FD_CRBA_NoGravity_##S, scene_FD_CRBA_ArmsOnly_##S, scene_CRBA_Full_##S, scene_CRBA_ArmsOnly_##S
  const Fn all[] = {ENTRY(static), ENTRY(runtime)};
  for (Fn fn : all) fn(reps);
  std::printf("reps %d\n", reps);
  delete g_whole;
  delete g_arms;
  delete g_whole_rt;
  delete g_arms_rt;
  return 0;
}
