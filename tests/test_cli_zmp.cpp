// spatial-dyn zmp on the HOAP-3 (fixed at base_link, floating, and rooted at the right sole): the output's columns
// (F:x … M:z, zmp:x, zmp:y), its numbers against the library's base_wrench / zmp_on_plane on the same loaded model
// (bit for bit: the tool writes the shortest text that reads back as the same double), the ZMP at rest against the
// centre of mass from `spatial-dyn com`, and the errors.

#include <gtest/gtest.h>

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/cli_hoap3.hpp"
#include "support/cli_runner.hpp"

#include <cmath>
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
using spatial::testing::cli_hoap3::make_robot;
using spatial::testing::cli_hoap3::random_states;
using spatial::testing::cli_hoap3::Robot;
using spatial::testing::cli_hoap3::Setup;

#ifdef SPATIAL_DYN_EXE

RunResult dyn(const std::vector<std::string>& args) { return spatial::testing::run_program(SPATIAL_DYN_EXE, args, ""); }

const std::vector<std::string> kColumns = {"F:x", "F:y", "F:z", "M:x", "M:y", "M:z", "zmp:x", "zmp:y"};

void check(bool floating) {
  SCOPED_TRACE(floating ? "floating" : "fixed at base_link");
  const Robot s = make_robot(floating ? Setup::Floating : Setup::FixedWristsLocked);
  ScratchDir dir("cli_zmp");
  const auto st = random_states(s, 4, floating ? 21u : 22u);
  st.csv.write(dir.file("in.csv"));
  std::vector<std::string> args = {"zmp"};
  args.insert(args.end(), s.model_args.begin(), s.model_args.end());
  args.insert(args.end(), {"--in", dir.file("in.csv"), "--out", dir.file("out.csv")});
  const RunResult r = dyn(args);
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv csv = parse_csv(slurp(dir.file("out.csv")));
  EXPECT_EQ(csv.header, kColumns);
  ASSERT_EQ(csv.rows.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    Force<double> w;
    if (floating) {
      const FloatingModel<double> fm = uio::floating_model(s.loaded);
      FloatingData<double> d(fm);
      w = base_wrench(fm, d, st.q[k], st.qd[k], st.qdd[k]);
    } else {
      Data<double> d(s.loaded.model);
      w = base_wrench(s.loaded.model, d, st.q[k], st.qd[k], st.qdd[k]);
    }
    const Eigen::Vector3d p = zmp_on_plane(w, 0.0);
    const double expected[8] = {w.f.x(), w.f.y(), w.f.z(), w.n.x(), w.n.y(), w.n.z(), p.x(), p.y()};
    for (std::size_t c = 0; c < 8; ++c) {
      if (std::isnan(expected[c])) {
        EXPECT_EQ(csv.rows[k][csv.column(kColumns[c])], "nan");
        continue;
      }
      EXPECT_EQ(csv.number(k, kColumns[c]), expected[c]) << kColumns[c] << " row " << k;
    }
    EXPECT_GT(std::abs(w.f.z()), 0.1);  // gravity at least
  }
}

TEST(CliZmp, FixedBaseMatchesTheLibrary) { check(false); }
TEST(CliZmp, FloatingBaseMatchesTheLibrary) { check(true); }

TEST(CliZmp, AtRestOnTheRightSoleTheZmpIsTheCentreOfMass) {
  // Rooted at the right sole (z up), standing still: the ground's force is the weight of the moving bodies and the
  // ZMP is their centre of mass projected on the sole's plane (spatial-dyn com: fixed base, moving bodies).
  ScratchDir dir("cli_zmp_rest");
  const Robot s = make_robot(Setup::Fixed);
  Csv in;
  for (const char* kind : {"q:", "qd:", "qdd:"})
    for (const auto& n : s.v_names) in.header.push_back(kind + n);
  std::vector<std::string> row;
  for (int k = 0; k < 3; ++k)
    for (std::size_t i = 0; i < s.v_names.size(); ++i) row.push_back(k == 0 ? exact(0.05 * double(i % 5)) : "0");
  in.rows.push_back(row);
  in.write(dir.file("rest.csv"));
  const std::vector<std::string> model = {"--urdf", urdf_path("hoap3.urdf"), "--root", "R_SOLE"};
  std::vector<std::string> a = {"zmp"}, b = {"com"};
  for (auto* v : {&a, &b}) {
    v->insert(v->end(), model.begin(), model.end());
    v->insert(v->end(), {"--in", dir.file("rest.csv")});
  }
  const RunResult rz = dyn(a), rc = dyn(b);
  ASSERT_EQ(rz.status, 0) << rz.err;
  ASSERT_EQ(rc.status, 0) << rc.err;
  const Csv z = parse_csv(rz.out), c = parse_csv(rc.out);
  EXPECT_NEAR(z.number(0, "zmp:x"), c.number(0, "com:x"), 1e-12);
  EXPECT_NEAR(z.number(0, "zmp:y"), c.number(0, "com:y"), 1e-12);
  EXPECT_NEAR(z.number(0, "F:x"), 0.0, 1e-9);
  EXPECT_GT(z.number(0, "F:z"), 1.0);
}

TEST(CliZmp, MissingAccelerationsAreAnError) {
  ScratchDir dir("cli_zmp_errors");
  const Robot s = make_robot(Setup::FixedWristsLocked);
  auto st = random_states(s, 1, 3u);
  Csv c = st.csv;
  const int k = c.column("qdd:" + s.v_names[0]);
  c.header.erase(c.header.begin() + k);
  c.rows[0].erase(c.rows[0].begin() + k);
  c.write(dir.file("no_qdd.csv"));
  std::vector<std::string> args = {"zmp"};
  args.insert(args.end(), s.model_args.begin(), s.model_args.end());
  args.insert(args.end(), {"--in", dir.file("no_qdd.csv")});
  const RunResult r = dyn(args);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("qdd:" + s.v_names[0]), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
}

#endif  // SPATIAL_DYN_EXE

}  // namespace
