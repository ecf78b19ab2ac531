#pragma once
// A small iterative LQR (iLQR, the Gauss–Newton form of DDP) for a fixed-base robot model, with box limits on the
// joint torques: the user of the analytical derivatives of forward dynamics (derivatives.hpp) that issue 13 asks for.
// Used by tools/ilqr_example.cpp (`spatial-ilqr`, run by scripts/main.sh) and tests/test_ilqr.cpp.
//
// Problem. State x = (q, v) ∈ R²ⁿ, control u = τ ∈ Rⁿ, N steps of dt, semi-implicit Euler:
//   v⁺ = v + dt q̈(q, v, τ),   q⁺ = q + dt v⁺,
// so with F_q = ∂q̈/∂q, F_v = ∂q̈/∂v, F_τ = ∂q̈/∂τ:
//   A = ∂x⁺/∂x = [1 + dt² F_q, dt 1 + dt² F_v; dt F_q, 1 + dt F_v],   B = ∂x⁺/∂u = [dt² F_τ; dt F_τ].
// Cost: Σₖ dt (½ w_q ‖qₖ − q*‖² + ½ r ‖uₖ‖²) + ½ W_q ‖q_N − q*‖² + ½ W_v ‖v_N‖².
// Torque limits |uᵢ| ≤ u_maxᵢ: the backward pass solves each step's box-constrained quadratic in u by one
// projected-Newton step (the controls at a bound and pushed beyond it are clamped and lose their feedback; the
// free ones are re-solved with the clamped ones fixed), the forward pass clamps too, so every iterate respects the
// limits. Levenberg–Marquardt regularisation μ on Q_uu, backtracking line search on the feed-forward term.
//
// The derivatives come from a `Linearize` functor: analytical (`aba_derivatives`) or forward finite differences of
// ABA (3n + 1 calls), so the same solver can be timed with either.

#include <spatial/spatial.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

namespace spatial::ilqr {

using Mat = Eigen::MatrixXd;
using Vec = Eigen::VectorXd;

struct Problem {
  int n = 0;                  ///< joints
  int steps = 100;            ///< N
  double dt = 0.01;           ///< s
  Vec q0, v0;                 ///< initial state
  Vec q_target;               ///< q*
  Vec u_max;                  ///< torque limits (> 0)
  double w_q = 1.0;           ///< running weight on the pose error (per second)
  double r = 1e-2;            ///< running weight on the torques (per second)
  double W_q = 1e3;           ///< terminal weight on the pose error
  double W_v = 1e2;           ///< terminal weight on the velocity
};

struct Options {
  int max_iterations = 60;
  double tolerance = 1e-7;    ///< stop when the relative cost decrease falls below this
  double mu0 = 1e-6, mu_min = 1e-9, mu_max = 1e10;
};

/// One iteration's record.
struct Iteration {
  int iteration = 0;
  double cost = 0;            ///< cost after the iteration (iteration 0: the initial rollout)
  double step = 0;            ///< accepted line-search step (0: rejected)
  double mu = 0;              ///< regularisation used
  double seconds = 0;         ///< wall time of the iteration
  double derivative_seconds = 0;  ///< of which computing the derivatives along the trajectory
};

struct Result {
  std::vector<Vec> x, u;      ///< states (N + 1) and controls (N)
  std::vector<Iteration> iterations;
  bool converged = false;
};

/// Analytical derivatives of forward dynamics: aba_derivatives.
template <class ModelT, class DataT, class DerivT>
struct AnalyticalLinearize {
  const ModelT& model;
  DataT& data;
  DerivT& dd;
  void operator()(const Vec& q, const Vec& v, const Vec& u, Vec& qdd, Mat& Fq, Mat& Fv, Mat& Fu) {
    aba_derivatives(model, data, dd, q, v, u);
    qdd = data.qdd;
    Fq = dd.dqdd_dq;
    Fv = dd.dqdd_dv;
    Fu = dd.dqdd_dtau;
  }
};

/// Forward differences of ABA with step h: 3n + 1 calls.
template <class ModelT, class DataT>
struct FiniteDifferenceLinearize {
  const ModelT& model;
  DataT& data;
  double h = 1e-7;
  Vec x;
  void operator()(const Vec& q, const Vec& v, const Vec& u, Vec& qdd, Mat& Fq, Mat& Fv, Mat& Fu) {
    qdd = aba(model, data, q, v, u);
    const int n = static_cast<int>(q.size());
    for (int k = 0; k < n; ++k) {
      x = q;
      x[k] += h;
      Fq.col(k) = (aba(model, data, x, v, u) - qdd) / h;
      x = v;
      x[k] += h;
      Fv.col(k) = (aba(model, data, q, x, u) - qdd) / h;
      x = u;
      x[k] += h;
      Fu.col(k) = (aba(model, data, q, v, x) - qdd) / h;
    }
  }
};

/// One step of the discrete dynamics.
template <class ModelT, class DataT>
Vec step(const ModelT& model, DataT& data, const Problem& p, const Vec& x, const Vec& u) {
  const int n = p.n;
  const Vec qdd = aba(model, data, x.head(n), x.tail(n), u);
  Vec y(2 * n);
  y.tail(n) = x.tail(n) + p.dt * qdd;
  y.head(n) = x.head(n) + p.dt * y.tail(n);
  return y;
}

inline double running_cost(const Problem& p, const Vec& x, const Vec& u) {
  return p.dt * (0.5 * p.w_q * (x.head(p.n) - p.q_target).squaredNorm() + 0.5 * p.r * u.squaredNorm());
}
inline double terminal_cost(const Problem& p, const Vec& x) {
  return 0.5 * p.W_q * (x.head(p.n) - p.q_target).squaredNorm() + 0.5 * p.W_v * x.tail(p.n).squaredNorm();
}

template <class ModelT, class DataT>
double rollout_cost(const ModelT& model, DataT& data, const Problem& p, std::vector<Vec>& x, const std::vector<Vec>& u) {
  double J = 0;
  for (int k = 0; k < p.steps; ++k) {
    const auto s = static_cast<std::size_t>(k);
    J += running_cost(p, x[s], u[s]);
    x[s + 1] = step(model, data, p, x[s], u[s]);
  }
  return J + terminal_cost(p, x.back());
}

/// Solves `p` from the controls `u_init` (N of them; clamped to the limits), with `linearize` for the derivatives.
template <class ModelT, class DataT, class Linearize>
Result solve(const ModelT& model, DataT& data, const Problem& p, std::vector<Vec> u_init, Linearize&& linearize,
             const Options& opt = Options()) {
  using clock = std::chrono::steady_clock;
  const int n = p.n, nx = 2 * n, N = p.steps;
  const auto clamp = [&](Vec& u) { u = u.cwiseMax(-p.u_max).cwiseMin(p.u_max); };
  Result res;
  res.u = std::move(u_init);
  for (auto& u : res.u) clamp(u);
  res.x.assign(static_cast<std::size_t>(N + 1), Vec::Zero(nx));
  res.x[0] << p.q0, p.v0;
  double J = rollout_cost(model, data, p, res.x, res.u);
  res.iterations.push_back({0, J, 0, 0, 0, 0});

  std::vector<Mat> A(static_cast<std::size_t>(N)), B(static_cast<std::size_t>(N)), K(static_cast<std::size_t>(N));
  std::vector<Vec> kff(static_cast<std::size_t>(N));
  std::vector<Vec> x_new(static_cast<std::size_t>(N + 1)), u_new(static_cast<std::size_t>(N));
  Vec qdd(n);
  Mat Fq(n, n), Fv(n, n), Fu(n, n);
  const Mat I = Mat::Identity(n, n);
  double mu = opt.mu0;

  for (int it = 1; it <= opt.max_iterations; ++it) {
    const auto t0 = clock::now();
    // Linearise along the trajectory.
    for (int k = 0; k < N; ++k) {
      const auto s = static_cast<std::size_t>(k);
      linearize(Vec(res.x[s].head(n)), Vec(res.x[s].tail(n)), res.u[s], qdd, Fq, Fv, Fu);
      Mat& a = A[s];
      Mat& b = B[s];
      a.resize(nx, nx);
      b.resize(nx, n);
      a.topLeftCorner(n, n) = I + p.dt * p.dt * Fq;
      a.topRightCorner(n, n) = p.dt * I + p.dt * p.dt * Fv;
      a.bottomLeftCorner(n, n) = p.dt * Fq;
      a.bottomRightCorner(n, n) = I + p.dt * Fv;
      b.topRows(n) = p.dt * p.dt * Fu;
      b.bottomRows(n) = p.dt * Fu;
    }
    const auto t1 = clock::now();

    // Backward pass (restarted with a larger μ when Q_uu + μ1 is not positive definite).
    bool ok = false;
    while (!ok && mu <= opt.mu_max) {
      ok = true;
      Vec Vx(nx);
      Mat Vxx = Mat::Zero(nx, nx);
      const Vec& xN = res.x.back();
      Vx << p.W_q * (xN.head(n) - p.q_target), p.W_v * xN.tail(n);
      Vxx.topLeftCorner(n, n) = p.W_q * I;
      Vxx.bottomRightCorner(n, n) = p.W_v * I;
      for (int k = N - 1; k >= 0; --k) {
        const auto s = static_cast<std::size_t>(k);
        const Vec& x = res.x[s];
        const Vec& u = res.u[s];
        Vec lx = Vec::Zero(nx);
        lx.head(n) = p.dt * p.w_q * (x.head(n) - p.q_target);
        const Vec lu = p.dt * p.r * u;
        const Vec Qx = lx + A[s].transpose() * Vx;
        const Vec Qu = lu + B[s].transpose() * Vx;
        const Mat VB = Vxx * B[s];
        Mat Qxx = A[s].transpose() * Vxx * A[s];
        Qxx.topLeftCorner(n, n).diagonal().array() += p.dt * p.w_q;
        Mat Quu = B[s].transpose() * VB;
        Quu.diagonal().array() += p.dt * p.r;
        const Mat Qux = VB.transpose() * A[s];
        Mat Quu_reg = Quu;
        Quu_reg.diagonal().array() += mu;
        Eigen::LLT<Mat> llt(Quu_reg);
        if (llt.info() != Eigen::Success) {
          ok = false;
          break;
        }
        // Unconstrained step, then one projected-Newton correction for the controls it pushes past a bound.
        Vec kk = -llt.solve(Qu);
        Mat KK = -llt.solve(Qux);
        std::vector<int> free, clamped;
        for (int i = 0; i < n; ++i) {
          const double ui = u[i] + kk[i];
          if (ui > p.u_max[i] || ui < -p.u_max[i]) clamped.push_back(i);
          else free.push_back(i);
        }
        if (!clamped.empty()) {
          Vec du_c(static_cast<Eigen::Index>(clamped.size()));
          for (std::size_t c = 0; c < clamped.size(); ++c) {
            const int i = clamped[c];
            const double target = std::clamp(u[i] + kk[i], -p.u_max[i], p.u_max[i]);
            du_c[static_cast<Eigen::Index>(c)] = target - u[i];
            kk[i] = target - u[i];
            KK.row(i).setZero();
          }
          if (!free.empty()) {
            const auto nf = static_cast<Eigen::Index>(free.size());
            Mat Qff(nf, nf), Qfc(nf, static_cast<Eigen::Index>(clamped.size())), Qfx(nf, nx);
            Vec qf(nf);
            for (Eigen::Index a = 0; a < nf; ++a) {
              const int i = free[static_cast<std::size_t>(a)];
              qf[a] = Qu[i];
              Qfx.row(a) = Qux.row(i);
              for (Eigen::Index b = 0; b < nf; ++b) Qff(a, b) = Quu_reg(i, free[static_cast<std::size_t>(b)]);
              for (std::size_t c = 0; c < clamped.size(); ++c)
                Qfc(a, static_cast<Eigen::Index>(c)) = Quu(i, clamped[c]);
            }
            const Eigen::LLT<Mat> lf(Qff);
            const Vec kf = -lf.solve(qf + Qfc * du_c);
            const Mat Kf = -lf.solve(Qfx);
            for (Eigen::Index a = 0; a < nf; ++a) {
              const int i = free[static_cast<std::size_t>(a)];
              kk[i] = kf[a];
              KK.row(i) = Kf.row(a);
            }
          }
        }
        kff[s] = kk;
        K[s] = KK;
        Vx = Qx + KK.transpose() * (Quu * kk) + KK.transpose() * Qu + Qux.transpose() * kk;
        Vxx = Qxx + KK.transpose() * Quu * KK + KK.transpose() * Qux + Qux.transpose() * KK;
        Vxx = 0.5 * (Vxx + Vxx.transpose()).eval();
      }
      if (!ok) mu = std::max(mu * 10, opt.mu_min);
    }
    if (!ok) break;

    // Forward pass with a backtracking line search on the feed-forward term.
    double accepted = 0, J_new = J;
    for (double alpha = 1.0; alpha > 1e-4; alpha *= 0.5) {
      x_new[0] = res.x[0];
      double Jt = 0;
      for (int k = 0; k < N; ++k) {
        const auto s = static_cast<std::size_t>(k);
        u_new[s] = res.u[s] + alpha * kff[s] + K[s] * (x_new[s] - res.x[s]);
        clamp(u_new[s]);
        Jt += running_cost(p, x_new[s], u_new[s]);
        x_new[s + 1] = step(model, data, p, x_new[s], u_new[s]);
      }
      Jt += terminal_cost(p, x_new.back());
      if (std::isfinite(Jt) && Jt < J) {
        accepted = alpha;
        J_new = Jt;
        break;
      }
    }
    const auto t2 = clock::now();
    const double decrease = J - J_new;
    if (accepted > 0) {
      res.x.swap(x_new);
      res.u.swap(u_new);
      x_new.assign(res.x.size(), Vec());
      u_new.assign(res.u.size(), Vec());
      J = J_new;
      mu = std::max(mu / 10, opt.mu_min);
    } else {
      mu *= 10;
    }
    res.iterations.push_back({it, J, accepted, mu, std::chrono::duration<double>(t2 - t0).count(),
                              std::chrono::duration<double>(t1 - t0).count()});
    if (accepted > 0 && decrease < opt.tolerance * J) {
      res.converged = true;
      break;
    }
    if (mu > opt.mu_max) break;
  }
  return res;
}

}  // namespace spatial::ilqr
