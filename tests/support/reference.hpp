#pragma once
// Independent reference computations for the test suites (not part of the installed library).
//
// Nothing here uses the library's spatial algebra or algorithms: poses are composed with Eigen's own active
// rotations and isometries, velocities are finite differences of those poses, and the 6×6 matrices are written
// out element by element from Featherstone's formulas. Tests compare the library against these.

#include <spatial/spatial.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace spatial::testing {

/// The 3×3 cross-product matrix, written out (r × p = crossmat(r) p).
template <class S>
Matrix3<S> crossmat(const Vector3<S>& r) {
  Matrix3<S> m;
  m(0, 0) = S(0);     m(0, 1) = -r(2);    m(0, 2) = r(1);
  m(1, 0) = r(2);     m(1, 1) = S(0);     m(1, 2) = -r(0);
  m(2, 0) = -r(1);    m(2, 1) = r(0);     m(2, 2) = S(0);
  return m;
}

/// The 6×6 Plücker motion transform of X = rot(E) xlt(r) built as the product of its two factors
/// (RBDA eqs. 2.22–2.24): rot(E) = diag(E, E), xlt(r) = [1 0; −r̃ 1].
template <class S>
Matrix6<S> motion_transform_6x6(const Matrix3<S>& E, const Vector3<S>& r) {
  Matrix6<S> rot = Matrix6<S>::Zero();
  rot.template block<3, 3>(0, 0) = E;
  rot.template block<3, 3>(3, 3) = E;
  Matrix6<S> x = Matrix6<S>::Identity();
  x.template block<3, 3>(3, 0) = -crossmat(r);
  return rot * x;
}

/// The 6×6 spatial inertia of a body of mass m, centre of mass c and rotational inertia Ic about c
/// (RBDA eq. 2.63): [Ic + m c̃ c̃ᵀ, m c̃; m c̃ᵀ, m 1].
template <class S>
Matrix6<S> inertia_6x6(S m, const Vector3<S>& c, const Matrix3<S>& Ic) {
  const Matrix3<S> cx = crossmat(c);
  Matrix6<S> M;
  M.template block<3, 3>(0, 0) = Ic + m * cx * cx.transpose();
  M.template block<3, 3>(0, 3) = m * cx;
  M.template block<3, 3>(3, 0) = m * cx.transpose();
  M.template block<3, 3>(3, 3) = m * Matrix3<S>::Identity();
  return M;
}

template <class S>
using Isometry = Eigen::Transform<S, 3, Eigen::Isometry>;

/// Poses of every body in the base frame, composed with Eigen's active rotations from the raw model numbers:
/// pose_i = pose_λ(i) · placement(X_T(i)) · motion of joint i.  A passive X_T = (E, r) places the joint frame at
/// origin r with axes Eᵀ in the parent frame; a revolute joint rotates the body actively by q about its axis, a
/// prismatic joint translates it by q along its axis.
template <class S, class T>
std::vector<Isometry<S>> reference_poses(const Model<S, T>& model, const Eigen::Matrix<S, Eigen::Dynamic, 1>& q) {
  std::vector<Isometry<S>> pose(static_cast<std::size_t>(model.size()));
  for (int i = 0; i < model.size(); ++i) {
    const Transform<S>& Xt = model.tree_transform(i);
    Isometry<S> placement = Isometry<S>::Identity();
    placement.linear() = Xt.E.transpose();
    placement.translation() = Xt.r;
    Isometry<S> joint = Isometry<S>::Identity();
    const Vector3<S> axis = model.axis(i);
    if (is_revolute(model.joint_type(i)))
      joint.linear() = Eigen::AngleAxis<S>(q[i], axis).toRotationMatrix();
    else
      joint.translation() = axis * q[i];
    const int p = model.parent(i);
    const Isometry<S> parent = p >= 0 ? pose[static_cast<std::size_t>(p)] : Isometry<S>::Identity();
    pose[static_cast<std::size_t>(i)] = parent * placement * joint;
  }
  return pose;
}

/// Centre of mass of body i in base coordinates, from reference poses.
template <class S, class T>
Vector3<S> reference_body_com(const Model<S, T>& model, const std::vector<Isometry<S>>& pose, int i) {
  const Inertia<S>& I = model.inertia(i);
  return pose[static_cast<std::size_t>(i)] * Vector3<S>(I.h / I.m);
}

/// Kinetic energy Σ ½ m |ċ|² + ½ ωᵀ R Ic Rᵀ ω with ċ and ω from central differences (step h) of the reference
/// poses along q̇: independent of the library's velocity propagation. Assumes every body has positive mass.
template <class S, class T>
S reference_kinetic_energy(const Model<S, T>& model, const Eigen::Matrix<S, Eigen::Dynamic, 1>& q,
                           const Eigen::Matrix<S, Eigen::Dynamic, 1>& qd, S h) {
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  const Vec qp = q + h * qd, qm = q - h * qd;
  const auto P = reference_poses(model, qp), M = reference_poses(model, qm), P0 = reference_poses(model, q);
  S e = S(0);
  for (int i = 0; i < model.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const Inertia<S>& I = model.inertia(i);
    const Vector3<S> cdot = (reference_body_com(model, P, i) - reference_body_com(model, M, i)) / (S(2) * h);
    // Ṙ Rᵀ = ω̃ (angular velocity in base coordinates).
    const Matrix3<S> W = (P[k].linear() - M[k].linear()) / (S(2) * h) * P0[k].linear().transpose();
    const Vector3<S> w((W(2, 1) - W(1, 2)) / S(2), (W(0, 2) - W(2, 0)) / S(2), (W(1, 0) - W(0, 1)) / S(2));
    const Matrix3<S> R = P0[k].linear();
    const Matrix3<S> Ic = I.I - I.m * crossmat<S>(I.h / I.m) * crossmat<S>(I.h / I.m).transpose();
    e += S(0.5) * I.m * cdot.squaredNorm() + S(0.5) * w.dot(R * Ic * R.transpose() * w);
  }
  return e;
}

/// ‖a − b‖∞ / max(‖b‖∞, floor).
template <class A, class B>
double rel_diff(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b, double floor = 1e-300) {
  const double num = static_cast<double>((a.template cast<long double>() - b.template cast<long double>())
                                             .cwiseAbs()
                                             .maxCoeff());
  const double den = std::max(static_cast<double>(b.template cast<long double>().cwiseAbs().maxCoeff()), floor);
  return num / den;
}

/// ‖a − b‖∞.
template <class A, class B>
double abs_diff(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return static_cast<double>((a.template cast<long double>() - b.template cast<long double>()).cwiseAbs().maxCoeff());
}

}  // namespace spatial::testing
