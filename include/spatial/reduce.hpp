#pragma once
/// \file reduce.hpp
/// Model reduction for scenes that move only part of the robot: lock joints at fixed positions (their bodies are
/// merged exactly into the nearest moving ancestor, or into the fixed base), or keep only the joints or branches a
/// scene moves. The result is a run-time `Model<S>` with fewer bodies, and the map from its joints to the original
/// ones. Reduction runs once, when the scene is set up (it allocates and may throw `ModelError`); the reduced model
/// then runs every algorithm at the cost of its own size.
///
/// What is merged, and why it is exact. Lock joint i at qᵢ = θ: body i is then rigidly attached to its parent, at
/// ⁱX_λ = X_J(θ) X_T(i). Walking up through locked joints to the nearest moving ancestor a (or to the base),
/// ⁱX_a = ⁱX_λ ᵏX_a … is a constant, and
///   - body i's inertia is added into a's: I_a += ⁱX_aᵀ Iᵢ ⁱX_a (RBDA eq. 2.66), exactly the inertia of the rigid
///     union, so a's RNEA force I_a a_a + v_a ×* I_a v_a, its CRBA composite inertia and its ABA articulated inertia
///     are those of the union;
///   - a moving child c of a locked body is re-attached to a with X_T′(c) = X_T(c) ⁱX_a;
///   - fixed frames on a locked body move to a with ᶠX_a = ᶠXᵢ ⁱX_a, and each locked body leaves a frame of its
///     own name at its body frame (so its pose stays available to `frame_pose`; for a model loaded from URDF the
///     body frame of a re-rooted or axis-aligned joint is not the link frame, see urdf.hpp);
///   - bodies that end up on the base add their mass to `base_mass()`; they cost nothing at run time.
///
/// The "frozen branch" is this merge. A branch B held at fixed angles on a parent body P is one rigid body; its
/// load on P under any motion of P (velocity v_P, acceleration a_P, which includes −a_g) is
///   f_B = I_B a_P + v_P ×* I_B v_P,   I_B = Σ_{k∈B} ᵏX_Pᵀ I_k ᵏX_P (constant),
/// and its gravity load alone, −I_B ᴾX₀ a_g, depends only on P's orientation. A table of that load per
/// configuration of P would still cost one inertia–motion product per call; merging I_B into I_P makes P's own
/// product I_P a_P carry it, so the merged model pays nothing extra, for gravity and for P's motion alike. Where
/// a branch is not rigid (its joints move), no precomputation is exact and the branch must stay in the model.
///
///   auto arms = keep_branches(model, {"R_SFE", "L_SFE"}, q);  // body (link) names: the arms move, the rest is
///   arms.gather(q, q_arms);                                   // held at q; q_arms: the reduced model's joints
///
/// A scene that holds the other joints still (q̇ = q̈ = 0 there) gets from the reduced model exactly the torques of
/// the kept joints that the full model gives (tests/test_reduce.cpp).

#include "spatial/model.hpp"
#include "spatial/names.hpp"

#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace spatial {

namespace detail {
struct ModelAccess {
  template <class S>
  static std::vector<FixedFrame<S>>& frames(Model<S>& m) {
    return m.frames_;
  }
  template <class S>
  static S& base_mass(Model<S>& m) {
    return m.base_mass_;
  }
};
}  // namespace detail

/// A joint (or the body it moves) by name or by index.
struct JointRef {
  std::string name;
  int index = -1;
  JointRef(std::string n) : name(std::move(n)) {}  // NOLINT: implicit on purpose ({"name", angle})
  JointRef(const char* n) : name(n) {}             // NOLINT
  JointRef(int i) : index(i) {}                    // NOLINT
};

/// A joint held at a fixed position (rad or m).
struct JointLock {
  JointRef joint;
  double position;
};

/// A model reduced by `lock_joints`, `keep_joints` or `keep_branches`.
template <class S>
struct ReducedModel {
  Model<S> model;
  std::vector<int> joints;   ///< joints[k]: index in the original model of the reduced model's joint k
  std::vector<int> locked;   ///< the original model's joints that were locked, ascending
  std::vector<S> locked_at;  ///< their positions

  /// out[k] = full[joints[k]]: the reduced model's entries of a vector of the original model (q, q̇, τ, …).
  template <class Full, class Out>
  void gather(const Eigen::MatrixBase<Full>& full, Eigen::MatrixBase<Out>& out) const {
    for (std::size_t k = 0; k < joints.size(); ++k) out[static_cast<Eigen::Index>(k)] = full[joints[k]];
  }
  /// full[joints[k]] = reduced[k]; the entries of locked joints are left as they are.
  template <class Red, class Full>
  void scatter(const Eigen::MatrixBase<Red>& reduced, Eigen::MatrixBase<Full>& full) const {
    for (std::size_t k = 0; k < joints.size(); ++k) full[joints[k]] = reduced[static_cast<Eigen::Index>(k)];
  }
};

namespace detail {
template <class S, class T>
std::vector<std::string> joint_names_of(const Model<S, T>& model) {
  std::vector<std::string> out;
  for (int i = 0; i < model.size(); ++i) out.push_back(model.joint_name(i));
  return out;
}
template <class S, class T>
std::vector<std::string> body_names_of(const Model<S, T>& model) {
  std::vector<std::string> out;
  for (int i = 0; i < model.size(); ++i) out.push_back(model.body_name(i));
  return out;
}
template <class S, class T>
int resolve_joint(const Model<S, T>& model, const JointRef& j, const char* who) {
  if (!j.name.empty()) {
    const int i = model.joint_index(j.name);
    if (i < 0) {
      std::string msg = std::string(who) + ": the model has no joint '" + j.name + "'";
      const int b = model.body_index(j.name);
      if (b >= 0)
        msg += " ('" + j.name + "' is a body (link) name: the joint that moves it is '" + model.joint_name(b) + "')";
      else msg += did_you_mean(j.name, joint_names_of(model));
      throw ModelError(msg);
    }
    return i;
  }
  if (j.index < 0 || j.index >= model.size()) {
    std::ostringstream os;
    os << who << ": joint index " << j.index << " is not a joint of the model (it has " << model.size() << ")";
    throw ModelError(os.str());
  }
  return j.index;
}
template <class S, class T>
std::string joint_label(const Model<S, T>& model, int i) {
  return "joint " + std::to_string(i) + " '" + model.joint_name(i) + "'";
}

template <class S, class T>
ReducedModel<S> lock_resolved(const Model<S, T>& model, const std::vector<std::optional<S>>& lock) {
  const int n = model.size();
  const auto nn = static_cast<std::size_t>(n);
  ReducedModel<S> out;
  std::vector<int> anchor(nn, -1);                     // new index of the nearest moving ancestor-or-self
  std::vector<Transform<S>> rel(nn, Transform<S>::Identity());  // ⁱX_anchor
  ModelBuilder<S> b;
  b.set_gravity(model.gravity());
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(i);
    const int up = p >= 0 ? anchor[static_cast<std::size_t>(p)] : -1;
    const Transform<S> up_rel = p >= 0 ? rel[static_cast<std::size_t>(p)] : Transform<S>::Identity();
    if (lock[k]) {
      rel[k] = model.joint(i).transform(*lock[k]) * model.tree_transform(i) * up_rel;
      anchor[k] = up;
      b.add_fixed_body(model.body_name(i), up, rel[k], model.inertia(i));
      out.locked.push_back(i);
      out.locked_at.push_back(*lock[k]);
    } else {
      anchor[k] = b.add_body(model.body_name(i), up, model.joint_type(i), model.tree_transform(i) * up_rel,
                             model.inertia(i), model.axis(i), model.joint_name(i));
      out.joints.push_back(i);
    }
  }
  out.model = b.build();
  std::vector<FixedFrame<S>> frames;
  for (const FixedFrame<S>& f : model.frames()) {
    if (f.body < 0) frames.push_back(f);
    else {
      const auto k = static_cast<std::size_t>(f.body);
      frames.push_back({f.name, anchor[k], f.X * rel[k]});
    }
  }
  for (const FixedFrame<S>& f : out.model.frames()) frames.push_back(f);
  ModelAccess::frames(out.model) = std::move(frames);
  ModelAccess::base_mass(out.model) += model.base_mass();
  return out;
}
}  // namespace detail

/// The model with the given joints held at the given positions, their bodies merged (see the file comment).
/// Throws `ModelError` naming the joint for an unknown name or index, a non-finite position, a joint locked twice
/// at different positions, or when every joint would be locked.
template <class S, class T>
ReducedModel<S> lock_joints(const Model<S, T>& model, const std::vector<JointLock>& locks) {
  const char* who = "lock_joints";
  std::vector<std::optional<S>> lock(static_cast<std::size_t>(model.size()));
  for (const JointLock& l : locks) {
    const int i = detail::resolve_joint(model, l.joint, who);
    if (!std::isfinite(l.position)) {
      std::ostringstream os;
      os << who << ": " << detail::joint_label(model, i) << " locked at a non-finite position (" << l.position << ")";
      throw ModelError(os.str());
    }
    auto& slot = lock[static_cast<std::size_t>(i)];
    if (slot && *slot != S(l.position)) {
      std::ostringstream os;
      os << who << ": " << detail::joint_label(model, i) << " locked twice, at " << *slot << " and " << l.position;
      throw ModelError(os.str());
    }
    slot = S(l.position);
  }
  bool any_moving = false;
  for (const auto& s : lock) any_moving = any_moving || !s;
  if (!any_moving && model.size() > 0)
    throw ModelError(std::string(who) + ": every joint is locked; the model would have no moving body");
  return detail::lock_resolved(model, lock);
}

/// The model with only the given joints moving; every other joint is held at its entry of `q` (a configuration
/// of the original model). Throws `ModelError` for an unknown joint, a non-finite q entry or an empty list.
template <class S, class T, class Q>
ReducedModel<S> keep_joints(const Model<S, T>& model, const std::vector<JointRef>& moving,
                            const Eigen::MatrixBase<Q>& q) {
  const char* who = "keep_joints";
  if (q.size() != model.size()) {
    std::ostringstream os;
    os << who << ": q has " << q.size() << " entries, the model " << model.size() << " joints";
    throw ModelError(os.str());
  }
  if (moving.empty()) throw ModelError(std::string(who) + ": no joint to keep");
  std::vector<bool> keep(static_cast<std::size_t>(model.size()), false);
  for (const JointRef& j : moving) keep[static_cast<std::size_t>(detail::resolve_joint(model, j, who))] = true;
  std::vector<JointLock> locks;
  for (int i = 0; i < model.size(); ++i) {
    if (keep[static_cast<std::size_t>(i)]) continue;
    if (!std::isfinite(double(q[i]))) {
      std::ostringstream os;
      os << who << ": q of " << detail::joint_label(model, i) << " (held) is not finite (" << q[i] << ")";
      throw ModelError(os.str());
    }
    locks.push_back({JointRef(i), double(q[i])});
  }
  return lock_joints(model, locks);
}

/// The model with only the subtrees of the given bodies moving (each body's own joint included); every other
/// joint is held at its entry of `q`. Bodies by name or index (`JointRef` names are body names here).
template <class S, class T, class Q>
ReducedModel<S> keep_branches(const Model<S, T>& model, const std::vector<JointRef>& roots,
                              const Eigen::MatrixBase<Q>& q) {
  std::vector<JointRef> moving;
  for (const JointRef& r : roots) {
    int root = r.index;
    if (!r.name.empty()) {
      root = model.body_index(r.name);
      if (root < 0) {
        std::string msg = "keep_branches: the model has no body '" + r.name + "' (it takes body (link) names, the "
                          "first body of each branch";
        const int j = model.joint_index(r.name);
        if (j >= 0) msg += "; '" + r.name + "' is a joint: the body it moves is '" + model.body_name(j) + "')";
        else msg += ")" + detail::did_you_mean(r.name, detail::body_names_of(model));
        throw ModelError(msg);
      }
    } else if (root < 0 || root >= model.size()) {
      std::ostringstream os;
      os << "keep_branches: body index " << root << " is not a body of the model (it has " << model.size() << ")";
      throw ModelError(os.str());
    }
    for (int i = root; i < model.size(); ++i)
      if (model.is_ancestor_or_self(root, i)) moving.emplace_back(i);
  }
  return keep_joints(model, moving, q);
}

}  // namespace spatial
