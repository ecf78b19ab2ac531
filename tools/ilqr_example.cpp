// spatial-ilqr: the HOAP-3 torso's arms (hoap3_torso, 8 joints, ±3 N m) swung from rest at q = 0 to a target pose in
// 1 s by iLQR (tools/ilqr.hpp), once with the analytical derivatives of forward dynamics (aba_derivatives) and once
// with forward finite differences of ABA (3n + 1 calls per knot), same solver, same problem.
//
//   spatial-ilqr [--out DIR] [--repeat R]
//
// Writes DIR/iterations.csv (derivatives,iteration,cost,step,regularization,time_ms,derivative_time_ms),
// DIR/trajectory.csv (t, q:<joint>, tau:<joint> of the analytical solution) and DIR/summary.json; prints a summary.
// The wall times are medians over R solves (default 5) of every iteration. DIR defaults to build/report/ilqr;
// tools/plot_ilqr.py plots it, tools/report.py quotes it.

#include "ilqr.hpp"

#include <spatial/models/hoap3_torso.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace torso = spatial::models::hoap3_torso;
using spatial::ilqr::Vec;

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

struct Variant {
  std::string name;
  ilqr::Result result;
  std::vector<double> iteration_ms, derivative_ms;
};

}  // namespace

int main(int argc, char** argv) {
  std::string out_dir = "build/report/ilqr";
  int repeat = 5;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) out_dir = argv[++i];
    else if (a == "--repeat" && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else {
      std::cerr << "usage: spatial-ilqr [--out DIR] [--repeat R]\n";
      return 2;
    }
  }
  const auto model = torso::model();
  using T = torso::Tree;
  const int n = torso::dof;
  Data<double, T> data(model);
  DerivativeData<double, T> dd(model);

  ilqr::Problem p;
  p.n = n;
  p.steps = 100;
  p.dt = 0.01;
  p.q0 = Vec::Zero(n);
  p.v0 = Vec::Zero(n);
  // Right arm forward and up with the elbow bent, left arm back and out (within the URDF limits).
  p.q_target = (Vec(n) << 1.4, -0.4, 0.3, -1.2, -0.8, 0.6, -0.3, -0.9).finished();
  // Weights: reaching the pose (terminal, and along the way) dominates; torques are cheap enough that the optimum
  // saturates the 3 N m motors early in the swing, so the limits are active.
  p.W_q = 1e3;
  p.W_v = 1e2;
  p.w_q = 10;
  p.r = 0.1;
  p.u_max = Vec(n);
  for (int i = 0; i < n; ++i) p.u_max[i] = torso::effort[static_cast<std::size_t>(i)];
  // Warm start: hold the initial pose against gravity.
  const Vec hold = gravity_torques(model, data, p.q0);
  const std::vector<Vec> u0(static_cast<std::size_t>(p.steps), hold);

  ilqr::Options options;
  options.max_iterations = 100;
  std::vector<Variant> variants = {{"analytical", {}, {}, {}}, {"finite_differences", {}, {}, {}}};
  for (int r = 0; r < repeat; ++r) {
    for (Variant& v : variants) {
      if (v.name == "analytical") {
        ilqr::AnalyticalLinearize<Model<double, T>, Data<double, T>, DerivativeData<double, T>> lin{model, data, dd};
        v.result = ilqr::solve(model, data, p, u0, lin, options);
      } else {
        ilqr::FiniteDifferenceLinearize<Model<double, T>, Data<double, T>> lin{model, data, 1e-7, Vec()};
        v.result = ilqr::solve(model, data, p, u0, lin, options);
      }
      for (const auto& it : v.result.iterations)
        if (it.iteration > 0) {
          v.iteration_ms.push_back(1e3 * it.seconds);
          v.derivative_ms.push_back(1e3 * it.derivative_seconds);
        }
    }
  }

  std::filesystem::create_directories(out_dir);
  {
    std::ofstream f(out_dir + "/iterations.csv");
    f << "derivatives,iteration,cost,step,regularization,time_ms,derivative_time_ms\n";
    for (const Variant& v : variants)
      for (const auto& it : v.result.iterations)
        f << v.name << ',' << it.iteration << ',' << it.cost << ',' << it.step << ',' << it.mu << ','
          << 1e3 * it.seconds << ',' << 1e3 * it.derivative_seconds << '\n';
  }
  {
    const ilqr::Result& r = variants[0].result;
    std::ofstream f(out_dir + "/trajectory.csv");
    f << "t";
    for (const char* kind : {"q:", "tau:"})
      for (int i = 0; i < n; ++i) f << ',' << kind << torso::joint_names[static_cast<std::size_t>(i)];
    f << '\n';
    for (int k = 0; k <= p.steps; ++k) {
      const auto s = static_cast<std::size_t>(k);
      f << k * p.dt;
      for (int i = 0; i < n; ++i) f << ',' << r.x[s][i];
      const Vec& u = r.u[std::min(s, r.u.size() - 1)];
      for (int i = 0; i < n; ++i) f << ',' << u[i];
      f << '\n';
    }
  }
  std::ofstream js(out_dir + "/summary.json");
  js << "{\n  \"model\": \"hoap3_torso\",\n  \"dof\": " << n << ",\n  \"steps\": " << p.steps << ",\n  \"dt\": " << p.dt
     << ",\n  \"torque_limit\": " << p.u_max.maxCoeff() << ",\n  \"repeat\": " << repeat << ",\n  \"variants\": {\n";
  std::printf("spatial-ilqr: hoap3_torso, %d joints, %d steps of %.3f s, |tau| <= %.1f N m, median of %d solves\n", n,
              p.steps, p.dt, p.u_max.maxCoeff(), repeat);
  for (std::size_t k = 0; k < variants.size(); ++k) {
    const Variant& v = variants[k];
    const ilqr::Result& r = v.result;
    double torque_ratio = 0;
    for (const Vec& u : r.u) torque_ratio = std::max(torque_ratio, (u.cwiseAbs().cwiseQuotient(p.u_max)).maxCoeff());
    const double pose_error = (r.x.back().head(n) - p.q_target).cwiseAbs().maxCoeff();
    const double speed = r.x.back().tail(n).cwiseAbs().maxCoeff();
    const int iterations = static_cast<int>(r.iterations.size()) - 1;
    js << "    \"" << v.name << "\": {\"iterations\": " << iterations << ", \"converged\": "
       << (r.converged ? "true" : "false") << ", \"initial_cost\": " << r.iterations.front().cost
       << ", \"final_cost\": " << r.iterations.back().cost << ", \"median_iteration_ms\": " << median(v.iteration_ms)
       << ", \"median_derivative_ms\": " << median(v.derivative_ms) << ", \"max_torque_ratio\": " << torque_ratio
       << ", \"final_pose_error\": " << pose_error << ", \"final_speed\": " << speed << "}"
       << (k + 1 < variants.size() ? "," : "") << "\n";
    std::printf("  %-18s %2d iterations%s, cost %.6g -> %.6g, %.3f ms/iteration (derivatives %.3f ms), "
                "max |tau|/limit %.3f, final pose error %.2e rad, speed %.2e rad/s\n",
                v.name.c_str(), iterations, r.converged ? " (converged)" : "", r.iterations.front().cost,
                r.iterations.back().cost, median(v.iteration_ms), median(v.derivative_ms), torque_ratio, pose_error,
                speed);
  }
  const double ratio = median(variants[1].iteration_ms) / median(variants[0].iteration_ms);
  const double dratio = median(variants[1].derivative_ms) / median(variants[0].derivative_ms);
  js << "  },\n  \"fd_over_analytical_iteration\": " << ratio << ",\n  \"fd_over_analytical_derivatives\": " << dratio
     << "\n}\n";
  std::printf("  finite differences / analytical: %.2f per iteration, %.2f for the derivatives alone\n", ratio, dratio);
  std::printf("  wrote %s/iterations.csv, trajectory.csv, summary.json\n", out_dir.c_str());
  return 0;
}
