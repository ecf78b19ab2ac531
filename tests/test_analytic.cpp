// The algorithms against closed-form mechanics: single pendulums, the double inverted pendulum of the HOAP-3
// thesis (eqs. 4.10–4.20), a prismatic joint along gravity, energy conservation of a free-swinging chain, external
// forces against virtual work, and forward kinematics of a planar arm.
//
// Tolerances: the closed forms are evaluated in double with O(1)–O(100) values; the library's results differ from
// them by rounding only, so 1e-12 relative is ~10³ ulps of margin. Finite-difference references use their own
// (documented) looser bounds.

#include <spatial/spatial.hpp>

#include "support/random_model.hpp"
#include "support/reference.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace {

using namespace spatial;
using spatial::testing::abs_diff;
using spatial::testing::rel_diff;
using Vec = Eigen::VectorXd;
using V3 = Vector3<double>;
using M3 = Matrix3<double>;

constexpr double kG = 9.81;
constexpr double kTight = 1e-12;

Vec vec(std::initializer_list<double> x) {
  Vec v(static_cast<Eigen::Index>(x.size()));
  Eigen::Index i = 0;
  for (double e : x) v[i++] = e;
  return v;
}

// ---------------------------------------------------------------------------------------------------------------
// Single pendulum
// ---------------------------------------------------------------------------------------------------------------

// A pendulum hanging from a revolute joint about y: a point mass m at (0, 0, −l) in the body frame. Rotating the
// body actively by q about y puts the mass at (−l sin q, 0, −l cos q): height −l cos q, so V = −m g l cos q, and
// Lagrange gives τ = m l² q̈ + m g l sin q. The joint is placed by a rotation about the vertical and a translation,
// which changes neither the plane's verticality nor the equation.
TEST(SinglePendulum, PointMassAboutY) {
  const double m = 1.7, l = 0.8;
  ModelBuilder<double> b;
  b.add_body("bob", -1, JointType::RevoluteY, Transform<double>(rotz_matrix(0.7), V3(0.3, -0.2, 1.0)),
             Inertia<double>::from_com(m, V3(0, 0, -l), M3::Zero()));
  const Model<double> model = b.build();
  Data<double> d(model);
  std::mt19937 rng(1);
  for (int t = 0; t < 100; ++t) {
    const Vec q = spatial::testing::random_vector(1, rng, 3.0), qd = spatial::testing::random_vector(1, rng, 3.0),
              qdd = spatial::testing::random_vector(1, rng, 3.0);
    const double tau_ref = m * l * l * qdd[0] + m * kG * l * std::sin(q[0]);
    EXPECT_NEAR(rnea(model, d, q, qd, qdd)[0], tau_ref, kTight * (1 + std::abs(tau_ref))) << "q " << q[0];
    EXPECT_NEAR(crba(model, d, q)(0, 0), m * l * l, kTight);
    EXPECT_NEAR(gravity_torques(model, d, q)[0], m * kG * l * std::sin(q[0]), kTight * 20);
    // A single revolute joint has no velocity-product torque.
    EXPECT_NEAR(bias_forces(model, d, q, qd)[0], m * kG * l * std::sin(q[0]), kTight * 20);
    const Vec tau = spatial::testing::random_vector(1, rng, 10.0);
    const double qdd_ref = (tau[0] - m * kG * l * std::sin(q[0])) / (m * l * l);
    EXPECT_NEAR(aba(model, d, q, qd, tau)[0], qdd_ref, kTight * (1 + std::abs(qdd_ref)));
    EXPECT_NEAR(forward_dynamics_crba(model, d, q, qd, tau)[0], qdd_ref, kTight * (1 + std::abs(qdd_ref)));
    EXPECT_NEAR(potential_energy(model, d, q), m * kG * (1.0 - l * std::cos(q[0])), kTight * 20);
    EXPECT_NEAR(kinetic_energy(model, d, q, qd), 0.5 * m * l * l * qd[0] * qd[0], kTight * 20);
  }
}

// A uniform thin rod of length l hanging from a revolute joint about x: centre of mass (0, 0, −l/2), inertia about
// the centre m l²/12 about x and y. Rotating actively by q about x puts the centre at (0, (l/2) sin q,
// −(l/2) cos q), so τ = (m l²/3) q̈ + m g (l/2) sin q.
TEST(SinglePendulum, RodAboutX) {
  const double m = 2.3, l = 1.1;
  ModelBuilder<double> b;
  M3 Ic = M3::Zero();
  Ic.diagonal() << m * l * l / 12, m * l * l / 12, 1e-6;
  b.add_body("rod", -1, JointType::RevoluteX, Transform<double>::Identity(),
             Inertia<double>::from_com(m, V3(0, 0, -l / 2), Ic));
  const Model<double> model = b.build();
  Data<double> d(model);
  std::mt19937 rng(2);
  for (int t = 0; t < 100; ++t) {
    const Vec q = spatial::testing::random_vector(1, rng, 3.0), qd = spatial::testing::random_vector(1, rng, 3.0),
              qdd = spatial::testing::random_vector(1, rng, 3.0);
    const double J = m * l * l / 3;
    const double tau_ref = J * qdd[0] + m * kG * (l / 2) * std::sin(q[0]);
    EXPECT_NEAR(rnea(model, d, q, qd, qdd)[0], tau_ref, kTight * (1 + std::abs(tau_ref)));
    EXPECT_NEAR(crba(model, d, q)(0, 0), J, kTight);
    const Vec tau = spatial::testing::random_vector(1, rng, 10.0);
    const double qdd_ref = (tau[0] - m * kG * (l / 2) * std::sin(q[0])) / J;
    EXPECT_NEAR(aba(model, d, q, qd, tau)[0], qdd_ref, kTight * (1 + std::abs(qdd_ref)));
    EXPECT_NEAR(forward_dynamics_crba(model, d, q, qd, tau)[0], qdd_ref, kTight * (1 + std::abs(qdd_ref)));
  }
}

// The bob attached as a fixed body to a massless link: add_fixed_body must merge exactly the point-mass inertia.
TEST(SinglePendulum, FixedBodyIsMergedIntoItsParent) {
  const double m = 0.9, l = 0.6;
  ModelBuilder<double> b;
  const int link = b.add_body("link", -1, JointType::RevoluteY, Transform<double>::Identity(), Inertia<double>::Zero());
  b.add_fixed_body("bob", link, xlt(V3(0, 0, -l)), Inertia<double>::from_com(m, V3::Zero(), M3::Zero()));
  const Model<double> model = b.build();
  ASSERT_EQ(model.size(), 1);
  ASSERT_EQ(model.frames().size(), 1u);
  EXPECT_EQ(model.frames()[0].name, "bob");
  EXPECT_NEAR(model.inertia(0).m, m, 0);
  EXPECT_LE(abs_diff(model.inertia(0).h, V3(0, 0, -m * l)), 1e-15);
  M3 Iref = M3::Zero();
  Iref.diagonal() << m * l * l, m * l * l, 0;
  EXPECT_LE(abs_diff(model.inertia(0).I, Iref), 1e-15);
  Data<double> d(model);
  const Vec q = vec({0.4}), qd = vec({-1.0}), qdd = vec({2.0});
  EXPECT_NEAR(rnea(model, d, q, qd, qdd)[0], m * l * l * 2.0 + m * kG * l * std::sin(0.4), kTight * 10);
  // The frame sits at the bob.
  forward_kinematics(model, d, q);
  const auto pose = frame_pose(model, d, 0);
  EXPECT_LE(abs_diff(pose.translation(), V3(-l * std::sin(0.4), 0, -l * std::cos(0.4))), kTight);
}

// ---------------------------------------------------------------------------------------------------------------
// Double inverted pendulum (HOAP-3 thesis, §4.5, eqs. 4.10–4.20)
// ---------------------------------------------------------------------------------------------------------------
//
// Point masses m1 (hip, end of link 1) and m2 (end of link 2) on massless rods l1, l2; gravity −z; θ1, θ2 are the
// ABSOLUTE angles of the links from the upward vertical, in the x–z plane: x1 = l1 sin θ1, z1 = l1 cos θ1 (4.10,
// 4.11), x2 = x1 + l2 sin θ2, z2 = z1 + l2 cos θ2 (4.12, 4.13). Tilting the z axis towards x is a positive rotation
// about y, so both joints are RevoluteY, link 1 at the base origin, link 2 at (0, 0, l1) in link 1, each mass at
// (0, 0, lᵢ) in its own body frame.
//
// Our model uses RELATIVE joint angles: q1 = θ1, q2 = θ2 − θ1, i.e. θ = T q with T = [1 0; 1 1].
//
// Eqs. 4.19–4.20 give Q1, Q2, the generalised forces conjugate to θ1, θ2. (The thesis's Lagrangian 4.17 has two
// typos – ½ m1 l1² θ̇1² should read ½ (m1+m2) l1² θ̇1², and the last term should be −m2 g l2 cos θ2 since
// V = m1 g z1 + m2 g z2 – but 4.19–4.20 are what the correct Lagrangian gives; we re-derived them.)
// Joint torques τj follow from virtual work: Q·δθ = τj·δq for all δq with δθ = T δq, so τj = Tᵀ Q:
//   τj1 = Q1 + Q2  (ankle torque),  τj2 = Q2  (hip torque).
// Physically: the hip torque acts on link 2 (+τj2) and reacts on link 1 (−τj2), so Q1 = τj1 − τj2.
// Likewise the joint-space inertia is H = Tᵀ M(θ) T with M the θ-space inertia read off 4.19–4.20.
struct DoublePendulum {
  double m1 = 1.3, m2 = 2.1, l1 = 0.7, l2 = 0.45;

  Model<double> model() const {
    ModelBuilder<double> b;
    b.set_gravity(V3(0, 0, -kG));
    const int leg = b.add_body("leg", -1, JointType::RevoluteY, Transform<double>::Identity(),
                               Inertia<double>::from_com(m1, V3(0, 0, l1), M3::Zero()), V3::Zero(), "ankle");
    b.add_body("torso", leg, JointType::RevoluteY, xlt(V3(0, 0, l1)),
               Inertia<double>::from_com(m2, V3(0, 0, l2), M3::Zero()), V3::Zero(), "hip");
    return b.build();
  }
  /// Eqs. 4.19–4.20: generalised forces conjugate to the absolute angles.
  Eigen::Vector2d Q(const Eigen::Vector2d& th, const Eigen::Vector2d& thd, const Eigen::Vector2d& thdd) const {
    const double c12 = std::cos(th[0] - th[1]), s12 = std::sin(th[0] - th[1]);
    Eigen::Vector2d out;
    out[0] = (m1 + m2) * l1 * l1 * thdd[0] + m2 * l1 * l2 * thdd[1] * c12 + m2 * l1 * l2 * thd[1] * thd[1] * s12 -
             (m1 + m2) * kG * l1 * std::sin(th[0]);
    out[1] = m2 * l2 * l2 * thdd[1] + m2 * l1 * l2 * thdd[0] * c12 - m2 * l1 * l2 * thd[0] * thd[0] * s12 -
             m2 * kG * l2 * std::sin(th[1]);
    return out;
  }
  /// θ-space inertia, the coefficients of θ̈ in 4.19–4.20.
  Eigen::Matrix2d M(const Eigen::Vector2d& th) const {
    const double c12 = std::cos(th[0] - th[1]);
    Eigen::Matrix2d out;
    out << (m1 + m2) * l1 * l1, m2 * l1 * l2 * c12, m2 * l1 * l2 * c12, m2 * l2 * l2;
    return out;
  }
  static Eigen::Matrix2d T() {
    Eigen::Matrix2d t;
    t << 1, 0, 1, 1;
    return t;
  }
  static Eigen::Vector2d theta(const Vec& q) { return T() * Eigen::Vector2d(q[0], q[1]); }
  /// Joint torques from (4.19, 4.20): τj = Tᵀ Q.
  Eigen::Vector2d tau_joint(const Vec& q, const Vec& qd, const Vec& qdd) const {
    return T().transpose() * Q(theta(q), theta(qd), theta(qdd));
  }
};

TEST(DoubleInvertedPendulum, AllAlgorithmsMatchThesisEquations) {
  const DoublePendulum P;
  const Model<double> model = P.model();
  Data<double> d(model);
  ASSERT_EQ(model.joint_index("hip"), 1);
  std::mt19937 rng(3);
  double worst_rnea = 0, worst_H = 0, worst_aba = 0, worst_crba_fd = 0;
  for (int t = 0; t < 500; ++t) {
    const Vec q = spatial::testing::random_vector(2, rng, 3.2), qd = spatial::testing::random_vector(2, rng, 4.0),
              qdd = spatial::testing::random_vector(2, rng, 10.0);
    const Eigen::Vector2d tau_ref = P.tau_joint(q, qd, qdd);
    const double scale = 1 + tau_ref.cwiseAbs().maxCoeff();
    // Inverse dynamics.
    const double e_rnea = abs_diff(rnea(model, d, q, qd, qdd), tau_ref) / scale;
    EXPECT_LE(e_rnea, kTight) << "q " << q.transpose() << " qd " << qd.transpose();
    worst_rnea = std::max(worst_rnea, e_rnea);
    // Bias and gravity terms: 4.19–4.20 with θ̈ = 0, and with θ̇ = θ̈ = 0.
    const Vec zero = Vec::Zero(2);
    EXPECT_LE(abs_diff(bias_forces(model, d, q, qd), P.tau_joint(q, qd, zero)) / scale, kTight);
    EXPECT_LE(abs_diff(gravity_torques(model, d, q), P.tau_joint(q, zero, zero)) / scale, kTight);
    // Joint-space inertia H = Tᵀ M T.
    const Eigen::Matrix2d H_ref = DoublePendulum::T().transpose() * P.M(DoublePendulum::theta(q)) * DoublePendulum::T();
    const double e_H = abs_diff(crba(model, d, q), H_ref) / H_ref.cwiseAbs().maxCoeff();
    EXPECT_LE(e_H, kTight);
    worst_H = std::max(worst_H, e_H);
    // Forward dynamics: q̈ = H⁻¹ (τ − C), with the 2×2 inverse written out.
    const Eigen::Vector2d tau(spatial::testing::random_vector(2, rng, 20.0));
    const Eigen::Vector2d rhs = tau - P.tau_joint(q, qd, zero);
    const double det = H_ref(0, 0) * H_ref(1, 1) - H_ref(0, 1) * H_ref(1, 0);
    const Eigen::Vector2d qdd_ref((H_ref(1, 1) * rhs[0] - H_ref(0, 1) * rhs[1]) / det,
                                  (H_ref(0, 0) * rhs[1] - H_ref(1, 0) * rhs[0]) / det);
    // cond(H) is at most ~52 for these masses and lengths; 1e-11 relative leaves room for it.
    const double qscale = 1 + qdd_ref.cwiseAbs().maxCoeff();
    const double e_aba = abs_diff(aba(model, d, q, qd, Vec(tau)), qdd_ref) / qscale;
    const double e_fd = abs_diff(forward_dynamics_crba(model, d, q, qd, Vec(tau)), qdd_ref) / qscale;
    EXPECT_LE(e_aba, 1e-11);
    EXPECT_LE(e_fd, 1e-11);
    worst_aba = std::max(worst_aba, e_aba);
    worst_crba_fd = std::max(worst_crba_fd, e_fd);
    // Energies: T = ½ θ̇ᵀ M θ̇, V = g (m1 z1 + m2 z2).
    const Eigen::Vector2d th = DoublePendulum::theta(q), thd = DoublePendulum::theta(qd);
    const double T_ref = 0.5 * thd.dot(P.M(th) * thd);
    const double V_ref = kG * (P.m1 * P.l1 * std::cos(th[0]) + P.m2 * (P.l1 * std::cos(th[0]) + P.l2 * std::cos(th[1])));
    EXPECT_NEAR(kinetic_energy(model, d, q, qd), T_ref, kTight * (1 + T_ref));
    EXPECT_NEAR(potential_energy(model, d, q), V_ref, kTight * 100);
  }
  std::printf("  double pendulum: worst rel. error rnea %.2e, crba %.2e, aba %.2e, crba+ltdl %.2e\n", worst_rnea,
              worst_H, worst_aba, worst_crba_fd);
}

// Hand-checked special cases: upright, no torque holds it. Link 1 tilted by θ1 = a towards +x and link 2 upright
// (θ2 = 0, i.e. q = (a, −a)): the hip torque is zero (mass 2 straight above the hip), and the ankle must pull back
// against the whole weight at lever l1 sin a: τj1 = −(m1 + m2) g l1 sin a (the gravity term of 4.19).
TEST(DoubleInvertedPendulum, StaticSpecialCases) {
  const DoublePendulum P;
  const Model<double> model = P.model();
  Data<double> d(model);
  EXPECT_LE(gravity_torques(model, d, vec({0, 0})).cwiseAbs().maxCoeff(), 1e-15);
  const double a = 0.3;
  const Vec tau = gravity_torques(model, d, vec({a, -a}));
  EXPECT_NEAR(tau[0], -(P.m1 + P.m2) * kG * P.l1 * std::sin(a), 1e-13);
  EXPECT_NEAR(tau[1], 0.0, 1e-13);
}

TEST(DoubleInvertedPendulum, CenterOfMassAndPotentialEnergy) {
  const DoublePendulum P;
  const Model<double> model = P.model();
  Data<double> d(model);
  const Vec q = vec({0.35, -0.8});
  const double t1 = q[0], t2 = q[0] + q[1];
  const V3 p1(P.l1 * std::sin(t1), 0, P.l1 * std::cos(t1));
  const V3 p2 = p1 + V3(P.l2 * std::sin(t2), 0, P.l2 * std::cos(t2));
  const V3 com_ref = (P.m1 * p1 + P.m2 * p2) / (P.m1 + P.m2);
  EXPECT_LE(abs_diff(center_of_mass(model, d, q), com_ref), kTight);
  EXPECT_NEAR(potential_energy(model, d, q), kG * (P.m1 * p1.z() + P.m2 * p2.z()), kTight * 10);
  EXPECT_NEAR(model.total_mass(), P.m1 + P.m2, 1e-15);
  EXPECT_NEAR(model.subtree_mass(1), P.m2, 1e-15);
  // Potential energy is relative to the gravity vector given: turning gravity off makes it zero.
  const Model<double> nog = model.with_gravity(V3::Zero());
  Data<double> d0(nog);
  EXPECT_EQ(potential_energy(nog, d0, q), 0.0);
}

// ---------------------------------------------------------------------------------------------------------------
// Prismatic joints
// ---------------------------------------------------------------------------------------------------------------

// A body of mass m sliding along z, gravity −g z: τ = m (q̈ + g), whatever its centre of mass and rotational inertia.
TEST(Prismatic, AlongGravity) {
  const double m = 3.4;
  ModelBuilder<double> b;
  M3 Ic = M3::Zero();
  Ic.diagonal() << 0.1, 0.2, 0.25;
  b.add_body("slider", -1, JointType::PrismaticZ, xlt(V3(0.1, 0.2, 0.3)),
             Inertia<double>::from_com(m, V3(0.3, -0.1, 0.2), Ic));
  const Model<double> model = b.build();
  Data<double> d(model);
  std::mt19937 rng(4);
  for (int t = 0; t < 50; ++t) {
    const Vec q = spatial::testing::random_vector(1, rng, 2.0), qd = spatial::testing::random_vector(1, rng, 2.0),
              qdd = spatial::testing::random_vector(1, rng, 5.0);
    EXPECT_NEAR(rnea(model, d, q, qd, qdd)[0], m * (qdd[0] + kG), kTight * 100);
    EXPECT_NEAR(crba(model, d, q)(0, 0), m, kTight);
    const Vec tau = spatial::testing::random_vector(1, rng, 50.0);
    EXPECT_NEAR(aba(model, d, q, qd, tau)[0], tau[0] / m - kG, kTight * 100);
    EXPECT_NEAR(forward_dynamics_crba(model, d, q, qd, tau)[0], tau[0] / m - kG, kTight * 100);
    EXPECT_NEAR(potential_energy(model, d, q), m * kG * (0.3 + q[0] + 0.2), kTight * 100);
  }
}

// Sliding along an arbitrary unit axis a: τ = m q̈ − m a·g.
TEST(Prismatic, AlongArbitraryAxis) {
  const double m = 1.6;
  const V3 a = V3(0.3, -0.5, 0.8).normalized();
  ModelBuilder<double> b;
  b.add_body("slider", -1, JointType::PrismaticAxis, Transform<double>::Identity(),
             Inertia<double>::from_com(m, V3(0.1, 0.1, 0.1), M3::Identity() * 0.01), V3(0.3, -0.5, 0.8) * 7.0);
  const Model<double> model = b.build();
  EXPECT_LE(abs_diff(model.axis(0), a), 1e-15) << "the builder normalises the axis";
  Data<double> d(model);
  const Vec q = vec({0.7}), qd = vec({-0.3}), qdd = vec({1.9});
  EXPECT_NEAR(rnea(model, d, q, qd, qdd)[0], m * qdd[0] - m * a.dot(V3(0, 0, -kG)), kTight * 100);
}

// ---------------------------------------------------------------------------------------------------------------
// Energy conservation of a free-swinging chain
// ---------------------------------------------------------------------------------------------------------------

// RK4 on ẋ = (q̇, ABA(q, q̇, 0)); with no torque, no friction and gravity conservative, E = T + V is constant. RK4's
// global error is O(h⁴); with h = 2.5e-4 s over 1.5 s the observed drift is ~2e-12 (revolute chains) and ~1.3e-10
// (with prismatic joints, which reach higher speeds) of |E| + max T. The bound 1e-8 keeps a wide margin, while any
// wrong term in ABA or in either energy (a missing Coriolis term, a wrong sign of gravity in one of them, a wrong
// inertia transform) breaks it by many orders of magnitude.
void check_energy_conservation(const Model<double>& model, unsigned seed, double* worst) {
  Data<double> d(model);
  const int n = model.size();
  std::mt19937 rng(seed);
  Vec q = spatial::testing::random_vector(n, rng, 1.0), qd = spatial::testing::random_vector(n, rng, 1.0);
  const Vec tau = Vec::Zero(n);
  const double h = 2.5e-4;
  const int steps = 6000;
  auto energy = [&](const Vec& x, const Vec& xd) {
    return kinetic_energy(model, d, x, xd) + potential_energy(model, d, x);
  };
  const double E0 = energy(q, qd);
  double max_T = 0, max_dev = 0;
  Vec k1q(n), k1v(n), k2q(n), k2v(n), k3q(n), k3v(n), k4q(n), k4v(n);
  for (int s = 0; s < steps; ++s) {
    k1q = qd;
    k1v = aba(model, d, q, qd, tau);
    k2q = qd + 0.5 * h * k1v;
    k2v = aba(model, d, Vec(q + 0.5 * h * k1q), k2q, tau);
    k3q = qd + 0.5 * h * k2v;
    k3v = aba(model, d, Vec(q + 0.5 * h * k2q), k3q, tau);
    k4q = qd + h * k3v;
    k4v = aba(model, d, Vec(q + h * k3q), k4q, tau);
    q += h / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
    qd += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    max_T = std::max(max_T, kinetic_energy(model, d, q, qd));
    max_dev = std::max(max_dev, std::abs(energy(q, qd) - E0));
  }
  ASSERT_GT(max_T, 0.1) << "the chain must actually swing";
  const double rel = max_dev / (std::abs(E0) + max_T);
  EXPECT_LE(rel, 1e-8) << "energy drift " << max_dev << " of E0 " << E0;
  *worst = std::max(*worst, rel);
}

TEST(EnergyConservation, FreeSwingingRevoluteChain) {
  double worst = 0;
  check_energy_conservation(spatial::testing::random_model(5, spatial::testing::Shape::Chain, 101, false), 7, &worst);
  check_energy_conservation(spatial::testing::random_model(4, spatial::testing::Shape::Branched, 102, false), 8,
                            &worst);
  std::printf("  worst relative energy drift (revolute): %.2e\n", worst);
}

TEST(EnergyConservation, FreeChainWithPrismaticJoints) {
  double worst = 0;
  check_energy_conservation(spatial::testing::random_model(5, spatial::testing::Shape::Chain, 103, true), 9, &worst);
  std::printf("  worst relative energy drift (all joint types): %.2e\n", worst);
}

// ---------------------------------------------------------------------------------------------------------------
// External forces
// ---------------------------------------------------------------------------------------------------------------

// A force F (base coordinates) through a point p fixed in body k, plus a couple N (base coordinates), does virtual
// work Qᵢ = F · ∂p/∂qᵢ + N · ωᵢ, with ∂p/∂qᵢ and the angular velocity ωᵢ = (∂R/∂qᵢ Rᵀ)ˇ per unit q̇ᵢ obtained by
// central differences of the reference forward kinematics (Eigen isometries, independent of the library). RNEA
// with that external force must return τ − Q, for the force given in body or in base coordinates.
TEST(ExternalForces, MatchVirtualWorkInBodyAndBaseFrames) {
  using spatial::testing::Isometry;
  for (unsigned seed : {21u, 22u, 23u}) {
    const Model<double> model = spatial::testing::random_model(7, spatial::testing::Shape::Branched, seed);
    const int n = model.size();
    Data<double> d(model);
    std::mt19937 rng(seed);
    const Vec q = spatial::testing::random_vector(n, rng, 1.5), qd = spatial::testing::random_vector(n, rng),
              qdd = spatial::testing::random_vector(n, rng);
    const auto pose = spatial::testing::reference_poses(model, q);
    std::vector<Force<double>> f_body(static_cast<std::size_t>(n), Force<double>::Zero());
    std::vector<Force<double>> f_base = f_body;
    Vec Q = Vec::Zero(n);
    std::vector<V3> pts(static_cast<std::size_t>(n)), F(static_cast<std::size_t>(n)), N(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      pts[kk] = V3(spatial::testing::random_vector(3, rng, 0.5));
      F[kk] = V3(spatial::testing::random_vector(3, rng, 5.0));
      N[kk] = V3(spatial::testing::random_vector(3, rng, 2.0));
      const M3 R = pose[kk].linear();        // body axes in base coordinates
      const V3 p_base = pose[kk] * pts[kk];  // application point in base coordinates
      // Body coordinates: moment about the body origin of F at p, plus the couple.
      f_body[kk] = Force<double>(R.transpose() * N[kk] + pts[kk].cross(R.transpose() * F[kk]), R.transpose() * F[kk]);
      // Base coordinates: moment about the base origin.
      f_base[kk] = Force<double>(N[kk] + p_base.cross(F[kk]), F[kk]);
    }
    const double h = 1e-6;
    for (int i = 0; i < n; ++i) {
      Vec qp = q, qm = q;
      qp[i] += h;
      qm[i] -= h;
      const auto P = spatial::testing::reference_poses(model, qp), M = spatial::testing::reference_poses(model, qm);
      for (int k = 0; k < n; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        const V3 dp = (P[kk] * pts[kk] - M[kk] * pts[kk]) / (2 * h);
        const M3 W = (P[kk].linear() - M[kk].linear()) / (2 * h) * pose[kk].linear().transpose();
        const V3 w((W(2, 1) - W(1, 2)) / 2, (W(0, 2) - W(2, 0)) / 2, (W(1, 0) - W(0, 1)) / 2);
        Q[i] += F[kk].dot(dp) + N[kk].dot(w);
      }
    }
    const Vec tau0 = rnea(model, d, q, qd, qdd);
    const Vec tau_body = rnea(model, d, q, qd, qdd, f_body, ForceFrame::Body);
    const Vec tau_base = rnea(model, d, q, qd, qdd, f_base, ForceFrame::Base);
    const double scale = 1 + Q.cwiseAbs().maxCoeff();
    // The same physical force in two frames: equal to rounding.
    EXPECT_LE(abs_diff(tau_body, tau_base) / scale, 1e-12) << "seed " << seed;
    // τ_ext − τ_0 = −Jᵀ f. Central differences with h = 1e-6: truncation ~h², rounding ~1e-16/h ≈ 1e-10.
    EXPECT_LE(abs_diff(Vec(tau_body - tau0), Vec(-Q)) / scale, 1e-8) << "seed " << seed;
    EXPECT_LE(abs_diff(Vec(tau_base - tau0), Vec(-Q)) / scale, 1e-8) << "seed " << seed;

    // ABA with the same external forces inverts RNEA with them.
    const Vec tau = spatial::testing::random_vector(n, rng, 5.0);
    const Vec a_body = aba(model, d, q, qd, tau, f_body, ForceFrame::Body);
    const Vec a_base = aba(model, d, q, qd, tau, f_base, ForceFrame::Base);
    EXPECT_LE(rel_diff(a_body, a_base, 1.0), 1e-10) << "seed " << seed;
    EXPECT_LE(rel_diff(rnea(model, d, q, qd, a_body, f_body, ForceFrame::Body), tau, 1.0), 1e-10) << "seed " << seed;
    // And an external force equals the opposite joint torque through forward dynamics: q̈(τ, f) = q̈(τ + Q, 0).
    EXPECT_LE(rel_diff(aba(model, d, q, qd, Vec(tau + Q)), a_body, 1.0), 1e-7) << "seed " << seed;
  }
}

// A single force on the last body of a chain: body vs base coordinates, and only that body's ancestors feel it.
TEST(ExternalForces, ForceOnLastBodyOfChain) {
  const Model<double> model = spatial::testing::random_model(6, spatial::testing::Shape::Chain, 31);
  const int n = model.size();
  std::mt19937 rng(31);
  const Vec q = spatial::testing::random_vector(n, rng, 1.5), zero = Vec::Zero(n);
  const auto pose = spatial::testing::reference_poses(model, q);
  const auto last = static_cast<std::size_t>(n - 1);
  const V3 F(1.0, -2.0, 0.5), p_body(0.1, 0.2, -0.3);
  const M3 R = pose[last].linear();
  std::vector<Force<double>> fb(last + 1, Force<double>::Zero()), fB = fb;
  fb[last] = Force<double>(p_body.cross(R.transpose() * F), R.transpose() * F);
  fB[last] = Force<double>((pose[last] * p_body).cross(F), F);
  const Model<double> nog = model.with_gravity(V3::Zero());
  Data<double> d0(nog);
  const Vec tb = rnea(nog, d0, q, zero, zero, fb, ForceFrame::Body);
  const Vec tB = rnea(nog, d0, q, zero, zero, fB, ForceFrame::Base);
  EXPECT_LE(abs_diff(tb, tB), 1e-13);
  // −Jᵀ F by finite differences of the point's position.
  for (int i = 0; i < n; ++i) {
    Vec qp = q, qm = q;
    qp[i] += 1e-6;
    qm[i] -= 1e-6;
    const V3 dp = (spatial::testing::reference_poses(nog, qp)[last] * p_body -
                   spatial::testing::reference_poses(nog, qm)[last] * p_body) /
                  2e-6;
    EXPECT_NEAR(tb[i], -F.dot(dp), 1e-8) << "joint " << i;
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Forward kinematics
// ---------------------------------------------------------------------------------------------------------------

// Planar 2-link arm, joints about z, link 1 along x of length l1, tool frame at (l2, 0, 0) on link 2:
//   elbow = (l1 cos q1, l1 sin q1, 0), tool = elbow + (l2 cos(q1+q2), l2 sin(q1+q2), 0), tool orientation Rz(q1+q2).
TEST(ForwardKinematics, PlanarTwoLinkArm) {
  const double l1 = 0.9, l2 = 0.55;
  ModelBuilder<double> b;
  const int u = b.add_body("upper", -1, JointType::RevoluteZ, Transform<double>::Identity(),
                           Inertia<double>::from_com(1.0, V3(l1 / 2, 0, 0), M3::Identity() * 0.01), V3::Zero(),
                           "shoulder");
  const int f = b.add_body("fore", u, JointType::RevoluteZ, xlt(V3(l1, 0, 0)),
                           Inertia<double>::from_com(0.7, V3(l2 / 2, 0, 0), M3::Identity() * 0.01), V3::Zero(),
                           "elbow");
  b.add_fixed_body("tool", f, xlt(V3(l2, 0, 0)), Inertia<double>::Zero());
  const Model<double> model = b.build();
  EXPECT_EQ(model.body_index("fore"), 1);
  EXPECT_EQ(model.joint_index("elbow"), 1);
  EXPECT_EQ(model.body_name(0), "upper");
  EXPECT_EQ(model.joint_name(0), "shoulder");
  Data<double> d(model);
  std::mt19937 rng(5);
  for (int t = 0; t < 100; ++t) {
    const Vec q = spatial::testing::random_vector(2, rng, 3.2);
    const double q1 = q[0], q12 = q[0] + q[1];
    forward_kinematics(model, d, q);
    const V3 elbow(l1 * std::cos(q1), l1 * std::sin(q1), 0);
    const V3 tool = elbow + V3(l2 * std::cos(q12), l2 * std::sin(q12), 0);
    M3 Rz1, Rz12;  // active rotations about z, written out
    Rz1 << std::cos(q1), -std::sin(q1), 0, std::sin(q1), std::cos(q1), 0, 0, 0, 1;
    Rz12 << std::cos(q12), -std::sin(q12), 0, std::sin(q12), std::cos(q12), 0, 0, 0, 1;
    EXPECT_LE(abs_diff(body_pose(d, 0).translation(), V3::Zero()), kTight);
    EXPECT_LE(abs_diff(body_pose(d, 0).linear(), Rz1), kTight);
    EXPECT_LE(abs_diff(body_pose(d, 1).translation(), elbow), kTight);
    EXPECT_LE(abs_diff(body_pose(d, 1).linear(), Rz12), kTight);
    EXPECT_LE(abs_diff(frame_pose(model, d, 0).translation(), tool), kTight);
    EXPECT_LE(abs_diff(frame_pose(model, d, 0).linear(), Rz12), kTight);
    // ⁱX_0 as a passive transform: E = Rᵀ, r = the body origin.
    EXPECT_LE(abs_diff(d.X_base[1].E, M3(Rz12.transpose())), kTight);
    EXPECT_LE(abs_diff(d.X_base[1].r, elbow), kTight);
    // Centre of mass of the two links.
    const V3 com_ref = (1.0 * V3(l1 / 2 * std::cos(q1), l1 / 2 * std::sin(q1), 0) +
                        0.7 * (elbow + V3(l2 / 2 * std::cos(q12), l2 / 2 * std::sin(q12), 0))) /
                       1.7;
    EXPECT_LE(abs_diff(center_of_mass(model, d, q), com_ref), kTight);
    // Gravity along −z is perpendicular to the plane: no potential energy, no gravity torque.
    EXPECT_NEAR(potential_energy(model, d, q), 0.0, 1e-15);
  }
}

// Forward kinematics of random trees against the reference composition of Eigen isometries.
TEST(ForwardKinematics, RandomTreesMatchReferencePoses) {
  double worst = 0;
  for (unsigned seed = 0; seed < 10; ++seed) {
    const Model<double> model = spatial::testing::random_model(13, spatial::testing::Shape::Branched, 300 + seed);
    Data<double> d(model);
    std::mt19937 rng(seed);
    const Vec q = spatial::testing::random_vector(model.size(), rng, 2.0);
    forward_kinematics(model, d, q);
    const auto ref = spatial::testing::reference_poses(model, q);
    for (int i = 0; i < model.size(); ++i) {
      const auto pose = body_pose(d, i);
      const double e = std::max(abs_diff(pose.translation(), ref[static_cast<std::size_t>(i)].translation()),
                                abs_diff(pose.linear(), ref[static_cast<std::size_t>(i)].linear()));
      EXPECT_LE(e, 1e-13) << "seed " << seed << " body " << i;
      worst = std::max(worst, e);
    }
    // Centre of mass and potential energy from the reference poses.
    V3 mc = V3::Zero();
    for (int i = 0; i < model.size(); ++i)
      mc += model.inertia(i).m * spatial::testing::reference_body_com(model, ref, i);
    EXPECT_LE(abs_diff(center_of_mass(model, d, q), V3(mc / model.total_mass())), 1e-13);
    EXPECT_NEAR(potential_energy(model, d, q), -model.gravity().dot(mc), 1e-12 * (1 + mc.norm()));
  }
  std::printf("  worst forward-kinematics error vs Eigen isometries: %.2e\n", worst);
}

}  // namespace
