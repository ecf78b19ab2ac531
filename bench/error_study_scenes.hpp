#pragma once
// Error study, part 3 (bench/error_study.cpp): the resultant force of the ground on the robot during the step
// (tools/scenes.hpp, scene "step"), computed by the full 21-DoF model, by reduced models with locked limbs and by
// the double pendulum, against the full model in long double. Each variant: median time per call of computing the
// resultant (RNEA + ground_wrench), and the error over the step's samples.
//
// Reduced models are loaded from urdf/hoap3.urdf (rooted at R_SOLE) with the limbs locked at their angles at the
// start of the step: run-time trees (the loader's models), in double.
#include "scenes.hpp"

#include <spatial/urdf.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace spatial::bench_scenes {

using namespace spatial::scenes;

struct StepPoint {
  std::string variant, scalar, tree;
  int dof;
  double ns;                    // median over samples of the time per call (RNEA + resultant)
  double max_rel_error;         // max over samples of ‖F − F_ref‖∞ / ‖F_ref‖∞ (F: 3D force)
  double max_rel_error_fz;      // max over samples of |Fz − Fz_ref| / |Fz_ref|
  double max_abs_error_fh;      // max over samples of max(|Fx − Fx_ref|, |Fy − Fy_ref|) [N]
};

/// The step's samples: q, q̇, q̈ of the whole body (stance model order).
struct StepSamples {
  std::vector<Eigen::VectorXd> q, qd, qdd;
};

inline StepSamples step_samples() {
  const Scene s = make_scene("step");
  StepSamples out;
  Eigen::VectorXd q, qd, qdd;
  for (int k = 0; k < s.trajectory.samples(); ++k) {
    s.trajectory.eval(k * kPeriod, q, qd, qdd);
    out.q.push_back(q);
    out.qd.push_back(qd);
    out.qdd.push_back(qdd);
  }
  return out;
}

namespace detail {

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

/// Time per call [ns] of f(), mean of `reps` back-to-back calls (steady_clock).
template <class F>
double time_ns(int reps, F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < reps; ++r) f();
  return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / reps;
}

/// Resultant forces of every sample with a model in scalar S; `select` maps the full q to the model's q.
template <class S, class T, class Select>
std::vector<Eigen::Vector3d> forces(const Model<S, T>& model, const Inertia<S>& base, const StepSamples& in,
                                    Select&& select, std::vector<double>* times) {
  Data<S, T> data(model);
  using V = typename Data<S, T>::VectorN;
  std::vector<Eigen::Vector3d> out;
  V q = V::Zero(model.size()), qd = q, qdd = q;
  for (std::size_t k = 0; k < in.q.size(); ++k) {
    select(k, q, qd, qdd);
    rnea(model, data, q, qd, qdd);
    const Force<S> w = ground_wrench(model, data, base);
    out.push_back(w.f.template cast<double>());
    if (times) {
      S sink = 0;
      times->push_back(time_ns(20, [&] {
        rnea(model, data, q, qd, qdd);
        sink += ground_wrench(model, data, base).f.z();
      }));
      if (!(sink == sink)) out.back().setConstant(std::nan(""));  // keeps the timed work alive
    }
  }
  return out;
}

template <class V>
void from_full(const StepSamples& in, std::size_t k, const std::vector<int>& index, V& q, V& qd, V& qdd) {
  using S = typename V::Scalar;
  for (std::size_t i = 0; i < index.size(); ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    q[r] = S(in.q[k][index[i]]);
    qd[r] = S(in.qd[k][index[i]]);
    qdd[r] = S(in.qdd[k][index[i]]);
  }
}

}  // namespace detail

/// Runs every variant; `urdf` is the path of urdf/hoap3.urdf. Appends the points and a JSON object to `js`.
inline std::vector<StepPoint> study_step_resultant(const std::string& urdf) {
  const StepSamples in = step_samples();
  std::vector<int> all(stance::dof);
  for (int i = 0; i < stance::dof; ++i) all[static_cast<std::size_t>(i)] = i;

  // Reference: the full model in long double, inputs cast from the double samples.
  const std::vector<Eigen::Vector3d> ref = detail::forces(
      stance::model<long double>(), stance::base_inertia<long double>(), in,
      [&](std::size_t k, auto& q, auto& qd, auto& qdd) { detail::from_full(in, k, all, q, qd, qdd); }, nullptr);

  std::vector<StepPoint> points;
  auto add = [&](const std::string& variant, const std::string& scalar, const std::string& tree, int dof,
                 const std::vector<Eigen::Vector3d>& f, const std::vector<double>& times) {
    StepPoint p{variant, scalar, tree, dof, detail::median(times), 0, 0, 0};
    for (std::size_t k = 0; k < f.size(); ++k) {
      const Eigen::Vector3d d = f[k] - ref[k];
      p.max_rel_error = std::max(p.max_rel_error, d.cwiseAbs().maxCoeff() / ref[k].cwiseAbs().maxCoeff());
      p.max_rel_error_fz = std::max(p.max_rel_error_fz, std::abs(d.z()) / std::abs(ref[k].z()));
      p.max_abs_error_fh = std::max(p.max_abs_error_fh, std::max(std::abs(d.x()), std::abs(d.y())));
    }
    points.push_back(p);
  };

  {
    std::vector<double> t;
    const auto f = detail::forces(
        stance::model<double>(), stance::base_inertia<double>(), in,
        [&](std::size_t k, auto& q, auto& qd, auto& qdd) { detail::from_full(in, k, all, q, qd, qdd); }, &t);
    add("full 21-DoF", "double", "static", stance::dof, f, t);
  }
  {
    std::vector<double> t;
    const auto f = detail::forces(
        stance::model<float>(), stance::base_inertia<float>(), in,
        [&](std::size_t k, auto& q, auto& qd, auto& qdd) { detail::from_full(in, k, all, q, qd, qdd); }, &t);
    add("full 21-DoF", "float", "static", stance::dof, f, t);
  }

  // Reduced models: limbs locked at their angles at the start of the step.
  const std::vector<std::string> head_wrists = {"CHEST_H_PAN_joint", "H_PAN_H_TILT_joint", "H_TILT_H_ROLL_joint",
                                                "R_EB_R_WR_joint", "L_EB_L_WR_joint"};
  const std::vector<std::string> arms = {"CHEST_R_SFE_joint", "R_SFE_R_SAA_joint", "R_SAA_R_SHR_joint",
                                         "R_SHR_R_EB_joint",  "CHEST_L_SFE_joint", "L_SFE_L_SAA_joint",
                                         "L_SAA_L_SHR_joint", "L_SHR_L_EB_joint"};
  const std::vector<std::string> swing = {"WAIST_L_LR_joint",  "L_LR_L_LAA_joint", "L_LAA_L_LFE_joint",
                                          "L_LFE_L_KN_joint",  "L_KN_L_AFE_joint", "L_AFE_L_AAA_joint"};
  struct Reduced {
    std::string name;
    std::vector<std::string> locked;
  };
  const std::vector<Reduced> reduced = {{"arms locked", arms},
                                        {"swing leg locked", swing},
                                        {"arms + swing leg locked", [&] {
                                           auto v = arms;
                                           v.insert(v.end(), swing.begin(), swing.end());
                                           return v;
                                         }()}};
  for (const Reduced& r : reduced) {
    urdf_io::LoadOptions opt;
    opt.root = "R_SOLE";
    for (const auto& j : head_wrists) opt.locked.emplace_back(j, 0.0);
    for (const auto& j : r.locked) opt.locked.emplace_back(j, in.q.front()[stance::joint_index(j)]);
    const urdf_io::LoadedModel loaded = urdf_io::load_file(urdf, opt);
    std::vector<int> index;
    for (int i = 0; i < loaded.model.size(); ++i) index.push_back(stance::joint_index(loaded.model.joint_name(i)));
    std::vector<double> t;
    const auto f = detail::forces(
        loaded.model, loaded.base_inertia, in,
        [&](std::size_t k, auto& q, auto& qd, auto& qdd) { detail::from_full(in, k, index, q, qd, qdd); }, &t);
    add(r.name, "double", "runtime", loaded.model.size(), f, t);
  }

  // The double pendulum on the same motion (angles as in `spatial-dyn scene pendulum`).
  {
    const Scene s = make_scene("step");
    const auto sm = stance::model();
    Data<double, stance::Tree> kin(sm);
    std::vector<Eigen::Vector2d> th, thd, thdd;
    Eigen::VectorXd qa, qda, qdda, qb, qdb, qddb;
    const double h = 1e-4;
    for (std::size_t k = 0; k < in.q.size(); ++k) {
      const double t = double(k) * kPeriod;
      s.trajectory.eval(t - h, qa, qda, qdda);
      s.trajectory.eval(t + h, qb, qdb, qddb);
      const Eigen::Vector2d p0 = pendulum_angles(sm, kin, in.q[k]), pa = pendulum_angles(sm, kin, qa),
                            pb = pendulum_angles(sm, kin, qb);
      th.push_back(p0);
      thd.push_back((pb - pa) / (2 * h));
      thdd.push_back((pb - 2 * p0 + pa) / (h * h));
    }
    std::vector<double> t;
    const auto f = detail::forces(
        pendulum::model<double>(), pendulum::base_inertia<double>(), in,
        [&](std::size_t k, auto& q, auto& qd, auto& qdd) {
          q = th[k];
          qd = thd[k];
          qdd = thdd[k];
        },
        &t);
    add("double pendulum", "double", "static", pendulum::dof, f, t);
  }
  return points;
}

inline std::string step_points_json(const std::vector<StepPoint>& points) {
  auto num = [](double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6e", x);
    return std::string(std::isfinite(x) ? buf : "null");
  };
  std::ostringstream js;
  js << "{\"scene\": \"step\", \"result\": \"resultant force of the ground on the robot (sole frame)\", "
        "\"reference\": \"full 21-DoF model in long double\", \"samples\": "
     << step_samples().q.size()
     << ", \"error_definition\": \"max over samples of ||F - F_ref||_inf / ||F_ref||_inf\", "
        "\"time_definition\": \"median over samples of the mean wall time of 20 back-to-back calls of RNEA + "
        "ground_wrench (steady_clock; shared machine)\",\n    \"points\": [\n";
  for (std::size_t i = 0; i < points.size(); ++i) {
    const StepPoint& p = points[i];
    js << "      {\"variant\": \"" << p.variant << "\", \"scalar\": \"" << p.scalar << "\", \"tree\": \"" << p.tree
       << "\", \"dof\": " << p.dof << ", \"ns\": " << num(p.ns) << ", \"max_rel_error\": " << num(p.max_rel_error)
       << ", \"max_rel_error_Fz\": " << num(p.max_rel_error_fz)
       << ", \"max_abs_error_Fh_N\": " << num(p.max_abs_error_fh) << "}" << (i + 1 < points.size() ? "," : "")
       << "\n";
  }
  js << "    ]}";
  return js.str();
}

}  // namespace spatial::bench_scenes
