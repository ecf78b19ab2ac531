// The command-line tool spatial-dyn (tools/spatial_dyn.cpp), run as a separate process on CSV files: each
// subcommand against the library, the id -> fd round trip through files, the CSV rules (column order, extra
// columns, columns of locked joints, stdin/stdout) and every error case (non-zero exit, one line naming the row and
// column), and the inertia warnings of spatial-dyn and spatial-gen. The binaries' paths come from CMake
// (SPATIAL_DYN_EXE, SPATIAL_GEN_EXE).

#include <gtest/gtest.h>

#include <spatial/models/hoap3_torso.hpp>
#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/cli_runner.hpp"
#include "support/urdf_reference.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
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

#ifdef SPATIAL_DYN_EXE

const char* kHeadAndWrists =
    "CHEST_H_PAN_joint=0,H_PAN_H_TILT_joint=0,H_TILT_H_ROLL_joint=0,R_EB_R_WR_joint=0,L_EB_L_WR_joint=0";

RunResult dyn(const std::vector<std::string>& args, const std::string& stdin_path = "") {
  return spatial::testing::run_program(SPATIAL_DYN_EXE, args, stdin_path);
}

uio::LoadOptions stance_right() {
  uio::LoadOptions o;
  o.root = "R_SOLE";
  o.locked = {{"CHEST_H_PAN_joint", 0.0}, {"H_PAN_H_TILT_joint", 0.0}, {"H_TILT_H_ROLL_joint", 0.0},
              {"R_EB_R_WR_joint", 0.0}, {"L_EB_L_WR_joint", 0.0}};
  return o;
}

/// Random states of `model` as a CSV with the given kinds of columns, in a shuffled order, plus a "time" column.
struct States {
  Csv csv;
  std::vector<Eigen::VectorXd> q, qd, x;  // x: qdd or tau, per row
};
States random_states(const uio::LoadedModel& m, const std::vector<std::string>& kinds, int rows, unsigned seed) {
  const Model<double>& model = m.model;
  const int n = model.size();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  States st;
  st.csv.header.push_back("time");
  for (int i = 0; i < n; ++i)
    for (const auto& k : kinds) st.csv.header.push_back(k + ":" + model.joint_name(i));
  std::shuffle(st.csv.header.begin(), st.csv.header.end(), rng);
  for (int r = 0; r < rows; ++r) {
    Eigen::VectorXd q(n), qd(n), x(n);
    for (int i = 0; i < n; ++i) {
      const auto& j = m.joints[static_cast<std::size_t>(i)];
      const double lo = std::isinf(j.lower) ? -3.0 : j.lower, hi = std::isinf(j.upper) ? 3.0 : j.upper;
      q[i] = lo + (hi - lo) * u(rng);
      qd[i] = 2.0 * s(rng);
      x[i] = 3.0 * s(rng);
    }
    std::vector<std::string> row;
    for (const auto& h : st.csv.header) {
      if (h == "time") {
        row.push_back(exact(0.005 * r));
        continue;
      }
      const std::size_t colon = h.find(':');
      const std::string kind = h.substr(0, colon);
      const int i = model.joint_index(h.substr(colon + 1));
      row.push_back(exact(kind == "q" ? q[i] : kind == "qd" ? qd[i] : x[i]));
    }
    st.csv.rows.push_back(row);
    st.q.push_back(q);
    st.qd.push_back(qd);
    st.x.push_back(x);
  }
  return st;
}

Eigen::VectorXd read_row(const Csv& c, std::size_t row, const std::string& prefix, const Model<double>& model) {
  Eigen::VectorXd v(model.size());
  for (int i = 0; i < model.size(); ++i) v[i] = c.number(row, prefix + model.joint_name(i));
  return v;
}

double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

/// One line on stderr, a failing status, and every expected piece of text in it.
void expect_one_line_error(const RunResult& r, const std::vector<std::string>& pieces, int status = 1) {
  EXPECT_EQ(r.status, status) << r.err;
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.back(), '\n');
  EXPECT_EQ(r.err.rfind("spatial-dyn: ", 0), 0u) << r.err;
  for (const auto& p : pieces) EXPECT_NE(r.err.find(p), std::string::npos) << "'" << p << "' not in: " << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(Cli, InverseDynamicsMatchesTheLibrary) {
  const uio::LoadedModel m = uio::load_file(urdf_path("hoap3.urdf"), stance_right());
  States st = random_states(m, {"q", "qd", "qdd"}, 5, 1);
  // A column of a locked joint: ignored (with a note), whatever its value.
  st.csv.header.push_back("q:CHEST_H_PAN_joint");
  for (auto& row : st.csv.rows) row.push_back("0.7");
  ScratchDir dir("cli_id");
  st.csv.write(dir.file("in.csv"));
  const RunResult r = dyn({"id", "--urdf", urdf_path("hoap3.urdf"), "--root", "R_SOLE", "--lock", kHeadAndWrists,
                           "--in", dir.file("in.csv"), "--out", dir.file("out.csv")});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("ignoring the columns of joints that the model does not move: CHEST_H_PAN_joint"),
            std::string::npos) << r.err;
  const Csv out = parse_csv(slurp(dir.file("out.csv")));
  ASSERT_EQ(out.header.size(), 21u);
  for (int i = 0; i < 21; ++i) EXPECT_EQ(out.header[static_cast<std::size_t>(i)], "tau:" + m.model.joint_name(i));
  ASSERT_EQ(out.rows.size(), 5u);
  Data<double> d(m.model);
  for (std::size_t row = 0; row < 5; ++row) {
    const Eigen::VectorXd tau = rnea(m.model, d, st.q[row], st.qd[row], st.x[row]);
    EXPECT_LE(relative_error(read_row(out, row, "tau:", m.model), tau), 1e-14) << "row " << row;
  }
}

TEST(Cli, ForwardDynamicsBothMethodsMatchTheLibrary) {
  const uio::LoadedModel m = uio::load_file(urdf_path("hoap3.urdf"), stance_right());
  const States st = random_states(m, {"q", "qd", "tau"}, 4, 2);
  ScratchDir dir("cli_fd");
  st.csv.write(dir.file("in.csv"));
  Data<double> d(m.model);
  for (const std::string method : {"aba", "crba"}) {
    SCOPED_TRACE(method);
    const RunResult r = dyn({"fd", "--urdf", urdf_path("hoap3.urdf"), "--root", "R_SOLE", "--lock", kHeadAndWrists,
                             "--method", method, "--in", dir.file("in.csv")});
    ASSERT_EQ(r.status, 0) << r.err;
    const Csv out = parse_csv(r.out);
    ASSERT_EQ(out.header.size(), 21u);
    EXPECT_EQ(out.header[0], "qdd:R_AFE_R_AAA_joint");
    ASSERT_EQ(out.rows.size(), 4u);
    for (std::size_t row = 0; row < 4; ++row) {
      const Eigen::VectorXd qdd = aba(m.model, d, st.q[row], st.qd[row], st.x[row]);
      EXPECT_LE(relative_error(read_row(out, row, "qdd:", m.model), qdd), 1e-10) << "row " << row;
    }
  }
}

TEST(Cli, JointSpaceInertiaRowMajor) {
  const uio::LoadedModel m = uio::load_file(urdf_path("double_pendulum.urdf"));
  const States st = random_states(m, {"q"}, 3, 3);
  ScratchDir dir("cli_crba");
  st.csv.write(dir.file("in.csv"));
  const RunResult r = dyn({"crba", "--urdf", urdf_path("double_pendulum.urdf"), "--in", dir.file("in.csv")});
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv out = parse_csv(r.out);
  const std::vector<std::string> header = {"H:ankle_pitch:ankle_pitch", "H:ankle_pitch:hip_pitch",
                                           "H:hip_pitch:ankle_pitch", "H:hip_pitch:hip_pitch"};
  EXPECT_EQ(out.header, header);
  ASSERT_EQ(out.rows.size(), 3u);
  // The pendulum's H by hand: point masses m1 at r1 (link 1), m2 at r1 + R(q2) r2, both rotating about y.
  const Model<double>& pm = m.model;
  const double m1 = pm.inertia(0).m, m2 = pm.inertia(1).m;
  const Eigen::Vector3d r1 = pm.tree_transform(1).r, r2 = pm.inertia(1).com(), c1 = pm.inertia(0).com();
  for (std::size_t row = 0; row < 3; ++row) {
    const double q2 = st.q[row][1];
    const Eigen::Vector3d r2q = Eigen::AngleAxisd(q2, Eigen::Vector3d::UnitY()) * r2;
    auto planar2 = [](const Eigen::Vector3d& v) { return v.x() * v.x() + v.z() * v.z(); };
    const double H11 = m1 * planar2(c1) + m2 * planar2(r1 + r2q);
    const double H12 = m2 * (r1.x() * r2q.x() + r1.z() * r2q.z() + planar2(r2q));  // (r1 + s) . s, s = R r2
    const double H22 = m2 * planar2(r2q);
    EXPECT_NEAR(out.number(row, header[0]), H11, 1e-12);
    EXPECT_NEAR(out.number(row, header[1]), H12, 1e-12);
    EXPECT_NEAR(out.number(row, header[2]), H12, 1e-12);
    EXPECT_NEAR(out.number(row, header[3]), H22, 1e-12);
  }
}

TEST(Cli, InverseThenForwardDynamicsThroughFilesReproducesQdd) {
  const uio::LoadedModel m = uio::load_file(urdf_path("hoap3.urdf"), stance_right());
  const States st = random_states(m, {"q", "qd", "qdd"}, 5, 4);
  ScratchDir dir("cli_roundtrip");
  st.csv.write(dir.file("states.csv"));
  const std::vector<std::string> model = {"--urdf", urdf_path("hoap3.urdf"), "--root", "R_SOLE", "--lock",
                                          kHeadAndWrists};
  auto with = [&](std::vector<std::string> a) {
    a.insert(a.begin() + 1, model.begin(), model.end());
    return a;
  };
  // id --echo: the states and their torques in one file; fd reads q, qd, tau from it (ignoring qdd and time).
  RunResult r = dyn(with({"id", "--in", dir.file("states.csv"), "--out", dir.file("with_tau.csv"), "--echo"}));
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv with_tau = parse_csv(slurp(dir.file("with_tau.csv")));
  EXPECT_EQ(with_tau.header.size(), st.csv.header.size() + 21);
  EXPECT_EQ(with_tau.header[0], st.csv.header[0]);
  for (const std::string method : {"aba", "crba"}) {
    SCOPED_TRACE(method);
    r = dyn(with({"fd", "--method", method, "--in", dir.file("with_tau.csv"), "--out", dir.file("qdd.csv")}));
    ASSERT_EQ(r.status, 0) << r.err;
    const Csv out = parse_csv(slurp(dir.file("qdd.csv")));
    ASSERT_EQ(out.rows.size(), 5u);
    for (std::size_t row = 0; row < 5; ++row)
      EXPECT_LE(relative_error(read_row(out, row, "qdd:", m.model), st.x[row]), 1e-9) << "row " << row;
  }
  // The same through stdin and stdout, fd's --echo replacing the qdd columns with its own.
  r = dyn(with({"fd", "--in", "-", "--echo"}), dir.file("with_tau.csv"));
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv echoed = parse_csv(r.out);
  EXPECT_EQ(echoed.header.size(), with_tau.header.size());
  for (std::size_t row = 0; row < 5; ++row)
    EXPECT_LE(relative_error(read_row(echoed, row, "qdd:", m.model), st.x[row]), 1e-9) << "row " << row;
}

TEST(Cli, SubtreeAndGravityOptionsMatchTheGeneratedTorso) {
  namespace torso = spatial::models::hoap3_torso;
  const auto model = torso::model();
  Data<double, torso::Tree> d(model);
  Csv in;
  for (const auto& j : torso::joint_names)
    for (const char* k : {"q:", "qd:", "qdd:"}) in.header.push_back(k + std::string(j));
  std::vector<Eigen::Matrix<double, 8, 1>> q, qd, qdd;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> s(-1.0, 1.0);
  for (int r = 0; r < 3; ++r) {
    Eigen::Matrix<double, 8, 1> a, b, c;
    for (int i = 0; i < 8; ++i) {
      const auto k = static_cast<std::size_t>(i);
      a[i] = torso::lower[k] + (torso::upper[k] - torso::lower[k]) * 0.5 * (1 + s(rng));
      b[i] = s(rng);
      c[i] = s(rng);
    }
    std::vector<std::string> row;
    for (int i = 0; i < 8; ++i)
      for (const double x : {a[i], b[i], c[i]}) row.push_back(exact(x));
    in.rows.push_back(row);
    q.push_back(a);
    qd.push_back(b);
    qdd.push_back(c);
  }
  ScratchDir dir("cli_torso");
  in.write(dir.file("in.csv"));
  for (const bool no_gravity : {false, true}) {
    SCOPED_TRACE(no_gravity ? "--gravity 0,0,0" : "default gravity");
    std::vector<std::string> args = {"id", "--urdf", urdf_path("hoap3.urdf"), "--subtree", "CHEST", "--lock",
                                     kHeadAndWrists, "--in", dir.file("in.csv")};
    if (no_gravity) args.insert(args.end(), {"--gravity", "0,0,0"});
    const RunResult r = dyn(args);
    ASSERT_EQ(r.status, 0) << r.err;
    const Csv out = parse_csv(r.out);
    ASSERT_EQ(out.rows.size(), 3u);
    const auto m = no_gravity ? model.with_gravity(Eigen::Vector3d::Zero()) : model;
    for (std::size_t row = 0; row < 3; ++row) {
      const Eigen::Matrix<double, 8, 1> tau = rnea(m, d, q[row], qd[row], qdd[row]);
      for (int i = 0; i < 8; ++i)
        EXPECT_NEAR(out.number(row, "tau:" + std::string(torso::joint_names[static_cast<std::size_t>(i)])), tau[i],
                    1e-14 * std::max(1.0, tau.cwiseAbs().maxCoeff()));
    }
  }
}

TEST(Cli, InfoListsJointsMassComAndMasslessJoints) {
  RunResult r = dyn({"info", "--urdf", urdf_path("hoap3.urdf"), "--root", "R_SOLE"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("dof:       26\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("mass:      8.8024 kg"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("massless:  R_EB_R_WR_joint, L_EB_L_WR_joint"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--lock R_EB_R_WR_joint=0,L_EB_L_WR_joint=0"), std::string::npos) << r.out;
  // Joints in model order: the stance ankle first, reversed.
  const std::size_t a = r.out.find("R_AFE_R_AAA_joint"), b = r.out.find("R_KN_R_AFE_joint"),
                    c = r.out.find("L_AFE_L_AAA_joint");
  EXPECT_LT(a, b);
  EXPECT_LT(b, c);
  EXPECT_NE(r.out.find("reversed"), std::string::npos);
  // The whole-body CoM height above the sole: 0.317 m (data sheet, rounded to the millimetre).
  const std::size_t com = r.out.find("com:");
  ASSERT_NE(com, std::string::npos);
  std::istringstream line(r.out.substr(com + 4));
  double x = 0, y = 0, z = 0;
  line >> x >> y >> z;
  EXPECT_NEAR(z, 0.317, 0.5e-3);

  r = dyn({"info", "--urdf", urdf_path("hoap3.urdf"), "--subtree", "CHEST", "--lock", kHeadAndWrists});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("dof:       8\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("massless:  none"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("root:      CHEST"), std::string::npos) << r.out;
}

// ---- errors: non-zero exit and one line naming the file, row and column -----------------------------------------

class CliErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    // A good file for the double pendulum, as the starting point of each broken one.
    good_.header = {"q:ankle_pitch", "q:hip_pitch", "qd:ankle_pitch", "qd:hip_pitch", "qdd:ankle_pitch",
                    "qdd:hip_pitch", "tau:ankle_pitch", "tau:hip_pitch"};
    good_.rows = {{"0.1", "0.2", "0", "0", "0", "0", "1", "2"}, {"-0.1", "0.3", "1", "2", "3", "4", "5", "6"},
                  {"0", "0", "0", "0", "0", "0", "0", "0"}};
  }
  RunResult run(const std::string& command, const Csv& csv, std::vector<std::string> extra = {}) {
    csv.write(dir_.file("in.csv"));
    std::vector<std::string> args = {command, "--urdf", urdf_path("double_pendulum.urdf"), "--in", dir_.file("in.csv"),
                                     "--out", dir_.file("out.csv")};
    args.insert(args.end(), extra.begin(), extra.end());
    RunResult r = dyn(args);
    // Nothing is written unless every sample is good.
    if (r.status != 0) {
      EXPECT_FALSE(std::filesystem::exists(dir_.file("out.csv")));
    }
    std::filesystem::remove(dir_.file("out.csv"));
    return r;
  }
  ScratchDir dir_{"cli_errors"};
  Csv good_;
};

TEST_F(CliErrors, TheGoodFileWorks) {
  EXPECT_EQ(run("id", good_).status, 0);
  EXPECT_EQ(run("fd", good_).status, 0);
  EXPECT_EQ(run("crba", good_).status, 0);
}

TEST_F(CliErrors, MissingColumn) {
  Csv c = good_;
  c.header.erase(c.header.begin() + 3);  // qd:hip_pitch
  for (auto& row : c.rows) row.erase(row.begin() + 3);
  expect_one_line_error(run("id", c), {"in.csv line 1 (header)", "missing column 'qd:hip_pitch'"});
  expect_one_line_error(run("fd", c), {"line 1 (header)", "missing column 'qd:hip_pitch'"});
  EXPECT_EQ(run("crba", c).status, 0);  // crba reads q only
  c = good_;
  c.header.erase(c.header.begin() + 7);  // tau:hip_pitch: id does not need it, fd does
  for (auto& row : c.rows) row.erase(row.begin() + 7);
  EXPECT_EQ(run("id", c).status, 0);
  expect_one_line_error(run("fd", c), {"line 1 (header)", "missing column 'tau:hip_pitch'"});
}

TEST_F(CliErrors, NotANumber) {
  Csv c = good_;
  c.rows[1][1] = "abc";  // row 2, column 2 q:hip_pitch
  expect_one_line_error(run("id", c), {"in.csv line 3 (row 2)", "column 2 'q:hip_pitch'", "'abc' is not a finite number"});
  c = good_;
  c.rows[2][6] = "";  // an empty cell
  expect_one_line_error(run("fd", c), {"line 4 (row 3)", "column 7 'tau:ankle_pitch'", "empty cell"});
  c = good_;
  c.rows[0][4] = "nan";
  expect_one_line_error(run("id", c), {"line 2 (row 1)", "column 5 'qdd:ankle_pitch'", "'nan'"});
  c = good_;
  c.rows[0][0] = "1.5x";
  expect_one_line_error(run("crba", c), {"line 2 (row 1)", "column 1 'q:ankle_pitch'", "'1.5x'"});
}

TEST_F(CliErrors, UnknownJoint) {
  Csv c = good_;
  c.header.push_back("qd:knee");
  for (auto& row : c.rows) row.push_back("0");
  expect_one_line_error(run("id", c), {"line 1 (header)", "column 9 'qd:knee'", "unknown joint 'knee'"});
  // Other column names are not joints: ignored.
  c = good_;
  c.header.push_back("time");
  for (auto& row : c.rows) row.push_back("not even a number");
  EXPECT_EQ(run("id", c).status, 0);
}

TEST_F(CliErrors, RowsOfTheWrongWidthAndDuplicateColumns) {
  Csv c = good_;
  c.rows[1].pop_back();
  expect_one_line_error(run("id", c), {"line 3 (row 2)", "column 8 'tau:hip_pitch'", "missing"});
  c = good_;
  c.rows[0].push_back("9");
  expect_one_line_error(run("id", c), {"line 2 (row 1)", "column 9", "extra field"});
  c = good_;
  c.header[7] = "q:ankle_pitch";
  expect_one_line_error(run("id", c), {"line 1 (header)", "column 8 'q:ankle_pitch'", "duplicate"});
}

TEST_F(CliErrors, MissingFiles) {
  expect_one_line_error(dyn({"id", "--urdf", urdf_path("double_pendulum.urdf"), "--in", dir_.file("nope.csv")}),
                        {"nope.csv", "cannot open"});
  good_.write(dir_.file("in.csv"));
  expect_one_line_error(dyn({"id", "--urdf", dir_.file("nope.urdf"), "--in", dir_.file("in.csv")}),
                        {"nope.urdf", "no such file"});
  std::ofstream(dir_.file("empty.csv")).close();
  expect_one_line_error(dyn({"id", "--urdf", urdf_path("double_pendulum.urdf"), "--in", dir_.file("empty.csv")}),
                        {"empty.csv", "header"});
  // A malformed URDF: urdfdom's message may span lines; the tool prints one.
  expect_one_line_error(dyn({"info", "--urdf", urdf_path("test/bad/malformed.urdf")}), {"malformed.urdf"});
}

TEST_F(CliErrors, ForwardDynamicsRefusesMasslessJoints) {
  // The whole HOAP-3 with its wrists free: they move no mass.
  good_.write(dir_.file("in.csv"));
  const RunResult r = dyn({"fd", "--urdf", urdf_path("hoap3.urdf"), "--in", dir_.file("in.csv")});
  expect_one_line_error(r, {"R_EB_R_WR_joint", "L_EB_L_WR_joint", "singular", "--lock R_EB_R_WR_joint=0,L_EB_L_WR_joint=0"});
  // id and crba are defined on it.
  Csv c;
  const uio::LoadedModel m = uio::load_file(urdf_path("hoap3.urdf"));
  for (int i = 0; i < m.model.size(); ++i) c.header.push_back("q:" + m.model.joint_name(i));
  c.rows.push_back(std::vector<std::string>(c.header.size(), "0"));
  c.write(dir_.file("q.csv"));
  EXPECT_EQ(dyn({"crba", "--urdf", urdf_path("hoap3.urdf"), "--in", dir_.file("q.csv")}).status, 0);
}

TEST_F(CliErrors, BadCommandLines) {
  good_.write(dir_.file("in.csv"));
  const std::string urdf = urdf_path("double_pendulum.urdf"), in = dir_.file("in.csv");
  expect_one_line_error(dyn({}), {"no subcommand"}, 2);
  expect_one_line_error(dyn({"jump", "--urdf", urdf}), {"unknown subcommand 'jump'"}, 2);
  expect_one_line_error(dyn({"id", "--urdf", urdf}), {"--in is required"}, 2);
  expect_one_line_error(dyn({"id", "--in", in}), {"--urdf is required"}, 2);
  expect_one_line_error(dyn({"id", "--urdf", urdf, "--in", in, "--frobnicate"}), {"unknown argument '--frobnicate'"}, 2);
  expect_one_line_error(dyn({"fd", "--urdf", urdf, "--in", in, "--method", "rk4"}), {"--method", "rk4"}, 2);
  expect_one_line_error(dyn({"id", "--urdf", urdf, "--in", in, "--lock", "hip_pitch"}), {"--lock", "JOINT=ANGLE"}, 2);
  expect_one_line_error(dyn({"id", "--urdf", urdf, "--in", in, "--gravity", "0,0"}), {"--gravity"}, 2);
  // Options the loader rejects: named by the loader.
  expect_one_line_error(dyn({"id", "--urdf", urdf, "--in", in, "--root", "nowhere"}), {"root", "'nowhere'"});
  expect_one_line_error(dyn({"id", "--urdf", urdf, "--in", in, "--lock", "knee=0"}), {"locked", "'knee'"});
  const RunResult help = dyn({"--help"});
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("spatial-dyn id"), std::string::npos);
}

// A link inertia breaking the triangle inequality (CAD exports): a warning line on stderr and the work done;
// --strict-inertia refuses the file (status 1, one line naming the link).
TEST_F(CliErrors, TriangleInequalityWarnsAndStrictInertiaRefuses) {
  const std::string urdf = dir_.file("imperfect.urdf");
  std::ofstream(urdf) << R"(<robot name="t"><link name="a"/>
    <link name="foot"><inertial><origin xyz="0.1 0 0"/><mass value="2"/>
      <inertia ixx="0.3" ixy="0" ixz="0" iyy="0.5" iyz="0" izz="1.0"/></inertial></link>
    <joint name="ankle" type="revolute"><parent link="a"/><child link="foot"/><axis xyz="0 1 0"/>
      <limit lower="-1" upper="1" effort="3" velocity="4"/></joint></robot>)";
  Csv c;
  c.header = {"q:ankle", "qd:ankle", "qdd:ankle"};
  c.rows = {{"0.1", "0.2", "0.3"}};
  c.write(dir_.file("in.csv"));
  const std::string warning = "spatial-dyn: warning: " + urdf +
                              ": link 'foot': principal moments violate the triangle inequality: I1 + I2 = 0.8 < I3 = "
                              "1 kg m^2 (short by 0.2, 20 %)\n";
  const RunResult id = dyn({"id", "--urdf", urdf, "--in", dir_.file("in.csv")});
  EXPECT_EQ(id.status, 0) << id.err;
  EXPECT_EQ(id.err, warning);
  const Csv out = parse_csv(id.out);
  const uio::LoadedModel m = uio::load_file(urdf);
  ASSERT_EQ(m.warnings.size(), 1u);
  Data<double> d(m.model);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 0.1), qd = Eigen::VectorXd::Constant(1, 0.2),
                        qdd = Eigen::VectorXd::Constant(1, 0.3);
  EXPECT_EQ(out.number(0, "tau:ankle"), rnea(m.model, d, q, qd, qdd)[0]);
  const RunResult info = dyn({"info", "--urdf", urdf});
  EXPECT_EQ(info.status, 0) << info.err;
  EXPECT_EQ(info.err, warning);

  for (const auto& args : std::vector<std::vector<std::string>>{
           {"id", "--urdf", urdf, "--in", dir_.file("in.csv"), "--strict-inertia"},
           {"info", "--strict-inertia", "--urdf", urdf}}) {
    const RunResult r = dyn(args);
    expect_one_line_error(r, {urdf + ": link 'foot': principal moments violate the triangle inequality", "short by 0.2"});
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  }
  // Files that are fine: no warning, with or without --strict-inertia.
  for (const bool strict : {false, true}) {
    std::vector<std::string> args = {"info", "--urdf", urdf_path("double_pendulum.urdf")};
    if (strict) args.emplace_back("--strict-inertia");
    const RunResult r = dyn(args);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << r.err;
  }
  expect_one_line_error(dyn({"info", "--urdf", urdf, "--strict-inertia=yes"}), {"--strict-inertia takes no value"}, 2);
  EXPECT_NE(dyn({"--help"}).out.find("--strict-inertia"), std::string::npos);
}

#ifdef SPATIAL_GEN_EXE
// spatial-gen loads through the same loader: the same warning on stderr (the header is written), and the same
// refusal with --strict-inertia (nothing written).
TEST_F(CliErrors, GeneratorPrintsTheWarningAndStrictInertiaRefuses) {
  const std::string urdf = urdf_path("test/bad/triangle.urdf"), out = dir_.file("tri.hpp");
  const RunResult ok = spatial::testing::run_program(SPATIAL_GEN_EXE, {"--urdf", urdf, "--name", "tri", "--out", out});
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_EQ(ok.err.rfind("spatial-gen: warning: " + urdf + ": link 'b': principal moments violate the triangle "
                         "inequality: I1 + I2 = 0.02 < I3 = 0.03 kg m^2 (short by 0.01, 33.3 %)\n",
                         0),
            0u)
      << ok.err;
  EXPECT_EQ(std::count(ok.err.begin(), ok.err.end(), '\n'), 1) << ok.err;
  EXPECT_TRUE(std::filesystem::exists(out));
  std::filesystem::remove(out);
  const RunResult strict = spatial::testing::run_program(
      SPATIAL_GEN_EXE, {"--urdf", urdf, "--name", "tri", "--out", out, "--strict-inertia"});
  EXPECT_EQ(strict.status, 1);
  EXPECT_EQ(strict.err.rfind("spatial-gen: " + urdf + ": link 'b': principal moments violate", 0), 0u) << strict.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}
#endif

#else
TEST(Cli, Skipped) { GTEST_SKIP() << "spatial-dyn is not built (SPATIAL_BUILD_TOOLS or SPATIAL_WITH_URDF off)"; }
#endif

}  // namespace
