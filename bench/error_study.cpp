// Run time against error: the accuracy half of the study (the run times come from the benchmark JSON; the report
// joins them). Writes JSON to the file named by the first argument (default: standard output).
//
// 1. Per algorithm and scalar: every algorithm of bench_algorithms, in float and in double, on every bench model,
//    against the same algorithm in long double on the same model (`model.cast<long double>()`) and the same inputs (64 states of the shared pool). The float and double models are the double model cast
//    down, and the inputs are the double pool cast down, so the error includes the rounding of parameters and
//    inputs, as a user of that scalar type gets it. Error = max over states of ‖y − y_ref‖∞ / ‖y_ref‖∞ (y: τ, H, q̈,
//    or every body's pose [E r] for forward kinematics). This covers float vs double and ABA vs CRBA + tree LTDL vs
//    CRBA + dense Cholesky (Eigen LLT). The derivatives of RNEA (y = [∂τ/∂q ∂τ/∂q̇]) analytically
//    (RNEA_derivatives), by forward differences (RNEA_derivatives_fd, step √ε) and by central differences
//    (RNEA_derivatives_central, step ∛ε), and in double by forward-mode automatic differentiation
//    (RNEA_derivatives_ad, tests/support/autodiff.hpp), all against the analytical derivatives in long double.
//    With spatial::batch (SPATIAL_ERROR_STUDY_BATCH), also the batched algorithms ("<algorithm>_batch": RNEA,
//    GravityTorques, BiasForces, CRBA, FD_CRBA_LTDL, ABA over the same states in one call of spatial::Batch, run-time
//    tree, one thread), in float and double: the points of the batched variants in the run-time-against-error chart.
// 2. Simulation: integrators (semi-implicit Euler, explicit midpoint RK2, classic RK4) at several step sizes on the
//    21-body model over 1 s of simulated time, from a random state, with τ = −D q̇ (light joint damping) and forward
//    dynamics by ABA in double. Error = max |q(1 s) − q_ref(1 s)| against RK4 in long double with a step 4× finer than
//    the finest tested; cost = median CPU time (of this thread, robust on a shared machine) of one simulated second,
//    measured here over 5 runs.
// 3. The stepping scene (tools/scenes.hpp): the resultant force of the ground on the robot by the full 21-DoF model
//    (double, float), reduced models with locked limbs and the double pendulum, against the full model in long
//    double, with the time per call of each (bench/error_study_scenes.hpp). Needs the URDF loader: without it
//    (SPATIAL_ERROR_STUDY_SCENES undefined) it is recorded as pending in the JSON.
#include "bench_models.hpp"
#include "fd_derivatives.hpp"
#include "support/autodiff.hpp"
#include "support/integrators.hpp"
#ifdef SPATIAL_ERROR_STUDY_SCENES
#include "error_study_scenes.hpp"
#endif
#ifdef SPATIAL_ERROR_STUDY_BATCH
#include <spatial/batch.hpp>
#endif

#include <algorithm>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace {
using namespace spatial;
using namespace spatial::bench;

constexpr int kSamples = 64;
/// The model the integrators run on: the HOAP-3 stance model (21 DoF).
const std::string kSimulationModel = "stance21";

template <class A, class B>
long double rel_error(const A& y, const B& ref) {
  using R = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  const R r = ref.template cast<long double>();
  const R d = y.template cast<long double>() - r;
  const long double scale = r.cwiseAbs().maxCoeff();
  return d.cwiseAbs().maxCoeff() / (scale > 0 ? scale : 1);
}

/// Every body's pose after forward kinematics, as an n×12 matrix [E r].
template <class S, class TreeT>
Eigen::Matrix<S, Eigen::Dynamic, 12> poses(const Model<S, TreeT>& m, const Data<S, TreeT>& d) {
  Eigen::Matrix<S, Eigen::Dynamic, 12> out(m.size(), 12);
  for (int i = 0; i < m.size(); ++i) {
    const Transform<S>& X = d.X_base[static_cast<std::size_t>(i)];
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) out(i, 3 * a + b) = X.E(a, b);
      out(i, 9 + a) = X.r[a];
    }
  }
  return out;
}

struct Point {
  std::string model, algorithm, scalar;
  double max_rel_error, median_rel_error;
};

/// All algorithm outputs of one scalar type on one state.
template <class S, class TreeT>
struct Evaluator {
  Model<S, TreeT> model;
  Data<S, TreeT> data;
  Eigen::LLT<typename Data<S, TreeT>::MatrixN> llt;
  DerivativeData<S, TreeT> dd;
  explicit Evaluator(const Model<S, TreeT>& m) : model(m), data(model), llt(m.size()), dd(model) {}

  template <class V>
  Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> run(const std::string& algorithm, const V& q, const V& qd,
                                                        const V& u) {
    using M = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
    if (algorithm == "RNEA") return M(rnea(model, data, q, qd, u));
    if (algorithm == "GravityTorques") return M(gravity_torques(model, data, q));
    if (algorithm == "BiasForces") return M(bias_forces(model, data, q, qd));
    if (algorithm == "CRBA") return M(crba(model, data, q));
    if (algorithm == "FD_CRBA_LTDL") return M(forward_dynamics_crba(model, data, q, qd, u));
    if (algorithm == "FD_CRBA_DenseLLT") return M(forward_dynamics_dense(model, data, llt, q, qd, u));
    if (algorithm == "ABA") return M(aba(model, data, q, qd, u));
    if (algorithm.rfind("RNEA_derivatives", 0) == 0) {
      if (algorithm == "RNEA_derivatives") rnea_derivatives(model, data, dd, q, qd, u);
      else if (algorithm == "RNEA_derivatives_fd")
        rnea_derivatives_fd(model, data, q, qd, u, dd.dtau_dq, dd.dtau_dv, forward_difference_step<S>());
      else rnea_derivatives_central(model, data, q, qd, u, dd.dtau_dq, dd.dtau_dv, central_difference_step<S>());
      M y(model.size(), 2 * model.size());
      y << dd.dtau_dq, dd.dtau_dv;
      return y;
    }
    forward_kinematics(model, data, q);
    return M(poses(model, data));
  }
};

const char* const kAlgorithms[] = {"RNEA", "GravityTorques", "BiasForces", "CRBA", "FD_CRBA_LTDL", "FD_CRBA_DenseLLT",
                                   "ABA", "FK", "RNEA_derivatives", "RNEA_derivatives_fd", "RNEA_derivatives_central"};
/// The long-double reference of an algorithm: itself, except the finite differences (the analytical derivatives).
std::string reference_of(const std::string& algorithm) {
  return algorithm.rfind("RNEA_derivatives", 0) == 0 ? "RNEA_derivatives" : algorithm;
}

template <class S, class TreeT>
void study_scalar(const BenchModel<TreeT>& entry, const InputPool<double>& pool, std::vector<Point>& out) {
  using Vd = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
  using Vs = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  // Run-time trees throughout: they run the same per-joint code as compile-time trees (README: "the same numbers"),
  // and unrolling every model in three scalar types would cost minutes of compile time. The run-time model is
  // built in double and then cast, exactly like `model.cast<long double>()` of the compile-time model.
  const Model<double> runtime = entry.model.to_runtime();
  Evaluator<long double, DynamicTree> ref(runtime.template cast<long double>());
  Evaluator<S, DynamicTree> ev(runtime.template cast<S>());
  for (const char* algorithm : kAlgorithms) {
    std::vector<double> errors;
    for (int k = 0; k < kSamples && k < pool.size(); ++k) {
      const auto s = static_cast<std::size_t>(k);
      const Vd ql = pool.q[s].cast<long double>(), qdl = pool.qd[s].cast<long double>(), ul = pool.u[s].cast<long double>();
      const Vs qs = pool.q[s].cast<S>(), qds = pool.qd[s].cast<S>(), us = pool.u[s].cast<S>();
      const auto y_ref = ref.run(reference_of(algorithm), ql, qdl, ul);
      const auto y = ev.run(algorithm, qs, qds, us);
      errors.push_back(static_cast<double>(rel_error(y, y_ref)));
    }
    std::sort(errors.begin(), errors.end());
    out.push_back({entry.name, algorithm, scalar_name<S>(), errors.back(), errors[errors.size() / 2]});
  }
#ifdef SPATIAL_ERROR_STUDY_BATCH
  {
    // The batched algorithms (spatial::Batch, one state per SIMD lane; bench_batch times them), "<algorithm>_batch":
    // the same kSamples states in one call, against the same long-double references.
    using Ms = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
    const int n = runtime.size(), B = std::min(kSamples, pool.size());
    Batch<S> batch(runtime.template cast<S>(), 1);
    Ms Q(n, B), V(n, B), U(n, B), Y(n, B), H(n, n * B);
    for (int k = 0; k < B; ++k) {
      const auto s = static_cast<std::size_t>(k);
      Q.col(k) = pool.q[s].cast<S>();
      V.col(k) = pool.qd[s].cast<S>();
      U.col(k) = pool.u[s].cast<S>();
    }
    for (const char* algorithm : {"RNEA", "GravityTorques", "BiasForces", "CRBA", "FD_CRBA_LTDL", "ABA"}) {
      const std::string a = algorithm;
      if (a == "RNEA") batch.rnea(Q, V, U, Y);
      else if (a == "GravityTorques") batch.gravity(Q, Y);
      else if (a == "BiasForces") batch.bias(Q, V, Y);
      else if (a == "CRBA") batch.crba(Q, H);
      else if (a == "FD_CRBA_LTDL") batch.forward_dynamics_crba(Q, V, U, Y);
      else batch.aba(Q, V, U, Y);
      std::vector<double> errors;
      for (int k = 0; k < B; ++k) {
        const auto s = static_cast<std::size_t>(k);
        const Vd ql = pool.q[s].cast<long double>(), qdl = pool.qd[s].cast<long double>(),
                 ul = pool.u[s].cast<long double>();
        const auto y_ref = ref.run(a, ql, qdl, ul);
        errors.push_back(a == "CRBA" ? static_cast<double>(rel_error(Ms(H.middleCols(k * n, n)), y_ref))
                                     : static_cast<double>(rel_error(Ms(Y.col(k)), y_ref)));
      }
      std::sort(errors.begin(), errors.end());
      out.push_back({entry.name, a + "_batch", scalar_name<S>(), errors.back(), errors[errors.size() / 2]});
    }
  }
#endif
  if constexpr (std::is_same_v<S, double>) {
    // Automatic differentiation (double duals): the same [∂τ/∂q ∂τ/∂q̇].
    std::vector<double> errors;
    for (int k = 0; k < kSamples && k < pool.size(); ++k) {
      const auto s = static_cast<std::size_t>(k);
      const Vd ql = pool.q[s].cast<long double>(), qdl = pool.qd[s].cast<long double>(), ul = pool.u[s].cast<long double>();
      const auto y_ref = ref.run("RNEA_derivatives", ql, qdl, ul);
      const auto ad = spatial::testing::ad_rnea_derivatives(runtime, pool.q[s], pool.qd[s], pool.u[s]);
      Eigen::MatrixXd y(runtime.size(), 2 * runtime.size());
      y << ad.dtau_dq, ad.dtau_dv;
      errors.push_back(static_cast<double>(rel_error(y, y_ref)));
    }
    std::sort(errors.begin(), errors.end());
    out.push_back({entry.name, "RNEA_derivatives_ad", "double", errors.back(), errors[errors.size() / 2]});
  }
}

// ---- simulation ------------------------------------------------------------------------------------------------

using spatial::testing::Integrator;

constexpr double kDamping = 0.05;  // N·m·s/rad, τ = −D q̇

/// CPU time of the calling thread, in nanoseconds (wall time would count the time other processes run).
double thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) * 1e9 + double(ts.tv_nsec);
}

/// Integrates 1 s; returns (q, q̇) at the end.
template <class S, class TreeT>
struct Simulator {
  using V = typename Data<S, TreeT>::VectorN;
  Model<S, TreeT> model;
  Data<S, TreeT> data;
  V q0, qd0;
  explicit Simulator(const Model<S, TreeT>& m, const V& q, const V& qd) : model(m), data(model), q0(q), qd0(qd) {}

  V acc(const V& q, const V& qd) { return aba(model, data, q, qd, V(-S(kDamping) * qd)); }

  std::pair<V, V> run(Integrator method, double duration, long steps) {
    const S h = S(duration / double(steps));
    V q = q0, qd = qd0;
    for (long s = 0; s < steps; ++s)
      spatial::testing::integrator_step(method, [this](const V& qq, const V& vv) { return acc(qq, vv); }, q, qd, h);
    return {q, qd};
  }
};

struct SimPoint {
  std::string method;
  double dt;
  long steps;
  int evaluations_per_step;
  double ns_per_simulated_second;
  double max_abs_error_q, max_abs_error_qd;
};

template <class TreeT>
void study_simulation(const BenchModel<TreeT>& entry, std::vector<SimPoint>& out, std::ostringstream& meta) {
  const double duration = 1.0;
  const InputPool<double> pool(entry.range, 1, 11);
  using Vd = typename Data<double, TreeT>::VectorN;
  using Vl = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
  const Vd q0 = pool.q[0], qd0 = pool.qd[0];
  const std::vector<double> dts = {1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4};
  const double ref_dt = dts.back() / 4;
  const long ref_steps = std::lround(duration / ref_dt);

  Simulator<long double, DynamicTree> reference(entry.model.to_runtime().template cast<long double>(),
                                                q0.template cast<long double>(), qd0.template cast<long double>());
  const double t_ref0 = thread_cpu_ns();
  const auto [q_ref, qd_ref] = reference.run(Integrator::RK4, duration, ref_steps);
  const double ref_seconds = (thread_cpu_ns() - t_ref0) * 1e-9;
  meta << "\"model\": \"" << entry.name << "\", \"duration_s\": " << duration << ", \"damping\": " << kDamping
       << ", \"reference\": {\"method\": \"RK4\", \"scalar\": \"long double\", \"dt\": " << ref_dt
       << ", \"steps\": " << ref_steps << ", \"wall_s\": " << ref_seconds << "}";

  Simulator<double, TreeT> sim(entry.model, q0, qd0);
  for (Integrator method : {Integrator::SemiImplicitEuler, Integrator::Midpoint, Integrator::RK4}) {
    for (double dt : dts) {
      const long steps = std::lround(duration / dt);
      std::vector<double> times;
      std::pair<Vd, Vd> end;
      for (int r = 0; r < 5; ++r) {
        const double t0 = thread_cpu_ns();
        end = sim.run(method, duration, steps);
        times.push_back(thread_cpu_ns() - t0);
      }
      std::sort(times.begin(), times.end());
      const Vl dq = end.first.template cast<long double>() - q_ref;
      const Vl dqd = end.second.template cast<long double>() - qd_ref;
      out.push_back({spatial::testing::integrator_name(method), dt, steps, spatial::testing::integrator_evaluations(method), times[2] / duration,
                     static_cast<double>(dq.cwiseAbs().maxCoeff()), static_cast<double>(dqd.cwiseAbs().maxCoeff())});
    }
  }
}

std::string json_number(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6e", x);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<Point> points;
  std::vector<SimPoint> sim;
  std::ostringstream sim_meta;
  for_each_bench_model([&](const auto& entry) {
    std::cerr << "error_study: " << entry.name << "\n";
    const InputPool<double> pool(entry.range);
    study_scalar<float>(entry, pool, points);
    study_scalar<double>(entry, pool, points);
    if (entry.name == kSimulationModel) study_simulation(entry, sim, sim_meta);
  });

  std::ostringstream js;
  js << "{\n  \"schema\": 1,\n  \"reference_scalar\": \"long double\",\n  \"long_double_digits\": "
     << std::numeric_limits<long double>::digits << ",\n  \"samples\": " << kSamples
     << ",\n  \"error_definition\": \"max over states of ||y - y_ref||_inf / ||y_ref||_inf\",\n  \"algorithms\": [\n";
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point& p = points[i];
    js << "    {\"model\": \"" << p.model << "\", \"algorithm\": \"" << p.algorithm << "\", \"scalar\": \"" << p.scalar
       << "\", \"tree\": \"runtime\", \"max_rel_error\": " << json_number(p.max_rel_error)
       << ", \"median_rel_error\": " << json_number(p.median_rel_error) << "}" << (i + 1 < points.size() ? "," : "")
       << "\n";
  }
  js << "  ],\n  \"simulation\": {" << sim_meta.str() << ",\n    \"points\": [\n";
  for (std::size_t i = 0; i < sim.size(); ++i) {
    const SimPoint& p = sim[i];
    js << "      {\"method\": \"" << p.method << "\", \"dt\": " << json_number(p.dt) << ", \"steps\": " << p.steps
       << ", \"evaluations_per_step\": " << p.evaluations_per_step
       << ", \"ns_per_simulated_second\": " << json_number(p.ns_per_simulated_second)
       << ", \"max_abs_error_q\": " << json_number(p.max_abs_error_q)
       << ", \"max_abs_error_qd\": " << json_number(p.max_abs_error_qd) << "}" << (i + 1 < sim.size() ? "," : "")
       << "\n";
  }
  js << "    ]\n  },\n";
#ifdef SPATIAL_ERROR_STUDY_SCENES
  std::cerr << "error_study: stepping scene (full, reduced, double pendulum)\n";
  const auto step_points = spatial::bench_scenes::study_step_resultant(SPATIAL_SOURCE_DIR "/urdf/hoap3.urdf");
  js << "  \"step_resultant\": " << spatial::bench_scenes::step_points_json(step_points) << ",\n  \"pending\": []\n}\n";
#else
  js << "  \"pending\": [\n    {\"study\": \"stepping scene: full 21-DoF vs reduced (locked limbs) vs double "
        "pendulum, resultant force\", \"needs\": \"the URDF loader (spatial::urdf)\"}\n  ]\n}\n";
#endif

  if (argc > 1) {
    std::ofstream f(argv[1]);
    f << js.str();
    if (!f) {
      std::cerr << "error_study: cannot write " << argv[1] << "\n";
      return 1;
    }
    std::cerr << "error_study: wrote " << argv[1] << "\n";
  } else {
    std::cout << js.str();
  }
  return 0;
}
