/// \file bind_walking.cpp
/// The walking pattern generator from Python (include/spatial/walking/, docs/walking.md): `spatial.walk(...)` plans
/// the footsteps, runs the two-stage ZMP preview control and the whole-body motion of the generated HOAP-3 floating
/// model (open loop, `run_whole_body`), then the closed-loop simulation (`run_closed_loop`), exactly as
/// `spatial-dyn walk` does, and returns the runs as NumPy arrays (one row per 2 ms control tick) with their
/// summaries. Runs without the GIL.

#include "bind_common.hpp"

#include <spatial/models/hoap3_floating.hpp>
#include <spatial/walking.hpp>

namespace spatial::python::walking_py {

namespace fb = spatial::models::hoap3_floating;
using FM = FloatingModel<double>;

/// What `walk` returns, named in the stubs.
struct WalkResult {
  nb::object o;
};

/// Rows of per-sample vectors: out[k, :] = get(samples[k]) (each of `width` entries).
template <class Samples, class Get>
nb::object rows(const Samples& samples, npy_intp width, Get get) {
  auto [obj, p] = new_array<double>({npy_intp(samples.size()), width});
  for (const auto& s : samples) {
    const auto& x = get(s);
    for (npy_intp i = 0; i < width; ++i) *p++ = x[i];
  }
  return obj;
}
/// The sample time of each row.
template <class Samples>
nb::object times(const Samples& samples) {
  auto [obj, p] = new_array<double>({npy_intp(samples.size())});
  for (const auto& s : samples) *p++ = s.t;
  return obj;
}
/// t, q (N, nq), v, a (N, nv) and tau (N, ntau) of a run's samples into `d`.
template <class Samples>
void motion(nb::dict& d, const Samples& samples, npy_intp nq, npy_intp nv, npy_intp ntau) {
  d["t"] = times(samples);
  d["q"] = rows(samples, nq, [](const auto& s) -> const auto& { return s.q; });
  d["v"] = rows(samples, nv, [](const auto& s) -> const auto& { return s.v; });
  d["a"] = rows(samples, nv, [](const auto& s) -> const auto& { return s.a; });
  d["tau"] = rows(samples, ntau, [](const auto& s) -> const auto& { return s.tau; });
}
/// (N, 2, 6) per-foot wrenches [force; moment] (left, right) and (N, 2) contact flags.
template <class Samples>
void feet(nb::dict& d, const Samples& samples) {
  const npy_intp n = npy_intp(samples.size());
  auto [w, pw] = new_array<double>({n, 2, 6});
  auto [c, pc] = new_array<bool>({n, 2});
  for (const auto& s : samples)
    for (int f = 0; f < 2; ++f) {
      for (int i = 0; i < 6; ++i) *pw++ = s.wrench[std::size_t(f)][i];
      *pc++ = s.contact[std::size_t(f)];
    }
  d["wrench"] = w;
  d["contact"] = c;
}
inline nb::object vector(const Eigen::VectorXd& x) {
  auto [obj, p] = new_array<double>({npy_intp(x.size())});
  for (Eigen::Index i = 0; i < x.size(); ++i) p[i] = x[i];
  return obj;
}

}  // namespace spatial::python::walking_py

namespace nanobind::detail {
template <>
struct type_caster<spatial::python::walking_py::WalkResult> {
  NB_TYPE_CASTER(spatial::python::walking_py::WalkResult, const_name("dict[str, typing.Any]"))
  static handle from_cpp(const spatial::python::walking_py::WalkResult& v, rv_policy, cleanup_list*) noexcept {
    return v.o.inc_ref();
  }
};
}  // namespace nanobind::detail

namespace spatial::python {

void bind_walking(nb::module_& m) {
  using namespace walking_py;
  m.def(
      "walk",
      [](int steps, double length, double width, double period, double double_support, double turn,
         double swing_height, const std::string& first_swing, int second_stage, double com_height,
         const std::string& zmp_model, bool closed_loop) -> WalkResult {
        walking::GaitParameters<double> gait;
        gait.steps = steps;
        gait.step_length = length;
        gait.step_width = width;
        gait.period = period;
        gait.double_support_ratio = double_support;
        gait.turn = turn;
        gait.swing_height = swing_height;
        if (first_swing == "right") gait.first_swing = walking::Foot::right;
        else if (first_swing == "left") gait.first_swing = walking::Foot::left;
        else throw nb::value_error(("walk: first_swing '" + first_swing + "' is not 'right' or 'left'").c_str());
        if (second_stage < 0) throw nb::value_error("walk: second_stage must be >= 0 (passes of the second stage)");
        if (!(com_height > 0)) throw nb::value_error("walk: com_height must be > 0 (m)");
        auto options = walking::hoap3_whole_body_options<double>(fb::joint_names);
        options.second_stage_iterations = second_stage;
        options.preview.com_height = com_height;
        if (zmp_model == "double_pendulum") options.second_stage_zmp = walking::SecondStageZmp::double_pendulum;
        else if (zmp_model != "multibody")
          throw nb::value_error(("walk: zmp_model '" + zmp_model + "' is not 'multibody' or 'double_pendulum'").c_str());
        const walking::FootstepPlan<double> plan(gait);  // std::invalid_argument (ValueError) names the parameter

        const FM model = fb::floating_model().to_runtime();
        const walking::WholeBodyFrames frames{fb::frame_index("L_SOLE"), fb::frame_index("R_SOLE"),
                                              fb::frame_index("base_link")};
        std::optional<walking::WholeBodyRun<FM>> open;
        std::optional<walking::ClosedLoopRun<FM>> closed;
        {
          nb::gil_scoped_release release;
          open.emplace(walking::run_whole_body(model, frames, ik_limits(fb::lower), ik_limits(fb::upper), plan,
                                               options));
          if (closed_loop)
            closed.emplace(walking::run_closed_loop(model, frames, plan, *open, options,
                                                    walking::ClosedLoopOptions<double>{}));
        }
        const npy_intp nq = model.nq(), nv = model.nv(), nj = model.njoints();

        nb::dict result;
        nb::list names;
        for (const auto& n : fb::joint_names) names.append(nb::str(std::string(n).c_str()));
        result["joint_names"] = names;
        result["dt"] = options.preview.dt;

        const auto& os = open->samples;
        nb::dict o;
        motion(o, os, nq, nv, nv);  // tau: nv (the root rows ~0)
        feet(o, os);
        {
          auto [ok, p] = new_array<bool>({npy_intp(os.size())});
          for (const auto& s : os) *p++ = s.ok;
          o["ok"] = ok;
        }
        o["zmp_reference"] = rows(os, 2, [](const auto& s) -> const auto& { return s.zmp_reference; });
        o["zmp_cart_table"] = rows(os, 2, [](const auto& s) -> const auto& { return s.zmp_cart_table; });
        o["zmp_multibody"] = rows(os, 2, [](const auto& s) -> const auto& { return s.zmp_multibody; });
        o["cop"] = rows(os, 2, [](const auto& s) -> const auto& { return s.cop; });
        o["com"] = rows(os, 3, [](const auto& s) -> const auto& { return s.com; });
        // The first stage (cart-table preview control alone): its CoM and ZMP, and the multibody ZMP of its pass.
        const auto matrix = [](const auto& x) {
          auto [obj, p] = new_array<double>({npy_intp(x.rows()), npy_intp(x.cols())});
          for (Eigen::Index r = 0; r < x.rows(); ++r)
            for (Eigen::Index c = 0; c < x.cols(); ++c) *p++ = x(r, c);
          return obj;
        };
        o["first_stage_com"] = matrix(open->first_stage.com);
        o["first_stage_zmp"] = matrix(open->first_stage.zmp);
        o["first_pass_zmp_multibody"] = matrix(open->zmp_multibody.front());
        result["open_loop"] = o;

        const auto& ws = open->summary;
        nb::dict osum;
        osum["ticks"] = ws.ticks;
        nb::list passes;
        for (const auto& p : ws.passes) {
          nb::dict pd;
          pd["zmp_error_max"] = p.zmp_error_max;
          pd["zmp_error_rms"] = p.zmp_error_rms;
          pd["zmp_error_ct_max"] = p.zmp_error_ct_max;
          pd["min_margin"] = p.min_margin;
          pd["not_ok"] = p.not_ok;
          pd["seconds"] = p.seconds;
          passes.append(pd);
        }
        osum["passes"] = passes;
        osum["cart_table_error_max"] = ws.cart_table_error_max;
        osum["reference_min_margin"] = ws.reference_min_margin;
        osum["multibody_min_margin"] = ws.multibody_min_margin;
        osum["cop_min_margin"] = ws.cop_min_margin;
        osum["cop_zmp_max"] = ws.cop_zmp_max;
        osum["contact_ok"] = ws.contact_ok;
        osum["root_residual_max"] = ws.root_residual_max;
        osum["ik_residual_max"] = ws.ik_residual_max;
        osum["ik_iterations_max"] = ws.ik_iterations_max;
        osum["ik_not_converged"] = ws.ik_not_converged;
        osum["foot_position_error_max"] = ws.foot_position_error_max;
        osum["foot_rotation_error_max"] = ws.foot_rotation_error_max;
        osum["torque_max"] = vector(ws.torque_max);
        osum["rated_ratio"] = vector(ws.rated_ratio);
        osum["max_ratio"] = vector(ws.max_ratio);
        osum["worst_joint"] = ws.worst_joint;
        osum["tick_seconds_mean"] = ws.tick_seconds_mean;
        osum["tick_seconds_max"] = ws.tick_seconds_max;
        result["open_loop_summary"] = osum;

        if (closed) {
          const auto& cs = closed->samples;
          nb::dict c;
          motion(c, cs, nq, nv, nj);  // tau: the joints only
          feet(c, cs);
          c["cop"] = rows(cs, 2, [](const auto& s) -> const auto& { return s.cop; });
          {
            auto [mg, p] = new_array<double>({npy_intp(cs.size())});
            for (const auto& s : cs) *p++ = s.margin;
            c["margin"] = mg;
          }
          c["com"] = rows(cs, 3, [](const auto& s) -> const auto& { return s.com; });
          c["pelvis"] = rows(cs, 3, [](const auto& s) -> const auto& { return s.pelvis; });
          result["closed_loop"] = c;
          const auto& su = closed->summary;
          nb::dict csum;
          csum["walked"] = su.walked;
          csum["completed"] = su.completed;
          csum["failed_steps"] = su.failed_steps;
          csum["steps_completed"] = su.steps_completed;
          csum["cop_min_margin"] = su.cop_min_margin;
          csum["cop_min_time"] = su.cop_min_time;
          csum["sole_cop_min_margin"] = su.sole_cop_min_margin;
          csum["min_normal_force"] = su.min_normal_force;
          csum["pulls"] = su.pulls;
          csum["max_friction_ratio"] = su.max_friction_ratio;
          csum["slips"] = su.slips;
          csum["pelvis_final_error"] = su.pelvis_final_error;
          csum["pelvis_max_error"] = su.pelvis_max_error;
          csum["com_max_error"] = su.com_max_error;
          csum["joint_error_max"] = su.joint_error_max;
          csum["impacts"] = su.impacts;
          csum["impact_energy_max"] = su.impact_energy_max;
          csum["seconds"] = su.seconds;
          csum["step_seconds_mean"] = su.step_seconds_mean;
          result["closed_loop_summary"] = csum;
        }
        return {result};
      },
      nb::kw_only(), "steps"_a = 8, "length"_a = 0.05, "width"_a = 0.088, "period"_a = 1.0,
      "double_support"_a = 0.2, "turn"_a = 0.0, "swing_height"_a = 0.02, "first_swing"_a = "right",
      "second_stage"_a = 3, "com_height"_a = 0.29, "zmp_model"_a = "multibody", "closed_loop"_a = true,
      "The HOAP-3 walks (the generated hoap3_floating model; docs/walking.md), as `spatial-dyn walk`: the footstep "
      "plan (steps, step length and width in m, period in s, the double-support fraction of it, turn in rad per "
      "step, swing height in m, the first swinging foot), the two-stage ZMP preview control (second_stage passes "
      "feeding back the multibody or the double pendulum's ZMP; CoM height in m) and the whole-body motion (IK, "
      "inverse dynamics with contacts), then (closed_loop=True) the rigid-contact simulation under joint PD + "
      "feed-forward. Returns a dict: 'joint_names', 'dt' (the 2 ms control period), 'open_loop' and 'closed_loop' "
      "(arrays with one row per tick: t, q (N, nq), v, a (N, nv), tau (open loop: (N, nv), root rows ~0; closed "
      "loop: (N, njoints)), wrench (N, 2, 6) per foot (left, right) [force; moment about the sole frame's origin] "
      "in sole axes, contact (N, 2), cop (N, 2); open loop also ok, zmp_reference, zmp_cart_table, zmp_multibody, "
      "com (the CoM target), first_stage_com and first_stage_zmp (N, 2: the cart-table preview control alone) and "
      "first_pass_zmp_multibody (the full model's ZMP of that first pass); closed loop also margin (the CoP's distance inside the support polygon), com, pelvis) "
      "and their summaries 'open_loop_summary', 'closed_loop_summary' (closed_loop_summary['walked']: the walk "
      "succeeded). World coordinates, z up. Invalid gait parameters raise ValueError naming the parameter.");
}

}  // namespace spatial::python
