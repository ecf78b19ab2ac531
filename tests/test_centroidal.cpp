// Centre of mass, CoM Jacobian and centroidal dynamics (centroidal.hpp) on random trees of every joint type, fixed
// and floating, and on the compile-time HOAP-3 stance model.
//
// Independent references:
//  - finite differences of the CoM position (`center_of_mass(model, data, q)`, algorithms.hpp / floating.hpp):
//    central first differences for J_c (along q + e_k h, floating: q ⊕ e_k h), second differences along
//    q ⊕ (v t + ½ a t²) for the CoM acceleration; central differences of A_G along q ⊕ v t for Ȧ_G v and of h_G
//    along (q ⊕ (v t + ½ a t²), v + a t) for ḣ_G (the body velocity along that curve is v + a t + O(t²) with an
//    even O(t²) term, so the central difference is exact to O(h²));
//  - the bodies' momenta about the CoM written with plain 3D vectors (poses from tests/support/reference.hpp,
//    Eigen's active rotations; body velocities from the library's velocity recursion, tested elsewhere):
//    P = Σ mᵢ ċᵢ, k_G = Σ Rᵢ I_cᵢ Rᵢᵀ ωᵢ + (cᵢ − c) × mᵢ ċᵢ; and I_G = Σ of the 6 × 6 body inertias about c;
//  - the identity: on a floating base, RNEA's first six rows (the root wrench) = ḣ_G − (M g, 0) taken to the root;
//  - physics: without gravity or torques, h_G is constant along an RK4 trajectory.
// Tolerances are stated where used: 1e-12 relative where no difference quotient is involved, the truncation and
// rounding of each difference otherwise.

#include <spatial/centroidal.hpp>
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include "support/random_model.hpp"
#include "support/reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
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
using M3 = Matrix3<double>;
using V6 = Vector6<double>;
using M6 = Matrix6<double>;

// ---------------------------------------------------------------------------------------------------------------
// Models
// ---------------------------------------------------------------------------------------------------------------

Model<double> random_fixed(int n, Shape shape, unsigned seed, const V3& g = V3(0, 0, -9.81)) {
  return spatial::testing::build_model(spatial::testing::random_bodies(n, shape, seed), g);
}

Vec random_q(const FloatingModel<double>& m, std::mt19937& rng) {
  const Vec lo = Vec::Constant(m.njoints(), -2.0), hi = Vec::Constant(m.njoints(), 2.0);
  return random_configuration(m, lo, hi, rng);
}

struct Case {
  int n;
  Shape shape;
  unsigned seed;
};
const Case kCases[] = {{1, Shape::Chain, 1}, {5, Shape::Chain, 2}, {12, Shape::Branched, 3},
                       {30, Shape::Branched, 4}, {8, Shape::Branched, 5}};

/// Bodies of a subtree: k is in body b's subtree.
bool in_subtree(const Model<double>& m, int b, int k) { return m.is_ancestor_or_self(b, k); }

// ---------------------------------------------------------------------------------------------------------------
// Independent momenta: plain 3D vectors
// ---------------------------------------------------------------------------------------------------------------

struct BodyState {
  M3 R;        // body axes in world (base) coordinates
  V3 p;        // body origin
  V3 w, v;     // body velocity in body coordinates: angular, velocity of the body-fixed point at the origin
  Inertia<double> I;
};

/// [P; k_G] (linear first) of the bodies about the point c, world axes.
V6 momentum_about(const std::vector<BodyState>& bodies, const V3& c) {
  V3 P = V3::Zero(), k = V3::Zero();
  for (const BodyState& b : bodies) {
    const double m = b.I.m;
    const V3 com_b = b.I.h / m;
    const M3 Ic = b.I.I - m * spatial::testing::crossmat<double>(com_b) * spatial::testing::crossmat<double>(com_b).transpose();
    const V3 w = b.R * b.w;
    const V3 ci = b.p + b.R * com_b;
    const V3 cdot = b.R * b.v + w.cross(ci - b.p);
    P += m * cdot;
    k += b.R * Ic * b.R.transpose() * w + (ci - c).cross(m * cdot);
  }
  V6 out;
  out << P, k;
  return out;
}

/// Σ of the bodies' 6 × 6 inertias about c with world axes, linear first.
M6 inertia_about(const std::vector<BodyState>& bodies, const V3& c) {
  M6 out = M6::Zero();
  for (const BodyState& b : bodies) {
    const double m = b.I.m;
    const V3 com_b = b.I.h / m;
    const M3 Ic = b.I.I - m * spatial::testing::crossmat<double>(com_b) * spatial::testing::crossmat<double>(com_b).transpose();
    const M6 A = spatial::testing::inertia_6x6(m, V3(b.p + b.R * com_b - c), M3(b.R * Ic * b.R.transpose()));
    M6 L;  // reorder to linear first
    L << A.bottomRightCorner<3, 3>(), A.bottomLeftCorner<3, 3>(), A.topRightCorner<3, 3>(), A.topLeftCorner<3, 3>();
    out += L;
  }
  return out;
}

std::vector<BodyState> fixed_bodies(const Model<double>& m, Data<double>& d, const Vec& q, const Vec& v) {
  forward_velocities(m, d, q, v);
  const auto pose = spatial::testing::reference_poses(m, q);
  std::vector<BodyState> out;
  for (int i = 0; i < m.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    out.push_back({pose[k].linear(), pose[k].translation(), d.v[k].w, d.v[k].v, m.inertia(i)});
  }
  return out;
}

std::vector<BodyState> floating_bodies(const FloatingModel<double>& m, FloatingData<double>& d, const Vec& q,
                                       const Vec& v) {
  kinetic_energy(m, d, q, v);  // d.v0 and d.tree.v
  const M3 R0 = root_quaternion(q).toRotationMatrix();
  const V3 p0 = q.head<3>();
  const auto pose = spatial::testing::reference_poses(m.tree(), Vec(q.tail(m.njoints())));
  std::vector<BodyState> out;
  out.push_back({R0, p0, d.v0.w, d.v0.v, m.root_inertia()});
  for (int i = 0; i < m.njoints(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    out.push_back({R0 * pose[k].linear(), p0 + R0 * pose[k].translation(), d.tree.v[k].w, d.tree.v[k].v,
                   m.tree().inertia(i)});
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Centre of mass and its Jacobian
// ---------------------------------------------------------------------------------------------------------------

TEST(CentroidalCom, FixedJacobianMatchesFiniteDifferences) {
  // Central differences, h = 1e-6: truncation ~h² |c‴| ≈ 1e-12, rounding ~ε |c| / h ≈ 1e-10 (|c| ~ 1).
  double worst = 0, worst_sub = 0;
  for (const Case& c : kCases) {
    const auto m = random_fixed(c.n, c.shape, c.seed);
    Data<double> d(m);
    std::mt19937 rng(c.seed);
    for (int t = 0; t < 3; ++t) {
      const Vec q = spatial::testing::random_vector(m.size(), rng, 2.0);
      const Vec v = spatial::testing::random_vector(m.size(), rng);
      Mat Jc(3, m.size());
      com_jacobian(m, d, q, Jc);
      const V3 c0 = center_of_mass(m, d, q);
      EXPECT_LT((d.com - c0).norm(), 1e-14);
      const double h = 1e-6;
      Mat fd(3, m.size());
      for (int k = 0; k < m.size(); ++k) {
        Vec qp = q, qm = q;
        qp[k] += h, qm[k] -= h;
        fd.col(k) = (center_of_mass(m, d, qp) - center_of_mass(m, d, qm)) / (2 * h);
      }
      worst = std::max(worst, (Jc - fd).cwiseAbs().maxCoeff());
      EXPECT_LT((Jc - fd).cwiseAbs().maxCoeff(), 1e-8) << "n " << c.n;
      // J_c v = the CoM velocity of center_of_mass(q, v) (momentum pass: a different computation).
      center_of_mass(m, d, q, v);
      EXPECT_LT((Jc * v - d.vcom).norm(), 1e-12 * (1 + d.vcom.norm())) << "n " << c.n;
      EXPECT_LT((d.com - c0).norm(), 1e-14);
      // Subtrees: every body's subtree, against differences of subtree_center_of_mass and a direct sum.
      for (int b = -1; b < m.size(); b += std::max(1, m.size() / 4)) {
        Mat Js(3, m.size());
        subtree_com_jacobian(m, d, q, b, Js);
        const SubtreeCom<double> sc = subtree_center_of_mass(m, d, q, b);
        forward_kinematics(m, d, q);
        double mass = 0;
        V3 h1 = V3::Zero();
        for (int k = 0; k < m.size(); ++k)
          if (b < 0 || in_subtree(m, b, k)) {
            const Transform<double>& X = d.X_base[static_cast<std::size_t>(k)];
            mass += m.inertia(k).m;
            h1 += m.inertia(k).m * X.r + X.E.transpose() * m.inertia(k).h;
          }
        EXPECT_NEAR(sc.mass, mass, 1e-13 * mass);
        EXPECT_LT((sc.com - h1 / mass).norm(), 1e-13);
        for (int k = 0; k < m.size(); ++k) {
          Vec qp = q, qm = q;
          qp[k] += h, qm[k] -= h;
          const V3 col = (subtree_center_of_mass(m, d, qp, b).com - subtree_center_of_mass(m, d, qm, b).com) / (2 * h);
          worst_sub = std::max(worst_sub, (Js.col(k) - col).cwiseAbs().maxCoeff());
          EXPECT_LT((Js.col(k) - col).cwiseAbs().maxCoeff(), 1e-8) << "n " << c.n << " body " << b << " joint " << k;
          // Joints neither in the subtree nor above it: exactly zero.
          if (b >= 0 && !in_subtree(m, b, k) && !m.is_ancestor_or_self(k, b)) {
            EXPECT_EQ(Js.col(k).norm(), 0.0);
          }
        }
        if (b < 0) {
          EXPECT_LT((Js - Jc).cwiseAbs().maxCoeff(), 1e-15);
        }
      }
    }
  }
  std::printf("fixed CoM Jacobian: worst |J_c − FD| %.2e, subtrees %.2e\n", worst, worst_sub);
}

TEST(CentroidalCom, FloatingJacobianMatchesFiniteDifferences) {
  // Central differences along q ⊕ ±e_k h, h = 1e-6: as above (|c| ≤ ~3 m: root in [−1, 1]³).
  double worst = 0, worst_sub = 0;
  for (const Case& c : kCases) {
    const auto m = random_floating(c.n, c.shape, c.seed);
    FloatingData<double> d(m);
    std::mt19937 rng(c.seed);
    for (int t = 0; t < 3; ++t) {
      const Vec q = random_q(m, rng);
      const Vec v = spatial::testing::random_vector(m.nv(), rng);
      Mat Jc(3, m.nv());
      com_jacobian(m, d, q, Jc);
      const V3 c0 = center_of_mass(m, d, q);
      EXPECT_LT((d.com - c0).norm(), 1e-14 * 10);
      const double h = 1e-6;
      for (int b = -1; b < m.njoints(); b += std::max(1, m.njoints() / 3)) {
        Mat Js(3, m.nv());
        subtree_com_jacobian(m, d, q, b, Js);
        if (b < 0) {
          EXPECT_LT((Js - Jc).cwiseAbs().maxCoeff(), 1e-15);
        }
        for (int k = 0; k < m.nv(); ++k) {
          const Vec e = Vec::Unit(m.nv(), k);
          const Vec qp = integrate(m, q, e, h), qm = integrate(m, q, e, -h);
          const V3 col = (subtree_center_of_mass(m, d, qp, b).com - subtree_center_of_mass(m, d, qm, b).com) / (2 * h);
          const double err = (Js.col(k) - col).cwiseAbs().maxCoeff();
          (b < 0 ? worst : worst_sub) = std::max(b < 0 ? worst : worst_sub, err);
          EXPECT_LT(err, 1e-8) << "n " << c.n << " body " << b << " coordinate " << k;
        }
      }
      const SubtreeCom<double> all = subtree_center_of_mass(m, d, q, -1);
      EXPECT_NEAR(all.mass, m.total_mass(), 1e-13 * m.total_mass());
      EXPECT_LT((all.com - c0).norm(), 1e-13);
      center_of_mass(m, d, q, v);
      EXPECT_LT((Jc * v - d.vcom).norm(), 1e-12 * (1 + d.vcom.norm())) << "n " << c.n;
    }
  }
  std::printf("floating CoM Jacobian: worst |J_c − FD| %.2e, subtrees %.2e\n", worst, worst_sub);
}

TEST(CentroidalCom, AccelerationMatchesSecondDifference) {
  // c̈ by the second central difference along q ⊕ (v t + ½ a t²) (fixed: q + v t + ½ a t²), h = 1e-4:
  // truncation ~h² |c⁗| ≈ 1e-7, rounding ~ε |c| / h² ≈ 1e-8; ċ by the first central difference (≈1e-8).
  double worst = 0;
  for (const Case& c : kCases) {
    {
      const auto m = random_fixed(c.n, c.shape, c.seed);
      Data<double> d(m);
      std::mt19937 rng(c.seed + 7);
      const Vec q = spatial::testing::random_vector(m.size(), rng, 2.0);
      const Vec v = spatial::testing::random_vector(m.size(), rng);
      const Vec a = spatial::testing::random_vector(m.size(), rng);
      const double h = 1e-4;
      const V3 cp = center_of_mass(m, d, Vec(q + v * h + 0.5 * a * h * h));
      const V3 cm = center_of_mass(m, d, Vec(q - v * h + 0.5 * a * h * h));
      const V3 c0 = center_of_mass(m, d, q, v, a);
      const V3 cdd = (cp - 2 * c0 + cm) / (h * h), cd = (cp - cm) / (2 * h);
      worst = std::max(worst, (d.acom - cdd).norm() / (1 + cdd.norm()));
      EXPECT_LT((d.acom - cdd).norm(), 1e-5 * (1 + cdd.norm())) << "fixed n " << c.n;
      EXPECT_LT((d.vcom - cd).norm(), 1e-6 * (1 + cd.norm())) << "fixed n " << c.n;
    }
    {
      const auto m = random_floating(c.n, c.shape, c.seed);
      FloatingData<double> d(m);
      std::mt19937 rng(c.seed + 8);
      const Vec q = random_q(m, rng);
      const Vec v = spatial::testing::random_vector(m.nv(), rng);
      const Vec a = spatial::testing::random_vector(m.nv(), rng);
      const double h = 1e-4;
      const V3 cp = center_of_mass(m, d, integrate(m, q, Vec(v * h + 0.5 * a * h * h)));
      const V3 cm = center_of_mass(m, d, integrate(m, q, Vec(-v * h + 0.5 * a * h * h)));
      const V3 c0 = center_of_mass(m, d, q, v, a);
      const V3 cdd = (cp - 2 * c0 + cm) / (h * h), cd = (cp - cm) / (2 * h);
      worst = std::max(worst, (d.acom - cdd).norm() / (1 + cdd.norm()));
      EXPECT_LT((d.acom - cdd).norm(), 1e-5 * (1 + cdd.norm())) << "floating n " << c.n;
      EXPECT_LT((d.vcom - cd).norm(), 1e-6 * (1 + cd.norm())) << "floating n " << c.n;
      // With gravity and internal torques only, ABA's acceleration makes the CoM fall at exactly g.
      Vec tau = spatial::testing::random_vector(m.nv(), rng, 2.0);
      tau.head<6>().setZero();
      const Vec qdd = aba(m, d, q, v, tau);
      center_of_mass(m, d, q, v, qdd);
      EXPECT_LT((d.acom - m.gravity()).norm(), 1e-10 * m.gravity().norm()) << "floating n " << c.n;
    }
  }
  std::printf("CoM acceleration: worst |c̈ − FD| / (1 + |c̈|) %.2e\n", worst);
}

// ---------------------------------------------------------------------------------------------------------------
// Centroidal momentum matrix, momentum and composite inertia
// ---------------------------------------------------------------------------------------------------------------

/// A_G computed into a block of a larger matrix (column stride 9) and into a row-major matrix, where the column move
/// to the CoM is scalar, is the same matrix as `Ag`, computed into a plain column-major one (its columns moved four
/// lanes at a time where the build has AVX2); the larger matrix keeps its entries outside the block.
template <class M, class D>
void expect_same_in_other_layouts(const M& m, D& d, const Vec& q, const Mat& Ag) {
  const auto n = Ag.cols();
  Mat big = Mat::Constant(9, n + 2, 7.0);
  centroidal_momentum_matrix(m, d, q, big.block(2, 1, 6, n));
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows(6, n);
  centroidal_momentum_matrix(m, d, q, rows);
  const double tol = 1e-14 * (1 + Ag.cwiseAbs().maxCoeff());
  EXPECT_LE((big.block(2, 1, 6, n) - Ag).cwiseAbs().maxCoeff(), tol) << "block of a larger matrix";
  EXPECT_LE((rows - Ag).cwiseAbs().maxCoeff(), tol) << "row-major";
  Mat outside = big;
  outside.block(2, 1, 6, n).setConstant(7.0);
  EXPECT_TRUE((outside.array() == 7.0).all()) << "entries outside the block changed";
}

TEST(CentroidalMomentum, FixedMatchesTheBodiesMomentaAboutTheCom) {
  // No difference quotient: 1e-12 relative to |h_G| (|I_G|).
  double worst = 0;
  for (const Case& c : kCases) {
    const auto m = random_fixed(c.n, c.shape, c.seed);
    Data<double> d(m);
    std::mt19937 rng(c.seed + 11);
    for (int t = 0; t < 3; ++t) {
      const Vec q = spatial::testing::random_vector(m.size(), rng, 2.0);
      const Vec v = spatial::testing::random_vector(m.size(), rng);
      Mat Ag(6, m.size());
      centroidal_momentum_matrix(m, d, q, Ag);
      expect_same_in_other_layouts(m, d, q, Ag);
      const V3 com = d.com;
      EXPECT_LT((com - center_of_mass(m, d, q)).norm(), 1e-14);
      const auto bodies = fixed_bodies(m, d, q, v);
      const V6 ref = momentum_about(bodies, com);
      const V6 hg = centroidal_momentum(m, d, q, v);
      worst = std::max(worst, rel_diff(Vec(Ag * v), ref));
      EXPECT_LT(rel_diff(Vec(Ag * v), ref), 1e-12) << "n " << c.n;
      EXPECT_LT(rel_diff(hg, ref), 1e-12) << "n " << c.n;
      EXPECT_LT((hg.head<3>() - m.total_mass() * d.vcom).norm(), 1e-12 * hg.norm());
      // The linear rows are M J_c.
      Mat Jc(3, m.size());
      com_jacobian(m, d, q, Jc);
      EXPECT_LT(rel_diff(Mat(Ag.topRows<3>()), Mat(m.total_mass() * Jc)), 1e-12);
      const M6 IG = centroidal_composite_inertia(m, d, q);
      const M6 IG_ref = inertia_about(bodies, com);
      EXPECT_LT(rel_diff(IG, IG_ref), 1e-12) << "n " << c.n;
      EXPECT_LT((IG.topRightCorner<3, 3>().cwiseAbs().maxCoeff()), 1e-13 * IG.norm());  // about the CoM: no coupling
    }
  }
  std::printf("fixed A_G v: worst relative error %.2e\n", worst);
}

TEST(CentroidalMomentum, FloatingMatchesTheBodiesMomentaAboutTheCom) {
  double worst = 0;
  for (const Case& c : kCases) {
    const auto m = random_floating(c.n, c.shape, c.seed);
    FloatingData<double> d(m);
    std::mt19937 rng(c.seed + 12);
    for (int t = 0; t < 3; ++t) {
      const Vec q = random_q(m, rng);
      const Vec v = spatial::testing::random_vector(m.nv(), rng);
      Mat Ag(6, m.nv());
      centroidal_momentum_matrix(m, d, q, Ag);
      expect_same_in_other_layouts(m, d, q, Ag);
      const V3 com = d.com;
      EXPECT_LT((com - center_of_mass(m, d, q)).norm(), 1e-14 * 10);
      const auto bodies = floating_bodies(m, d, q, v);
      const V6 ref = momentum_about(bodies, com);
      const V6 hg = centroidal_momentum(m, d, q, v);
      worst = std::max(worst, rel_diff(Vec(Ag * v), ref));
      EXPECT_LT(rel_diff(Vec(Ag * v), ref), 1e-12) << "n " << c.n;
      EXPECT_LT(rel_diff(hg, ref), 1e-12) << "n " << c.n;
      Mat Jc(3, m.nv());
      com_jacobian(m, d, q, Jc);
      EXPECT_LT(rel_diff(Mat(Ag.topRows<3>()), Mat(m.total_mass() * Jc)), 1e-12);
      const M6 IG = centroidal_composite_inertia(m, d, q);
      EXPECT_LT(rel_diff(IG, inertia_about(bodies, com)), 1e-12) << "n " << c.n;
      // The first six columns: the composite inertia at the root (CRBA's H₀₀, linear first: [m 1, h̃ᵀ; h̃, Ī]) moved
      // to G = (origin c, world axes): with P the linear-first ↔ angular-first swap, A_G[:, 0:6] = P ᴳX_r* P H₀₀,
      // ᴳX_r = (E = R, r = c in root coordinates).
      const Mat H = crba(m, d, q);
      M6 P = M6::Zero();
      P.topRightCorner<3, 3>().setIdentity();
      P.bottomLeftCorner<3, 3>().setIdentity();
      const M3 R = root_quaternion(q).toRotationMatrix();
      const V3 c_root = R.transpose() * (com - q.head<3>());
      const M6 X = Transform<double>(R, c_root).force_matrix();
      const M6 expect = P * X * P * M6(H.topLeftCorner<6, 6>());
      EXPECT_LT(rel_diff(M6(Ag.leftCols<6>()), expect), 1e-12) << "n " << c.n;
    }
  }
  std::printf("floating A_G v: worst relative error %.2e\n", worst);
}

TEST(CentroidalMomentum, RootRowsOfRneaAreTheMomentumRateMinusTheWeight) {
  // RNEA's first six rows are the wrench f₀ the root needs (force first, root coordinates, moment about the root
  // origin) = the net external wrench on the robot = ḣ − weight. ḣ_G and the weight (M g, 0) are both about c with
  // world axes: their difference F_G = (k̇_G, ṗ − M g) (angular first) is moved to the world origin,
  // n_O = n_G + c × f, then to root coordinates by ⁰X_w* (data.X0.apply_force). 1e-12 relative.
  const V3 g(0.3, -0.2, -9.81);
  double worst = 0;
  for (const Case& c : kCases) {
    const auto m = random_floating(c.n, c.shape, c.seed, g);
    FloatingData<double> d(m);
    std::mt19937 rng(c.seed + 13);
    for (int t = 0; t < 3; ++t) {
      const Vec q = random_q(m, rng);
      const Vec v = spatial::testing::random_vector(m.nv(), rng);
      const Vec a = spatial::testing::random_vector(m.nv(), rng);
      const CentroidalMomentumRate<double> r = centroidal_momentum_time_variation(m, d, q, v, a);
      const V3 com = d.com;
      const Force<double> FG(r.dhg.tail<3>(), V3(r.dhg.head<3>() - m.total_mass() * g));
      const Force<double> FO(FG.n + com.cross(FG.f), FG.f);
      const Force<double> Fr = detail::root_transform<double>(q).apply_force(FO);
      const Vec tau = rnea(m, d, q, v, a);
      V6 expect;
      expect << Fr.f, Fr.n;
      worst = std::max(worst, rel_diff(V6(tau.head<6>()), expect));
      EXPECT_LT(rel_diff(V6(tau.head<6>()), expect), 1e-12) << "n " << c.n;
    }
  }
  std::printf("RNEA root rows = ḣ_G − weight: worst relative error %.2e\n", worst);
}

TEST(CentroidalMomentum, RateMatchesFiniteDifferences) {
  // Ȧ_G v: central difference of A_G along q ⊕ v t (v constant along it), times v; ḣ_G: central difference of h_G
  // along (q ⊕ (v t + ½ a t²), v + a t). h = 1e-5: truncation ~h² ≈ 1e-10, rounding ~ε/h ≈ 2e-11 (relative).
  // Also ḣ_G = A_G a + Ȧ_G v (1e-12).
  double worst = 0;
  for (const Case& c : kCases) {
    const double h = 1e-5;
    {
      const auto m = random_fixed(c.n, c.shape, c.seed);
      Data<double> d(m);
      std::mt19937 rng(c.seed + 14);
      const Vec q = spatial::testing::random_vector(m.size(), rng, 2.0);
      const Vec v = spatial::testing::random_vector(m.size(), rng);
      const Vec a = spatial::testing::random_vector(m.size(), rng);
      Mat Ap(6, m.size()), Am(6, m.size()), A0(6, m.size());
      centroidal_momentum_matrix(m, d, Vec(q + h * v), Ap);
      centroidal_momentum_matrix(m, d, Vec(q - h * v), Am);
      centroidal_momentum_matrix(m, d, q, A0);
      const V6 dAv = (Ap - Am) * v / (2 * h);
      const V6 hp = centroidal_momentum(m, d, Vec(q + h * v + 0.5 * h * h * a), Vec(v + h * a));
      const V6 hm = centroidal_momentum(m, d, Vec(q - h * v + 0.5 * h * h * a), Vec(v - h * a));
      const V6 dh = (hp - hm) / (2 * h);
      const CentroidalMomentumRate<double> r = centroidal_momentum_time_variation(m, d, q, v, a);
      worst = std::max({worst, rel_diff(r.dAg_v, dAv), rel_diff(r.dhg, dh)});
      EXPECT_LT(rel_diff(r.dAg_v, dAv), 1e-7) << "fixed n " << c.n;
      EXPECT_LT(rel_diff(r.dhg, dh), 1e-7) << "fixed n " << c.n;
      EXPECT_LT(rel_diff(r.dhg, V6(A0 * a + r.dAg_v)), 1e-12) << "fixed n " << c.n;
      EXPECT_GT(r.dAg_v.norm(), 1e-3);  // not trivially zero
    }
    {
      const auto m = random_floating(c.n, c.shape, c.seed);
      FloatingData<double> d(m);
      std::mt19937 rng(c.seed + 15);
      const Vec q = random_q(m, rng);
      const Vec v = spatial::testing::random_vector(m.nv(), rng);
      const Vec a = spatial::testing::random_vector(m.nv(), rng);
      Mat Ap(6, m.nv()), Am(6, m.nv()), A0(6, m.nv());
      centroidal_momentum_matrix(m, d, integrate(m, q, v, h), Ap);
      centroidal_momentum_matrix(m, d, integrate(m, q, v, -h), Am);
      centroidal_momentum_matrix(m, d, q, A0);
      const V6 dAv = (Ap - Am) * v / (2 * h);
      const V6 hp = centroidal_momentum(m, d, integrate(m, q, Vec(h * v + 0.5 * h * h * a)), Vec(v + h * a));
      const V6 hm = centroidal_momentum(m, d, integrate(m, q, Vec(-h * v + 0.5 * h * h * a)), Vec(v - h * a));
      const V6 dh = (hp - hm) / (2 * h);
      const CentroidalMomentumRate<double> r = centroidal_momentum_time_variation(m, d, q, v, a);
      worst = std::max({worst, rel_diff(r.dAg_v, dAv), rel_diff(r.dhg, dh)});
      EXPECT_LT(rel_diff(r.dAg_v, dAv), 1e-7) << "floating n " << c.n;
      EXPECT_LT(rel_diff(r.dhg, dh), 1e-7) << "floating n " << c.n;
      EXPECT_LT(rel_diff(r.dhg, V6(A0 * a + r.dAg_v)), 1e-12) << "floating n " << c.n;
      EXPECT_GT(r.dAg_v.norm(), 1e-3);
    }
  }
  std::printf("ḣ_G, Ȧ_G v against differences: worst relative error %.2e\n", worst);
}

TEST(CentroidalMomentum, ConservedInFreeFlight) {
  // No gravity, τ = 0: no external force, so h_G (linear momentum and angular momentum about the moving CoM) is
  // constant. RK4 on the manifold over 1 s (as test_floating.cpp: of order 2 in the pose); the drift must be small
  // and shrink at least threefold when the step is halved (a wrong term would leave a drift that does not shrink).
  for (const Case& c : {Case{6, Shape::Branched, 31}, Case{12, Shape::Chain, 32}}) {
    const auto m = random_floating(c.n, c.shape, c.seed, V3::Zero());
    FloatingData<double> d(m);
    std::mt19937 rng(c.seed);
    const Vec q0 = random_q(m, rng);
    const Vec v0 = spatial::testing::random_vector(m.nv(), rng);
    const Vec tau = Vec::Zero(m.nv());
    const V6 h0 = centroidal_momentum(m, d, q0, v0);
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
      drift[run] = (centroidal_momentum(m, d, q, v) - h0).norm() / h0.norm();
      // Along the way ḣ_G = 0 (no external force other than gravity, which is off).
      const CentroidalMomentumRate<double> r = centroidal_momentum_time_variation(m, d, q, v, acc(q, v));
      EXPECT_LT(r.dhg.norm(), 1e-10 * (1 + r.dAg_v.norm())) << "n " << c.n;
    }
    EXPECT_LT(drift[1], 1e-6) << "n " << c.n;
    EXPECT_LT(drift[1], drift[0] / 3) << "n " << c.n;
    std::printf("h_G drift over 1 s (n = %d): %.2e at 2 ms, %.2e at 1 ms\n", c.n, drift[0], drift[1]);
  }
}

}  // namespace
