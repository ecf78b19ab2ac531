#pragma once
// The HOAP-3 as the command-line tests load it (not part of the installed library): the same model as spatial-dyn
// builds from its model options, fixed at base_link with the wrists locked (they move no mass: forward dynamics
// needs them locked) or floating with the head's pan and tilt and the wrists locked; the q:/qd: column names; random
// states as a CSV with a `time` column. Used by tests/test_cli_derivatives.cpp, test_cli_zmp.cpp and
// test_cli_kinematics.cpp.

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/cli_runner.hpp"
#include "support/urdf_reference.hpp"

#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace spatial::testing::cli_hoap3 {

namespace uio = spatial::urdf_io;

inline const char* kWrists = "R_EB_R_WR_joint=0,L_EB_L_WR_joint=0";
inline const char* kPanTiltAndWrists = "CHEST_H_PAN_joint=0,H_PAN_H_TILT_joint=0,R_EB_R_WR_joint=0,L_EB_L_WR_joint=0";
/// The study's stance model: rooted at the right sole, head and wrists locked.
inline const char* kHeadAndWrists =
    "CHEST_H_PAN_joint=0,H_PAN_H_TILT_joint=0,H_TILT_H_ROLL_joint=0,R_EB_R_WR_joint=0,L_EB_L_WR_joint=0";

/// The set-ups: fixed at base_link with every joint free (`Fixed`) or with the wrists locked (`FixedWristsLocked`:
/// they move no mass, forward dynamics needs them locked); floating, with the head's pan and tilt and the wrists
/// locked; fixed at the right sole (the right leg's joints reversed), head and wrists locked.
enum class Setup { Fixed, FixedWristsLocked, Floating, RightSole };

struct Robot {
  bool floating = false;
  uio::LoadedModel loaded;
  std::vector<std::string> model_args;        // the command line's model options
  std::vector<std::string> q_names, v_names;  // coordinates, as in the q: and qd: columns less the prefix
  int nq() const { return static_cast<int>(q_names.size()); }
  int nv() const { return static_cast<int>(v_names.size()); }
};

inline Robot make_robot(Setup setup) {
  Robot s;
  s.floating = setup == Setup::Floating;
  uio::LoadOptions o;
  s.model_args = {"--urdf", urdf_path("hoap3.urdf")};
  switch (setup) {
    case Setup::Fixed: break;
    case Setup::FixedWristsLocked:
      o.locked = {{"R_EB_R_WR_joint", 0.0}, {"L_EB_L_WR_joint", 0.0}};
      s.model_args.insert(s.model_args.end(), {"--lock", kWrists});
      break;
    case Setup::Floating:
      o.floating = true;
      o.locked = {{"CHEST_H_PAN_joint", 0.0}, {"H_PAN_H_TILT_joint", 0.0}, {"R_EB_R_WR_joint", 0.0},
                  {"L_EB_L_WR_joint", 0.0}};
      s.model_args.insert(s.model_args.end(), {"--floating", "--lock", kPanTiltAndWrists});
      for (const char* c : {"x", "y", "z", "qx", "qy", "qz", "qw"}) s.q_names.push_back(std::string("floating_base:") + c);
      for (const char* c : {"vx", "vy", "vz", "wx", "wy", "wz"}) s.v_names.push_back(std::string("floating_base:") + c);
      break;
    case Setup::RightSole:
      o.root = "R_SOLE";
      o.locked = {{"CHEST_H_PAN_joint", 0.0}, {"H_PAN_H_TILT_joint", 0.0}, {"H_TILT_H_ROLL_joint", 0.0},
                  {"R_EB_R_WR_joint", 0.0}, {"L_EB_L_WR_joint", 0.0}};
      s.model_args.insert(s.model_args.end(), {"--root", "R_SOLE", "--lock", kHeadAndWrists});
      break;
  }
  s.loaded = uio::load_file(urdf_path("hoap3.urdf"), o);
  for (int i = 0; i < s.loaded.model.size(); ++i) {
    s.q_names.push_back(s.loaded.model.joint_name(i));
    s.v_names.push_back(s.loaded.model.joint_name(i));
  }
  return s;
}

/// The joints' limits, ±3 where the URDF gives none: the range random configurations are drawn from.
inline std::pair<Eigen::VectorXd, Eigen::VectorXd> joint_range(const Robot& s) {
  const int n = s.loaded.model.size();
  Eigen::VectorXd lo(n), hi(n);
  for (int i = 0; i < n; ++i) {
    const uio::JointInfo& j = s.loaded.joints[std::size_t(i)];
    lo[i] = std::isfinite(j.lower) ? j.lower : -3.0;
    hi[i] = std::isfinite(j.upper) ? j.upper : 3.0;
  }
  return {lo, hi};
}

/// Random states: q within the limits (unit quaternion), qd, qdd and tau in [−1, 1], with a `time` column.
struct States {
  Csv csv;
  std::vector<Eigen::VectorXd> q, qd, qdd, tau;
};

inline States random_states(const Robot& s, int rows, unsigned seed) {
  States st;
  st.csv.header.push_back("time");
  for (const char* kind : {"q:", "qd:", "qdd:", "tau:"})
    for (const auto& n : std::string(kind) == "q:" ? s.q_names : s.v_names) st.csv.header.push_back(kind + n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = s.loaded.model.size();
  const auto [lo, hi] = joint_range(s);
  for (int r = 0; r < rows; ++r) {
    Eigen::VectorXd q(s.nq()), qd(s.nv()), qdd(s.nv()), tau(s.nv());
    if (s.floating) {
      q = random_configuration(uio::floating_model(s.loaded), lo, hi, rng);
      q.segment<4>(3).normalize();
    } else {
      for (int i = 0; i < n; ++i) q[i] = lo[i] + (hi[i] - lo[i]) * (u(rng) + 1) / 2;
    }
    for (int i = 0; i < s.nv(); ++i) qd[i] = u(rng), qdd[i] = u(rng), tau[i] = u(rng);
    std::vector<std::string> row = {exact(0.01 * r)};
    for (const Eigen::VectorXd* x : {&q, &qd, &qdd, &tau})
      for (int i = 0; i < x->size(); ++i) row.push_back(exact((*x)[i]));
    st.csv.rows.push_back(row);
    st.q.push_back(q), st.qd.push_back(qd), st.qdd.push_back(qdd), st.tau.push_back(tau);
  }
  return st;
}

}  // namespace spatial::testing::cli_hoap3
