// spatial-dyn walk: a one-step walk through the tool against the same walk through the library (the CSV's numbers bit
// for bit: the tool writes the shortest text that reads back as the same double), the CSV's columns and their
// consistency (unit quaternions, no force on a sole out of contact), walk.json's verdict, an unreachable plan (reported,
// valid JSON), and the errors.

#include <gtest/gtest.h>

#include <spatial/models/hoap3_floating.hpp>
#include <spatial/walking.hpp>

#include "support/cli_runner.hpp"

#include <cmath>
#include <cstdlib>
#include <regex>
#include <string>
#include <vector>

namespace {

using spatial::testing::Csv;
using spatial::testing::parse_csv;
using spatial::testing::RunResult;
using spatial::testing::ScratchDir;
using spatial::testing::slurp;
namespace fb = spatial::models::hoap3_floating;
namespace wk = spatial::walking;

#ifdef SPATIAL_DYN_EXE

RunResult dyn(const std::vector<std::string>& args) {
  ::setenv("SPATIAL_PYTHON", "true", 1);  // the plotting script is not run (`true SCRIPT DIR`): no matplotlib needed
  return spatial::testing::run_program(SPATIAL_DYN_EXE, args, "");
}

TEST(CliWalk, OneStepMatchesTheLibrary) {
  ScratchDir dir("cli_walk");
  const RunResult r = dyn({"walk", "--steps", "1", "--length", "0.04", "--turn", "0.1", "--out", dir.file("w")});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("WALKED"), std::string::npos) << r.out;
  const Csv csv = parse_csv(slurp(dir.file("w/walk.csv")));
  const std::string json = slurp(dir.file("w/walk.json"));
  EXPECT_NE(json.find("\"walked\": true"), std::string::npos) << json;
  EXPECT_NE(json.find("\"steps\": 1,"), std::string::npos);
  EXPECT_NE(json.find("\"ik_not_converged\": 0,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"ik_first_failure_t\": null,"), std::string::npos) << json;
  EXPECT_EQ(r.err.find("not reachable"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--length and --turn have no effect"), std::string::npos) << r.err;  // one step: in place

  // the same walk through the library
  wk::GaitParameters<double> g;
  g.steps = 1;
  g.step_length = 0.04;
  g.turn = 0.1;
  const wk::FootstepPlan<double> plan(g);
  const auto model = fb::floating_model().to_runtime();
  const wk::WholeBodyFrames fr{fb::frame_index("L_SOLE"), fb::frame_index("R_SOLE"), fb::frame_index("base_link")};
  const auto options = wk::hoap3_whole_body_options<double>(fb::joint_names);
  const auto open = wk::run_whole_body(model, fr, spatial::ik_limits(fb::lower), spatial::ik_limits(fb::upper), plan,
                                       options);
  const auto closed = wk::run_closed_loop(model, fr, plan, open, options);
  ASSERT_EQ(csv.rows.size(), closed.samples.size());
  const std::vector<std::string> q_fb = {"x", "y", "z", "qx", "qy", "qz", "qw"};
  for (std::size_t k : {std::size_t(0), closed.samples.size() / 2, closed.samples.size() - 1}) {
    const auto& s = closed.samples[k];
    EXPECT_EQ(csv.number(k, "t"), s.t);
    for (int i = 0; i < 7; ++i) EXPECT_EQ(csv.number(k, "q:floating_base:" + q_fb[static_cast<std::size_t>(i)]), s.q[i]);
    for (int j = 0; j < 21; ++j) {
      const std::string name(fb::joint_names[static_cast<std::size_t>(j)]);
      EXPECT_EQ(csv.number(k, "q:" + name), s.q[7 + j]) << name;
      EXPECT_EQ(csv.number(k, "tau:" + name), s.tau[j]) << name;
    }
    EXPECT_EQ(csv.number(k, "F:right:z"), s.wrench[1][2]);
    EXPECT_EQ(csv.number(k, "zmp_mb:x"), open.samples[k].zmp_multibody.x());
    EXPECT_EQ(csv.number(k, "zmp_mb0:y"), open.zmp_multibody.front()(static_cast<Eigen::Index>(k), 1));
    EXPECT_EQ(csv.number(k, "cop:y"), s.cop.y());
  }
  // consistency of every row
  for (std::size_t k = 0; k < csv.rows.size(); ++k) {
    double n2 = 0;
    for (const char* c : {"qx", "qy", "qz", "qw"}) n2 += std::pow(csv.number(k, std::string("q:floating_base:") + c), 2);
    EXPECT_NEAR(n2, 1.0, 1e-12);
    for (const char* f : {"left", "right"}) {
      if (csv.number(k, std::string("contact:") + f) == 0.0) {
        EXPECT_EQ(csv.number(k, std::string("F:") + f + ":z"), 0.0);
      }
    }
  }
  const std::size_t last = csv.rows.size() - 1;
  EXPECT_NEAR(csv.number(last, "pelvis:x"), csv.number(last, "pelvis_plan:x"), 0.01);
}

/// Whether `json` holds a NaN or an infinity where a number belongs (JSON has neither: readers refuse the file).
bool has_non_finite(const std::string& json) {
  static const std::regex bad(R"((^|[:,\[\s])[-+]?(nan|inf)([\s,\]}]|$))", std::regex::icase);
  return std::regex_search(json, bad);
}

// Steps far too long for the HOAP-3's legs: the whole-body IK cannot follow the plan, and the walk's figures diverge.
// The tool still writes its files (the verdict is "did not walk"), but says why on stderr and in walk.json (how many
// ticks the IK missed, the first one), and walk.json stays valid JSON: the diverged figures are null, not nan.
TEST(CliWalk, UnreachablePlanIsReported) {
  ScratchDir dir("cli_walk_unreachable");
  const RunResult r = dyn({"walk", "--steps", "2", "--length", "0.25", "--out", dir.file("w")});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("not reachable"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("did NOT walk"), std::string::npos) << r.out;
  const std::string json = slurp(dir.file("w/walk.json"));
  EXPECT_NE(json.find("\"walked\": false"), std::string::npos) << json;
  EXPECT_EQ(json.find("\"ik_not_converged\": 0,"), std::string::npos) << json;
  EXPECT_EQ(json.find("\"ik_first_failure_t\": null"), std::string::npos) << json;
  EXPECT_FALSE(has_non_finite(json)) << json;
  EXPECT_TRUE(has_non_finite("{\"a\": nan}") && has_non_finite("[1, -inf]") && !has_non_finite("{\"info\": 1}"));
}

TEST(CliWalk, RejectsBadOptions) {
  ScratchDir dir("cli_walk_bad");
  const auto fails = [&](std::vector<std::string> args, const std::string& word) {
    args.insert(args.begin(), "walk");
    args.insert(args.end(), {"--out", dir.file("w")});
    const RunResult r = dyn(args);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find(word), std::string::npos) << r.err;
  };
  fails({"--steps", "-1"}, "--steps");
  fails({"--steps", "2.5"}, "--steps");
  fails({"--length", "abc"}, "--length");
  fails({"--period", "0"}, "period");
  fails({"--double-support", "1.5"}, "double");
  fails({"--zmp-model", "cart"}, "--zmp-model");
  fails({"--bogus", "1"}, "--bogus");
  EXPECT_FALSE(std::filesystem::exists(dir.file("w/walk.csv")));  // nothing written
}

#endif  // SPATIAL_DYN_EXE

}  // namespace
