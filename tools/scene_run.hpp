#pragma once
// `spatial-dyn scene NAME|all [--out DIR]`: runs one of the reference study's experiments (tools/scenes.hpp) and
// writes DIR/NAME.csv (one row per 2 ms sample) and DIR/NAME.json (maxima, timings, comparison with the study).
// Not part of the installed library.

#include "cli_common.hpp"
#include "scenes.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace spatial::scenes {

// Numbers quoted from the study (thesis §6.4; DATASHEET.md "Results of the reference study").
inline constexpr double kStudyFzWhole = 83.3;     // N, vertical resultant at the start of the step, whole model
inline constexpr double kStudyFzPendulum = 85.7;  // N, the same for the double pendulum
inline constexpr double kStudyWeight = 86.24;     // N, 8.8 kg × 9.8 m/s²
inline constexpr double kStudyFyWhole = 5.5;      // N, horizontal component at the start, whole model

namespace run_detail {

inline std::string num(double x) { return cli::format_double(x); }
/// A number in JSON, which has no NaN or infinity: those (a diverged run's figures) are written as null.
inline std::string json_num(double x) { return std::isfinite(x) ? num(x) : "null"; }

inline std::string json_str(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}

inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

using Clock = std::chrono::steady_clock;

/// Wall time of f() per call [ns], over `reps` back-to-back calls.
template <class F>
double time_ns(int reps, F&& f) {
  const auto t0 = Clock::now();
  for (int r = 0; r < reps; ++r) f();
  const auto t1 = Clock::now();
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / reps;
}

struct Max {
  double value = 0, time = 0;
  std::string joint;
  void update(double v, double t, const std::string& j) {
    if (v > value) {
      value = v;
      time = t;
      joint = j;
    }
  }
  std::string json() const {
    return "{\"value\": " + num(value) + ", \"time\": " + num(time) + ", \"joint\": " + json_str(joint) + "}";
  }
};

}  // namespace run_detail

/// What `run_scene` measured (also written to NAME.json).
struct SceneResult {
  std::string name;
  int samples = 0;
  double max_tau_over_rated = 0, max_tau_over_max = 0, max_qdd_diff_crba = 0, max_qdd_diff_aba = 0;
  double sample_ns = 0;
  double fz_start = 0, fy_start = 0, fx_start = 0, weight = 0, static_fz = 0, min_zmp_margin = 0;
  double pendulum_fz_start = 0;
  bool zmp_inside = true;
};

/// Runs `scene` on `model` (whose fixed base holds `base_inertia`) and writes dir/NAME.csv and dir/NAME.json.
template <class T>
SceneResult run_scene_on(const Scene& scene, const Model<double, T>& model, const Inertia<double>& base_inertia,
                         double whole_mass, const std::string& dir) {
  using namespace run_detail;
  using V = typename Data<double, T>::VectorN;
  const int n = model.size();
  const Trajectory& traj = scene.trajectory;
  Data<double, T> data(model);
  const auto pm = pendulum::model();
  Data<double, pendulum::Tree> pdata(pm);
  Data<double, stance::Tree> kin(stance::model());  // kinematics for the pendulum angles and the CoM
  const auto sm = stance::model();
  const SupportPolygon polygon;
  const double g = -model.gravity().z();

  std::vector<MotorTorque> motors;
  for (int i = 0; i < n; ++i) motors.push_back(motor_torque(model.joint_name(i)));

  SceneResult res;
  res.name = scene.name;
  res.samples = traj.samples();
  res.weight = whole_mass * g;
  res.min_zmp_margin = 1e300;
  Max tau_rated, tau_max, d_crba, d_aba;
  double max_qdd = 0;
  std::vector<double> t_rnea, t_crba, t_aba, t_res, t_pend;
  const int reps = 10;

  std::ostringstream csv;
  csv << "time";
  for (const char* kind : {"q", "qd", "qdd", "tau", "tau/rated", "tau/max", "qdd_crba", "qdd_aba"})
    for (int i = 0; i < n; ++i) csv << "," << kind << ":" << model.joint_name(i);
  csv << ",max_dqdd_crba,max_dqdd_aba";
  if (scene.resultant) csv << ",F_x,F_y,F_z,M_x,M_y,M_z,zmp_x,zmp_y,zmp_margin,com_x,com_y,com_z";
  if (scene.pendulum)
    csv << ",pend_q:ankle_pitch,pend_q:hip_pitch,pend_tau:ankle_pitch,pend_tau:hip_pitch,pend_F_x,pend_F_y,pend_F_z,"
           "pend_M_y";
  csv << "\n";

  // The static resultant at the first pose (q̇ = q̈ = 0): must be the weight.
  {
    Eigen::VectorXd q, qd, qdd;
    traj.eval(0, q, qd, qdd);
    const V qv = q, zero = V::Zero(n);
    rnea(model, data, qv, zero, zero);
    res.static_fz = ground_wrench(model, data, base_inertia).f.z();
  }

  Eigen::VectorXd q, qd, qdd, qa, qda, qdda, qb, qdb, qddb;
  for (int s = 0; s < res.samples; ++s) {
    const double t = s * kPeriod;
    traj.eval(t, q, qd, qdd);
    const V qv = q, qdv = qd, qddv = qdd;
    const V tau = rnea(model, data, qv, qdv, qddv);
    const Force<double> w = scene.resultant ? ground_wrench(model, data, base_inertia) : Force<double>::Zero();
    const V a_crba = forward_dynamics_crba(model, data, qv, qdv, tau);
    const V a_aba = aba(model, data, qv, qdv, tau);

    t_rnea.push_back(time_ns(reps, [&] { rnea(model, data, qv, qdv, qddv); }));
    t_crba.push_back(time_ns(reps, [&] { forward_dynamics_crba(model, data, qv, qdv, tau); }));
    t_aba.push_back(time_ns(reps, [&] { aba(model, data, qv, qdv, tau); }));
    if (scene.resultant) {
      Force<double> sink = Force<double>::Zero();
      t_res.push_back(time_ns(reps, [&] {
        rnea(model, data, qv, qdv, qddv);
        sink += ground_wrench(model, data, base_inertia);
      }));
      if (!std::isfinite(sink.f.z())) res.zmp_inside = false;  // keeps `sink` alive
    }

    double dc = 0, da = 0;
    csv << num(t);
    for (const Eigen::VectorXd* v : {&q, &qd, &qdd}) for (int i = 0; i < n; ++i) csv << "," << num((*v)[i]);
    for (int i = 0; i < n; ++i) csv << "," << num(tau[i]);
    for (int i = 0; i < n; ++i) {
      const std::string& j = model.joint_name(i);
      const double r = std::abs(tau[i]) / motors[static_cast<std::size_t>(i)].rated;
      const double x = std::abs(tau[i]) / motors[static_cast<std::size_t>(i)].max;
      tau_rated.update(r, t, j);
      tau_max.update(x, t, j);
      csv << "," << num(tau[i] / motors[static_cast<std::size_t>(i)].rated);
    }
    for (int i = 0; i < n; ++i) csv << "," << num(tau[i] / motors[static_cast<std::size_t>(i)].max);
    for (int i = 0; i < n; ++i) {
      csv << "," << num(a_crba[i]);
      dc = std::max(dc, std::abs(a_crba[i] - qdd[i]));
      d_crba.update(std::abs(a_crba[i] - qdd[i]), t, model.joint_name(i));
      max_qdd = std::max(max_qdd, std::abs(qdd[i]));
    }
    for (int i = 0; i < n; ++i) {
      csv << "," << num(a_aba[i]);
      da = std::max(da, std::abs(a_aba[i] - qdd[i]));
      d_aba.update(std::abs(a_aba[i] - qdd[i]), t, model.joint_name(i));
    }
    csv << "," << num(dc) << "," << num(da);

    if (scene.resultant) {
      const Eigen::Vector2d z = zmp(w);
      const double margin = polygon.margin(z.x(), z.y());
      res.min_zmp_margin = std::min(res.min_zmp_margin, margin);
      if (!polygon.contains(z.x(), z.y())) res.zmp_inside = false;
      const Eigen::Matrix<double, stance::dof, 1> qs = q;
      const Eigen::Vector3d c = stance::whole_body_com(sm, kin, qs);
      csv << "," << num(w.f.x()) << "," << num(w.f.y()) << "," << num(w.f.z()) << "," << num(w.n.x()) << ","
          << num(w.n.y()) << "," << num(w.n.z()) << "," << num(z.x()) << "," << num(z.y()) << "," << num(margin)
          << "," << num(c.x()) << "," << num(c.y()) << "," << num(c.z());
      if (s == 0) {
        res.fx_start = w.f.x();
        res.fy_start = w.f.y();
        res.fz_start = w.f.z();
      }
    }
    if (scene.pendulum) {
      // Angles on the whole body's motion; rates by central differences on the cubic trajectory.
      const double h = 1e-4;
      traj.eval(t - h, qa, qda, qdda);
      traj.eval(t + h, qb, qdb, qddb);
      const Eigen::Vector2d p0 = pendulum_angles(sm, kin, q), pa = pendulum_angles(sm, kin, qa),
                            pb = pendulum_angles(sm, kin, qb);
      const Eigen::Vector2d pqd = (pb - pa) / (2 * h), pqdd = (pb - 2 * p0 + pa) / (h * h);
      const auto& ptau = rnea(pm, pdata, p0, pqd, pqdd);
      const Force<double> pw = ground_wrench(pm, pdata, pendulum::base_inertia<double>());
      t_pend.push_back(time_ns(reps, [&] { rnea(pm, pdata, p0, pqd, pqdd); }));
      csv << "," << num(p0[0]) << "," << num(p0[1]) << "," << num(ptau[0]) << "," << num(ptau[1]) << ","
          << num(pw.f.x()) << "," << num(pw.f.y()) << "," << num(pw.f.z()) << "," << num(pw.n.y());
      if (s == 0) res.pendulum_fz_start = pw.f.z();
    }
    csv << "\n";
  }
  res.max_tau_over_rated = tau_rated.value;
  res.max_tau_over_max = tau_max.value;
  res.max_qdd_diff_crba = d_crba.value;
  res.max_qdd_diff_aba = d_aba.value;
  const double m_rnea = median(t_rnea), m_crba = median(t_crba), m_aba = median(t_aba);
  res.sample_ns = m_rnea + m_crba + m_aba;

  std::ostringstream js;
  js << "{\n  \"scene\": " << json_str(scene.name) << ",\n  \"title\": " << json_str(scene.title)
     << ",\n  \"model\": " << json_str(scene.model == ModelKind::Torso ? "hoap3_torso" : "hoap3_stance_right")
     << ",\n  \"dof\": " << n << ",\n  \"period_s\": " << num(kPeriod) << ",\n  \"duration_s\": "
     << num(traj.duration()) << ",\n  \"samples\": " << res.samples << ",\n  \"via_points\": " << traj.via_points()
     << ",\n  \"notes\": [";
  for (std::size_t k = 0; k < scene.notes.size(); ++k) js << (k ? ", " : "") << json_str(scene.notes[k]);
  js << "],\n  \"max_abs_qdd\": " << num(max_qdd) << ",\n  \"max_tau_over_rated\": " << tau_rated.json()
     << ",\n  \"max_tau_over_max\": " << tau_max.json() << ",\n  \"max_qdd_diff_crba\": " << d_crba.json()
     << ",\n  \"max_qdd_diff_aba\": " << d_aba.json()
     << ",\n  \"timing\": {\"clock\": \"std::chrono::steady_clock, wall time, median over the samples of the mean "
        "of "
     << reps
     << " back-to-back calls; the machine is shared with other jobs\", \"rnea_ns\": " << num(m_rnea)
     << ", \"fd_crba_ns\": " << num(m_crba) << ", \"aba_ns\": " << num(m_aba)
     << ", \"sample_ns\": " << num(res.sample_ns);
  if (scene.resultant) js << ", \"resultant_ns\": " << num(median(t_res));
  if (scene.pendulum) js << ", \"pendulum_rnea_ns\": " << num(median(t_pend));
  js << ", \"period_ns\": " << num(kPeriod * 1e9) << "}";
  if (scene.resultant) {
    js << ",\n  \"resultant\": {\"frame\": \"right sole (x forward, y left, z up), moment about its origin\", "
       << "\"mass_kg\": " << num(whole_mass) << ", \"g\": " << num(g) << ", \"weight_N\": " << num(res.weight)
       << ", \"static_Fz_N\": " << num(res.static_fz) << ", \"start_F_N\": [" << num(res.fx_start) << ", "
       << num(res.fy_start) << ", " << num(res.fz_start) << "], \"zmp_inside\": "
       << (res.zmp_inside ? "true" : "false") << ", \"min_zmp_margin_m\": " << num(res.min_zmp_margin)
       << ", \"support_polygon_m\": [" << num(polygon.x_min) << ", " << num(polygon.x_max) << ", "
       << num(polygon.y_min) << ", " << num(polygon.y_max) << "]";
    if (scene.pendulum) js << ", \"pendulum_start_Fz_N\": " << num(res.pendulum_fz_start);
    js << "}";
    js << ",\n  \"study\": {\"Fz_start_whole_N\": " << num(kStudyFzWhole)
       << ", \"Fz_start_pendulum_N\": " << num(kStudyFzPendulum) << ", \"static_weight_N\": " << num(kStudyWeight)
       << ", \"Fy_start_whole_N\": " << num(kStudyFyWhole) << "}";
  }
  js << "\n}\n";

  auto write = [](const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    if (!f) throw cli::InputError(path + ": cannot open the file for writing");
    f << text;
    f.close();
    if (!f) throw cli::InputError(path + ": error while writing the file");
  };
  write(dir + "/" + scene.name + ".csv", csv.str());
  write(dir + "/" + scene.name + ".json", js.str());
  return res;
}

inline SceneResult run_scene(const std::string& name, const std::string& dir) {
  const Scene scene = make_scene(name);
  if (scene.model == ModelKind::Torso)
    return run_scene_on(scene, torso::model(), torso::base_inertia<double>(), torso::whole_body_mass, dir);
  return run_scene_on(scene, stance::model(), stance::base_inertia<double>(), stance::whole_body_mass, dir);
}

}  // namespace spatial::scenes
