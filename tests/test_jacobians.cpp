// Jacobians, frame velocities and accelerations and their time variation (kinematics.hpp), on random trees of every
// joint type (fixed base and floating base, with frames on bodies and on the base) and on the compile-time HOAP-3
// stance tree.
//
// Independent references:
//  - velocities: `forward_velocities` (fixed base; body coordinates) carried into each reference frame with the 6×6
//    matrices of reference.hpp, and central differences of world poses along q ⊕ v t (fixed and floating base);
//  - Jacobians: column c by central differences of the frame's pose along q ⊕ h e_c (`integrate` on the manifold);
//  - J̇: central differences of J along q ⊕ v t; J̇ q̇ (spatial and classical) and the accelerations of
//    forward_kinematics(q, v, a): central differences of the frame velocity along the trajectory;
//  - the three reference frames against each other by 6×6 transforms of the frame's pose, the one-walk Jacobians
//    against the all-joints ones, compile-time trees against run-time trees.
// Tolerances: 1e-12 relative (norm-wise, to max(‖ref‖, 1)) between exact formulas (rounding only, a few ε per
// transform on trees up to 30 deep). Central differences with step h have truncation error ~h² ‖f'''‖ and rounding
// ~ε ‖f‖ / h: pose differences at h = 1e-6 → ~1e-12 + 2e-10, bound 1e-8; J differences at h = 1e-5 (J is an
// O(1) function, its third derivative O(10) on these trees) → ~1e-9 + 2e-11, bound 1e-7. The worst errors seen are
// printed at the end.

#include <spatial/floating.hpp>
#include <spatial/kinematics.hpp>
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include "support/random_model.hpp"
#include "support/reference.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
using spatial::testing::Shape;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;
using V3 = Vector3<double>;
using M3 = Matrix3<double>;
using V6 = Vector6<double>;
using Iso = Eigen::Transform<double, 3, Eigen::Isometry>;
using spatial::testing::crossmat;

constexpr ReferenceFrame kFrames[] = {ReferenceFrame::Local, ReferenceFrame::World,
                                      ReferenceFrame::LocalWorldAligned};
const char* rf_name(ReferenceFrame rf) {
  return rf == ReferenceFrame::Local ? "Local" : rf == ReferenceFrame::World ? "World" : "LWA";
}

// ---- worst errors, printed at the end ------------------------------------------------------------------------
std::map<std::string, double>& worst() {
  static std::map<std::string, double> w;
  return w;
}
class ReportWorst : public ::testing::Environment {
 public:
  void TearDown() override {
    std::printf("\nJacobian tests, largest relative errors:\n");
    for (const auto& [k, v] : worst()) std::printf("  %-36s %10.3e\n", k.c_str(), v);
  }
};
const auto* const kReport = ::testing::AddGlobalTestEnvironment(new ReportWorst);

/// ‖a − b‖ / max(‖b‖, 1), recorded under `what`.
double err(const std::string& what, const Mat& a, const Mat& b) {
  const double e = (a - b).norm() / std::max(b.norm(), 1.0);
  double& w = worst()[what];
  w = std::max(w, e);
  return e;
}

/// A spatial vector with the linear part first (Jacobian row order).
V6 lin_first(const Motion<double>& m) {
  V6 out;
  out << m.v, m.w;
  return out;
}
V3 vee(const M3& W) { return V3(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1)) / 2; }

/// The three reference-frame velocities (linear first) of a frame whose world pose is `pose(t)`, by central
/// differences at ±h: LWA = [ṗ; ω], Local = [Rᵀṗ; Rᵀω], World = [ṗ − ω × p; ω].
struct FdVel {
  V6 local, world, lwa;
  const V6& in(ReferenceFrame rf) const {
    return rf == ReferenceFrame::Local ? local : rf == ReferenceFrame::World ? world : lwa;
  }
};
FdVel fd_velocity(const Iso& P0, const Iso& Pp, const Iso& Pm, double h) {
  const V3 pd = (Pp.translation() - Pm.translation()) / (2 * h);
  const M3 Rd = (Pp.linear() - Pm.linear()) / (2 * h);
  const M3 R = P0.linear();
  const V3 w = vee(Rd * R.transpose());
  FdVel out;
  out.lwa << pd, w;
  out.local << R.transpose() * pd, R.transpose() * w;
  out.world << pd - w.cross(P0.translation()), w;
  return out;
}

/// 6×6 (linear first) map from World to the frame's reference frame, given its pose P (independent of the
/// library's Transform: from reference.hpp's motion_transform_6x6 with E = Rᵀ, r = p).
Mat world_to(ReferenceFrame rf, const Iso& P) {
  Matrix6<double> X = Matrix6<double>::Identity();  // angular first
  const M3 R = P.linear();
  const V3 p = P.translation();
  if (rf == ReferenceFrame::Local) X = spatial::testing::motion_transform_6x6<double>(R.transpose(), p);
  if (rf == ReferenceFrame::LocalWorldAligned) X = spatial::testing::motion_transform_6x6<double>(M3::Identity(), p);
  Matrix6<double> swap = Matrix6<double>::Zero();  // angular first <-> linear first
  swap.block<3, 3>(0, 3).setIdentity();
  swap.block<3, 3>(3, 0).setIdentity();
  return swap * X * swap;
}

// ---- the models: fixed and floating, run-time and compile-time, behind one interface ---------------------------

/// Random bodies as a model with frames: one on the base, one on the last body, one on a middle body.
Model<double> random_model_with_frames(int n, Shape shape, unsigned seed) {
  const auto bodies = spatial::testing::random_bodies(n, shape, seed);
  ModelBuilder<double> b;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const auto& r = bodies[i];
    b.add_body("body" + std::to_string(i), r.parent, r.type, r.X_tree,
               Inertia<double>::from_com(r.mass, r.com, r.inertia_com), r.axis, "joint" + std::to_string(i));
  }
  std::mt19937 rng(seed + 77);
  const Inertia<double> small = Inertia<double>::from_com(0.1, V3::Zero(), 1e-4 * M3::Identity());
  for (int body : {-1, n - 1, n / 2}) {
    // Sequenced draws, in GCC's order (random_model.hpp, draw3): the offset, then the rotation.
    const Eigen::VectorXd r = spatial::testing::random_vector(3, rng, 0.4);
    b.add_fixed_body("frame_on_" + std::to_string(body), body,
                     Transform<double>(spatial::testing::random_rotation(rng), r), small);
  }
  return b.build();
}

using spatial::testing::random_root_inertia;

template <class S, class T>
int n_bodies(const Model<S, T>& m) { return m.size(); }
template <class S, class T>
int n_bodies(const FloatingModel<S, T>& m) { return m.njoints(); }
template <class S, class T>
int n_frames(const Model<S, T>& m) { return static_cast<int>(m.frames().size()); }
template <class S, class T>
int n_frames(const FloatingModel<S, T>& m) { return static_cast<int>(m.tree().frames().size()); }
template <class S, class T>
int nv(const Model<S, T>& m) { return m.size(); }
template <class S, class T>
int nv(const FloatingModel<S, T>& m) { return m.nv(); }

template <class T>
Vec random_config(const Model<double, T>& m, std::mt19937& rng) { return spatial::testing::random_vector(m.size(), rng, 2.0); }
template <class T>
Vec random_config(const FloatingModel<double, T>& m, std::mt19937& rng) {
  const Vec lo = Vec::Constant(m.njoints(), -2.0), hi = Vec::Constant(m.njoints(), 2.0);
  return random_configuration(m, lo, hi, rng);
}
/// q ⊕ dv.
template <class T>
Vec step(const Model<double, T>&, const Vec& q, const Vec& dv) { return q + dv; }
template <class T>
Vec step(const FloatingModel<double, T>& m, const Vec& q, const Vec& dv) { return integrate(m, q, dv); }

/// World pose of a target: body b (−1: base/root) when `frame` is false, else frame b; after forward_kinematics.
template <class T>
Iso pose(const Model<double, T>& m, const Data<double, T>& d, bool frame, int b) {
  if (frame) return frame_pose(m, d, b);
  return b >= 0 ? body_pose(d, b) : Iso::Identity();
}
template <class T>
Iso pose(const FloatingModel<double, T>& m, const FloatingData<double, T>& d, bool frame, int b) {
  return frame ? frame_pose(m, d, b) : body_pose(m, d, b);
}

template <class M, class D>
Iso pose_at(const M& m, D& d, const Vec& q, bool frame, int b) {
  forward_kinematics(m, d, q);
  return pose(m, d, frame, b);
}

/// A 6 × n output filled with NaN: every entry the functions under test leave unwritten (a column that should be
/// zero, not only left alone) fails the comparisons below.
Mat not_written(int n) { return Mat::Constant(6, n, std::numeric_limits<double>::quiet_NaN()); }

template <class M, class D>
Mat jacobian(const M& m, const D& d, bool frame, int b, ReferenceFrame rf) {
  Mat J = not_written(nv(m));
  if (frame) frame_jacobian(m, d, b, rf, J);
  else body_jacobian(m, d, b, rf, J);
  return J;
}
template <class M, class D>
Mat jacobian_dot(const M& m, const D& d, bool frame, int b, ReferenceFrame rf) {
  Mat J = not_written(nv(m));
  if (frame) frame_jacobian_time_variation(m, d, b, rf, J);
  else body_jacobian_time_variation(m, d, b, rf, J);
  return J;
}
template <class M, class D>
Motion<double> velocity(const M& m, const D& d, bool frame, int b, ReferenceFrame rf) {
  return frame ? frame_velocity(m, d, b, rf) : body_velocity(m, d, b, rf);
}
template <class M, class D>
Motion<double> acceleration(const M& m, const D& d, bool frame, int b, ReferenceFrame rf) {
  return frame ? frame_acceleration(m, d, b, rf) : body_acceleration(m, d, b, rf);
}

/// Every check of this file on one model: all bodies (base/root included) and frames, `states` random states.
template <class M, class D>
void check_model(const M& m, D& d, unsigned seed, int states, const std::string& where) {
  std::mt19937 rng(seed);
  const int n = nv(m);
  const Vec zero = Vec::Zero(n);
  for (int s = 0; s < states; ++s) {
    const Vec q = random_config(m, rng);
    const Vec v = spatial::testing::random_vector(n, rng, 1.5);
    const Vec a = spatial::testing::random_vector(n, rng, 2.0);
    std::vector<std::pair<bool, int>> targets;
    for (int b = -1; b < n_bodies(m); ++b) targets.push_back({false, b});
    for (int f = 0; f < n_frames(m); ++f) targets.push_back({true, f});
    for (const auto& target : targets) {
      // Named copies, not a structured binding: lambdas below capture them (C++17 lets no lambda capture a binding).
      const bool is_frame = target.first;
      const int b = target.second;
      const std::string at = where + (is_frame ? " frame " : " body ") + std::to_string(b) + " state " + std::to_string(s);
      // Poses along q ⊕ v t, and the reference velocities.
      const double hp = 1e-6;
      const Iso P0 = pose_at(m, d, q, is_frame, b);
      const FdVel fv = fd_velocity(P0, pose_at(m, d, step(m, q, Vec(hp * v)), is_frame, b),
                                   pose_at(m, d, step(m, q, Vec(-hp * v)), is_frame, b), hp);
      // J and the reference frames.
      compute_joint_jacobians(m, d, q);
      Mat Jrf[3];
      for (int r = 0; r < 3; ++r) Jrf[r] = jacobian(m, d, is_frame, b, kFrames[r]);
      for (int r = 0; r < 3; ++r) {
        const ReferenceFrame rf = kFrames[r];
        const std::string tag = std::string(rf_name(rf));
        // Consistency: J(rf) = X(rf) J(World) with X from the pose.
        EXPECT_LT(err("frames_consistent", Jrf[r], world_to(rf, P0) * Jrf[1]), 1e-12) << at << " " << tag;
        // One walk = all joints then select.
        Mat Jw = not_written(n);
        if (is_frame) compute_frame_jacobian(m, d, q, b, rf, Jw);
        else compute_body_jacobian(m, d, q, b, rf, Jw);
        EXPECT_LT(err("compute_vs_from_joint_jacobians", Jw, Jrf[r]), 1e-12) << at << " " << tag;
        // J v = velocity (finite differences of poses).
        EXPECT_LT(err("Jv_vs_fd_pose", Jrf[r] * v, fv.in(rf)), 1e-8) << at << " " << tag;
      }
      // Columns of J by central differences of the pose along q ⊕ h e_c (LWA; the other frames follow above).
      for (int c = 0; c < n; ++c) {
        Vec e = Vec::Zero(n);
        e[c] = hp;
        const FdVel col = fd_velocity(P0, pose_at(m, d, step(m, q, e), is_frame, b),
                                      pose_at(m, d, step(m, q, Vec(-e)), is_frame, b), hp);
        for (int r = 0; r < 3; ++r)
          EXPECT_LT(err("J_column_vs_fd_pose", Jrf[r].col(c), col.in(kFrames[r])), 1e-8) << at << " col " << c;
      }
      // Velocities after forward_kinematics(q, v, a): J v.
      forward_kinematics(m, d, q, v, a);
      for (int r = 0; r < 3; ++r)
        EXPECT_LT(err("velocity_vs_Jv", lin_first(velocity(m, d, is_frame, b, kFrames[r])), Jrf[r] * v), 1e-12) << at;
      // Accelerations: central differences of the velocity along q(t) = q ⊕ (v t + ½ a t²), v(t) = v + a t
      // (second-order accurate on the free-flyer's group), and at a = 0 the drift terms.
      const double hv = 1e-5;
      auto vel_at = [&](const Vec& qq, const Vec& vv, ReferenceFrame rf) {
        forward_kinematics(m, d, qq, vv, zero);
        return lin_first(velocity(m, d, is_frame, b, rf));
      };
      const Vec qp = step(m, q, Vec(hv * v + 0.5 * hv * hv * a)), qm = step(m, q, Vec(-hv * v + 0.5 * hv * hv * a));
      const Vec q0p = step(m, q, Vec(hv * v)), q0m = step(m, q, Vec(-hv * v));
      for (int r = 0; r < 3; ++r) {
        const ReferenceFrame rf = kFrames[r];
        const V6 dv_fd = (vel_at(qp, v + hv * a, rf) - vel_at(qm, v - hv * a, rf)) / (2 * hv);
        const V6 drift_fd = (vel_at(q0p, v, rf) - vel_at(q0m, v, rf)) / (2 * hv);
        forward_kinematics(m, d, q, v, a);
        const Motion<double> acc = acceleration(m, d, is_frame, b, rf);
        Vector3<double> classical = V3::Zero(), classical0 = V3::Zero();
        Motion<double> drift = Motion<double>::Zero();
        if (is_frame) {
          classical = frame_classical_acceleration(m, d, b, rf);
          drift = frame_jdot_qdot(m, d, q, v, b, rf);
          classical0 = frame_classical_jdot_qdot(m, d, q, v, b, rf);
        } else {
          classical = body_classical_acceleration(m, d, b, rf);
          forward_kinematics(m, d, q, v, zero);
          drift = acceleration(m, d, false, b, rf);
          classical0 = body_classical_acceleration(m, d, b, rf);
        }
        // d/dt of the rf velocity: the spatial acceleration for Local and World, [p̈; R ω̇] for LWA.
        if (rf == ReferenceFrame::LocalWorldAligned) {
          V6 expect, expect0;
          expect << classical, acc.w;
          expect0 << classical0, drift.w;
          EXPECT_LT(err("accel_vs_fd_velocity", expect, dv_fd), 1e-7) << at << " " << rf_name(rf);
          EXPECT_LT(err("jdot_qdot_vs_fd_velocity", expect0, drift_fd), 1e-7) << at << " " << rf_name(rf);
          // Spatial LWA = rotated Local: linear part p̈ − ω × ṗ.
          const Motion<double> vl = velocity(m, d, is_frame, b, rf);
          EXPECT_LT(err("spatial_vs_classical", acc.v, V3(classical - vl.w.cross(vl.v))), 1e-12) << at;
        } else {
          EXPECT_LT(err("accel_vs_fd_velocity", lin_first(acc), dv_fd), 1e-7) << at << " " << rf_name(rf);
          EXPECT_LT(err("jdot_qdot_vs_fd_velocity", lin_first(drift), drift_fd), 1e-7) << at << " " << rf_name(rf);
        }
        if (rf == ReferenceFrame::Local) {
          forward_kinematics(m, d, q, v, a);
          const Motion<double> vl = velocity(m, d, is_frame, b, rf);
          EXPECT_LT(err("spatial_vs_classical", classical, V3(acc.v + vl.w.cross(vl.v))), 1e-12) << at;
        }
      }
      // J̇ against central differences of J along q ⊕ v t; J̇ v against the drift.
      auto J_at = [&](const Vec& qq, ReferenceFrame rf) {
        compute_joint_jacobians(m, d, qq);
        return jacobian(m, d, is_frame, b, rf);
      };
      compute_joint_jacobians_time_variation(m, d, q, v);
      for (int r = 0; r < 3; ++r) {
        const ReferenceFrame rf = kFrames[r];
        const Mat dJ = jacobian_dot(m, d, is_frame, b, rf);
        const Mat dJ_fd = (J_at(q0p, rf) - J_at(q0m, rf)) / (2 * hv);
        EXPECT_LT(err("Jdot_vs_fd_J", dJ, dJ_fd), 1e-7) << at << " " << rf_name(rf);
        // J̇ v: spatial drift for Local and World, [classical; R ω̇] for LWA.
        const Motion<double> drift =
            is_frame ? frame_jdot_qdot(m, d, q, v, b, rf) : (forward_kinematics(m, d, q, v, zero), acceleration(m, d, false, b, rf));
        V6 expect = lin_first(drift);
        if (rf == ReferenceFrame::LocalWorldAligned)
          expect.head<3>() = is_frame ? frame_classical_jdot_qdot(m, d, q, v, b, rf)
                                      : (forward_kinematics(m, d, q, v, zero), body_classical_acceleration(m, d, b, rf));
        EXPECT_LT(err("Jdot_v_vs_jdot_qdot", dJ * v, expect), 1e-12) << at << " " << rf_name(rf);
        compute_joint_jacobians_time_variation(m, d, q, v);
      }
    }
  }
}

struct Case {
  int n;
  Shape shape;
  unsigned seed;
};
const Case kCases[] = {{1, Shape::Chain, 1}, {4, Shape::Chain, 2}, {9, Shape::Branched, 3}, {14, Shape::Branched, 4}};

TEST(Jacobians, FixedBaseRandomTrees) {
  for (const Case& c : kCases) {
    const Model<double> m = random_model_with_frames(c.n, c.shape, c.seed);
    Data<double> d(m);
    check_model(m, d, c.seed, 2, "fixed n=" + std::to_string(c.n));
  }
}

TEST(Jacobians, FloatingBaseRandomTrees) {
  for (const Case& c : kCases) {
    std::mt19937 rng(c.seed + 1000);
    const FloatingModel<double> m(random_model_with_frames(c.n, c.shape, c.seed), random_root_inertia(rng));
    FloatingData<double> d(m);
    check_model(m, d, c.seed, 2, "floating n=" + std::to_string(c.n));
  }
}

namespace stance = spatial::models::hoap3_stance_right;
using CTModel = Model<double, stance::Tree>;
using CTFloating = FloatingModel<double, stance::Tree>;

TEST(Jacobians, Hoap3CompileTimeFixedAndFloating) {
  const CTModel m = stance::model();
  Data<double, stance::Tree> d(m);
  check_model(m, d, 21, 1, "hoap3 fixed");
  const CTFloating fm(m, stance::base_inertia<double>(), "R_SOLE");
  FloatingData<double, stance::Tree> fd(fm);
  check_model(fm, fd, 22, 1, "hoap3 floating");
}

/// Fixed-velocity-size results of the compile-time tree equal the run-time tree's.
TEST(Jacobians, CompileTimeTreeMatchesRunTimeTree) {
  const CTModel ct = stance::model();
  ModelBuilder<double> b;
  b.set_gravity(ct.gravity());
  for (int i = 0; i < ct.size(); ++i)
    b.add_body(ct.body_name(i), ct.parent(i), ct.joint_type(i), ct.tree_transform(i), ct.inertia(i), ct.axis(i),
               ct.joint_name(i));
  for (const auto& f : ct.frames()) b.add_fixed_body(f.name, f.body, f.X, Inertia<double>::Zero());
  const Model<double> rt = b.build();
  const CTFloating fct(ct, stance::base_inertia<double>(), "R_SOLE");
  const FloatingModel<double> frt(rt, stance::base_inertia<double>(), "R_SOLE");
  Data<double, stance::Tree> cd(ct);
  Data<double> rd(rt);
  FloatingData<double, stance::Tree> fcd(fct);
  FloatingData<double> frd(frt);
  static_assert(decltype(cd.J)::ColsAtCompileTime == stance::dof, "fixed-size Jacobians");
  static_assert(decltype(fcd.J)::ColsAtCompileTime == stance::dof + 6, "fixed-size Jacobians");
  std::mt19937 rng(5);
  for (int t = 0; t < 5; ++t) {
    const Vec q = spatial::testing::random_vector(stance::dof, rng), v = spatial::testing::random_vector(stance::dof, rng);
    const Eigen::Matrix<double, stance::dof, 1> qs = q, vs = v;
    EXPECT_LT(err("compile_time_vs_run_time", Mat(compute_joint_jacobians_time_variation(ct, cd, qs, vs)),
                  Mat(compute_joint_jacobians_time_variation(rt, rd, q, v))), 1e-13);
    EXPECT_LT(err("compile_time_vs_run_time", Mat(cd.J), Mat(rd.J)), 1e-13);
    const Vec fq = random_config(frt, rng), fv = spatial::testing::random_vector(frt.nv(), rng);
    const Eigen::Matrix<double, CTFloating::NQ, 1> fqs = fq;
    const Eigen::Matrix<double, CTFloating::NV, 1> fvs = fv;
    EXPECT_LT(err("compile_time_vs_run_time", Mat(compute_joint_jacobians_time_variation(fct, fcd, fqs, fvs)),
                  Mat(compute_joint_jacobians_time_variation(frt, frd, fq, fv))), 1e-13);
    EXPECT_LT(err("compile_time_vs_run_time", Mat(fcd.J), Mat(frd.J)), 1e-13);
    for (int f = 0; f < static_cast<int>(ct.frames().size()); ++f)
      for (ReferenceFrame rf : kFrames) {
        Eigen::Matrix<double, 6, stance::dof> Jc;
        Mat Jr(6, stance::dof);
        compute_frame_jacobian(ct, cd, qs, f, rf, Jc);
        compute_frame_jacobian(rt, rd, q, f, rf, Jr);
        EXPECT_LT(err("compile_time_vs_run_time", Mat(Jc), Jr), 1e-13);
        EXPECT_LT(err("compile_time_vs_run_time", lin_first(frame_jdot_qdot(fct, fcd, fqs, fvs, f, rf)),
                      lin_first(frame_jdot_qdot(frt, frd, fq, fv, f, rf))), 1e-13);
      }
  }
}

/// Hand-checked geometry: a planar two-link arm (revolute z, links along x of lengths 1 and 0.5).
TEST(Jacobians, TwoLinkArmClosedForm) {
  ModelBuilder<double> b;
  const Inertia<double> I = Inertia<double>::from_com(1.0, V3(0.5, 0, 0), 0.01 * M3::Identity());
  b.add_body("l1", -1, JointType::RevoluteZ, Transform<double>::Identity(), I);
  b.add_body("l2", 0, JointType::RevoluteZ, xlt(V3(1, 0, 0)), I);
  b.add_fixed_body("tip", 1, xlt(V3(0.5, 0, 0)), Inertia<double>::Zero());
  const Model<double> m = b.build();
  Data<double> d(m);
  const double q1 = 0.3, q2 = -0.7;
  const Vec q = (Vec(2) << q1, q2).finished();
  compute_joint_jacobians(m, d, q);
  Mat J(6, 2);
  frame_jacobian(m, d, 0, ReferenceFrame::LocalWorldAligned, J);
  Mat expect = Mat::Zero(6, 2);
  expect(0, 0) = -std::sin(q1) - 0.5 * std::sin(q1 + q2);
  expect(1, 0) = std::cos(q1) + 0.5 * std::cos(q1 + q2);
  expect(0, 1) = -0.5 * std::sin(q1 + q2);
  expect(1, 1) = 0.5 * std::cos(q1 + q2);
  expect(5, 0) = expect(5, 1) = 1;
  EXPECT_LT(err("closed_form", J, expect), 1e-15);
  // World: the point at the world origin; joint 1's axis passes through it, joint 2's through (cos q1, sin q1).
  frame_jacobian(m, d, 0, ReferenceFrame::World, J);
  expect.setZero();
  expect(0, 1) = std::sin(q1);
  expect(1, 1) = -std::cos(q1);
  expect(5, 0) = expect(5, 1) = 1;
  EXPECT_LT(err("closed_form", J, expect), 1e-15);
  // Classical drift of the tip at q̇ = (1, 0): centripetal, −|ω|² p towards the origin.
  const Vec v = (Vec(2) << 1.0, 0.0).finished();
  const V3 p = frame_pose(m, d, 0).translation();
  EXPECT_LT(err("closed_form", frame_classical_jdot_qdot(m, d, q, v, 0, ReferenceFrame::LocalWorldAligned), V3(-p)),
            1e-15);
}

}  // namespace
