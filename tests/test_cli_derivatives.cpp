// spatial-dyn derivatives id|fd on the HOAP-3 (fixed at base_link with the wrists locked, and floating with the
// head's pan and tilt and the wrists locked): the output's column names (dtau_dq:<row>:<column> …, named like the qd: columns), its
// numbers against the library's rnea_derivatives / aba_derivatives on the same loaded model (the tool writes the
// shortest text that reads back as the same double: equal bit for bit), --echo, and the errors.

#include <gtest/gtest.h>

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/cli_hoap3.hpp"
#include "support/cli_runner.hpp"
#include "support/urdf_reference.hpp"

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace uio = spatial::urdf_io;
using spatial::testing::Csv;
using spatial::testing::exact;
using spatial::testing::parse_csv;
using spatial::testing::RunResult;
using spatial::testing::ScratchDir;
using spatial::testing::slurp;
using spatial::testing::urdf_path;
using spatial::testing::cli_hoap3::kWrists;
using spatial::testing::cli_hoap3::make_robot;
using spatial::testing::cli_hoap3::random_states;
using spatial::testing::cli_hoap3::Robot;
using spatial::testing::cli_hoap3::Setup;
using spatial::testing::cli_hoap3::States;

#ifdef SPATIAL_DYN_EXE

RunResult dyn(const std::vector<std::string>& args) { return spatial::testing::run_program(SPATIAL_DYN_EXE, args, ""); }

std::vector<std::string> header_of(const Robot& s, const std::vector<std::string>& blocks) {
  std::vector<std::string> h;
  for (const auto& b : blocks)
    for (const auto& r : s.v_names)
      for (const auto& c : s.v_names) h.push_back(b + ":" + r + ":" + c);
  return h;
}

/// The tool's block `name` of row `row` as an nv × nv matrix.
Eigen::MatrixXd block(const Csv& csv, std::size_t row, const Robot& s, const std::string& name) {
  Eigen::MatrixXd M(s.nv(), s.nv());
  for (int i = 0; i < s.nv(); ++i)
    for (int j = 0; j < s.nv(); ++j)
      M(i, j) = csv.number(row, name + ":" + s.v_names[std::size_t(i)] + ":" + s.v_names[std::size_t(j)]);
  return M;
}

void check(bool floating) {
  SCOPED_TRACE(floating ? "floating" : "fixed at base_link");
  const Robot s = make_robot(floating ? Setup::Floating : Setup::FixedWristsLocked);
  ScratchDir dir("cli_derivatives");
  const States st = random_states(s, 3, floating ? 7u : 8u);
  st.csv.write(dir.file("in.csv"));
  const Model<double>& model = s.loaded.model;
  const FloatingModel<double> fmodel = floating ? uio::floating_model(s.loaded) : FloatingModel<double>();
  for (const std::string what : {"id", "fd"}) {
    SCOPED_TRACE(what);
    std::vector<std::string> args = {"derivatives", what};
    args.insert(args.end(), s.model_args.begin(), s.model_args.end());
    args.insert(args.end(), {"--in", dir.file("in.csv"), "--out", dir.file("out.csv")});
    const RunResult r = dyn(args);
    ASSERT_EQ(r.status, 0) << r.err;
    const Csv csv = parse_csv(slurp(dir.file("out.csv")));
    const std::vector<std::string> blocks = what == "id" ? std::vector<std::string>{"dtau_dq", "dtau_dv"}
                                                         : std::vector<std::string>{"dqdd_dq", "dqdd_dv", "dqdd_dtau"};
    EXPECT_EQ(csv.header, header_of(s, blocks));
    ASSERT_EQ(csv.rows.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
      std::vector<Eigen::MatrixXd> expected;
      const auto compute = [&](const auto& m, auto& data, auto& dd) {
        if (what == "id") {
          rnea_derivatives(m, data, dd, st.q[k], st.qd[k], st.qdd[k]);
          expected = {dd.dtau_dq, dd.dtau_dv};
        } else {
          aba_derivatives(m, data, dd, st.q[k], st.qd[k], st.tau[k]);
          expected = {dd.dqdd_dq, dd.dqdd_dv, dd.dqdd_dtau};
        }
      };
      if (floating) {
        FloatingData<double> data(fmodel);
        FloatingDerivativeData<double> dd(fmodel);
        compute(fmodel, data, dd);
      } else {
        Data<double> data(model);
        DerivativeData<double> dd(model);
        compute(model, data, dd);
      }
      for (std::size_t b = 0; b < blocks.size(); ++b) {
        const Eigen::MatrixXd got = block(csv, k, s, blocks[b]);
        EXPECT_TRUE(got == expected[b]) << blocks[b] << " row " << k << ": max difference "
                                        << (got - expected[b]).cwiseAbs().maxCoeff();
        EXPECT_GT(got.cwiseAbs().maxCoeff(), 0.0);
      }
    }
  }
}

TEST(CliDerivatives, FixedBaseMatchesTheLibrary) { check(false); }
TEST(CliDerivatives, FloatingBaseMatchesTheLibrary) { check(true); }

TEST(CliDerivatives, EchoKeepsTheInputColumns) {
  const Robot s = make_robot(Setup::FixedWristsLocked);
  ScratchDir dir("cli_derivatives_echo");
  random_states(s, 1, 9u).csv.write(dir.file("in.csv"));
  std::vector<std::string> args = {"derivatives", "id"};
  args.insert(args.end(), s.model_args.begin(), s.model_args.end());
  args.insert(args.end(), {"--in", dir.file("in.csv"), "--echo"});
  const RunResult r = dyn(args);
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv csv = parse_csv(r.out);
  ASSERT_GE(csv.header.size(), 2u);
  EXPECT_EQ(csv.header[0], "time");
  EXPECT_GE(csv.column("q:R_LFE_R_KN_joint"), 0);
  EXPECT_GE(csv.column("dtau_dv:R_LFE_R_KN_joint:R_LFE_R_KN_joint"), 0);
}

void expect_error(const RunResult& r, int status, const std::vector<std::string>& pieces) {
  EXPECT_EQ(r.status, status) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  for (const auto& p : pieces) EXPECT_NE(r.err.find(p), std::string::npos) << "'" << p << "' not in: " << r.err;
}

TEST(CliDerivatives, Errors) {
  const Robot s = make_robot(Setup::FixedWristsLocked);
  ScratchDir dir("cli_derivatives_errors");
  States st = random_states(s, 1, 10u);
  st.csv.write(dir.file("in.csv"));
  const std::string urdf = urdf_path("hoap3.urdf"), in = dir.file("in.csv");
  expect_error(dyn({"derivatives", "--urdf", urdf, "--in", in}), 2, {"'id' or 'fd'", "'--urdf'"});
  expect_error(dyn({"derivatives"}), 2, {"derivatives id", "derivatives fd"});
  expect_error(dyn({"derivatives", "ik", "--urdf", urdf, "--in", in}), 2, {"'ik'"});
  expect_error(dyn({"derivatives", "fd", "--urdf", urdf, "--in", in, "--method", "crba"}), 2, {"--method"});
  // A missing qdd: column for id, a missing tau: column for fd: named.
  Csv c = st.csv;
  const int k = c.column("qdd:R_LFE_R_KN_joint");
  ASSERT_GE(k, 0);
  c.header[std::size_t(k)] = "knee";
  c.write(dir.file("no_qdd.csv"));
  expect_error(dyn({"derivatives", "id", "--urdf", urdf, "--lock", kWrists, "--in", dir.file("no_qdd.csv")}), 1,
               {"missing column 'qdd:R_LFE_R_KN_joint'", "derivatives id"});
  const int t = c.column("tau:R_LFE_R_KN_joint");
  c.header[std::size_t(t)] = "knee torque";
  c.write(dir.file("no_tau.csv"));
  expect_error(dyn({"derivatives", "fd", "--urdf", urdf, "--lock", kWrists, "--in", dir.file("no_tau.csv")}), 1,
               {"missing column 'tau:R_LFE_R_KN_joint'", "derivatives fd"});
  // Forward dynamics with massless joints: refused, naming them and the --lock that fixes it.
  random_states(make_robot(Setup::Fixed), 1, 11u).csv.write(dir.file("all_joints.csv"));
  expect_error(dyn({"derivatives", "fd", "--urdf", urdf, "--in", dir.file("all_joints.csv")}), 1,
               {"'R_EB_R_WR_joint'", "singular", "--lock R_EB_R_WR_joint=0"});
  const RunResult help = dyn({"--help"});
  EXPECT_NE(help.out.find("spatial-dyn derivatives id|fd"), std::string::npos);
}

#endif  // SPATIAL_DYN_EXE

}  // namespace
