// spatial-dyn --floating: the free-flyer's columns (q:floating_base:x … qw, qd:/qdd:/tau:floating_base:vx … wz),
// id, fd (both methods) and crba against the library's floating-base algorithms, the id -> fd round trip, and the
// errors: a free-flyer column without --floating, an unknown free-flyer coordinate, a missing one, a quaternion
// that is not of unit length.

#include <gtest/gtest.h>

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/cli_runner.hpp"
#include "support/urdf_reference.hpp"

#include <algorithm>
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

RunResult dyn(const std::vector<std::string>& args) { return spatial::testing::run_program(SPATIAL_DYN_EXE, args, ""); }

uio::LoadedModel floating_hoap3() {
  uio::LoadOptions o;
  o.floating = true;
  o.locked = {{"CHEST_H_PAN_joint", 0.0}, {"H_PAN_H_TILT_joint", 0.0}, {"H_TILT_H_ROLL_joint", 0.0},
              {"R_EB_R_WR_joint", 0.0}, {"L_EB_L_WR_joint", 0.0}};
  return uio::load_file(urdf_path("hoap3.urdf"), o);
}

std::vector<std::string> names(const FloatingModel<double>& m, bool config) {
  std::vector<std::string> out;
  for (const char* c : config ? std::vector<const char*>{"x", "y", "z", "qx", "qy", "qz", "qw"}
                              : std::vector<const char*>{"vx", "vy", "vz", "wx", "wy", "wz"})
    out.push_back(std::string("floating_base:") + c);
  for (int i = 0; i < m.njoints(); ++i) out.push_back(m.tree().joint_name(i));
  return out;
}

struct States {
  Csv csv;
  std::vector<Eigen::VectorXd> q, v, x;
};

States random_states(const uio::LoadedModel& loaded, const std::string& x_kind, int rows) {
  const auto m = uio::floating_model(loaded);
  const auto qn = names(m, true), vn = names(m, false);
  States st;
  for (const auto& n : qn) st.csv.header.push_back("q:" + n);
  for (const auto& n : vn) st.csv.header.push_back("qd:" + n);
  for (const auto& n : vn) st.csv.header.push_back(x_kind + ":" + n);
  std::mt19937 rng(4);
  Eigen::VectorXd lo(m.njoints()), hi(m.njoints());
  for (int i = 0; i < m.njoints(); ++i)
    lo[i] = loaded.joints[std::size_t(i)].lower, hi[i] = loaded.joints[std::size_t(i)].upper;
  std::uniform_real_distribution<double> s(-1.0, 1.0);
  for (int r = 0; r < rows; ++r) {
    const Eigen::VectorXd q = random_configuration(m, lo, hi, rng);
    Eigen::VectorXd v(m.nv()), x(m.nv());
    for (int i = 0; i < m.nv(); ++i) v[i] = 2 * s(rng), x[i] = 3 * s(rng);
    std::vector<std::string> row;
    for (int i = 0; i < m.nq(); ++i) row.push_back(exact(q[i]));
    for (int i = 0; i < m.nv(); ++i) row.push_back(exact(v[i]));
    for (int i = 0; i < m.nv(); ++i) row.push_back(exact(x[i]));
    st.csv.rows.push_back(row);
    st.q.push_back(q), st.v.push_back(v), st.x.push_back(x);
  }
  return st;
}

double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

TEST(CliFloating, InverseForwardAndInertiaMatchTheLibrary) {
  const auto loaded = floating_hoap3();
  const auto m = uio::floating_model(loaded);
  FloatingData<double> d(m);
  const auto vn = names(m, false);
  ScratchDir dir("cli_floating");
  const std::vector<std::string> model_args = {"--urdf", urdf_path("hoap3.urdf"), "--floating", "--lock",
                                               kHeadAndWrists};
  auto args = [&](const std::string& cmd, std::vector<std::string> more) {
    std::vector<std::string> a = {cmd};
    a.insert(a.end(), model_args.begin(), model_args.end());
    a.insert(a.end(), more.begin(), more.end());
    return a;
  };
  // id
  States id = random_states(loaded, "qdd", 4);
  id.csv.write(dir.file("id.csv"));
  RunResult r = dyn(args("id", {"--in", dir.file("id.csv"), "--out", dir.file("tau.csv")}));
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv tau = parse_csv(slurp(dir.file("tau.csv")));
  ASSERT_EQ(tau.header.size(), 27u);
  EXPECT_EQ(tau.header[0], "tau:floating_base:vx");
  EXPECT_EQ(tau.header[5], "tau:floating_base:wz");
  for (std::size_t row = 0; row < 4; ++row) {
    const Eigen::VectorXd ref = rnea(m, d, id.q[row], id.v[row], id.x[row]);
    Eigen::VectorXd got(27);
    for (int i = 0; i < 27; ++i) got[i] = tau.number(row, "tau:" + vn[std::size_t(i)]);
    EXPECT_LE(relative_error(got, ref), 1e-15) << row;
  }
  // fd by both methods, and the round trip through the files.
  for (const std::string method : {"aba", "crba"}) {
    States fd = random_states(loaded, "tau", 3);
    fd.csv.write(dir.file("fd.csv"));
    r = dyn(args("fd", {"--in", dir.file("fd.csv"), "--out", dir.file("qdd.csv"), "--method", method}));
    ASSERT_EQ(r.status, 0) << r.err;
    const Csv qdd = parse_csv(slurp(dir.file("qdd.csv")));
    for (std::size_t row = 0; row < 3; ++row) {
      const Eigen::VectorXd ref = method == "aba" ? Eigen::VectorXd(aba(m, d, fd.q[row], fd.v[row], fd.x[row]))
                                                  : Eigen::VectorXd(forward_dynamics_crba(m, d, fd.q[row], fd.v[row], fd.x[row]));
      Eigen::VectorXd got(27);
      for (int i = 0; i < 27; ++i) got[i] = qdd.number(row, "qdd:" + vn[std::size_t(i)]);
      EXPECT_LE(relative_error(got, ref), 1e-15) << method << " row " << row;
    }
  }
  r = dyn(args("id", {"--in", dir.file("id.csv"), "--out", dir.file("echo.csv"), "--echo"}));
  ASSERT_EQ(r.status, 0) << r.err;
  r = dyn(args("fd", {"--in", dir.file("echo.csv"), "--out", dir.file("back.csv"), "--method", "crba"}));
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv back = parse_csv(slurp(dir.file("back.csv")));
  for (std::size_t row = 0; row < 4; ++row)
    for (int i = 0; i < 27; ++i)
      EXPECT_NEAR(back.number(row, "qdd:" + vn[std::size_t(i)]), id.x[row][i], 1e-10) << row << " " << i;
  // crba: 27 × 27, row-major, named by the velocity coordinates.
  r = dyn(args("crba", {"--in", dir.file("id.csv"), "--out", dir.file("H.csv")}));
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv H = parse_csv(slurp(dir.file("H.csv")));
  ASSERT_EQ(H.header.size(), 27u * 27u);
  EXPECT_EQ(H.header[1], "H:floating_base:vx:floating_base:vy");
  const Eigen::MatrixXd Href = crba(m, d, id.q[0]);
  for (int i = 0; i < 27; ++i)
    for (int j = 0; j < 27; ++j)
      EXPECT_EQ(H.number(0, "H:" + vn[std::size_t(i)] + ":" + vn[std::size_t(j)]), i >= j ? Href(i, j) : Href(j, i));
}

TEST(CliFloating, Errors) {
  const auto loaded = floating_hoap3();
  States st = random_states(loaded, "qdd", 2);
  ScratchDir dir("cli_floating_errors");
  auto run = [&](const Csv& c, bool floating) {
    c.write(dir.file("in.csv"));
    std::vector<std::string> a = {"id", "--urdf", urdf_path("hoap3.urdf"), "--lock", kHeadAndWrists, "--in",
                                  dir.file("in.csv")};
    if (floating) a.push_back("--floating");
    return dyn(a);
  };
  auto expect_error = [](const RunResult& r, const std::vector<std::string>& pieces) {
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    for (const auto& p : pieces) EXPECT_NE(r.err.find(p), std::string::npos) << "'" << p << "' not in: " << r.err;
    EXPECT_TRUE(r.out.empty());
  };
  EXPECT_EQ(run(st.csv, true).status, 0);
  expect_error(run(st.csv, false), {"column 1 'q:floating_base:x'", "no free-flyer", "--floating"});
  Csv c = st.csv;
  c.header[3] = "q:floating_base:roll";
  expect_error(run(c, true), {"column 4 'q:floating_base:roll'", "unknown free-flyer coordinate",
                              "q:floating_base:qw"});
  c = st.csv;
  const auto vy = std::find(c.header.begin(), c.header.end(), "qd:floating_base:vy") - c.header.begin();
  c.header.erase(c.header.begin() + vy);
  for (auto& row : c.rows) row.erase(row.begin() + vy);
  expect_error(run(c, true), {"missing column 'qd:floating_base:vy'", "free-flyer"});
  c = st.csv;
  c.rows[1][6] = "2.5";  // qw
  expect_error(run(c, true), {"line 3 (row 2)", "quaternion has length", "unit quaternion"});
}

#else
TEST(CliFloating, Skipped) { GTEST_SKIP() << "spatial-dyn is not built"; }
#endif

}  // namespace
