// Rigid contacts (contact.hpp): constrained forward dynamics and impulse dynamics against a dense KKT solve built
// from independent parts (CRBA's H, the one-walk frame Jacobians of compute_frame_jacobian, the drift of
// frame_jdot_qdot / frame_classical_jdot_qdot, RNEA's bias), the round trip through RNEA (H v̇ + C = τ + Jᵀλ), the
// frames' accelerations after forward kinematics with the result (= the Baumgarte terms), the impact laws (J v⁺ =
// −e J v⁻, no energy gained), damped redundant contacts, float, the HOAP-3's two feet, and bad input; whole-body
// inverse dynamics with contacts (the physical split: cones, soles, the known split of a symmetric stance, the
// round trip through constrained forward dynamics); the multibody ZMP against the CoP of the contact forces.

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>

#include "support/compile_time_trees.hpp"  // SPATIAL_TEST_COMPILE_TIME_TREES: 0 in the sanitizer build
#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <Eigen/SVD>

#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
using spatial::testing::random_vector;
using spatial::testing::Shape;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;

double rel_err(const Mat& a, const Mat& b) { return (a - b).cwiseAbs().maxCoeff() / (1.0 + b.cwiseAbs().maxCoeff()); }

template <class M>
using DataOf = typename detail::ModelTraits<M>::DataType;

template <class M>
const Model<double>& tree_of(const M& m) {
  return detail::ModelTraits<M>::tree(m);
}

/// World rotation R (frame axes → world) and origin p of frame f after forward kinematics at q.
template <class M>
std::pair<Matrix3<double>, Vector3<double>> frame_pose_at(const M& model, const Vec& q, int f) {
  DataOf<M> d(model);
  forward_kinematics(model, d, q);
  const auto pose = frame_pose(model, d, f);
  return {pose.linear(), pose.translation()};
}

/// The rows of each contact, the drift, and a* = −K_d J v − K_p e, computed from the public kinematics functions.
struct Reference {
  Mat J;
  Vec drift, a_star;
};
template <class M>
Reference reference(const M& model, const std::vector<RigidContact<double>>& contacts, const Vec& q, const Vec& v) {
  const int nv = static_cast<int>(v.size());
  int m = 0;
  for (const auto& c : contacts) m += c.dim();
  Reference r{Mat::Zero(m, nv), Vec::Zero(m), Vec::Zero(m)};
  DataOf<M> d(model);
  int row = 0;
  for (const auto& c : contacts) {
    const auto [R, p] = frame_pose_at(model, q, c.frame);
    Mat J6 = Mat::Zero(6, nv);
    if (c.type == ContactType::Contact6D) {
      compute_frame_jacobian(model, d, q, c.frame, ReferenceFrame::Local, J6);
      r.J.middleRows(row, 6) = J6;
      const Motion<double> g = frame_jdot_qdot(model, d, q, v, c.frame, ReferenceFrame::Local);
      r.drift.segment<3>(row) = g.v;
      r.drift.segment<3>(row + 3) = g.w;
      Vec e(6);
      e << R.transpose() * (p - c.target_position), detail::so3_log<double>(c.target_rotation.transpose() * R);
      r.a_star.segment(row, 6) = -c.kd * (J6 * v) - c.kp * e;
    } else {
      compute_frame_jacobian(model, d, q, c.frame, ReferenceFrame::LocalWorldAligned, J6);
      r.J.middleRows(row, 3) = J6.topRows(3);
      r.drift.segment<3>(row) = frame_classical_jdot_qdot(model, d, q, v, c.frame, ReferenceFrame::LocalWorldAligned);
      r.a_star.segment(row, 3) = -c.kd * (J6.topRows(3) * v) - c.kp * (p - c.target_position);
    }
    row += c.dim();
  }
  return r;
}

/// λ from each contact's reference axes into its rows' axes (6D: frame axes, 3D: world axes).
template <class M>
Vec to_row_axes(const M& model, const std::vector<RigidContact<double>>& contacts, const Vec& q, Vec lambda) {
  int row = 0;
  for (const auto& c : contacts) {
    const Matrix3<double> R = frame_pose_at(model, q, c.frame).first;
    const bool local_rows = c.type == ContactType::Contact6D;
    if (local_rows != (c.reference == ReferenceFrame::Local))
      for (int b = 0; b < c.dim(); b += 3) {
        const Vector3<double> f = lambda.segment<3>(row + b);
        lambda.segment<3>(row + b) = local_rows ? Vector3<double>(R.transpose() * f) : Vector3<double>(R * f);
      }
    row += c.dim();
  }
  return lambda;
}

/// Gains and targets away from the current pose, so that a* has all three terms.
void perturb_targets(std::vector<RigidContact<double>>& contacts, std::mt19937& rng) {
  for (auto& c : contacts) {
    c.kp = 100.0;
    c.kd = 20.0;
    c.target_position = random_vector(3, rng, 1.0);
    c.target_rotation = spatial::testing::random_rotation(rng);
  }
}

/// Constrained forward dynamics against the dense KKT system, the RNEA round trip and the frames' accelerations.
template <class M>
void check_forward(const M& model, std::vector<RigidContact<double>> contacts, const Vec& q, const Vec& v,
                   const Vec& tau, double tol = 1e-9) {
  DataOf<M> data(model);
  ContactData<M> cd(model, contacts);
  constrained_forward_dynamics(model, data, cd, q, v, tau);
  ASSERT_TRUE(cd.ok);
  const Vec qdd = cd.qdd, lambda = to_row_axes(model, contacts, q, cd.lambda);

  // KKT: [H −Jᵀ; J 0] [v̇; λ] = [τ − C; a* − J̇ q̇].
  const Reference ref = reference(model, contacts, q, v);
  DataOf<M> d(model);
  const int nv = static_cast<int>(v.size()), m = cd.m;
  const Mat H = crba(model, d, q);
  const Vec C = rnea(model, d, q, v, Vec::Zero(nv));
  Mat K = Mat::Zero(nv + m, nv + m);
  K.topLeftCorner(nv, nv) = H;
  K.topRightCorner(nv, m) = -ref.J.transpose();
  K.bottomLeftCorner(m, nv) = ref.J;
  Vec b(nv + m);
  b << tau - C, ref.a_star - ref.drift;
  const Vec x = K.fullPivLu().solve(b);
  EXPECT_LT(rel_err(qdd, x.head(nv)), tol) << "v̇\n" << qdd.transpose() << "\n" << x.head(nv).transpose();
  EXPECT_LT(rel_err(lambda, x.tail(m)), tol) << "λ\n" << lambda.transpose() << "\n" << x.tail(m).transpose();
  EXPECT_LT(rel_err(cd.J, ref.J), 1e-12);

  // Round trip: RNEA(q, v, v̇) = τ + Jᵀ λ.
  EXPECT_LT(rel_err(rnea(model, d, q, v, qdd), tau + ref.J.transpose() * lambda), tol);

  // The frames' accelerations with v̇ are a*: J v̇ + J̇ q̇ = −K_d J v − K_p e.
  forward_kinematics(model, d, q, v, qdd);
  int row = 0;
  for (const auto& c : contacts) {
    if (c.type == ContactType::Contact6D) {
      const Motion<double> a = frame_acceleration(model, d, c.frame, ReferenceFrame::Local);
      Vec a6(6);
      a6 << a.v, a.w;
      EXPECT_LT(rel_err(a6, ref.a_star.segment(row, 6)), tol) << c.name;
    } else {
      const Vector3<double> a = frame_classical_acceleration(model, d, c.frame, ReferenceFrame::LocalWorldAligned);
      EXPECT_LT(rel_err(a, ref.a_star.segment(row, 3)), tol) << c.name;
    }
    row += c.dim();
  }

  // A second call on the same buffers gives the same numbers.
  constrained_forward_dynamics(model, data, cd, q, v, tau);
  EXPECT_EQ(Vec(cd.qdd), qdd);
}

/// Impulse dynamics: the impact law, the impulse balance, and the kinetic energy.
template <class M>
void check_impulse(const M& model, const std::vector<RigidContact<double>>& contacts, const Vec& q, const Vec& v) {
  DataOf<M> data(model);
  ContactData<M> cd(model, contacts);
  const Reference ref = reference(model, contacts, q, v);
  DataOf<M> d(model);
  const Mat H = crba(model, d, q);
  const double ke_before = 0.5 * v.dot(H * v);
  for (double e : {0.0, 0.5, 1.0}) {
    SCOPED_TRACE("restitution " + std::to_string(e));
    const Vec v_after = impulse_dynamics(model, data, cd, q, v, e);
    ASSERT_TRUE(cd.ok);
    const Vec impulse = to_row_axes(model, contacts, q, cd.lambda);
    EXPECT_LT(rel_err(ref.J * v_after, -e * (ref.J * v)), 1e-10);
    EXPECT_LT(rel_err(H * (v_after - v), ref.J.transpose() * impulse), 1e-10);
    const double ke_after = 0.5 * v_after.dot(H * v_after);
    if (e < 1.0) EXPECT_LT(ke_after, ke_before);
    else EXPECT_NEAR(ke_after, ke_before, 1e-10 * ke_before);
  }
}

FloatingModel<double> random_floating_with_frames(int n, Shape shape, unsigned seed) {
  std::mt19937 rng(seed + 1000);
  return FloatingModel<double>(
      spatial::testing::build_model_with_frames(spatial::testing::random_bodies(n, shape, seed), seed),
      spatial::testing::random_root_inertia(rng), "root");
}

// Frames 0, 1, 2: on the root, the last body, a middle body. On a chain every set is independent (frames 1 and 2
// are five or more joints apart); on a branched tree the middle body may be the last one's parent, and a weld on one
// with a point contact on the other is then redundant (Λ⁻¹ singular), so those trees get the sets without frame 2.
std::vector<std::vector<RigidContact<double>>> contact_sets(bool chain) {
  if (!chain) return {{contact_6d(1)}, {contact_6d(0), contact_3d(1)}, {contact_3d(0, ReferenceFrame::Local), contact_3d(1)}};
  return {
      {contact_6d(1)},
      {contact_6d(1, ReferenceFrame::LocalWorldAligned), contact_3d(2, ReferenceFrame::Local)},
      {contact_3d(0), contact_3d(1, ReferenceFrame::Local), contact_3d(2)},
      {contact_6d(0), contact_3d(1)},
  };
}

TEST(Contact, FloatingRandomTreesAgainstDenseKkt) {
  for (const auto& [n, shape, seed] : {std::tuple{9, Shape::Branched, 1u}, std::tuple{12, Shape::Chain, 2u},
                                       std::tuple{15, Shape::Branched, 3u}, std::tuple{14, Shape::Chain, 4u}}) {
    const FloatingModel<double> model = random_floating_with_frames(n, shape, seed);
    std::mt19937 rng(seed);
    const Vec q = random_configuration(model, Vec::Constant(n, -2.0), Vec::Constant(n, 2.0), rng);
    const Vec v = random_vector(model.nv(), rng, 2.0), tau = random_vector(model.nv(), rng, 5.0);
    int k = 0;
    for (auto contacts : contact_sets(shape == Shape::Chain)) {
      SCOPED_TRACE("tree " + std::to_string(n) + ", contact set " + std::to_string(k++));
      check_forward(model, contacts, q, v, tau);
      perturb_targets(contacts, rng);
      check_forward(model, contacts, q, v, tau);
      check_impulse(model, contacts, q, v);
    }
  }
}

TEST(Contact, FixedBaseChainWithAnEndEffectorConstraint) {
  for (unsigned seed : {4u, 5u}) {
    const Model<double> model =
        spatial::testing::build_model_with_frames(spatial::testing::random_bodies(8, Shape::Chain, seed), seed);
    std::mt19937 rng(seed);
    const Vec q = random_vector(8, rng, 2.0), v = random_vector(8, rng, 2.0), tau = random_vector(8, rng, 5.0);
    std::vector<RigidContact<double>> point{contact_3d(1)}, weld{contact_6d(1)};
    check_forward(model, point, q, v, tau);
    check_forward(model, weld, q, v, tau);
    perturb_targets(point, rng);
    check_forward(model, point, q, v, tau);
    check_impulse(model, weld, q, v);
  }
}

TEST(Contact, Hoap3StandingOnBothFeetCompileTimeAndRunTimeTrees) {
  const auto model = models::hoap3_floating::floating_model<double>();
  const auto rt = model.to_runtime();
  const std::vector<RigidContact<double>> feet{contact_6d(models::hoap3_floating::frame_index("L_SOLE")),
                                               contact_6d(models::hoap3_floating::frame_index("R_SOLE"))};
  std::mt19937 rng(7);
  const int n = model.njoints();
  for (int k = 0; k < 4; ++k) {
    const Vec q = random_configuration(rt, Vec::Constant(n, -0.5), Vec::Constant(n, 0.5), rng);
    const Vec v = random_vector(model.nv(), rng, 1.0), tau = random_vector(model.nv(), rng, 2.0);
    check_forward(rt, feet, q, v, tau);
    check_impulse(rt, feet, q, v);
#if SPATIAL_TEST_COMPILE_TIME_TREES
    FloatingData<double, models::hoap3_floating::Tree> data(model);
    ContactData<std::decay_t<decltype(model)>> cd(model, feet);
    const Eigen::Matrix<double, 28, 1> qs = q;
    const Eigen::Matrix<double, 27, 1> vs = v, ts = tau;
    constrained_forward_dynamics(model, data, cd, qs, vs, ts);
    FloatingData<double> drt(rt);
    ContactData<FloatingModel<double>> crt(rt, feet);
    constrained_forward_dynamics(rt, drt, crt, q, v, tau);
    EXPECT_LT(rel_err(cd.qdd, crt.qdd), 1e-12);
    EXPECT_LT(rel_err(cd.lambda, crt.lambda), 1e-12);
#endif
  }
}

TEST(Contact, NewtonsLawForTheWholeRobotOnItsFeet) {
  // The feet's forces (world axes) and gravity accelerate the centre of mass: Σ f + m g = m c̈.
  const auto rt = models::hoap3_floating::floating_model<double>().to_runtime();
  const std::vector<RigidContact<double>> feet{
      contact_6d(rt.frame_index("L_SOLE"), ReferenceFrame::LocalWorldAligned),
      contact_6d(rt.frame_index("R_SOLE"), ReferenceFrame::LocalWorldAligned)};
  std::mt19937 rng(11);
  const int n = rt.njoints();
  FloatingData<double> data(rt);
  ContactData<FloatingModel<double>> cd(rt, feet);
  for (int k = 0; k < 4; ++k) {
    const Vec q = k == 0 ? Vec(neutral(rt)) : Vec(random_configuration(rt, Vec::Constant(n, -0.5), Vec::Constant(n, 0.5), rng));
    const Vec v = k == 0 ? Vec(Vec::Zero(rt.nv())) : random_vector(rt.nv(), rng, 1.0);
    Vec tau = random_vector(rt.nv(), rng, 2.0);
    tau.head(6).setZero();
    constrained_forward_dynamics(rt, data, cd, q, v, tau);
    ASSERT_TRUE(cd.ok);
    center_of_mass(rt, data, q, v, cd.qdd);
    const Vector3<double> lhs = cd.lambda.segment<3>(0) + cd.lambda.segment<3>(6) + rt.total_mass() * rt.gravity();
    const Vector3<double> rhs = rt.total_mass() * data.acom;
    EXPECT_LT((lhs - rhs).norm(), 1e-9 * rt.total_mass() * 9.81) << lhs.transpose() << " vs " << rhs.transpose();
  }
}

TEST(Contact, RedundantContactsWithDampingShareTheLoad) {
  // The same weld twice: Λ⁻¹ is singular; with a small damping the motion is that of one weld and the force is
  // split in two equal halves (the least-norm split). The damping μ biases v̇ by O(μ) and amplifies the rounding
  // of Λ⁻¹'s two equal blocks in the split by O(ε‖Λ⁻¹‖/μ); μ = 1e-8 ≈ √ε balances the two. (With μ = 1e-10 the
  // split was 7e-7 off on x86-64 and 1e-5 on aarch64, where the random model differs: the order in which
  // random_rotation's Quaterniond(n(rng), ...) draws its arguments is unspecified.)
  const FloatingModel<double> model = random_floating_with_frames(9, Shape::Branched, 8);
  std::mt19937 rng(8);
  const Vec q = random_configuration(model, Vec::Constant(9, -2.0), Vec::Constant(9, 2.0), rng);
  const Vec v = random_vector(model.nv(), rng, 1.0), tau = random_vector(model.nv(), rng, 2.0);
  FloatingData<double> data(model);
  ContactData<FloatingModel<double>> one(model, {contact_6d(1)}), two(model, {contact_6d(1), contact_6d(1)});
  constrained_forward_dynamics(model, data, one, q, v, tau);
  constrained_forward_dynamics(model, data, two, q, v, tau);
  EXPECT_FALSE(two.ok) << "an undamped redundant pair of welds must be reported";
  two.damping = 1e-8;
  constrained_forward_dynamics(model, data, two, q, v, tau);
  ASSERT_TRUE(two.ok);
  EXPECT_LT(rel_err(two.qdd, one.qdd), 1e-6);
  EXPECT_LT(rel_err(two.lambda.head(6), 0.5 * one.lambda), 1e-6);
  EXPECT_LT(rel_err(two.lambda.tail(6), 0.5 * one.lambda), 1e-6);
}

TEST(Contact, FloatAgreesWithDouble) {
  const FloatingModel<double> model = random_floating_with_frames(12, Shape::Chain, 9);
  const FloatingModel<float> mf = model.cast<float>();
  std::mt19937 rng(9);
  const Vec q = random_configuration(model, Vec::Constant(12, -1.0), Vec::Constant(12, 1.0), rng);
  const Vec v = random_vector(model.nv(), rng, 1.0), tau = random_vector(model.nv(), rng, 2.0);
  FloatingData<double> d(model);
  FloatingData<float> df(mf);
  ContactData<FloatingModel<double>> cd(model, {contact_6d(1), contact_3d(2)});
  ContactData<FloatingModel<float>> cf(mf, {contact_6d<float>(1), contact_3d<float>(2)});
  constrained_forward_dynamics(model, d, cd, q, v, tau);
  constrained_forward_dynamics(mf, df, cf, q.cast<float>(), v.cast<float>(), tau.cast<float>());
  EXPECT_LT(rel_err(cf.qdd.cast<double>(), cd.qdd), 1e-3);
  EXPECT_LT(rel_err(cf.lambda.cast<double>(), cd.lambda), 1e-3);
}

TEST(Contact, BadContactsAreRefusedByName) {
  const FloatingModel<double> model = random_floating_with_frames(5, Shape::Chain, 10);
  RigidContact<double> bad = contact_6d(7);
  bad.name = "left foot";
  try {
    ContactData<FloatingModel<double>> cd(model, {bad});
    FAIL() << "a frame index out of range was accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("contact 'left foot': frame index 7"), std::string::npos) << e.what();
  }
  try {
    ContactData<FloatingModel<double>> cd(model, {contact_3d(1), contact_3d(2, ReferenceFrame::World)});
    FAIL() << "a World reference was accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("contact #1 (frame 'frame_on_2')"), std::string::npos) << e.what();
  }
  // Unnamed contacts take their frame's name.
  ContactData<FloatingModel<double>> cd(model, {contact_3d(1)});
  EXPECT_EQ(cd.contacts[0].name, "frame_on_4");
}

// ---- whole-body inverse dynamics with contacts, ZMP and CoP ----------------------------------------------------

/// The HOAP-3's soles as 6D contacts with the data sheet's sole rectangle (108 × 73 mm; here centred on the sole
/// frame's origin, which is what the split needs to be checked against) and μ = 0.6, forces in world axes.
std::vector<RigidContact<double>> hoap3_feet(const FloatingModel<double>& rt, bool left = true, bool right = true) {
  std::vector<RigidContact<double>> feet;
  for (const char* name : {"L_SOLE", "R_SOLE"}) {
    if ((name[0] == 'L' && !left) || (name[0] == 'R' && !right)) continue;
    RigidContact<double> c = contact_6d(rt.frame_index(name), ReferenceFrame::Local);
    c.sole_x_min = -0.054, c.sole_x_max = 0.054, c.sole_y_min = -0.0365, c.sole_y_max = 0.0365;
    c.friction = 0.6;
    feet.push_back(c);
  }
  return feet;
}

/// A v̇ that respects the contacts at (q, v = 0): a random vector projected on the null space of J.
Vec consistent_acceleration(const Mat& J, std::mt19937& rng, double scale) {
  const Vec x = random_vector(static_cast<int>(J.cols()), rng, scale);
  Eigen::JacobiSVD<Mat> svd(J, Eigen::ComputeFullV);
  const Mat V = svd.matrixV();
  const int r = static_cast<int>(svd.rank());
  const Mat N = V.rightCols(J.cols() - r);
  return N * (N.transpose() * x);
}

/// Every contact force of cd (Local axes) inside its cone: f_z ≥ 0, |f_x|, |f_y| ≤ μ f_z, CoP inside the sole.
void expect_physical(const ContactData<FloatingModel<double>>& cd, double tol) {
  int r = 0;
  for (const auto& c : cd.contacts) {
    const auto w = cd.lambda.segment<6>(r);
    SCOPED_TRACE(c.name + " wrench " + ::testing::PrintToString(Vec(w).transpose()));
    EXPECT_GE(w[2], -tol);
    EXPECT_LE(std::abs(w[0]), c.friction * w[2] + tol);
    EXPECT_LE(std::abs(w[1]), c.friction * w[2] + tol);
    const double cop_x = -w[4] / w[2], cop_y = w[3] / w[2];
    EXPECT_GE(cop_x, c.sole_x_min - 1e-9);
    EXPECT_LE(cop_x, c.sole_x_max + 1e-9);
    EXPECT_GE(cop_y, c.sole_y_min - 1e-9);
    EXPECT_LE(cop_y, c.sole_y_max + 1e-9);
    r += 6;
  }
}

TEST(ContactInverseDynamics, Hoap3OnBothFeetRoundTripThroughForwardDynamics) {
  // Standing (q neutral: both soles flat at the same height), at rest, accelerations that keep the feet still:
  // the split must be physical, the root's wrench supplied exactly, and constrained forward dynamics with the
  // torques found must give back the same v̇ and the same contact forces (the KKT solution is unique).
  const auto rt = models::hoap3_floating::floating_model<double>().to_runtime();
  FloatingData<double> data(rt);
  ContactData<FloatingModel<double>> cd(rt, hoap3_feet(rt)), fd(rt, hoap3_feet(rt));
  const Vec q = neutral(rt), v = Vec::Zero(rt.nv());
  std::mt19937 rng(12);
  Mat J = Mat::Zero(12, rt.nv());
  int solved = 0;
  for (int k = 0; k < 20; ++k) {
    constrained_forward_dynamics(rt, data, fd, q, v, Vec::Zero(rt.nv()));  // only for J at q
    J = fd.J;
    const Vec a = consistent_acceleration(J, rng, k == 0 ? 0.0 : 0.3);
    contact_inverse_dynamics(rt, data, cd, q, v, a);
    if (!cd.ok) continue;  // a random acceleration may need a pulling foot
    ++solved;
    const double scale = rt.total_mass() * 9.81;
    EXPECT_LT(cd.tau.head<6>().norm(), 1e-10 * scale);
    expect_physical(cd, 1e-9 * scale);
    // RNEA = Sᵀτ + Jᵀλ.
    Vec st = cd.tau;
    st.head<6>().setZero();
    EXPECT_LT(rel_err(rnea(rt, data, q, v, a), st + J.transpose() * cd.lambda), 1e-12);
    // Round trip.
    constrained_forward_dynamics(rt, data, fd, q, v, st);
    EXPECT_LT(rel_err(fd.qdd, a), 1e-9);
    EXPECT_LT(rel_err(fd.lambda, cd.lambda), 1e-9);
    // The multibody ZMP is the CoP of the contact forces (ground plane at the soles' height).
    const double h = frame_pose(rt, data, rt.frame_index("L_SOLE")).translation().z();
    const Vector3<double> zmp = multibody_zmp(rt, data, q, v, a, h);
    EXPECT_LT((zmp - center_of_pressure(rt, data, cd, h)).norm(), 1e-12) << zmp.transpose();
  }
  EXPECT_GE(solved, 10);
}

TEST(ContactInverseDynamics, SymmetricStanceSplitsTheWeightEvenly) {
  // One rigid box (mass 2, CoM at the root origin) standing on two soles 0.2 m apart, 0.3 m below the CoM, at rest:
  // by symmetry each sole carries m g / 2 with its centre of pressure at its centre and no tangential force.
  ModelBuilder<double> b;
  b.add_fixed_body("left", -1, Transform<double>(Matrix3<double>::Identity(), Vector3<double>(0, 0.1, -0.3)),
                   Inertia<double>::Zero());
  b.add_fixed_body("right", -1, Transform<double>(Matrix3<double>::Identity(), Vector3<double>(0, -0.1, -0.3)),
                   Inertia<double>::Zero());
  const FloatingModel<double> box(b.build(), Inertia<double>::from_com(2.0, Vector3<double>::Zero(),
                                                                       Vector3<double>(0.02, 0.03, 0.04).asDiagonal()),
                                  "box");
  std::vector<RigidContact<double>> soles{contact_6d(0), contact_6d(1)};
  for (auto& c : soles) c.sole_x_min = -0.05, c.sole_x_max = 0.05, c.sole_y_min = -0.03, c.sole_y_max = 0.03;
  FloatingData<double> data(box);
  ContactData<FloatingModel<double>> cd(box, soles);
  const Vec q = neutral(box), zero = Vec::Zero(6);
  contact_inverse_dynamics(box, data, cd, q, zero, zero);
  ASSERT_TRUE(cd.ok);
  Vec half(6);
  half << 0, 0, 2.0 * 9.81 / 2, 0, 0, 0;
  EXPECT_LT((cd.lambda.head(6) - half).norm(), 1e-12) << cd.lambda.transpose();
  EXPECT_LT((cd.lambda.tail(6) - half).norm(), 1e-12) << cd.lambda.transpose();
  // The box accelerating sideways at 0.5 g: the ZMP moves 0.15 m towards the rear of the motion, beyond the
  // soles' outer edges (0.13 m) — no physical split exists.
  Vec a = Vec::Zero(6);
  a[1] = 0.5 * 9.81;
  contact_inverse_dynamics(box, data, cd, q, zero, a);
  EXPECT_FALSE(cd.ok);
  EXPECT_GT(cd.tau.head<6>().norm(), 1e-3);
  // At 0.3 g (ZMP 0.09 m off centre, inside the right sole) it exists again, and the left foot is nearly unloaded.
  a[1] = 0.3 * 9.81;
  contact_inverse_dynamics(box, data, cd, q, zero, a);
  ASSERT_TRUE(cd.ok);
  EXPECT_LT(cd.tau.head<6>().norm(), 1e-12);
  expect_physical(cd, 1e-12);
  EXPECT_LT((multibody_zmp(box, data, q, zero, a, -0.3) - center_of_pressure(box, data, cd, -0.3)).norm(), 1e-12);
}

TEST(Zmp, MultibodyZmpIsTheCopOfTheContactForcesInSingleAndDoubleSupport) {
  // Constrained forward dynamics on one foot and on both, from random states and torques: whatever the forces
  // (pulling or not), the ZMP of the motion computed by RNEA is the CoP of the contact forces.
  const auto rt = models::hoap3_floating::floating_model<double>().to_runtime();
  FloatingData<double> data(rt);
  std::mt19937 rng(13);
  const int n = rt.njoints();
  for (bool both : {false, true}) {
    int compared = 0;
    ContactData<FloatingModel<double>> cd(rt, hoap3_feet(rt, true, both));
    for (int k = 0; k < 5; ++k) {
      const Vec q = random_configuration(rt, Vec::Constant(n, -0.5), Vec::Constant(n, 0.5), rng);
      const Vec v = random_vector(rt.nv(), rng, 1.0);
      Vec tau = random_vector(rt.nv(), rng, 2.0);
      tau.head<6>().setZero();
      constrained_forward_dynamics(rt, data, cd, q, v, tau);
      const double h = frame_pose(rt, data, rt.frame_index("L_SOLE")).translation().z();
      const Vector3<double> cop = center_of_pressure(rt, data, cd, h);
      const Vector3<double> zmp = multibody_zmp(rt, data, q, v, cd.qdd, h);
      if (!std::isfinite(cop.x())) {  // the feet pull: neither point exists
        EXPECT_FALSE(std::isfinite(zmp.x()));
        continue;
      }
      EXPECT_LT((zmp - cop).norm(), 1e-10 * (1.0 + cop.norm())) << zmp.transpose() << " vs " << cop.transpose();
      ++compared;
    }
    EXPECT_GE(compared, 3) << (both ? "double" : "single") << " support";
  }
}

// ---- impacts of a falling box (analytic) ------------------------------------------------------------------------

/// A uniform box (mass 2, half sizes 0.1 × 0.15 × 0.05) with its root frame at the centre of mass, and frames at the
/// centre of its bottom face (0) and at a bottom corner (1).
FloatingModel<double> falling_box() {
  const double m = 2.0, a = 0.1, b = 0.15, c = 0.05;
  ModelBuilder<double> builder;
  builder.add_fixed_body("bottom", -1, Transform<double>(Matrix3<double>::Identity(), Vector3<double>(0, 0, -c)),
                         Inertia<double>::Zero());
  builder.add_fixed_body("corner", -1, Transform<double>(Matrix3<double>::Identity(), Vector3<double>(a, b, -c)),
                         Inertia<double>::Zero());
  const Vector3<double> I(m / 3 * (b * b + c * c), m / 3 * (a * a + c * c), m / 3 * (a * a + b * b));
  return FloatingModel<double>(builder.build(), Inertia<double>::from_com(m, Vector3<double>::Zero(), I.asDiagonal()),
                               "box");
}

TEST(Impulse, FallingBoxLandingFlatStopsDead) {
  // Translating down at 1 m/s onto its bottom face (a weld): everything stops, the impulse is m v up, no moment.
  const FloatingModel<double> box = falling_box();
  FloatingData<double> data(box);
  ContactData<FloatingModel<double>> cd(box, {contact_6d(0)});
  Vec v = Vec::Zero(6);
  v[2] = -1.0;
  const Vec q = neutral(box);
  impulse_dynamics(box, data, cd, q, v);
  EXPECT_LT(cd.v_after.norm(), 1e-15);
  Vec expected = Vec::Zero(6);
  expected[2] = 2.0;
  EXPECT_LT((cd.lambda - expected).norm(), 1e-14) << cd.lambda.transpose();
}

TEST(Impulse, FallingBoxLandingOnACornerMatchesTheTextbookFormula) {
  // A point impact at r from the centre of mass: the corner's velocity changes by K P with
  // K = (1/m) 1 − [r]× I⁻¹ [r]× (the inverse effective mass), so P = −(1 + e) K⁻¹ v_c⁻, then v⁺ = v⁻ + P / m and
  // ω⁺ = I⁻¹ (r × P).
  const FloatingModel<double> box = falling_box();
  const double m = 2.0;
  const Matrix3<double> I = box.root_inertia().I;  // about the root origin = the centre of mass
  const Vector3<double> r(0.1, 0.15, -0.05);
  const Matrix3<double> rx = skew(r);
  const Matrix3<double> K = Matrix3<double>::Identity() / m - rx * I.inverse() * rx;
  FloatingData<double> data(box);
  ContactData<FloatingModel<double>> cd(box, {contact_3d(1)});
  const Vec q = neutral(box);
  for (double e : {0.0, 0.5, 1.0}) {
    SCOPED_TRACE("restitution " + std::to_string(e));
    Vec v(6);
    v << 0.3, -0.2, -1.0, 0.0, 0.0, 0.0;  // translating, not turning
    const Vector3<double> vc = v.head<3>();
    const Vector3<double> P = -(1 + e) * K.inverse() * vc;
    const Vector3<double> v_after = vc + P / m, w_after = I.inverse() * r.cross(P);
    impulse_dynamics(box, data, cd, q, v, e);
    ASSERT_TRUE(cd.ok);
    EXPECT_LT((cd.lambda - P).norm(), 1e-13 * P.norm()) << cd.lambda.transpose() << " vs " << P.transpose();
    EXPECT_LT((cd.v_after.head<3>() - v_after).norm(), 1e-13);
    EXPECT_LT((cd.v_after.tail<3>() - w_after).norm(), 1e-12);
    // The corner: stopped (e = 0) or bouncing back.
    EXPECT_LT((v_after + w_after.cross(r) + e * vc).norm(), 1e-13);
    const double ke_before = 0.5 * m * vc.squaredNorm();
    const double ke_after = 0.5 * m * v_after.squaredNorm() + 0.5 * w_after.dot(I * w_after);
    if (e < 1) EXPECT_LT(ke_after, ke_before);
    else EXPECT_NEAR(ke_after, ke_before, 1e-13);
  }
}

}  // namespace
