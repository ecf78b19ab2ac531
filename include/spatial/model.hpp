#pragma once
/// \file model.hpp
/// Kinematic trees (RBDA ch. 4): topology, the immutable `Model` and the preallocated `Data`.
///
/// Bodies are numbered 0 … n−1 so that every parent precedes its children (`parent(i) < i`); −1 is the fixed
/// base. Body i is connected to its parent by joint i, which has one degree of freedom, so q, q̇, q̈ and τ all have
/// n entries in body order. The transform from the parent body's coordinates to body i's is
/// ⁱX_λ(i) = X_J(qᵢ) X_T(i) (RBDA eq. 4.11): X_T(i) ("tree transform") locates joint i's frame in the parent
/// body, and X_J is the joint transform.
///
/// A tree is either a compile-time fact, `Model<S, Tree<Parents<…>, Joints<…>>>`, with the number of bodies, the
/// parent array and each joint type known to the compiler, or a run-time one, `Model<S>` (`DynamicTree`), loaded
/// from a file. The algorithms are written once for both and give the same numbers.

#include "spatial/algebra.hpp"
#include "spatial/joints.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

namespace spatial {

/// Error raised while building a model (never by the algorithms). Its message names the body or joint at fault.
class ModelError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

template <int... P>
struct Parents {};
template <JointType... J>
struct Joints {};

namespace detail {
template <std::size_t N>
constexpr bool parents_precede(const std::array<int, N>& p) {
  for (std::size_t i = 0; i < N; ++i)
    if (p[i] < -1 || p[i] >= static_cast<int>(i)) return false;
  return true;
}

/// An order of the bodies of a tree (`parent[i]`, −1 for the base) with every child before its parent, in which the
/// branches take turns: Kahn's algorithm from the leaves with a first-in first-out queue (the leaves in decreasing
/// index order first; a body joins the queue once its last child is done). On HOAP-3's stance tree (the other leg
/// and two arms hanging from the pelvis and chest above the stance leg) it begins 20, 14, 10, 19, 13, 9, …: bodies
/// next to each other seldom wait on each other, so that a backward pass whose steps form a chain of latencies (a
/// body's result feeds its parent's step) runs the branches' chains side by side. `queue` and `pending` are n
/// ints of scratch.
constexpr void interleaved_reverse_order(int n, const int* parent, int* out, int* queue, int* pending) {
  for (int i = 0; i < n; ++i) pending[i] = 0;
  for (int i = 0; i < n; ++i)
    if (parent[i] >= 0) ++pending[parent[i]];
  int tail = 0;
  for (int i = n - 1; i >= 0; --i)
    if (pending[i] == 0) queue[tail++] = i;
  for (int head = 0; head < n; ++head) {
    const int i = queue[head];
    out[head] = i;
    const int p = parent[i];
    if (p >= 0 && --pending[p] == 0) queue[tail++] = p;
  }
}
}  // namespace detail

/// A compile-time topology: `Tree<Parents<-1, 0, 1>, Joints<JointType::RevoluteZ, …>>`.
template <class P, class J>
struct Tree;
template <int... P, JointType... J>
struct Tree<Parents<P...>, Joints<J...>> {
  static_assert(sizeof...(P) == sizeof...(J), "one joint type per body");
  static constexpr int size = static_cast<int>(sizeof...(P));
  static constexpr std::array<int, sizeof...(P)> parent{{P...}};
  static constexpr std::array<JointType, sizeof...(J)> joint{{J...}};
  static_assert(detail::parents_precede(parent), "every parent must precede its child (-1 = base)");
};

/// The topology of a model loaded at run time.
struct DynamicTree {};

template <class TreeT>
inline constexpr bool is_static_tree_v = !std::is_same_v<TreeT, DynamicTree>;

/// Largest compile-time tree whose joint-space matrices are fixed-size Eigen objects; above it they are allocated
/// once, when the `Data` is built (Eigen refuses fixed-size objects over 128 KiB).
inline constexpr int kMaxFixedMatrixSize = 64;

template <class S>
struct FixedFrame {
  std::string name;
  int body;              ///< the moving body the frame is attached to (-1: the base)
  Transform<S> X;        ///< ᶠX_body: from the body's coordinates to the frame's
};

template <class S>
class ModelBuilder;

namespace detail {
struct ModelAccess;  // reduce.hpp: edits the frames and base mass of a model it builds
}  // namespace detail

/// The immutable description of a tree: topology, joint types and axes, tree transforms, body inertias and
/// gravity. Build it with `ModelBuilder` (run time) or `Model<S, Tree>::from(…)` (compile time, checked).
template <class S, class TreeT = DynamicTree>
class Model {
 public:
  using Scalar = S;
  using tree_type = TreeT;
  static constexpr bool is_static = is_static_tree_v<TreeT>;
  static constexpr int NB = [] {
    if constexpr (is_static_tree_v<TreeT>) return TreeT::size;
    else return int(Eigen::Dynamic);
  }();
  template <class T>
  using Array = std::conditional_t<is_static, std::array<T, (is_static ? std::size_t(NB) : 0)>, std::vector<T>>;

  /// Number of bodies (= number of joints = degrees of freedom).
  int size() const {
    if constexpr (is_static) return NB;
    else return static_cast<int>(parent_.size());
  }
  int nv() const { return size(); }

  /// λ(i): parent body of body i, -1 for the base.
  template <int I>
  static constexpr int parent(std::integral_constant<int, I>) {
    return TreeT::parent[I];
  }
  int parent(int i) const {
    if constexpr (is_static) return TreeT::parent[static_cast<std::size_t>(i)];
    else return parent_[static_cast<std::size_t>(i)];
  }
  /// The type of joint i.
  JointType joint_type(int i) const {
    if constexpr (is_static) return TreeT::joint[static_cast<std::size_t>(i)];
    else return type_[static_cast<std::size_t>(i)];
  }
  /// The model of joint i: a `Joint<S, type>` when i is a compile-time index of a compile-time tree, otherwise a
  /// `RuntimeJoint<S>`.
  template <int I>
  auto joint(std::integral_constant<int, I>) const {
    if constexpr (is_static) return Joint<S, TreeT::joint[I]>(axis_[I]);
    else return joint(I);
  }
  RuntimeJoint<S> joint(int i) const { return RuntimeJoint<S>{joint_type(i), axis_[static_cast<std::size_t>(i)]}; }
  /// True when every joint is a revolute joint about a coordinate axis (RevoluteX/Y/Z): the trees that the AVX2
  /// kernels of simd.hpp serve, compile-time or run-time.
  /// Kept with the model (set wherever its joint types are), so that the per-call dispatch of a run-time tree
  /// costs one load.
  bool revolute_axes_only() const {
    if constexpr (is_static) return axes_only_of_types_();
    else return axes_only_;
  }

  /// X_T(i): from the parent body's coordinates to joint i's predecessor frame.
  const Transform<S>& tree_transform(int i) const { return Xtree_[static_cast<std::size_t>(i)]; }
  /// Spatial inertia of body i in its own coordinates (fixed children already merged in).
  const Inertia<S>& inertia(int i) const { return I_[static_cast<std::size_t>(i)]; }
  /// Joint axis of body i (unit vector in body coordinates; meaningful for the *Axis joint types, and filled in
  /// with the coordinate axis for the others).
  const Vector3<S>& axis(int i) const { return axis_[static_cast<std::size_t>(i)]; }
  /// Gravity g as a 3D vector in base coordinates (default (0, 0, −9.81) m/s²).
  const Vector3<S>& gravity() const { return g_; }
  /// Spatial gravity acceleration a_g = [0; g] in base coordinates; RNEA starts from a₀ = −a_g (RBDA §5.3).
  Motion<S> gravity_motion() const { return Motion<S>(Vector3<S>::Zero(), g_); }

  const std::string& body_name(int i) const { return body_names_[static_cast<std::size_t>(i)]; }
  const std::string& joint_name(int i) const { return joint_names_[static_cast<std::size_t>(i)]; }
  /// Index of the body with the given name, or -1.
  int body_index(const std::string& name) const {
    for (int i = 0; i < size(); ++i)
      if (body_names_[static_cast<std::size_t>(i)] == name) return i;
    return -1;
  }
  /// Index of the joint with the given name, or -1.
  int joint_index(const std::string& name) const {
    for (int i = 0; i < size(); ++i)
      if (joint_names_[static_cast<std::size_t>(i)] == name) return i;
    return -1;
  }
  /// Frames attached rigidly to bodies (the folded fixed joints: feet, hands, sensors).
  const std::vector<FixedFrame<S>>& frames() const { return frames_; }
  /// Index in `frames()` of the fixed frame with the given name, or -1.
  int frame_index(const std::string& name) const {
    for (std::size_t k = 0; k < frames_.size(); ++k)
      if (frames_[k].name == name) return static_cast<int>(k);
    return -1;
  }
  /// Mass of the base (fixed bodies merged into the base); it moves nothing.
  S base_mass() const { return base_mass_; }

  /// Total mass of body i and all its descendants.
  S subtree_mass(int i) const {
    S m = S(0);
    for (int k = i; k < size(); ++k)
      if (is_ancestor_or_self(i, k)) m += inertia(k).m;
    return m;
  }
  /// Total mass of the moving bodies.
  S total_mass() const {
    S m = S(0);
    for (int k = 0; k < size(); ++k) m += inertia(k).m;
    return m;
  }
  /// True when body `a` is body `b` or one of its ancestors.
  bool is_ancestor_or_self(int a, int b) const {
    for (int k = b; k >= 0; k = parent(k))
      if (k == a) return true;
    return false;
  }
  /// Joints whose subtree carries no mass (and no rotational inertia): they make H singular.
  std::vector<int> massless_joints() const {
    std::vector<int> out;
    for (int i = 0; i < size(); ++i) {
      bool moves_inertia = false;
      for (int k = i; k < size(); ++k)
        if (is_ancestor_or_self(i, k) && (inertia(k).m > S(0) || inertia(k).I.norm() > S(0))) moves_inertia = true;
      if (!moves_inertia) out.push_back(i);
    }
    return out;
  }

  /// The same model with another gravity vector.
  Model with_gravity(const Vector3<S>& g) const {
    Model m = *this;
    m.g_ = g;
    return m;
  }

  /// The same model as a run-time tree (`Model<S>`): the same numbers, names, frames and base mass, so every
  /// algorithm gives the same results through the run-time code paths (tests, benchmarks, run-time-only tools).
  Model<S, DynamicTree> to_runtime() const {
    Model<S, DynamicTree> out;
    out.resize_(size());
    for (int i = 0; i < size(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      out.Xtree_[k] = Xtree_[k];
      out.I_[k] = I_[k];
      out.axis_[k] = axis_[k];
      out.parent_[k] = parent(i);
      out.type_[k] = joint_type(i);
    }
    out.axes_only_ = out.axes_only_of_types_();
    out.g_ = g_;
    out.body_names_ = body_names_;
    out.joint_names_ = joint_names_;
    out.frames_ = frames_;
    out.base_mass_ = base_mass_;
    return out;
  }

  /// The same model in another scalar type (e.g. long double as an accuracy reference).
  template <class T>
  Model<T, TreeT> cast() const {
    Model<T, TreeT> out;
    out.resize_(size());
    for (int i = 0; i < size(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      out.Xtree_[k] = Xtree_[k].template cast<T>();
      out.I_[k] = I_[k].template cast<T>();
      out.axis_[k] = axis_[k].template cast<T>();
    }
    if constexpr (!is_static) {
      out.parent_ = parent_;
      out.type_ = type_;
      out.axes_only_ = axes_only_;
    }
    out.g_ = g_.template cast<T>();
    out.body_names_ = body_names_;
    out.joint_names_ = joint_names_;
    out.base_mass_ = T(base_mass_);
    for (const auto& f : frames_) out.frames_.push_back({f.name, f.body, f.X.template cast<T>()});
    return out;
  }

  /// A compile-time model from a run-time one; throws `ModelError` unless sizes, parents and joint types match.
  template <class OtherTree>
  static Model from(const Model<S, OtherTree>& other) {
    static_assert(is_static, "Model::from converts into a compile-time model");
    if (other.size() != NB) {
      std::ostringstream os;
      os << "model size mismatch: the compile-time tree has " << NB << " bodies, the model has " << other.size();
      if (other.size() > NB)
        os << " (body " << NB << " '" << other.body_name(NB) << "' has no counterpart in the tree)";
      else if (other.size() > 0)
        os << " (the model ends at body " << other.size() - 1 << " '" << other.body_name(other.size() - 1) << "')";
      throw ModelError(os.str());
    }
    Model out;
    for (int i = 0; i < NB; ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (other.parent(i) != TreeT::parent[k] || other.joint_type(i) != TreeT::joint[k]) {
        std::ostringstream os;
        os << "model topology mismatch at body " << i << " '" << other.body_name(i) << "' (joint '"
           << other.joint_name(i) << "'): the compile-time tree expects parent " << TreeT::parent[k] << " and "
           << joint_type_name(TreeT::joint[k]) << ", the model has parent " << other.parent(i) << " and "
           << joint_type_name(other.joint_type(i));
        throw ModelError(os.str());
      }
      out.Xtree_[k] = other.tree_transform(i);
      out.I_[k] = other.inertia(i);
      out.axis_[k] = other.axis(i);
    }
    out.g_ = other.gravity();
    out.body_names_.clear();
    out.joint_names_.clear();
    for (int i = 0; i < NB; ++i) {
      out.body_names_.push_back(other.body_name(i));
      out.joint_names_.push_back(other.joint_name(i));
    }
    out.frames_ = other.frames();
    out.base_mass_ = other.base_mass();
    return out;
  }

  /// A compile-time model straight from its numbers, without `ModelBuilder` (the generated models of src/models,
  /// written by tools/spatial-gen, are built this way). Per body i, in model order: `X_tree[i]` (= `tree_transform(i)`),
  /// `inertia[i]` (= `inertia(i)`: body coordinates, fixed children already merged), `axis[i]` (= `axis(i)`: ignored
  /// and set to the coordinate axis for the X/Y/Z joint types, normalised for the *Axis types), the body and joint
  /// names; then gravity (base coordinates), the fixed frames and the mass merged into the base. Checks what
  /// `ModelBuilder` checks (rigid finite transforms, physical inertias, non-zero axes, frames attached to existing
  /// bodies) and throws `ModelError` naming the body or frame at fault. Like a default `ModelBuilder` it accepts
  /// inertias whose principal moments break the triangle inequality; when `warnings` is given, one message per such
  /// body is appended to it (`ModelBuilder::warnings`).
  static Model from_arrays(const Array<Transform<S>>& X_tree, const Array<Inertia<S>>& inertia,
                           const Array<Vector3<S>>& axis, const Array<std::string>& body_names,
                           const Array<std::string>& joint_names, const Vector3<S>& gravity,
                           std::vector<FixedFrame<S>> frames = {}, S base_mass = S(0),
                           std::vector<std::string>* warnings = nullptr);

  Model() {
    g_ = Vector3<S>(S(0), S(0), S(-9.81));
    if constexpr (is_static) resize_(NB);
  }

 private:
  template <class, class>
  friend class Model;
  friend class ModelBuilder<S>;
  friend struct detail::ModelAccess;

  bool axes_only_of_types_() const {
    for (int i = 0; i < size(); ++i)
      if (joint_type(i) > JointType::RevoluteZ) return false;
    return true;
  }
  void resize_(int n) {
    if constexpr (!is_static) {
      const auto k = static_cast<std::size_t>(n);
      Xtree_.resize(k);
      I_.resize(k);
      axis_.resize(k);
      parent_.resize(k);
      type_.resize(k);
    }
    body_names_.assign(static_cast<std::size_t>(n), std::string());
    joint_names_.assign(static_cast<std::size_t>(n), std::string());
  }

  Array<Transform<S>> Xtree_{};
  Array<Inertia<S>> I_{};
  Array<Vector3<S>> axis_{};
  std::vector<int> parent_;      // run-time trees only
  std::vector<JointType> type_;  // run-time trees only
  bool axes_only_ = true;        // run-time trees only: revolute_axes_only()
  Vector3<S> g_;
  std::vector<std::string> body_names_, joint_names_;
  std::vector<FixedFrame<S>> frames_;
  S base_mass_ = S(0);
};

namespace detail {
template <class S>
bool all_finite(const Transform<S>& X) {
  return X.E.allFinite() && X.r.allFinite();
}
template <class S>
bool all_finite(const Inertia<S>& I) {
  using std::isfinite;
  return isfinite(I.m) && I.h.allFinite() && I.I.allFinite();
}

/// What is wrong with an inertia. `error`: something the algorithms cannot work with (NaN/Inf, negative mass, an
/// asymmetric rotational inertia, zero mass with a non-zero first moment, a rotational inertia about the centre of
/// mass that is not positive semi-definite); always refused. `warning`: physically impossible but numerically
/// harmless (principal moments breaking the triangle inequality I1 + I2 >= I3: the spatial inertia stays positive
/// semi-definite, as CAD exports of published robots often have it); refused only in strict mode. Both empty: fine.
struct InertiaProblem {
  std::string error;
  std::string warning;
  /// The reason to refuse the inertia (the error, or in strict mode the warning too), or an empty string.
  std::string refusal(bool strict) const { return !error.empty() || !strict ? error : warning; }
};

/// The one check of an inertia shared by `ModelBuilder`, `Model::from_arrays` and the URDF loader.
template <class S>
InertiaProblem inertia_problem(const Inertia<S>& I) {
  InertiaProblem out;
  if (!all_finite(I)) return {"mass properties contain NaN or Inf", {}};
  if (I.m < S(0)) return {"negative mass", {}};
  const S scale = std::max<S>(S(1), I.I.cwiseAbs().maxCoeff());
  const S tol = S(64) * std::numeric_limits<S>::epsilon() * scale;
  if ((I.I - I.I.transpose()).cwiseAbs().maxCoeff() > tol) return {"rotational inertia is not symmetric", {}};
  if (I.m == S(0)) {
    if (I.h.norm() > tol) return {"zero mass with a non-zero first moment", {}};
  }
  const Matrix3<S> Ic = I.m > S(0) ? I.inertia_com() : I.I;
  Eigen::SelfAdjointEigenSolver<Matrix3<S>> es(Ic, Eigen::EigenvaluesOnly);
  const Vector3<S> ev = es.eigenvalues();  // ascending
  if (ev[0] < -tol) return {"rotational inertia about the centre of mass is not positive semi-definite", {}};
  if (ev[0] + ev[1] < ev[2] - tol) {
    const S sum = ev[0] + ev[1], short_by = ev[2] - sum;
    std::ostringstream os;
    os << "principal moments violate the triangle inequality: I1 + I2 = " << sum << " < I3 = " << ev[2]
       << " kg m^2 (short by " << short_by << ", " << std::setprecision(3)
       << (ev[2] > S(0) ? S(100) * short_by / ev[2] : S(100)) << " %)";
    out.warning = os.str();
  }
  return out;
}
template <class S>
bool is_rotation(const Matrix3<S>& E) {
  // 1e-9, but never below what the scalar can represent (a float rotation is orthonormal only to ~1e-7).
  const S tol = std::max(S(1e-9), S(64) * std::numeric_limits<S>::epsilon());
  return (E * E.transpose() - Matrix3<S>::Identity()).cwiseAbs().maxCoeff() < tol && E.determinant() > S(0);
}
}  // namespace detail

template <class S, class TreeT>
Model<S, TreeT> Model<S, TreeT>::from_arrays(const Array<Transform<S>>& X_tree, const Array<Inertia<S>>& inertia,
                                             const Array<Vector3<S>>& axis, const Array<std::string>& body_names,
                                             const Array<std::string>& joint_names, const Vector3<S>& gravity,
                                             std::vector<FixedFrame<S>> frames, S base_mass,
                                             std::vector<std::string>* warnings) {
  static_assert(is_static, "Model::from_arrays builds compile-time models; use ModelBuilder for run-time trees");
  Model out;
  if (!gravity.allFinite()) throw ModelError("gravity contains NaN or Inf");
  std::vector<std::string> found;
  for (int i = 0; i < NB; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const std::string what = "body " + std::to_string(i) + " '" + body_names[k] + "' (joint '" + joint_names[k] + "')";
    if (!detail::all_finite(X_tree[k]) || !detail::is_rotation(X_tree[k].E))
      throw ModelError(what + ": joint placement is not a finite rigid transform");
    const detail::InertiaProblem bad = detail::inertia_problem(inertia[k]);
    if (!bad.error.empty()) throw ModelError(what + ": " + bad.error);
    if (!bad.warning.empty()) found.push_back(what + ": " + bad.warning);
    Vector3<S> a = axis[k];
    switch (TreeT::joint[k]) {
      case JointType::RevoluteX: case JointType::PrismaticX: a = Vector3<S>::UnitX(); break;
      case JointType::RevoluteY: case JointType::PrismaticY: a = Vector3<S>::UnitY(); break;
      case JointType::RevoluteZ: case JointType::PrismaticZ: a = Vector3<S>::UnitZ(); break;
      case JointType::RevoluteAxis:
      case JointType::PrismaticAxis:
        if (!a.allFinite() || !(a.norm() > S(0))) throw ModelError(what + ": joint axis is zero or not finite");
        a.normalize();
        break;
    }
    out.Xtree_[k] = X_tree[k];
    out.I_[k] = inertia[k];
    out.axis_[k] = a;
    out.body_names_[k] = body_names[k];
    out.joint_names_[k] = joint_names[k].empty() ? body_names[k] : joint_names[k];
  }
  for (const FixedFrame<S>& f : frames) {
    if (f.body < -1 || f.body >= NB)
      throw ModelError("fixed frame '" + f.name + "': body " + std::to_string(f.body) + " is not a body of the model");
    if (!detail::all_finite(f.X) || !detail::is_rotation(f.X.E))
      throw ModelError("fixed frame '" + f.name + "': placement is not a finite rigid transform");
  }
  using std::isfinite;
  if (!isfinite(base_mass) || base_mass < S(0)) throw ModelError("base mass is negative or not finite");
  out.g_ = gravity;
  out.frames_ = std::move(frames);
  out.base_mass_ = base_mass;
  if (warnings != nullptr) warnings->insert(warnings->end(), found.begin(), found.end());
  return out;
}

/// Builds a run-time `Model<S>` body by body, checking every input; `build()` returns a complete model or throws
/// `ModelError` naming the body at fault (the builder's own state is left as it was before the failing call).
///
/// Inertias: what the algorithms cannot work with is always refused (see `detail::InertiaProblem`). An inertia whose
/// principal moments break the triangle inequality (physically impossible, numerically harmless; common in CAD
/// exports) is accepted with a message in `warnings()`, unless `set_strict_inertia(true)`, which refuses it.
template <class S = double>
class ModelBuilder {
 public:
  ModelBuilder() { model_.g_ = Vector3<S>(S(0), S(0), S(-9.81)); }

  /// true: refuse inertias that break the triangle inequality (`ModelError`) instead of warning. Default false.
  void set_strict_inertia(bool strict) { strict_inertia_ = strict; }
  bool strict_inertia() const { return strict_inertia_; }
  /// One message per body or fixed body accepted with a physically impossible inertia, in the order added, e.g.
  /// "body 'foot' (joint 'ankle'): principal moments violate the triangle inequality: I1 + I2 = 0.02 < I3 = 0.03
  /// kg m^2 (short by 0.01, 33.3 %)".
  const std::vector<std::string>& warnings() const { return warnings_; }

  void set_gravity(const Vector3<S>& g) {
    if (!g.allFinite()) throw ModelError("gravity contains NaN or Inf");
    model_.g_ = g;
  }

  /// Adds a body connected to `parent` (-1: the base) by a one-DoF joint. `X_tree` is ʲX_λ: from the parent's
  /// coordinates to the joint frame; the joint then moves the body frame relative to the joint frame. `inertia` is
  /// in the body's coordinates; `axis` is used by the *Axis joint types and must be non-zero (it is normalised).
  /// Returns the new body's index.
  int add_body(const std::string& name, int parent, JointType type, const Transform<S>& X_tree,
               const Inertia<S>& inertia, const Vector3<S>& axis = Vector3<S>::Zero(),
               const std::string& joint_name = std::string()) {
    const int index = model_.size();
    const std::string what = "body '" + name + "'" + (joint_name.empty() ? "" : " (joint '" + joint_name + "')");
    if (parent < -1 || parent >= index) {
      std::ostringstream os;
      os << what << ": parent index " << parent << " does not precede the body (index " << index << ")";
      throw ModelError(os.str());
    }
    if (!detail::all_finite(X_tree) || !detail::is_rotation(X_tree.E))
      throw ModelError(what + ": joint placement is not a finite rigid transform");
    const detail::InertiaProblem bad = detail::inertia_problem(inertia);
    if (const std::string refused = bad.refusal(strict_inertia_); !refused.empty())
      throw ModelError(what + ": " + refused);
    Vector3<S> a = axis;
    switch (type) {
      case JointType::RevoluteX: case JointType::PrismaticX: a = Vector3<S>::UnitX(); break;
      case JointType::RevoluteY: case JointType::PrismaticY: a = Vector3<S>::UnitY(); break;
      case JointType::RevoluteZ: case JointType::PrismaticZ: a = Vector3<S>::UnitZ(); break;
      case JointType::RevoluteAxis:
      case JointType::PrismaticAxis:
        if (!a.allFinite() || !(a.norm() > S(0))) throw ModelError(what + ": joint axis is zero or not finite");
        a.normalize();
        break;
    }
    model_.Xtree_.push_back(X_tree);
    model_.I_.push_back(inertia);
    model_.axis_.push_back(a);
    model_.parent_.push_back(parent);
    model_.type_.push_back(type);
    model_.axes_only_ = model_.axes_only_ && type <= JointType::RevoluteZ;
    model_.body_names_.push_back(name);
    model_.joint_names_.push_back(joint_name.empty() ? name : joint_name);
    if (!bad.warning.empty()) warnings_.push_back(what + ": " + bad.warning);
    return index;
  }

  /// Attaches a rigid frame to `parent` (-1: the base) at ᶠX_parent = `X`, carrying `inertia` (in the frame's
  /// coordinates), which is merged exactly into the parent body (dropped onto the base when parent is -1).
  void add_fixed_body(const std::string& name, int parent, const Transform<S>& X, const Inertia<S>& inertia) {
    const std::string what = "fixed body '" + name + "'";
    if (parent < -1 || parent >= model_.size()) {
      std::ostringstream os;
      os << what << ": parent index " << parent << " is not a body of the model";
      throw ModelError(os.str());
    }
    if (!detail::all_finite(X) || !detail::is_rotation(X.E))
      throw ModelError(what + ": placement is not a finite rigid transform");
    const detail::InertiaProblem bad = detail::inertia_problem(inertia);
    if (const std::string refused = bad.refusal(strict_inertia_); !refused.empty())
      throw ModelError(what + ": " + refused);
    if (parent >= 0)
      model_.I_[static_cast<std::size_t>(parent)] += inertia.transformed_inverse(X);
    else
      model_.base_mass_ += inertia.m;
    model_.frames_.push_back({name, parent, X});
    if (!bad.warning.empty()) warnings_.push_back(what + ": " + bad.warning);
  }

  int size() const { return model_.size(); }
  const Model<S>& peek() const { return model_; }

  /// The finished model.
  Model<S> build() const { return model_; }

 private:
  Model<S> model_;
  bool strict_inertia_ = false;
  std::vector<std::string> warnings_;
};

namespace detail {
template <class S, int N>
using JointVector = Eigen::Matrix<S, N, 1>;
constexpr int matrix_dim(int nb) { return (nb != Eigen::Dynamic && nb <= kMaxFixedMatrixSize) ? nb : Eigen::Dynamic; }
/// 64 aligned bytes of `Data::work`; each body of a run-time tree gets kWorkBlocksPerBody of them (1 KiB: the
/// largest per-body record, ABA's in double, takes ~0.9 KiB).
struct alignas(64) WorkBlock {
  unsigned char bytes[64];
};
inline constexpr std::size_t kWorkBlocksPerBody = 16;
}  // namespace detail

/// Per-call buffers of every algorithm, allocated once here (fixed-size for compile-time trees) and never again.
/// All per-body quantities are in that body's coordinates unless said otherwise.
template <class S, class TreeT = DynamicTree>
struct Data {
  using ModelType = Model<S, TreeT>;
  static constexpr int NB = ModelType::NB;
  static constexpr int NM = detail::matrix_dim(NB);
  template <class T>
  using Array = typename ModelType::template Array<T>;
  using VectorN = Eigen::Matrix<S, NB, 1>;
  using MatrixN = Eigen::Matrix<S, NM, NM>;

  explicit Data(const ModelType& model) {
    const int n = model.size();
    if constexpr (!ModelType::is_static) {
      const auto k = static_cast<std::size_t>(n);
      X_up.resize(k); X_base.resize(k); v.resize(k); a.resize(k); f.resize(k); c.resize(k);
      Ic.resize(k); S_base.resize(k); IA.resize(k); pA.resize(k); U.resize(k); Dinv.resize(k); u.resize(k);
    }
    tau = VectorN::Zero(n);
    qdd = VectorN::Zero(n);
    tmp = VectorN::Zero(n);
    cos_q = VectorN::Zero(n);
    sin_q = VectorN::Zero(n);
    H = MatrixN::Zero(n, n);
    L = MatrixN::Zero(n, n);
    J = decltype(J)::Zero(6, n), dJ = J;
    if constexpr (!ModelType::is_static && (std::is_same_v<S, double> || std::is_same_v<S, float>))
      work.resize(static_cast<std::size_t>(n) * detail::kWorkBlocksPerBody);
  }

  Array<Transform<S>> X_up{};    ///< ⁱX_λ(i): parent coordinates → body i coordinates
  Array<Transform<S>> X_base{};  ///< ⁱX_0: base coordinates → body i coordinates (forward kinematics)
  Array<Motion<S>> v{};          ///< body velocities
  Array<Motion<S>> a{};          ///< body accelerations (RNEA/ABA: including the fictitious −a_g, RBDA §5.3)
  Array<Force<S>> f{};           ///< RNEA: force transmitted across joint i from body λ(i) to body i
  Array<Motion<S>> c{};          ///< ABA: velocity-product acceleration cᵢ = vᵢ × S q̇
  Array<Inertia<S>> Ic{};        ///< CRBA: composite inertia of the subtree rooted at i
  Array<Motion<S>> S_base{};     ///< CRBA: joint i's motion subspace Sᵢ in base coordinates (ⁱX_0⁻¹ Sᵢ)
  Array<ArticulatedInertia<S>> IA{};  ///< ABA: articulated-body inertias
  Array<Force<S>> pA{};          ///< ABA: bias forces
  Array<Force<S>> U{};           ///< ABA: Uᵢ = I^A S
  Array<S> Dinv{};               ///< ABA: 1 / (Sᵀ U)
  Array<S> u{};                  ///< ABA: τ − Sᵀ p^A
  VectorN tau;                   ///< joint forces (RNEA output)
  VectorN qdd;                   ///< joint accelerations (forward dynamics output)
  VectorN tmp;                   ///< scratch: right-hand side of forward dynamics by CRBA
  VectorN cos_q, sin_q;          ///< cos qᵢ and sin qᵢ of the last configuration whose transforms were computed
  MatrixN H;                     ///< joint-space inertia (CRBA output); only ancestor–descendant entries non-zero
  MatrixN L;                     ///< LTDL factor of H: unit L below the diagonal, D on the diagonal
  Eigen::Matrix<S, 6, NM> J, dJ; ///< kinematics.hpp: joint Jacobians (World, rows linear first) and their J̇
  /// centroidal.hpp: centre of mass, its velocity and acceleration (base coordinates)
  Vector3<S> com = Vector3<S>::Zero(), vcom = Vector3<S>::Zero(), acom = Vector3<S>::Zero();
  /// Run-time trees in double or float: the per-body workspace of the AVX2 kernels (simd.hpp), which compile-time
  /// trees keep on the stack.
  std::vector<detail::WorkBlock> work{};
};

}  // namespace spatial
