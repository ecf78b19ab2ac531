#pragma once
/// \file walking/simulation.hpp
/// A rigid-contact simulator for a floating-base robot (issue 12's closed loop): the contacts are made and broken
/// when the caller says (a walking plan's instants), the motion between is the constrained forward dynamics of
/// contact.hpp, and a contact that is made starts with an impact (impulse_dynamics).
///
/// State and step. The state is (q, v) of a `FloatingModel` (q: nq, v: nv; floating.hpp's conventions) and the set of
/// active contacts, a bit mask over the candidate contacts given at construction (at most 4: e.g. the two soles).
/// `step(τ, mask)` advances by `dt`:
///   1. contacts that join (in `mask`, not active before) have their targets set to their frames' current poses, and
///      the velocity jumps by the impact on the new active set: v ← impulse_dynamics(q, v, e) (restitution e,
///      default 0: the new contacts stop, the old ones stay still);
///   2. v̇ = constrained_forward_dynamics(q, v, τ) on the active set (Baumgarte stabilisation with K_p = ω²,
///      K_d = 2ω, ω = `contact_frequency`, against the targets, which persist while a contact stays active);
///   3. semi-implicit Euler on the manifold: v ← v + dt v̇, q ← integrate(q, v dt).
/// With no contact the robot flies (ABA). τ has nv entries: the first six are a wrench applied to the root (root
/// coordinates, usually zero for a robot), the others the joint forces.
///
/// Outputs after a step: `q()`, `v()`, `qdd()` (the v̇ used), `active()` (the ContactData of the active set: its
/// `lambda` holds each active contact's force in that contact's reference axes, its `contacts` the contacts in
/// candidate order), `impact()` (true when step 1 ran in this step) and `impact_energy_loss()`.
///
/// Costs. The constructor builds one ContactData per non-empty subset of the candidates (allocates); `reset` and
/// `step` neither allocate nor throw.

#include "spatial/contact.hpp"
#include "spatial/floating.hpp"

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace spatial::walking {

/// Settings of `ContactSimulator`.
template <class S = double>
struct SimulationSettings {
  S dt = S(0.001);                ///< s, > 0: integration step
  S contact_frequency = S(30);    ///< ω (1/s) ≥ 0: Baumgarte gains K_p = ω², K_d = 2ω (critically damped drift)
  S restitution = S(0);           ///< e ∈ [0, 1] of the impacts when contacts are made
};

template <class ModelT>
class ContactSimulator;

/// The simulator for a floating-base model over a compile-time or run-time tree.
template <class S, class T>
class ContactSimulator<FloatingModel<S, T>> {
 public:
  using ModelType = FloatingModel<S, T>;
  using DataType = FloatingData<S, T>;
  using Contacts = ContactData<ModelType>;
  using VectorV = typename Contacts::VectorV;
  using ConfigVector = typename ModelType::ConfigVector;
  static constexpr int kMaxContacts = 4;

  /// `candidates`: the contacts that may be made (frames, types, reference axes, soles; their gains and targets are
  /// set here). Throws std::invalid_argument for more than four candidates or bad settings, ModelError (naming the
  /// contact) for a bad contact.
  ContactSimulator(const ModelType& model, std::vector<RigidContact<S>> candidates, SimulationSettings<S> settings = {})
      : model_(model), data_(model_), settings_(settings), candidates_(std::move(candidates)) {
    const int k = static_cast<int>(candidates_.size());
    if (k > kMaxContacts)
      throw std::invalid_argument("ContactSimulator: at most " + std::to_string(kMaxContacts) + " candidate contacts, got " +
                                  std::to_string(k));
    if (!(settings_.dt > S(0))) throw std::invalid_argument("ContactSimulator: settings.dt must be > 0");
    if (!(settings_.contact_frequency >= S(0)))
      throw std::invalid_argument("ContactSimulator: settings.contact_frequency must be >= 0");
    if (!(settings_.restitution >= S(0) && settings_.restitution <= S(1)))
      throw std::invalid_argument("ContactSimulator: settings.restitution must be in [0, 1]");
    const S w = settings_.contact_frequency;
    for (auto& c : candidates_) c.kp = w * w, c.kd = S(2) * w;
    for (unsigned mask = 1; mask < (1u << k); ++mask) {
      std::vector<RigidContact<S>> set;
      for (int i = 0; i < k; ++i)
        if (mask & (1u << i)) set.push_back(candidates_[static_cast<std::size_t>(i)]);
      sets_.emplace_back(model_, std::move(set));
    }
    q_ = neutral(model_);
    q_next_ = q_;
    v_ = VectorV::Zero(model_.nv());
    qdd_ = VectorV::Zero(model_.nv());
  }

  /// Sets the state and the active contacts (no impact); the active contacts' targets are their current poses.
  template <class Q, class V>
  void reset(const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v, unsigned mask) {
    q_ = q;
    v_ = v;
    mask_ = 0;
    time_ = S(0);
    impact_ = false;
    impact_loss_ = S(0);
    take_targets(mask);
    mask_ = mask & full_mask();
  }

  /// One step of `dt` with the forces τ (nv) and the contacts of `mask` active (see the top of the file).
  template <class Tau>
  void step(const Eigen::MatrixBase<Tau>& tau, unsigned mask) {
    mask &= full_mask();
    impact_ = false;
    impact_loss_ = S(0);
    const unsigned joined = mask & ~mask_;
    if (joined != 0u) {
      take_targets(joined);
      Contacts& cd = set(mask);
      copy_targets(cd, mask);
      const S before = kinetic_energy(model_, data_, q_, v_);
      v_ = impulse_dynamics(model_, data_, cd, q_, v_, settings_.restitution);
      impact_loss_ = before - kinetic_energy(model_, data_, q_, v_);
      impact_ = true;
    }
    mask_ = mask;
    if (mask_ == 0u) {
      qdd_ = aba(model_, data_, q_, v_, tau);
    } else {
      Contacts& cd = set(mask_);
      copy_targets(cd, mask_);
      qdd_ = constrained_forward_dynamics(model_, data_, cd, q_, v_, tau);
    }
    v_ += settings_.dt * qdd_;
    integrate(model_, q_, v_, settings_.dt, q_next_);
    q_.swap(q_next_);
    time_ += settings_.dt;
  }

  const ModelType& model() const { return model_; }
  /// Scratch data whose kinematics are those of the last dynamics call (the q before the last step's update).
  DataType& data() { return data_; }
  const ConfigVector& q() const { return q_; }
  const VectorV& v() const { return v_; }
  const VectorV& qdd() const { return qdd_; }
  S time() const { return time_; }
  unsigned mask() const { return mask_; }
  const SimulationSettings<S>& settings() const { return settings_; }
  /// The ContactData of the active set (its lambda: the forces of the last step), nullptr without contact.
  const Contacts* active() const { return mask_ ? &sets_[mask_ - 1u] : nullptr; }
  /// Whether the last step began with an impact, and the kinetic energy it took (J).
  bool impact() const { return impact_; }
  S impact_energy_loss() const { return impact_loss_; }
  /// The candidates with their current targets.
  const std::vector<RigidContact<S>>& candidates() const { return candidates_; }
  /// Moves candidate i's target (world position of its frame's origin, rotation frame axes → world axes); the
  /// Baumgarte terms pull the frame there while the contact is active. Contacts that join take their current pose.
  void set_target(std::size_t i, const Vector3<S>& position, const Matrix3<S>& rotation) {
    candidates_.at(i).target_position = position;
    candidates_.at(i).target_rotation = rotation;
  }

 private:
  unsigned full_mask() const { return (1u << candidates_.size()) - 1u; }
  Contacts& set(unsigned mask) { return sets_[mask - 1u]; }

  /// The candidates of `mask` take their frames' current poses as targets.
  void take_targets(unsigned mask) {
    forward_kinematics(model_, data_, q_);
    for (std::size_t i = 0; i < candidates_.size(); ++i)
      if (mask & (1u << i)) {
        const auto pose = frame_pose(model_, data_, candidates_[i].frame);
        candidates_[i].target_position = pose.translation();
        candidates_[i].target_rotation = pose.linear();
      }
  }
  /// The set's contacts take the candidates' targets.
  void copy_targets(Contacts& cd, unsigned mask) const {
    std::size_t j = 0;
    for (std::size_t i = 0; i < candidates_.size(); ++i)
      if (mask & (1u << i)) {
        cd.contacts[j].target_position = candidates_[i].target_position;
        cd.contacts[j].target_rotation = candidates_[i].target_rotation;
        ++j;
      }
  }

  ModelType model_;
  DataType data_;
  SimulationSettings<S> settings_;
  std::vector<RigidContact<S>> candidates_;
  std::vector<Contacts> sets_;  // index mask − 1
  ConfigVector q_, q_next_;
  VectorV v_, qdd_;
  unsigned mask_ = 0;
  S time_ = S(0);
  bool impact_ = false;
  S impact_loss_ = S(0);
};

}  // namespace spatial::walking
