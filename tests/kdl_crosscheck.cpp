// Cross-check of spatial's dynamics algorithms against KDL (orocos-kdl 1.5) on the same trees, built from the same
// numbers (tests/kdl_bridge.hpp does every conversion). Agreement is measured norm-wise,
//   err = ‖ours − kdl‖ / max(‖kdl‖, tiny),
// and must be ≤ 1e-12 for every quantity, with two documented exceptions:
//  - bias forces minus gravity torques: relative to max(‖C‖, ‖G‖), the size of the operands of the subtraction;
//  - forward dynamics: the residual ‖H (ours − kdl)‖ / ‖H kdl‖ must be ≤ 1e-12, the forward error
//    ‖ours − kdl‖ / ‖kdl‖ only ≤ max(1e-12, 16 eps cond(H)) (see KdlCheck::solves_alike).
// The largest error seen per quantity is printed at the end of the run (and recorded as test properties, e.g. in
// --gtest_output=xml).

#include "kdl_bridge.hpp"

#include <gtest/gtest.h>

#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/treefksolverpos_recursive.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace spatial;
using namespace spatial::kdl_bridge;
namespace st = spatial::testing;
using spatial::testing::RandomBody;
using spatial::testing::Shape;
using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kTol = 1e-12;
/// Floor of the denominator: results whose norm is below it (only mathematically zero ones, e.g. the Coriolis
/// torque of a single joint) are compared absolutely, to kTol * kTiny.
constexpr double kTiny = 1e-4;
constexpr double kPi = 3.14159265358979323846;

// ----------------------------------------------------------------------------------------------------------------
// Bookkeeping of the largest disagreement per quantity.

struct Worst {
  double err = 0.0;
  std::string where;
};
std::map<std::string, Worst>& worst_seen() {
  static std::map<std::string, Worst> w;
  return w;
}

/// Prints (and records) the largest relative disagreement with KDL per quantity once all tests have run.
class ReportWorst : public ::testing::Environment {
 public:
  void TearDown() override {
    std::printf("\nLargest relative disagreement with KDL or closed form (norm-wise, tolerance %.0e):\n", kTol);
    for (const auto& [quantity, w] : worst_seen()) {
      std::printf("  %-34s %10.3e   at %s\n", quantity.c_str(), w.err, w.where.c_str());
      ::testing::Test::RecordProperty("max_rel_err_" + quantity, std::to_string(w.err));
    }
    std::fflush(stdout);
  }
};
const auto* const kReportWorst = ::testing::AddGlobalTestEnvironment(new ReportWorst);

/// ‖ours − kdl‖ / max(‖kdl‖, floor).
double rel_error(const MatrixXd& ours, const MatrixXd& kdl, double floor = kTiny) {
  return (ours - kdl).norm() / std::max(kdl.norm(), floor);
}

/// 2-norm condition number of a symmetric positive definite matrix.
double condition_number(const MatrixXd& H) {
  const Eigen::SelfAdjointEigenSolver<MatrixXd> es(H, Eigen::EigenvaluesOnly);
  return es.eigenvalues().maxCoeff() / es.eigenvalues().minCoeff();
}

/// Base of the tests: `agrees(quantity, ours, kdl, where)` measures the disagreement, keeps the maxima (per test,
/// recorded as properties of the test, and over the run) and fails above kTol.
class KdlCheck : public ::testing::Test {
 protected:
  /// Records err for `quantity` and checks err ≤ bound.
  ::testing::AssertionResult within(const std::string& quantity, double err, double bound, const std::string& where) {
    double& local = local_worst_[quantity];
    local = std::max(local, err);
    Worst& w = worst_seen()[quantity];
    if (!(err <= w.err)) w = Worst{err, where};
    if (err <= bound) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << quantity << " at " << where << ": relative disagreement " << err
                                         << " > " << bound;
  }
  /// ‖ours − kdl‖ / max(‖kdl‖, floor) ≤ kTol.
  ::testing::AssertionResult agrees(const std::string& quantity, const MatrixXd& ours, const MatrixXd& kdl,
                                    const std::string& where, double floor = kTiny) {
    if (ours.rows() != kdl.rows() || ours.cols() != kdl.cols())
      return ::testing::AssertionFailure() << quantity << " at " << where << ": size mismatch";
    auto result = within(quantity, rel_error(ours, kdl, floor), kTol, where);
    if (!result && ours.size() <= 12) {
      const Eigen::IOFormat fmt(Eigen::FullPrecision, 0, ", ", "; ", "", "", "[", "]");
      result << "\n  ours: " << ours.format(fmt) << "\n  kdl:  " << kdl.format(fmt);
    }
    return result;
  }
  /// Two solutions of H q̈ = rhs (forward dynamics). Solving with an ill-conditioned H, no two double-precision
  /// algorithms agree to better than about eps·cond(H) (the random 60-body chains reach cond(H) ≈ 2e6), so:
  ///  - backward: the torques that explain the difference, ‖H (ours − kdl)‖ / ‖H kdl‖, must be ≤ kTol
  ///    (recorded as "<quantity>_residual");
  ///  - forward: ‖ours − kdl‖ / ‖kdl‖ must be ≤ max(kTol, 16 eps cond(H)) (recorded as "<quantity>", with cond(H)
  ///    in the location).
  ::testing::AssertionResult solves_alike(const std::string& quantity, const VectorXd& ours, const VectorXd& kdl,
                                          const MatrixXd& H, const std::string& where) {
    const double cond = condition_number(H);
    std::ostringstream at;
    at << where << ", cond(H) = " << std::setprecision(2) << cond;
    const VectorXd diff = ours - kdl;
    auto backward = within(quantity + "_residual", (H * diff).norm() / std::max((H * kdl).norm(), kTiny), kTol,
                           at.str());
    const double bound = std::max(kTol, 16 * std::numeric_limits<double>::epsilon() * cond);
    auto forward = within(quantity, rel_error(ours, kdl), bound, at.str());
    if (!backward) return backward;
    return forward;
  }
  void TearDown() override {
    for (const auto& [quantity, err] : local_worst_) RecordProperty("max_rel_err_" + quantity, std::to_string(err));
  }

 private:
  std::map<std::string, double> local_worst_;
};

// ----------------------------------------------------------------------------------------------------------------
// Helpers.

MatrixXd vec(const Vector3<double>& v) { return MatrixXd(v); }
MatrixXd vec(const KDL::Vector& v) { return vec(from_kdl(v)); }
MatrixXd vec(const Motion<double>& m) { return MatrixXd(m.vector()); }
MatrixXd vec(const Force<double>& f) { return MatrixXd(f.vector()); }
/// A pose as 12 numbers [M row-major; p].
MatrixXd vec(const KDL::Frame& F) {
  MatrixXd out(12, 1);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(3 * i + j, 0) = F.M(i, j);
  for (int i = 0; i < 3; ++i) out(9 + i, 0) = F.p(i);
  return out;
}

struct State {
  VectorXd q, qd, qdd, tau;
  std::vector<Force<double>> fext;  // one per body; zero on most, random on several
};

State random_state(int n, std::mt19937& rng) {
  State s;
  s.q = st::random_vector(n, rng, kPi);
  s.qd = st::random_vector(n, rng, 2.0);
  s.qdd = st::random_vector(n, rng, 3.0);
  s.tau = st::random_vector(n, rng, 10.0);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  std::bernoulli_distribution loaded(1.0 / 3.0);
  for (int i = 0; i < n; ++i) {
    if (i == n - 1 || loaded(rng)) {  // the last body always, others with probability 1/3
      const Vector3<double> lin = spatial::testing::draw3(u, rng);  // sequenced draws (random_model.hpp)
      const Vector3<double> ang = spatial::testing::draw3(u, rng);
      s.fext.emplace_back(ang, lin);
    } else {
      s.fext.push_back(Force<double>::Zero());
    }
  }
  return s;
}

Vector3<double> random_gravity(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return 9.81 * spatial::testing::draw3(n, rng).normalized();
}

std::string where(const char* shape, int n, unsigned seed, Layout layout, int state) {
  std::ostringstream os;
  os << shape << " n=" << n << " seed=" << seed << " " << layout_name(layout) << " state " << state;
  return os.str();
}

constexpr int kStates = 3;

// ================================================================================================================
// 1. The conversions themselves, on hand-written cases, so that a convention mistake cannot cancel out.

using Bridge = KdlCheck;

// Frame B is rotated by +90° about A's z axis and has its origin at (1, 2, 3) in A: B's x axis is A's y axis, B's y
// axis is A's −x axis.
Transform<double> hand_frame() { return Transform<double>(rotz_matrix(kPi / 2), Vector3<double>(1, 2, 3)); }

TEST_F(Bridge, FrameKnownGeometry) {
  const Transform<double> X_BA = hand_frame();
  const KDL::Frame F = to_kdl(X_BA);  // pose of B in A
  const KDL::Frame expected(KDL::Rotation(0, -1, 0,  //
                                          1, 0, 0,   //
                                          0, 0, 1),
                            KDL::Vector(1, 2, 3));
  EXPECT_TRUE(agrees("bridge_frame", vec(F), vec(expected), "hand frame"));
  EXPECT_TRUE(agrees("bridge_frame", vec(KDL::Frame(KDL::Rotation::RotZ(kPi / 2), KDL::Vector(1, 2, 3))),
                     vec(expected), "KDL RotZ"));
  // The point with B coordinates (1, 0, 0) has A coordinates (1, 3, 3); ours maps A coordinates to B's.
  EXPECT_TRUE(agrees("bridge_frame", vec(F * KDL::Vector(1, 0, 0)), vec(Vector3<double>(1, 3, 3)), "point B->A"));
  EXPECT_TRUE(agrees("bridge_frame", vec(Vector3<double>(X_BA.E * (Vector3<double>(1, 3, 3) - X_BA.r))),
                     vec(Vector3<double>(1, 0, 0)), "point A->B"));
  // Round trip, and composition order: ᶜX_B ᴮX_A  <->  F_AB * F_BC.
  const Transform<double> back = from_kdl(F);
  EXPECT_TRUE(agrees("bridge_frame", back.matrix(), X_BA.matrix(), "round trip"));
  const Transform<double> X_CB(rotx_matrix(0.7) * roty_matrix(-0.4), Vector3<double>(-0.5, 0.25, 2.0));
  EXPECT_TRUE(agrees("bridge_frame", vec(to_kdl(X_CB * X_BA)), vec(to_kdl(X_BA) * to_kdl(X_CB)), "composition"));
  // Our passive rotations are the transposes of KDL's active ones.
  for (double a : {0.3, -1.2, 2.5}) {
    EXPECT_TRUE(agrees("bridge_frame", vec(to_kdl(rotx<double>(a))), vec(KDL::Frame(KDL::Rotation::RotX(a))), "rotx"));
    EXPECT_TRUE(agrees("bridge_frame", vec(to_kdl(roty<double>(a))), vec(KDL::Frame(KDL::Rotation::RotY(a))), "roty"));
    EXPECT_TRUE(agrees("bridge_frame", vec(to_kdl(rotz<double>(a))), vec(KDL::Frame(KDL::Rotation::RotZ(a))), "rotz"));
    const Vector3<double> axis = Vector3<double>(0.2, -0.6, 0.7).normalized();
    EXPECT_TRUE(agrees("bridge_frame",
                       vec(to_kdl(Transform<double>(rot_axis_matrix(axis, a), Vector3<double>::Zero()))),
                       vec(KDL::Frame(KDL::Rotation::Rot2(to_kdl(axis), a))), "rot_axis"));
  }
}

TEST_F(Bridge, TwistAndWrenchKnownValues) {
  const Transform<double> X_BA = hand_frame();
  const KDL::Frame F = to_kdl(X_BA);
  // A body spinning at 2 rad/s about A's z axis (through A's origin). In A coordinates: ω = (0, 0, 2), and the body
  // point at A's origin is still. At B's origin (1, 2, 3) it moves at ω × r = (−4, 2, 0) (A axes) = (2, 4, 0) in B
  // axes.
  const Motion<double> m_A(Vector3<double>(0, 0, 2), Vector3<double>(0, 0, 0));
  const KDL::Twist t_B_expected(KDL::Vector(2, 4, 0), KDL::Vector(0, 0, 2));
  EXPECT_TRUE(agrees("bridge_twist", vec(from_kdl(F.Inverse(to_kdl(m_A)))), vec(from_kdl(t_B_expected)), "KDL A->B"));
  EXPECT_TRUE(agrees("bridge_twist", vec(X_BA.apply(m_A)), vec(from_kdl(t_B_expected)), "ours A->B"));
  EXPECT_TRUE(agrees("bridge_twist", vec(from_kdl(F * t_B_expected)), vec(m_A), "KDL B->A"));
  EXPECT_TRUE(agrees("bridge_twist", vec(X_BA.apply_inverse(from_kdl(t_B_expected))), vec(m_A), "ours B->A"));
  const KDL::Twist t = to_kdl(m_A);  // linear part first in KDL
  EXPECT_EQ(t.vel, KDL::Vector(0, 0, 0));
  EXPECT_EQ(t.rot, KDL::Vector(0, 0, 2));

  // A pure force (1, 0, 0) along a line through A's origin. About B's origin its moment is −r × f = (0, −3, 2)
  // (A axes) = (−3, 0, 2) in B axes; the force is (0, −1, 0) in B axes.
  const Force<double> f_A(Vector3<double>(0, 0, 0), Vector3<double>(1, 0, 0));
  const KDL::Wrench w_B_expected(KDL::Vector(0, -1, 0), KDL::Vector(-3, 0, 2));
  EXPECT_TRUE(agrees("bridge_wrench", vec(from_kdl(F.Inverse(to_kdl(f_A)))), vec(from_kdl(w_B_expected)), "KDL A->B"));
  EXPECT_TRUE(agrees("bridge_wrench", vec(X_BA.apply_force(f_A)), vec(from_kdl(w_B_expected)), "ours A->B"));
  EXPECT_TRUE(agrees("bridge_wrench", vec(from_kdl(F * w_B_expected)), vec(f_A), "KDL B->A"));
  EXPECT_TRUE(agrees("bridge_wrench", vec(X_BA.apply_force_inverse(from_kdl(w_B_expected))), vec(f_A), "ours B->A"));
  const KDL::Wrench w = to_kdl(f_A);
  EXPECT_EQ(w.force, KDL::Vector(1, 0, 0));
  EXPECT_EQ(w.torque, KDL::Vector(0, 0, 0));

  // Random vectors: both libraries transform alike, the power is frame independent and the same in both, and the
  // cross products agree.
  std::mt19937 rng(7);
  for (int k = 0; k < 20; ++k) {
    const Transform<double> X(st::random_rotation(rng), st::random_vector(3, rng, 2.0));
    const Motion<double> m(Vector6<double>(st::random_vector(6, rng, 3.0)));
    const Motion<double> m2(Vector6<double>(st::random_vector(6, rng, 3.0)));
    const Force<double> f(Vector6<double>(st::random_vector(6, rng, 3.0)));
    const KDL::Frame FX = to_kdl(X);
    EXPECT_TRUE(agrees("bridge_twist", vec(X.apply(m)), vec(from_kdl(FX.Inverse(to_kdl(m)))), "random A->B"));
    EXPECT_TRUE(agrees("bridge_twist", vec(X.apply_inverse(m)), vec(from_kdl(FX * to_kdl(m))), "random B->A"));
    EXPECT_TRUE(agrees("bridge_wrench", vec(X.apply_force(f)), vec(from_kdl(FX.Inverse(to_kdl(f)))), "random A->B"));
    EXPECT_TRUE(agrees("bridge_wrench", vec(X.apply_force_inverse(f)), vec(from_kdl(FX * to_kdl(f))), "random B->A"));
    EXPECT_NEAR(dot(m, f), KDL::dot(to_kdl(m), to_kdl(f)), 1e-13);
    EXPECT_NEAR(dot(X.apply(m), X.apply_force(f)), dot(m, f), 1e-12);
    EXPECT_TRUE(agrees("bridge_twist", vec(cross(m, m2)), vec(from_kdl(to_kdl(m) * to_kdl(m2))), "motion cross"));
    EXPECT_TRUE(agrees("bridge_wrench", vec(cross(m, f)), vec(from_kdl(to_kdl(m) * to_kdl(f))), "force cross"));
  }
}

TEST_F(Bridge, InertiaKnownValues) {
  // A point mass of 2 kg at (1, 0, 0): about the origin its rotational inertia is diag(0, 2, 2).
  const KDL::RigidBodyInertia K = to_kdl_inertia(2.0, Vector3<double>(1, 0, 0), Matrix3<double>::Zero());
  const Matrix3<double> about_origin = Vector3<double>(0, 2, 2).asDiagonal();
  EXPECT_TRUE(agrees("bridge_inertia", from_kdl(K.getRotationalInertia()), about_origin, "KDL point mass"));
  EXPECT_TRUE(agrees("bridge_inertia",
                     Inertia<double>::from_com(2.0, Vector3<double>(1, 0, 0), Matrix3<double>::Zero()).I,
                     about_origin, "ours point mass"));
  // Spinning at 1 rad/s about z, it moves at (0, 1, 0): momentum (0, 2, 0), angular momentum about the origin
  // (0, 0, 2). KDL's Wrench has the linear part first.
  const Motion<double> spin(Vector3<double>(0, 0, 1), Vector3<double>(0, 0, 0));
  const Force<double> momentum(Vector3<double>(0, 0, 2), Vector3<double>(0, 2, 0));
  EXPECT_TRUE(agrees("bridge_inertia", vec(from_kdl(K * to_kdl(spin))), vec(momentum), "KDL momentum"));
  EXPECT_TRUE(agrees("bridge_inertia", vec(from_kdl(K) * spin), vec(momentum), "ours momentum"));

  // KDL's RotationalInertia(Ixx, Iyy, Izz, Ixy, Ixz, Iyz) takes matrix entries.
  Matrix3<double> I;
  I << 1.0, 0.1, 0.2,  //
      0.1, 2.0, 0.3,   //
      0.2, 0.3, 3.0;
  const KDL::RotationalInertia KI = to_kdl_rotational_inertia(I);
  EXPECT_TRUE(agrees("bridge_inertia", vec(KI * KDL::Vector(0, 1, 0)), vec(Vector3<double>(0.1, 2.0, 0.3)), "Ixy"));
  EXPECT_TRUE(agrees("bridge_inertia", from_kdl(KI), I, "round trip"));

  // Random inertias: momentum, round trip and change of frame agree.
  std::mt19937 rng(11);
  for (int k = 0; k < 20; ++k) {
    const double m = 0.5 + k * 0.1;
    const Vector3<double> c = st::random_vector(3, rng, 0.5);
    const Matrix3<double> Ic = st::random_inertia_com(rng, m);
    const Inertia<double> ours = Inertia<double>::from_com(m, c, Ic);
    const KDL::RigidBodyInertia kdl = to_kdl_inertia(m, c, Ic);
    EXPECT_TRUE(agrees("bridge_inertia", from_kdl(kdl).matrix(), ours.matrix(), "from_com"));
    EXPECT_TRUE(agrees("bridge_inertia", from_kdl(to_kdl(ours)).matrix(), ours.matrix(), "round trip"));
    const Motion<double> v(Vector6<double>(st::random_vector(6, rng, 2.0)));
    EXPECT_TRUE(agrees("bridge_inertia", vec(ours * v), vec(from_kdl(kdl * to_kdl(v))), "momentum"));
    // X = ᴮX_A, inertia given in B: in A it is Xᵀ I X (ours) = (pose of B in A) * I (KDL).
    const Transform<double> X(st::random_rotation(rng), st::random_vector(3, rng, 1.0));
    EXPECT_TRUE(agrees("bridge_inertia", ours.transformed_inverse(X).matrix(), from_kdl(to_kdl(X) * kdl).matrix(),
                       "B->A"));
    EXPECT_TRUE(agrees("bridge_inertia", ours.transformed(X).matrix(),
                       from_kdl(to_kdl(X).Inverse() * kdl).matrix(), "A->B"));
    EXPECT_TRUE(agrees("bridge_inertia", ours.transformed_inverse(X).matrix(),
                       (X.matrix().transpose() * ours.matrix() * X.matrix()).eval(), "Xt I X"));
  }
}

// One body on a joint frame turned by 90° about z at (1, 2, 3) (hand_frame): its pose, centre of mass and inertia as
// KDL sees them, in every layout, against hand-computed values.
TEST_F(Bridge, SingleSegmentKnownGeometry) {
  const Matrix3<double> Ic = Vector3<double>(0.1, 0.2, 0.3).asDiagonal();
  const RandomBody revolute{-1, JointType::RevoluteZ, Vector3<double>::UnitZ(), hand_frame(), 2.0,
                            Vector3<double>(0.5, 0, 0), Ic};
  RandomBody prismatic = revolute;
  prismatic.type = JointType::PrismaticAxis;
  prismatic.axis = Vector3<double>::UnitY();
  // Revolute, q = π/2: the body is turned by 180° about z, origin still at (1, 2, 3); its CoM is at (0.5, 2, 3).
  // Prismatic along the joint frame's y axis (= A's −x axis), q = 2: body origin at (−1, 2, 3), axes as the joint
  // frame's; CoM at (−1, 2.5, 3).
  const KDL::Frame revolute_pose(KDL::Rotation(-1, 0, 0, 0, -1, 0, 0, 0, 1), KDL::Vector(1, 2, 3));
  const KDL::Frame prismatic_pose(KDL::Rotation(0, -1, 0, 1, 0, 0, 0, 0, 1), KDL::Vector(-1, 2, 3));
  struct Expect {
    RandomBody body;
    double q;
    KDL::Frame pose;
    Vector3<double> com;
  };
  for (const Expect& e : {Expect{revolute, kPi / 2, revolute_pose, Vector3<double>(0.5, 2, 3)},
                          Expect{prismatic, 2.0, prismatic_pose, Vector3<double>(-1, 2.5, 3)}}) {
    const std::vector<RandomBody> bodies{e.body};
    const VectorXd q = VectorXd::Constant(1, e.q);
    for (Layout layout : {Layout::FixedThenJoint, Layout::JointOrigin, Layout::TipAtNextJoint}) {
      const std::string at = std::string(joint_type_name(e.body.type)) + " " + layout_name(layout);
      const KdlChain kc(bodies, layout);
      KDL::ChainFkSolverPos_recursive fk(kc.chain());
      KDL::Frame pose;
      ASSERT_EQ(fk.JntToCart(kc.joints(q), pose), 0);
      EXPECT_TRUE(agrees("bridge_segment", vec(pose), vec(e.pose), at + " pose"));
      const KDL::Segment& seg = kc.chain().getSegment(kc.segment(0));
      EXPECT_TRUE(agrees("bridge_segment", vec(pose * seg.getInertia().getCOG()), vec(e.com), at + " CoM"));
      EXPECT_EQ(seg.getInertia().getMass(), 2.0);
      // About the CoM, in body axes: Ic.
      const Inertia<double> I = from_kdl(seg.getInertia());
      EXPECT_TRUE(agrees("bridge_segment", I.inertia_com(), Ic, at + " Ic"));
      if (layout == Layout::TipAtNextJoint) continue;
      const KdlTree kt(bodies, layout);
      KDL::TreeFkSolverPos_recursive tfk(kt.tree());
      ASSERT_EQ(tfk.JntToCart(kt.joints(q), pose, kt.segment(0)), 0);
      EXPECT_TRUE(agrees("bridge_segment", vec(pose), vec(e.pose), at + " tree pose"));
    }
  }
}

// A two-link planar arm about z, in closed form (any robotics text): link 1 of length l1, centres of mass at
// distance c1, c2 along each link's x axis (plus an out-of-plane offset that must not matter), gravity −g0 ŷ.
// Joint 1 sits at r0 and is turned by a fixed angle α about z, so the first absolute angle is θ1 = α + q1.
struct TwoLinkArm {
  double m1 = 1.3, m2 = 0.7, l1 = 0.9, c1 = 0.4, c2 = 0.35, g0 = 9.81, alpha = 0.6;
  Vector3<double> r0{0.3, -0.2, 0.5};
  Matrix3<double> Ic1, Ic2;  // about the CoMs; only the zz entries enter the planar dynamics
  TwoLinkArm() {
    Ic1 << 0.05, 0.01, -0.02,  //
        0.01, 0.06, 0.015,     //
        -0.02, 0.015, 0.08;
    Ic2 << 0.03, -0.005, 0.01,  //
        -0.005, 0.04, 0.002,    //
        0.01, 0.002, 0.02;
  }
  Vector3<double> gravity() const { return Vector3<double>(0, -g0, 0); }
  std::vector<RandomBody> bodies() const {
    RandomBody b1{-1, JointType::RevoluteZ, Vector3<double>::UnitZ(), Transform<double>(rotz_matrix(alpha), r0),
                  m1, Vector3<double>(c1, 0, 0.1), Ic1};
    RandomBody b2{0, JointType::RevoluteZ, Vector3<double>::UnitZ(),
                  Transform<double>(Matrix3<double>::Identity(), Vector3<double>(l1, 0, 0)),
                  m2, Vector3<double>(c2, 0, -0.2), Ic2};
    return {b1, b2};
  }
  Eigen::Matrix2d H(double q2) const {
    const double I1 = Ic1(2, 2), I2 = Ic2(2, 2), c = std::cos(q2);
    Eigen::Matrix2d h;
    h(0, 0) = I1 + m1 * c1 * c1 + I2 + m2 * (l1 * l1 + c2 * c2 + 2 * l1 * c2 * c);
    h(0, 1) = h(1, 0) = I2 + m2 * (c2 * c2 + l1 * c2 * c);
    h(1, 1) = I2 + m2 * c2 * c2;
    return h;
  }
  Eigen::Vector2d coriolis(const Eigen::Vector2d& q, const Eigen::Vector2d& qd) const {
    const double h = m2 * l1 * c2 * std::sin(q[1]);
    return Eigen::Vector2d(-h * (2 * qd[0] * qd[1] + qd[1] * qd[1]), h * qd[0] * qd[0]);
  }
  Eigen::Vector2d gravity_torques(const Eigen::Vector2d& q) const {
    const double t1 = alpha + q[0], t12 = t1 + q[1];
    const double g2 = m2 * c2 * g0 * std::cos(t12);
    return Eigen::Vector2d((m1 * c1 + m2 * l1) * g0 * std::cos(t1) + g2, g2);
  }
  Eigen::Vector2d tau(const Eigen::Vector2d& q, const Eigen::Vector2d& qd, const Eigen::Vector2d& qdd) const {
    return H(q[1]) * qdd + coriolis(q, qd) + gravity_torques(q);
  }
};

TEST_F(Bridge, TwoLinkArmClosedForm) {
  const TwoLinkArm arm;
  const std::vector<RandomBody> bodies = arm.bodies();
  const Model<double> model = st::build_model(bodies, arm.gravity());
  Data<double> data(model);
  const Eigen::Vector2d q(0.4, -1.1), qd(0.8, -1.5), qdd(2.0, 0.5);
  // A push of F = 3 N along body 2's y axis, applied at its centre of mass p = (c2, 0, −0.2): in body 2
  // coordinates the wrench is [p × F ŷ; F ŷ] = [(0.2 F, 0, c2 F); (0, F, 0)]. Its generalised forces are
  // F (l1 cos q2 + c2) on joint 1 and F c2 on joint 2; the joints then need that much less torque.
  const double F = 3.0;
  const std::vector<Force<double>> push{Force<double>::Zero(),
                                        Force<double>(Vector3<double>(0.2 * F, 0, arm.c2 * F), Vector3<double>(0, F, 0))};
  const Eigen::Vector2d tau = arm.tau(q, qd, qdd) - F * Eigen::Vector2d(arm.l1 * std::cos(q[1]) + arm.c2, arm.c2);
  EXPECT_TRUE(agrees("closed_form", rnea(model, data, q, qd, qdd, push), tau, "ours"));
  EXPECT_TRUE(agrees("closed_form", crba(model, data, q), arm.H(q[1]), "ours H"));

  for (Layout layout : {Layout::FixedThenJoint, Layout::JointOrigin, Layout::TipAtNextJoint}) {
    const KdlChain kc(bodies, layout);
    KDL::ChainIdSolver_RNE id(kc.chain(), to_kdl(arm.gravity()));
    KDL::JntArray out(2);
    ASSERT_EQ(id.CartToJnt(kc.joints(q), kc.joints(qd), kc.joints(qdd), kc.wrenches(push), out), 0);
    EXPECT_TRUE(agrees("closed_form", kc.joints(out), tau, std::string("KDL chain ") + layout_name(layout)));
    KDL::ChainDynParam dyn(kc.chain(), to_kdl(arm.gravity()));
    KDL::JntSpaceInertiaMatrix Hk(2);
    ASSERT_EQ(dyn.JntToMass(kc.joints(q), Hk), 0);
    EXPECT_TRUE(agrees("closed_form", from_kdl_joints(Hk, kc.q_index()), arm.H(q[1]),
                       std::string("KDL H ") + layout_name(layout)));
    if (layout == Layout::TipAtNextJoint) continue;
    const KdlTree kt(bodies, layout);
    KDL::TreeIdSolver_RNE tid(kt.tree(), to_kdl(arm.gravity()));
    ASSERT_EQ(tid.CartToJnt(kt.joints(q), kt.joints(qd), kt.joints(qdd), kt.wrenches(push), out), 0);
    EXPECT_TRUE(agrees("closed_form", kt.joints(out), tau, std::string("KDL tree ") + layout_name(layout)));
  }
}

// A single prismatic joint along a skew axis a, its joint frame turned by a random rotation: τ = m (q̈ − g · a₀)
// with a₀ = Eᵀ a the axis in base coordinates, whatever the centre of mass; a force f on the body adds −f · a.
TEST_F(Bridge, PrismaticClosedForm) {
  std::mt19937 rng(5);
  const Vector3<double> a = Vector3<double>(0.3, -0.8, 0.5).normalized();
  const Matrix3<double> E = st::random_rotation(rng);
  const double m = 1.7;
  const Vector3<double> g(1.0, -2.0, -9.5);
  const std::vector<RandomBody> bodies{RandomBody{-1, JointType::PrismaticAxis, a,
                                                  Transform<double>(E, Vector3<double>(0.1, 0.2, -0.3)), m,
                                                  Vector3<double>(0.2, -0.1, 0.05), st::random_inertia_com(rng, m)}};
  const Model<double> model = st::build_model(bodies, g);
  Data<double> data(model);
  const Force<double> push(Vector3<double>(0.3, 0.1, -0.2), Vector3<double>(1.0, 2.0, 0.5));  // body coordinates
  const std::vector<Force<double>> fext{push};
  for (double qdd : {-1.0, 0.0, 2.5}) {
    const VectorXd q = VectorXd::Constant(1, 0.4), qd = VectorXd::Constant(1, -0.7), acc = VectorXd::Constant(1, qdd);
    const VectorXd tau = VectorXd::Constant(1, m * (qdd - g.dot(E.transpose() * a)) - push.f.dot(a));
    EXPECT_TRUE(agrees("closed_form", rnea(model, data, q, qd, acc, fext), tau, "ours prismatic"));
    for (Layout layout : {Layout::FixedThenJoint, Layout::JointOrigin, Layout::TipAtNextJoint}) {
      const KdlChain kc(bodies, layout);
      KDL::ChainIdSolver_RNE id(kc.chain(), to_kdl(g));
      KDL::JntArray out(1);
      ASSERT_EQ(id.CartToJnt(kc.joints(q), kc.joints(qd), kc.joints(acc), kc.wrenches(fext), out), 0);
      EXPECT_TRUE(agrees("closed_form", kc.joints(out), tau, std::string("KDL prismatic ") + layout_name(layout)));
    }
  }
}

// ================================================================================================================
// 2. The KDL behaviours the bridge relies on (if a KDL release changes one, these say which).

using KdlBehaviour = KdlCheck;

// The f_tip given to a Segment is the tip pose relative to the segment ROOT at q = 0: KDL stores
// joint.pose(0)⁻¹ * f_tip, so a joint origin does not shift the tip.
TEST_F(KdlBehaviour, SegmentTipIsRootToTipAtZero) {
  const KDL::Frame tip(KDL::Rotation::RotX(0.3), KDL::Vector(1, 2, 3));
  const KDL::Segment seg("s", KDL::Joint("j", KDL::Vector(0.5, -1, 2), KDL::Vector(0, 0, 1), KDL::Joint::RotAxis),
                         tip);
  EXPECT_TRUE(agrees("kdl_behaviour", vec(seg.pose(0.0)), vec(tip), "pose(0)"));
  // At q the tip turns about the joint axis through the joint origin (0.5, −1, 2).
  const double q = 0.8;
  const KDL::Frame about_axis = KDL::Frame(KDL::Vector(0.5, -1, 2)) * KDL::Frame(KDL::Rotation::RotZ(q)) *
                                KDL::Frame(KDL::Vector(-0.5, 1, -2)) * tip;
  EXPECT_TRUE(agrees("kdl_behaviour", vec(seg.pose(q)), vec(about_axis), "pose(q)"));
}

// A KDL::Tree numbers its joints in the order segments are added, but a copy renumbers them depth-first, and
// TreeFkSolverPos_recursive works on a copy (TreeIdSolver_RNE on a reference). KdlTree adds segments depth-first so
// that all numberings agree.
TEST_F(KdlBehaviour, TreeCopyRenumbersJoints) {
  KDL::Tree t("base");
  t.addSegment(KDL::Segment("a", KDL::Joint("ja", KDL::Joint::RotZ)), "base");
  t.addSegment(KDL::Segment("b", KDL::Joint("jb", KDL::Joint::RotZ)), "base");
  t.addSegment(KDL::Segment("c", KDL::Joint("jc", KDL::Joint::RotZ)), "a");
  const KDL::Tree copy(t);
  const auto qnr = [](const KDL::Tree& tree, const char* name) { return GetTreeElementQNr(tree.getSegment(name)->second); };
  EXPECT_EQ(qnr(t, "b"), 1u);
  EXPECT_EQ(qnr(t, "c"), 2u);
  EXPECT_EQ(qnr(copy, "b"), 2u);
  EXPECT_EQ(qnr(copy, "c"), 1u);
  // So FK on the tree reads joint "c" from q(1), while the inverse dynamics reads it from q(2).
  KDL::TreeFkSolverPos_recursive fk(t);
  KDL::JntArray q(3);
  q(1) = 0.5;
  KDL::Frame pose;
  ASSERT_EQ(fk.JntToCart(q, pose, "c"), 0);
  EXPECT_TRUE(agrees("kdl_behaviour", vec(pose), vec(KDL::Frame(KDL::Rotation::RotZ(0.5))), "FK numbering"));

  // The same topology through the bridge: bodies 0 and 1 on the base, body 2 on body 0.
  std::vector<RandomBody> bodies = st::random_bodies(3, Shape::Chain, 3);
  bodies[1].parent = -1;
  bodies[2].parent = 0;
  const KdlTree kt(bodies, Layout::JointOrigin);
  EXPECT_EQ(kt.q_index(), (std::vector<unsigned>{0, 2, 1}));  // depth-first
  const KDL::Tree kt_copy(kt.tree());
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(qnr(kt_copy, kt.segment(i).c_str()), kt.q_index()[i]);
}

// ================================================================================================================
// 3. Random chains and trees.

struct Case {
  int n;
  unsigned seed;
  Layout layout;
};
void PrintTo(const Case& c, std::ostream* os) {
  *os << layout_name(c.layout) << " n=" << c.n << " seed=" << c.seed;
}
std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return std::string(layout_name(info.param.layout)) + "_n" + std::to_string(info.param.n) + "_seed" +
         std::to_string(info.param.seed);
}
std::vector<Case> cases(const std::vector<Layout>& layouts) {
  std::vector<Case> out;
  for (Layout l : layouts)
    for (int n : {1, 2, 3, 5, 8, 13, 21, 34, 60})
      for (unsigned seed : {1u, 2u, 3u}) out.push_back(Case{n, seed, l});
  return out;
}

class KdlChainCheck : public KdlCheck, public ::testing::WithParamInterface<Case> {};
class KdlTreeCheck : public KdlCheck, public ::testing::WithParamInterface<Case> {};

TEST_P(KdlChainCheck, AgreesWithKdl) {
  const Case c = GetParam();
  std::mt19937 rng(1000u + c.seed);
  const std::vector<RandomBody> bodies = st::random_bodies(c.n, Shape::Chain, c.seed);
  const Vector3<double> g = random_gravity(rng);
  const Model<double> model = st::build_model(bodies, g);
  const Model<double> model_no_gravity = model.with_gravity(Vector3<double>::Zero());
  Data<double> data(model);

  const KdlChain kc(bodies, c.layout);  // declared before, so destroyed after, every solver that refers to it
  const auto& qi = kc.q_index();
  const unsigned nj = kc.chain().getNrOfJoints();
  ASSERT_EQ(nj, static_cast<unsigned>(c.n));
  KDL::ChainIdSolver_RNE id(kc.chain(), to_kdl(g));
  KDL::ChainDynParam dyn(kc.chain(), to_kdl(g));
  KDL::ChainFdSolver_RNE fd(kc.chain(), to_kdl(g));
  KDL::ChainFkSolverPos_recursive fk(kc.chain());
  const KDL::Wrenches no_wrenches(kc.chain().getNrOfSegments(), KDL::Wrench::Zero());

  for (int k = 0; k < kStates; ++k) {
    const State s = random_state(c.n, rng);
    const std::string at = where("chain", c.n, c.seed, c.layout, k);
    const KDL::JntArray q = kc.joints(s.q), qd = kc.joints(s.qd), qdd = kc.joints(s.qdd), tau = kc.joints(s.tau);
    KDL::JntArray out(nj);

    // Forward kinematics: the pose of each body's KDL tip frame (ᵗⁱᵖX_0 = ᵗⁱᵖX_body ⁱX_0).
    forward_kinematics(model, data, s.q);
    for (int i = 0; i < c.n; ++i) {
      KDL::Frame tip;
      ASSERT_EQ(fk.JntToCart(q, tip, static_cast<int>(kc.segment(static_cast<std::size_t>(i))) + 1), 0);
      const Transform<double> ours = kc.tip_from_body(static_cast<std::size_t>(i)) * data.X_base[static_cast<std::size_t>(i)];
      EXPECT_TRUE(agrees("fk_pose", vec(to_kdl(ours)), vec(tip), at + " body " + std::to_string(i)));
    }

    // Inverse dynamics with gravity, velocities, accelerations and external forces in body coordinates ...
    ASSERT_EQ(id.CartToJnt(q, qd, qdd, kc.wrenches(s.fext), out), 0);
    EXPECT_TRUE(agrees("chain_id", rnea(model, data, s.q, s.qd, s.qdd, s.fext), from_kdl_joints(out, qi), at));
    // ... and in base coordinates.
    std::vector<Force<double>> f_base(s.fext.size());
    for (std::size_t i = 0; i < f_base.size(); ++i)
      f_base[i] = Force<double>(Vector6<double>(st::random_vector(6, rng, 5.0)));
    ASSERT_EQ(id.CartToJnt(q, qd, qdd, kc.wrenches_from_base(f_base, s.q), out), 0);
    EXPECT_TRUE(agrees("chain_id_base_forces", rnea(model, data, s.q, s.qd, s.qdd, f_base, ForceFrame::Base),
                       from_kdl_joints(out, qi), at));

    // Joint-space inertia.
    KDL::JntSpaceInertiaMatrix H(nj);
    ASSERT_EQ(dyn.JntToMass(q, H), 0);
    const MatrixXd H_kdl = from_kdl_joints(H, qi);
    EXPECT_TRUE(agrees("chain_mass", crba(model, data, s.q), H_kdl, at));

    // Gravity and Coriolis/centrifugal torques.
    ASSERT_EQ(dyn.JntToGravity(q, out), 0);
    const VectorXd G_kdl = from_kdl_joints(out, qi);
    const VectorXd G = gravity_torques(model, data, s.q);
    EXPECT_TRUE(agrees("chain_gravity", G, G_kdl, at));
    ASSERT_EQ(dyn.JntToCoriolis(q, qd, out), 0);
    const VectorXd C_kdl = from_kdl_joints(out, qi);
    // C from our bias forces without gravity ...
    EXPECT_TRUE(agrees("chain_coriolis", bias_forces(model_no_gravity, data, s.q, s.qd), C_kdl, at));
    // ... and as bias forces minus gravity torques: that difference carries rounding errors of the size of its
    // operands (eps ‖G‖), so it is measured relative to max(‖C‖, ‖G‖). (C is exactly zero for one joint.)
    const VectorXd C = bias_forces(model, data, s.q, s.qd) - G;
    EXPECT_TRUE(agrees("chain_bias_minus_gravity", C, C_kdl, at, std::max(kTiny, G_kdl.norm())));

    // Forward dynamics, with external forces (ABA) and without (ABA and CRBA + LTDL).
    ASSERT_EQ(fd.CartToJnt(q, qd, tau, kc.wrenches(s.fext), out), 0);
    EXPECT_TRUE(solves_alike("chain_fd_aba", aba(model, data, s.q, s.qd, s.tau, s.fext), from_kdl_joints(out, qi),
                             H_kdl, at));
    ASSERT_EQ(fd.CartToJnt(q, qd, tau, kc.wrenches_from_base(f_base, s.q), out), 0);
    EXPECT_TRUE(solves_alike("chain_fd_aba_base_forces", aba(model, data, s.q, s.qd, s.tau, f_base, ForceFrame::Base),
                             from_kdl_joints(out, qi), H_kdl, at));
    ASSERT_EQ(fd.CartToJnt(q, qd, tau, no_wrenches, out), 0);
    const VectorXd qdd_kdl = from_kdl_joints(out, qi);
    EXPECT_TRUE(solves_alike("chain_fd_aba", aba(model, data, s.q, s.qd, s.tau), qdd_kdl, H_kdl, at));
    EXPECT_TRUE(
        solves_alike("chain_fd_crba", forward_dynamics_crba(model, data, s.q, s.qd, s.tau), qdd_kdl, H_kdl, at));
  }
}

TEST_P(KdlTreeCheck, AgreesWithKdl) {
  const Case c = GetParam();
  std::mt19937 rng(2000u + c.seed);
  const std::vector<RandomBody> bodies = st::random_bodies(c.n, Shape::Branched, c.seed);
  const Vector3<double> g = random_gravity(rng);
  const Model<double> model = st::build_model(bodies, g);
  const Model<double> model_no_gravity = model.with_gravity(Vector3<double>::Zero());
  Data<double> data(model);

  const KdlTree kt(bodies, c.layout);  // declared before, so destroyed after, every solver that refers to it
  const auto& qi = kt.q_index();
  const unsigned nj = kt.tree().getNrOfJoints();
  ASSERT_EQ(nj, static_cast<unsigned>(c.n));
  KDL::TreeIdSolver_RNE id(kt.tree(), to_kdl(g));
  KDL::TreeIdSolver_RNE id_no_gravity(kt.tree(), KDL::Vector::Zero());
  KDL::TreeFkSolverPos_recursive fk(kt.tree());
  const VectorXd zero = VectorXd::Zero(c.n);

  for (int k = 0; k < kStates; ++k) {
    const State s = random_state(c.n, rng);
    const std::string at = where("tree", c.n, c.seed, c.layout, k);
    const KDL::JntArray q = kt.joints(s.q), qd = kt.joints(s.qd), qdd = kt.joints(s.qdd), z = kt.joints(zero);
    KDL::JntArray out(nj);

    forward_kinematics(model, data, s.q);
    for (int i = 0; i < c.n; ++i) {
      KDL::Frame tip;
      ASSERT_EQ(fk.JntToCart(q, tip, kt.segment(static_cast<std::size_t>(i))), 0);
      EXPECT_TRUE(agrees("fk_pose", vec(to_kdl(data.X_base[static_cast<std::size_t>(i)])), vec(tip),
                         at + " body " + std::to_string(i)));
    }

    // Inverse dynamics, external forces in body and in base coordinates.
    ASSERT_EQ(id.CartToJnt(q, qd, qdd, kt.wrenches(s.fext), out), 0);
    EXPECT_TRUE(agrees("tree_id", rnea(model, data, s.q, s.qd, s.qdd, s.fext), from_kdl_joints(out, qi), at));
    std::vector<Force<double>> f_base(s.fext.size());
    for (std::size_t i = 0; i < f_base.size(); ++i)
      f_base[i] = Force<double>(Vector6<double>(st::random_vector(6, rng, 5.0)));
    ASSERT_EQ(id.CartToJnt(q, qd, qdd, kt.wrenches_from_base(f_base, s.q), out), 0);
    EXPECT_TRUE(agrees("tree_id_base_forces", rnea(model, data, s.q, s.qd, s.qdd, f_base, ForceFrame::Base),
                       from_kdl_joints(out, qi), at));

    // Joint-space inertia, column by column: H e_j = ID(q, 0, e_j) − ID(q, 0, 0) without gravity.
    ASSERT_EQ(id_no_gravity.CartToJnt(q, z, z, KDL::WrenchMap(), out), 0);
    const VectorXd offset = from_kdl_joints(out, qi);
    MatrixXd H_kdl(c.n, c.n);
    for (int j = 0; j < c.n; ++j) {
      ASSERT_EQ(id_no_gravity.CartToJnt(q, z, kt.joints(VectorXd::Unit(c.n, j)), KDL::WrenchMap(), out), 0);
      H_kdl.col(j) = from_kdl_joints(out, qi) - offset;
    }
    EXPECT_TRUE(agrees("tree_mass", crba(model, data, s.q), H_kdl, at));

    // Gravity torques ID(q, 0, 0) and Coriolis/centrifugal torques ID(q, q̇, 0) without gravity.
    ASSERT_EQ(id.CartToJnt(q, z, z, KDL::WrenchMap(), out), 0);
    const VectorXd G = gravity_torques(model, data, s.q);
    EXPECT_TRUE(agrees("tree_gravity", G, from_kdl_joints(out, qi), at));
    ASSERT_EQ(id_no_gravity.CartToJnt(q, qd, z, KDL::WrenchMap(), out), 0);
    const VectorXd C_kdl = from_kdl_joints(out, qi);
    EXPECT_TRUE(agrees("tree_coriolis", bias_forces(model_no_gravity, data, s.q, s.qd), C_kdl, at));
    const VectorXd C = bias_forces(model, data, s.q, s.qd) - G;
    EXPECT_TRUE(agrees("tree_bias_minus_gravity", C, C_kdl, at, std::max(kTiny, G.norm())));

    // Forward dynamics (KDL has no tree solver): q̈ = H⁻¹ (τ − ID(q, q̇, 0, fext)) from KDL's numbers.
    ASSERT_EQ(id.CartToJnt(q, qd, z, kt.wrenches(s.fext), out), 0);
    const Eigen::LDLT<MatrixXd> ldlt(H_kdl);
    const VectorXd qdd_ext = ldlt.solve(s.tau - from_kdl_joints(out, qi));
    EXPECT_TRUE(solves_alike("tree_fd_aba", aba(model, data, s.q, s.qd, s.tau, s.fext), qdd_ext, H_kdl, at));
    ASSERT_EQ(id.CartToJnt(q, qd, z, kt.wrenches_from_base(f_base, s.q), out), 0);
    EXPECT_TRUE(solves_alike("tree_fd_aba_base_forces", aba(model, data, s.q, s.qd, s.tau, f_base, ForceFrame::Base),
                             VectorXd(ldlt.solve(s.tau - from_kdl_joints(out, qi))), H_kdl, at));
    ASSERT_EQ(id.CartToJnt(q, qd, z, KDL::WrenchMap(), out), 0);
    const VectorXd qdd_kdl = ldlt.solve(s.tau - from_kdl_joints(out, qi));
    EXPECT_TRUE(solves_alike("tree_fd_aba", aba(model, data, s.q, s.qd, s.tau), qdd_kdl, H_kdl, at));
    EXPECT_TRUE(
        solves_alike("tree_fd_crba", forward_dynamics_crba(model, data, s.q, s.qd, s.tau), qdd_kdl, H_kdl, at));
  }
}

INSTANTIATE_TEST_SUITE_P(Chains, KdlChainCheck,
                         ::testing::ValuesIn(cases({Layout::FixedThenJoint, Layout::JointOrigin,
                                                    Layout::TipAtNextJoint})),
                         case_name);
INSTANTIATE_TEST_SUITE_P(Trees, KdlTreeCheck,
                         ::testing::ValuesIn(cases({Layout::FixedThenJoint, Layout::JointOrigin})), case_name);

// A compile-time tree (unrolled loops, joint types known to the compiler) against KDL: every joint type, branches.
TEST_F(KdlCheck, CompileTimeTreeAgreesWithKdl) {
  using JT = JointType;
  using T = Tree<Parents<-1, 0, 1, 1, 3, -1, 5, 0>,
                 Joints<JT::RevoluteX, JT::PrismaticAxis, JT::RevoluteY, JT::PrismaticZ, JT::RevoluteAxis,
                        JT::PrismaticX, JT::RevoluteZ, JT::PrismaticY>>;
  std::vector<RandomBody> bodies = st::random_bodies(T::size, Shape::Chain, 42);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    bodies[i].parent = T::parent[i];
    bodies[i].type = T::joint[i];
    if (!has_axis(bodies[i].type))
      bodies[i].axis = Vector3<double>::Unit(static_cast<int>(bodies[i].type) % 4);  // X, Y, Z = 0, 1, 2
  }
  std::mt19937 rng(42);
  const Vector3<double> g = random_gravity(rng);
  const Model<double> dynamic_model = st::build_model(bodies, g);
  const auto model = Model<double, T>::from(dynamic_model);
  Data<double, T> data(model);
  const KdlTree kt(bodies, Layout::FixedThenJoint);
  const auto& qi = kt.q_index();
  KDL::TreeIdSolver_RNE id(kt.tree(), to_kdl(g));
  KDL::TreeIdSolver_RNE id_no_gravity(kt.tree(), KDL::Vector::Zero());
  const int n = T::size;
  const VectorXd zero = VectorXd::Zero(n);
  for (int k = 0; k < kStates; ++k) {
    const State s = random_state(n, rng);
    const std::string at = "compile-time tree state " + std::to_string(k);
    KDL::JntArray out(static_cast<unsigned>(n));
    const KDL::JntArray q = kt.joints(s.q), qd = kt.joints(s.qd), z = kt.joints(zero);
    ASSERT_EQ(id.CartToJnt(q, qd, kt.joints(s.qdd), kt.wrenches(s.fext), out), 0);
    const VectorXd tau_ours = rnea(model, data, s.q, s.qd, s.qdd, s.fext);
    EXPECT_TRUE(agrees("static_tree_id", tau_ours, from_kdl_joints(out, qi), at));
    MatrixXd H_kdl(n, n);
    for (int j = 0; j < n; ++j) {
      ASSERT_EQ(id_no_gravity.CartToJnt(q, z, kt.joints(VectorXd::Unit(n, j)), KDL::WrenchMap(), out), 0);
      H_kdl.col(j) = from_kdl_joints(out, qi);
    }
    const MatrixXd H_ours = crba(model, data, s.q);
    EXPECT_TRUE(agrees("static_tree_mass", H_ours, H_kdl, at));
    ASSERT_EQ(id.CartToJnt(q, qd, z, kt.wrenches(s.fext), out), 0);
    const VectorXd qdd_kdl = Eigen::LDLT<MatrixXd>(H_kdl).solve(s.tau - from_kdl_joints(out, qi));
    const VectorXd qdd_ours = aba(model, data, s.q, s.qd, s.tau, s.fext);
    EXPECT_TRUE(solves_alike("static_tree_fd_aba", qdd_ours, qdd_kdl, H_kdl, at));
  }
}

// The random trees exercise every joint type KDL has (and every type we have).
TEST(KdlCoverage, EveryJointTypeAndBranching) {
  std::map<JointType, int> seen;
  int branch_points = 0;
  for (Shape shape : {Shape::Chain, Shape::Branched})
    for (const Case& c : cases({Layout::JointOrigin})) {
      const std::vector<RandomBody> bodies = st::random_bodies(c.n, shape, c.seed);
      std::vector<int> children(bodies.size() + 1, 0);
      for (const RandomBody& b : bodies) {
        ++seen[b.type];
        ++children[static_cast<std::size_t>(b.parent + 1)];
      }
      for (int k : children) branch_points += k > 1;
    }
  EXPECT_EQ(seen.size(), 8u);
  for (const auto& [type, count] : seen) EXPECT_GT(count, 10) << joint_type_name(type);
  EXPECT_GT(branch_points, 20);
}

}  // namespace
