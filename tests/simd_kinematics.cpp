// The kinematics on the AVX2 paths (a translation unit built with -mavx2 -mfma): forward kinematics
// (simd::forward_kinematics, which also leaves the motion subspaces in base coordinates), the world Jacobian columns
// (simd::world_jacobian_columns) and the one-walk body and frame Jacobians (detail::jacobian_walk_simd), which serve
// compile-time trees of axis-aligned revolute joints and, chosen per call, run-time trees of such joints. Each is
// compared, on a compile-time model and on its run-time twin, with the same call on the model's scalar twin (every
// joint a RevoluteAxis joint about the same axis: the scalar path), on the HOAP-3 models and random trees, fixed and
// floating; so are the functions built on them (CoM Jacobian, A_G). The one-walk Jacobians are also written into a
// block of a larger matrix (outer stride ≠ 6), which takes the scalar walk; a run-time chain deeper than the walk's
// stack arrays takes it too. The Jacobians taken from the world columns (`body_jacobian`, `frame_jacobian`) move
// them to the body's or frame's origin in lanes (simd::jacobian_column_at) and are compared with the one-walk ones;
// both write into matrices filled with NaN first, so a column left unwritten (rather than zeroed) fails.
// A_G is also computed into such a block, where its columns are moved to the CoM one by one rather than four lanes
// at a time.
#include "support/simd_compare.hpp"

#include <spatial/models/hoap3_floating.hpp>

#include <limits>

namespace {
using namespace spatial;
using namespace spatial::testing::simd;

constexpr ReferenceFrame kFrames[] = {ReferenceFrame::Local, ReferenceFrame::World,
                                      ReferenceFrame::LocalWorldAligned};

template <class A, class B>
double max_diff(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return double((a - b).cwiseAbs().template maxCoeff<Eigen::PropagateNaN>());  // a NaN left in `a` fails
}

/// Every output of the kinematics on a model M (AVX2: compile-time, or its run-time twin) and its scalar twin R, at q.
template <class M, class R, class DM, class DR, class Q>
void compare_kinematics(const M& m, const R& r, DM& dm, DR& dr, const Q& q, int nv, double tol) {
  using S = typename Q::Scalar;
  using MX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  const Eigen::Matrix<S, Eigen::Dynamic, 1> qd = q;
  // Forward kinematics: transforms, and the subspaces the AVX2 pass leaves in S_base.
  forward_kinematics(m, dm, q);
  forward_kinematics(r, dr, qd);
  const auto& tm = detail::kin(m, dm).td();
  const auto& tr = detail::kin(r, dr).td();
  const auto& tree = detail::kin(m, dm).tree;
  for (int i = 0; i < tree.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_LE(max_diff(tm.X_base[k].E, tr.X_base[k].E), tol) << "E of body " << i;
    EXPECT_LE(max_diff(tm.X_base[k].r, tr.X_base[k].r), tol * (1 + tr.X_base[k].r.norm())) << "r of body " << i;
    const Motion<S> s = tree.joint(i).subspace_inverse(tr.X_base[k]);
    EXPECT_LE(max_diff(tm.S_base[k].w, s.w), tol) << "S_base of body " << i;
    EXPECT_LE(max_diff(tm.S_base[k].v, s.v), tol * (1 + s.v.norm())) << "S_base of body " << i;
  }
  // All joint Jacobians (World).
  const MX Jr = compute_joint_jacobians(r, dr, qd);
  const MX Jm = compute_joint_jacobians(m, dm, q);
  const double scale = 1 + double(Jr.cwiseAbs().maxCoeff());
  EXPECT_LE(max_diff(Jm, Jr), tol * scale) << "compute_joint_jacobians";
  // One-walk Jacobians of every body (and the base/root) and every frame, in the three reference frames; into a
  // 6 × nv matrix (AVX2 walk) and into a block of a larger one (scalar walk on the same compile-time tree).
  MX Js(6, nv), Jb(6, nv), big(9, nv + 2), Jref(6, nv);
  const S kNaN = std::numeric_limits<S>::quiet_NaN();
  for (ReferenceFrame rf : kFrames) {
    for (int b = -1; b < tree.size(); ++b) {
      compute_body_jacobian(r, dr, qd, b, rf, Jref);
      Js.setConstant(kNaN);  // every entry must be written, the zero columns too
      Jb.setConstant(kNaN);
      compute_body_jacobian(m, dm, q, b, rf, Js);
      big.setConstant(S(7));
      compute_body_jacobian(m, dm, q, b, rf, big.block(2, 1, 6, nv));
      EXPECT_LE(max_diff(Js, Jref), tol * scale) << "body " << b << " rf " << int(rf);
      EXPECT_LE(max_diff(big.block(2, 1, 6, nv), Jref), tol * scale) << "block, body " << b << " rf " << int(rf);
      EXPECT_EQ(big.row(0).sum() + big.row(1).sum() + big.row(8).sum(), S(3 * 7 * (nv + 2))) << "outside the block";
      // The walk agrees with the Jacobian taken from all joint Jacobians.
      body_jacobian(m, dm, b, rf, Jb);
      EXPECT_LE(max_diff(Js, Jb), tol * scale) << "walk vs joint Jacobians, body " << b;
    }
    for (int f = 0; f < static_cast<int>(tree.frames().size()); ++f) {
      compute_frame_jacobian(r, dr, qd, f, rf, Jref);
      Js.setConstant(kNaN);
      Jb.setConstant(kNaN);
      compute_frame_jacobian(m, dm, q, f, rf, Js);
      EXPECT_LE(max_diff(Js, Jref), tol * scale) << "frame " << tree.frames()[std::size_t(f)].name;
      frame_jacobian(m, dm, f, rf, Jb);
      EXPECT_LE(max_diff(Js, Jb), tol * scale) << "walk vs joint Jacobians, frame " << f;
    }
  }
  // CoM Jacobian and A_G (built on the forward kinematics).
  MX Cm(3, nv), Cr(3, nv), Am(6, nv), Ar(6, nv);
  com_jacobian(m, dm, q, Cm);
  com_jacobian(r, dr, qd, Cr);
  EXPECT_LE(max_diff(Cm, Cr), tol * (1 + double(Cr.cwiseAbs().maxCoeff()))) << "com_jacobian";
  centroidal_momentum_matrix(m, dm, q, Am);
  centroidal_momentum_matrix(r, dr, qd, Ar);
  EXPECT_LE(max_diff(Am, Ar), tol * (1 + double(Ar.cwiseAbs().maxCoeff()))) << "centroidal_momentum_matrix";
  // A_G's joint columns are moved to the CoM four lanes at a time in a plain matrix (simd::move_force_columns), one
  // by one in a block of a larger one (outer stride ≠ 6): the same matrix, and nothing outside the block written.
  MX bigA = MX::Constant(9, nv + 2, S(7));
  centroidal_momentum_matrix(m, dm, q, bigA.block(2, 1, 6, nv));
  EXPECT_LE(max_diff(bigA.block(2, 1, 6, nv), Am), tol * (1 + double(Ar.cwiseAbs().maxCoeff())))
      << "centroidal_momentum_matrix into a block";
  bigA.block(2, 1, 6, nv).setConstant(S(7));
  EXPECT_TRUE((bigA.array() == S(7)).all()) << "centroidal_momentum_matrix wrote outside the block";
}

template <class TreeT, class S>
void compare_fixed(const Model<S, TreeT>& m, unsigned seed) {
  static_assert(detail::simd_enabled<S, TreeT>());
  const Model<S> rt = m.to_runtime(), r = scalar_twin(m);
  ASSERT_TRUE(detail::simd_applies(rt));
  Data<S, TreeT> dm(m);
  Data<S> drt(rt), dr(r);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.2, 3.2);
  for (int trial = 0; trial < 10; ++trial) {
    Eigen::Matrix<S, TreeT::size, 1> q;
    for (int i = 0; i < TreeT::size; ++i) q[i] = S(u(rng));
    const Eigen::Matrix<S, Eigen::Dynamic, 1> qd = q;
    compare_kinematics(m, r, dm, dr, q, TreeT::size, tolerance<TreeT, S>());
    compare_kinematics(rt, r, drt, dr, qd, TreeT::size, tolerance<TreeT, S>());
  }
}

template <class TreeT, class S>
void compare_floating(const FloatingModel<S, TreeT>& m, unsigned seed) {
  static_assert(detail::simd_enabled<S, TreeT>());
  const FloatingModel<S> rt = m.to_runtime(), r = scalar_twin(m);
  ASSERT_TRUE(detail::simd_applies(rt.tree()));
  FloatingData<S, TreeT> dm(m);
  FloatingData<S> drt(rt), dr(r);
  std::mt19937 rng(seed);
  const Eigen::Matrix<S, Eigen::Dynamic, 1> lo = Eigen::Matrix<S, Eigen::Dynamic, 1>::Constant(TreeT::size, S(-3.2));
  const Eigen::Matrix<S, Eigen::Dynamic, 1> hi = -lo;
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Matrix<S, FloatingModel<S, TreeT>::NQ, 1> q = random_configuration(m, lo, hi, rng);
    const Eigen::Matrix<S, Eigen::Dynamic, 1> qd = q;
    compare_kinematics(m, r, dm, dr, q, m.nv(), tolerance<TreeT, S>());
    compare_kinematics(rt, r, drt, dr, qd, m.nv(), tolerance<TreeT, S>());
  }
}

TEST(SimdKinematics, FixedHoap3) { compare_fixed(models::hoap3_stance_right::model(), 80); }

TEST(SimdKinematics, FloatingHoap3) { compare_floating(models::hoap3_floating::floating_model(), 81); }

TEST(SimdKinematics, Float) {
  compare_fixed(models::hoap3_stance_right::model().cast<float>(), 86);
  compare_floating(FloatingModel<double, Rev9>(random_static<Rev9>(87), test_root_inertia()).cast<float>(), 87);
}

TEST(SimdKinematics, RandomTrees) {
  for (unsigned seed = 82; seed < 85; ++seed) {
    compare_fixed(random_static<Rev9>(seed), seed);
    compare_fixed(random_static<RevChain24>(seed), seed);
    compare_floating(FloatingModel<double, Rev9>(random_static<Rev9>(seed), test_root_inertia()), seed);
    compare_floating(FloatingModel<double, RevChain24>(random_static<RevChain24>(seed), test_root_inertia()), seed);
  }
}

// A run-time chain of revolute joints about coordinate axes deeper than the walk's stack arrays
// (detail::kMaxWalkDepth): the bodies near the tip take the scalar walk, the others the AVX2 walk, and all
// give the scalar twin's Jacobians.
TEST(SimdKinematics, DeepRuntimeChainTakesTheScalarWalk) {
  const int n = detail::kMaxWalkDepth + 6;
  std::vector<spatial::testing::RandomBody> bodies = spatial::testing::random_bodies(
      n, spatial::testing::Shape::Chain, 88, false);
  for (int i = 0; i < n; ++i) bodies[std::size_t(i)].type = kAxes[i % 3];
  const Model<double> rt = spatial::testing::build_model(bodies), r = scalar_twin(rt);
  ASSERT_TRUE(detail::simd_applies(rt));
  Data<double> drt(rt), dr(r);
  std::mt19937 rng(88);
  const Eigen::VectorXd q = spatial::testing::random_vector(n, rng, 3.0);
  Eigen::MatrixXd Js(6, n), Jref(6, n);
  for (ReferenceFrame rf : kFrames) {
    for (int b : {n - 1, n - 6, n - 7, 10}) {
      compute_body_jacobian(rt, drt, q, b, rf, Js);
      compute_body_jacobian(r, dr, q, b, rf, Jref);
      EXPECT_LE(max_diff(Js, Jref), 1e-12 * (1 + Jref.cwiseAbs().maxCoeff())) << "body " << b << " rf " << int(rf);
    }
  }
}

}  // namespace
