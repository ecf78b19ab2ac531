#pragma once
/// \file walking/closed_loop.hpp
/// The proof that the walk works (issue 12, "Proof that it walks"): the open-loop whole-body motion of
/// `run_whole_body` played on the rigid-contact simulator of simulation.hpp, with the contacts made and broken at the
/// plan's instants, impacts at touchdown, and joint torques τ = inverse-dynamics feed-forward + a joint PD on the
/// planned angles. The robot is not held anywhere: the free-flyer is unactuated, so the pelvis goes where the feet,
/// the joints and the dynamics put it.
///
/// ## Control (every simulation step, `options.simulation.dt`, default 1 ms)
/// The plan's samples come every control tick T_c (`WholeBodyOptions::preview.dt`, 2 ms); at time t the set-points
/// q*_j, q̇*_j and the feed-forward τ_ff,j of every joint j are linearly interpolated between the two samples around t.
///   τ_j = τ_ff,j + K_p,j (q*_j − q_j) + K_d,j (q̇*_j − q̇_j),
///   K_p,j = m_j ω², K_d,j = 2 ζ m_j ω,  m_j = 1 / G_jj,
/// ω = `pd_frequency`, ζ = `pd_damping_ratio`: each joint's PD is a second-order system of natural frequency ω for
/// the inertia m_j the joint moves, which depends on the contacts: G is the robot's mobility at the standing pose
/// with the current contacts, H⁻¹ with none, H⁻¹ − H⁻¹Jᵀ(JH⁻¹Jᵀ)⁻¹JH⁻¹ with one sole welded (J its 6 rows), and in
/// double support each joint takes the larger of its two single-support inertias (a stance leg's ankle moves the
/// whole robot, ≈ 0.7 kg m²; the same ankle swinging moves a foot). So the gains switch with the contact set, as a
/// real biped's stance and swing gains do: one gain for both would either not hold the body up (the stance ankle
/// must beat the inverted pendulum's gravity stiffness m g l ≈ 25 N m/rad) or be unstable for the swinging leg.
/// K_d dt / m_j = 2 ζ ω dt stays ≤ 0.2 at the defaults (ω = 100 /s, 1 ms: far below the explicit limit 2). ω = 60 /s
/// and below let the stance leg drift over a step (measured). Gains fall at once when a contact set changes and rise
/// over `gain_rise_time` (50 ms): a landing leg still has its swing error, which its stance gains would otherwise
/// turn into a jolt of internal force between the feet. The root's
/// six entries of τ are zero: nothing pushes the pelvis. `feed_forward = false` leaves the PD alone.
///
/// ## Contacts
/// Both soles are candidate 6D contacts (Local axes: λ = [force; moment about the sole frame's origin] in sole
/// axes, the ground on the robot). Foot f is active at t when the plan says so (`FootstepPlan::in_contact`); a
/// contact that is made takes the sole's current pose as its target and starts with an inelastic impact
/// (`impulse_dynamics`); Baumgarte stabilisation (`SimulationSettings::contact_frequency`) holds it there. The
/// contacts are bilateral in the simulation: whether the robot would in fact lift a heel, pull on the ground or slip
/// is judged from the forces: every step checks, for each sole in contact, the normal force (> 0), the friction
/// ratio ‖F_t‖ / F_n (≤ μ), the sole's own CoP inside its rectangle, and the CoP of all contact forces inside the
/// support polygon (the convex hull of the simulated soles in contact).
///
/// ## Figures (`ClosedLoopSummary`)
/// `walked` is true when the simulation ran to the end (every constrained forward dynamics `ok`, finite state), no
/// contact pulled or slipped, the CoP stayed inside the support polygon, and the pelvis ended within
/// `pelvis_tolerance` of the plan. Each sole's own CoP is reported beside (`sole_cop_min_margin`), over the soles
/// that carry at least `sole_load_threshold` of the weight (as force plates do, a nearly unloaded sole's CoP is not
/// judged): it is ≈ 0 by design just before a lift-off, when the sole that leaves carries its last load on its toe
/// edge (the inverse dynamics' split puts the force on the corners), so it is not part of `walked`. Samples are recorded at every control tick (the state at
/// t_k = k T_c and the forces, accelerations and torques of the step that starts there).

#include "spatial/walking/simulation.hpp"
#include "spatial/walking/whole_body.hpp"
#include "spatial/zmp.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace spatial::walking {

/// Settings of `run_closed_loop`.
template <class S = double>
struct ClosedLoopOptions {
  SimulationSettings<S> simulation{};  ///< dt (1 ms), Baumgarte ω (30 /s), restitution (0)
  S pd_frequency = S(100);             ///< ω (1/s) of each joint's PD
  S pd_damping_ratio = S(1);           ///< ζ
  bool feed_forward = true;            ///< add the inverse dynamics' joint torques
  S gain_rise_time = S(0.05);          ///< s: a joint's gains rise to a contact set's larger ones over this time
  S sole_load_threshold = S(0.1);      ///< a sole's own CoP is checked when it carries ≥ this fraction of the weight
  S pelvis_tolerance = S(0.03);        ///< m: the final pelvis error below which the walk counts as done
};

/// One control tick of the simulation (world coordinates unless said otherwise).
template <class ModelT>
struct ClosedLoopSample {
  using S = typename ModelT::Scalar;
  S t = S(0);
  typename ModelT::ConfigVector q;       ///< simulated state at t
  typename ModelT::TangentVector v;      ///< at t (before an impact of this step)
  typename ModelT::TangentVector a;      ///< v̇ of the step from t
  Eigen::Matrix<S, Eigen::Dynamic, 1> tau;  ///< n: joint torques applied in the step from t
  std::array<Vector6<S>, 2> wrench;     ///< per foot (index(Foot)): [force; moment about the sole frame's origin],
                                        ///< sole axes, the ground on the robot; zero when not in contact
  std::array<bool, 2> contact{};        ///< per foot: active in the step
  Vec2<S> cop = Vec2<S>::Zero();        ///< CoP of the contact forces on the ground plane (NaN without contact)
  S margin = S(0);                      ///< signed distance of the CoP to the support polygon's edge (> 0 inside)
  Vec3<S> com = Vec3<S>::Zero();        ///< simulated CoM
  Vec3<S> pelvis = Vec3<S>::Zero();     ///< simulated root origin
};

/// The figures of a closed-loop run (over every simulation step).
template <class S = double>
struct ClosedLoopSummary {
  bool walked = false;                 ///< see the file comment
  bool completed = false;              ///< the simulation reached the end of the plan with a finite state
  int failed_steps = 0;                ///< simulation steps whose constrained dynamics was not `ok`
  int steps_completed = 0;             ///< the plan's steps whose touchdown was reached
  S cop_min_margin = S(0);             ///< min signed distance of the CoP to the support polygon's edge (m)
  S cop_min_time = S(0);               ///< s: when
  S sole_cop_min_margin = S(0);        ///< min over soles in contact of their own CoP's distance to the sole's edge
  S sole_cop_min_time = S(0);          ///< s: when
  int sole_cop_unchecked = 0;          ///< simulation steps × soles in contact below the load threshold
  S min_normal_force = S(0);           ///< N, over soles in contact
  int pulls = 0;                       ///< steps with a normal force ≤ 0
  S max_friction_ratio = S(0);         ///< max ‖F_t‖ / F_n
  int slips = 0;                       ///< steps with ‖F_t‖ > μ F_n
  S pelvis_final_error = S(0);         ///< ‖pelvis − plan‖ at the end (m)
  S pelvis_max_error = S(0);           ///< max over the run (m)
  S com_max_error = S(0);              ///< max ‖CoM − plan‖ (m)
  S joint_error_max = S(0);            ///< max |q_j − q*_j| (rad)
  int impacts = 0;                     ///< touchdowns (contacts made)
  S impact_energy_max = S(0);          ///< J, the largest kinetic energy an impact took
  S seconds = S(0);                    ///< wall-clock time of the simulation
  S step_seconds_mean = S(0);          ///< per simulation step (control + dynamics + checks)
};

template <class ModelT>
struct ClosedLoopRun {
  std::vector<ClosedLoopSample<ModelT>> samples;  ///< one per control tick
  ClosedLoopSummary<typename ModelT::Scalar> summary;
  /// n × 4: the PD gains, column = the contact set (0 none, 1 left sole, 2 right sole, 3 both)
  Eigen::Matrix<typename ModelT::Scalar, Eigen::Dynamic, 4> kp, kd;
};

/// Simulates `open` (the result of `run_whole_body` for the same model, frames, plan and options) in closed loop; see
/// the file comment. Throws std::invalid_argument when `open` has no samples or the simulation step does not divide
/// the control tick.
template <class ModelT>
ClosedLoopRun<ModelT> run_closed_loop(const ModelT& model, const WholeBodyFrames& frames,
                                      const FootstepPlan<typename ModelT::Scalar>& plan,
                                      const WholeBodyRun<ModelT>& open,
                                      const WholeBodyOptions<typename ModelT::Scalar>& wb,
                                      const ClosedLoopOptions<typename ModelT::Scalar>& options = {}) {
  using S = typename ModelT::Scalar;
  using Clock = std::chrono::steady_clock;
  using Traits = spatial::detail::ModelTraits<ModelT>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  if (open.samples.empty()) throw std::invalid_argument("run_closed_loop: the open-loop run has no samples");
  const S Tc = wb.preview.dt, dt = options.simulation.dt;
  const long ratio = std::lround(Tc / dt);
  if (ratio < 1 || std::abs(S(ratio) * dt - Tc) > S(1e-9) * Tc)
    throw std::invalid_argument("run_closed_loop: the simulation step must divide the control tick");
  const int nj = model.njoints();
  typename Traits::DataType data(model);

  // PD gains from the standing pose's inertia, per contact set (mask: bit 0 left sole, bit 1 right sole)
  ClosedLoopRun<ModelT> run;
  const auto& s0 = open.samples.front();
  using MatrixX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  const int nv = model.nv();
  const MatrixX H = crba(model, data, s0.q);
  const MatrixX Hinv = H.ldlt().solve(MatrixX::Identity(nv, nv));
  const S w = options.pd_frequency, z = options.pd_damping_ratio;
  Eigen::Matrix<S, Eigen::Dynamic, 4> mass(nj, 4);
  mass.col(0) = Hinv.diagonal().tail(nj).cwiseInverse();
  for (int f = 0; f < 2; ++f) {
    MatrixX J(6, nv);
    compute_frame_jacobian(model, data, s0.q, f == 0 ? frames.left_sole : frames.right_sole, ReferenceFrame::Local, J);
    const MatrixX HJ = Hinv * J.transpose();
    const MatrixX G = Hinv - HJ * (J * HJ).ldlt().solve(HJ.transpose());  // the mobility with that sole welded
    mass.col(1 + f) = G.diagonal().tail(nj).cwiseInverse();
  }
  mass.col(3) = mass.col(1).cwiseMax(mass.col(2));
  run.kp = w * w * mass;
  run.kd = S(2) * z * w * mass;

  ContactSimulator<ModelT> sim(model, {sole_contact(frames.left_sole, wb), sole_contact(frames.right_sole, wb)},
                               options.simulation);
  const auto mask_at = [&](S t) {
    return (plan.in_contact(Foot::left, t) ? 1u : 0u) | (plan.in_contact(Foot::right, t) ? 2u : 0u);
  };
  sim.reset(s0.q, Vector::Zero(model.nv()), mask_at(S(0)));

  ClosedLoopSummary<S>& sum = run.summary;
  sum.cop_min_margin = sum.sole_cop_min_margin = sum.min_normal_force = std::numeric_limits<S>::infinity();
  const std::size_t n = open.samples.size();
  const long steps = static_cast<long>(n - 1) * ratio;
  const S ground = plan.parameters().ground_height;
  const S mu = wb.friction;
  const S load_min = options.sole_load_threshold * model.total_mass() * model.tree().gravity().norm();
  Vector tau = Vector::Zero(model.nv()), qref(nj), vref(nj), ff(nj);
  Vector kp = run.kp.col(mask_at(S(0))), kd = run.kd.col(mask_at(S(0)));
  const S rise = options.gain_rise_time > S(0) ? dt / options.gain_rise_time : S(1);
  typename ModelT::ConfigVector q_prev = s0.q;
  typename ModelT::TangentVector v_prev = Vector::Zero(model.nv());
  run.samples.reserve(n);
  bool alive = true;
  const auto t0 = Clock::now();
  long i = 0;
  for (; i < steps && alive; ++i) {
    const S t = S(i) * dt;
    const std::size_t k = static_cast<std::size_t>(i / ratio);
    const S alpha = S(i % ratio) / S(ratio);
    const auto& a = open.samples[k];
    const auto& b = open.samples[std::min(k + 1, n - 1)];
    qref = (S(1) - alpha) * a.q.tail(nj) + alpha * b.q.tail(nj);
    vref = (S(1) - alpha) * a.v.tail(nj) + alpha * b.v.tail(nj);
    if (options.feed_forward) ff = (S(1) - alpha) * a.tau.tail(nj) + alpha * b.tau.tail(nj);
    else ff.setZero();
    q_prev = sim.q();
    v_prev = sim.v();
    sum.joint_error_max = std::max(sum.joint_error_max, (q_prev.tail(nj) - qref).cwiseAbs().maxCoeff());
    const unsigned mask = mask_at(t);
    // gains fall at once and rise at a bounded rate (a leg that lands keeps its swing error for a moment)
    kp = run.kp.col(mask).cwiseMin(kp + rise * run.kp.col(mask));
    kd = run.kd.col(mask).cwiseMin(kd + rise * run.kd.col(mask));
    tau.tail(nj) = ff + kp.cwiseProduct(qref - q_prev.tail(nj)) + kd.cwiseProduct(vref - v_prev.tail(nj));
    sim.step(tau, mask);
    if (sim.impact()) {
      ++sum.impacts;
      sum.impact_energy_max = std::max(sum.impact_energy_max, sim.impact_energy_loss());
    }
    const auto* cd = sim.active();
    if (cd != nullptr && !cd->ok) ++sum.failed_steps;
    if (!sim.q().allFinite() || !sim.v().allFinite()) alive = false;

    // forces, CoPs, support polygon (data(): the kinematics of q_prev)
    ClosedLoopSample<ModelT> smp;
    smp.wrench[0].setZero();
    smp.wrench[1].setZero();
    std::array<Vec2<S>, 8> corners{};
    int nc = 0, r = 0;
    for (Foot f : {Foot::left, Foot::right}) {
      const int fi = index(f);
      smp.contact[static_cast<std::size_t>(fi)] = (sim.mask() >> fi) & 1u;
      if (!smp.contact[static_cast<std::size_t>(fi)]) continue;
      const Vector6<S> wr = cd->lambda.template segment<6>(6 * r++);
      smp.wrench[static_cast<std::size_t>(fi)] = wr;
      const S fn = wr[2];
      sum.min_normal_force = std::min(sum.min_normal_force, fn);
      if (!(fn > S(0))) {
        ++sum.pulls;
      } else {
        const S ratio_t = std::hypot(wr[0], wr[1]) / fn;
        sum.max_friction_ratio = std::max(sum.max_friction_ratio, ratio_t);
        if (ratio_t > mu) ++sum.slips;
        const S cx = -wr[4] / fn, cy = wr[3] / fn;  // the sole's CoP in sole axes (moment about its origin)
        const S sm = std::min({wb.sole.front - cx, cx + wb.sole.back, wb.sole.left - cy, cy + wb.sole.right});
        if (fn < load_min) ++sum.sole_cop_unchecked;
        else if (sm < sum.sole_cop_min_margin) sum.sole_cop_min_margin = sm, sum.sole_cop_min_time = t;
      }
      const auto pose = frame_pose(model, sim.data(), f == Foot::left ? frames.left_sole : frames.right_sole);
      const Matrix3<S> R = pose.linear();
      const S yaw = std::atan2(R(1, 0), R(0, 0));
      const auto c4 = sole_corners(wb.sole, Vec2<S>(pose.translation().x(), pose.translation().y()), yaw);
      for (const auto& c : c4) corners[static_cast<std::size_t>(nc++)] = c;
    }
    if (cd != nullptr) {
      const Vector3<S> p = center_of_pressure(model, sim.data(), *cd, ground);
      smp.cop = p.template head<2>();
      smp.margin = signed_distance(convex_hull<S, 8>(corners, nc), smp.cop);
      const S m = std::isfinite(smp.margin) ? smp.margin : -std::numeric_limits<S>::infinity();
      if (m < sum.cop_min_margin) sum.cop_min_margin = m, sum.cop_min_time = t;
    } else {
      smp.cop.setConstant(std::numeric_limits<S>::quiet_NaN());
      smp.margin = std::numeric_limits<S>::quiet_NaN();
    }

    // tracking of the plan at the control ticks
    if (i % ratio == 0) {
      smp.t = t;
      smp.q = q_prev;
      smp.v = v_prev;
      smp.a = sim.qdd();
      smp.tau = tau.tail(nj);
      smp.com = center_of_mass(model, data, q_prev);
      smp.pelvis = q_prev.template head<3>();
      sum.com_max_error = std::max(sum.com_max_error, (smp.com - a.com).norm());
      sum.pelvis_max_error = std::max(sum.pelvis_max_error, (smp.pelvis - a.q.template head<3>()).norm());
      run.samples.push_back(smp);
    }
  }
  sum.seconds = std::chrono::duration<S>(Clock::now() - t0).count();
  sum.step_seconds_mean = i > 0 ? sum.seconds / S(i) : S(0);
  sum.completed = alive && i == steps;
  if (sum.completed) {
    sum.pelvis_final_error = (sim.q().template head<3>() - open.samples.back().q.template head<3>()).norm();
    sum.pelvis_max_error = std::max(sum.pelvis_max_error, sum.pelvis_final_error);
  } else {
    sum.pelvis_final_error = std::numeric_limits<S>::infinity();
  }
  const S t_end = S(i) * dt;
  for (const Phase<S>& ph : plan.phases())
    if (ph.kind == PhaseKind::single_support && ph.end <= t_end) ++sum.steps_completed;
  sum.walked = sum.completed && sum.failed_steps == 0 && sum.pulls == 0 && sum.slips == 0 && sum.cop_min_margin > S(0) &&
               sum.pelvis_final_error <= options.pelvis_tolerance;
  return run;
}

}  // namespace spatial::walking
