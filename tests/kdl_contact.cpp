// Cross-check of contact.hpp's constrained_forward_dynamics against KDL 1.5's ChainHdSolver_Vereshchagin (the
// Popov-Vereshchagin acceleration-constrained hybrid dynamics solver) on fixed-base random revolute chains whose
// end effector is held.
//
// What KDL's solver computes, read from its source (orocos_kdl/src/chainhdsolver_vereshchagin.cpp, 1.5.1):
//  - Chains only, with as many segments as joints (a fixed segment gets D = 0 and breaks the recursion), so the
//    bridge's Layout::JointOrigin is the layout it accepts: one segment per body, segment i's tip = our body i's
//    frame. Its end effector O is the last segment's tip, the last body's frame.
//  - Gravity is a root acceleration: root_acc = −g (the opposite sign of the g given to KDL's RNE solvers). Every
//    spatial acceleration inside the solver, the end effector's included, carries the fictitious −g.
//  - `alpha` (6 × nc, rows LINEAR first: [force; moment]) are unit constraint wrenches in BASE axes with the moment
//    about the END EFFECTOR's origin O (the solver rotates them into the tip frame, it does not move them).
//  - `beta` (nc): the constraint is αᵀ a_O = β, a_O the end effector's SPATIAL acceleration [a_lin; ω̇] in base axes
//    at O, root acceleration included: a_lin = p̈ − ω × ṗ − g. The "acceleration energy" is this projection (a unit
//    force times an acceleration); β = 0 with gravity on does NOT hold the end effector still.
//  - Outputs: q̈; ν (getContraintForceMagnitude; it asserts, not resizes, its argument's size): −α ν is the wrench
//    the constraint applies to the end effector (the minus sign is KDL's: ν enters its inward sweep like a bias
//    force). `constraint_torques` are NOT Jᵀ(−α ν) (only the last joint's is): joint i gets −Zᵢ·(Eᵢ ν), the
//    constraint wrench carried inwards through the articulated inertias of the joints beyond i, i.e. the
//    constraint's share of the ABA's uᵢ = τᵢ − Sᵢᵀ pᴬᵢ (see articulated_constraint_torques). M₀ is pseudo-inverted
//    by a truncated SVD (singular values < 1e-14 dropped), which only matters at singular configurations.
//
// The held frame P is our frame "ee", at a random placement on the last body. O itself would not do for a point
// contact: it lies on the last joint's axis, which then moves nothing the contact sees (Λ⁻¹ singular). KDL's α and β
// carry the offset r = P − O instead: the columns [f; n_P + r × f] are unit wrenches at P, and αᵀ a_O = a_P.
//
// What is compared (every random state: q uniform in [−π, π], q̇ in [−2, 2] rad/s, τ in [−5, 5] N·m):
//  1. 6D weld (our contact_6d on P: P's spatial acceleration, Local axes, = a*) ⇔ 6 columns,
//     β = R a* + [−g; 0] (a* = 0 without Baumgarte). A zero spatial acceleration is the same in every frame, and a*
//     is a function of the state, so this compares at any q̇. Chains of 7, 8 and 12 bodies (a weld of a chain with
//     ≤ 6 joints leaves no motion to compute).
//  2. 3D point contact (our contact_3d on P: the classical acceleration p̈ of P's origin, world axes, = a*) ⇔ the 3
//     force columns, β = a* − ω × ṗ − g: at q̇ = 0 spatial and classical accelerations coincide; at q̇ ≠ 0 they
//     differ by ω × ṗ, a function of the state only, which β takes (ω, ṗ from KDL's own velocity kinematics), so
//     non-zero velocities compare as well. Chains of 3 (the 3-body chain: three constraints on three
//     joints, q̈ is fixed by the kinematics and the dynamics show in the forces), 4, 5 and 8 bodies.
//  Each at q̇ = 0, at random q̇, and at random q̇ with Baumgarte gains (K_p = 100 /s², K_d = 20 /s) against a
//  perturbed target; a* from KDL's kinematics (p, R, ṗ, ω of P): 3D a* = −K_d ṗ − K_p (p − p*), 6D (base axes)
//  R a* = −K_d [ṗ; ω] − K_p [p − p*; R log(R*ᵀR)].
//  Quantities: q̈; the constraint force, our λ (LocalWorldAligned, and Local rotated to base axes) against −ν; the
//  constraint torques in KDL's sense (ours: data.u of ABA with λ applied at P minus data.u without), and that ABA's
//  q̈ against KDL's.
//  3. A constraint on some directions only (a 3-body chain whose point P may not accelerate along the base's x and
//     y axes, β zero or random), which our API cannot express (contacts are whole 3D or 6D): KDL against a dense KKT
//     solve from our building blocks (crba, rnea, frame_jacobian, frame_jdot_qdot: the spatial drift, since that is
//     what KDL's β constrains), NOT against constrained_forward_dynamics.
// Agreement: ‖ours − kdl‖ / max(‖kdl‖, s, 1e-4) ≤ 1e-10, with s = ‖q̈ of unconstrained ABA‖ for q̈ (the 3-body
// point contact at rest has q̈ = 0 exactly: the constraint cancels the free acceleration, both libraries leave
// rounding errors of its size) and s = 0 otherwise; the worst per quantity is printed at the end (measured:
// ≤ 4e-13).
// The test can fail: the constrained q̈ must differ from the unconstrained ABA result by more than 1e-3, and KDL
// given a wrong β (without the root acceleration: the naive "β = 0 holds the end effector"; for the point contact
// at q̇ ≠ 0, the classical acceleration taken for the spatial one) must disagree with us by more than 1e-3. (Flipping
// the sign of J̇ q̇ in constrained_forward_dynamics makes every comparison at q̇ ≠ 0 fail by O(1).)
//
// Not compared: external forces (KDL's f_ext are in base axes about each segment's tip; ours enter
// constrained_forward_dynamics only through τ); several contacts, or contacts on other bodies than the last (KDL
// constrains the end effector only); trees and floating bases (KDL's solver takes fixed-base chains); prismatic
// joints (the random chains here are revolute); impulse_dynamics and damping > 0 (no KDL counterpart; its truncated
// SVD is not a damped solve); singular configurations (KDL drops constraint directions, we would need damping).

#include "kdl_bridge.hpp"

#include <gtest/gtest.h>

#include <spatial/contact.hpp>

#include <kdl/chainfksolvervel_recursive.hpp>
#include <kdl/chainhdsolver_vereshchagin.hpp>
#include <kdl/framevel.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarrayvel.hpp>

#include <Eigen/LU>

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>
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

constexpr double kTol = 1e-10;
constexpr double kTiny = 1e-4;
/// How far apart a deliberately wrong input must put the results.
constexpr double kWrong = 1e-3;
constexpr double kPi = 3.14159265358979323846;
constexpr double kKp = 100.0, kKd = 20.0;

struct Worst {
  double err = 0.0;
  std::string where;
};
std::map<std::string, Worst>& worst() {
  static std::map<std::string, Worst> w;
  return w;
}
/// The smallest disagreement seen in the deliberately wrong runs (must stay large).
std::map<std::string, double>& least_wrong() {
  static std::map<std::string, double> w;
  return w;
}
class ReportWorst : public ::testing::Environment {
 public:
  void TearDown() override {
    std::printf("\nConstrained forward dynamics vs KDL's ChainHdSolver_Vereshchagin, largest relative disagreement "
                "(tolerance %.0e):\n",
                kTol);
    for (const auto& [k, v] : worst()) std::printf("  %-34s %10.3e  (%s)\n", k.c_str(), v.err, v.where.c_str());
    std::printf("Deliberately wrong inputs, smallest relative disagreement (must exceed %.0e):\n", kWrong);
    for (const auto& [k, v] : least_wrong()) std::printf("  %-34s %10.3e\n", k.c_str(), v);
  }
};
const auto* const kReport = ::testing::AddGlobalTestEnvironment(new ReportWorst);

double rel(const VectorXd& ours, const VectorXd& kdl, double scale = 0.0) {
  return (ours - kdl).norm() / std::max({kdl.norm(), scale, kTiny});
}
/// `scale`: the size of the operands the result is computed from, when the result itself can be zero (q̈ of three
/// joints whose end point is held at rest: the constraint cancels the free acceleration exactly).
double agree(const std::string& what, const std::string& where, const VectorXd& ours, const VectorXd& kdl,
             double scale = 0.0) {
  const double e = rel(ours, kdl, scale);
  Worst& w = worst()[what];
  if (e > w.err) w = Worst{e, where};
  return e;
}
double differ(const std::string& what, const VectorXd& a, const VectorXd& b) {
  const double e = rel(a, b);
  auto it = least_wrong().find(what);
  if (it == least_wrong().end())
    least_wrong()[what] = e;
  else
    it->second = std::min(it->second, e);
  return e;
}

const Vector3<double> kGravity(0.0, 0.0, -9.81);

/// A random revolute chain, as our model and as the KDL chain of Layout::JointOrigin (one segment per joint: what
/// ChainHdSolver_Vereshchagin accepts), from the same numbers. Our model has the frame "ee" at a random placement
/// on the last body (ᵉᵉX_body, origin within 0.3 of the body's): KDL's end effector is the last segment's tip, the
/// last body's frame, whose origin lies on the last joint's axis, so a point held there would leave that joint
/// free and Λ⁻¹ singular; the offset is carried into KDL's α and β instead (see Held).
class Rig {
 public:
  Rig(int n, unsigned seed)
      : bodies_(st::random_bodies(n, Shape::Chain, seed, /*all_joint_types=*/false)),
        kc_(bodies_, Layout::JointOrigin),
        ee_from_body_(offset(seed)),
        model_(build(bodies_, ee_from_body_)),
        ee_(model_.frame_index("ee")) {}
  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;

  const KdlChain& kdl() const { return kc_; }
  const Model<double>& model() const { return model_; }
  int ee() const { return ee_; }
  int n() const { return model_.size(); }
  const Transform<double>& ee_from_body() const { return ee_from_body_; }

 private:
  static Transform<double> offset(unsigned seed) {
    std::mt19937 rng(seed + 777u);
    const Matrix3<double> E = st::random_rotation(rng);
    return Transform<double>(E, 0.3 * Vector3<double>(st::random_vector(3, rng)));
  }
  static Model<double> build(const std::vector<RandomBody>& bodies, const Transform<double>& X) {
    ModelBuilder<double> b;
    b.set_gravity(kGravity);
    st::add_bodies(b, bodies);
    b.add_fixed_body("ee", static_cast<int>(bodies.size()) - 1, X, Inertia<double>::Zero());
    return b.build();
  }
  std::vector<RandomBody> bodies_;
  KdlChain kc_;
  Transform<double> ee_from_body_;
  Model<double> model_;
  int ee_;
};

/// The held frame P ("ee") seen from KDL: its pose and velocity by KDL's forward kinematics of the chain's tip O
/// (the last body's frame) and KDL's own frame and twist arithmetic; base axes.
struct Held {
  Vector3<double> p, pd, w;  ///< P's origin, the velocity of that point, the angular velocity
  Matrix3<double> R;         ///< P's axes in base axes
  Vector3<double> r;         ///< P's origin − O's origin (base axes)
  /// KDL's α for unit wrenches at P in base axes (columns [f; n_P], linear first), as its solver wants them: the
  /// same wrenches about O, [f; n_P + r × f]. Then αᵀ a_O = a_P for spatial accelerations in base axes.
  MatrixXd alpha(int columns) const {
    MatrixXd a = MatrixXd::Zero(6, columns);
    a.topRows(std::min(columns, 3)) = MatrixXd::Identity(std::min(columns, 3), columns);
    if (columns == 6) a.bottomRightCorner<3, 3>().setIdentity();
    for (int k = 0; k < std::min(columns, 3); ++k) a.col(k).tail<3>() = r.cross(Vector3<double>::Unit(k));
    return a;
  }
};
Held kdl_held_frame(const Rig& rig, const VectorXd& q, const VectorXd& v) {
  const KdlChain& kc = rig.kdl();
  KDL::ChainFkSolverVel_recursive fkv(kc.chain());
  KDL::FrameVel fv;
  if (fkv.JntToCart(KDL::JntArrayVel(kc.joints(q), kc.joints(v)), fv) < 0)
    throw std::runtime_error("KDL velocity kinematics failed");
  const KDL::Frame O = fv.GetFrame();
  const KDL::Frame P = O * to_kdl(rig.ee_from_body());  // pose of P in the base
  const KDL::Twist tP = fv.GetTwist().RefPoint(P.p - O.p);
  return Held{from_kdl(P.p), from_kdl(tP.vel), from_kdl(tP.rot), from_kdl(P.M), from_kdl(P.p - O.p)};
}

struct KdlResult {
  VectorXd qdd;          ///< our joint order
  VectorXd constraint;   ///< constraint_torques, our joint order
  VectorXd nu;           ///< constraint force magnitudes, one per column of alpha
};
/// ChainHdSolver_Vereshchagin with gravity as the root acceleration −g, no external forces, τ as ff_torques.
KdlResult kdl_hybrid_dynamics(const KdlChain& kc, const MatrixXd& alpha, const VectorXd& beta, const VectorXd& q,
                              const VectorXd& v, const VectorXd& tau) {
  const auto nc = static_cast<unsigned>(alpha.cols());
  const unsigned nj = kc.chain().getNrOfJoints();
  KDL::ChainHdSolver_Vereshchagin hd(kc.chain(), KDL::Twist(to_kdl(Vector3<double>(-kGravity)), KDL::Vector::Zero()),
                                     nc);
  KDL::Jacobian a(nc);
  a.data = alpha;
  KDL::JntArray b(nc);
  b.data = beta;
  const KDL::Wrenches f_ext(kc.chain().getNrOfSegments(), KDL::Wrench::Zero());
  KDL::JntArray qdd(nj), constraint(nj);
  const int rc = hd.CartToJnt(kc.joints(q), kc.joints(v), qdd, a, b, f_ext, kc.joints(tau), constraint);
  if (rc < 0) throw std::runtime_error("ChainHdSolver_Vereshchagin::CartToJnt failed: " + std::to_string(rc));
  KdlResult out;
  out.qdd = kc.joints(qdd);
  out.constraint = kc.joints(constraint);
  out.nu.resize(nc);  // getContraintForceMagnitude asserts the size, it does not resize
  hd.getContraintForceMagnitude(out.nu);
  return out;
}

/// KDL's constraint_torques are not Jᵀλ (only the last joint's is): joint i gets −Zᵢ·(Eᵢ ν), the constraint wrench
/// carried inwards through the ARTICULATED inertias of the joints beyond i (Eᵢ = (1 − Pᵢ Zᵢ Zᵢᵀ / Dᵢ) Eᵢ₊₁, the
/// ABA's bias-force recursion), i.e. the constraint's share of the ABA's uᵢ. Ours: the difference of data.u
/// between ABA with and without the constraint force λ applied to the last body; that ABA must also reproduce the
/// constrained q̈. `wrench_P`: [f; n_P] at P, base axes, linear first.
VectorXd articulated_constraint_torques(const Model<double>& model, Data<double>& data, const VectorXd& q,
                                        const VectorXd& v, const VectorXd& tau, const Vector6<double>& wrench_P,
                                        const Vector3<double>& p, VectorXd& qdd_with_force) {
  const int n = model.size();
  std::vector<Force<double>> f(static_cast<std::size_t>(n), Force<double>::Zero());
  const Vector3<double> force = wrench_P.head<3>();
  f.back() = Force<double>(wrench_P.tail<3>() + p.cross(force), force);  // about the base origin
  aba(model, data, q, v, tau);
  VectorXd u0(n);
  for (int i = 0; i < n; ++i) u0[i] = data.u[static_cast<std::size_t>(i)];
  qdd_with_force = aba(model, data, q, v, tau, f, ForceFrame::Base);
  VectorXd u(n);
  for (int i = 0; i < n; ++i) u[i] = data.u[static_cast<std::size_t>(i)];
  return u - u0;
}

// ---------------------------------------------------------------------------------------------------------------
// Our full contacts against KDL.

enum class Kind { Weld6D, Point3D };
struct Case {
  Kind kind;
  int n;
  unsigned seed;
};
std::vector<Case> cases() {
  std::vector<Case> out;
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    for (int n : {7, 8, 12}) out.push_back(Case{Kind::Weld6D, n, seed});
    for (int n : {3, 4, 5, 8}) out.push_back(Case{Kind::Point3D, n, seed});
  }
  return out;
}
std::string case_name(const Case& c) {
  return std::string(c.kind == Kind::Weld6D ? "Weld6D" : "Point3D") + "_n" + std::to_string(c.n) + "_seed" +
         std::to_string(c.seed);
}

class KdlContact : public ::testing::TestWithParam<Case> {};

TEST_P(KdlContact, ConstrainedForwardDynamicsAgreesWithVereshchagin) {
  const Case c = GetParam();
  const Rig rig(c.n, c.seed);
  const Model<double>& model = rig.model();
  const int n = rig.n();
  std::mt19937 rng(4000u + c.seed);
  const bool weld = c.kind == Kind::Weld6D;
  const int m = weld ? 6 : 3;
  const std::string kind = weld ? "weld 6D " : "point 3D ";

  Data<double> data(model), d2(model);
  RigidContact<double> contact = weld ? contact_6d(rig.ee(), ReferenceFrame::LocalWorldAligned)
                                      : contact_3d(rig.ee(), ReferenceFrame::LocalWorldAligned);
  for (int state = 0; state < 3; ++state) {
    const std::string where = case_name(c) + " state " + std::to_string(state);
    SCOPED_TRACE(where);
    const VectorXd q = st::random_vector(n, rng, kPi), tau = st::random_vector(n, rng, 5.0);
    const VectorXd v = state == 0 ? VectorXd(VectorXd::Zero(n)) : st::random_vector(n, rng, 2.0);
    const Held s = kdl_held_frame(rig, q, v);

    // The contact's Baumgarte gains and target (state 2 only), and the acceleration a* they ask for, in base axes
    // (linear first): 3D, p̈ = a*_lin; 6D, the spatial acceleration of P is a* (ours: Rᵀ a* in P's axes).
    const double kp = state == 2 ? kKp : 0.0, kd = state == 2 ? kKd : 0.0;
    const Vector3<double> p_star = s.p + 0.05 * Vector3<double>(st::random_vector(3, rng));
    const Matrix3<double> R_star =
        s.R * Eigen::AngleAxisd(0.1, Vector3<double>(st::random_vector(3, rng)).normalized()).toRotationMatrix();
    contact.kp = kp;
    contact.kd = kd;
    contact.target_position = p_star;
    contact.target_rotation = R_star;
    Vector6<double> a_star;
    a_star.head<3>() = -kd * s.pd - kp * (s.p - p_star);
    const KDL::Vector log_rel = (to_kdl_rotation(R_star).Inverse() * to_kdl_rotation(s.R)).GetRot();
    a_star.tail<3>() = -kd * s.w - kp * (s.R * from_kdl(log_rel));

    // KDL's α and β. Its accelerations carry the root acceleration −g; the spatial linear acceleration of P is
    // its classical one minus ω × ṗ.
    const MatrixXd alpha = s.alpha(m);
    Vector6<double> root;
    root << -kGravity, Vector3<double>::Zero();
    VectorXd beta, beta_wrong;
    std::string wrong;
    if (weld) {
      beta = a_star + root;
      beta_wrong = a_star;  // "β = a* (β = 0 holds the end effector)", forgetting the root acceleration
      wrong = "beta without root acc.";
    } else {
      beta = a_star.head<3>() - s.w.cross(s.pd) + root.head<3>();
      if (state == 0) {
        beta_wrong = a_star.head<3>();
        wrong = "beta without root acc.";
      } else {
        beta_wrong = beta + s.w.cross(s.pd);  // the classical acceleration taken for KDL's spatial one
        wrong = "beta classical, not spatial";
      }
    }

    // Ours.
    ContactData<Model<double>> cd(model, {contact});
    constrained_forward_dynamics(model, data, cd, q, v, tau);
    ASSERT_TRUE(cd.ok);
    const VectorXd qdd = cd.qdd, lambda = cd.lambda;
    RigidContact<double> local = contact;
    local.reference = ReferenceFrame::Local;
    ContactData<Model<double>> cl(model, {local});
    constrained_forward_dynamics(model, data, cl, q, v, tau);
    Vector6<double> wrench = Vector6<double>::Zero();  // [f; n_P], base axes
    wrench.head(m) = lambda;
    VectorXd qdd_aba;
    const VectorXd articulated = articulated_constraint_torques(model, d2, q, v, tau, wrench, s.p, qdd_aba);

    // KDL: the constraint wrench at P is −ν (see Held::alpha).
    const KdlResult k = kdl_hybrid_dynamics(rig.kdl(), alpha, beta, q, v, tau);
    const VectorXd lambda_kdl = -k.nu;
    VectorXd lambda_kdl_local(m);
    lambda_kdl_local.head<3>() = s.R.transpose() * lambda_kdl.head<3>();
    if (weld) lambda_kdl_local.tail<3>() = s.R.transpose() * lambda_kdl.tail<3>();

    const VectorXd free = aba(model, d2, q, v, tau);
    EXPECT_LT(agree(kind + "qdd", where, qdd, k.qdd, free.norm()), kTol)
        << "ours " << qdd.transpose() << "\nKDL  " << k.qdd.transpose();
    EXPECT_LT(agree(kind + "lambda (LWA)", where, lambda, lambda_kdl), kTol)
        << "ours " << lambda.transpose() << "\nKDL  " << lambda_kdl.transpose();
    EXPECT_LT(agree(kind + "lambda (Local)", where, cl.lambda, lambda_kdl_local), kTol);
    EXPECT_LT(agree(kind + "constraint torques", where, articulated, k.constraint), kTol)
        << "ours " << articulated.transpose() << "\nKDL  " << k.constraint.transpose();
    EXPECT_LT(agree(kind + "qdd of ABA with lambda", where, qdd_aba, k.qdd, free.norm()), kTol);

    // The test can fail: the constraint matters, and a wrong β shows.
    EXPECT_GT(differ(kind + "qdd vs unconstrained ABA", free, qdd), kWrong);
    const KdlResult w = kdl_hybrid_dynamics(rig.kdl(), alpha, beta_wrong, q, v, tau);
    EXPECT_GT(differ(kind + "qdd, " + wrong, qdd, w.qdd), kWrong) << wrong;
    // Jᵀλ is not what KDL calls constraint torques (except for the last joint).
    const VectorXd jt_lambda = rnea(model, d2, q, v, qdd) - tau;
    EXPECT_GT(differ(kind + "constraint torques vs J^T lambda", jt_lambda, k.constraint), kWrong);
  }
}

INSTANTIATE_TEST_SUITE_P(RandomRevoluteChains, KdlContact, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& info) { return case_name(info.param); });

// ---------------------------------------------------------------------------------------------------------------
// A constraint on two directions only: KDL against a dense KKT solve from our building blocks.

TEST(KdlContactPartial, ThreeBodyChainHeldAlongTwoBaseAxes) {
  for (unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    const Rig rig(3, seed);
    const Model<double>& model = rig.model();
    const int n = rig.n();
    std::mt19937 rng(5000u + seed);
    Data<double> data(model);
    for (int state = 0; state < 3; ++state) {
      const std::string where = "3 bodies seed " + std::to_string(seed) + " state " + std::to_string(state);
      SCOPED_TRACE(where);
      const VectorXd q = st::random_vector(n, rng, kPi), tau = st::random_vector(n, rng, 5.0);
      const VectorXd v = state == 0 ? VectorXd(VectorXd::Zero(n)) : st::random_vector(n, rng, 2.0);
      const VectorXd beta = state == 2 ? st::random_vector(2, rng, 3.0) : VectorXd(VectorXd::Zero(2));
      const Held s = kdl_held_frame(rig, q, v);
      const MatrixXd alpha = s.alpha(2);  // forces along the base's x and y at P

      // Ours: H v̇ + C = τ + Aᵀ f, A v̇ + (a_drift + [−g; 0])_xy = β, with A the x and y rows of P's
      // LocalWorldAligned Jacobian and a_drift P's spatial drift acceleration in base axes (frame_jdot_qdot).
      const MatrixXd H = crba(model, data, q);
      const VectorXd C = rnea(model, data, q, v, VectorXd::Zero(n));
      compute_joint_jacobians(model, data, q);
      MatrixXd J(6, n);
      frame_jacobian(model, data, rig.ee(), ReferenceFrame::LocalWorldAligned, J);
      const Motion<double> drift = frame_jdot_qdot(model, data, q, v, rig.ee(), ReferenceFrame::LocalWorldAligned);
      const MatrixXd A = J.topRows(2);
      MatrixXd K = MatrixXd::Zero(n + 2, n + 2);
      K.topLeftCorner(n, n) = H;
      K.topRightCorner(n, 2) = -A.transpose();
      K.bottomLeftCorner(2, n) = A;
      VectorXd rhs(n + 2);
      rhs << tau - C, beta - (drift.v - kGravity).head<2>();
      const VectorXd x = K.fullPivLu().solve(rhs);
      Vector6<double> wrench = Vector6<double>::Zero();
      wrench.head<2>() = x.tail(2);
      VectorXd qdd_aba;
      const VectorXd articulated = articulated_constraint_torques(model, data, q, v, tau, wrench, s.p, qdd_aba);

      const KdlResult k = kdl_hybrid_dynamics(rig.kdl(), alpha, beta, q, v, tau);
      const VectorXd free = aba(model, data, q, v, tau);
      EXPECT_LT(agree("2 directions qdd (dense KKT)", where, x.head(n), k.qdd, free.norm()), kTol)
          << "ours " << x.head(n).transpose() << "\nKDL  " << k.qdd.transpose();
      EXPECT_LT(agree("2 directions force (dense KKT)", where, x.tail(2), -k.nu), kTol)
          << "ours " << x.tail(2).transpose() << "\nKDL  " << (-k.nu).transpose();
      EXPECT_LT(agree("2 directions constraint torques", where, articulated, k.constraint), kTol);
      EXPECT_GT(differ("2 directions qdd vs unconstrained", free, k.qdd), kWrong);
    }
  }
}

}  // namespace
