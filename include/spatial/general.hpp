#pragma once
/// \file general.hpp
/// Trees of multi-degree-of-freedom joints: **spherical joints** (and free-flyers) anywhere in the tree, beside the
/// one-DoF joints of joints.hpp. `GeneralModel<S>` is a run-time tree in which joint i has nqᵢ configuration
/// coordinates and nvᵢ velocity coordinates, stored one after the other in body order (`idx_q(i)`, `idx_v(i)`):
///
/// | joint                       | nq | nv | q entries                     | v entries (all in the child body's axes)   |
/// |-----------------------------|----|----|-------------------------------|--------------------------------------------|
/// | one-DoF (`JointType`)       | 1  | 1  | angle or displacement         | its rate                                   |
/// | `GeneralJointKind::Spherical` | 4  | 3  | quaternion (qx, qy, qz, qw)   | ωx, ωy, ωz: angular velocity of the child  |
/// |                             |    |    | of the child's orientation    | relative to the parent, child coordinates  |
/// |                             |    |    | (child axes → joint frame)    |                                            |
/// | `GeneralJointKind::FreeFlyer` | 7  | 6  | x, y, z, qx, qy, qz, qw       | vx, vy, vz, ωx, ωy, ωz (linear first)      |
///
/// The spherical joint is Pinocchio's `JointModelSpherical` (same q, v, τ). MuJoCo's ball joint stores the same
/// quaternion scalar first (qpos = [qw qx qy qz]) and the same body-frame angular velocity; RBDL's
/// `JointTypeSpherical` stores (qx, qy, qz) with the joint's qw at the end of q, and the same body-frame ω. A
/// spherical joint's torque τᵢ (3 entries) is the moment about the joint centre in child coordinates (τᵢ = Sᵢᵀ fᵢ,
/// Sᵢ = [1₃; 0]). The free-flyer is floating.hpp's (`FloatingModel`), here allowed at any body.
///
/// Jᵢ's motion subspace Sᵢ (6 × nvᵢ, angular rows first) is constant in body coordinates for every joint here, so
/// the velocity-product term is cᵢ = vᵢ × Sᵢ q̇ᵢ as for one-DoF joints (RBDA §4.4).
///
/// The algorithms are scalar and run-time (no unrolled or SIMD paths; the compile-time and AVX2 paths of the
/// one-DoF models are the fast ones): forward kinematics, RNEA (external forces in body or base coordinates),
/// gravity and bias forces, CRBA, ABA, body Jacobians in the three reference frames of kinematics.hpp, centre of
/// mass and its Jacobian, kinetic and potential energy, and the configuration space's `integrate`, `difference`,
/// `normalize`, `neutral` and `random_configuration`. None allocates or throws after `GeneralData` is built.
/// `general_model(Model)` and `general_model(FloatingModel)` give the same tree in this form (same q, v, τ layout),
/// which the tests use to check one against the other.

#include "spatial/floating.hpp"
#include "spatial/kinematics.hpp"

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace spatial {

enum class GeneralJointKind : std::uint8_t { OneDof, Spherical, FreeFlyer };

/// A joint of a `GeneralModel`: a one-DoF joint (`type`, `axis` as in `Model`), a spherical joint or a free-flyer.
template <class S>
struct GeneralJoint {
  GeneralJointKind kind = GeneralJointKind::OneDof;
  JointType type = JointType::RevoluteZ;  ///< one-DoF joints only
  Vector3<S> axis = Vector3<S>::UnitZ();  ///< the *Axis one-DoF types only (joint axes; `add_body` normalises it)

  static GeneralJoint one_dof(JointType t, const Vector3<S>& a = Vector3<S>::UnitZ()) {
    return GeneralJoint{GeneralJointKind::OneDof, t, a};
  }
  static GeneralJoint spherical() { return GeneralJoint{GeneralJointKind::Spherical, JointType::RevoluteZ, {0, 0, 1}}; }
  static GeneralJoint free_flyer() { return GeneralJoint{GeneralJointKind::FreeFlyer, JointType::RevoluteZ, {0, 0, 1}}; }

  int nq() const { return kind == GeneralJointKind::OneDof ? 1 : kind == GeneralJointKind::Spherical ? 4 : 7; }
  int nv() const { return kind == GeneralJointKind::OneDof ? 1 : kind == GeneralJointKind::Spherical ? 3 : 6; }
};

template <class S = double>
class GeneralModel {
 public:
  using Scalar = S;
  using VectorX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using MatrixX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;

  explicit GeneralModel(const Vector3<S>& gravity = Vector3<S>(S(0), S(0), S(-9.81))) : g_(gravity) {}

  /// Appends a body hanging from `parent` (−1: the base; it must precede the new body) by `joint`, placed by
  /// `X_tree` (parent coordinates → the joint's predecessor frame), with spatial inertia `I` (body coordinates).
  /// Returns its index. A *Axis one-DoF joint's axis is normalised. Throws `ModelError` naming the joint for a parent
  /// out of range, a repeated or empty name, a zero or non-finite axis, or an unphysical inertia; the model is then
  /// unchanged.
  int add_body(int parent, const GeneralJoint<S>& joint, const Transform<S>& X_tree, const Inertia<S>& I,
               const std::string& joint_name, const std::string& body_name) {
    const std::string who = "joint '" + joint_name + "' (body '" + body_name + "')";
    if (joint_name.empty() || body_name.empty()) throw ModelError("add_body: empty joint or body name");
    if (parent < -1 || parent >= size())
      throw ModelError(who + ": parent " + std::to_string(parent) + " is not -1 or one of the " +
                       std::to_string(size()) + " bodies added before it");
    if (joint_index(joint_name) >= 0) throw ModelError(who + ": a joint of that name exists already");
    if (body_index(body_name) >= 0) throw ModelError(who + ": a body of that name exists already");
    GeneralJoint<S> j = joint;
    if (j.kind == GeneralJointKind::OneDof && has_axis(j.type)) {
      if (!j.axis.allFinite() || !(j.axis.norm() > S(0))) throw ModelError(who + ": joint axis is zero or not finite");
      j.axis.normalize();
    }
    const std::string bad = detail::inertia_problem(I).error;
    if (!bad.empty()) throw ModelError(who + ": " + bad);
    parent_.push_back(parent);
    joint_.push_back(j);
    Xtree_.push_back(X_tree);
    I_.push_back(I);
    iq_.push_back(nq_);
    iv_.push_back(nv_);
    nqi_.push_back(joint.nq());
    nvi_.push_back(joint.nv());
    // The velocity coordinates' own tree: a joint's first coordinate hangs from the last one of its parent joint,
    // each further coordinate from the one before it.
    for (int c = 0; c < joint.nv(); ++c)
      dof_parent_.push_back(c > 0 ? nv_ + c - 1 : parent < 0 ? -1 : iv_[std::size_t(parent)] + nvi_[std::size_t(parent)] - 1);
    nq_ += joint.nq();
    nv_ += joint.nv();
    joint_names_.push_back(joint_name);
    body_names_.push_back(body_name);
    Matrix6<S> Sm = Matrix6<S>::Zero();
    switch (joint.kind) {
      case GeneralJointKind::OneDof:
        Sm.col(0) = RuntimeJoint<S>{j.type, j.axis}.motion(S(1)).vector();
        break;
      case GeneralJointKind::Spherical:
        Sm.template topLeftCorner<3, 3>().setIdentity();
        break;
      case GeneralJointKind::FreeFlyer:  // v = [linear; angular]: the first three columns are linear motions
        Sm.template bottomLeftCorner<3, 3>().setIdentity();
        Sm.template topRightCorner<3, 3>().setIdentity();
        break;
    }
    S_.push_back(Sm);
    return size() - 1;
  }

  int size() const { return static_cast<int>(parent_.size()); }
  int nq() const { return nq_; }
  int nv() const { return nv_; }
  int parent(int i) const { return parent_[std::size_t(i)]; }
  const GeneralJoint<S>& joint(int i) const { return joint_[std::size_t(i)]; }
  /// First entry of joint i in q, and in v (and v̇, τ).
  int idx_q(int i) const { return iq_[std::size_t(i)]; }
  int idx_v(int i) const { return iv_[std::size_t(i)]; }
  int nq(int i) const { return nqi_[std::size_t(i)]; }
  int nv(int i) const { return nvi_[std::size_t(i)]; }
  /// The velocity coordinate that coordinate k hangs from (−1: none): the tree of the coordinates, in which a
  /// joint's first coordinate hangs from its parent joint's last and each further one from the one before it.
  int dof_parent(int k) const { return dof_parent_[std::size_t(k)]; }
  /// Sᵢ: 6 × nvᵢ (the left columns of this 6 × 6 matrix), angular rows first, body coordinates.
  const Matrix6<S>& subspace(int i) const { return S_[std::size_t(i)]; }
  const Transform<S>& tree_transform(int i) const { return Xtree_[std::size_t(i)]; }
  const Inertia<S>& inertia(int i) const { return I_[std::size_t(i)]; }
  /// Gravity in base coordinates.
  const Vector3<S>& gravity() const { return g_; }
  void set_gravity(const Vector3<S>& g) { g_ = g; }
  const std::string& joint_name(int i) const { return joint_names_[std::size_t(i)]; }
  const std::string& body_name(int i) const { return body_names_[std::size_t(i)]; }
  int joint_index(const std::string& name) const {
    for (int i = 0; i < size(); ++i)
      if (joint_names_[std::size_t(i)] == name) return i;
    return -1;
  }
  int body_index(const std::string& name) const {
    for (int i = 0; i < size(); ++i)
      if (body_names_[std::size_t(i)] == name) return i;
    return -1;
  }
  S total_mass() const {
    S m = S(0);
    for (const auto& I : I_) m += I.m;
    return m;
  }

 private:
  std::vector<int> parent_, iq_, iv_, nqi_, nvi_, dof_parent_;
  std::vector<GeneralJoint<S>> joint_;
  std::vector<Transform<S>> Xtree_;
  std::vector<Inertia<S>> I_;
  std::vector<Matrix6<S>> S_;
  std::vector<std::string> joint_names_, body_names_;
  Vector3<S> g_;
  int nq_ = 0, nv_ = 0;
};

/// Per-call buffers of the `GeneralModel` algorithms (allocated once, here).
template <class S = double>
struct GeneralData {
  using VectorX = typename GeneralModel<S>::VectorX;
  using MatrixX = typename GeneralModel<S>::MatrixX;

  explicit GeneralData(const GeneralModel<S>& model) {
    const auto n = std::size_t(model.size());
    Xup.assign(n, Transform<S>::Identity());
    X0 = Xup;
    v.assign(n, Motion<S>::Zero());
    a = v;
    c = v;
    f.assign(n, Force<S>::Zero());
    Ic.assign(n, Inertia<S>::Zero());
    IA.assign(n, ArticulatedInertia<S>(Inertia<S>::Zero()));
    U.assign(n, {});
    Dinv.assign(n, Matrix6<S>::Zero());
    pA.assign(n, Force<S>::Zero());
    u.assign(n, Vector6<S>::Zero());
    msub.assign(n, S(0));
    mc.assign(n, Vector3<S>::Zero());
    Sw.assign(std::size_t(model.nv()), Motion<S>::Zero());
    cos_q = VectorX::Zero(model.nq());
    sin_q = cos_q;
    tau = VectorX::Zero(model.nv());
    qdd = tau;
    zero = tau;
    H = MatrixX::Zero(model.nv(), model.nv());
  }

  std::vector<Transform<S>> Xup;  ///< ⁱX_λ(i)
  std::vector<Transform<S>> X0;   ///< ⁱX_0: base → body i
  std::vector<Motion<S>> v, a;    ///< body velocities, accelerations (RNEA, ABA: minus gravity), body coordinates
  std::vector<Motion<S>> c;       ///< ABA: vᵢ × Sᵢ q̇ᵢ
  std::vector<Force<S>> f;        ///< RNEA: force across joint i, body i coordinates
  std::vector<Inertia<S>> Ic;     ///< CRBA: composite inertias
  std::vector<Motion<S>> Sw;      ///< CRBA: the columns of S (one per velocity coordinate) in base coordinates
  VectorX cos_q, sin_q;           ///< cos and sin of every entry of q (read for the one-DoF joints)
  std::vector<ArticulatedInertia<S>> IA;       ///< ABA: articulated inertias
  std::vector<std::array<Force<S>, 6>> U;      ///< ABA: Uᵢ = Iᴬᵢ Sᵢ (nvᵢ columns)
  std::vector<Matrix6<S>> Dinv;                ///< ABA: Dᵢ⁻¹ = (Sᵢᵀ Uᵢ)⁻¹ (top-left nvᵢ × nvᵢ)
  std::vector<Force<S>> pA;                    ///< ABA: bias forces
  std::vector<Vector6<S>> u;                   ///< ABA: uᵢ = τᵢ − Sᵢᵀ pᴬᵢ (first nvᵢ entries)
  std::vector<S> msub;                  ///< centre of mass: subtree masses
  std::vector<Vector3<S>> mc;           ///< centre of mass: Σ mₖ cₖ over the subtree (base coordinates)
  VectorX tau, qdd, zero;
  MatrixX H;
  Vector3<S> com = Vector3<S>::Zero();
};

namespace detail {
[[noreturn]] inline void general_size_assertion_failed(const char* function, const char* argument, long long given,
                                                       bool config, long long expected) {
  std::fprintf(stderr, "spatial: %s: argument '%s' has %lld entries, the general model has %s = %lld\n", function,
               argument, given, config ? "nq" : "nv", expected);
  std::fflush(stderr);
  std::abort();
}
/// Size check of an argument (q: nq entries; v, v̇, τ: nv), as the other models' (SPATIAL_CHECK_SIZES).
template <bool Config, class S, class Vec>
inline void check_general(const GeneralModel<S>& model, const Eigen::MatrixBase<Vec>& x, const char* function,
                          const char* argument) {
#if SPATIAL_CHECK_SIZES
  const long long expected = Config ? model.nq() : model.nv();
  if (static_cast<long long>(x.size()) != expected)
    general_size_assertion_failed(function, argument, static_cast<long long>(x.size()), Config, expected);
#else
  (void)model, (void)x, (void)function, (void)argument;
#endif
}

/// ⁱX_λ = X_J(qᵢ) X_T(i), from q and its sines and cosines (`GeneralData::sin_q`, `cos_q`).
template <class S, class Q>
Transform<S> general_joint_transform(const GeneralModel<S>& model, const GeneralData<S>& data, int i,
                                     const Eigen::MatrixBase<Q>& q) {
  const GeneralJoint<S>& j = model.joint(i);
  const int k = model.idx_q(i);
  switch (j.kind) {
    case GeneralJointKind::OneDof:
      return RuntimeJoint<S>{j.type, j.axis}.compose(S(q[k]), data.cos_q[k], data.sin_q[k], model.tree_transform(i));
    case GeneralJointKind::Spherical: {
      const Eigen::Quaternion<S> r = quaternion_at<S>(q, k);
      return Transform<S>(r.toRotationMatrix().transpose(), Vector3<S>::Zero()) * model.tree_transform(i);
    }
    case GeneralJointKind::FreeFlyer: break;
  }
  return root_transform<S>(q.template segment<7>(k)) * model.tree_transform(i);
}

/// Sᵢ xᵢ as a motion, xᵢ = joint i's entries of a velocity-sized vector (by joint kind: no 6 × nv product).
template <class S, class V>
Motion<S> general_motion(const GeneralModel<S>& model, int i, const Eigen::MatrixBase<V>& x) {
  const GeneralJoint<S>& j = model.joint(i);
  const int k = model.idx_v(i);
  switch (j.kind) {
    case GeneralJointKind::OneDof: return RuntimeJoint<S>{j.type, j.axis}.motion(S(x[k]));
    case GeneralJointKind::Spherical: return Motion<S>(Vector3<S>(x[k], x[k + 1], x[k + 2]), Vector3<S>::Zero());
    case GeneralJointKind::FreeFlyer: break;
  }
  return Motion<S>(Vector3<S>(x[k + 3], x[k + 4], x[k + 5]), Vector3<S>(x[k], x[k + 1], x[k + 2]));
}
/// Sᵢᵀ f written to out[0 … nvᵢ − 1].
template <class S>
void general_project(const GeneralModel<S>& model, int i, const Force<S>& f, S* out) {
  const GeneralJoint<S>& j = model.joint(i);
  switch (j.kind) {
    case GeneralJointKind::OneDof: out[0] = RuntimeJoint<S>{j.type, j.axis}.project(f); return;
    case GeneralJointKind::Spherical: out[0] = f.n[0], out[1] = f.n[1], out[2] = f.n[2]; return;
    case GeneralJointKind::FreeFlyer: break;
  }
  out[0] = f.f[0], out[1] = f.f[1], out[2] = f.f[2], out[3] = f.n[0], out[4] = f.n[1], out[5] = f.n[2];
}
/// Column c of Sᵢ as a motion.
template <class S>
Motion<S> general_column(const GeneralModel<S>& model, int i, int c) {
  return Motion<S>(Vector6<S>(model.subspace(i).col(c)));
}
/// X⁻¹ (column c of Sᵢ) for X = ⁱX_A: the column in A coordinates (one-DoF joints: their own `subspace_inverse`).
template <class S>
Motion<S> general_column_inverse(const GeneralModel<S>& model, int i, int c, const Transform<S>& X) {
  const GeneralJoint<S>& j = model.joint(i);
  if (j.kind == GeneralJointKind::OneDof) return RuntimeJoint<S>{j.type, j.axis}.subspace_inverse(X);
  return X.apply_inverse(general_column(model, i, c));
}
/// I (column c of Sᵢ) for a rigid-body inertia I (one-DoF joints: their own `apply_inertia`).
template <class S>
Force<S> general_inertia_column(const GeneralModel<S>& model, int i, int c, const Inertia<S>& I) {
  const GeneralJoint<S>& j = model.joint(i);
  if (j.kind == GeneralJointKind::OneDof) return RuntimeJoint<S>{j.type, j.axis}.apply_inertia(I);
  return I * general_column(model, i, c);
}

/// The forward pass shared by the algorithms: transforms, and (Velocity) body velocities.
template <bool Velocity, class S, class Q, class V>
void general_positions(const GeneralModel<S>& model, GeneralData<S>& data, const Eigen::MatrixBase<Q>& q,
                       const Eigen::MatrixBase<V>& v) {
  sincos_all<S>(q, data.cos_q, data.sin_q, model.nq());
  for (int i = 0; i < model.size(); ++i) {
    const auto k = std::size_t(i);
    const int p = model.parent(i);
    data.Xup[k] = general_joint_transform(model, data, i, q);
    data.X0[k] = p < 0 ? data.Xup[k] : data.Xup[k] * data.X0[std::size_t(p)];
    if constexpr (Velocity) {
      const Motion<S> vJ = general_motion(model, i, v);
      data.v[k] = p < 0 ? vJ : data.Xup[k].apply(data.v[std::size_t(p)]) + vJ;
    }
  }
}

}  // namespace detail

// ---------------------------------------------------------------------------------------------------------------
// The configuration space
// ---------------------------------------------------------------------------------------------------------------

/// Every joint at rest: one-DoF joints at 0, quaternions at the identity, free-flyers at the origin.
template <class S>
typename GeneralModel<S>::VectorX neutral(const GeneralModel<S>& model) {
  typename GeneralModel<S>::VectorX q = GeneralModel<S>::VectorX::Zero(model.nq());
  for (int i = 0; i < model.size(); ++i)
    if (model.joint(i).kind != GeneralJointKind::OneDof) q[model.idx_q(i) + model.nq(i) - 1] = S(1);
  return q;
}

/// q ⊕ v dt on the manifold: one-DoF joints q + q̇ dt; a spherical joint's quaternion r ← r exp(ω̂ dt) (ω in child
/// coordinates, renormalised); a free-flyer as in floating.hpp. Writes `out` (nq), which may be `q`. No allocation.
template <class S, class Q, class V, class Out>
void integrate(const GeneralModel<S>& model, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v, S dt,
               const Eigen::MatrixBase<Out>& out_) {
  detail::check_general<true>(model, q, "integrate", "q");
  detail::check_general<false>(model, v, "integrate", "v");
  detail::check_general<true>(model, out_, "integrate", "out");
  auto& out = const_cast<Eigen::MatrixBase<Out>&>(out_);
  for (int i = 0; i < model.size(); ++i) {
    const int kq = model.idx_q(i), kv = model.idx_v(i);
    switch (model.joint(i).kind) {
      case GeneralJointKind::OneDof: out[kq] = q[kq] + v[kv] * dt; break;
      case GeneralJointKind::Spherical: {
        const Eigen::Quaternion<S> r0 = detail::quaternion_at<S>(q, kq);
        Eigen::Quaternion<S> r1 = r0 * detail::quaternion_exp<S>(Vector3<S>(v[kv], v[kv + 1], v[kv + 2]) * dt);
        r1.normalize();
        out[kq] = r1.x(), out[kq + 1] = r1.y(), out[kq + 2] = r1.z(), out[kq + 3] = r1.w();
        break;
      }
      case GeneralJointKind::FreeFlyer:
        detail::free_flyer_integrate<S>(q.template segment<7>(kq), v.template segment<6>(kv), dt,
                                        out.template segment<7>(kq));
        break;
    }
  }
}
template <class S, class Q, class V>
typename GeneralModel<S>::VectorX integrate(const GeneralModel<S>& model, const Eigen::MatrixBase<Q>& q,
                                            const Eigen::MatrixBase<V>& v, S dt = S(1)) {
  typename GeneralModel<S>::VectorX out(model.nq());
  integrate(model, q, v, dt, out);
  return out;
}

/// q₁ ⊖ q₀ (nv): the v with q₀ ⊕ v = q₁ (a spherical joint: the rotation vector of r₀⁻¹ r₁ in child coordinates,
/// the shorter path). Writes `out`.
template <class S, class Q0, class Q1, class Out>
void difference(const GeneralModel<S>& model, const Eigen::MatrixBase<Q0>& q0, const Eigen::MatrixBase<Q1>& q1,
                const Eigen::MatrixBase<Out>& out_) {
  detail::check_general<true>(model, q0, "difference", "q0");
  detail::check_general<true>(model, q1, "difference", "q1");
  detail::check_general<false>(model, out_, "difference", "out");
  auto& out = const_cast<Eigen::MatrixBase<Out>&>(out_);
  for (int i = 0; i < model.size(); ++i) {
    const int kq = model.idx_q(i), kv = model.idx_v(i);
    switch (model.joint(i).kind) {
      case GeneralJointKind::OneDof: out[kv] = q1[kq] - q0[kq]; break;
      case GeneralJointKind::Spherical: {
        const Eigen::Quaternion<S> r0 = detail::quaternion_at<S>(q0, kq);
        const Eigen::Quaternion<S> r1 = detail::quaternion_at<S>(q1, kq);
        out.template segment<3>(kv) = detail::quaternion_log_between(r0, r1);
        break;
      }
      case GeneralJointKind::FreeFlyer:
        detail::free_flyer_difference<S>(q0.template segment<7>(kq), q1.template segment<7>(kq),
                                         out.template segment<6>(kv));
        break;
    }
  }
}
template <class S, class Q0, class Q1>
typename GeneralModel<S>::VectorX difference(const GeneralModel<S>& model, const Eigen::MatrixBase<Q0>& q0,
                                             const Eigen::MatrixBase<Q1>& q1) {
  typename GeneralModel<S>::VectorX out(model.nv());
  difference(model, q0, q1, out);
  return out;
}

/// Scales every quaternion of q to unit length (in place).
template <class S, class Q>
void normalize(const GeneralModel<S>& model, Eigen::MatrixBase<Q>& q) {
  for (int i = 0; i < model.size(); ++i) {
    const int k = model.idx_q(i);
    if (model.joint(i).kind == GeneralJointKind::Spherical) q.template segment<4>(k).normalize();
    else if (model.joint(i).kind == GeneralJointKind::FreeFlyer) q.template segment<4>(k + 3).normalize();
  }
}

/// A random configuration: every coordinate but the quaternions' uniform in [lower, upper] (nq entries; an infinite
/// bound is replaced by ∓π; quaternion entries are not read), every quaternion uniform over the rotations.
template <class S, class L, class U, class Rng>
typename GeneralModel<S>::VectorX random_configuration(const GeneralModel<S>& model, const Eigen::MatrixBase<L>& lower,
                                                       const Eigen::MatrixBase<U>& upper, Rng& rng) {
  using std::isfinite;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  typename GeneralModel<S>::VectorX q(model.nq());
  const auto draw = [&](int k) {
    const S lo = isfinite(double(lower[k])) ? S(lower[k]) : -S(EIGEN_PI);
    const S hi = isfinite(double(upper[k])) ? S(upper[k]) : S(EIGEN_PI);
    q[k] = lo + S(unit(rng)) * (hi - lo);
  };
  for (int i = 0; i < model.size(); ++i) {
    const int k = model.idx_q(i);
    switch (model.joint(i).kind) {
      case GeneralJointKind::OneDof: draw(k); break;
      case GeneralJointKind::Spherical: detail::random_unit_quaternion<S>(rng, q.template segment<4>(k)); break;
      case GeneralJointKind::FreeFlyer:
        for (int c = 0; c < 3; ++c) draw(k + c);
        detail::random_unit_quaternion<S>(rng, q.template segment<4>(k + 3));
        break;
    }
  }
  return q;
}

// ---------------------------------------------------------------------------------------------------------------
// Algorithms
// ---------------------------------------------------------------------------------------------------------------

/// Body placements (`data.Xup`, `data.X0`) at q, and with v the body velocities (`data.v`, body coordinates).
template <class S, class Q>
void forward_kinematics(const GeneralModel<S>& model, GeneralData<S>& data, const Eigen::MatrixBase<Q>& q) {
  detail::check_general<true>(model, q, "forward_kinematics", "q");
  detail::general_positions<false>(model, data, q, q);
}
template <class S, class Q, class V>
void forward_kinematics(const GeneralModel<S>& model, GeneralData<S>& data, const Eigen::MatrixBase<Q>& q,
                        const Eigen::MatrixBase<V>& v) {
  detail::check_general<true>(model, q, "forward_kinematics", "q");
  detail::check_general<false>(model, v, "forward_kinematics", "v");
  detail::general_positions<true>(model, data, q, v);
}

/// Inverse dynamics (RBDA Table 5.1 with nvᵢ-column subspaces): τ = H(q) v̇ + C(q, v) − Σ Jᵢᵀ fᵢˣ, gravity as the
/// base acceleration −a_g. `fext[i]`: the external force on body i, in body or base coordinates per `frame`.
/// Returns `data.tau`; `data.v`, `data.a` (minus gravity), `data.f` hold the per-body values.
template <class S, class Q, class V, class A, class Ext = NoExternalForces>
const typename GeneralData<S>::VectorX& rnea(const GeneralModel<S>& model, GeneralData<S>& data,
                                             const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v,
                                             const Eigen::MatrixBase<A>& a, const Ext& fext = Ext(),
                                             ForceFrame frame = ForceFrame::Body) {
  detail::check_general<true>(model, q, "rnea", "q");
  detail::check_general<false>(model, v, "rnea", "v");
  detail::check_general<false>(model, a, "rnea", "a");
  const Motion<S> a0(Vector3<S>::Zero(), -model.gravity());
  detail::general_positions<true>(model, data, q, v);
  for (int i = 0; i < model.size(); ++i) {
    const auto k = std::size_t(i);
    const int p = model.parent(i);
    const Motion<S> vJ = detail::general_motion(model, i, v);
    const Motion<S> ap = p < 0 ? a0 : data.a[std::size_t(p)];
    data.a[k] = data.Xup[k].apply(ap) + detail::general_motion(model, i, a) + cross(data.v[k], vJ);
    const Inertia<S>& I = model.inertia(i);
    data.f[k] = I * data.a[k] + cross(data.v[k], I * data.v[k]);
    if constexpr (!std::is_same_v<Ext, NoExternalForces>) {
      data.f[k] -= frame == ForceFrame::Body ? Force<S>(fext[k]) : data.X0[k].apply_force(fext[k]);
    } else {
      (void)fext, (void)frame;
    }
  }
  for (int i = model.size() - 1; i >= 0; --i) {
    const auto k = std::size_t(i);
    detail::general_project(model, i, data.f[k], data.tau.data() + model.idx_v(i));
    const int p = model.parent(i);
    if (p >= 0) data.f[std::size_t(p)] += data.Xup[k].apply_force_inverse(data.f[k]);
  }
  return data.tau;
}

/// C(q, v) = RNEA(q, v, 0). Returns `data.tau`.
template <class S, class Q, class V>
const typename GeneralData<S>::VectorX& bias_forces(const GeneralModel<S>& model, GeneralData<S>& data,
                                                    const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v) {
  return rnea(model, data, q, v, data.zero);
}
/// G(q) = RNEA(q, 0, 0). Returns `data.tau`.
template <class S, class Q>
const typename GeneralData<S>::VectorX& gravity_torques(const GeneralModel<S>& model, GeneralData<S>& data,
                                                        const Eigen::MatrixBase<Q>& q) {
  return rnea(model, data, q, data.zero, data.zero);
}

/// Joint-space inertia H(q) (nv × nv, both triangles) by CRBA (RBDA Table 6.2) with nvᵢ × nvⱼ blocks Hⱼᵢ = Sⱼᵀ Fᵢ,
/// Fᵢ = Iᶜᵢ Sᵢ, for j = i and i's ancestors, evaluated in base coordinates. Blocks coupling different branches are zero. Returns `data.H`.
template <class S, class Q>
const typename GeneralData<S>::MatrixX& crba(const GeneralModel<S>& model, GeneralData<S>& data,
                                             const Eigen::MatrixBase<Q>& q) {
  detail::check_general<true>(model, q, "crba", "q");
  detail::general_positions<false>(model, data, q, q);
  const int n = model.size();
  for (int i = 0; i < n; ++i) data.Ic[std::size_t(i)] = model.inertia(i);
  for (int i = n - 1; i >= 0; --i) {
    const int p = model.parent(i);
    if (p >= 0) data.Ic[std::size_t(p)] += data.Ic[std::size_t(i)].transformed_inverse(data.Xup[std::size_t(i)]);
  }
  // In base coordinates (RBDA §6.2's alternative form): Hₖₗ = (⁰Sₖ)ᵀ ⁰Fₗ for coordinate l of joint i and every
  // coordinate k on l's path to the root in the coordinates' tree (`dof_parent`), with ⁰Fₗ = ⁱX_0ᵀ Iᶜᵢ Sₗ; each
  // entry is one six-term dot product. The upper triangle, then the lower from it.
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < model.nv(i); ++c)
      data.Sw[std::size_t(model.idx_v(i) + c)] = detail::general_column_inverse(model, i, c, data.X0[std::size_t(i)]);
  data.H.setZero();
  for (int i = 0; i < n; ++i) {
    for (int c = 0, l = model.idx_v(i); c < model.nv(i); ++c, ++l) {
      const Force<S> F = data.X0[std::size_t(i)].apply_force_inverse(
          detail::general_inertia_column(model, i, c, data.Ic[std::size_t(i)]));
      for (int k = l; k >= 0; k = model.dof_parent(k)) data.H(k, l) = dot(data.Sw[std::size_t(k)], F);
    }
  }
  data.H.template triangularView<Eigen::StrictlyLower>() = data.H.transpose();
  return data.H;
}

/// Forward dynamics by the articulated-body algorithm (RBDA Table 7.1) with nvᵢ × nvᵢ blocks Dᵢ = Sᵢᵀ Iᴬᵢ Sᵢ
/// (inverted by Cholesky; a joint whose subtree has no inertia gives non-finite results). `fext` as for `rnea`.
/// Returns `data.qdd`.
template <class S, class Q, class V, class Tau, class Ext = NoExternalForces>
const typename GeneralData<S>::VectorX& aba(const GeneralModel<S>& model, GeneralData<S>& data,
                                            const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v,
                                            const Eigen::MatrixBase<Tau>& tau, const Ext& fext = Ext(),
                                            ForceFrame frame = ForceFrame::Body) {
  detail::check_general<true>(model, q, "aba", "q");
  detail::check_general<false>(model, v, "aba", "v");
  detail::check_general<false>(model, tau, "aba", "tau");
  const int n = model.size();
  detail::general_positions<true>(model, data, q, v);
  for (int i = 0; i < n; ++i) {
    const auto k = std::size_t(i);
    const Inertia<S>& I = model.inertia(i);
    data.c[k] = cross(data.v[k], detail::general_motion(model, i, v));
    data.IA[k] = ArticulatedInertia<S>(I);
    data.pA[k] = cross(data.v[k], I * data.v[k]);
    if constexpr (!std::is_same_v<Ext, NoExternalForces>) {
      data.pA[k] -= frame == ForceFrame::Body ? Force<S>(fext[k]) : data.X0[k].apply_force(fext[k]);
    } else {
      (void)fext, (void)frame;
    }
  }
  for (int i = n - 1; i >= 0; --i) {
    const auto k = std::size_t(i);
    const int ni = model.nv(i);
    auto& U = data.U[k];
    auto Dinv = data.Dinv[k].topLeftCorner(ni, ni);
    Matrix6<S> D;
    for (int c = 0; c < ni; ++c) {
      U[std::size_t(c)] = data.IA[k] * detail::general_column(model, i, c);
      detail::general_project(model, i, U[std::size_t(c)], &D(0, c));
    }
    detail::general_project(model, i, data.pA[k], data.u[k].data());
    auto u = data.u[k].head(ni);
    u = tau.segment(model.idx_v(i), ni) - u;
    const int p = model.parent(i);
    if (ni == 1) {
      Dinv(0, 0) = S(1) / D(0, 0);
      if (p < 0) continue;
      data.IA[k].subtract_outer(U[0], Dinv(0, 0));
    } else {
      // D = L Lᵀ: D⁻¹ from the factor, and U D⁻¹ Uᵀ = Σₖ Yₖ Yₖᵀ with Y = U L⁻ᵀ (forward substitution).
      using Small = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
      const Eigen::LLT<Small> llt{Small(D.topLeftCorner(ni, ni))};
      Dinv = llt.solve(Small::Identity(ni, ni));
      if (p < 0) continue;
      const Small& L = llt.matrixLLT();  // L in the lower triangle
      std::array<Force<S>, 6> Y;
      for (int c = 0; c < ni; ++c) {
        Force<S> y = U[std::size_t(c)];
        for (int e = 0; e < c; ++e) y -= L(c, e) * Y[std::size_t(e)];
        Y[std::size_t(c)] = (S(1) / L(c, c)) * y;
      }
      for (int c = 0; c < ni; ++c) data.IA[k].subtract_outer(Y[std::size_t(c)], S(1));
    }
    // pᵃ = pᴬ + Iᵃ c + U D⁻¹ u, carried to the parent with Iᵃ.
    Force<S> pa = data.pA[k] + data.IA[k] * data.c[k];
    const Eigen::Matrix<S, Eigen::Dynamic, 1, 0, 6, 1> Du = Dinv * u;
    for (int c = 0; c < ni; ++c) pa += Du[c] * U[std::size_t(c)];
    const Transform<S>& X = data.Xup[k];
    data.IA[std::size_t(p)] += data.IA[k].transformed_inverse(X);
    data.pA[std::size_t(p)] += X.apply_force_inverse(pa);
  }
  const Motion<S> a0(Vector3<S>::Zero(), -model.gravity());
  for (int i = 0; i < n; ++i) {
    const auto k = std::size_t(i);
    const int ni = model.nv(i), p = model.parent(i);
    const Motion<S> ap = data.Xup[k].apply(p < 0 ? a0 : data.a[std::size_t(p)]) + data.c[k];
    Eigen::Matrix<S, Eigen::Dynamic, 1, 0, 6, 1> r = data.u[k].head(ni);
    for (int c = 0; c < ni; ++c) r[c] -= dot(ap, data.U[k][std::size_t(c)]);
    auto qdd = data.qdd.segment(model.idx_v(i), ni);
    qdd.noalias() = data.Dinv[k].topLeftCorner(ni, ni) * r;
    data.a[k] = ap + detail::general_motion(model, i, data.qdd);
  }
  return data.qdd;
}

/// The Jacobian (6 × nv, rows linear first as in kinematics.hpp) of body `body` in `rf`, after
/// `forward_kinematics`: columns of body's ancestors' velocity coordinates, zero elsewhere.
template <class S, class Out>
void body_jacobian(const GeneralModel<S>& model, const GeneralData<S>& data, int body, ReferenceFrame rf,
                   const Eigen::MatrixBase<Out>& J_) {
  auto& J = const_cast<Eigen::MatrixBase<Out>&>(J_);
  J.setZero();
  const Transform<S>& Xb = data.X0[std::size_t(body)];
  for (int j = body; j >= 0; j = model.parent(j)) {
    const Transform<S>& Xj = data.X0[std::size_t(j)];
    for (int c = 0; c < model.nv(j); ++c) {
      const Motion<S> world = Xj.apply_inverse(Motion<S>(Vector6<S>(model.subspace(j).col(c))));
      detail::set_jacobian_column(J, model.idx_v(j) + c, detail::world_to_frame(rf, Xb, world));
    }
  }
}

/// Position of the centre of mass in base coordinates, after `forward_kinematics`; also fills `data.msub` and
/// `data.mc` (subtree masses and mass-weighted CoM sums) for `com_jacobian`. Returns `data.com`.
template <class S>
const Vector3<S>& center_of_mass(const GeneralModel<S>& model, GeneralData<S>& data) {
  for (int i = 0; i < model.size(); ++i) {
    const auto k = std::size_t(i);
    const Inertia<S>& I = model.inertia(i);
    data.msub[k] = I.m;
    data.mc[k] = I.m * data.X0[k].r + data.X0[k].E.transpose() * I.h;  // m · (base position of the CoM)
  }
  for (int i = model.size() - 1; i >= 0; --i) {
    const int p = model.parent(i);
    if (p < 0) continue;
    data.msub[std::size_t(p)] += data.msub[std::size_t(i)];
    data.mc[std::size_t(p)] += data.mc[std::size_t(i)];
  }
  data.com.setZero();
  S m = S(0);
  for (int i = 0; i < model.size(); ++i)
    if (model.parent(i) < 0) data.com += data.mc[std::size_t(i)], m += data.msub[std::size_t(i)];
  data.com /= m;
  return data.com;
}

/// The centre of mass's Jacobian (3 × nv, base coordinates), after `forward_kinematics` and `center_of_mass`: column
/// of joint j's coordinate = (m_sub v_O + ω × Σ mₖ cₖ) / M for its world motion [ω; v_O].
template <class S, class Out>
void com_jacobian(const GeneralModel<S>& model, const GeneralData<S>& data, const Eigen::MatrixBase<Out>& J_) {
  auto& J = const_cast<Eigen::MatrixBase<Out>&>(J_);
  const S M = model.total_mass();
  for (int j = 0; j < model.size(); ++j) {
    const auto k = std::size_t(j);
    for (int c = 0; c < model.nv(j); ++c) {
      const Motion<S> w = data.X0[k].apply_inverse(Motion<S>(Vector6<S>(model.subspace(j).col(c))));
      J.col(model.idx_v(j) + c) = (data.msub[k] * w.v + w.w.cross(data.mc[k])) / M;
    }
  }
}

/// ½ Σ vᵢᵀ Iᵢ vᵢ, after `forward_kinematics(q, v)`.
template <class S>
S kinetic_energy(const GeneralModel<S>& model, const GeneralData<S>& data) {
  S e = S(0);
  for (int i = 0; i < model.size(); ++i) e += dot(data.v[std::size_t(i)], model.inertia(i) * data.v[std::size_t(i)]);
  return e / S(2);
}
/// −Σ mᵢ g · cᵢ (zero at the base origin), after `forward_kinematics`.
template <class S>
S potential_energy(const GeneralModel<S>& model, const GeneralData<S>& data) {
  S e = S(0);
  for (int i = 0; i < model.size(); ++i) {
    const Transform<S>& X = data.X0[std::size_t(i)];
    e -= model.gravity().dot(model.inertia(i).m * X.r + X.E.transpose() * model.inertia(i).h);
  }
  return e;
}

// ---------------------------------------------------------------------------------------------------------------
// The one-DoF models in this form
// ---------------------------------------------------------------------------------------------------------------

/// A fixed-base model's tree as a `GeneralModel` (same bodies, joints, names, gravity; q, v, τ unchanged).
template <class S, class T>
GeneralModel<S> general_model(const Model<S, T>& model) {
  GeneralModel<S> out(model.gravity());
  for (int i = 0; i < model.size(); ++i)
    out.add_body(model.parent(i), GeneralJoint<S>::one_dof(model.joint_type(i), model.axis(i)),
                 model.tree_transform(i), model.inertia(i), model.joint_name(i), model.body_name(i));
  return out;
}
/// A floating model as a `GeneralModel`: body 0 the root on a free-flyer `floating_base`, then the tree's bodies
/// (body i ↦ i + 1). Its q, v and τ are the `FloatingModel`'s, entry for entry.
template <class S, class T>
GeneralModel<S> general_model(const FloatingModel<S, T>& model) {
  const auto& tree = model.tree();
  GeneralModel<S> out(tree.gravity());
  out.add_body(-1, GeneralJoint<S>::free_flyer(), Transform<S>::Identity(), model.root_inertia(), kFreeFlyerName,
               model.root_name());
  for (int i = 0; i < tree.size(); ++i)
    out.add_body(tree.parent(i) + 1, GeneralJoint<S>::one_dof(tree.joint_type(i), tree.axis(i)),
                 tree.tree_transform(i), tree.inertia(i), tree.joint_name(i), tree.body_name(i));
  return out;
}

}  // namespace spatial
