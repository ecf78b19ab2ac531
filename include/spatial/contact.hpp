#pragma once
/// \file contact.hpp
/// Rigid contacts: constrained forward dynamics and impulse dynamics of a tree (floating base or fixed base) whose
/// frames are held by the environment.
///
/// ## Contacts
/// A `RigidContact` holds one frame of the model (an index into `frames()`; floating: `tree().frames()`):
///   - `ContactType::Contact6D` (a flat foot on the ground, a weld): the frame's whole spatial velocity is zero;
///     6 constraint rows, **linear first**, in the frame's own axes: the rows of `frame_jacobian(Local)`.
///   - `ContactType::Contact3D` (a point contact): the velocity of the frame's origin is zero; 3 rows, world axes:
///     the linear rows of `frame_jacobian(LocalWorldAligned)`.
/// The constraint force λ of a contact is what the environment applies to the robot, at the frame's origin:
/// 6D: [force; moment about the frame's origin] (linear first), 3D: the force. It is reported in
/// `ReferenceFrame::Local` (the frame's axes) or `ReferenceFrame::LocalWorldAligned` (world axes), the contact's
/// `reference` (World, the moment about the world origin, is not offered). Pinocchio's `RigidConstraintModel`
/// (CONTACT_6D / CONTACT_3D, LOCAL / LOCAL_WORLD_ALIGNED, `data.lambda_c`) uses the same convention; MuJoCo's
/// `efc_force` are per-constraint-row scalars in its own contact frames instead.
///
/// ## Acceleration constraints and Baumgarte stabilisation
/// With J the stacked rows above and J̇ q̇ their drift (6D: the frame's **spatial** acceleration at v̇ = 0 in Local,
/// `frame_jdot_qdot(Local)`; 3D: the **classical** acceleration of its origin at v̇ = 0 in world axes,
/// `frame_classical_jdot_qdot(LocalWorldAligned)`), the dynamics with contacts are
///     H v̇ + C(q, v) = τ + Jᵀ λ,        J v̇ + J̇ q̇ = a*,
///     a* = −K_d (J v) − K_p e
/// (Baumgarte stabilisation, RBDA §8.3; per contact `kp`, `kd`, default 0 = the pure acceleration constraint). The
/// position error e is measured against the contact's `target` (a world pose, `set_contact_targets` takes the
/// current one): 3D: e = p − p* (world axes); 6D: e = [Rᵀ (p − p*); log(R*ᵀ R)] (frame axes, linear first). With
/// ω_n² = K_p and K_d = 2 ω_n the error of each row decays critically damped; the gains have units 1/s² and 1/s
/// (e.g. ω_n = 1 / (5 dt) for a simulation step dt). J v and e are the velocity and position drift of an
/// integrator that does not respect the constraint exactly; at zero gains they grow unchecked.
///
/// ## How it is solved (constrained_forward_dynamics)
/// CRBA and the tree-sparse LTDL factor H = Lᵀ D L (algorithms.hpp, floating.hpp) give the unconstrained
/// v̇_free = H⁻¹ (τ − C); then Y = L⁻ᵀ Jᵀ (one sparse back-substitution per constraint row), the contact-space
/// inverse inertia Λ⁻¹ = J H⁻¹ Jᵀ = Yᵀ D⁻¹ Y (m × m, m = Σ 3 or 6), its Cholesky factor, and
///     λ = Λ (a* − J̇ q̇ − J v̇_free),        v̇ = v̇_free + L⁻¹ D⁻¹ (Y λ).
/// H⁻¹ is never formed. Λ⁻¹ is singular when the contacts are redundant (two 6D contacts on one body, three
/// collinear points, more than six constrained directions on one rigid subtree...); then set `damping` μ > 0:
/// λ = (Λ⁻¹ + μ I)⁻¹ (…), the damped least-squares solution, whose constraint residual grows with μ.
/// `ContactData::ok` is false when the factorisation failed (Λ⁻¹ + μ I not positive definite) or Λ⁻¹ + μ I is
/// numerically singular (its condition number, estimated from the Cholesky factor's diagonal, above 1 / (100 ε):
/// a singular configuration such as a point contact on its body's last joint axis); the outputs are then not
/// meaningful. Nothing allocates after `ContactData` is built; nothing throws.
///
/// ## Impulses (impulse_dynamics)
/// An inelastic (restitution e = 0) or partly elastic impact at the contacts, during which the configuration does
/// not change: H (v⁺ − v⁻) = Jᵀ Λ̂ and J v⁺ = −e J v⁻, so Λ̂ = −(1 + e) Λ J v⁻ (the contact impulses, N·s and
/// N·m·s, in the contacts' reference frames as λ) and v⁺ = v⁻ + H⁻¹ Jᵀ Λ̂. The kinetic energy does not grow for
/// e ∈ [0, 1]. Pinocchio's `impulseDynamics` (`data.dq_after`, `data.impulse_c`) is the same.

#include "spatial/algorithms.hpp"
#include "spatial/floating.hpp"
#include "spatial/ik.hpp"
#include "spatial/kinematics.hpp"

#include <Eigen/Cholesky>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace spatial {

/// Kinds of rigid contact (Pinocchio's CONTACT_6D and CONTACT_3D).
enum class ContactType {
  Contact6D,  ///< the frame is welded: 6 rows (linear first), frame axes
  Contact3D,  ///< the frame's origin is held: 3 rows, world axes
};

/// One rigid contact on a frame of the model (see the top of contact.hpp).
template <class S>
struct RigidContact {
  std::string name;          ///< for messages (defaults to the frame's name)
  int frame = -1;            ///< index into the model's frames
  ContactType type = ContactType::Contact6D;
  ReferenceFrame reference = ReferenceFrame::Local;  ///< the axes λ is reported in: Local or LocalWorldAligned
  S kp = S(0);               ///< Baumgarte position gain (1/s²)
  S kd = S(0);               ///< Baumgarte velocity gain (1/s)
  Vector3<S> target_position = Vector3<S>::Zero();      ///< p*: world position of the frame's origin
  Matrix3<S> target_rotation = Matrix3<S>::Identity();  ///< R*: frame axes → world axes (6D only)
  /// contact_inverse_dynamics only: friction coefficient μ (the pyramid |f_x|, |f_y| ≤ μ f_n inside the cone) and,
  /// for 6D contacts, the sole: the rectangle [x_min, x_max] × [y_min, y_max] of the frame's x-y plane (metres; the
  /// frame's z axis is the contact normal, pointing from the ground into the robot). 3D contacts push along the
  /// world's +z.
  S friction = S(0.6);
  S sole_x_min = S(0), sole_x_max = S(0), sole_y_min = S(0), sole_y_max = S(0);

  int dim() const { return type == ContactType::Contact6D ? 6 : 3; }
  /// Generators of the contact's wrench cone in contact_inverse_dynamics: 4 corners × 4 pyramid edges (6D), or the
  /// 4 edges (3D).
  int generators() const { return type == ContactType::Contact6D ? 16 : 4; }
};

/// A 6D contact on `frame` (λ in the frame's axes by default) and a 3D contact (λ in world axes by default).
template <class S = double>
RigidContact<S> contact_6d(int frame, ReferenceFrame reference = ReferenceFrame::Local) {
  RigidContact<S> c;
  c.frame = frame;
  c.type = ContactType::Contact6D;
  c.reference = reference;
  return c;
}
template <class S = double>
RigidContact<S> contact_3d(int frame, ReferenceFrame reference = ReferenceFrame::LocalWorldAligned) {
  RigidContact<S> c;
  c.frame = frame;
  c.type = ContactType::Contact3D;
  c.reference = reference;
  return c;
}


/// The contacts of a model and every buffer their algorithms need, allocated here once. `ModelT`: `Model<S, T>` or
/// `FloatingModel<S, T>`. The contacts' frames and types are fixed at construction (they set the sizes); their
/// gains, targets and reference frames may be changed between calls through `contacts`.
template <class ModelT>
struct ContactData {
  using Scalar = typename ModelT::Scalar;
  using S = Scalar;
  using Traits = detail::ModelTraits<ModelT>;
  static constexpr int NV = Traits::NV;
  static constexpr int NM = Traits::NM;
  using VectorV = Eigen::Matrix<S, NV, 1>;
  using MatrixX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using VectorX = Eigen::Matrix<S, Eigen::Dynamic, 1>;

  /// Checks every contact against the model: throws `ModelError` naming the contact (its `name`, or its index) for
  /// a frame index out of range or a reference frame other than Local and LocalWorldAligned; names default to
  /// the frames' names.
  ContactData(const ModelT& model, std::vector<RigidContact<S>> list) : contacts(std::move(list)) {
    const auto& frames = Traits::tree(model).frames();
    m = 0;
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      RigidContact<S>& c = contacts[k];
      const std::string who = "contact " + (c.name.empty() ? "#" + std::to_string(k) : "'" + c.name + "'");
      if (c.frame < 0 || c.frame >= static_cast<int>(frames.size()))
        throw ModelError(who + ": frame index " + std::to_string(c.frame) + " is not one of the model's " +
                         std::to_string(frames.size()) + " frames");
      if (c.reference != ReferenceFrame::Local && c.reference != ReferenceFrame::LocalWorldAligned)
        throw ModelError(who + " (frame '" + frames[static_cast<std::size_t>(c.frame)].name +
                         "'): the constraint force can be reported in Local or LocalWorldAligned axes, not World");
      if (c.name.empty()) c.name = frames[static_cast<std::size_t>(c.frame)].name;
      m += c.dim();
      ng += c.generators();
    }
    const int nv = Traits::nv(model);
    G = MatrixX::Zero(m, ng);
    A = Eigen::Matrix<S, 6, Eigen::Dynamic>::Zero(6, ng);
    beta = VectorX::Zero(ng);
    tau = VectorV::Zero(nv);
    J = MatrixX::Zero(m, nv);
    Y = MatrixX::Zero(nv, m);
    DY = MatrixX::Zero(nv, m);
    K = MatrixX::Zero(m, m);
    // Factorise an identity once: sizes the factor's storage and sets its status (a freshly constructed LLT's status
    // is uninitialised, and copying one is undefined behaviour).
    llt.compute(MatrixX::Identity(m, m));
    lambda = VectorX::Zero(m);
    rhs = VectorX::Zero(m);
    drift = VectorX::Zero(m);
    velocity_error = VectorX::Zero(m);
    position_error = VectorX::Zero(m);
    qdd = VectorV::Zero(nv);
    v_after = VectorV::Zero(nv);
    tmp = VectorV::Zero(nv);
    J6 = Eigen::Matrix<S, 6, NM>::Zero(6, nv);
  }

  std::vector<RigidContact<S>> contacts;
  int m = 0;            ///< constraint rows: Σ 6 (6D) or 3 (3D)
  int ng = 0;           ///< wrench-cone generators (contact_inverse_dynamics): Σ 16 (6D) or 4 (3D)
  S damping = S(0);     ///< μ added to the diagonal of Λ⁻¹ (redundant contacts)
  bool ok = true;       ///< false when Λ⁻¹ + μ I could not be factorised
  MatrixX J;            ///< m × nv contact Jacobian (the rows of each contact, in `contacts` order)
  VectorX lambda;       ///< constraint forces (or impulses), each contact's in its `reference` axes
  VectorX drift;        ///< J̇ q̇ (m)
  VectorX velocity_error;  ///< J v (m)
  VectorX position_error;  ///< e (m; see the top of contact.hpp)
  VectorV qdd;          ///< constrained_forward_dynamics: v̇
  VectorV v_after;      ///< impulse_dynamics: v⁺
  VectorV tau;          ///< contact_inverse_dynamics: τ (nv; the first six: what the contacts could not supply)
  int iterations = 0;   ///< contact_inverse_dynamics: Newton iterations of the force distribution
  MatrixX K;            ///< Λ⁻¹ = J H⁻¹ Jᵀ (+ μ I), m × m
  // scratch
  MatrixX Y, DY, G;
  Eigen::Matrix<S, 6, Eigen::Dynamic> A;
  VectorX beta;
  Eigen::LLT<MatrixX> llt;
  VectorX rhs;
  VectorV tmp;
  Eigen::Matrix<S, 6, NM> J6;
};

namespace detail {
/// Rows, drift, velocity and position errors of every contact, from the kinematics left by
/// `compute_joint_jacobians_time_variation` (or, without `Drift`, `compute_joint_jacobians`).
template <bool Drift, class ModelT, class DataT>
void contact_rows(const ModelT& model, const DataT& data, ContactData<ModelT>& cd) {
  using S = typename ModelT::Scalar;
  const auto k = kin(model, data);
  int r = 0;
  for (const RigidContact<S>& c : cd.contacts) {
    int body;
    const Transform<S> Xfw = frame_world(k, c.frame, body);  // E = Rᵀ, r = p
    if (c.type == ContactType::Contact6D) {
      frame_jacobian(model, data, c.frame, ReferenceFrame::Local, cd.J.middleRows(r, 6));
      if constexpr (Drift) {
        const Motion<S> a = frame_acceleration(model, data, c.frame, ReferenceFrame::Local);
        const Motion<S> vf = frame_velocity(model, data, c.frame, ReferenceFrame::Local);
        cd.drift.template segment<3>(r) = a.v;
        cd.drift.template segment<3>(r + 3) = a.w;
        cd.velocity_error.template segment<3>(r) = vf.v;
        cd.velocity_error.template segment<3>(r + 3) = vf.w;
        cd.position_error.template segment<3>(r) = Xfw.E * (Xfw.r - c.target_position);
        cd.position_error.template segment<3>(r + 3) = so3_log<S>(c.target_rotation.transpose() * Xfw.E.transpose());
      }
    } else {
      frame_jacobian(model, data, c.frame, ReferenceFrame::LocalWorldAligned, cd.J6);
      cd.J.middleRows(r, 3) = cd.J6.template topRows<3>();
      if constexpr (Drift) {
        cd.drift.template segment<3>(r) = frame_classical_acceleration(model, data, c.frame,
                                                                       ReferenceFrame::LocalWorldAligned);
        cd.velocity_error.template segment<3>(r) =
            frame_velocity(model, data, c.frame, ReferenceFrame::LocalWorldAligned).v;
        cd.position_error.template segment<3>(r) = Xfw.r - c.target_position;
      }
    }
    r += c.dim();
  }
}

/// Λ⁻¹ = Yᵀ D⁻¹ Y with Y = L⁻ᵀ Jᵀ (data.L: the LTDL factor of H), and its Cholesky factor.
template <class ModelT, class DataT>
void contact_inverse_inertia(const ModelT& model, const DataT& data, ContactData<ModelT>& cd) {
  const int nv = ModelTraits<ModelT>::nv(model);
  cd.Y = cd.J.transpose();
  for (int c = 0; c < cd.m; ++c) {
    auto col = cd.Y.col(c);
    ltdl_solve_lt(model, data, col);
  }
  for (int i = 0; i < nv; ++i) cd.DY.row(i) = cd.Y.row(i) / data.L(i, i);
  cd.K.noalias() = cd.Y.transpose() * cd.DY;
  cd.K.diagonal().array() += cd.damping;
  cd.llt.compute(cd.K);
  // A singular configuration (a point contact on its body's last joint axis, a stretched limb) leaves Λ⁻¹
  // numerically singular without failing the factorisation: also refuse a condition number above 1 / (100 ε)
  // (≈ 4.5e13 in double, 8e4 in float: fewer than ~2 significant digits left), estimated from the Cholesky
  // factor's diagonal.
  using S = typename ModelT::Scalar;
  bool ok = cd.llt.info() == Eigen::Success;
  if (ok && cd.m > 0) {
    const auto d = cd.llt.matrixLLT().diagonal().cwiseAbs();
    const S lo = d.minCoeff(), hi = d.maxCoeff();
    ok = lo * lo >= S(100) * Eigen::NumTraits<S>::epsilon() * hi * hi;
  }
  cd.ok = ok;
}

/// λ (solved in the rows' axes: 6D frame axes, 3D world axes) into each contact's reference axes.
template <class ModelT, class DataT>
void contact_forces_to_reference(const ModelT& model, const DataT& data, ContactData<ModelT>& cd) {
  using S = typename ModelT::Scalar;
  const auto k = kin(model, data);
  int r = 0;
  for (const RigidContact<S>& c : cd.contacts) {
    const bool local_rows = c.type == ContactType::Contact6D;
    const bool local_out = c.reference == ReferenceFrame::Local;
    if (local_rows != local_out) {
      int body;
      const Matrix3<S> E = frame_world(k, c.frame, body).E;  // frame axes ← world axes
      for (int b = 0; b < c.dim(); b += 3) {
        const Vector3<S> f = cd.lambda.template segment<3>(r + b);
        cd.lambda.template segment<3>(r + b) = local_out ? Vector3<S>(E * f) : Vector3<S>(E.transpose() * f);
      }
    }
    r += c.dim();
  }
}

/// x += H⁻¹ Jᵀ λ = L⁻¹ D⁻¹ (Y λ), then λ into the contacts' reference axes.
template <class ModelT, class DataT, class X>
void contact_apply_forces(const ModelT& model, const DataT& data, ContactData<ModelT>& cd, Eigen::MatrixBase<X>& x) {
  cd.tmp.noalias() = cd.Y * cd.lambda;
  ltdl_solve_dl(model, data, cd.tmp);
  x += cd.tmp;
  contact_forces_to_reference(model, data, cd);
}

/// The wrench-cone generators of every contact as the columns of cd.G (m × ng, block diagonal, in the rows' axes).
template <class ModelT>
void contact_generators(ContactData<ModelT>& cd) {
  using S = typename ModelT::Scalar;
  cd.G.setZero();
  int r = 0, g = 0;
  for (const RigidContact<S>& c : cd.contacts) {
    const S mu = c.friction;
    const Vector3<S> edges[4] = {Vector3<S>(mu, 0, 1), Vector3<S>(-mu, 0, 1), Vector3<S>(0, mu, 1),
                                 Vector3<S>(0, -mu, 1)};
    if (c.type == ContactType::Contact6D) {
      const Vector3<S> corners[4] = {Vector3<S>(c.sole_x_min, c.sole_y_min, 0), Vector3<S>(c.sole_x_max, c.sole_y_min, 0),
                                     Vector3<S>(c.sole_x_max, c.sole_y_max, 0), Vector3<S>(c.sole_x_min, c.sole_y_max, 0)};
      for (const Vector3<S>& p : corners)
        for (const Vector3<S>& e : edges) {
          cd.G.template block<3, 1>(r, g) = e;
          cd.G.template block<3, 1>(r + 3, g) = p.cross(e);
          ++g;
        }
    } else {
      for (const Vector3<S>& e : edges) cd.G.template block<3, 1>(r, g++) = e;
    }
    r += c.dim();
  }
}

/// min ½‖β‖² subject to A β = w, β ≥ 0, through its dual: β = (Aᵀν)₊ with ν maximising wᵀν − ½‖(Aᵀν)₊‖² (concave,
/// piecewise quadratic, six unknowns), by Newton's method on the active generators ((Aᵀν)ᵢ > 0) with a backtracking
/// line search. Exact once the active set is right; returns false when it does not converge (w outside the cone:
/// the dual is unbounded).
template <class S, class AM, class W, class B>
bool nonnegative_min_norm(const Eigen::MatrixBase<AM>& A, const Eigen::MatrixBase<W>& w, Eigen::MatrixBase<B>& beta,
                          int& iterations) {
  const int n = static_cast<int>(A.cols());
  const S scale = A.cwiseAbs().maxCoeff();
  const S tol = S(64) * Eigen::NumTraits<S>::epsilon() * (w.norm() + S(1)) * (scale + S(1));
  const S rho = Eigen::NumTraits<S>::epsilon() * (scale * scale + S(1));
  Vector6<S> nu = Vector6<S>::Zero(), grad, d;
  const auto dual = [&](const Vector6<S>& x) {
    S v = w.dot(x);
    for (int i = 0; i < n; ++i) {
      const S a = A.col(i).dot(x);
      if (a > S(0)) v -= S(0.5) * a * a;
    }
    return v;
  };
  bool first = true;
  for (iterations = 0; iterations < 100; ++iterations) {
    Matrix6<S> H = rho * Matrix6<S>::Identity();
    for (int i = 0; i < n; ++i) {
      const S a = A.col(i).dot(nu);
      beta[i] = a > S(0) ? a : S(0);
      if (a > S(0) || first) H.noalias() += A.col(i) * A.col(i).transpose();
    }
    first = false;
    grad = w - A * beta;
    if (grad.norm() <= tol) return true;
    d = H.ldlt().solve(grad);
    const S g0 = dual(nu), slope = grad.dot(d);
    S t = S(1);
    for (int k = 0; k < 60 && dual(nu + t * d) < g0 + S(1e-4) * t * slope; ++k) t *= S(0.5);
    nu += t * d;
  }
  return false;
}
}  // namespace detail

/// Forward dynamics with the contacts of `cd` held (see the top of contact.hpp): v̇ in `cd.qdd` (returned), the
/// constraint forces in `cd.lambda`, J in `cd.J`, Λ⁻¹ in `cd.K`. Also leaves H and its LTDL factor in `data`.
template <class ModelT, class DataT, class Q, class V, class Tau>
const typename ContactData<ModelT>::VectorV& constrained_forward_dynamics(const ModelT& model, DataT& data,
                                                                         ContactData<ModelT>& cd,
                                                                         const Eigen::MatrixBase<Q>& q,
                                                                         const Eigen::MatrixBase<V>& v,
                                                                         const Eigen::MatrixBase<Tau>& tau) {
  using S = typename ModelT::Scalar;
  compute_joint_jacobians_time_variation(model, data, q, v);
  detail::contact_rows<true>(model, data, cd);
  forward_dynamics_crba(model, data, q, v, tau);  // v̇_free in data.qdd, the factor in data.L
  detail::contact_inverse_inertia(model, data, cd);
  int r = 0;
  for (const RigidContact<S>& c : cd.contacts) {
    const int d = c.dim();
    cd.rhs.segment(r, d) = -c.kd * cd.velocity_error.segment(r, d) - c.kp * cd.position_error.segment(r, d);
    r += d;
  }
  cd.rhs -= cd.drift;
  cd.rhs.noalias() -= cd.J * data.qdd;
  cd.lambda = cd.rhs;
  cd.llt.solveInPlace(cd.lambda);
  cd.qdd = data.qdd;
  detail::contact_apply_forces(model, data, cd, cd.qdd);
  return cd.qdd;
}

/// The impact at the contacts of `cd` (see the top of contact.hpp): v⁺ in `cd.v_after` (returned), the impulses in
/// `cd.lambda`. `restitution` e ∈ [0, 1] (0: inelastic, the contacts stop). Leaves H and its factor in `data`.
template <class ModelT, class DataT, class Q, class V>
const typename ContactData<ModelT>::VectorV& impulse_dynamics(const ModelT& model, DataT& data,
                                                             ContactData<ModelT>& cd, const Eigen::MatrixBase<Q>& q,
                                                             const Eigen::MatrixBase<V>& v_before,
                                                             typename ModelT::Scalar restitution = 0) {
  using S = typename ModelT::Scalar;
  compute_joint_jacobians(model, data, q);
  detail::contact_rows<false>(model, data, cd);
  crba(model, data, q);
  ltdl(model, data);
  detail::contact_inverse_inertia(model, data, cd);
  cd.velocity_error.noalias() = cd.J * v_before;
  cd.lambda = -(S(1) + restitution) * cd.velocity_error;
  cd.llt.solveInPlace(cd.lambda);
  cd.v_after = v_before;
  detail::contact_apply_forces(model, data, cd, cd.v_after);
  return cd.v_after;
}

/// Whole-body inverse dynamics of a floating base with contacts: given q, v and v̇ that respect the contacts, the
/// joint torques and the contact forces (see the top of contact.hpp for the frames). RNEA gives the wrench w the
/// root needs (τ's first six entries); the contacts must supply it, w = J_rootᵀ λ, and the rest of the RNEA torques
/// minus Jᵀλ are the joint torques. With two feet the split is not unique; it is resolved physically:
///   - each 6D contact's wrench is a non-negative combination of forces at the four corners of its sole, each force
///     inside the friction pyramid |f_x|, |f_y| ≤ μ f_z (four edges, inside the cone of the same μ); a 3D contact's
///     force is a non-negative combination of the pyramid's edges about the world's z: so every normal force is
///     ≥ 0, every centre of pressure is inside its sole and no contact slips;
///   - among those, the one with the least Σβ² over the generators' weights β: it spreads the load over the soles'
///     corners (centres of pressure towards the soles' centres) and between the feet, and uses no internal forces.
/// Solved exactly (to round-off) by `nonnegative_min_norm` (a Newton method on the six-dimensional dual). When no
/// split can supply w (the ZMP outside the support polygon, a pulling contact, too much friction needed),
/// `cd.ok` is false and `cd.tau`'s first six entries are the part of w the contacts leave missing (otherwise zero to
/// round-off). Results: `cd.tau` (nv; returned), `cd.lambda` in each contact's reference axes, J in `cd.J`.
template <class S, class T, class Q, class V, class A>
const typename ContactData<FloatingModel<S, T>>::VectorV& contact_inverse_dynamics(
    const FloatingModel<S, T>& model, FloatingData<S, T>& data, ContactData<FloatingModel<S, T>>& cd,
    const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a) {
  cd.tau = rnea(model, data, q, v, a);
  compute_joint_jacobians(model, data, q);
  detail::contact_rows<false>(model, data, cd);
  detail::contact_generators(cd);
  cd.A.noalias() = cd.J.leftCols(6).transpose() * cd.G;
  const Vector6<S> w = cd.tau.template head<6>();
  cd.ok = detail::nonnegative_min_norm<S>(cd.A, w, cd.beta, cd.iterations);
  cd.lambda.noalias() = cd.G * cd.beta;
  cd.tau.noalias() -= cd.J.transpose() * cd.lambda;
  detail::contact_forces_to_reference(model, data, cd);
  return cd.tau;
}

/// Sets every contact's target to its frame's current world pose at q (forward kinematics), so that the Baumgarte
/// position error starts at zero.
template <class ModelT, class DataT, class Q>
void set_contact_targets(const ModelT& model, DataT& data, ContactData<ModelT>& cd, const Eigen::MatrixBase<Q>& q) {
  using S = typename ModelT::Scalar;
  forward_kinematics(model, data, q);
  const auto k = detail::kin(model, data);
  for (RigidContact<S>& c : cd.contacts) {
    int body;
    const Transform<S> X = detail::frame_world(k, c.frame, body);
    c.target_position = X.r;
    c.target_rotation = X.E.transpose();
  }
}

}  // namespace spatial
