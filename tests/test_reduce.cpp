// Model reduction (include/spatial/reduce.hpp): lock_joints, keep_joints and keep_branches against the full model
// with the locked joints held (q at the lock position, q̇ = q̈ = 0): the torques, inertia matrix, forward dynamics,
// frame poses and masses of the kept joints agree; against the URDF loader's `locked` option on urdf/hoap3.urdf and
// against the generated 21-DoF stance model; and every rejection names the joint.
//
// Bound: the reduced model's numbers differ from the full model's only by the order of floating-point operations
// (merged inertias are transformed once instead of at every call), along paths of at most n bodies:
// |Δ| ≤ 16 n ε max(1, ‖ref‖∞), 7.5e-14 for n = 21. Forward dynamics is checked as a residual (H q̈ − (τ − C)),
// which does not depend on the condition of H.

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/urdf.hpp>

#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
using spatial::testing::random_model;
using spatial::testing::random_vector;
using spatial::testing::Shape;
using Vec = Eigen::VectorXd;
namespace stance = spatial::models::hoap3_stance_right;

constexpr double kEps = std::numeric_limits<double>::epsilon();

template <class A, class B>
void expect_close(const Eigen::MatrixBase<A>& got, const Eigen::MatrixBase<B>& ref, int n, const std::string& what) {
  ASSERT_EQ(got.rows(), ref.rows()) << what;
  ASSERT_EQ(got.cols(), ref.cols()) << what;
  ASSERT_TRUE(got.allFinite()) << what;
  const double tol = 16.0 * double(n) * kEps * std::max(1.0, ref.cwiseAbs().maxCoeff());
  EXPECT_LE((got - ref).cwiseAbs().maxCoeff(), tol) << what << "\n got\n" << got << "\n ref\n" << ref;
}

template <class S, class T>
Eigen::Matrix<S, 4, 4> pose_matrix(const Model<S, T>& model, Data<S, T>& data, int frame) {
  return frame_pose(model, data, frame).matrix();
}

/// The full model and its reduction agree on every kept joint when the locked joints are held still.
template <class T>
void check_reduction(const Model<double, T>& full, const ReducedModel<double>& red, const Vec& q_full_in,
                     unsigned seed, const std::string& name) {
  const int n = full.size(), nr = red.model.size();
  ASSERT_EQ(static_cast<int>(red.joints.size()), nr) << name;
  ASSERT_EQ(static_cast<int>(red.joints.size() + red.locked.size()), n) << name;
  for (int k = 0; k < nr; ++k)
    EXPECT_EQ(red.model.joint_name(k), full.joint_name(red.joints[static_cast<std::size_t>(k)])) << name;
  // Masses and centre of mass.
  EXPECT_NEAR(red.model.total_mass() + red.model.base_mass(), full.total_mass() + full.base_mass(),
              4.0 * n * kEps * (full.total_mass() + full.base_mass()))
      << name;

  std::mt19937 rng(seed);
  Vec q = q_full_in;
  for (std::size_t k = 0; k < red.locked.size(); ++k) q[red.locked[k]] = red.locked_at[k];
  const Vec qdr = random_vector(nr, rng, 2.0), qddr = random_vector(nr, rng, 3.0),
            taur = random_vector(nr, rng, 4.0);
  Vec qr(nr), qd = Vec::Zero(n), qdd = Vec::Zero(n);
  red.gather(q, qr);
  red.scatter(qdr, qd);
  red.scatter(qddr, qdd);
  Data<double, T> df(full);
  Data<double> dr(red.model);

  // Inverse dynamics, with and without external forces, and every option.
  Vec want(nr);
  red.gather(rnea(full, df, q, qd, qdd), want);
  expect_close(rnea(red.model, dr, qr, qdr, qddr), want, n, name + ": rnea");
  red.gather(gravity_torques(full, df, q), want);
  expect_close(rnea<Dyn::Static>(red.model, dr, qr, qr, qr), want, n, name + ": static rnea");
  red.gather(bias_forces(full, df, q, qd), want);
  expect_close(bias_forces(red.model, dr, qr, qdr), want, n, name + ": bias forces");

  // Joint-space inertia: the kept rows and columns.
  const Eigen::MatrixXd H = crba(full, df, q);
  Eigen::MatrixXd Hk(nr, nr);
  for (int a = 0; a < nr; ++a)
    for (int b = 0; b < nr; ++b) Hk(a, b) = H(red.joints[std::size_t(a)], red.joints[std::size_t(b)]);
  expect_close(crba(red.model, dr, qr), Hk, n, name + ": crba");

  // Forward dynamics of the reduced model = the full model's with the locked joints held: the full model's RNEA
  // of that motion gives back the kept joints' torques.
  const Vec fd = aba(red.model, dr, qr, qdr, taur);
  Vec qdd_full = Vec::Zero(n), tau_back(nr);
  red.scatter(fd, qdd_full);
  red.gather(rnea(full, df, q, qd, qdd_full), tau_back);
  const double scale = std::max({taur.cwiseAbs().maxCoeff(), (Hk * fd).cwiseAbs().maxCoeff(), 1.0});
  EXPECT_LE((tau_back - taur).cwiseAbs().maxCoeff(), 64.0 * n * kEps * scale) << name << ": aba residual";

  // Poses: every frame of the full model, and every locked body, at the same place.
  Data<double> dr2(red.model);
  forward_kinematics(full, df, q);
  forward_kinematics(red.model, dr2, qr);
  for (std::size_t f = 0; f < full.frames().size(); ++f) {
    ASSERT_EQ(red.model.frames()[f].name, full.frames()[f].name) << name;
    expect_close(pose_matrix(red.model, dr2, int(f)), pose_matrix(full, df, int(f)), n,
                 name + ": frame " + full.frames()[f].name);
  }
  for (std::size_t k = 0; k < red.locked.size(); ++k) {
    const int i = red.locked[k];
    const auto& frames = red.model.frames();
    int found = -1;
    for (std::size_t f = full.frames().size(); f < frames.size(); ++f)
      if (frames[f].name == full.body_name(i)) found = int(f);
    ASSERT_GE(found, 0) << name << ": no frame for locked body " << full.body_name(i);
    expect_close(pose_matrix(red.model, dr2, found), body_pose(df, i).matrix(), n,
                 name + ": locked body " + full.body_name(i));
  }
}

TEST(Reduce, LockRandomJointsOfRandomTrees) {
  for (Shape shape : {Shape::Chain, Shape::Branched}) {
    for (unsigned seed = 1; seed <= 8; ++seed) {
      const int n = 4 + int(seed) * 2;
      const Model<double> model = random_model(n, shape, 300 + seed);
      std::mt19937 rng(seed);
      std::bernoulli_distribution pick(0.4);
      std::vector<JointLock> locks;
      for (int i = 1; i < n; ++i)  // joint 0 always moves (some locks must leave a moving body)
        if (pick(rng)) locks.push_back({JointRef(i), random_vector(1, rng)[0]});
      if (locks.empty()) locks.push_back({JointRef(n - 1), 0.3});
      const ReducedModel<double> red = lock_joints(model, locks);
      EXPECT_EQ(red.model.size(), n - int(locks.size()));
      // Bodies ending up on the base: lock the first joint too, in a second reduction.
      const Vec q = random_vector(n, rng);
      check_reduction(model, red, q, seed, "random " + std::to_string(seed));
      std::vector<JointLock> with_root = locks;
      with_root.push_back({JointRef(0), -0.4});
      if (int(with_root.size()) < n) {
        const ReducedModel<double> red0 = lock_joints(model, with_root);
        check_reduction(model, red0, q, seed + 50, "random with root locked " + std::to_string(seed));
      }
    }
  }
}

// Locking by name on the whole HOAP-3 rooted at the right sole gives what the URDF loader gives with the same
// `locked` option, to the order of rounding; with the head and wrists at 0 it is the generated stance model.
Vec named(const Model<double>& m, const Vec& v, const Model<double>& order) {
  Vec out(order.size());
  for (int i = 0; i < order.size(); ++i) out[i] = v[m.joint_index(order.joint_name(i))];
  return out;
}

TEST(Reduce, Hoap3LockMatchesTheUrdfLoader) {
  const std::string urdf = std::string(SPATIAL_SOURCE_DIR) + "/urdf/hoap3.urdf";
  urdf_io::LoadOptions opt;
  opt.root = "R_SOLE";
  const Model<double> whole = urdf_io::load_file(urdf, opt).model;
  const std::vector<std::pair<std::string, double>> lock_sets[] = {
      {{"CHEST_H_PAN_joint", 0.0}, {"H_PAN_H_TILT_joint", 0.0}, {"H_TILT_H_ROLL_joint", 0.0},
       {"R_EB_R_WR_joint", 0.0}, {"L_EB_L_WR_joint", 0.0}},
      {{"CHEST_H_PAN_joint", 0.3}, {"H_PAN_H_TILT_joint", -0.2}, {"H_TILT_H_ROLL_joint", 0.1},
       {"R_EB_R_WR_joint", 0.5}, {"L_EB_L_WR_joint", -0.5}, {"R_LFE_R_KN_joint", 0.8}, {"WAIST_CHEST_joint", 0.2},
       {"L_SFE_L_SAA_joint", 0.4}},
  };
  int set = 0;
  for (const auto& locks : lock_sets) {
    opt.locked = locks;
    const Model<double> ref = urdf_io::load_file(urdf, opt).model;
    std::vector<JointLock> jl;
    for (const auto& [name, at] : locks) jl.push_back({name, at});
    const ReducedModel<double> red = lock_joints(whole, jl);
    ASSERT_EQ(red.model.size(), ref.size());
    EXPECT_NEAR(red.model.base_mass(), ref.base_mass(), 16 * kEps * ref.base_mass());
    Data<double> dr(red.model), dref(ref);
    std::map<std::string, Eigen::Matrix4d> locked_rel;
    std::mt19937 rng(20 + set);
    for (int rep = 0; rep < 5; ++rep) {
      const int n = ref.size();
      const Vec q = random_vector(n, rng), qd = random_vector(n, rng, 2.0), qdd = random_vector(n, rng, 3.0);
      const Vec want = rnea(ref, dref, q, qd, qdd);
      const Vec got = named(red.model, rnea(red.model, dr, named(ref, q, red.model), named(ref, qd, red.model),
                                            named(ref, qdd, red.model)),
                            ref);
      expect_close(got, want, n, "hoap3 lock set " + std::to_string(set) + ": rnea vs the loader");
      forward_kinematics(ref, dref, q);
      forward_kinematics(red.model, dr, named(ref, q, red.model));
      for (std::size_t f = 0; f < ref.frames().size(); ++f) {
        int g = -1;
        for (std::size_t h = 0; h < red.model.frames().size(); ++h)
          if (red.model.frames()[h].name == ref.frames()[f].name) g = int(h);
        ASSERT_GE(g, 0) << "frame " << ref.frames()[f].name << " missing";
        if (std::size_t(g) < whole.frames().size()) {
          expect_close(pose_matrix(red.model, dr, g), pose_matrix(ref, dref, int(f)), n,
                       "frame " + ref.frames()[f].name);
        } else {
          // A locked body's frame is its body frame in the model, which for a URDF model need not be the link
          // frame that the loader records (re-rooted joints put the body frame at the joint; axis-aligned joints
          // turn it by π): the two must be rigidly attached, i.e. a constant transform apart.
          const Eigen::Matrix4d rel = pose_matrix(red.model, dr, g).inverse() * pose_matrix(ref, dref, int(f));
          auto it = locked_rel.find(ref.frames()[f].name);
          if (it == locked_rel.end()) locked_rel.emplace(ref.frames()[f].name, rel);
          else expect_close(rel, it->second, n, "locked link " + ref.frames()[f].name + " rigid on its body");
        }
      }
    }
    ++set;
  }
  // The first set is the generated stance model (same joint order: both keep the loader's order).
  opt.locked = lock_sets[0];
  std::vector<JointLock> jl;
  for (const auto& [name, at] : lock_sets[0]) jl.push_back({name, at});
  const ReducedModel<double> red = lock_joints(whole, jl);
  const auto gen = stance::model();
  ASSERT_EQ(red.model.size(), stance::dof);
  for (int i = 0; i < stance::dof; ++i) EXPECT_EQ(red.model.joint_name(i), gen.joint_name(i));
  Data<double> dr(red.model);
  Data<double, stance::Tree> dg(gen);
  std::mt19937 rng(9);
  const Vec q = random_vector(stance::dof, rng), qd = random_vector(stance::dof, rng);
  const Data<double, stance::Tree>::VectorN qg = q, qdg = qd;
  const Vec want = rnea(gen, dg, qg, qdg, qdg);
  expect_close(rnea(red.model, dr, q, qd, qd), want, stance::dof, "lock_joints = generated stance model");
}

// The arm-gesture scene: only the arms move; legs, waist and chest are held at their pose (q̇ = q̈ = 0 there).
TEST(Reduce, Hoap3ArmsOnly) {
  const auto gen = stance::model();
  Vec q(stance::dof);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < stance::dof; ++i)
    q[i] = stance::lower[std::size_t(i)] + u(rng) * (stance::upper[std::size_t(i)] - stance::lower[std::size_t(i)]);
  const ReducedModel<double> arms = keep_branches(gen, {"R_SFE", "L_SFE"}, q);
  ASSERT_EQ(arms.model.size(), 8);
  EXPECT_EQ(arms.joints, (std::vector<int>{7, 8, 9, 10, 11, 12, 13, 14}));
  // Everything below the arms is merged into the base.
  EXPECT_NEAR(arms.model.base_mass(), gen.base_mass() + gen.total_mass() - arms.model.total_mass(),
              16 * kEps * gen.total_mass());
  check_reduction(gen, arms, q, 77, "arms only");
  // The same by joint names and by indices.
  const ReducedModel<double> by_name =
      keep_joints(gen, {"CHEST_R_SFE_joint", "R_SFE_R_SAA_joint", "R_SAA_R_SHR_joint", "R_SHR_R_EB_joint",
                        "CHEST_L_SFE_joint", "L_SFE_L_SAA_joint", "L_SAA_L_SHR_joint", "L_SHR_L_EB_joint"},
                  q);
  const ReducedModel<double> by_index = keep_joints(gen, {7, 8, 9, 10, 11, 12, 13, 14}, q);
  for (const auto* r : {&by_name, &by_index}) {
    EXPECT_EQ(r->joints, arms.joints);
    for (int i = 0; i < 8; ++i) {
      EXPECT_EQ(r->model.inertia(i).m, arms.model.inertia(i).m);
      EXPECT_EQ(r->model.tree_transform(i).r, arms.model.tree_transform(i).r);
    }
  }
}

template <class F>
void expect_model_error(F&& f, const std::vector<std::string>& needles) {
  try {
    f();
    ADD_FAILURE() << "no ModelError";
  } catch (const ModelError& e) {
    for (const auto& s : needles) EXPECT_NE(std::string(e.what()).find(s), std::string::npos) << e.what();
  }
}

TEST(Reduce, Rejections) {
  const auto gen = stance::model();
  const Vec q = Vec::Zero(stance::dof);
  expect_model_error([&] { lock_joints(gen, {{"NO_SUCH_joint", 0.0}}); }, {"lock_joints", "'NO_SUCH_joint'"});
  expect_model_error([&] { lock_joints(gen, {{21, 0.0}}); }, {"lock_joints", "index 21", "21"});
  expect_model_error([&] { lock_joints(gen, {{-1, 0.0}}); }, {"index -1"});
  expect_model_error([&] { lock_joints(gen, {{"R_KN_R_AFE_joint", std::nan("")}}); },
                     {"joint 1 'R_KN_R_AFE_joint'", "non-finite"});
  expect_model_error([&] { lock_joints(gen, {{"R_KN_R_AFE_joint", 0.1}, {1, 0.2}}); },
                     {"'R_KN_R_AFE_joint'", "locked twice"});
  std::vector<JointLock> all;
  for (int i = 0; i < stance::dof; ++i) all.push_back({i, 0.0});
  expect_model_error([&] { lock_joints(gen, all); }, {"every joint is locked"});
  expect_model_error([&] { keep_joints(gen, {"R_KN"}, q); }, {"keep_joints", "'R_KN'"});
  expect_model_error([&] { keep_joints(gen, {1}, Vec::Zero(3)); }, {"keep_joints", "3 entries", "21 joints"});
  Vec bad = q;
  bad[3] = std::nan("");
  expect_model_error([&] { keep_joints(gen, {1}, bad); }, {"joint 3 'R_LAA_R_LFE_joint'", "not finite"});
  expect_model_error([&] { keep_branches(gen, {"R_SFE_joint"}, q); }, {"keep_branches", "no body 'R_SFE_joint'"});
  // A joint locked twice at the same position is fine.
  EXPECT_EQ(lock_joints(gen, {{1, 0.5}, {"R_KN_R_AFE_joint", 0.5}}).model.size(), stance::dof - 1);
}

}  // namespace
