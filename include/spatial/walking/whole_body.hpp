#pragma once
/// \file walking/whole_body.hpp
/// The open-loop whole-body walking pipeline of a biped on a floating base (issue 12, "Second stage", "Whole-body
/// motion", "Real time"; see docs/walking.md): per 2 ms tick, the footstep plan's feet and the preview controller's
/// centre of mass (CoM) become the joint angles q by inverse kinematics, the velocities v and accelerations v̇ by
/// velocity- and acceleration-level inverse kinematics, the joint torques and contact wrenches by whole-body
/// inverse dynamics with contacts, and the multibody ZMP; the second stage of Kajita et al. 2003 (§IV) feeds the
/// multibody ZMP error back into a second preview controller that corrects the CoM.
///
/// ## Frames and conventions
/// World frame of footsteps.hpp: x forward, y left, z up, ground z = `ground_height`. q, v, v̇, τ as in floating.hpp
/// (free-flyer first: q = [x y z qx qy qz qw, joints], v = [v_lin ω (root coordinates), q̇], v̇ the root's spatial
/// acceleration in root coordinates). The robot has two **sole frames** (`WholeBodyFrames`): origin on the sole,
/// z along the contact normal (up), x forward; the plan's foot centre is that origin, so the foot's target pose is
/// (plan position, Rz(yaw)). On the HOAP-3 (`L_SOLE`, `R_SOLE` of urdf/hoap3.urdf) the sole frame's origin is
/// 40 mm below the ankle-roll axis, 14 mm ahead of and 5 mm outboard of the point under the ankle: exactly the
/// centre of the data sheet's 108 × 73 mm sole (x ∈ [−40, 68] mm, y 5 mm outboard of the ankle ± 36.5 mm), so the
/// sole rectangle is ±54 × ±36.5 mm about the sole frame (`WholeBodyOptions::sole`; checked numerically by
/// tests/test_walking_whole_body.cpp). The pelvis (`WholeBodyFrames::pelvis`, the root frame) is kept level with
/// the feet's mean yaw.
///
/// ## One tick (`WholeBodyGenerator::tick`)
/// Inputs: the plan, the time t and the CoM state C = [c; ċ; c̈] (3 × 2, columns world x, y; the preview
/// controller's state); the CoM height is z_c = `preview.com_height` above the ground, constant.
///   1. **Targets**: both soles' poses (footsteps.hpp's `foot`: the stance foot flat on its footprint, the swing foot
///      on its trajectory, both with roll = pitch = 0), the CoM (c, ground + z_c), the pelvis orientation
///      Rz((ψ_L + ψ_R)/2). The joints that do not carry the feet (arms, waist: `passive` joints, all but the
///      ancestors of the two soles) follow a prescribed posture: `posture + swing · s(t)`, with s(t) =
///      (p_R − p_L) · u / L the right foot's lead over the left along the pelvis heading u, in step lengths L (in
///      [−1, 1] on a straight walk): the HOAP-3 options swing the arms against the legs.
///   2. **Position IK** (`IkSolver`, joint limits on): tasks both sole poses (6 + 6 rows), the CoM (3), the pelvis
///      orientation (3), all weight 1, over the 18 active velocity coordinates (free-flyer + 12 leg joints): a
///      square problem, solved to `ik_tolerance`. Warm start: the previous tick's q moved by v dt + v̇ dt²/2 (a
///      second-order prediction; typically 1–2 iterations).
///   3. **Velocities and accelerations by differential IK, not by differencing q**: with the stacked task Jacobian
///      A (18 × 27: the soles' LocalWorldAligned Jacobians, the CoM Jacobian, the root's angular rows [0 R 0]) split
///      into its active and passive columns, v_a solves A_a v_a = ẋ* − A_p v_p and v̇_a solves
///      A_a v̇_a = ẍ* − J̇v − A_p v̇_p (J̇v: the soles' classical drift [p̈; ω̇] at v̇ = 0 and the CoM's c̈ at v̇ = 0; the
///      root's angular row has none since ω_world = R ω_root). ẋ*, ẍ* are the exact time derivatives of the targets
///      (the plan's foot velocities and accelerations, ċ and c̈ of the preview state, the yaw rates). So the stance
///      sole's velocity and acceleration are zero to round-off (no Baumgarte residue for the inverse dynamics to
///      absorb), v and v̇ are the exact derivatives of the IK solution (up to the IK tolerance), and nothing needs
///      q of the next tick (central differences would: one tick of latency and O(dt²) contact accelerations).
///   4. **Inverse dynamics with contacts** (`contact_inverse_dynamics`): the soles in contact (plan.in_contact) as
///      6D contacts with the sole rectangle and the friction coefficient; τ, the contact wrenches, `ok`. Then the
///      multibody ZMP (`multibody_zmp`, from RNEA alone) and the CoP of the split wrenches (`center_of_pressure`).
/// `tick` allocates nothing and throws nothing (the solver and contact buffers are built by the constructor).
///
/// ## The whole run (`run_whole_body`) and the second stage
/// First stage: `run_preview` over the plan's reference ZMP gives the CoM x₀(k) and the cart-table ZMP p_ct(k).
/// A pass runs `tick` over every sample and gives the multibody ZMP p_mb(k). Second stage (Kajita 2003 §IV, over
/// the whole horizon): the error e = p_ct − p_mb is the reference of a second preview controller (the same
/// parameters) started at rest; its state Δx (c, ċ, c̈) is added to the CoM, x_{i+1} = x_i + Δx_i, and the pass is
/// run again. The cart-table ZMP of the correction tracks e, so the multibody ZMP of the corrected motion moves
/// onto p_ct; since a pass is cheap, `second_stage_iterations` repeats this (the error left after each pass is the
/// second controller's tracking error of the previous one, so it shrinks geometrically). Pass 0 is the first stage
/// alone; the samples of the last pass are returned with the statistics of every pass. Only the last pass runs the
/// contact inverse dynamics (`tick_kinematics` before it: the multibody ZMP needs RNEA alone).

#include "spatial/contact.hpp"
#include "spatial/floating.hpp"
#include "spatial/ik.hpp"
#include "spatial/kinematics.hpp"
#include "spatial/walking/footsteps.hpp"
#include "spatial/walking/preview.hpp"
#include "spatial/zmp.hpp"

#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace spatial::walking {

/// The frames the pipeline needs: the two soles and the pelvis (the root's own frame, e.g. `base_link`).
struct WholeBodyFrames {
  int left_sole = -1;
  int right_sole = -1;
  int pelvis = -1;
};

/// Which ZMP the second stage feeds back (`WholeBodyOptions::second_stage_zmp`).
enum class SecondStageZmp { multibody, double_pendulum };

/// Settings of the pipeline. Vectors with one entry per tree joint (n) may be left empty (zeros; no torque report).
template <class S = double>
struct WholeBodyOptions {
  PreviewParameters<S> preview{};   ///< both preview stages: dt, z_c = com_height, weights, horizon
  int second_stage_iterations = 3;  ///< passes with a CoM correction after the first-stage pass (0: none)
  S friction = S(0.6);              ///< μ of the contacts (friction pyramid) in the inverse dynamics
  Sole<S> sole{};                   ///< the sole rectangle about each sole frame (x forward, y left)
  S ik_tolerance = S(1e-11);        ///< ‖r‖₂ (m, rad) at which the per-tick IK stops
  int ik_max_iterations = 50;       ///< per tick
  Eigen::Matrix<S, Eigen::Dynamic, 1> posture;  ///< n: passive joints' angles; active ones: the start's guess
  Eigen::Matrix<S, Eigen::Dynamic, 1> swing;    ///< n: passive joints' swing, rad per unit of s(t)
  Eigen::Matrix<S, Eigen::Dynamic, 1> rated_torque;  ///< n: motor rated torques (N m) for the ratios
  Eigen::Matrix<S, Eigen::Dynamic, 1> max_torque;    ///< n: motor maximum torques (N m)
  /// The ZMP the second stage feeds back: the full model's (`multibody`, RNEA) or the reference study's double
  /// inverted pendulum's (`double_pendulum`: two point masses, `pendulum_leg_mass` on the stance hip's pitch axis,
  /// half on each hip in double support, and the rest at the whole-body CoM; applied in both the sagittal and the
  /// lateral plane). The passes' statistics always measure the full model's ZMP.
  SecondStageZmp second_stage_zmp = SecondStageZmp::multibody;
  S pendulum_leg_mass = S(0);                ///< kg: m1 of the double pendulum
  std::array<int, 2> pendulum_hips{-1, -1};  ///< bodies (left, right) whose origins are on the hip pitch axes
};

/// The HOAP-3's settings from /work/shared/hoap3/DATASHEET.md, by joint name (`joint_names` in model order, e.g.
/// `models::hoap3_floating::joint_names`): arms hanging (shoulder pitch π/2; at 0 the arms point forward), swinging
/// ±`arm_swing` against the legs (the public walk's ±10°); start guess for the legs: hip pitch −0.4, knee 0.8, ankle
/// pitch −0.4 rad (knees bent); motor torques rated / maximum: hip yaw, hip pitch, ankle roll and the arm joints
/// 1.5 / 3 N m; hip roll, knee, ankle pitch and waist 2 / 4.5 N m. Throws std::invalid_argument for a joint name it
/// does not know.
template <class S = double, class Names>
WholeBodyOptions<S> hoap3_whole_body_options(const Names& joint_names, S arm_swing = S(10 * EIGEN_PI / 180)) {
  WholeBodyOptions<S> o;
  o.preview.com_height = S(0.29);
  o.pendulum_leg_mass = S(1.196);  // urdf/double_pendulum.urdf's m1: the leg below the hip pitch joint
  const auto n = static_cast<Eigen::Index>(joint_names.size());
  o.posture = o.swing = o.rated_torque = o.max_torque = Eigen::Matrix<S, Eigen::Dynamic, 1>::Zero(n);
  const auto ends = [](std::string_view s, std::string_view suffix) {
    return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
  };
  Eigen::Index i = 0;
  for (const auto& name_ : joint_names) {
    const std::string_view name(name_);
    const bool left = name.find("L_") != std::string_view::npos && name.find("R_") == std::string_view::npos;
    S rated = S(0), peak = S(0);
    if (name == "WAIST_CHEST_joint") {
      rated = S(2), peak = S(4.5);
    } else if (ends(name, "_SFE_joint")) {
      rated = S(1.5), peak = S(3);
      o.posture[i] = S(EIGEN_PI / 2);
      // right foot ahead (s > 0): left arm forward (shoulder pitch below π/2), right arm back
      o.swing[i] = left ? -arm_swing : arm_swing;
    } else if (ends(name, "_EB_joint")) {
      rated = S(1.5), peak = S(3);
      o.posture[i] = S(-EIGEN_PI / 2);  // forearms forward
    } else if (ends(name, "_SAA_joint") || ends(name, "_SHR_joint") || ends(name, "_LR_joint") ||
               ends(name, "_AAA_joint")) {
      rated = S(1.5), peak = S(3);
    } else if (ends(name, "_LFE_joint")) {
      rated = S(1.5), peak = S(3);
      o.posture[i] = S(-0.4);
      o.pendulum_hips[left ? 0 : 1] = static_cast<int>(i);  // the hip pitch joint's body: origin on its axis
    } else if (ends(name, "_KN_joint")) {
      rated = S(2), peak = S(4.5);
      o.posture[i] = S(0.8);
    } else if (ends(name, "_AFE_joint")) {
      rated = S(2), peak = S(4.5);
      o.posture[i] = S(-0.4);
    } else if (ends(name, "_LAA_joint")) {
      rated = S(2), peak = S(4.5);
    } else {
      throw std::invalid_argument("hoap3_whole_body_options: unknown joint '" + std::string(name) + "'");
    }
    o.rated_torque[i] = rated;
    o.max_torque[i] = peak;
    ++i;
  }
  return o;
}

/// A sole as a 6D contact (Local axes) with the options' friction coefficient and sole rectangle.
template <class S>
RigidContact<S> sole_contact(int frame, const WholeBodyOptions<S>& o) {
  RigidContact<S> c = contact_6d<S>(frame);
  c.friction = o.friction;
  c.sole_x_min = -o.sole.back, c.sole_x_max = o.sole.front;
  c.sole_y_min = -o.sole.right, c.sole_y_max = o.sole.left;
  return c;
}

/// Everything one tick produces (world coordinates unless said otherwise).
template <class ModelT>
struct WholeBodyState {
  using S = typename ModelT::Scalar;
  S t = S(0);
  typename ModelT::ConfigVector q;    ///< nq
  typename ModelT::TangentVector v;   ///< nv
  typename ModelT::TangentVector a;   ///< v̇, nv
  typename ModelT::TangentVector tau; ///< nv: joint torques (N m) after the six root entries (what the contacts
                                      ///< could not supply; zero to round-off when `ok`)
  std::array<Vector6<S>, 2> wrench{};  ///< per foot (index(Foot)): [force; moment about the sole frame's origin], sole
                                       ///< axes; zero when the foot is not in contact
  std::array<bool, 2> contact{};       ///< per foot: in contact (plan)
  bool ok = false;                     ///< contact_inverse_dynamics found a physical split
  S root_residual = S(0);              ///< ‖τ[0:6]‖: the wrench the contacts could not supply
  Vec2<S> zmp_reference = Vec2<S>::Zero();   ///< run_whole_body only: the plan's reference ZMP
  Vec2<S> zmp_cart_table = Vec2<S>::Zero();  ///< cart-table ZMP of the CoM target (c − z_c c̈ / g)
  Vec2<S> zmp_multibody = Vec2<S>::Zero();   ///< multibody ZMP from RNEA (ground plane)
  Vec2<S> cop = Vec2<S>::Zero();             ///< CoP of the split contact wrenches (ground plane)
  Vec3<S> com = Vec3<S>::Zero();             ///< the CoM target (= the model's CoM to the IK tolerance)
  IkStatus<S> ik{};                          ///< the position IK of this tick
  S foot_position_error = S(0);  ///< max over both soles of ‖p − p*‖ (m) after the IK
  S foot_rotation_error = S(0);  ///< max over both soles of ‖log(R* Rᵀ)‖ (rad)
};

/// The per-tick pipeline of the file comment for one model. `ModelT`: `FloatingModel<S, T>`. Keeps a reference to
/// the model (which must outlive it); allocates everything in the constructor; `start` and `tick` neither allocate
/// nor throw. Not thread-safe: one generator per thread.
template <class ModelT>
class WholeBodyGenerator {
 public:
  using S = typename ModelT::Scalar;
  using State = WholeBodyState<ModelT>;
  using ComState = Eigen::Matrix<S, 3, 2>;
  using VectorX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  static constexpr int kRows = 18;  ///< task rows: two soles (6 + 6), CoM (3), pelvis orientation (3)
  using TaskMatrix = Eigen::Matrix<S, kRows, ModelT::NV>;

  /// `lower`, `upper`: joint limits (one per tree joint, or empty). Throws std::invalid_argument for a bad frame, a
  /// wrongly sized vector, or soles whose ancestors are not 12 joints (the square IK of the file comment).
  WholeBodyGenerator(const ModelT& model, const WholeBodyFrames& frames, const VectorX& lower, const VectorX& upper,
                     const WholeBodyOptions<S>& options)
      : model_(model), frames_(frames), opt_(checked(model, frames, options)), data_(model),
        ik_(model,
            {ik_pose(frames.left_sole, Vector3<S>::Zero(), Matrix3<S>::Identity()),
             ik_pose(frames.right_sole, Vector3<S>::Zero(), Matrix3<S>::Identity()),
             ik_center_of_mass(Vector3<S>::Zero()), ik_orientation(frames.pelvis, Matrix3<S>::Identity())},
            ik_options(model, frames, lower, upper, options)),
        cd_left_(model, {sole_contact(frames.left_sole, options)}),
        cd_right_(model, {sole_contact(frames.right_sole, options)}),
        cd_both_(model, {sole_contact(frames.left_sole, options), sole_contact(frames.right_sole, options)}) {
    const int n = model.njoints();
    active_ = active_coordinates(model, frames);
    if (static_cast<int>(active_.size()) != kRows)
      throw std::invalid_argument("WholeBodyGenerator: the soles must hang from 12 joints in all (found " +
                                  std::to_string(static_cast<int>(active_.size()) - 6) + ")");
    is_active_ = VectorX::Zero(model.nv());
    for (int c : active_) is_active_[c] = S(1);
    A_ = TaskMatrix::Zero(kRows, model.nv());
    J6_ = Eigen::Matrix<S, 6, ModelT::NV>::Zero(6, model.nv());
    Jc_ = Eigen::Matrix<S, 3, ModelT::NV>::Zero(3, model.nv());
    st_.q = neutral(model);
    st_.v = st_.a = st_.tau = ModelT::TangentVector::Zero(model.nv());
    qpred_ = st_.q;
    zero_ = st_.v;
    vp_ = ap_ = st_.v;
    (void)n;
  }

  const ModelT& model() const noexcept { return model_; }
  const WholeBodyOptions<S>& options() const noexcept { return opt_; }
  /// The 18 velocity coordinates the IK moves (free-flyer, then the soles' ancestor joints).
  const std::vector<int>& active() const noexcept { return active_; }
  /// The state of the last `start` or `tick`.
  const State& state() const noexcept { return st_; }

  /// The standing pose at t = 0: both feet on the plan's initial footprints, the CoM at (c_xy, ground + z_c), the
  /// pelvis level; solved from the posture (knees bent) with the pelvis z_c above the ground, up to 200 IK
  /// iterations. v = v̇ = 0; then the inverse dynamics of that static pose. Returns the IK status.
  IkStatus<S> start(const FootstepPlan<S>& plan, const Vec2<S>& c_xy) {
    st_.q.setZero();  // neutral (root at the origin, identity quaternion) without neutral()'s temporary
    st_.q[6] = S(1);
    const int n = model_.njoints();
    for (int j = 0; j < n; ++j)
      if (j < opt_.posture.size()) st_.q[7 + j] = opt_.posture[j];
    st_.q[0] = c_xy.x();
    st_.q[1] = c_xy.y();
    st_.q[2] = plan.parameters().ground_height + opt_.preview.com_height;
    st_.v.setZero();
    st_.a.setZero();
    ComState com = ComState::Zero();
    com.row(0) = c_xy.transpose();
    ik_.set_max_iterations(200);
    const S t0 = S(0);
    run_tick(plan, t0, com, /*predict=*/false);
    ik_.set_max_iterations(opt_.ik_max_iterations);
    return st_.ik;
  }

  /// One tick at time t with the CoM state `com` (rows c, ċ, c̈; columns world x, y): steps 1–4 of the file comment,
  /// warm-started from the previous tick (t should advance by dt). Returns the new state. No allocation, no exception.
  const State& tick(const FootstepPlan<S>& plan, S t, const ComState& com) { return run_tick(plan, t, com, true); }

  /// `tick` without the contact inverse dynamics (τ, the wrenches, `ok`, the CoP are left as they were): what a
  /// second-stage pass needs (the multibody ZMP comes from RNEA alone).
  const State& tick_kinematics(const FootstepPlan<S>& plan, S t, const ComState& com) {
    return run_tick(plan, t, com, true, false);
  }

 private:
  static const WholeBodyOptions<S>& checked(const ModelT& model, const WholeBodyFrames& f,
                                            const WholeBodyOptions<S>& o) {
    const int nf = static_cast<int>(model.tree().frames().size());
    for (int fr : {f.left_sole, f.right_sole, f.pelvis})
      if (fr < 0 || fr >= nf) throw std::invalid_argument("WholeBodyGenerator: frame index " + std::to_string(fr) +
                                                          " is not a frame of the model");
    const int n = model.njoints();
    for (const auto* v : {&o.posture, &o.swing, &o.rated_torque, &o.max_torque})
      if (v->size() != 0 && v->size() != n)
        throw std::invalid_argument("WholeBodyGenerator: posture, swing and torque vectors need " + std::to_string(n) +
                                    " entries (or none)");
    PreviewController<S>::validate(o.preview);
    if (!(o.friction > S(0))) throw std::invalid_argument("WholeBodyGenerator: friction must be > 0");
    if (o.second_stage_iterations < 0) throw std::invalid_argument("WholeBodyGenerator: second_stage_iterations < 0");
    return o;
  }

  /// The free-flyer's six coordinates and the joints between the root and either sole (velocity indices).
  static std::vector<int> active_coordinates(const ModelT& model, const WholeBodyFrames& f) {
    const auto& tree = model.tree();
    std::vector<bool> on(static_cast<std::size_t>(tree.size()), false);
    for (int fr : {f.left_sole, f.right_sole})
      for (int b = tree.frames()[static_cast<std::size_t>(fr)].body; b >= 0; b = tree.parent(b))
        on[static_cast<std::size_t>(b)] = true;
    std::vector<int> a = {0, 1, 2, 3, 4, 5};
    for (int j = 0; j < tree.size(); ++j)
      if (on[static_cast<std::size_t>(j)]) a.push_back(6 + j);
    return a;
  }

  static IkOptions<S> ik_options(const ModelT& model, const WholeBodyFrames& f, const VectorX& lower,
                                 const VectorX& upper, const WholeBodyOptions<S>& o) {
    IkOptions<S> io;
    io.lower = lower;
    io.upper = upper;
    io.tolerance = o.ik_tolerance;
    io.max_iterations = o.ik_max_iterations;
    io.active = active_coordinates(model, f);
    return io;
  }

  static Matrix3<S> rot_z(S yaw) {
    using std::cos;
    using std::sin;
    const S c = cos(yaw), s = sin(yaw);
    Matrix3<S> R;
    R << c, -s, S(0), s, c, S(0), S(0), S(0), S(1);
    return R;
  }

  const State& run_tick(const FootstepPlan<S>& plan, S t, const ComState& com, bool predict, bool dynamics = true) {
    const int n = model_.njoints();
    const S ground = plan.parameters().ground_height;
    const FootState<S> fl = plan.foot(Foot::left, t), fr = plan.foot(Foot::right, t);
    const S psi = S(0.5) * (fl.yaw + fr.yaw), dpsi = S(0.5) * (fl.yaw_rate + fr.yaw_rate),
            ddpsi = S(0.5) * (fl.yaw_acceleration + fr.yaw_acceleration);
    const Matrix3<S> Rl = rot_z(fl.yaw), Rr = rot_z(fr.yaw), Rp = rot_z(psi);
    const Vector3<S> c(com(0, 0), com(0, 1), ground + opt_.preview.com_height);
    const Vector3<S> dc(com(1, 0), com(1, 1), S(0)), ddc(com(2, 0), com(2, 1), S(0));

    // s(t): the right foot's lead along the heading u, in step lengths, and its derivatives
    using std::cos;
    using std::sin;
    const S L = plan.parameters().step_length;
    const Vector3<S> u(cos(psi), sin(psi), S(0)), up(-sin(psi), cos(psi), S(0));
    const Vector3<S> d = fr.position - fl.position, dd = fr.velocity - fl.velocity,
                     ddd = fr.acceleration - fl.acceleration;
    const Vector3<S> du = dpsi * up, ddu = ddpsi * up - dpsi * dpsi * u;
    const S inv = std::abs(L) > S(1e-9) ? S(1) / L : S(0);
    const S s = d.dot(u) * inv, ds = (dd.dot(u) + d.dot(du)) * inv,
            dds = (ddd.dot(u) + S(2) * dd.dot(du) + d.dot(ddu)) * inv;

    // 1. targets; warm start
    ik_.set_target(0, fl.position, Rl);
    ik_.set_target(1, fr.position, Rr);
    ik_.set_target(2, c);
    ik_.set_target(3, Rp);
    if (predict) {
      vp_ = st_.v * opt_.preview.dt + st_.a * (S(0.5) * opt_.preview.dt * opt_.preview.dt);
      integrate(model_, st_.q, vp_, S(1), qpred_);
    } else {
      qpred_ = st_.q;
    }
    vp_.setZero();
    ap_.setZero();
    for (int j = 0; j < n; ++j) {
      if (is_active_[6 + j] != S(0)) continue;
      const S p0 = j < opt_.posture.size() ? opt_.posture[j] : S(0);
      const S sw = j < opt_.swing.size() ? opt_.swing[j] : S(0);
      qpred_[7 + j] = p0 + sw * s;
      vp_[6 + j] = sw * ds;
      ap_[6 + j] = sw * dds;
    }
    // 2. position IK
    st_.ik = ik_.solve(qpred_);
    st_.q = qpred_;
    st_.t = t;
    st_.com = c;
    {
      const auto Pl = frame_pose(model_, ik_.data(), frames_.left_sole);
      const auto Pr = frame_pose(model_, ik_.data(), frames_.right_sole);
      st_.foot_position_error = std::max((Pl.translation() - fl.position).norm(), (Pr.translation() - fr.position).norm());
      st_.foot_rotation_error = std::max(spatial::detail::so3_log<S>(Rl * Pl.linear().transpose()).norm(),
                                         spatial::detail::so3_log<S>(Rr * Pr.linear().transpose()).norm());
    }

    // 3. velocities and accelerations: A_a x_a = rhs − A_p x_p
    compute_joint_jacobians(model_, data_, st_.q);
    frame_jacobian(model_, data_, frames_.left_sole, ReferenceFrame::LocalWorldAligned, J6_);
    A_.template middleRows<6>(0) = J6_;
    frame_jacobian(model_, data_, frames_.right_sole, ReferenceFrame::LocalWorldAligned, J6_);
    A_.template middleRows<6>(6) = J6_;
    com_jacobian(model_, data_, st_.q, Jc_);
    A_.template middleRows<3>(12) = Jc_;
    A_.template middleRows<3>(15).setZero();
    const Matrix3<S> R = root_quaternion(st_.q).toRotationMatrix();
    A_.template block<3, 3>(15, 3) = R;
    for (int r = 0; r < kRows; ++r)
      for (int k = 0; k < kRows; ++k) Aa_(r, k) = A_(r, active_[static_cast<std::size_t>(k)]);
    lu_.compute(Aa_);

    xd_ << fl.velocity, Vector3<S>(S(0), S(0), fl.yaw_rate), fr.velocity, Vector3<S>(S(0), S(0), fr.yaw_rate), dc,
        Vector3<S>(S(0), S(0), dpsi);
    xd_.noalias() -= A_ * vp_;  // passive columns only: vp_ is zero on the active ones
    y_ = lu_.solve(xd_);
    st_.v = vp_;
    for (int k = 0; k < kRows; ++k) st_.v[active_[static_cast<std::size_t>(k)]] = y_[k];

    // drift at v̇ = 0 (plus the passive joints' own accelerations)
    forward_kinematics(model_, data_, st_.q, st_.v, ap_);
    const Vector3<S> al = frame_classical_acceleration(model_, data_, frames_.left_sole, ReferenceFrame::LocalWorldAligned);
    const Vector3<S> wl = frame_acceleration(model_, data_, frames_.left_sole, ReferenceFrame::LocalWorldAligned).w;
    const Vector3<S> ar = frame_classical_acceleration(model_, data_, frames_.right_sole, ReferenceFrame::LocalWorldAligned);
    const Vector3<S> wr = frame_acceleration(model_, data_, frames_.right_sole, ReferenceFrame::LocalWorldAligned).w;
    center_of_mass(model_, data_, st_.q, st_.v, ap_);
    const Vector3<S> acom = data_.acom;
    xd_ << fl.acceleration - al, Vector3<S>(S(0), S(0), fl.yaw_acceleration) - wl, fr.acceleration - ar,
        Vector3<S>(S(0), S(0), fr.yaw_acceleration) - wr, ddc - acom, Vector3<S>(S(0), S(0), ddpsi);
    y_ = lu_.solve(xd_);
    st_.a = ap_;
    for (int k = 0; k < kRows; ++k) st_.a[active_[static_cast<std::size_t>(k)]] = y_[k];

    // 4. inverse dynamics with contacts, ZMP, CoP
    st_.contact[0] = plan.in_contact(Foot::left, t);
    st_.contact[1] = plan.in_contact(Foot::right, t);
    ContactData<ModelT>& cd = st_.contact[0] ? (st_.contact[1] ? cd_both_ : cd_left_) : cd_right_;
    const Vector3<S> zmb = multibody_zmp(model_, data_, st_.q, st_.v, st_.a, ground);
    st_.zmp_multibody = zmb.template head<2>();
    const S zg = opt_.preview.com_height / opt_.preview.gravity;
    st_.zmp_cart_table = Vec2<S>(com(0, 0) - zg * com(2, 0), com(0, 1) - zg * com(2, 1));
    if (!dynamics) return st_;
    contact_inverse_dynamics(model_, data_, cd, st_.q, st_.v, st_.a);
    st_.tau = cd.tau;
    st_.ok = cd.ok;
    st_.root_residual = cd.tau.template head<6>().norm();
    st_.cop = center_of_pressure(model_, data_, cd, ground).template head<2>();
    st_.wrench[0].setZero();
    st_.wrench[1].setZero();
    int r = 0;
    for (int f = 0; f < 2; ++f)
      if (st_.contact[static_cast<std::size_t>(f)]) {
        st_.wrench[static_cast<std::size_t>(f)] = cd.lambda.template segment<6>(r);
        r += 6;
      }
    return st_;
  }

  const ModelT& model_;
  WholeBodyFrames frames_;
  WholeBodyOptions<S> opt_;
  typename spatial::detail::ModelTraits<ModelT>::DataType data_;
  IkSolver<ModelT> ik_;
  ContactData<ModelT> cd_left_, cd_right_, cd_both_;
  std::vector<int> active_;
  VectorX is_active_;
  State st_;
  typename ModelT::ConfigVector qpred_;
  typename ModelT::TangentVector vp_, ap_, zero_;
  TaskMatrix A_;
  Eigen::Matrix<S, 6, ModelT::NV> J6_;
  Eigen::Matrix<S, 3, ModelT::NV> Jc_;
  Eigen::Matrix<S, kRows, kRows> Aa_;
  Eigen::PartialPivLU<Eigen::Matrix<S, kRows, kRows>> lu_;
  Eigen::Matrix<S, kRows, 1> xd_, y_;
};

/// Statistics of one pass over the plan (pass 0: first stage only; pass i: after i second-stage corrections).
template <class S = double>
struct WholeBodyPass {
  S zmp_error_max = S(0);        ///< max_k ‖p_mb − p_ref‖ (m)
  S zmp_error_rms = S(0);        ///< RMS over the ticks of ‖p_mb − p_ref‖
  S zmp_error_ct_max = S(0);     ///< max_k ‖p_mb − p_ct‖: the multibody error against the cart-table ZMP
  S zmp_error_ct_rms = S(0);
  S min_margin = S(0);           ///< min_k margin of p_mb in the support polygon (m; > 0 inside)
  int not_ok = 0;                ///< last pass: ticks where contact_inverse_dynamics found no physical split
  S seconds = S(0);              ///< wall-clock time of the pass
};

/// The summary of `run_whole_body` (the last pass unless said otherwise).
template <class S = double>
struct WholeBodySummary {
  int ticks = 0;
  S dt = S(0);
  std::vector<WholeBodyPass<S>> passes;
  S cart_table_error_max = S(0);   ///< max ‖p_ct − p_ref‖ of the first stage
  S cart_table_min_margin = S(0);
  S reference_min_margin = S(0);   ///< of the reference ZMP itself
  S multibody_min_margin = S(0);
  S cop_min_margin = S(0);         ///< of the CoP of the split (over the ticks where it is ok)
  S cop_zmp_max = S(0);            ///< max ‖CoP − p_mb‖ over the ok ticks
  int contact_ok = 0;              ///< ticks where the split is physical
  S root_residual_max = S(0);      ///< max ‖τ[0:6]‖ over the ok ticks
  S ik_residual_max = S(0);
  int ik_iterations_max = 0;
  S ik_iterations_mean = S(0);
  int ik_not_converged = 0;
  S foot_position_error_max = S(0);
  S foot_rotation_error_max = S(0);
  Eigen::Matrix<S, Eigen::Dynamic, 1> torque_max;   ///< n: max |τ_j| over the run (N m)
  Eigen::Matrix<S, Eigen::Dynamic, 1> rated_ratio;  ///< n: torque_max / rated (empty without rated torques)
  Eigen::Matrix<S, Eigen::Dynamic, 1> max_ratio;    ///< n: torque_max / maximum
  int worst_joint = -1;            ///< the joint of the largest rated ratio
  S tick_seconds_mean = S(0);      ///< wall-clock time per tick of the last pass (IK + v, v̇ + ID + ZMP)
  S tick_seconds_max = S(0);
};

/// The result of `run_whole_body`.
template <class ModelT>
struct WholeBodyRun {
  using S = typename ModelT::Scalar;
  std::vector<WholeBodyState<ModelT>> samples;         ///< the last pass, t_k = k dt
  PreviewTrajectory<S> first_stage;                    ///< the first preview controller's CoM and cart-table ZMP
  Eigen::Matrix<S, Eigen::Dynamic, 2> com_correction;  ///< the total second-stage CoM correction (n × 2)
  std::vector<Eigen::Matrix<S, Eigen::Dynamic, 2>> zmp_multibody;  ///< p_mb of every pass (n × 2)
  WholeBodySummary<S> summary;
  IkStatus<S> start{};                                 ///< the standing pose's IK
};

/// The double inverted pendulum's ZMP on the ground plane z = h for the tick `st` (see
/// `WholeBodyOptions::second_stage_zmp`): point masses m1 on the stance hips (their classical accelerations from
/// the tick's q, v, v̇) and M − m1 at the CoM (acceleration: the CoM state's, at constant height).
template <class ModelT, class DataT>
Vec2<typename ModelT::Scalar> pendulum_zmp(const ModelT& model, DataT& data, const WholeBodyState<ModelT>& st,
                                           const Eigen::Matrix<typename ModelT::Scalar, 3, 2>& com,
                                           const WholeBodyOptions<typename ModelT::Scalar>& options,
                                           typename ModelT::Scalar h) {
  using S = typename ModelT::Scalar;
  forward_kinematics(model, data, st.q, st.v, st.a);
  const S g = model.tree().gravity().norm();
  const S m1 = options.pendulum_leg_mass;
  const int stance = int(st.contact[0]) + int(st.contact[1]);
  S num_x = S(0), num_y = S(0), den = S(0);
  const auto add = [&](S m, const Vec3<S>& p, const Vec3<S>& a) {
    num_x += m * (p.x() * (a.z() + g) - (p.z() - h) * a.x());
    num_y += m * (p.y() * (a.z() + g) - (p.z() - h) * a.y());
    den += m * (a.z() + g);
  };
  for (int f = 0; f < 2; ++f) {
    if (!st.contact[static_cast<std::size_t>(f)]) continue;
    const int b = options.pendulum_hips[static_cast<std::size_t>(f)];
    add(m1 / S(stance), world_transform(data, b).r,
        body_classical_acceleration(model, data, b, ReferenceFrame::LocalWorldAligned));
  }
  add(model.total_mass() - m1, st.com, Vec3<S>(com(2, 0), com(2, 1), S(0)));
  return Vec2<S>(num_x / den, num_y / den);
}

/// The whole open-loop pipeline over a plan (see the file comment): first stage, passes of `tick` and second-stage
/// corrections, statistics. Allocates (the samples); the ticks themselves do not.
template <class ModelT>
WholeBodyRun<ModelT> run_whole_body(const ModelT& model, const WholeBodyFrames& frames,
                                    const Eigen::Matrix<typename ModelT::Scalar, Eigen::Dynamic, 1>& lower,
                                    const Eigen::Matrix<typename ModelT::Scalar, Eigen::Dynamic, 1>& upper,
                                    const FootstepPlan<typename ModelT::Scalar>& plan,
                                    const WholeBodyOptions<typename ModelT::Scalar>& options) {
  using S = typename ModelT::Scalar;
  using Clock = std::chrono::steady_clock;
  WholeBodyGenerator<ModelT> gen(model, frames, lower, upper, options);
  WholeBodyRun<ModelT> run;
  const S dt = options.preview.dt;
  const Eigen::Matrix<S, Eigen::Dynamic, 2> ref = sample_zmp_reference(plan, dt);
  const Eigen::Index n = ref.rows();
  PreviewController<S> first(options.preview), second(options.preview);
  run.first_stage = run_preview(first, ref);
  Eigen::Matrix<S, Eigen::Dynamic, 2> dc = Eigen::Matrix<S, Eigen::Dynamic, 2>::Zero(n, 2), ddc = dc, dddc = dc;
  Eigen::Matrix<S, Eigen::Dynamic, 2> pmb(n, 2), pfb(n, 2);
  run.samples.resize(static_cast<std::size_t>(n));
  const bool pendulum = options.second_stage_zmp == SecondStageZmp::double_pendulum;
  if (pendulum && (options.pendulum_hips[0] < 0 || options.pendulum_hips[1] < 0 ||
                   options.pendulum_hips[0] >= model.njoints() || options.pendulum_hips[1] >= model.njoints() ||
                   !(options.pendulum_leg_mass > S(0) && options.pendulum_leg_mass < model.total_mass())))
    throw std::invalid_argument("run_whole_body: the double pendulum needs two hip bodies and 0 < m1 < total mass");
  typename spatial::detail::ModelTraits<ModelT>::DataType pdata(model);
  WholeBodySummary<S>& sum = run.summary;
  sum.ticks = static_cast<int>(n);
  sum.dt = dt;
  const int nj = model.njoints();
  for (int pass = 0; pass <= options.second_stage_iterations; ++pass) {
    const bool last = pass == options.second_stage_iterations;
    WholeBodyPass<S> ps;
    ps.min_margin = std::numeric_limits<S>::infinity();
    run.start = gen.start(plan, Vec2<S>(ref(0, 0) + dc(0, 0), ref(0, 1) + dc(0, 1)));
    S err2 = S(0), errct2 = S(0);
    S tick_max = S(0);
    const auto t0 = Clock::now();
    for (Eigen::Index k = 0; k < n; ++k) {
      const S t = S(k) * dt;
      Eigen::Matrix<S, 3, 2> com;
      com.row(0) = run.first_stage.com.row(k) + dc.row(k);
      com.row(1) = run.first_stage.com_velocity.row(k) + ddc.row(k);
      com.row(2) = run.first_stage.com_acceleration.row(k) + dddc.row(k);
      const auto tk = last ? Clock::now() : Clock::time_point{};
      const WholeBodyState<ModelT>& st = last ? gen.tick(plan, t, com) : gen.tick_kinematics(plan, t, com);
      if (last) tick_max = std::max(tick_max, std::chrono::duration<S>(Clock::now() - tk).count());
      pmb.row(k) = st.zmp_multibody.transpose();
      const Vec2<S> fed =
          pendulum ? pendulum_zmp(model, pdata, st, com, options, plan.parameters().ground_height) : st.zmp_multibody;
      pfb.row(k) = fed.transpose();
      const Vec2<S> pref = ref.row(k).transpose();
      const Vec2<S> pct = run.first_stage.zmp.row(k).transpose();
      const S e = (st.zmp_multibody - pref).norm(), ect = (st.zmp_multibody - pct).norm();
      ps.zmp_error_max = std::max(ps.zmp_error_max, e);
      ps.zmp_error_ct_max = std::max(ps.zmp_error_ct_max, ect);
      err2 += e * e;
      errct2 += ect * ect;
      ps.min_margin = std::min(ps.min_margin, plan.margin(t, st.zmp_multibody));
      if (last && !st.ok) ++ps.not_ok;
      if (last) {
        WholeBodyState<ModelT>& out = run.samples[static_cast<std::size_t>(k)];
        out = st;
        out.zmp_reference = pref;
      }
    }
    ps.seconds = std::chrono::duration<S>(Clock::now() - t0).count();
    ps.zmp_error_rms = std::sqrt(err2 / S(n));
    ps.zmp_error_ct_rms = std::sqrt(errct2 / S(n));
    sum.passes.push_back(ps);
    run.zmp_multibody.push_back(pmb);
    if (last) {
      sum.tick_seconds_mean = ps.seconds / S(n);
      sum.tick_seconds_max = tick_max;
      break;
    }
    // second stage: the cart-table ZMP of the correction tracks e = p_ct − p_mb
    const Eigen::Matrix<S, Eigen::Dynamic, 2> e = run.first_stage.zmp - pfb;
    const PreviewTrajectory<S> corr = run_preview(second, e);
    dc += corr.com;
    ddc += corr.com_velocity;
    dddc += corr.com_acceleration;
  }
  run.com_correction = dc;

  // summary of the last pass
  sum.cart_table_error_max = (run.first_stage.zmp - ref).rowwise().norm().maxCoeff();
  sum.cart_table_min_margin = sum.reference_min_margin = sum.multibody_min_margin = sum.cop_min_margin =
      std::numeric_limits<S>::infinity();
  sum.torque_max = Eigen::Matrix<S, Eigen::Dynamic, 1>::Zero(nj);
  long iterations = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const WholeBodyState<ModelT>& st = run.samples[static_cast<std::size_t>(k)];
    const S t = st.t;
    sum.cart_table_min_margin =
        std::min(sum.cart_table_min_margin, plan.margin(t, Vec2<S>(run.first_stage.zmp.row(k).transpose())));
    sum.reference_min_margin = std::min(sum.reference_min_margin, plan.margin(t, st.zmp_reference));
    sum.multibody_min_margin = std::min(sum.multibody_min_margin, plan.margin(t, st.zmp_multibody));
    if (st.ok) {
      ++sum.contact_ok;
      sum.cop_min_margin = std::min(sum.cop_min_margin, plan.margin(t, st.cop));
      sum.cop_zmp_max = std::max(sum.cop_zmp_max, (st.cop - st.zmp_multibody).norm());
      sum.root_residual_max = std::max(sum.root_residual_max, st.root_residual);
    }
    sum.ik_residual_max = std::max(sum.ik_residual_max, st.ik.residual);
    sum.ik_iterations_max = std::max(sum.ik_iterations_max, st.ik.iterations);
    iterations += st.ik.iterations;
    if (!st.ik.converged) ++sum.ik_not_converged;
    sum.foot_position_error_max = std::max(sum.foot_position_error_max, st.foot_position_error);
    sum.foot_rotation_error_max = std::max(sum.foot_rotation_error_max, st.foot_rotation_error);
    sum.torque_max = sum.torque_max.cwiseMax(st.tau.tail(nj).cwiseAbs());
  }
  sum.ik_iterations_mean = S(iterations) / S(n);
  if (options.rated_torque.size() == nj) {
    sum.rated_ratio = sum.torque_max.cwiseQuotient(options.rated_torque);
    sum.rated_ratio.maxCoeff(&sum.worst_joint);
  }
  if (options.max_torque.size() == nj) sum.max_ratio = sum.torque_max.cwiseQuotient(options.max_torque);
  return run;
}

}  // namespace spatial::walking
