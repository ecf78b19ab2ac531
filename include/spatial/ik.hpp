#pragma once
/// \file ik.hpp
/// Inverse kinematics: several weighted tasks at once (frame position, orientation, pose, centre of mass), solved
/// by damped least squares with adaptive (Levenberg–Marquardt) damping, on fixed-base (`Model`) and floating-base
/// (`FloatingModel`, on the configuration manifold) trees, compile-time and run-time. Joint limits are kept by
/// projection. `IkSolver` allocates its workspace once, when it is built; `solve` then neither allocates nor throws
/// and returns an `IkStatus`.
///
/// ## Tasks and their error conventions
/// Every task compares the current value x(q) with its target x* and contributes the error e = x* − x(q) — target
/// minus current — expressed in **world coordinates** (the base frame for a fixed base), times its weight:
///   - `ik_position(frame, p*)`       3 rows: e = p* − p(q), p the origin of fixed frame `frame`, world coordinates.
///   - `ik_orientation(frame, R*)`    3 rows: e = log(R* R(q)ᵀ), the rotation vector (axis × angle, |angle| ≤ π, world
///                                    axes) that turns the frame's current orientation R (frame axes → world axes)
///                                    into R*.
///   - `ik_pose(frame, p*, R*)`       6 rows, **linear first**: [p* − p; log(R* Rᵀ)], as the Jacobians of
///                                    kinematics.hpp (the LocalWorldAligned Jacobian is its derivative).
///   - `ik_center_of_mass(c*)`        3 rows: e = c* − c(q), the centre of mass in world coordinates; for a fixed base
///                                    over the moving bodies only (centroidal.hpp's convention: the base and the mass
///                                    merged into it do not move), for a floating base over the whole robot.
/// Frames are indices into `model.frames()` (floating: `model.tree().frames()`); frame −1 is not allowed, but any
/// body's origin can be given a frame with `ModelBuilder::add_fixed_body`. A task's `weight` multiplies all its
/// rows, `axes` (default all ones) each row separately: `axes = (0, 0, 1)` on a position task constrains the
/// height only. The solver minimises ½ ‖r‖², r = W e stacked over the tasks (W = weight × axes).
///
/// ## Method (Levenberg–Marquardt on the configuration manifold)
/// With the task Jacobian J (de/dv = −J; for the orientation rows J = J_r⁻¹(e) J_ω, J_r the right Jacobian of
/// SO(3), so that the linearisation is exact to first order at any error, not only near zero), each iteration
/// solves (Jᵀ W² J + μ 1) Δv = Jᵀ W r — in task space, Δv = Jᵀ W (W J Jᵀ W + μ 1)⁻¹ r, when there are fewer rows than
/// velocity coordinates — and tries q ⊕ Δv (`integrate` for a floating base: the free-flyer moves by the
/// exponential of the body twist, its quaternion stays unit). The step is accepted when it lowers ‖r‖; μ adapts
/// with the gain ratio ρ = actual / predicted decrease (Nielsen's rule: μ ← μ max(1/3, 1 − (2ρ − 1)³) after a
/// good step, μ ← μ ν, ν ← 2ν after a rejected one). `IkOptions::adaptive = false` keeps μ fixed: plain damped
/// least squares (every step taken).
///
/// ## Joint limits and locked coordinates
/// `IkOptions::lower` / `upper` (one entry per joint of the tree, not the free-flyer; ±∞ for none) are kept by
/// projection: the start is clamped into [lower, upper], every trial configuration is clamped, and a joint at a
/// bound whose gradient pushes it outwards is held there for that iteration (its column removed), so the limits are
/// never violated. `Model` stores no limits; the generated models of src/models carry `lower` and `upper` arrays
/// and the URDF loader `LoadedModel::joints[i].lower/upper` (`ik_limits` builds the vectors). `IkOptions::active`
/// lists the velocity coordinates the solver may move (empty: all); the others keep their values.

#include "spatial/centroidal.hpp"
#include "spatial/kinematics.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace spatial {

/// What an `IkTask` constrains (see the top of ik.hpp for each error convention).
enum class IkTaskKind {
  Position,      ///< 3 rows: p* − p, world coordinates
  Orientation,   ///< 3 rows: log(R* Rᵀ), world axes
  Pose,          ///< 6 rows, linear first: [p* − p; log(R* Rᵀ)]
  CenterOfMass,  ///< 3 rows: c* − c, world coordinates
};

/// One task: what, on which frame, its target and weights. Change the targets and weights between solves freely;
/// the kind and the frame are fixed when the solver is built.
template <class S>
struct IkTask {
  IkTaskKind kind = IkTaskKind::Pose;
  int frame = 0;                                  ///< fixed frame (index into the frames); unused for CoM
  Vector3<S> position = Vector3<S>::Zero();       ///< target p* or c* (world coordinates)
  Matrix3<S> rotation = Matrix3<S>::Identity();   ///< target R* (frame axes → world axes)
  S weight = S(1);                                ///< multiplies every row
  Vector6<S> axes = Vector6<S>::Ones();           ///< per-row factors (first rows() entries used; pose: linear first)

  int rows() const { return kind == IkTaskKind::Pose ? 6 : 3; }
};

/// Task constructors (the scalar is the target's; expressions are accepted).
template <class P>
IkTask<typename P::Scalar> ik_position(int frame, const Eigen::MatrixBase<P>& p,
                                       typename P::Scalar weight = typename P::Scalar(1)) {
  IkTask<typename P::Scalar> t;
  t.kind = IkTaskKind::Position, t.frame = frame, t.position = p, t.weight = weight;
  return t;
}
template <class R>
IkTask<typename R::Scalar> ik_orientation(int frame, const Eigen::MatrixBase<R>& rot,
                                          typename R::Scalar weight = typename R::Scalar(1)) {
  IkTask<typename R::Scalar> t;
  t.kind = IkTaskKind::Orientation, t.frame = frame, t.rotation = rot, t.weight = weight;
  return t;
}
template <class P, class R>
IkTask<typename P::Scalar> ik_pose(int frame, const Eigen::MatrixBase<P>& p, const Eigen::MatrixBase<R>& rot,
                                   typename P::Scalar weight = typename P::Scalar(1)) {
  IkTask<typename P::Scalar> t;
  t.kind = IkTaskKind::Pose, t.frame = frame, t.position = p, t.rotation = rot, t.weight = weight;
  return t;
}
template <class P>
IkTask<typename P::Scalar> ik_center_of_mass(const Eigen::MatrixBase<P>& c,
                                             typename P::Scalar weight = typename P::Scalar(1)) {
  IkTask<typename P::Scalar> t;
  t.kind = IkTaskKind::CenterOfMass, t.frame = -1, t.position = c, t.weight = weight;
  return t;
}

/// Solver settings.
template <class S>
struct IkOptions {
  int max_iterations = 200;         ///< iterations (linear solves) at most
  S tolerance = S(1e-12);           ///< converged when ‖r‖₂ ≤ tolerance (r: the weighted stacked error)
  S step_tolerance = S(1e-15);      ///< stalled when ‖Δv‖ ≤ step_tolerance (‖q‖ + step_tolerance)
  S damping = S(1e-6);              ///< μ: the initial (adaptive) or fixed damping, added to Jᵀ W² J's diagonal
  bool adaptive = true;             ///< adapt μ (Levenberg–Marquardt); false: fixed μ, every step taken
  Eigen::Matrix<S, Eigen::Dynamic, 1> lower, upper;  ///< joint limits (one per tree joint; empty: none; ±∞ allowed)
  std::vector<int> active;          ///< velocity coordinates that may move (empty: all)
};

/// Why `IkSolver::solve` stopped.
enum class IkReason {
  Converged,      ///< ‖r‖ ≤ tolerance
  MaxIterations,  ///< the iteration budget ran out
  Stalled,        ///< no step can lower ‖r‖ any more (a local minimum: typically an unreachable target)
  NonFinite,      ///< the start or the error is not finite (NaN/Inf in q or a target)
};

inline const char* ik_reason_name(IkReason r) {
  switch (r) {
    case IkReason::Converged: return "converged";
    case IkReason::MaxIterations: return "max_iterations";
    case IkReason::Stalled: return "stalled";
    case IkReason::NonFinite: return "non_finite";
  }
  return "?";
}

/// The outcome of `IkSolver::solve`.
template <class S>
struct IkStatus {
  bool converged = false;       ///< reason == Converged
  IkReason reason = IkReason::MaxIterations;
  int iterations = 0;           ///< linear solves done (accepted and rejected steps)
  int accepted = 0;             ///< steps taken
  S residual = S(0);            ///< ‖r‖₂ at the returned q (weighted stacked error)
  S damping = S(0);             ///< μ at the end
};

namespace detail {

/// log(R) as a rotation vector (angle in [0, π]), through the quaternion (accurate near 0 and π).
template <class S>
Vector3<S> so3_log(const Matrix3<S>& R) {
  using std::atan2;
  Eigen::Quaternion<S> qt(R);
  if (qt.w() < S(0)) qt.coeffs() = -qt.coeffs();
  const Vector3<S> v = qt.vec();
  const S s = v.norm();
  if (s < S(1e-8)) return v * (S(2) / qt.w());  // 2 atan(s / w) / s = 2 / w (1 − s² / 3w² + …)
  return v * (S(2) * atan2(s, qt.w()) / s);
}

/// J_r⁻¹(φ), the inverse of SO(3)'s right Jacobian: log(exp(φ) exp(δ)) = φ + J_r⁻¹(φ) δ + O(δ²).
template <class S>
Matrix3<S> so3_right_jacobian_inverse(const Vector3<S>& phi) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S th2 = phi.squaredNorm();
  const Matrix3<S> K = skew(phi);
  S c;
  if (th2 < S(1e-6)) {
    c = S(1) / S(12) + th2 / S(720);
  } else {
    const S th = sqrt(th2);
    const S sn = sin(th);
    // Near π the coefficient is unbounded; there the orientation error has no unique direction anyway.
    if (sn < S(1e-6)) return Matrix3<S>::Identity() + S(0.5) * K;
    c = S(1) / th2 - (S(1) + cos(th)) / (S(2) * th * sn);
  }
  return Matrix3<S>::Identity() + S(0.5) * K + c * (K * K);
}

}  // namespace detail

/// Joint-limit vectors (n entries) from per-joint arrays, e.g. a generated model's `lower` / `upper`.
template <class S = double, class A>
Eigen::Matrix<S, Eigen::Dynamic, 1> ik_limits(const A& values) {
  Eigen::Matrix<S, Eigen::Dynamic, 1> out(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (const auto& x : values) out[i++] = S(x);
  return out;
}

/// The inverse-kinematics solver of a model (`Model<S, T>` or `FloatingModel<S, T>`) for a fixed set of tasks.
/// Built once (allocates its workspace and its own `Data`; keeps a reference to the model, which must outlive it);
/// `solve(q)` then runs without heap allocation or exceptions. Not thread-safe: one solver per thread.
template <class ModelT>
class IkSolver {
 public:
  using Scalar = typename ModelT::Scalar;
  using S = Scalar;
  using Traits = detail::ModelTraits<ModelT>;
  using DataType = typename Traits::DataType;
  using VectorX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using MatrixX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;

  /// Throws `std::invalid_argument` for a frame that does not exist, limit vectors of the wrong size or lower >
  /// upper, or an active coordinate out of range (construction only: `solve` never throws).
  IkSolver(const ModelT& model, std::vector<IkTask<S>> tasks, IkOptions<S> options = {})
      : model_(model), data_(model), tasks_(std::move(tasks)), opt_(std::move(options)) {
    nq_ = Traits::nq(model);
    nv_ = Traits::nv(model);
    const int nj = Traits::tree(model).size();
    const int nframes = static_cast<int>(Traits::tree(model).frames().size());
    m_ = 0;
    for (const IkTask<S>& t : tasks_) {
      if (t.kind != IkTaskKind::CenterOfMass && (t.frame < 0 || t.frame >= nframes))
        throw std::invalid_argument("IkSolver: task frame " + std::to_string(t.frame) + " is not a frame of the model");
      m_ += t.rows();
    }
    if (opt_.lower.size() == 0) opt_.lower = VectorX::Constant(nj, -std::numeric_limits<S>::infinity());
    if (opt_.upper.size() == 0) opt_.upper = VectorX::Constant(nj, std::numeric_limits<S>::infinity());
    if (opt_.lower.size() != nj || opt_.upper.size() != nj)
      throw std::invalid_argument("IkSolver: joint limits need one entry per joint (" + std::to_string(nj) + ")");
    for (int j = 0; j < nj; ++j)
      if (!(opt_.lower[j] <= opt_.upper[j]))
        throw std::invalid_argument("IkSolver: joint " + std::to_string(j) + ": lower limit above the upper limit");
    free_ = VectorX::Constant(nv_, opt_.active.empty() ? S(1) : S(0));
    for (int c : opt_.active) {
      if (c < 0 || c >= nv_) throw std::invalid_argument("IkSolver: active coordinate " + std::to_string(c) + " out of range");
      free_[c] = S(1);
    }
    q_ = VectorX::Zero(nq_);
    qt_ = VectorX::Zero(nq_);
    dv_ = VectorX::Zero(nv_);
    g_ = VectorX::Zero(nv_);
    use_mask_ = VectorX::Zero(nv_);
    r_ = VectorX::Zero(m_);
    rt_ = VectorX::Zero(m_);
    pred_ = VectorX::Zero(m_);
    J_ = MatrixX::Zero(m_, nv_);
    J6_ = Eigen::Matrix<S, 6, Eigen::Dynamic>::Zero(6, nv_);
    Jc_ = Eigen::Matrix<S, 3, Eigen::Dynamic>::Zero(3, nv_);
    k_ = std::min(m_, nv_);
    A_ = MatrixX::Zero(k_, k_);
    y_ = VectorX::Zero(k_);
    ldlt_.compute(MatrixX::Identity(k_, k_));  // size its buffers
  }

  const ModelT& model() const { return model_; }
  int tasks() const { return static_cast<int>(tasks_.size()); }
  const IkTask<S>& task(int i) const { return tasks_[static_cast<std::size_t>(i)]; }
  /// Targets and weights of task i (its kind and frame are fixed).
  void set_target(int i, const Vector3<S>& p) { tasks_[static_cast<std::size_t>(i)].position = p; }
  void set_target(int i, const Matrix3<S>& R) { tasks_[static_cast<std::size_t>(i)].rotation = R; }
  void set_target(int i, const Vector3<S>& p, const Matrix3<S>& R) {
    tasks_[static_cast<std::size_t>(i)].position = p;
    tasks_[static_cast<std::size_t>(i)].rotation = R;
  }
  void set_weight(int i, S w) { tasks_[static_cast<std::size_t>(i)].weight = w; }
  void set_axes(int i, const Vector6<S>& axes) { tasks_[static_cast<std::size_t>(i)].axes = axes; }
  const IkOptions<S>& options() const { return opt_; }
  /// Settings that may change between solves (limits and active coordinates are fixed at construction).
  void set_max_iterations(int n) { opt_.max_iterations = n; }
  void set_tolerance(S tol) { opt_.tolerance = tol; }
  void set_damping(S mu, bool adaptive = true) { opt_.damping = mu, opt_.adaptive = adaptive; }
  /// Rows of the stacked error.
  int rows() const { return m_; }
  /// The weighted stacked error r = W e at the q of the last `solve` (or `residual(q)`), tasks in order.
  const VectorX& residual_vector() const { return r_; }
  /// The solver's own data (forward kinematics at the returned q after `solve`).
  const DataType& data() const { return data_; }

  /// ‖r‖₂ at q (fills `residual_vector()`); q is nq long. No allocation.
  template <class Q>
  S residual(const Eigen::MatrixBase<Q>& q) {
    q_ = q.template cast<S>();
    return std::sqrt(error(q_, r_));
  }

  /// Moves q (nq entries; floating: [x y z qx qy qz qw, joints]) towards the tasks' targets; q is read as the
  /// start (clamped into the limits) and written with the result (the last accepted configuration: inside the limits,
  /// with adaptive damping the lowest ‖r‖ found; also when not converged). No heap allocation, no exception.
  template <class Q>
  IkStatus<S> solve(const Eigen::MatrixBase<Q>& q_inout) {
    auto& qio = const_cast<Eigen::MatrixBase<Q>&>(q_inout);
    IkStatus<S> st;
    q_ = qio.template cast<S>();
    clamp(q_);
    using std::sqrt;
    S F = error(q_, r_);  // ‖r‖²
    S mu = opt_.damping;
    S nu = S(2);
    st.reason = IkReason::MaxIterations;
    for (;;) {
      if (!std::isfinite(F) || !q_.allFinite()) {
        st.reason = IkReason::NonFinite;
        break;
      }
      if (sqrt(F) <= opt_.tolerance) {
        st.reason = IkReason::Converged;
        break;
      }
      if (st.iterations >= opt_.max_iterations) break;
      // Linearise at q_ (only after a move: a rejected step keeps J and r).
      if (st.iterations == 0 || linearise_) {
        jacobian(q_);
        linearise_ = false;
      }
      ++st.iterations;
      solve_step(mu);
      // Trial point, projected into the limits; the step actually taken in the joints.
      Traits::integrate(model_, q_, dv_, qt_);
      clamp(qt_);
      for (int j = 0; j < nq_ - Traits::qoff; ++j) dv_[Traits::voff + j] = qt_[Traits::qoff + j] - q_[Traits::qoff + j];
      const S Ft = error(qt_, rt_);
      pred_.noalias() = r_ - J_ * dv_;
      const S predicted = F - pred_.squaredNorm();
      const bool better = std::isfinite(Ft) && Ft < F;
      if (!opt_.adaptive || (better && predicted > S(0))) {
        const S rho = predicted > S(0) ? (F - Ft) / predicted : S(0);
        q_.swap(qt_);
        r_.swap(rt_);
        F = Ft;
        ++st.accepted;
        linearise_ = true;
        if (opt_.adaptive) {
          const S t = S(2) * rho - S(1);
          mu *= std::max(S(1) / S(3), S(1) - t * t * t);
          nu = S(2);
        }
      } else {
        mu *= nu;
        nu *= S(2);
      }
      const S step = dv_.norm();
      if (step <= opt_.step_tolerance * (q_.norm() + opt_.step_tolerance) || !(mu < S(1e30))) {
        if (sqrt(F) <= opt_.tolerance) st.reason = IkReason::Converged;
        else st.reason = IkReason::Stalled;
        break;
      }
    }
    st.converged = st.reason == IkReason::Converged;
    st.residual = sqrt(F);
    st.damping = mu;
    // Leave data_ and r_ at the returned configuration.
    error(q_, r_);
    qio = q_.template cast<typename Q::Scalar>();
    return st;
  }

 private:
  /// Clamps the joints of q into [lower, upper].
  void clamp(VectorX& q) const {
    for (int j = 0; j < nq_ - Traits::qoff; ++j) {
      S& x = q[Traits::qoff + j];
      x = std::min(std::max(x, opt_.lower[j]), opt_.upper[j]);
    }
  }

  /// Pose of a task's frame after forward kinematics: p and R (frame axes → world axes).
  void frame_placement(int frame, Vector3<S>& p, Matrix3<S>& R) const {
    const auto pose = frame_pose(model_, data_, frame);
    p = pose.translation();
    R = pose.linear();
  }

  /// The weighted stacked error at q into r; returns ‖r‖².
  S error(const VectorX& q, VectorX& r) {
    forward_kinematics(model_, data_, q);
    int row = 0;
    bool com_done = false;
    Vector3<S> com = Vector3<S>::Zero();
    for (const IkTask<S>& t : tasks_) {
      Vector6<S> e = Vector6<S>::Zero();
      Vector3<S> p;
      Matrix3<S> R;
      switch (t.kind) {
        case IkTaskKind::Position:
          frame_placement(t.frame, p, R);
          e.template head<3>() = t.position - p;
          break;
        case IkTaskKind::Orientation:
          frame_placement(t.frame, p, R);
          e.template head<3>() = detail::so3_log<S>(t.rotation * R.transpose());
          break;
        case IkTaskKind::Pose:
          frame_placement(t.frame, p, R);
          e.template head<3>() = t.position - p;
          e.template tail<3>() = detail::so3_log<S>(t.rotation * R.transpose());
          break;
        case IkTaskKind::CenterOfMass:
          if (!com_done) {
            com = subtree_center_of_mass(model_, data_, q, -1).com;
            com_done = true;
          }
          e.template head<3>() = t.position - com;
          break;
      }
      const int n = t.rows();
      for (int k = 0; k < n; ++k) r[row + k] = t.weight * t.axes[k] * e[k];
      row += n;
    }
    return r.squaredNorm();
  }

  /// The weighted task Jacobian J_ (de = −J dv) at q; r_ must hold the error at q (for the orientation rows).
  void jacobian(const VectorX& q) {
    bool com_done = false;
    int row = 0;
    compute_joint_jacobians(model_, data_, q);
    for (const IkTask<S>& t : tasks_) {
      const int n = t.rows();
      if (t.kind == IkTaskKind::CenterOfMass) {
        if (!com_done) {
          com_jacobian(model_, data_, q, Jc_);
          com_done = true;
        }
        J_.middleRows(row, 3) = Jc_;
      } else {
        frame_jacobian(model_, data_, t.frame, ReferenceFrame::LocalWorldAligned, J6_);
        if (t.kind == IkTaskKind::Position) {
          J_.middleRows(row, 3) = J6_.template topRows<3>();
        } else {
          const int ro = t.kind == IkTaskKind::Pose ? 3 : 0;  // first orientation row of the task
          if (ro) J_.middleRows(row, 3) = J6_.template topRows<3>();
          // e = log(R* Rᵀ): de = −J_r⁻¹(e) ω dt with ω the frame's angular velocity (world axes).
          Vector3<S> e;
          for (int k = 0; k < 3; ++k) {
            const S w = t.weight * t.axes[ro + k];
            e[k] = w != S(0) ? r_[row + ro + k] / w : S(0);
          }
          // Rows with zero weight carry no error information; recompute the full error then.
          bool zero_weight = false;
          for (int k = 0; k < 3; ++k) zero_weight = zero_weight || t.weight * t.axes[ro + k] == S(0);
          if (zero_weight) {
            Vector3<S> p;
            Matrix3<S> R;
            frame_placement(t.frame, p, R);
            e = detail::so3_log<S>(t.rotation * R.transpose());
          }
          const Matrix3<S> Jinv = detail::so3_right_jacobian_inverse<S>(e);
          J_.middleRows(row + ro, 3).noalias() = Jinv * J6_.template bottomRows<3>();
        }
      }
      for (int k = 0; k < n; ++k) J_.row(row + k) *= t.weight * t.axes[k];
      row += n;
    }
  }

  /// Δv from the damped normal equations, with locked coordinates and joints held at their bounds removed.
  void solve_step(S mu) {
    use_mask_ = free_;
    g_.noalias() = J_.transpose() * r_;
    for (int j = 0; j < nq_ - Traits::qoff; ++j) {
      const int c = Traits::voff + j;
      const S x = q_[Traits::qoff + j];
      if ((x <= opt_.lower[j] && g_[c] < S(0)) || (x >= opt_.upper[j] && g_[c] > S(0))) use_mask_[c] = S(0);
    }
    for (int c = 0; c < nv_; ++c)
      if (use_mask_[c] == S(0)) J_.col(c).setZero();
    if (m_ < nv_) {
      // Task space: Δv = Jᵀ (J Jᵀ + μ 1)⁻¹ r.
      A_.noalias() = J_ * J_.transpose();
      A_.diagonal().array() += mu;
      ldlt_.compute(A_);
      y_ = r_;
      ldlt_.solveInPlace(y_);
      dv_.noalias() = J_.transpose() * y_;
    } else {
      A_.noalias() = J_.transpose() * J_;
      A_.diagonal().array() += mu;
      ldlt_.compute(A_);
      y_.noalias() = J_.transpose() * r_;
      ldlt_.solveInPlace(y_);
      dv_ = y_;
    }
    for (int c = 0; c < nv_; ++c)
      if (use_mask_[c] == S(0)) dv_[c] = S(0);
    if (!dv_.allFinite()) dv_.setZero();
  }

  const ModelT& model_;
  DataType data_;
  std::vector<IkTask<S>> tasks_;
  IkOptions<S> opt_;
  int nq_ = 0, nv_ = 0, m_ = 0, k_ = 0;
  bool linearise_ = true;
  VectorX q_, qt_, dv_, g_, free_, use_mask_, r_, rt_, pred_, y_;
  MatrixX J_, A_;
  Eigen::Matrix<S, 6, Eigen::Dynamic> J6_;
  Eigen::Matrix<S, 3, Eigen::Dynamic> Jc_;
  Eigen::LDLT<MatrixX> ldlt_;
};

}  // namespace spatial
