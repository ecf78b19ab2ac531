#pragma once
// `spatial-dyn walk [--steps N --length M --width M --period S --double-support F --turn RAD --second-stage N
// --com-height M --zmp-model multibody|double-pendulum --out DIR]`: the HOAP-3 walks (include/spatial/walking/, docs/walking.md): the footstep plan, the two-stage ZMP
// preview control and the whole-body motion (open loop, run_whole_body), then the closed-loop simulation
// (run_closed_loop). Writes DIR/walk.csv (one row per 2 ms control tick), DIR/walk.json (the summary) and, through
// tools/plot_walk.py, the PNGs. Not part of the installed library.

#include "cli_common.hpp"
#include "scene_run.hpp"  // run_detail::num, json_num, json_str

#include <spatial/models/hoap3_floating.hpp>
#include <spatial/walking.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace spatial::walk_cli {

namespace fb = spatial::models::hoap3_floating;

struct WalkRequest {
  walking::GaitParameters<double> gait{};
  int second_stage = 3;
  double com_height = 0;  ///< m; 0: the HOAP-3 options' 0.29 m
  bool double_pendulum = false;  ///< the second stage feeds back the double pendulum's ZMP
  std::string dir = "build/report/walk";
};

inline const char* foot_name(walking::Foot f) { return f == walking::Foot::left ? "left" : "right"; }

/// Runs the walk of `req` and writes DIR/walk.csv and DIR/walk.json; returns the closed-loop summary's `walked`.
inline bool run_walk(const WalkRequest& req) {
  using scenes::run_detail::json_str;
  using scenes::run_detail::json_num;
  using scenes::run_detail::num;
  using FM = FloatingModel<double>;
  const FM model = fb::floating_model().to_runtime();
  const walking::WholeBodyFrames frames{fb::frame_index("L_SOLE"), fb::frame_index("R_SOLE"),
                                        fb::frame_index("base_link")};
  auto options = walking::hoap3_whole_body_options<double>(fb::joint_names);
  options.second_stage_iterations = req.second_stage;
  if (req.com_height > 0) options.preview.com_height = req.com_height;
  if (req.double_pendulum) options.second_stage_zmp = walking::SecondStageZmp::double_pendulum;
  const walking::FootstepPlan<double> plan(req.gait);  // validates (std::invalid_argument names the parameter)
  if (req.gait.steps == 1)
    std::fprintf(stderr, "walk: note: a walk advances (N - 1) step lengths (its last step closes the feet): with "
                         "--steps 1 the one step puts the swing foot back beside the other, --length and --turn "
                         "have no effect\n");
  const auto open = walking::run_whole_body(model, frames, ik_limits(fb::lower), ik_limits(fb::upper), plan, options);
  const walking::ClosedLoopOptions<double> copt;
  const auto closed = walking::run_closed_loop(model, frames, plan, open, options, copt);
  const auto& cs = closed.summary;
  const int nj = model.njoints();

  // ---- walk.csv
  std::ostringstream csv;
  csv << "t";
  for (const char* c : {"x", "y", "z", "qx", "qy", "qz", "qw"}) csv << ",q:floating_base:" << c;
  for (int j = 0; j < nj; ++j) csv << ",q:" << fb::joint_names[static_cast<std::size_t>(j)];
  for (const char* p : {"qd", "qdd"}) {
    for (const char* c : {"vx", "vy", "vz", "wx", "wy", "wz"}) csv << "," << p << ":floating_base:" << c;
    for (int j = 0; j < nj; ++j) csv << "," << p << ":" << fb::joint_names[static_cast<std::size_t>(j)];
  }
  for (int j = 0; j < nj; ++j) csv << ",tau:" << fb::joint_names[static_cast<std::size_t>(j)];
  csv << ",contact:left,contact:right";
  for (const char* f : {"left", "right"})
    for (const char* c : {"F:%s:x", "F:%s:y", "F:%s:z", "M:%s:x", "M:%s:y", "M:%s:z"}) {
      char buf[32];
      std::snprintf(buf, sizeof buf, c, f);
      csv << "," << buf;
    }
  for (const char* p : {"zmp_ref", "zmp_ct", "zmp_mb", "zmp_mb0", "cop"}) csv << "," << p << ":x," << p << ":y";
  csv << ",margin";
  for (const char* p : {"com", "com_plan", "pelvis", "pelvis_plan"}) csv << "," << p << ":x," << p << ":y," << p << ":z";
  csv << "\n";
  for (std::size_t k = 0; k < closed.samples.size(); ++k) {
    const auto& s = closed.samples[k];
    const auto& o = open.samples[k];
    csv << num(s.t);
    const auto row = [&](const auto& v) {
      for (Eigen::Index i = 0; i < v.size(); ++i) csv << "," << num(v[i]);
    };
    row(s.q);
    row(s.v);
    row(s.a);
    row(s.tau);
    csv << "," << (s.contact[0] ? 1 : 0) << "," << (s.contact[1] ? 1 : 0);
    row(s.wrench[0]);
    row(s.wrench[1]);
    row(o.zmp_reference);
    row(Eigen::Vector2d(open.first_stage.zmp.row(static_cast<Eigen::Index>(k)).transpose()));
    row(o.zmp_multibody);
    row(Eigen::Vector2d(open.zmp_multibody.front().row(static_cast<Eigen::Index>(k)).transpose()));
    row(s.cop);
    csv << "," << num(s.margin);
    row(s.com);
    row(o.com);
    row(s.pelvis);
    row(Eigen::Vector3d(o.q.head<3>()));
    csv << "\n";
  }

  // ---- walk.json
  const auto& g = req.gait;
  Eigen::VectorXd tau_max = Eigen::VectorXd::Zero(nj);
  for (const auto& s : closed.samples) tau_max = tau_max.cwiseMax(s.tau.cwiseAbs());
  // The whole-body IK of the open loop: a tick where it did not converge (an unreachable plan: steps too long for the
  // legs, a CoM too high) makes every later figure meaningless; walk.json and the output say so.
  const auto& os = open.summary;
  double ik_first_failure = std::numeric_limits<double>::quiet_NaN();  // null in walk.json when every tick converged
  for (const auto& o : open.samples)
    if (!o.ik.converged) {
      ik_first_failure = o.t;
      break;
    }
  double open_seconds = 0;
  for (const auto& p : open.summary.passes) open_seconds += p.seconds;
  std::ostringstream js;
  js << "{\n  \"robot\": \"hoap3_floating\",\n  \"parameters\": {\"steps\": " << g.steps << ", \"length\": "
     << json_num(g.step_length) << ", \"width\": " << json_num(g.step_width) << ", \"period\": " << json_num(g.period)
     << ", \"double_support\": " << json_num(g.double_support_ratio) << ", \"turn\": " << json_num(g.turn)
     << ", \"swing_height\": " << json_num(g.swing_height) << ", \"com_height\": " << json_num(options.preview.com_height)
     << ", \"control_dt\": " << json_num(options.preview.dt) << ", \"simulation_dt\": " << json_num(copt.simulation.dt)
     << ", \"second_stage_iterations\": " << req.second_stage << ", \"zmp_model\": \"" << (req.double_pendulum ? "double_pendulum" : "multibody")
     << "\", \"friction\": "
     << json_num(options.friction) << ", \"pd_frequency\": " << json_num(copt.pd_frequency) << "},\n";
  js << "  \"sole\": {\"front\": " << json_num(options.sole.front) << ", \"back\": " << json_num(options.sole.back)
     << ", \"left\": " << json_num(options.sole.left) << ", \"right\": " << json_num(options.sole.right) << "},\n";
  js << "  \"footsteps\": [";
  bool first = true;
  const auto footstep = [&](const walking::Footstep<double>& f) {
    js << (first ? "" : ", ") << "{\"foot\": \"" << foot_name(f.foot) << "\", \"x\": " << json_num(f.position.x())
       << ", \"y\": " << json_num(f.position.y()) << ", \"yaw\": " << json_num(f.yaw) << "}";
    first = false;
  };
  for (const auto& f : plan.initial_feet()) footstep(f);
  for (const auto& f : plan.footsteps()) footstep(f);
  js << "],\n  \"duration\": " << json_num(plan.duration()) << ",\n";
  js << "  \"open_loop\": {\"passes\": [";
  for (std::size_t p = 0; p < open.summary.passes.size(); ++p) {
    const auto& ps = open.summary.passes[p];
    js << (p ? ", " : "") << "{\"zmp_error_max\": " << json_num(ps.zmp_error_max) << ", \"zmp_error_rms\": "
       << json_num(ps.zmp_error_rms) << ", \"zmp_error_ct_max\": " << json_num(ps.zmp_error_ct_max)
       << ", \"min_margin\": " << json_num(ps.min_margin) << "}";
  }
  js << "], \"cart_table_error_max\": " << json_num(open.summary.cart_table_error_max)
     << ", \"contact_ok\": " << open.summary.contact_ok << ", \"ticks\": " << open.summary.ticks
     << ", \"ik_not_converged\": " << os.ik_not_converged << ", \"ik_first_failure_t\": " << json_num(ik_first_failure)
     << ", \"ik_residual_max\": " << json_num(os.ik_residual_max) << ", \"ik_iterations_max\": " << os.ik_iterations_max
     << ", \"foot_position_error_max\": " << json_num(os.foot_position_error_max)
     << ", \"foot_rotation_error_max\": " << json_num(os.foot_rotation_error_max) << "},\n";
  js << "  \"closed_loop\": {\"walked\": " << (cs.walked ? "true" : "false") << ", \"steps_completed\": "
     << cs.steps_completed << ", \"cop_min_margin\": " << json_num(cs.cop_min_margin)
     << ", \"sole_cop_min_margin\": " << json_num(cs.sole_cop_min_margin) << ", \"min_normal_force\": "
     << json_num(cs.min_normal_force) << ", \"pulls\": " << cs.pulls << ", \"max_friction_ratio\": "
     << json_num(cs.max_friction_ratio) << ", \"slips\": " << cs.slips << ", \"pelvis_final_error\": "
     << json_num(cs.pelvis_final_error) << ", \"pelvis_max_error\": " << json_num(cs.pelvis_max_error)
     << ", \"com_max_error\": " << json_num(cs.com_max_error) << ", \"joint_error_max\": " << json_num(cs.joint_error_max)
     << ", \"impacts\": " << cs.impacts << ", \"impact_energy_max\": " << json_num(cs.impact_energy_max)
     << ", \"failed_steps\": " << cs.failed_steps << "},\n";
  js << "  \"torques\": [";
  for (int j = 0; j < nj; ++j) {
    const double rated = options.rated_torque[j], maximum = options.max_torque[j];
    js << (j ? ", " : "") << "{\"joint\": " << json_str(std::string(fb::joint_names[static_cast<std::size_t>(j)]))
       << ", \"max\": " << json_num(tau_max[j]) << ", \"rated\": " << json_num(rated) << ", \"maximum\": " << json_num(maximum)
       << ", \"rated_ratio\": " << json_num(tau_max[j] / rated) << ", \"max_ratio\": " << json_num(tau_max[j] / maximum) << "}";
  }
  const double tick_us = open.summary.tick_seconds_mean * 1e6;
  js << "],\n  \"timings\": {\"clock\": \"std::chrono::steady_clock wall time, run-time tree, one run on a shared "
        "machine (the benchmark spatial/WalkTick is the measured figure)\", \"open_loop_s\": "
     << json_num(open_seconds) << ", \"closed_loop_s\": " << json_num(cs.seconds) << ", \"tick_us\": " << json_num(tick_us)
     << ", \"tick_fraction\": " << json_num(tick_us * 1e-6 / options.preview.dt)
     << ", \"simulation_step_us\": " << json_num(cs.step_seconds_mean * 1e6) << "}\n}\n";

  std::error_code ec;
  std::filesystem::create_directories(req.dir, ec);
  if (ec) throw cli::InputError(req.dir + ": cannot create the directory (" + ec.message() + ")");
  const auto write = [](const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    if (!f) throw cli::InputError(path + ": cannot open the file for writing");
    f << text;
    f.close();
    if (!f) throw cli::InputError(path + ": error while writing the file");
  };
  write(req.dir + "/walk.csv", csv.str());
  write(req.dir + "/walk.json", js.str());

  std::printf("walk: %d steps of %.3f m, turn %.3f rad/step, period %.3f s: %s (%d steps completed)\n", g.steps,
              g.step_length, g.turn, g.period, cs.walked ? "WALKED" : "did NOT walk", cs.steps_completed);
  std::printf("  open loop: multibody ZMP error max %.2f mm (first stage alone %.2f mm), %.1f us per tick\n",
              open.summary.passes.back().zmp_error_max * 1e3, open.summary.passes.front().zmp_error_max * 1e3,
              tick_us);
  std::printf("  whole-body IK: %d of %d ticks not converged, foot position error max %.3g mm\n", os.ik_not_converged,
              os.ticks, os.foot_position_error_max * 1e3);
  if (os.ik_not_converged > 0)
    std::fprintf(stderr,
                 "walk: warning: the plan is not reachable: the whole-body IK did not converge at %d of %d ticks (the "
                 "first at t = %.3f s; foot position error up to %.3g mm), so the figures of this walk are not "
                 "meaningful; try shorter steps (--length), a lower CoM (--com-height) or a longer period\n",
                 os.ik_not_converged, os.ticks, ik_first_failure, os.foot_position_error_max * 1e3);
  std::printf("  closed loop: CoP margin min %.1f mm, min normal force %.2f N, friction ratio max %.3f (mu %.2f), "
              "pelvis final error %.2f mm, pulls %d, slips %d\n",
              cs.cop_min_margin * 1e3, cs.min_normal_force, cs.max_friction_ratio, options.friction,
              cs.pelvis_final_error * 1e3, cs.pulls, cs.slips);
  std::printf("wrote %s/walk.csv and %s/walk.json\n", req.dir.c_str(), req.dir.c_str());
  return cs.walked;
}

/// Runs tools/plot_walk.py on DIR with $SPATIAL_PYTHON (default python3); returns its exit status.
inline int plot_walk(const std::string& dir, const std::string& script) {
  if (!std::filesystem::exists(script)) {
    std::printf("walk: no plots (%s not found)\n", script.c_str());
    return 0;
  }
  std::fflush(stdout);  // our lines first, then the script's
  const char* py = std::getenv("SPATIAL_PYTHON");
  const std::string quote = "'";
  const std::string cmd = std::string(py && *py ? py : "python3") + " " + quote + script + quote + " " + quote + dir + quote;
  return std::system(cmd.c_str());
}

}  // namespace spatial::walk_cli
