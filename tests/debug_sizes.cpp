// The debug size assertion (include/spatial/sizes.hpp): this binary is built without NDEBUG, so every run-time
// entry point checks its vector arguments and, on a wrong size, aborts with a message that names the function,
// the argument, its size and the model's. Death tests, on a run-time model and on a compile-time model with
// dynamic-size vectors (the static_assert for fixed sizes is tested by tests/compile_fail/).

#ifdef NDEBUG
#error "debug_sizes.cpp must be compiled without NDEBUG"
#endif

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include <gtest/gtest.h>

namespace {

using namespace spatial;
namespace stance = spatial::models::hoap3_stance_right;
using Vec = Eigen::VectorXd;

static_assert(SPATIAL_CHECK_SIZES == 1, "the size checks must be on in this binary");

template <class M>
void expect_size_assertions(const M& model) {
  Data<double, typename M::tree_type> data(model);
  const Vec g = Vec::Zero(21), s = Vec::Zero(20), l = Vec::Zero(22);
  Vec x = s;
  // The right sizes pass (no false alarm from the library's own calls between entry points).
  rnea(model, data, g, g, g);
  aba(model, data, g, g, g);
  forward_dynamics_crba(model, data, g, g, g);
  forward_kinematics(model, data, g, g, g);
  compute_joint_jacobians_time_variation(model, data, g, g);
  (void)frame_jdot_qdot(model, data, g, g, 0, ReferenceFrame::World);
  (void)centroidal_momentum_time_variation(model, data, g, g, g);
  Eigen::MatrixXd Jc(3, 21), Ag(6, 21);
  com_jacobian(model, data, g, Jc);
  centroidal_momentum_matrix(model, data, g, Ag);
  EXPECT_DEATH(rnea(model, data, s, g, g), "spatial: rnea: argument 'q' has 20 entries, the model has 21 joints");
  EXPECT_DEATH(rnea(model, data, g, l, g), "spatial: rnea: argument 'qd' has 22 entries, the model has 21 joints");
  EXPECT_DEATH(rnea(model, data, g, g, s), "spatial: rnea: argument 'qdd' has 20 entries");
  EXPECT_DEATH(bias_forces(model, data, g, s), "spatial: bias_forces: argument 'qd' has 20 entries");
  EXPECT_DEATH(gravity_torques(model, data, s), "spatial: gravity_torques: argument 'q' has 20 entries");
  EXPECT_DEATH(crba(model, data, l), "spatial: crba: argument 'q' has 22 entries");
  EXPECT_DEATH(forward_kinematics(model, data, s), "spatial: forward_kinematics: argument 'q'");
  EXPECT_DEATH(forward_velocities(model, data, g, s), "spatial: forward_velocities: argument 'qd'");
  EXPECT_DEATH(kinetic_energy(model, data, s, g), "spatial: kinetic_energy: argument 'q'");
  EXPECT_DEATH(potential_energy(model, data, s), "spatial: potential_energy: argument 'q'");
  EXPECT_DEATH(center_of_mass(model, data, s), "spatial: center_of_mass: argument 'q'");
  EXPECT_DEATH(forward_dynamics_crba(model, data, g, g, s), "spatial: forward_dynamics_crba: argument 'tau'");
  EXPECT_DEATH(aba(model, data, g, g, l), "spatial: aba: argument 'tau' has 22 entries");
  EXPECT_DEATH(ltdl_solve(model, data, x), "spatial: ltdl_solve: argument 'x' has 20 entries");
  EXPECT_DEATH(rnea<Dyn::Static>(model, data, s, g, g), "spatial: rnea: argument 'q' has 20 entries");
  EXPECT_DEATH(aba<Dyn::Static>(model, data, g, g, s), "spatial: aba: argument 'tau' has 20 entries");
  EXPECT_DEATH(forward_dynamics_crba<Dyn::Velocity>(model, data, s, g, g),
               "spatial: forward_dynamics_crba: argument 'q' has 20 entries");
  // kinematics.hpp and centroidal.hpp
  EXPECT_DEATH(forward_kinematics(model, data, g, g, s), "spatial: kinematics: argument 'a' has 20 entries");
  EXPECT_DEATH(compute_joint_jacobians(model, data, l), "spatial: forward_kinematics: argument 'q' has 22 entries");
  Eigen::MatrixXd J(6, 21);
  EXPECT_DEATH(compute_frame_jacobian(model, data, s, 0, ReferenceFrame::World, J),
               "spatial: compute_frame_jacobian: argument 'q' has 20 entries");
  EXPECT_DEATH(centroidal_momentum(model, data, g, s), "spatial: centroidal: argument 'v' has 20 entries");
}

TEST(DebugSizes, RunTimeModelAborts) {
  ::testing::FLAGS_gtest_death_test_style = "threadsafe";
  expect_size_assertions(lock_joints(stance::model(), {}).model);
}

TEST(DebugSizes, CompileTimeModelWithDynamicVectorsAborts) {
  ::testing::FLAGS_gtest_death_test_style = "threadsafe";
  expect_size_assertions(stance::model());
}

// Floating bases: q has nq = 28 entries, v, a and tau nv = 27 (21 joints).
template <class M>
void expect_floating_size_assertions(const M& model) {
  FloatingData<double, typename M::tree_type> data(model);
  const Vec q = neutral(model), v = Vec::Zero(27), s = Vec::Zero(26), qs = Vec::Zero(21), qj = Vec::Zero(27);
  Vec x = s;
  rnea(model, data, q, v, v);  // the right sizes pass
  aba(model, data, q, v, v);
  forward_dynamics_crba(model, data, q, v, v);
  (void)kinetic_energy(model, data, q, v);
  (void)potential_energy(model, data, q);
  forward_kinematics(model, data, q, v, v);
  compute_joint_jacobians_time_variation(model, data, q, v);
  (void)frame_jdot_qdot(model, data, q, v, 0, ReferenceFrame::World);
  (void)centroidal_momentum_time_variation(model, data, q, v, v);
  Eigen::MatrixXd Jc(3, 27), Ag(6, 27);
  com_jacobian(model, data, q, Jc);
  centroidal_momentum_matrix(model, data, q, Ag);
  (void)difference(model, q, integrate(model, q, v, 0.1));
  EXPECT_DEATH(rnea(model, data, qs, v, v),
               "spatial: rnea: argument 'q' has 21 entries, the floating model has nq = 28 \\(7 free-flyer "
               "coordinates \\+ 21 joints\\)");
  EXPECT_DEATH(rnea(model, data, q, s, v),
               "spatial: rnea: argument 'v' has 26 entries, the floating model has nv = 27 \\(6 free-flyer "
               "velocities \\+ 21 joints\\)");
  EXPECT_DEATH(rnea(model, data, q, v, s), "spatial: rnea: argument 'a' has 26 entries");
  EXPECT_DEATH(aba(model, data, qj, v, v), "spatial: aba: argument 'q' has 27 entries");  // nv where nq is due
  EXPECT_DEATH(aba(model, data, q, v, s), "spatial: aba: argument 'tau' has 26 entries");
  EXPECT_DEATH(forward_dynamics_crba(model, data, q, s, v), "spatial: forward_dynamics_crba: argument 'v'");
  EXPECT_DEATH(bias_forces(model, data, q, s), "spatial: bias_forces: argument 'v'");
  EXPECT_DEATH(gravity_torques(model, data, qs), "spatial: gravity_torques: argument 'q'");
  EXPECT_DEATH(crba(model, data, qj), "spatial: crba: argument 'q' has 27 entries");
  EXPECT_DEATH(ltdl_solve(model, data, x), "spatial: ltdl_solve: argument 'x' has 26 entries");
  EXPECT_DEATH(forward_kinematics(model, data, qs), "spatial: forward_kinematics: argument 'q' has 21 entries");
  EXPECT_DEATH(forward_kinematics(model, data, q, v, s), "spatial: kinematics: argument 'a' has 26 entries");
  EXPECT_DEATH(kinetic_energy(model, data, q, s), "spatial: kinetic_energy: argument 'v'");
  EXPECT_DEATH(center_of_mass(model, data, qj), "spatial: center_of_mass: argument 'q'");
  EXPECT_DEATH(centroidal_momentum(model, data, q, s), "spatial: centroidal: argument 'v' has 26 entries");
  EXPECT_DEATH(integrate(model, q, s, 0.1), "spatial: integrate: argument 'v' has 26 entries");
  EXPECT_DEATH(difference(model, q, qj), "spatial: difference: argument 'q1' has 27 entries");
}

TEST(DebugSizes, FloatingModelAborts) {
  ::testing::FLAGS_gtest_death_test_style = "threadsafe";
  namespace fb = spatial::models::hoap3_floating;
  const auto ct = fb::floating_model();
  const FloatingModel<double> rt(lock_joints(ct.tree(), {}).model, ct.root_inertia(), ct.root_name());
  expect_floating_size_assertions(rt);
  expect_floating_size_assertions(ct);
}

}  // namespace
