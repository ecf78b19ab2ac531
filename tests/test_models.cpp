// The generated reference models (src/models/, <spatial/models/...>) against the run-time loader with the same
// options, against urdfdom's own numbers, and against the data sheet (../shared/hoap3/DATASHEET.md). Also
// Model::from_arrays, which the generated headers build their models with.

#include <gtest/gtest.h>

#include <spatial/models/hoap3_double_pendulum.hpp>
#include <spatial/models/hoap3_stance_left.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/models/hoap3_torso.hpp>
#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/urdf_reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace uio = spatial::urdf_io;
namespace gm = spatial::models;
using spatial::testing::urdf_path;

const double kMass = 8.8024;  // data sheet: the sum of the manufacturer's link masses

// The options of src/models/CMakeLists.txt, written out again.
std::vector<std::pair<std::string, double>> head_and_wrists() {
  return {{"CHEST_H_PAN_joint", 0.0}, {"H_PAN_H_TILT_joint", 0.0}, {"H_TILT_H_ROLL_joint", 0.0},
          {"R_EB_R_WR_joint", 0.0}, {"L_EB_L_WR_joint", 0.0}};
}

// One struct per generated model: its namespace's contents, the loader's options and the DoF the study expects.
#define SPATIAL_MODEL_CASE(NAME, FILE, DOF, OPTIONS)                                                  \
  struct NAME##_case {                                                                                \
    static constexpr const char* name = #NAME;                                                        \
    static constexpr const char* file = FILE;                                                         \
    static constexpr int expected_dof = DOF;                                                          \
    using Tree = gm::NAME::Tree;                                                                      \
    static constexpr int dof = gm::NAME::dof;                                                         \
    template <class S = double>                                                                       \
    static Model<S, Tree> model() {                                                                   \
      return gm::NAME::model<S>();                                                                    \
    }                                                                                                 \
    static uio::LoadOptions options() {                                                               \
      uio::LoadOptions o;                                                                             \
      OPTIONS;                                                                                        \
      return o;                                                                                       \
    }                                                                                                 \
    static const auto& joint_names() { return gm::NAME::joint_names; }                                \
    static const auto& body_names() { return gm::NAME::body_names; }                                  \
    static const auto& reversed() { return gm::NAME::reversed; }                                      \
    static const auto& lower() { return gm::NAME::lower; }                                            \
    static const auto& upper() { return gm::NAME::upper; }                                            \
    static const auto& effort() { return gm::NAME::effort; }                                          \
    static const auto& velocity() { return gm::NAME::velocity; }                                      \
    static const auto& locked_joints() { return gm::NAME::locked_joints; }                            \
    static const auto& locked_positions() { return gm::NAME::locked_positions; }                      \
    static const auto& frame_names() { return gm::NAME::frame_names; }                                \
    static const auto& frame_bodies() { return gm::NAME::frame_bodies; }                              \
    static double whole_body_mass() { return gm::NAME::whole_body_mass; }                             \
    static double base_mass() { return gm::NAME::base_mass; }                                         \
    static double moving_mass() { return gm::NAME::moving_mass; }                                     \
    static std::string_view root_link() { return gm::NAME::root_link; }                               \
    static Inertia<double> base_inertia() { return gm::NAME::base_inertia<double>(); }                \
    template <class Q>                                                                                \
    static Vector3<double> whole_body_com(const Model<double, Tree>& m, Data<double, Tree>& d,        \
                                          const Eigen::MatrixBase<Q>& q) {                            \
      return gm::NAME::whole_body_com(m, d, q);                                                       \
    }                                                                                                 \
    static int joint_index(std::string_view n) { return gm::NAME::joint_index(n); }                   \
    static int frame_index(std::string_view n) { return gm::NAME::frame_index(n); }                   \
  }

SPATIAL_MODEL_CASE(hoap3_torso, "hoap3.urdf", 8, (o.subtree = "CHEST", o.locked = head_and_wrists()));
SPATIAL_MODEL_CASE(hoap3_stance_right, "hoap3.urdf", 21, (o.root = "R_SOLE", o.locked = head_and_wrists()));
SPATIAL_MODEL_CASE(hoap3_stance_left, "hoap3.urdf", 21, (o.root = "L_SOLE", o.locked = head_and_wrists()));
SPATIAL_MODEL_CASE(hoap3_double_pendulum, "double_pendulum.urdf", 2, (void)o);

// The DoF counts of the study, checked by the compiler too.
static_assert(gm::hoap3_torso::dof == 8 && gm::hoap3_torso::Tree::size == 8);
static_assert(gm::hoap3_stance_right::dof == 21 && gm::hoap3_stance_left::dof == 21);
static_assert(gm::hoap3_double_pendulum::dof == 2);
// The look-ups are constexpr.
static_assert(gm::hoap3_stance_right::joint_index("R_AFE_R_AAA_joint") == 0);
static_assert(gm::hoap3_stance_right::joint_index("no such joint") == -1);

template <class Case>
class GeneratedModel : public ::testing::Test {
 protected:
  static uio::LoadedModel load() { return uio::load_file(urdf_path(Case::file), Case::options()); }
};
using Cases = ::testing::Types<hoap3_torso_case, hoap3_stance_right_case, hoap3_stance_left_case,
                               hoap3_double_pendulum_case>;
struct CaseName {
  template <class T>
  static std::string GetName(int) {
    return T::name;
  }
};
TYPED_TEST_SUITE(GeneratedModel, Cases, CaseName);

bool same(const Transform<double>& a, const Transform<double>& b) { return a.E == b.E && a.r == b.r; }
bool same(const Inertia<double>& a, const Inertia<double>& b) { return a.m == b.m && a.h == b.h && a.I == b.I; }

// ∞-norm of the difference relative to the ∞-norm of the reference.
template <class A, class B>
double relative_error(const A& a, const B& b) {
  const double ref = b.cwiseAbs().maxCoeff();
  const double diff = (a - b).cwiseAbs().maxCoeff();
  return ref > 0 ? diff / ref : diff;
}

TYPED_TEST(GeneratedModel, HasTheStudysDegreesOfFreedom) {
  using C = TypeParam;
  EXPECT_EQ(C::dof, C::expected_dof);
  const auto m = C::model();
  EXPECT_EQ(m.size(), C::expected_dof);
  EXPECT_TRUE(m.massless_joints().empty()) << "forward dynamics must be defined on every reference model";
}

TYPED_TEST(GeneratedModel, HoldsExactlyTheLoadersNumbers) {
  using C = TypeParam;
  const uio::LoadedModel loaded = TestFixture::load();
  const Model<double>& ref = loaded.model;
  const auto m = C::model();
  ASSERT_EQ(ref.size(), C::dof);
  EXPECT_EQ(loaded.root, C::root_link());
  for (int i = 0; i < C::dof; ++i) {
    const auto k = static_cast<std::size_t>(i);
    SCOPED_TRACE(ref.joint_name(i));
    EXPECT_EQ(m.parent(i), ref.parent(i));
    EXPECT_EQ(m.joint_type(i), ref.joint_type(i));
    EXPECT_EQ(m.joint_name(i), ref.joint_name(i));
    EXPECT_EQ(m.body_name(i), ref.body_name(i));
    EXPECT_EQ(C::joint_names()[k], ref.joint_name(i));
    EXPECT_EQ(C::body_names()[k], ref.body_name(i));
    EXPECT_EQ(C::joint_index(ref.joint_name(i)), i);
    // The numbers are printed so that they read back as the same doubles: equal, not close.
    EXPECT_TRUE(same(m.tree_transform(i), ref.tree_transform(i)));
    EXPECT_TRUE(same(m.inertia(i), ref.inertia(i)));
    EXPECT_EQ(m.axis(i), ref.axis(i));
    const uio::JointInfo& j = loaded.joints[k];
    EXPECT_EQ(C::lower()[k], j.lower);
    EXPECT_EQ(C::upper()[k], j.upper);
    EXPECT_EQ(C::effort()[k], j.effort);
    EXPECT_EQ(C::velocity()[k], j.velocity);
    EXPECT_EQ(C::reversed()[k], j.reversed);
  }
  EXPECT_EQ(m.gravity(), ref.gravity());
  EXPECT_EQ(m.base_mass(), ref.base_mass());
  EXPECT_TRUE(same(C::base_inertia(), loaded.base_inertia));
  EXPECT_EQ(C::whole_body_mass(), uio::whole_body_mass(loaded));
  EXPECT_EQ(C::moving_mass(), ref.total_mass());
  EXPECT_EQ(C::base_mass(), ref.base_mass());
  ASSERT_EQ(m.frames().size(), ref.frames().size());
  ASSERT_EQ(C::frame_names().size(), ref.frames().size());
  for (std::size_t k = 0; k < ref.frames().size(); ++k) {
    EXPECT_EQ(m.frames()[k].name, ref.frames()[k].name);
    EXPECT_EQ(C::frame_names()[k], ref.frames()[k].name);
    EXPECT_EQ(m.frames()[k].body, ref.frames()[k].body);
    EXPECT_EQ(C::frame_bodies()[k], ref.frames()[k].body);
    EXPECT_TRUE(same(m.frames()[k].X, ref.frames()[k].X)) << ref.frames()[k].name;
  }
  ASSERT_EQ(C::locked_joints().size(), loaded.locked.size());
  for (std::size_t k = 0; k < loaded.locked.size(); ++k) {
    EXPECT_EQ(C::locked_joints()[k], loaded.locked[k].first);
    EXPECT_EQ(C::locked_positions()[k], loaded.locked[k].second);
  }
  // And the conversion the library offers gives the same model.
  const auto converted = uio::to_static<typename C::Tree>(loaded);
  for (int i = 0; i < C::dof; ++i) EXPECT_TRUE(same(converted.inertia(i), m.inertia(i)));
}

TYPED_TEST(GeneratedModel, LimitsAreTheUrdfs) {
  // Straight from urdfdom, without the loader.
  using C = TypeParam;
  const auto urdf = spatial::testing::parse_urdf_or_throw(urdf_path(C::file));
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < C::dof; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const auto joint = urdf->getJoint(std::string(C::joint_names()[k]));
    ASSERT_TRUE(joint) << C::joint_names()[k];
    SCOPED_TRACE(joint->name);
    if (joint->type == urdf::Joint::CONTINUOUS) {
      EXPECT_EQ(C::lower()[k], -inf);
      EXPECT_EQ(C::upper()[k], inf);
    } else {
      ASSERT_TRUE(joint->limits);
      EXPECT_EQ(C::lower()[k], joint->limits->lower);
      EXPECT_EQ(C::upper()[k], joint->limits->upper);
    }
    EXPECT_EQ(C::effort()[k], joint->limits ? joint->limits->effort : 0.0);
    EXPECT_EQ(C::velocity()[k], joint->limits ? joint->limits->velocity : 0.0);
  }
}

TYPED_TEST(GeneratedModel, AlgorithmsAgreeWithTheRunTimeLoader) {
  using C = TypeParam;
  using Tree = typename C::Tree;
  const uio::LoadedModel loaded = TestFixture::load();
  const Model<double>& ref = loaded.model;
  const auto m = C::model();
  Data<double> dr(ref);
  Data<double, Tree> ds(m);
  const int n = C::dof;
  std::mt19937 rng(42 + static_cast<unsigned>(n));
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  const double kPi = 3.141592653589793;
  const double tol = 1e-14;
  for (int trial = 0; trial < 25; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    Eigen::VectorXd q(n), qd(n), qdd(n), tau(n);
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const double lo = std::isinf(C::lower()[k]) ? -kPi : C::lower()[k];
      const double hi = std::isinf(C::upper()[k]) ? kPi : C::upper()[k];
      q[i] = lo + (hi - lo) * u(rng);  // within the joint limits
      qd[i] = 3.0 * s(rng);
      qdd[i] = 10.0 * s(rng);
      tau[i] = 2.0 * s(rng);
    }
    const Eigen::VectorXd t_ref = rnea(ref, dr, q, qd, qdd);
    const Eigen::VectorXd t_gen = rnea(m, ds, q, qd, qdd);
    EXPECT_LE(relative_error(t_gen, t_ref), tol) << "RNEA";

    const Eigen::MatrixXd H_ref = crba(ref, dr, q);
    const Eigen::MatrixXd H_gen = crba(m, ds, q);
    EXPECT_LE(relative_error(H_gen, H_ref), tol) << "CRBA";

    const Eigen::VectorXd a_ref = aba(ref, dr, q, qd, tau);
    const Eigen::VectorXd a_gen = aba(m, ds, q, qd, tau);
    EXPECT_LE(relative_error(a_gen, a_ref), tol) << "ABA";

    const Eigen::VectorXd f_ref = forward_dynamics_crba(ref, dr, q, qd, tau);
    const Eigen::VectorXd f_gen = forward_dynamics_crba(m, ds, q, qd, tau);
    EXPECT_LE(relative_error(f_gen, f_ref), tol) << "FD-CRBA";

    forward_kinematics(ref, dr, q);
    forward_kinematics(m, ds, q);
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      EXPECT_LE(relative_error(ds.X_base[k].E, dr.X_base[k].E), tol) << "FK rotation, body " << i;
      EXPECT_LE(relative_error(ds.X_base[k].r, dr.X_base[k].r), tol) << "FK position, body " << i;
    }
    for (int k = 0; k < static_cast<int>(ref.frames().size()); ++k) {
      const Eigen::Matrix4d P_ref = frame_pose(ref, dr, k).matrix();
      const Eigen::Matrix4d P_gen = frame_pose(m, ds, k).matrix();
      EXPECT_LE(relative_error(P_gen, P_ref), tol) << "FK frame " << ref.frames()[static_cast<std::size_t>(k)].name;
    }
    const Eigen::Vector3d c_ref = uio::whole_body_com(loaded, dr, q);
    const Eigen::Vector3d c_gen = C::whole_body_com(m, ds, q);
    EXPECT_LE(relative_error(c_gen, c_ref), tol) << "whole-body CoM";
  }
}

TYPED_TEST(GeneratedModel, OtherScalarTypes) {
  // long double holds the doubles exactly: the same model as the loader's cast; float rounds them.
  using C = TypeParam;
  const uio::LoadedModel loaded = TestFixture::load();
  const Model<long double> ref = loaded.model.template cast<long double>();
  const auto m = C::template model<long double>();
  const auto mf = C::template model<float>();
  for (int i = 0; i < C::dof; ++i) {
    EXPECT_EQ(m.inertia(i).I, ref.inertia(i).I);
    EXPECT_EQ(m.tree_transform(i).r, ref.tree_transform(i).r);
    EXPECT_EQ(mf.inertia(i).m, static_cast<float>(ref.inertia(i).m));
  }
}

// ---- against the data sheet -------------------------------------------------------------------------------------

double urdf_mass_below(const std::string& file, const std::vector<std::string>& links) {
  const auto urdf = spatial::testing::parse_urdf_or_throw(urdf_path(file));
  double m = 0;
  for (const auto& name : links) {
    const auto link = urdf->getLink(name);
    if (link && link->inertial) m += link->inertial->mass;
  }
  return m;
}

TEST(GeneratedModelDataSheet, TotalMass) {
  EXPECT_NEAR(gm::hoap3_stance_right::whole_body_mass, kMass, 1e-12);
  EXPECT_NEAR(gm::hoap3_stance_left::whole_body_mass, kMass, 1e-12);
  EXPECT_NEAR(gm::hoap3_double_pendulum::whole_body_mass, kMass, 1e-12);
  // The stance foot's last link (R_AAA / L_AAA, 0.154 kg) is rigidly fixed to the sole: on the base.
  EXPECT_NEAR(gm::hoap3_stance_right::base_mass, 0.154, 1e-15);
  EXPECT_NEAR(gm::hoap3_stance_right::moving_mass, kMass - 0.154, 1e-12);
  // The torso is what the subtree below CHEST keeps: the chest (3.26 kg), the head (0.483 kg, on the base with the
  // head joints locked) and two arms (0.21 + 0.234 + 0.1965 + 0.216 kg each); everything else (pelvis, waist
  // joint, legs) is not part of it. Summed here from urdfdom's links, not from the loader.
  const double arms = urdf_mass_below("hoap3.urdf", {"R_SFE", "R_SAA", "R_SHR", "R_EB", "R_WR", "R_HAND", "L_SFE",
                                                     "L_SAA", "L_SHR", "L_EB", "L_WR", "L_HAND"});
  const double chest_and_head =
      urdf_mass_below("hoap3.urdf", {"CHEST", "H_PAN", "H_TILT", "H_ROLL", "HEAD", "EYE", "REYE", "LEYE"});
  EXPECT_NEAR(gm::hoap3_torso::moving_mass, arms, 1e-12);
  EXPECT_NEAR(gm::hoap3_torso::base_mass, chest_and_head, 1e-12);
  EXPECT_NEAR(gm::hoap3_torso::whole_body_mass, 5.456, 1e-12);
  const auto torso = gm::hoap3_torso::model();
  EXPECT_NEAR(torso.total_mass(), 2 * (0.21 + 0.234 + 0.1965 + 0.216), 1e-12);
}

template <class NS_Tree, class ComFn>
Eigen::Vector3d com_at_zero(const Model<double, NS_Tree>& m, ComFn&& com) {
  Data<double, NS_Tree> d(m);
  return com(m, d, Eigen::VectorXd::Zero(m.size()));
}

TEST(GeneratedModelDataSheet, CentreOfMassAboveTheSoles) {
  // Data sheet: 0.317 m above the soles at q = 0 (rounded to the millimetre). The stance models' base is the sole,
  // z up, so the height is the CoM's z.
  const double tol = 0.5e-3;
  {
    namespace ns = gm::hoap3_stance_right;
    const Eigen::Vector3d c = com_at_zero(ns::model(), [](auto& m, auto& d, const auto& q) {
      return ns::whole_body_com(m, d, q);
    });
    EXPECT_NEAR(c.z(), 0.317, tol);
  }
  {
    namespace ns = gm::hoap3_stance_left;
    const Eigen::Vector3d c = com_at_zero(ns::model(), [](auto& m, auto& d, const auto& q) {
      return ns::whole_body_com(m, d, q);
    });
    EXPECT_NEAR(c.z(), 0.317, tol);
  }
  {
    // The pendulum's m2 sits at the whole-body CoM (sagittal plane): 0.317 m above the sole as well.
    namespace ns = gm::hoap3_double_pendulum;
    const auto m = ns::model();
    Data<double, ns::Tree> d(m);
    forward_kinematics(m, d, Eigen::Vector2d::Zero());
    const Transform<double>& X = d.X_base[1];
    const Eigen::Vector3d c2 = X.r + X.E.transpose() * m.inertia(1).com();
    EXPECT_NEAR(c2.z(), 0.317, tol);
  }
}

// Rooted at a sole and at rest at q = 0, the ankle joints carry everything above them: τ = a · ((c − p) × (−m g)),
// with the supported mass m and its centre of mass c, the ankle axis point p and direction a (reversed: the stance
// model walks the ankle joints from the foot up), all from urdfdom's numbers and an independent forward kinematics.
// For the roll axis (−x) that is −W (c − p)_y, for the pitch axis (−y) W (c − p)_x: weight times lever arm.
void check_static_ankle_torques(const std::string& side, const Eigen::VectorXd& tau, int roll_index, int pitch_index) {
  SCOPED_TRACE(side + " stance");
  const auto urdf = spatial::testing::parse_urdf_or_throw(urdf_path("hoap3.urdf"));
  const auto pose = spatial::testing::reference_link_poses(*urdf, {});  // base_link frame, parallel to the soles
  const double g = 9.81;
  auto supported = [&](const std::vector<std::string>& below, double& mass) {
    Eigen::Vector3d first = Eigen::Vector3d::Zero();
    mass = 0;
    for (const auto& [name, link] : urdf->links_) {
      if (!link->inertial || std::find(below.begin(), below.end(), name) != below.end()) continue;
      const auto& o = link->inertial->origin.position;
      first += link->inertial->mass * (pose.at(name) * Eigen::Vector3d(o.x, o.y, o.z));
      mass += link->inertial->mass;
    }
    return Eigen::Vector3d(first / mass);
  };
  double m_roll = 0, m_pitch = 0;
  const Eigen::Vector3d c_roll = supported({side + "_AAA"}, m_roll);
  const Eigen::Vector3d c_pitch = supported({side + "_AAA", side + "_AFE"}, m_pitch);
  const Eigen::Vector3d p = pose.at(side + "_AFE").translation();  // both ankle axes pass through it
  EXPECT_NEAR(m_roll, kMass - 0.154, 1e-12);
  EXPECT_NEAR(m_pitch, kMass - 0.154 - 0.195, 1e-12);
  const double tau_roll = -m_roll * g * (c_roll - p).y();
  const double tau_pitch = m_pitch * g * (c_pitch - p).x();
  EXPECT_NEAR(tau[roll_index], tau_roll, 1e-12);
  EXPECT_NEAR(tau[pitch_index], tau_pitch, 1e-12);
  EXPECT_GT(std::abs(tau_roll), 1.0);  // the stance foot is 39 mm to the side of the pelvis centre
}

TEST(GeneratedModelDataSheet, StanceAnkleTorqueIsWeightTimesLeverArm) {
  {
    namespace ns = gm::hoap3_stance_right;
    const auto m = ns::model();
    Data<double, ns::Tree> d(m);
    const Eigen::VectorXd tau = gravity_torques(m, d, Eigen::VectorXd::Zero(ns::dof));
    check_static_ankle_torques("R", tau, ns::joint_index("R_AFE_R_AAA_joint"), ns::joint_index("R_KN_R_AFE_joint"));
    EXPECT_NEAR(tau[0], -3.40, 0.01);
  }
  {
    namespace ns = gm::hoap3_stance_left;
    const auto m = ns::model();
    Data<double, ns::Tree> d(m);
    const Eigen::VectorXd tau = gravity_torques(m, d, Eigen::VectorXd::Zero(ns::dof));
    check_static_ankle_torques("L", tau, ns::joint_index("L_AFE_L_AAA_joint"), ns::joint_index("L_KN_L_AFE_joint"));
    EXPECT_NEAR(tau[0], 3.34, 0.01);  // mirrored; the pelvis CoM's 11 mm y offset makes it no exact mirror image
  }
}

// ---- Model::from_arrays -----------------------------------------------------------------------------------------

using Two = Tree<Parents<-1, 0>, Joints<JointType::RevoluteZ, JointType::RevoluteAxis>>;

struct TwoArrays {
  std::array<Transform<double>, 2> X{{Transform<double>::Identity(), xlt<double>(Eigen::Vector3d(0.5, 0, 0))}};
  std::array<Inertia<double>, 2> I{{Inertia<double>::from_com(1.0, {0.25, 0, 0}, Eigen::Matrix3d::Identity() * 1e-3),
                                    Inertia<double>::from_com(2.0, {0.1, 0, 0}, Eigen::Matrix3d::Identity() * 2e-3)}};
  std::array<Eigen::Vector3d, 2> axis{{Eigen::Vector3d(7, 8, 9), Eigen::Vector3d(0, 3, 4)}};
  std::array<std::string, 2> bodies{{"upper", "fore"}};
  std::array<std::string, 2> joints{{"shoulder", "elbow"}};
  Model<double, Two> make(std::vector<FixedFrame<double>> frames = {}, double base_mass = 0) const {
    return Model<double, Two>::from_arrays(X, I, axis, bodies, joints, Eigen::Vector3d(0, 0, -9.81), frames,
                                           base_mass);
  }
};

TEST(ModelFromArrays, BuildsTheSameModelAsTheBuilder) {
  const TwoArrays a;
  const auto m = a.make({{"tip", 1, xlt<double>(Eigen::Vector3d(0.3, 0, 0))}}, 0.5);
  ModelBuilder<double> b;
  b.add_body("upper", -1, JointType::RevoluteZ, a.X[0], a.I[0], Eigen::Vector3d::Zero(), "shoulder");
  b.add_body("fore", 0, JointType::RevoluteAxis, a.X[1], a.I[1], Eigen::Vector3d(0, 3, 4), "elbow");
  const Model<double> ref = b.build();
  EXPECT_EQ(m.axis(0), Eigen::Vector3d::UnitZ());           // X/Y/Z joint types: the coordinate axis
  EXPECT_EQ(m.axis(1), Eigen::Vector3d(0, 0.6, 0.8));       // *Axis: normalised
  EXPECT_EQ(m.joint_name(1), "elbow");
  EXPECT_EQ(m.body_index("fore"), 1);
  EXPECT_EQ(m.frames().size(), 1u);
  EXPECT_EQ(m.base_mass(), 0.5);
  Data<double, Two> d(m);
  Data<double> dr(ref);
  const Eigen::Vector2d q(0.3, -1.2), qd(0.5, 2.0), qdd(-1.0, 0.25);
  const Eigen::Vector2d t = rnea(m, d, q, qd, qdd);
  const Eigen::VectorXd t_ref = rnea(ref, dr, q, qd, qdd);
  EXPECT_LE(relative_error(t, t_ref), 1e-15);
}

TEST(ModelFromArrays, RejectsBadNumbersNamingTheBody) {
  auto message = [](const TwoArrays& a, std::vector<FixedFrame<double>> frames = {}, double base_mass = 0) {
    try {
      a.make(std::move(frames), base_mass);
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  TwoArrays a;
  a.I[1].m = -1.0;
  EXPECT_NE(message(a).find("'fore'"), std::string::npos) << message(a);
  EXPECT_NE(message(a).find("negative mass"), std::string::npos) << message(a);
  a = TwoArrays();
  a.X[0].E(0, 0) = 2.0;
  EXPECT_NE(message(a).find("'upper'"), std::string::npos) << message(a);
  a = TwoArrays();
  a.axis[1] = Eigen::Vector3d::Zero();
  EXPECT_NE(message(a).find("'elbow'"), std::string::npos) << message(a);
  a = TwoArrays();
  a.I[0].I(0, 1) = std::nan("");
  EXPECT_NE(message(a).find("NaN"), std::string::npos) << message(a);
  a = TwoArrays();
  EXPECT_NE(message(a, {{"tip", 2, Transform<double>::Identity()}}).find("'tip'"), std::string::npos);
  EXPECT_NE(message(a, {}, -1.0).find("base mass"), std::string::npos);
  EXPECT_EQ(message(a), "no error");
}

}  // namespace
