// Trees of multi-DoF joints (general.hpp): spherical joints and free-flyers anywhere in the tree.
//
// Independent references:
//  - The one-DoF algorithms: a fixed-base or floating model turned into a GeneralModel (`general_model`) gives the
//    same FK, RNEA (external forces in body and base coordinates), CRBA, ABA, Jacobians, centre of mass, CoM
//    Jacobian, energies, integrate and difference as algorithms.hpp, floating.hpp, kinematics.hpp, centroidal.hpp.
//  - A spherical joint against three revolute joints z, y, x through two massless bodies (Euler angles α, β, γ,
//    child → parent rotation Rz(α) Ry(β) Rx(γ), the quaternion of that rotation on the spherical side): same body
//    placements; with ω = G θ̇ and ω̇ = G θ̈ + Ġ θ̇ (G and Ġ θ̇ read off the Euler tree's own velocities and
//    accelerations), the Euler tree's H, τ and energy are Jᵀ H J, Jᵀ τ and the same.
//  - Identities on random trees mixing one-DoF, spherical and free-flyer joints: RNEA(ABA(τ)) = τ, ABA = H⁻¹ (τ − C),
//    RNEA linear in v̇ with slope H, ½ vᵀ H v = kinetic energy, v = q₁ ⊖ q₀ ⇔ q₀ ⊕ v = q₁, Jacobians and the CoM
//    Jacobian against central differences on the manifold, the kinetic plus potential energy's rate against τᵀv.
// Tolerances: 1e-12 relative where no system is solved; 1e-10 through a solve; central differences with step
// h = 1e-6: truncation ~h² · (third derivative ~ 1) plus rounding ~1e-16 / h, so 1e-7.

#include <spatial/general.hpp>
#include <spatial/spatial.hpp>

#include "support/random_model.hpp"
#include "support/reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace spatial;
using spatial::testing::random_forces;
using spatial::testing::random_vector;
using spatial::testing::rel_diff;
using spatial::testing::Shape;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;
using V3 = Vector3<double>;

constexpr double kExact = 1e-12;
constexpr double kSolved = 1e-10;
constexpr double kFd = 1e-7;

/// Random q, v of a general model: quaternions uniform, other coordinates in [−1, 1]; v in [−1, 1].
Vec random_q(const GeneralModel<double>& m, std::mt19937& rng) {
  const Vec lo = Vec::Constant(m.nq(), -1.0), hi = Vec::Constant(m.nq(), 1.0);
  return random_configuration(m, lo, hi, rng);
}

/// A random tree of `n` bodies whose joints are drawn from every one-DoF type, spherical and (not at the first
/// body) free-flyer joints; at least one spherical joint.
GeneralModel<double> random_general(int n, Shape shape, unsigned seed, bool free_flyers = true) {
  const auto bodies = spatial::testing::random_bodies(n, shape, seed, true);
  std::mt19937 rng(seed + 7);
  std::uniform_int_distribution<int> kind(0, 9);
  GeneralModel<double> m(V3(0.3, -0.2, -9.81));
  for (int i = 0; i < n; ++i) {
    const auto& b = bodies[std::size_t(i)];
    const int k = kind(rng);
    GeneralJoint<double> j = GeneralJoint<double>::one_dof(b.type, b.axis);
    if (k < 3 || i == 1) j = GeneralJoint<double>::spherical();
    else if (k == 3 && free_flyers && i > 0) j = GeneralJoint<double>::free_flyer();
    m.add_body(b.parent, j, b.X_tree, Inertia<double>::from_com(b.mass, b.com, b.inertia_com),
               "joint" + std::to_string(i), "body" + std::to_string(i));
  }
  return m;
}

/// World pose change from q₋ to q₊ over 2h as [ω; ṗ] (world axes, body origin): LOCAL_WORLD_ALIGNED velocity.
Vector6<double> lwa_difference(const Transform<double>& Xm, const Transform<double>& Xp, double h) {
  const Eigen::Matrix3d dR = Xp.E.transpose() * Xm.E;  // R₊ R₋ᵀ (E = Rᵀ)
  const Eigen::AngleAxisd aa(dR);
  Vector6<double> out;
  out.head<3>() = aa.angle() * aa.axis() / (2 * h);
  out.tail<3>() = (Xp.r - Xm.r) / (2 * h);
  return out;
}

// ---------------------------------------------------------------------------------------------------------------

TEST(GeneralModel, OneDofTreesGiveTheModelAlgorithmsNumbers) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const Model<double> model = spatial::testing::random_model(11, seed % 2 ? Shape::Chain : Shape::Branched, seed);
    const GeneralModel<double> gm = general_model(model);
    ASSERT_EQ(gm.nq(), model.size());
    ASSERT_EQ(gm.nv(), model.size());
    Data<double> d(model);
    GeneralData<double> gd(gm);
    std::mt19937 rng(seed);
    const int n = model.size();
    const Vec q = random_vector(n, rng, 2.0), v = random_vector(n, rng, 2.0), a = random_vector(n, rng, 2.0);
    const Vec tau = random_vector(n, rng, 2.0);
    const auto fext = random_forces(n, rng);

    for (ForceFrame frame : {ForceFrame::Body, ForceFrame::Base}) {
      const Vec t_ref = rnea(model, d, q, v, a, fext, frame);
      EXPECT_LT(rel_diff(rnea(gm, gd, q, v, a, fext, frame), t_ref), kExact);
      const Vec qdd_ref = aba(model, d, q, v, tau, fext, frame);
      EXPECT_LT(rel_diff(aba(gm, gd, q, v, tau, fext, frame), qdd_ref), kSolved);
    }
    EXPECT_LT(rel_diff(gravity_torques(gm, gd, q), Vec(gravity_torques(model, d, q))), kExact);
    EXPECT_LT(rel_diff(bias_forces(gm, gd, q, v), Vec(bias_forces(model, d, q, v))), kExact);
    EXPECT_LT(rel_diff(crba(gm, gd, q), Mat(crba(model, d, q))), kExact);

    forward_kinematics(model, d, q);
    forward_kinematics(gm, gd, q, v);
    for (int i = 0; i < n; ++i) {
      EXPECT_LT(rel_diff(gd.X0[std::size_t(i)].matrix(), d.X_base[std::size_t(i)].matrix()), kExact) << i;
      for (ReferenceFrame rf : {ReferenceFrame::Local, ReferenceFrame::World, ReferenceFrame::LocalWorldAligned}) {
        Mat J(6, n), Jref(6, n);
        body_jacobian(gm, gd, i, rf, J);
        compute_body_jacobian(model, d, q, i, rf, Jref);
        EXPECT_LT(rel_diff(J, Jref), kExact) << "body " << i << " frame " << int(rf);
      }
    }
    forward_kinematics(gm, gd, q, v);
    EXPECT_NEAR(kinetic_energy(gm, gd), kinetic_energy(model, d, q, v), 1e-12 * kinetic_energy(model, d, q, v));
    EXPECT_NEAR(potential_energy(gm, gd), potential_energy(model, d, q), 1e-11);
    const V3 com = center_of_mass(gm, gd);
    Mat Jc(3, n), Jc_ref(3, n);
    com_jacobian(model, d, q, Jc_ref);
    EXPECT_LT(rel_diff(com, Vec(d.com)), kExact);
    com_jacobian(gm, gd, Jc);
    EXPECT_LT(rel_diff(Jc, Jc_ref), kExact);
  }
}

TEST(GeneralModel, FloatingModelsGiveTheFloatingAlgorithmsNumbers) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const FloatingModel<double> model =
        spatial::testing::random_floating(9, seed % 2 ? Shape::Chain : Shape::Branched, seed, V3(0.5, 0.1, -9.81));
    const GeneralModel<double> gm = general_model(model);
    ASSERT_EQ(gm.nq(), model.nq());
    ASSERT_EQ(gm.nv(), model.nv());
    FloatingData<double> d(model);
    GeneralData<double> gd(gm);
    std::mt19937 rng(seed);
    const Vec lo = Vec::Constant(model.njoints(), -2.0), hi = Vec::Constant(model.njoints(), 2.0);
    const Vec q = random_configuration(model, lo, hi, rng);
    const int nv = model.nv();
    const Vec v = random_vector(nv, rng, 2.0), a = random_vector(nv, rng, 2.0), tau = random_vector(nv, rng, 2.0);
    const auto fext = random_forces(model.njoints() + 1, rng);  // [0] on the root, as for both models

    EXPECT_LT(rel_diff(rnea(gm, gd, q, v, a, fext), Vec(rnea(model, d, q, v, a, fext))), kExact);
    EXPECT_LT(rel_diff(rnea(gm, gd, q, v, a, fext, ForceFrame::Base),
                       Vec(rnea(model, d, q, v, a, fext, ForceFrame::Base))),
              kExact);
    EXPECT_LT(rel_diff(crba(gm, gd, q), Mat(crba(model, d, q))), kExact);
    EXPECT_LT(rel_diff(aba(gm, gd, q, v, tau, fext), Vec(aba(model, d, q, v, tau, fext))), kSolved);
    EXPECT_LT(rel_diff(integrate(gm, q, v, 0.3), Vec(integrate(model, q, v, 0.3))), kExact);
    const Vec q1 = integrate(model, q, v, 0.4);
    EXPECT_LT(rel_diff(difference(gm, q, q1), Vec(difference(model, q, q1))), kExact);

    forward_kinematics(gm, gd, q);
    for (int i = 0; i < model.njoints(); i += 3)
      for (ReferenceFrame rf : {ReferenceFrame::Local, ReferenceFrame::World, ReferenceFrame::LocalWorldAligned}) {
        Mat J(6, nv), Jref(6, nv);
        body_jacobian(gm, gd, i + 1, rf, J);
        compute_body_jacobian(model, d, q, i, rf, Jref);
        EXPECT_LT(rel_diff(J, Jref), kExact) << "body " << i << " frame " << int(rf);
      }
    Mat Jc(3, nv), Jc_ref(3, nv);
    com_jacobian(model, d, q, Jc_ref);
    center_of_mass(gm, gd);
    EXPECT_LT(rel_diff(gd.com, Vec(d.com)), kExact);
    com_jacobian(gm, gd, Jc);
    EXPECT_LT(rel_diff(Jc, Jc_ref), kExact);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// A spherical joint against three revolute joints

struct EulerPair {
  GeneralModel<double> sph, euler;
  int s;                     // the spherical joint's body (same index in both trees up to the two inserted bodies)
  std::vector<int> body_of;  // body i of `sph` ↦ its body in `euler`
};

/// A random tree with body `s` on a spherical joint, and the same tree with that joint replaced by revolute z → y → x
/// through two massless bodies (the last carries body s's inertia and children).
EulerPair euler_pair(int n, int s, Shape shape, unsigned seed, const V3& g) {
  const auto bodies = spatial::testing::random_bodies(n, shape, seed, true);
  EulerPair p{GeneralModel<double>(g), GeneralModel<double>(g), s, {}};
  for (int i = 0; i < n; ++i) {
    const auto& b = bodies[std::size_t(i)];
    const Inertia<double> I = Inertia<double>::from_com(b.mass, b.com, b.inertia_com);
    const std::string name = std::to_string(i);
    const int pe = b.parent < 0 ? -1 : p.body_of[std::size_t(b.parent)];
    if (i == s) {
      p.sph.add_body(b.parent, GeneralJoint<double>::spherical(), b.X_tree, I, "j" + name, "b" + name);
      const int z = p.euler.add_body(pe, GeneralJoint<double>::one_dof(JointType::RevoluteZ), b.X_tree,
                                     Inertia<double>::Zero(), "jz", "bz");
      const int y = p.euler.add_body(z, GeneralJoint<double>::one_dof(JointType::RevoluteY),
                                     Transform<double>::Identity(), Inertia<double>::Zero(), "jy", "by");
      p.body_of.push_back(p.euler.add_body(y, GeneralJoint<double>::one_dof(JointType::RevoluteX),
                                           Transform<double>::Identity(), I, "j" + name, "b" + name));
    } else {
      const auto j = GeneralJoint<double>::one_dof(b.type, b.axis);
      p.sph.add_body(b.parent, j, b.X_tree, I, "j" + name, "b" + name);
      p.body_of.push_back(p.euler.add_body(pe, j, b.X_tree, I, "j" + name, "b" + name));
    }
  }
  return p;
}

TEST(GeneralModel, SphericalJointEqualsThreeRevoluteJointsThroughTheEulerRates) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const int n = 7, s = 1 + int(seed % 4);
    const V3 g(0.2, -0.4, -9.81);
    const EulerPair p = euler_pair(n, s, seed % 2 ? Shape::Chain : Shape::Branched, seed, g);
    const GeneralModel<double>&sph = p.sph, &eul = p.euler;
    ASSERT_EQ(sph.nv(), n + 2);
    ASSERT_EQ(eul.nv(), n + 2);
    ASSERT_EQ(sph.nq(), n + 3);
    std::mt19937 rng(seed);
    const int nv = eul.nv(), vs = sph.idx_v(s);  // the spherical joint's three velocities; z, y, x on the Euler side
    const Vec th = random_vector(nv, rng, 1.2), thd = random_vector(nv, rng, 1.5), thdd = random_vector(nv, rng, 1.5);
    // q of the spherical tree: the same joint values, the quaternion of Rz(α) Ry(β) Rx(γ).
    const double al = th[vs], be = th[vs + 1], ga = th[vs + 2];
    const Eigen::Quaterniond r(Eigen::AngleAxisd(al, V3::UnitZ()) * Eigen::AngleAxisd(be, V3::UnitY()) *
                               Eigen::AngleAxisd(ga, V3::UnitX()));
    Vec q(sph.nq());
    q.head(vs) = th.head(vs);
    q.segment<4>(vs) << r.x(), r.y(), r.z(), r.w();
    q.tail(nv - vs - 3) = th.tail(nv - vs - 3);

    GeneralData<double> ds(sph), de(eul);
    forward_kinematics(eul, de, th);
    forward_kinematics(sph, ds, q);
    for (int i = 0; i < n; ++i)
      EXPECT_LT(rel_diff(ds.X0[std::size_t(i)].matrix(), de.X0[std::size_t(p.body_of[std::size_t(i)])].matrix()),
                kExact)
          << "body " << i;

    // G: the child's angular velocity relative to its parent (child coordinates) for unit Euler rates, read off the
    // Euler tree with everything else at rest; Ġ θ̇: its acceleration for θ̈ = 0 without gravity.
    const int child = p.body_of[std::size_t(s)];
    GeneralModel<double> eul0 = eul;
    eul0.set_gravity(V3::Zero());
    GeneralData<double> d0(eul0);
    Mat Jmap = Mat::Identity(nv, nv);  // v_sph = Jmap θ̇
    for (int c = 0; c < 3; ++c) {
      Vec e = Vec::Zero(nv);
      e[vs + c] = 1;
      forward_kinematics(eul0, d0, th, e);
      Jmap.block(vs, vs + c, 3, 1) = d0.v[std::size_t(child)].w;
    }
    Vec rates = Vec::Zero(nv);
    rates.segment<3>(vs) = thd.segment<3>(vs);
    rnea(eul0, d0, th, rates, Vec::Zero(nv));
    Vec Jdot_thd = Vec::Zero(nv);
    Jdot_thd.segment<3>(vs) = d0.a[std::size_t(child)].w;
    ASSERT_GT(Jdot_thd.norm(), 1e-3);  // the correction matters: without it the τ check below fails

    const Vec v = Jmap * thd, a = Jmap * thdd + Jdot_thd;
    const Mat He = crba(eul, de, th), Hs = crba(sph, ds, q);
    EXPECT_LT(rel_diff(He, Mat(Jmap.transpose() * Hs * Jmap)), kExact);
    EXPECT_LT(rel_diff(gravity_torques(eul, de, th), Vec(Jmap.transpose() * gravity_torques(sph, ds, q))), kExact);
    const Vec te = rnea(eul, de, th, thd, thdd);
    EXPECT_LT(rel_diff(te, Vec(Jmap.transpose() * rnea(sph, ds, q, v, a))), kExact);
    forward_kinematics(eul, de, th, thd);
    forward_kinematics(sph, ds, q, v);
    EXPECT_NEAR(kinetic_energy(sph, ds), kinetic_energy(eul, de), 1e-12 * kinetic_energy(eul, de));
    // ABA on both sides: the spherical tree's v̇ maps back to the Euler rates' θ̈ (Jmap is invertible away from
    // β = ±π/2, which |β| ≤ 1.2 avoids).
    const Vec qdd_s = aba(sph, ds, q, v, rnea(sph, ds, q, v, a));
    EXPECT_LT(rel_diff(qdd_s, a), kSolved);
    EXPECT_LT(rel_diff(aba(eul, de, th, thd, te), thdd), kSolved);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Identities on trees of spherical joints, free-flyers and one-DoF joints

TEST(GeneralModel, RandomMixedTreesSatisfyTheDynamicsIdentities) {
  for (unsigned seed = 1; seed <= 8; ++seed) {
    const GeneralModel<double> m = random_general(9, seed % 2 ? Shape::Chain : Shape::Branched, seed);
    GeneralData<double> d(m);
    std::mt19937 rng(seed);
    const int nv = m.nv();
    const Vec q = random_q(m, rng), v = random_vector(nv, rng, 1.5), a = random_vector(nv, rng, 1.5),
              tau = random_vector(nv, rng, 3.0);
    const auto fext = random_forces(m.size(), rng);

    const Mat H = crba(m, d, q);
    EXPECT_LT(rel_diff(H, Mat(H.transpose())), kExact);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat>(H).eigenvalues().minCoeff(), 0.0);
    const Vec C = bias_forces(m, d, q, v);
    EXPECT_LT(rel_diff(Vec(rnea(m, d, q, v, a)), Vec(H * a + C)), kExact);
    for (ForceFrame frame : {ForceFrame::Body, ForceFrame::Base}) {
      const Vec qdd = aba(m, d, q, v, tau, fext, frame);
      EXPECT_LT(rel_diff(Vec(rnea(m, d, q, v, qdd, fext, frame)), tau), kSolved);
      const Vec Cf = rnea(m, d, q, v, Vec::Zero(nv), fext, frame);
      EXPECT_LT(rel_diff(qdd, Vec(H.ldlt().solve(tau - Cf))), kSolved);
    }
    // External forces given in base coordinates equal the same forces turned into body coordinates.
    forward_kinematics(m, d, q);
    std::vector<Force<double>> fbody;
    for (int i = 0; i < m.size(); ++i) fbody.push_back(d.X0[std::size_t(i)].apply_force(fext[std::size_t(i)]));
    const Vec tb = rnea(m, d, q, v, a, fext, ForceFrame::Base);
    EXPECT_LT(rel_diff(Vec(rnea(m, d, q, v, a, fbody)), tb), kExact);

    forward_kinematics(m, d, q, v);
    EXPECT_NEAR(kinetic_energy(m, d), 0.5 * v.dot(H * v), 1e-12 * kinetic_energy(m, d));
  }
}

TEST(GeneralModel, IntegrateAndDifferenceAreInverseOnTheManifold) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const GeneralModel<double> m = random_general(8, Shape::Branched, seed);
    std::mt19937 rng(seed);
    const Vec q0 = random_q(m, rng), v = random_vector(m.nv(), rng, 1.0);
    const Vec q1 = integrate(m, q0, v, 0.9);
    EXPECT_LT(rel_diff(difference(m, q0, q1), Vec(0.9 * v)), 1e-12);
    EXPECT_LT(difference(m, q1, q1).norm(), 1e-15);
    // In place, and normalize() restores unit quaternions.
    Vec q = q0;
    integrate(m, q, v, 0.9, q);
    EXPECT_LT(rel_diff(q, q1), kExact);
    Vec qs = 3.0 * q1;
    normalize(m, qs);
    for (int i = 0; i < m.size(); ++i) {
      if (m.joint(i).kind == GeneralJointKind::Spherical) {
        EXPECT_NEAR(qs.segment<4>(m.idx_q(i)).norm(), 1.0, 1e-15);
      }
    }
    // A spherical joint moves by its child-frame angular velocity: r₁ = r₀ exp(ω̂ dt).
    for (int i = 0; i < m.size(); ++i) {
      if (m.joint(i).kind != GeneralJointKind::Spherical) continue;
      const int k = m.idx_q(i), kv = m.idx_v(i);
      const Eigen::Quaterniond r0(q0[k + 3], q0[k], q0[k + 1], q0[k + 2]);
      const Eigen::Quaterniond r1(q1[k + 3], q1[k], q1[k + 1], q1[k + 2]);
      const V3 w = 0.9 * v.segment<3>(kv);
      const Eigen::Matrix3d expected = r0.toRotationMatrix() * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
      EXPECT_LT(rel_diff(Mat(r1.toRotationMatrix()), Mat(expected)), kExact);
    }
    const Vec n0 = neutral(m);
    GeneralData<double> d(m);
    forward_kinematics(m, d, n0);
    for (int i = 0; i < m.size(); ++i)
      EXPECT_LT(rel_diff(d.Xup[std::size_t(i)].matrix(), m.tree_transform(i).matrix()), kExact) << i;
  }
}

TEST(GeneralModel, JacobiansMatchCentralDifferencesOnTheManifold) {
  const double h = 1e-6;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const GeneralModel<double> m = random_general(8, seed % 2 ? Shape::Chain : Shape::Branched, seed);
    GeneralData<double> d(m), dp(m), dm(m);
    std::mt19937 rng(seed);
    const Vec q = random_q(m, rng);
    const int nv = m.nv();
    forward_kinematics(m, d, q);
    center_of_mass(m, d);
    Mat Jc(3, nv);
    com_jacobian(m, d, Jc);
    std::vector<Mat> J(std::size_t(m.size()), Mat(6, nv));
    for (int b = 0; b < m.size(); ++b) body_jacobian(m, d, b, ReferenceFrame::LocalWorldAligned, J[std::size_t(b)]);
    for (int c = 0; c < nv; ++c) {
      Vec e = Vec::Zero(nv);
      e[c] = h;
      forward_kinematics(m, dp, integrate(m, q, e));
      forward_kinematics(m, dm, integrate(m, q, Vec(-e)));
      for (int b = 0; b < m.size(); ++b) {
        const Vector6<double> fd = lwa_difference(dm.X0[std::size_t(b)], dp.X0[std::size_t(b)], h);
        const Mat& Jb = J[std::size_t(b)];
        // J's rows are linear first; fd is [ω; ṗ].
        EXPECT_LT((Jb.block(0, c, 3, 1) - fd.tail<3>()).norm(), kFd) << "body " << b << " column " << c;
        EXPECT_LT((Jb.block(3, c, 3, 1) - fd.head<3>()).norm(), kFd) << "body " << b << " column " << c;
      }
      const V3 cp = center_of_mass(m, dp), cm = center_of_mass(m, dm);
      EXPECT_LT((Jc.col(c) - (cp - cm) / (2 * h)).norm(), kFd) << "column " << c;
    }
    // J v is the body's velocity from the forward pass (LOCAL: body coordinates).
    const Vec v = random_vector(nv, rng, 1.0);
    forward_kinematics(m, d, q, v);
    for (int b = 0; b < m.size(); ++b) {
      Mat Jl(6, nv);
      body_jacobian(m, d, b, ReferenceFrame::Local, Jl);
      const Vec Jv = Jl * v;
      const Motion<double>& vb = d.v[std::size_t(b)];
      EXPECT_LT((Jv.head<3>() - vb.v).norm() + (Jv.tail<3>() - vb.w).norm(), 1e-12) << b;
    }
  }
}

TEST(GeneralModel, EnergyRateEqualsThePowerOfTheJointForces) {
  // d/dt (T + V) = τᵀ v along the motion q̇ = v, v̇ = ABA(τ): central differences of T + V along a trajectory.
  const double dt = 1e-5;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const GeneralModel<double> m = random_general(7, Shape::Branched, seed);
    GeneralData<double> d(m);
    std::mt19937 rng(seed);
    const Vec q = random_q(m, rng), v = random_vector(m.nv(), rng, 1.0), tau = random_vector(m.nv(), rng, 2.0);
    const Vec a = aba(m, d, q, v, tau);
    const auto energy = [&](double t) {
      const Vec qt = integrate(m, q, Vec(v * t + 0.5 * a * t * t));
      const Vec vt = v + a * t;  // the tangent velocity of this curve at t, to first order in t
      forward_kinematics(m, d, qt, vt);
      return kinetic_energy(m, d) + potential_energy(m, d);
    };
    const double rate = (energy(dt) - energy(-dt)) / (2 * dt);
    EXPECT_NEAR(rate, tau.dot(v), 1e-5 * (1 + std::abs(tau.dot(v))));
  }
}

TEST(GeneralModel, FloatGivesTheDoubleResultsToFloatPrecision) {
  const GeneralModel<double> m = random_general(8, Shape::Branched, 5);
  GeneralModel<float> mf(m.gravity().cast<float>());
  for (int i = 0; i < m.size(); ++i) {
    const GeneralJoint<double>& j = m.joint(i);
    mf.add_body(m.parent(i), GeneralJoint<float>{j.kind, j.type, j.axis.cast<float>()}, m.tree_transform(i).cast<float>(),
                m.inertia(i).cast<float>(), m.joint_name(i), m.body_name(i));
  }
  GeneralData<double> d(m);
  GeneralData<float> df(mf);
  std::mt19937 rng(3);
  const Vec q = random_q(m, rng), v = random_vector(m.nv(), rng, 1.0), a = random_vector(m.nv(), rng, 1.0);
  const Eigen::VectorXf qf = q.cast<float>(), vf = v.cast<float>(), af = a.cast<float>();
  EXPECT_LT(rel_diff(rnea(mf, df, qf, vf, af).cast<double>(), Vec(rnea(m, d, q, v, a))), 1e-5);
  EXPECT_LT(rel_diff(crba(mf, df, qf).cast<double>(), Mat(crba(m, d, q))), 1e-5);
  EXPECT_LT(rel_diff(aba(mf, df, qf, vf, af).cast<double>(), Vec(aba(m, d, q, v, a))), 1e-4);
  EXPECT_LT(rel_diff(integrate(mf, qf, vf, 0.1f).cast<double>(), Vec(integrate(m, q, v, 0.1))), 1e-6);
}

TEST(GeneralModel, BadBodiesAreRefusedByNameAndLeaveTheModelUnchanged) {
  GeneralModel<double> m;
  const Inertia<double> I = Inertia<double>::from_com(1.0, V3(0, 0, 0.1), Eigen::Matrix3d::Identity() * 0.01);
  m.add_body(-1, GeneralJoint<double>::spherical(), Transform<double>::Identity(), I, "hip", "thigh");
  const auto refused = [&](int parent, const GeneralJoint<double>& j, const Inertia<double>& In, const char* joint,
                           const std::string& reason) {
    try {
      m.add_body(parent, j, Transform<double>::Identity(), In, joint, std::string("link_") + joint);
      ADD_FAILURE() << joint << " was accepted";
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + joint + "'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
    EXPECT_EQ(m.size(), 1);
    EXPECT_EQ(m.nq(), 4);
    EXPECT_EQ(m.nv(), 3);
  };
  refused(1, GeneralJoint<double>::spherical(), I, "knee", "parent 1");
  refused(-2, GeneralJoint<double>::spherical(), I, "knee", "parent -2");
  refused(0, GeneralJoint<double>::spherical(), I, "hip", "exists already");
  refused(0, GeneralJoint<double>::one_dof(JointType::RevoluteAxis, V3(0, 0, 0)), I, "knee", "zero or not finite");
  refused(0, GeneralJoint<double>::one_dof(JointType::PrismaticAxis, V3(NAN, 0, 1)), I, "knee", "zero or not finite");
  refused(0, GeneralJoint<double>::free_flyer(), Inertia<double>(-1.0, V3::Zero(), Eigen::Matrix3d::Identity()),
          "knee", "negative mass");
  m.add_body(0, GeneralJoint<double>::one_dof(JointType::RevoluteAxis, V3(3, 4, 0)), Transform<double>::Identity(),
             I, "knee", "shank");
  EXPECT_LT((m.joint(1).axis - V3(0.6, 0.8, 0)).norm(), 1e-16);  // normalised
  EXPECT_EQ(m.nq(), 5);
  EXPECT_EQ(m.idx_q(1), 4);
  EXPECT_EQ(m.idx_v(1), 3);
}

}  // namespace
