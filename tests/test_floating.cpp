// Floating-base trees (floating.hpp): the configuration space (integrate, difference, normalize, neutral, random
// configurations), and RNEA, CRBA, ABA, CRBA + LTDL forward dynamics, energy and centre of mass on a free-flying
// root, on random trees of every joint type and on the HOAP-3 (compile-time and run-time trees).
//
// Independent references:
//  - A fixed-base model with six virtual joints (prismatic x, y, z, then revolute x, y, z, massless bodies, the
//    root body on the last one): at zero virtual angles its velocities are exactly the free-flyer's
//    (v_lin, ω), so its H equals the floating H, and its gravity torques equal the floating G when its gravity is
//    the floating root's gravity in root coordinates, Rᵀ g (any root pose).
//  - Physics: with no gravity and no torque the world-frame spatial momentum is constant along an integrated
//    trajectory (RK4 on the manifold), and with gravity and τ = 0 the centre of mass accelerates at exactly g
//    (second central difference along q ⊕ (v t + ½ v̇ t²), whose acceleration at t = 0 is v̇).
//  - Identities: RNEA(ABA(τ)) = τ (with a non-zero root wrench too), ABA = CRBA + LTDL, RNEA linear in v̇ with
//    slope H, ½ vᵀ H v = kinetic energy.
// Tolerances: as in test_properties.cpp, 1e-12 relative where no system is solved, forward dynamics by its
// residual; finite differences by their truncation and rounding, stated where used.

#include <spatial/floating.hpp>
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include "support/random_model.hpp"
#include "support/reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

using namespace spatial;
using spatial::testing::rel_diff;
using spatial::testing::Shape;
using spatial::testing::random_floating;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;
using V3 = Vector3<double>;

Vec random_q(const FloatingModel<double>& m, std::mt19937& rng) {
  const Vec lo = Vec::Constant(m.njoints(), -2.0), hi = Vec::Constant(m.njoints(), 2.0);
  return random_configuration(m, lo, hi, rng);
}

/// The fixed-base model with six virtual joints (see the top of the file), gravity g_root.
Model<double> virtual_chain(const FloatingModel<double>& fm, const V3& g_root) {
  ModelBuilder<double> b;
  b.set_gravity(g_root);
  const JointType types[6] = {JointType::PrismaticX, JointType::PrismaticY, JointType::PrismaticZ,
                              JointType::RevoluteX,  JointType::RevoluteY,  JointType::RevoluteZ};
  for (int k = 0; k < 6; ++k)
    b.add_body("virtual" + std::to_string(k), k - 1, types[k], Transform<double>::Identity(),
               k == 5 ? fm.root_inertia() : Inertia<double>::Zero());
  const Model<double>& t = fm.tree();
  for (int i = 0; i < t.size(); ++i)
    b.add_body(t.body_name(i), t.parent(i) >= 0 ? t.parent(i) + 6 : 5, t.joint_type(i), t.tree_transform(i),
               t.inertia(i), t.axis(i), t.joint_name(i));
  return b.build();
}

/// World-frame spatial momentum Σ ʷXᵢ* Iᵢ vᵢ (root included), from `data` after rnea/kinetic_energy.
Force<double> world_momentum(const FloatingModel<double>& m, FloatingData<double>& d, const Vec& q, const Vec& v) {
  kinetic_energy(m, d, q, v);  // fills d.tree.v and the transforms
  Force<double> h = d.X0.apply_force_inverse(m.root_inertia() * d.v0);
  for (int i = 0; i < m.njoints(); ++i)
    h += world_transform(d, i).apply_force_inverse(m.tree().inertia(i) * d.tree.v[static_cast<std::size_t>(i)]);
  return h;
}

struct Case {
  int n;
  Shape shape;
  unsigned seed;
};
const Case kCases[] = {{1, Shape::Chain, 1}, {5, Shape::Chain, 2}, {12, Shape::Branched, 3},
                       {30, Shape::Branched, 4}, {8, Shape::Branched, 5}};

// ---------------------------------------------------------------------------------------------------------------
// Configuration space
// ---------------------------------------------------------------------------------------------------------------

TEST(FloatingConfiguration, NeutralIntegrateDifferenceRoundTrip) {
  const auto m = random_floating(4, Shape::Branched, 7);
  std::mt19937 rng(11);
  const Vec q0n = neutral(m);
  EXPECT_EQ(q0n.size(), m.nq());
  EXPECT_EQ(q0n[6], 1.0);
  EXPECT_EQ(q0n.norm(), 1.0);
  double worst = 0;
  for (int t = 0; t < 200; ++t) {
    const Vec q0 = random_q(m, rng);
    ASSERT_TRUE(is_normalized(m, q0));
    // Angles up to 3 rad (below π: the logarithm returns the shorter rotation) and tiny ones (series branches).
    const double scale = t % 3 == 0 ? 1e-7 : (t % 3 == 1 ? 0.5 : 3.0 / std::sqrt(3.0));
    Vec v = spatial::testing::random_vector(m.nv(), rng, scale);
    const Vec q1 = integrate(m, q0, v);
    ASSERT_TRUE(is_normalized(m, q1, 1e-14));
    const Vec back = difference(m, q0, q1);
    // Relative to |v| + |q|: for tiny v the positions' own rounding (ε |q|) dominates q₁ − q₀.
    worst = std::max(worst, (back - v).norm() / (v.norm() + q0.norm()));
    // And the other way: q0 ⊕ (q1 ⊖ q0) = q1 for two unrelated configurations (quaternion up to sign).
    const Vec q2 = random_q(m, rng);
    const Vec d = difference(m, q0, q2);
    Vec q3 = integrate(m, q0, d);
    if (q3.segment<4>(3).dot(q2.segment<4>(3)) < 0) q3.segment<4>(3) *= -1.0;
    EXPECT_LT((q3 - q2).norm(), 1e-12) << t;
  }
  EXPECT_LT(worst, 1e-12);
  // In place, and dt scales v.
  Vec q = random_q(m, rng);
  const Vec v = spatial::testing::random_vector(m.nv(), rng);
  const Vec expect = integrate(m, q, Vec(0.25 * v));
  integrate(m, q, v, 0.25, q);
  EXPECT_LT((q - expect).norm(), 1e-15);
}

TEST(FloatingConfiguration, IntegrateMovesTheRootWithItsBodyVelocity) {
  // d/dt of the root pose along q ⊕ v t at t = 0: ṗ = R v_lin, Ṙ = R ω̂ (central differences, h = 1e-6:
  // truncation ~h² |v|³ ≈ 1e-12, rounding ~ε/h ≈ 2e-10).
  const auto m = random_floating(3, Shape::Chain, 8);
  std::mt19937 rng(12);
  for (int t = 0; t < 20; ++t) {
    const Vec q = random_q(m, rng);
    const Vec v = spatial::testing::random_vector(m.nv(), rng);
    const double h = 1e-6;
    const Vec qp = integrate(m, q, v, h), qm = integrate(m, q, v, -h);
    const Matrix3<double> R = root_quaternion(q).toRotationMatrix();
    const V3 pdot = (qp.head<3>() - qm.head<3>()) / (2 * h);
    EXPECT_LT((pdot - R * v.head<3>()).norm(), 1e-8);
    const Matrix3<double> Rdot =
        (root_quaternion(qp).toRotationMatrix() - root_quaternion(qm).toRotationMatrix()) / (2 * h);
    EXPECT_LT((Rdot - R * spatial::skew(V3(v.segment<3>(3)))).norm(), 1e-8);
    EXPECT_LT((qp.tail(m.njoints()) - q.tail(m.njoints()) - h * v.tail(m.njoints())).norm(), 1e-15);
  }
}

TEST(FloatingConfiguration, NormalizeAndRandomWithinLimits) {
  const auto m = random_floating(6, Shape::Chain, 9);
  std::mt19937 rng(13);
  Vec lo(6), hi(6);
  lo << -1, -0.5, 0, 0.2, -std::numeric_limits<double>::infinity(), -3;
  hi << 1, 0.5, 0.1, 0.3, std::numeric_limits<double>::infinity(), -2;
  for (int t = 0; t < 100; ++t) {
    Vec q = random_configuration(m, lo, hi, rng, V3(-2, 0, 1), V3(2, 0.5, 1.5));
    EXPECT_TRUE(is_normalized(m, q));
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(q[k], k == 0 ? -2 : (k == 1 ? 0 : 1));
      EXPECT_LE(q[k], k == 0 ? 2 : (k == 1 ? 0.5 : 1.5));
    }
    for (int i = 0; i < 6; ++i) {
      EXPECT_GE(q[7 + i], std::isfinite(lo[i]) ? lo[i] : -M_PI);
      EXPECT_LE(q[7 + i], std::isfinite(hi[i]) ? hi[i] : M_PI);
    }
    q.segment<4>(3) *= 3.0;
    EXPECT_FALSE(is_normalized(m, q));
    normalize(m, q);
    EXPECT_TRUE(is_normalized(m, q, 1e-15));
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Dynamics against the virtual six-joint chain
// ---------------------------------------------------------------------------------------------------------------

TEST(FloatingDynamics, InertiaAndGravityEqualTheVirtualChains) {
  for (const Case& c : kCases) {
    const auto m = random_floating(c.n, c.shape, c.seed);
    FloatingData<double> d(m);
    std::mt19937 rng(c.seed);
    for (int t = 0; t < 5; ++t) {
      const Vec q = random_q(m, rng);
      const Matrix3<double> R = root_quaternion(q).toRotationMatrix();
      const Model<double> chain = virtual_chain(m, R.transpose() * m.gravity());
      Data<double> cd(chain);
      Vec qc = Vec::Zero(chain.size());
      qc.tail(m.njoints()) = q.tail(m.njoints());
      const Mat H = crba(m, d, q);
      const Mat Hc = crba(chain, cd, qc);
      const Mat Hcs = Hc.selfadjointView<Eigen::Lower>();  // CRBA leaves cross-branch entries zero: both full
      EXPECT_LT(rel_diff(H, Hc), 1e-12) << "n " << c.n << " seed " << c.seed;
      EXPECT_LT(rel_diff(H, H.transpose()), 1e-15);
      (void)Hcs;
      const Vec G = gravity_torques(m, d, q);
      const Vec Gc = gravity_torques(chain, cd, qc);
      EXPECT_LT(rel_diff(G, Gc), 1e-12) << "n " << c.n << " seed " << c.seed;
      const Vec zero = Vec::Zero(m.nv());
      EXPECT_LT(rel_diff(rnea(m, d, q, zero, zero), Gc), 1e-12);
    }
  }
}

TEST(FloatingDynamics, RneaIsLinearInTheAccelerationWithSlopeH) {
  for (const Case& c : kCases) {
    const auto m = random_floating(c.n, c.shape, c.seed);
    FloatingData<double> d(m);
    std::mt19937 rng(c.seed + 1);
    for (int t = 0; t < 5; ++t) {
      const Vec q = random_q(m, rng);
      const Vec v = spatial::testing::random_vector(m.nv(), rng);
      const Vec a = spatial::testing::random_vector(m.nv(), rng);
      const Vec C = bias_forces(m, d, q, v);
      EXPECT_LT(rel_diff(C, Vec(rnea(m, d, q, v, Vec::Zero(m.nv())))), 1e-13);
      const Vec tau = rnea(m, d, q, v, a);
      const Mat H = crba(m, d, q);
      EXPECT_LT(rel_diff(Vec(tau - C), Vec(H * a)), 1e-12) << "n " << c.n;
      // ½ vᵀ H v = kinetic energy.
      const double T = kinetic_energy(m, d, q, v);
      EXPECT_NEAR(0.5 * v.dot(H * v), T, 1e-12 * T);
    }
  }
}

TEST(FloatingDynamics, ForwardDynamicsRoundTrips) {
  double worst = 0;
  for (const Case& c : kCases) {
    const auto m = random_floating(c.n, c.shape, c.seed);
    FloatingData<double> d(m);
    std::mt19937 rng(c.seed + 2);
    for (int t = 0; t < 5; ++t) {
      const Vec q = random_q(m, rng);
      const Vec v = spatial::testing::random_vector(m.nv(), rng);
      Vec tau = spatial::testing::random_vector(m.nv(), rng, 5.0);
      if (t % 2 == 0) tau.head<6>().setZero();  // a free root, and one pushed by a wrench
      const Vec qdd_aba = aba(m, d, q, v, tau);
      const Vec qdd_crba = forward_dynamics_crba(m, d, q, v, tau);
      const Mat H = crba(m, d, q);
      const Vec C = bias_forces(m, d, q, v);
      // Residuals of both (backward stable): |RNEA(FD(τ)) − τ| ≤ 8 nv ε (|τ| + |H||q̈| + |C|).
      for (const Vec* qdd : {&qdd_aba, &qdd_crba}) {
        const Vec back = rnea(m, d, q, v, *qdd);
        const double scale = tau.norm() + H.norm() * qdd->norm() + C.norm();
        const double res = (back - tau).norm() / scale;
        worst = std::max(worst, res);
        EXPECT_LT(res, 8 * m.nv() * 2.2e-16) << "n " << c.n;
      }
      // The two forward dynamics agree to what the conditioning of H allows.
      Eigen::SelfAdjointEigenSolver<Mat> es(H);
      const double kappa = es.eigenvalues().maxCoeff() / es.eigenvalues().minCoeff();
      EXPECT_LT(rel_diff(qdd_aba, qdd_crba), 64 * m.nv() * 2.2e-16 * kappa) << "n " << c.n;
    }
  }
  std::printf("floating forward dynamics: worst residual %.2e\n", worst);
}

TEST(FloatingDynamics, ExternalForcesInBodyAndWorldCoordinates) {
  const auto m = random_floating(10, Shape::Branched, 21);
  FloatingData<double> d(m);
  std::mt19937 rng(22);
  const Vec q = random_q(m, rng);
  const Vec v = spatial::testing::random_vector(m.nv(), rng);
  const Vec a = spatial::testing::random_vector(m.nv(), rng);
  std::vector<Force<double>> fb(static_cast<std::size_t>(m.njoints() + 1)), fw = fb;
  forward_kinematics(m, d, q);
  for (int b = 0; b <= m.njoints(); ++b) {
    const Vec f = spatial::testing::random_vector(6, rng, 3.0);
    fb[static_cast<std::size_t>(b)] = Force<double>(f.head<3>(), f.tail<3>());
    // The same force in world coordinates: ʷf = (ᵇX_w)ᵀ ᵇf.
    fw[static_cast<std::size_t>(b)] = world_transform(d, b - 1).apply_force_inverse(fb[static_cast<std::size_t>(b)]);
  }
  const Vec free = rnea(m, d, q, v, a);
  const Vec with_body = rnea(m, d, q, v, a, fb, ForceFrame::Body);
  const Vec with_world = rnea(m, d, q, v, a, fw, ForceFrame::Base);
  EXPECT_LT(rel_diff(with_body, with_world), 1e-12);
  // τ − τ_free = −Σ Jᵢᵀ fᵢ: not zero, and a single force on the root only changes the root's six entries.
  EXPECT_GT((with_body - free).norm(), 1e-3);
  std::vector<Force<double>> only_root(fb.size(), Force<double>::Zero());
  only_root[0] = fb[0];
  const Vec r = rnea(m, d, q, v, a, only_root);
  EXPECT_LT((r.tail(m.njoints()) - free.tail(m.njoints())).norm(), 1e-12 * free.norm());
  EXPECT_LT((r.head<3>() - free.head<3>() + fb[0].f).norm(), 1e-12 * free.norm());
  // ABA with the same forces inverts it.
  const Vec qdd = aba(m, d, q, v, with_body, fb, ForceFrame::Body);
  EXPECT_LT(rel_diff(qdd, a), 1e-9);
  const Vec qdd_w = aba(m, d, q, v, with_world, fw, ForceFrame::Base);
  EXPECT_LT(rel_diff(qdd_w, a), 1e-9);
}

// ---------------------------------------------------------------------------------------------------------------
// Physics
// ---------------------------------------------------------------------------------------------------------------

TEST(FloatingPhysics, MomentumIsConservedWithoutGravityOrTorque) {
  // Runge–Kutta 4 on the manifold (stages q ⊕ k h, without the dexp correction, so of order 2 in the pose), over
  // 1 s: the spatial momentum in world coordinates must stay constant up to the integrator's error, which halving
  // the step must cut at least threefold (a wrong term in the dynamics would give a drift that does not shrink).
  for (const Case& c : {Case{6, Shape::Branched, 31}, Case{12, Shape::Chain, 32}}) {
    const auto m = random_floating(c.n, c.shape, c.seed, V3::Zero());
    FloatingData<double> d(m);
    std::mt19937 rng(c.seed);
    const Vec q0 = random_q(m, rng);
    const Vec v0 = spatial::testing::random_vector(m.nv(), rng);
    const Vec tau = Vec::Zero(m.nv());
    const Force<double> h0 = world_momentum(m, d, q0, v0);
    const double e0 = kinetic_energy(m, d, q0, v0);
    auto acc = [&](const Vec& qq, const Vec& vv) { return Vec(aba(m, d, qq, vv, tau)); };
    double drift[2];
    for (int run = 0; run < 2; ++run) {
      const int steps = run == 0 ? 500 : 1000;
      const double h = 1.0 / steps;
      Vec q = q0, v = v0;
      for (int step = 0; step < steps; ++step) {
        const Vec k1v = v, k1a = acc(q, v);
        const Vec q2 = integrate(m, q, k1v, h / 2);
        const Vec k2v = v + h / 2 * k1a, k2a = acc(q2, k2v);
        const Vec q3 = integrate(m, q, k2v, h / 2);
        const Vec k3v = v + h / 2 * k2a, k3a = acc(q3, k3v);
        const Vec q4 = integrate(m, q, k3v, h);
        const Vec k4v = v + h * k3a, k4a = acc(q4, k4v);
        q = integrate(m, q, Vec((k1v + 2 * k2v + 2 * k3v + k4v) / 6), h);
        v += h / 6 * (k1a + 2 * k2a + 2 * k3a + k4a);
      }
      EXPECT_TRUE(is_normalized(m, q, 1e-14));
      drift[run] = (world_momentum(m, d, q, v).vector() - h0.vector()).norm() / h0.vector().norm();
      EXPECT_NEAR(kinetic_energy(m, d, q, v), e0, 1e-6 * e0);
    }
    EXPECT_LT(drift[1], 1e-6) << "n " << c.n;
    EXPECT_LT(drift[1], drift[0] / 3) << "n " << c.n;
    std::printf("momentum drift over 1 s (n = %d): %.2e at 2 ms, %.2e at 1 ms\n", c.n, drift[0], drift[1]);
  }
}

TEST(FloatingPhysics, CentreOfMassFallsAtExactlyG) {
  // c̈ by the second central difference along q ⊕ (v t + ½ v̇ t²), h = 1e-4: truncation ~h² |c⁗| ≈ 1e-7,
  // rounding ~ε |c| / h² ≈ 1e-8.
  const V3 g(0.3, -0.2, -9.81);
  for (const Case& c : kCases) {
    const auto m = random_floating(c.n, c.shape, c.seed, g);
    FloatingData<double> d(m);
    std::mt19937 rng(c.seed + 3);
    const Vec q = random_q(m, rng);
    const Vec v = spatial::testing::random_vector(m.nv(), rng, 0.5);
    Vec tau = spatial::testing::random_vector(m.nv(), rng, 2.0);
    tau.head<6>().setZero();  // internal torques only
    const Vec a = aba(m, d, q, v, tau);
    const double h = 1e-4;
    const V3 cp = center_of_mass(m, d, integrate(m, q, Vec(v * h + 0.5 * a * h * h)));
    const V3 c0 = center_of_mass(m, d, q);
    const V3 cm = center_of_mass(m, d, integrate(m, q, Vec(-v * h + 0.5 * a * h * h)));
    const V3 cdd = (cp - 2 * c0 + cm) / (h * h);
    EXPECT_LT((cdd - g).norm(), 1e-5 * g.norm()) << "n " << c.n << " c̈ " << cdd.transpose();
  }
}

TEST(FloatingDynamics, PotentialEnergyAndCentreOfMass) {
  const auto m = random_floating(7, Shape::Branched, 41);
  FloatingData<double> d(m);
  std::mt19937 rng(42);
  const Vec q = random_q(m, rng);
  const V3 c = center_of_mass(m, d, q);
  EXPECT_NEAR(potential_energy(m, d, q), -m.total_mass() * m.gravity().dot(c), 1e-12 * m.total_mass() * 10);
  // Moving the root by p moves the centre of mass by p.
  Vec q2 = q;
  q2.head<3>() += V3(1, -2, 0.5);
  EXPECT_LT((center_of_mass(m, d, q2) - c - V3(1, -2, 0.5)).norm(), 1e-14 * 10);
}

// ---------------------------------------------------------------------------------------------------------------
// Compile-time trees: the HOAP-3 stance tree on a free-flying root gives the run-time tree's numbers
// ---------------------------------------------------------------------------------------------------------------

TEST(FloatingDynamics, CompileTimeTreeMatchesRunTimeTree) {
  namespace stance = spatial::models::hoap3_stance_right;
  using CT = FloatingModel<double, stance::Tree>;
  const auto tree = stance::model();
  ModelBuilder<double> b;
  b.set_gravity(tree.gravity());
  for (int i = 0; i < tree.size(); ++i)
    b.add_body(tree.body_name(i), tree.parent(i), tree.joint_type(i), tree.tree_transform(i), tree.inertia(i),
               tree.axis(i), tree.joint_name(i));
  const Inertia<double> I0 = stance::base_inertia<double>();
  const CT ct(tree, I0, "R_SOLE");
  const FloatingModel<double> rt(b.build(), I0, "R_SOLE");
  FloatingData<double, stance::Tree> cd(ct);
  FloatingData<double> rd(rt);
  std::mt19937 rng(51);
  Vec lo(stance::dof), hi(stance::dof);
  for (int i = 0; i < stance::dof; ++i) lo[i] = stance::lower[i], hi[i] = stance::upper[i];
  for (int t = 0; t < 10; ++t) {
    const Vec q = random_configuration(rt, lo, hi, rng);
    const Vec v = spatial::testing::random_vector(rt.nv(), rng);
    const Vec a = spatial::testing::random_vector(rt.nv(), rng);
    const Eigen::Matrix<double, CT::NQ, 1> qs = q;
    const Eigen::Matrix<double, CT::NV, 1> vs = v, as = a;
    EXPECT_LT(rel_diff(Vec(rnea(ct, cd, qs, vs, as)), Vec(rnea(rt, rd, q, v, a))), 1e-13);
    EXPECT_LT(rel_diff(Mat(crba(ct, cd, qs)), Mat(crba(rt, rd, q))), 1e-13);
    EXPECT_LT(rel_diff(Vec(aba(ct, cd, qs, vs, as)), Vec(aba(rt, rd, q, v, a))), 1e-11);
    EXPECT_LT(rel_diff(Vec(forward_dynamics_crba(ct, cd, qs, vs, as)), Vec(forward_dynamics_crba(rt, rd, q, v, a))),
              1e-11);
    EXPECT_LT((center_of_mass(ct, cd, qs) - center_of_mass(rt, rd, q)).norm(), 1e-14);
  }
}

}  // namespace
