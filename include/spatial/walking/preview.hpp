#pragma once
/// \file walking/preview.hpp
/// ZMP preview control on the cart-table model (Kajita, Kanehiro, Kaneko, Fujiwara, Harada, Yokoi, Hirukawa,
/// "Biped walking pattern generation by using preview control of zero-moment point", ICRA 2003), in the
/// integral-augmented (increment) form of Katayama, Ohki, Inoue, Kato, "Design of an optimal controller for a
/// discrete-time system subject to previewable demand", Int. J. Control 41(3), 1985. See docs/walking.md.
///
/// Model, per horizontal axis (world x and world y, independent and with the same gains): the CoM at constant
/// height z_c above the ground, state x = [c, ċ, c̈] (m, m/s, m/s²), input the CoM jerk u (m/s³), sample time dt,
///   x(k+1) = A x(k) + B u(k),  A = [1 dt dt²/2; 0 1 dt; 0 0 1],  B = [dt³/6; dt²/2; dt]   (exact for a constant
///   jerk over the sample),
///   p(k)   = C x(k),           C = [1 0 −z_c/g]                                         (the cart-table ZMP).
/// Augmented system (e(k) = p(k) − p_ref(k), Δ the backward difference): z(k) = [e(k); Δx(k)],
///   z(k+1) = Ã z(k) + B̃ Δu(k) − Ĩ Δp_ref(k+1),  Ã = [1 CA; 0 A],  B̃ = [CB; B],  Ĩ = [1; 0; 0; 0].
/// Cost  J = Σ_k  Q_e e(k)² + Δx(k)ᵀ Q_x Δx(k) + R Δu(k)²   (Q_x = q_x I₃).
/// P solves the discrete algebraic Riccati equation (DARE)
///   P = Ãᵀ P Ã − Ãᵀ P B̃ (R + B̃ᵀ P B̃)⁻¹ B̃ᵀ P Ã + Q̃,  Q̃ = diag(Q_e, Q_x),
/// here by the structured doubling algorithm (quadratic convergence) refined by Newton (Hewer) steps.
/// Gains: K = (R + B̃ᵀ P B̃)⁻¹ B̃ᵀ P Ã = [G_i, G_x];  A_c = Ã − B̃ K;
///   G_p(j) = −(R + B̃ᵀ P B̃)⁻¹ B̃ᵀ (A_cᵀ)^{j−1} P Ĩ,  j = 1 … N_L   (so G_p(1) = −G_i, as in Kajita 2003).
/// Control law (the optimum of J when the reference is known up to k + N_L and constant after it):
///   Δu(k) = −G_i e(k) − G_x Δx(k) − Σ_{j=1}^{N_L} G_p(j) Δp_ref(k+j),   u(k) = u(k−1) + Δu(k).
/// Summed from a state at rest this is Kajita's u(k) = −G_i Σ e − G_x x(k) − Σ G_p(j) p_ref(k+j) up to a constant;
/// the increment form needs no constant and holds the reference at the window's last value beyond the window.
///
/// Costs. The constructor solves the DARE and computes the gains (allocates the N_L preview gains; throws
/// std::invalid_argument on bad parameters, std::runtime_error if the DARE does not converge). `step` neither
/// allocates nor throws; `run_preview` allocates its result only.

#include "spatial/walking/footsteps.hpp"

#include <Eigen/Core>
#include <Eigen/LU>

#include <cassert>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace spatial::walking {

/// Parameters of the preview controller. Defaults: the HOAP-3 (dt = 2 ms, z_c = 0.30 m) with Kajita 2003's
/// weights (Q_e = 1, Q_x = 0, R = 1e-6) and preview horizon (1.6 s). See docs/walking.md for the sources.
template <class S = double>
struct PreviewParameters {
  S dt = S(0.002);             ///< s, > 0: sample time
  S com_height = S(0.30);      ///< m, > 0: z_c, CoM height above the ground (constant)
  S gravity = S(9.81);         ///< m/s², > 0
  S q_error = S(1);            ///< Q_e > 0: weight of the ZMP tracking error
  S q_state = S(0);            ///< q_x ≥ 0: weight of the state increments (Q_x = q_x I₃)
  S r_input = S(1e-6);         ///< R > 0: weight of the jerk increment
  S preview_time = S(1.6);     ///< s, ≥ dt: preview horizon; N_L = round(preview_time / dt)
};

/// The CoM trajectory of `run_preview`: row k is time k dt; columns world x, y. The CoM height is z_c above the
/// ground throughout.
template <class S = double>
struct PreviewTrajectory {
  Eigen::Matrix<S, Eigen::Dynamic, 2> com;           ///< c (m)
  Eigen::Matrix<S, Eigen::Dynamic, 2> com_velocity;  ///< ċ (m/s)
  Eigen::Matrix<S, Eigen::Dynamic, 2> com_acceleration;  ///< c̈ (m/s²)
  Eigen::Matrix<S, Eigen::Dynamic, 2> jerk;          ///< u(k) applied over [k dt, (k+1) dt] (m/s³)
  Eigen::Matrix<S, Eigen::Dynamic, 2> zmp;           ///< cart-table ZMP p = c − (z_c / g) c̈ (m)
};

/// Both horizontal axes' preview controllers (the same gains). The state is a 3 × 2 matrix: rows c, ċ, c̈;
/// columns world x, y.
template <class S = double>
class PreviewController {
 public:
  using State = Eigen::Matrix<S, 3, 2>;
  using Mat4 = Eigen::Matrix<S, 4, 4>;
  using Vec4 = Eigen::Matrix<S, 4, 1>;
  using Row3 = Eigen::Matrix<S, 1, 3>;
  using Reference = Eigen::Matrix<S, Eigen::Dynamic, 2>;

  explicit PreviewController(const PreviewParameters<S>& p) : p_(p) {
    validate(p);
    const S dt = p.dt;
    A_ << S(1), dt, dt * dt / S(2), S(0), S(1), dt, S(0), S(0), S(1);
    B_ << dt * dt * dt / S(6), dt * dt / S(2), dt;
    C_ << S(1), S(0), -p.com_height / p.gravity;
    At_.setZero();
    At_(0, 0) = S(1);
    At_.template block<1, 3>(0, 1) = C_ * A_;
    At_.template block<3, 3>(1, 1) = A_;
    Bt_(0) = (C_ * B_)(0);
    Bt_.template tail<3>() = B_;
    Qt_.setZero();
    Qt_(0, 0) = p.q_error;
    for (int i = 1; i < 4; ++i) Qt_(i, i) = p.q_state;
    solve_dare();
    const S m = p.r_input + Bt_.dot(P_ * Bt_);
    K_ = (Bt_.transpose() * P_ * At_) / m;
    Ac_ = At_ - Bt_ * K_;
    n_ = static_cast<int>(std::lround(static_cast<double>(p.preview_time / p.dt)));
    Gp_.resize(n_);
    Vec4 x = P_.col(0);  // (A_cᵀ)^{j−1} P Ĩ
    for (int j = 0; j < n_; ++j) {
      Gp_(j) = -Bt_.dot(x) / m;
      x = (Ac_.transpose() * x).eval();
    }
    reset(State::Zero());
  }

  const PreviewParameters<S>& parameters() const noexcept { return p_; }
  /// N_L, the number of preview samples.
  int horizon() const noexcept { return n_; }
  const Eigen::Matrix<S, 3, 3>& A() const noexcept { return A_; }
  const Eigen::Matrix<S, 3, 1>& B() const noexcept { return B_; }
  const Row3& C() const noexcept { return C_; }
  const Mat4& augmented_A() const noexcept { return At_; }
  const Vec4& augmented_B() const noexcept { return Bt_; }
  const Mat4& augmented_Q() const noexcept { return Qt_; }
  /// P, the DARE's stabilising solution.
  const Mat4& riccati() const noexcept { return P_; }
  /// Iterations of the doubling algorithm + Newton refinement steps.
  int riccati_iterations() const noexcept { return iterations_; }
  S integral_gain() const noexcept { return K_(0); }
  Row3 state_gain() const noexcept { return K_.template tail<3>(); }
  /// G_p(1) … G_p(N_L) (element j − 1 is G_p(j)).
  const Eigen::Matrix<S, Eigen::Dynamic, 1>& preview_gains() const noexcept { return Gp_; }
  /// A_c = Ã − B̃ [G_i G_x], the closed loop of the augmented system.
  const Mat4& closed_loop() const noexcept { return Ac_; }

  /// The cart-table ZMP of a state (world x, y).
  Vec2<S> zmp(const State& x) const noexcept { return (C_ * x).transpose(); }

  /// Starts at x0 with the CoM's past equal to x0 (x(−1) = x0) and u(−1) = 0: at rest when ċ = c̈ = 0.
  void reset(const State& x0) noexcept {
    x_prev_ = x0;
    u_.setZero();
  }

  /// One sample: from the state x(k) and the reference window ref (row j is p_ref(k + j), j = 0 … N_L; a shorter
  /// window, at least one row, is held at its last row; rows beyond N_L are ignored), applies the control law of
  /// the file comment and returns x(k+1) = A x(k) + B u(k). Call it with the x(k+1) it returned (or a measured
  /// state). No allocation (pass a block of an Eigen matrix with two columns, or such a matrix).
  State step(const State& x, const Eigen::Ref<const Reference>& ref) noexcept {
    assert(ref.rows() >= 1);
    const Eigen::Index last = std::min<Eigen::Index>(ref.rows() - 1, n_);
    for (int a = 0; a < 2; ++a) {
      const S e = C_.dot(x.col(a)) - ref(0, a);
      const Eigen::Matrix<S, 3, 1> dx = x.col(a) - x_prev_.col(a);
      S du = -K_(0) * e - K_.template tail<3>().dot(dx);
      for (Eigen::Index j = 1; j <= last; ++j) du -= Gp_(j - 1) * (ref(j, a) - ref(j - 1, a));
      u_(a) += du;
    }
    x_prev_ = x;
    return A_ * x + B_ * u_;
  }

  /// The jerk of the last step (world x, y).
  const Eigen::Matrix<S, 1, 2>& jerk() const noexcept { return u_; }

  static void validate(const PreviewParameters<S>& p) {
    const auto fail = [](const char* name, const char* rule, S value) {
      std::ostringstream os;
      os << "spatial::walking::PreviewParameters: " << name << " must be " << rule << " (got " << value << ")";
      throw std::invalid_argument(os.str());
    };
    const auto pos = [](S v) { return v > S(0) && std::isfinite(static_cast<double>(v)); };
    if (!pos(p.dt)) fail("dt", "finite and > 0", p.dt);
    if (!pos(p.com_height)) fail("com_height", "finite and > 0", p.com_height);
    if (!pos(p.gravity)) fail("gravity", "finite and > 0", p.gravity);
    if (!pos(p.q_error)) fail("q_error", "finite and > 0", p.q_error);
    if (!(p.q_state >= S(0)) || !std::isfinite(static_cast<double>(p.q_state)))
      fail("q_state", "finite and >= 0", p.q_state);
    if (!pos(p.r_input)) fail("r_input", "finite and > 0", p.r_input);
    if (!pos(p.preview_time) || p.preview_time < p.dt * S(0.5))
      fail("preview_time", "finite and >= dt", p.preview_time);
    if (p.preview_time / p.dt > S(1e7)) fail("preview_time", "at most 1e7 samples", p.preview_time);
  }

 private:
  /// Structured doubling algorithm for P = Aᵀ P A − Aᵀ P B (R + Bᵀ P B)⁻¹ Bᵀ P A + Q (Chu, Fan, Lin, Wang 2004):
  /// A₀ = Ã, G₀ = B̃ R⁻¹ B̃ᵀ, H₀ = Q̃;  W = (I + G H)⁻¹;  A' = A W A, G' = G + A W G Aᵀ, H' = H + Aᵀ H W A;
  /// H → P quadratically.
  void solve_dare() {
    const Mat4 I = Mat4::Identity();
    Mat4 Ak = At_, Gk = Bt_ * Bt_.transpose() / p_.r_input, Hk = Qt_;
    iterations_ = 0;
    bool converged = false;
    for (int it = 0; it < 100 && !converged; ++it) {
      const Mat4 W = (I + Gk * Hk).lu().solve(I);
      const Mat4 Hn = Hk + Ak.transpose() * Hk * W * Ak;
      const Mat4 Gn = Gk + Ak * W * Gk * Ak.transpose();
      const Mat4 An = Ak * W * Ak;
      converged = (Hn - Hk).norm() <= S(64) * Eigen::NumTraits<S>::epsilon() * Hn.norm();
      Hk = S(0.5) * (Hn + Hn.transpose());
      Gk = S(0.5) * (Gn + Gn.transpose());
      Ak = An;
      ++iterations_;
    }
    P_ = Hk;
    // Newton refinement (Hewer 1971): with K and A_c = Ã − B̃ K from the current P, the next P solves the Stein
    // equation P = A_cᵀ P A_c + Q̃ + Kᵀ R K, a 16 × 16 linear system in vec(P). Keeps the P of least residual.
    S best = dare_residual(P_);
    for (int it = 0; it < 8 && best > S(0); ++it) {
      const S m = p_.r_input + Bt_.dot(P_ * Bt_);
      const Eigen::Matrix<S, 1, 4> K = (Bt_.transpose() * P_ * At_) / m;
      const Mat4 Ac = At_ - Bt_ * K;
      const Mat4 rhs = Qt_ + p_.r_input * K.transpose() * K;
      Eigen::Matrix<S, 16, 16> L;
      Eigen::Matrix<S, 16, 1> b;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          b(i + 4 * j) = rhs(i, j);
          for (int l = 0; l < 4; ++l)
            for (int k = 0; k < 4; ++k)
              L(i + 4 * j, k + 4 * l) = (i + 4 * j == k + 4 * l ? S(1) : S(0)) - Ac(k, i) * Ac(l, j);
        }
      const Eigen::Matrix<S, 16, 1> v = L.partialPivLu().solve(b);
      Mat4 Pn = Eigen::Map<const Mat4>(v.data());
      Pn = (S(0.5) * (Pn + Pn.transpose())).eval();
      ++iterations_;
      const S r = dare_residual(Pn);
      if (!(r < best)) break;
      best = r;
      P_ = Pn;
    }
    // the doubling stagnating at round-off is fine when the refined P solves the DARE
    if (!P_.allFinite() || !(best <= std::sqrt(Eigen::NumTraits<S>::epsilon())))
      throw std::runtime_error("spatial::walking::PreviewController: the Riccati equation did not converge");
  }

  /// ‖P − (Ãᵀ P Ã − Ãᵀ P B̃ (R + B̃ᵀ P B̃)⁻¹ B̃ᵀ P Ã + Q̃)‖ / ‖P‖ (Frobenius norms).
  S dare_residual(const Mat4& P) const {
    const S m = p_.r_input + Bt_.dot(P * Bt_);
    const Eigen::Matrix<S, 1, 4> bpa = Bt_.transpose() * P * At_;
    const Mat4 rhs = At_.transpose() * P * At_ - bpa.transpose() * bpa / m + Qt_;
    return (P - rhs).norm() / P.norm();
  }

  PreviewParameters<S> p_;
  Eigen::Matrix<S, 3, 3> A_;
  Eigen::Matrix<S, 3, 1> B_;
  Row3 C_;
  Mat4 At_;
  Vec4 Bt_;
  Mat4 Qt_;
  Mat4 P_;
  Eigen::Matrix<S, 1, 4> K_;
  Mat4 Ac_;
  int n_ = 0;
  Eigen::Matrix<S, Eigen::Dynamic, 1> Gp_;
  int iterations_ = 0;
  State x_prev_;
  Eigen::Matrix<S, 1, 2> u_;
};

/// Runs the controller along a whole reference (row k is p_ref(k dt), columns world x, y; at least one row),
/// starting at rest with the CoM above ref(0) (the controller is reset), the reference held at its last row after
/// the end. Returns the state and the cart-table ZMP at every sample k = 0 … rows − 1.
template <class S>
PreviewTrajectory<S> run_preview(PreviewController<S>& ctl, const Eigen::Matrix<S, Eigen::Dynamic, 2>& ref) {
  const Eigen::Index n = ref.rows();
  if (n < 1) throw std::invalid_argument("spatial::walking::run_preview: the reference has no sample");
  PreviewTrajectory<S> out;
  for (auto* m : {&out.com, &out.com_velocity, &out.com_acceleration, &out.jerk, &out.zmp}) m->resize(n, 2);
  typename PreviewController<S>::State x = PreviewController<S>::State::Zero();
  x.row(0) = ref.row(0);
  ctl.reset(x);
  const Eigen::Index window = ctl.horizon() + 1;
  for (Eigen::Index k = 0; k < n; ++k) {
    out.com.row(k) = x.row(0);
    out.com_velocity.row(k) = x.row(1);
    out.com_acceleration.row(k) = x.row(2);
    out.zmp.row(k) = ctl.zmp(x).transpose();
    x = ctl.step(x, ref.middleRows(k, std::min(window, n - k)));
    out.jerk.row(k) = ctl.jerk();
  }
  return out;
}

/// The reference ZMP of a plan sampled at the controller's dt, then `run_preview` on it.
template <class S>
PreviewTrajectory<S> run_preview(PreviewController<S>& ctl, const FootstepPlan<S>& plan) {
  return run_preview(ctl, sample_zmp_reference(plan, ctl.parameters().dt));
}

}  // namespace spatial::walking
