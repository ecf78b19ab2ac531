// spatial-dyn jacobian and com on the HOAP-3: the output's column names, and its numbers against the library's
// compute_frame_jacobian (links merged into a body or the base: fixed frames of the model), the body Jacobian moved
// to the link's own frame with link_pose (moving links, some of whose body frames are turned by π), center_of_mass
// and com_jacobian, for the three reference frames, fixed at the pelvis, floating, and fixed at the right sole
// (reversed joints); then the errors (unknown frame, bad --reference, missing q: column, options in the wrong
// place).

#include <gtest/gtest.h>

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/cli_hoap3.hpp"
#include "support/cli_runner.hpp"
#include "support/urdf_reference.hpp"

#include <algorithm>
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

#ifdef SPATIAL_DYN_EXE

RunResult dyn(const std::vector<std::string>& args) { return spatial::testing::run_program(SPATIAL_DYN_EXE, args, ""); }

// The floating model locks the head's pan and tilt (H_PAN and H_TILT, turned by π when moving, become fixed frames of
// the chest; H_ROLL, also turned, hangs from the chest) and the wrists.
const char* kJacobianRows[] = {"vx", "vy", "vz", "wx", "wy", "wz"};  // linear first

using Kind = spatial::testing::cli_hoap3::Setup;
using KinRobot = spatial::testing::cli_hoap3::Robot;
using spatial::testing::cli_hoap3::make_robot;

/// Random configurations (joints within their limits, the free-flyer anywhere near the origin), written with a
/// `time` column in front and qd: columns behind that the kinematics subcommands do not need.
struct States {
  Csv csv;
  std::vector<Eigen::VectorXd> q;
};

States random_configurations(const KinRobot& s, int rows, unsigned seed) {
  States st;
  st.csv.header.push_back("time");
  for (const auto& n : s.q_names) st.csv.header.push_back("q:" + n);
  for (const auto& n : s.v_names) st.csv.header.push_back("qd:" + n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = s.loaded.model.size();
  const auto [lo, hi] = spatial::testing::cli_hoap3::joint_range(s);
  for (int r = 0; r < rows; ++r) {
    Eigen::VectorXd q(s.nq());
    if (s.floating) {
      q = random_configuration(uio::floating_model(s.loaded), lo, hi, rng);
      q.segment<4>(3).normalize();  // as the tool does with the quaternion it reads
    } else {
      for (int i = 0; i < n; ++i) q[i] = lo[i] + (hi[i] - lo[i]) * u(rng);
    }
    std::vector<std::string> row = {exact(0.01 * r)};
    for (int i = 0; i < s.nq(); ++i) row.push_back(exact(q[i]));
    for (int i = 0; i < s.nv(); ++i) row.push_back(exact(2 * u(rng) - 1));
    st.csv.rows.push_back(row);
    st.q.push_back(q);
  }
  return st;
}

ReferenceFrame reference_of(const std::string& name) {
  if (name == "local") return ReferenceFrame::Local;
  if (name == "world") return ReferenceFrame::World;
  return ReferenceFrame::LocalWorldAligned;
}

/// Pose of a URDF link in the world (fixed base: the base frame) at q, from link_pose (rotation: link axes in world
/// coordinates, translation: its origin).
Eigen::Isometry3d link_world_pose(const KinRobot& s, const Eigen::VectorXd& q, const std::string& link) {
  Data<double> d(s.loaded.model);
  const int n = s.loaded.model.size();
  const Eigen::VectorXd qj = q.tail(n);
  forward_kinematics(s.loaded.model, d, qj);
  const Eigen::Isometry3d in_base = uio::link_pose(s.loaded, d, link);
  if (!s.floating) return in_base;
  Eigen::Isometry3d root = Eigen::Isometry3d::Identity();
  root.translation() = q.head<3>();
  root.linear() = Eigen::Quaterniond(q[6], q[3], q[4], q[5]).toRotationMatrix();
  return root * in_base;
}

/// The library's Jacobian of `link` (rows linear first) in `rf` at q. A link that is a fixed frame of the model:
/// compute_frame_jacobian. A moving link: compute_body_jacobian (World) of its body, moved to the link's origin
/// (LocalWorldAligned: v + ω × p) and turned into its axes (Local), with the link's pose from link_pose — the
/// link's frame, not the body's, which differs for the bodies turned by π.
Eigen::MatrixXd reference_jacobian(const KinRobot& s, const Eigen::VectorXd& q, const std::string& link,
                                   ReferenceFrame rf) {
  const Model<double>& model = s.loaded.model;
  Eigen::MatrixXd J = Eigen::MatrixXd::Constant(6, s.nv(), 7.0);  // every entry must be written
  int frame = -1;
  for (std::size_t k = 0; k < model.frames().size(); ++k)
    if (model.frames()[k].name == link) frame = static_cast<int>(k);
  const FloatingModel<double> fmodel = s.floating ? uio::floating_model(s.loaded)
                                                  : FloatingModel<double>(model, Inertia<double>::Zero());
  Data<double> d(model);
  FloatingData<double> fd(fmodel);
  if (frame >= 0) {
    if (s.floating) compute_frame_jacobian(fmodel, fd, q, frame, rf, J);
    else compute_frame_jacobian(model, d, q, frame, rf, J);
    return J;
  }
  const int body = model.body_index(link);
  EXPECT_GE(body, 0) << link;
  if (s.floating) compute_body_jacobian(fmodel, fd, q, body, ReferenceFrame::World, J);
  else compute_body_jacobian(model, d, q, body, ReferenceFrame::World, J);
  if (rf == ReferenceFrame::World) return J;
  const Eigen::Isometry3d pose = link_world_pose(s, q, link);
  for (int c = 0; c < s.nv(); ++c) {
    const Eigen::Vector3d w = J.block<3, 1>(3, c);
    J.block<3, 1>(0, c) += w.cross(pose.translation());
  }
  if (rf == ReferenceFrame::LocalWorldAligned) return J;
  const Eigen::Matrix3d Rt = pose.linear().transpose();
  J.topRows<3>() = (Rt * J.topRows<3>()).eval();
  J.bottomRows<3>() = (Rt * J.bottomRows<3>()).eval();
  return J;
}

std::vector<std::string> jacobian_header(const KinRobot& s) {
  std::vector<std::string> h;
  for (const char* r : kJacobianRows)
    for (const auto& c : s.v_names) h.push_back(std::string("J:") + r + ":" + c);
  return h;
}

std::vector<std::string> com_header(const KinRobot& s) {
  std::vector<std::string> h = {"com:x", "com:y", "com:z"};
  for (const char* r : {"x", "y", "z"})
    for (const auto& c : s.v_names) h.push_back(std::string("Jcom:") + r + ":" + c);
  return h;
}

/// A moving link whose body frame is not the link's frame (a joint about −x, −y or −z: the body is turned by π).
std::string turned_link(const KinRobot& s) {
  for (const uio::LinkInfo& l : s.loaded.links)
    if (l.moving && !l.X.E.isIdentity(0.0)) return l.name;
  return "";
}

class CliKinematics : public ::testing::TestWithParam<Kind> {};

TEST_P(CliKinematics, JacobianMatchesTheLibrary) {
  const KinRobot s = make_robot(GetParam());
  ScratchDir dir("cli_kinematics");
  const States st = random_configurations(s, 4, s.floating ? 11u : 12u);
  st.csv.write(dir.file("q.csv"));
  const std::string turned = turned_link(s);
  // H_PAN_H_TILT_joint turns about −z, H_TILT_H_ROLL_joint about −x (the first is locked in the floating set-up);
  // at the right sole the first is a reversed leg joint.
  ASSERT_EQ(turned, GetParam() == Kind::Fixed ? "H_TILT" : GetParam() == Kind::Floating ? "H_ROLL" : "R_AFE");
  // A moving link turned by π, a plain moving link, links merged into a body (the sole, the hand; with the head's
  // pan and tilt locked, H_TILT), and the base link (on the fixed base: zero; floating: the free-flyer's columns).
  std::vector<std::string> links = {turned, "R_KN", "R_SOLE", "L_SOLE", "L_HAND", "base_link"};
  if (s.floating) links.push_back("H_TILT");
  for (const std::string& link : links) {
    for (const std::string ref : {"local", "world", "local_world_aligned"}) {
      SCOPED_TRACE(link + " " + ref);
      const std::string out = dir.file("J_" + link + "_" + ref + ".csv");
      std::vector<std::string> args = {"jacobian"};
      args.insert(args.end(), s.model_args.begin(), s.model_args.end());
      args.insert(args.end(), {"--frame", link, "--reference", ref, "--in", dir.file("q.csv"), "--out", out});
      const RunResult r = dyn(args);
      ASSERT_EQ(r.status, 0) << r.err;
      const Csv csv = parse_csv(slurp(out));
      ASSERT_EQ(csv.header, jacobian_header(s));
      ASSERT_EQ(csv.rows.size(), st.q.size());
      for (std::size_t row = 0; row < st.q.size(); ++row) {
        const Eigen::MatrixXd ref_J = reference_jacobian(s, st.q[row], link, reference_of(ref));
        double err = 0;
        for (int i = 0; i < 6; ++i)
          for (int c = 0; c < s.nv(); ++c)
            err = std::max(err, std::abs(csv.number(row, csv.header[std::size_t(i * s.nv() + c)]) - ref_J(i, c)));
        EXPECT_LE(err, 1e-12) << "row " << row;
      }
    }
  }
  // The example names of the README, and the default reference (local_world_aligned), on stdout.
  const Csv lwa = parse_csv(slurp(dir.file("J_R_SOLE_local_world_aligned.csv")));
  EXPECT_GE(lwa.column("J:vz:R_LFE_R_KN_joint"), 0);
  EXPECT_EQ(lwa.column("J:wx:floating_base:vy") >= 0, s.floating);
  std::vector<std::string> args = {"jacobian"};
  args.insert(args.end(), s.model_args.begin(), s.model_args.end());
  args.insert(args.end(), {"--frame", "R_SOLE", "--in", dir.file("q.csv")});
  const RunResult def = dyn(args);
  ASSERT_EQ(def.status, 0) << def.err;
  EXPECT_EQ(def.out, slurp(dir.file("J_R_SOLE_local_world_aligned.csv")));
  // --echo: the input's columns first.
  args.push_back("--echo");
  const RunResult echo = dyn(args);
  ASSERT_EQ(echo.status, 0) << echo.err;
  const Csv e = parse_csv(echo.out);
  ASSERT_EQ(e.header.size(), st.csv.header.size() + std::size_t(6 * s.nv()));
  EXPECT_EQ(e.header[0], "time");
  EXPECT_EQ(e.rows[1][0], st.csv.rows[1][0]);
  EXPECT_EQ(e.number(2, "J:vx:" + s.v_names[0]), lwa.number(2, "J:vx:" + s.v_names[0]));
}

TEST_P(CliKinematics, CenterOfMassAndItsJacobianMatchTheLibrary) {
  const KinRobot s = make_robot(GetParam());
  ScratchDir dir("cli_com");
  const States st = random_configurations(s, 5, s.floating ? 21u : 22u);
  st.csv.write(dir.file("q.csv"));
  std::vector<std::string> args = {"com"};
  args.insert(args.end(), s.model_args.begin(), s.model_args.end());
  args.insert(args.end(), {"--in", dir.file("q.csv"), "--out", dir.file("com.csv")});
  const RunResult r = dyn(args);
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv csv = parse_csv(slurp(dir.file("com.csv")));
  ASSERT_EQ(csv.header, com_header(s));
  ASSERT_EQ(csv.rows.size(), st.q.size());
  const Model<double>& model = s.loaded.model;
  const FloatingModel<double> fmodel = s.floating ? uio::floating_model(s.loaded)
                                                  : FloatingModel<double>(model, Inertia<double>::Zero());
  Data<double> d(model);
  FloatingData<double> fd(fmodel);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(s.nv());
  for (std::size_t row = 0; row < st.q.size(); ++row) {
    const Eigen::VectorXd& q = st.q[row];
    const Eigen::Vector3d c = s.floating ? center_of_mass(fmodel, fd, q, zero) : center_of_mass(model, d, q, zero);
    Eigen::MatrixXd Jc = Eigen::MatrixXd::Constant(3, s.nv(), 7.0);
    if (s.floating) com_jacobian(fmodel, fd, q, Jc);
    else com_jacobian(model, d, q, Jc);
    const char* xyz[] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(std::abs(csv.number(row, std::string("com:") + xyz[k]) - c[k]), 1e-12) << row << " " << k;
      for (int j = 0; j < s.nv(); ++j)
        EXPECT_LE(std::abs(csv.number(row, std::string("Jcom:") + xyz[k] + ":" + s.v_names[std::size_t(j)]) - Jc(k, j)),
                  1e-12)
            << row << " " << k << " " << j;
    }
  }
  if (s.floating) {
    // World coordinates: the free-flyer's linear columns are the root's rotation.
    const Eigen::Matrix3d R = Eigen::Quaterniond(st.q[0][6], st.q[0][3], st.q[0][4], st.q[0][5]).toRotationMatrix();
    EXPECT_NEAR(csv.number(0, "Jcom:x:floating_base:vy"), R(0, 1), 1e-15);
  }
}

INSTANTIATE_TEST_SUITE_P(Hoap3, CliKinematics, ::testing::Values(Kind::Fixed, Kind::Floating, Kind::RightSole),
                         [](const ::testing::TestParamInfo<Kind>& i) {
                           return i.param == Kind::Fixed      ? "Fixed"
                                  : i.param == Kind::Floating ? "Floating"
                                                              : "RightSole";
                         });

/// Status, and one line on stderr that contains every piece.
void expect_error(const RunResult& r, int status, const std::vector<std::string>& pieces) {
  EXPECT_EQ(r.status, status) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.rfind("spatial-dyn: ", 0), 0u) << r.err;
  for (const auto& p : pieces) EXPECT_NE(r.err.find(p), std::string::npos) << "'" << p << "' not in: " << r.err;
}

TEST(CliKinematicsErrors, NamesTheProblem) {
  const KinRobot s = make_robot(Kind::Fixed);
  ScratchDir dir("cli_kinematics_errors");
  States st = random_configurations(s, 2, 31u);
  st.csv.write(dir.file("q.csv"));
  const std::string urdf = urdf_path("hoap3.urdf"), in = dir.file("q.csv");
  // Unknown frame (status 1 like the model's other errors): named, with some of the links that exist.
  expect_error(dyn({"jacobian", "--urdf", urdf, "--frame", "R_TOE", "--in", in}), 1,
               {"--frame", "'R_TOE'", "base_link", "WAIST", "spatial-dyn info"});
  // A joint's name is not a link's.
  expect_error(dyn({"jacobian", "--urdf", urdf, "--frame", "R_LFE_R_KN_joint", "--in", in}), 1,
               {"'R_LFE_R_KN_joint'", "is a joint"});
  // A link outside --subtree.
  expect_error(dyn({"jacobian", "--urdf", urdf, "--subtree", "R_LR", "--frame", "L_SOLE", "--in", in}), 1,
               {"'L_SOLE'", "--subtree R_LR"});
  // Bad or missing options (status 2).
  expect_error(dyn({"jacobian", "--urdf", urdf, "--frame", "R_SOLE", "--reference", "body", "--in", in}), 2,
               {"--reference", "'body'", "local_world_aligned"});
  expect_error(dyn({"jacobian", "--urdf", urdf, "--in", in}), 2, {"--frame is required"});
  expect_error(dyn({"com", "--urdf", urdf, "--frame", "R_SOLE", "--in", in}), 2, {"unknown argument '--frame'"});
  expect_error(dyn({"id", "--urdf", urdf, "--reference", "world", "--in", in}), 2, {"unknown argument '--reference'"});
  expect_error(dyn({"com", "--urdf", urdf, "--in", in, "--method", "aba"}), 2, {"--method"});
  // A missing q: column, named.
  Csv c = st.csv;
  const int k = c.column("q:R_LFE_R_KN_joint");
  ASSERT_GE(k, 0);
  c.header[std::size_t(k)] = "knee";
  c.write(dir.file("no_knee.csv"));
  expect_error(dyn({"jacobian", "--urdf", urdf, "--frame", "R_SOLE", "--in", dir.file("no_knee.csv")}), 1,
               {"missing column 'q:R_LFE_R_KN_joint'", "jacobian needs q:"});
  expect_error(dyn({"com", "--urdf", urdf, "--in", dir.file("no_knee.csv")}), 1,
               {"missing column 'q:R_LFE_R_KN_joint'", "com needs q:"});
  // Floating: the free-flyer's q: columns are needed too.
  const KinRobot f = make_robot(Kind::Floating);
  States fs = random_configurations(f, 1, 32u);
  const int w = fs.csv.column("q:floating_base:qw");
  ASSERT_GE(w, 0);
  fs.csv.header[std::size_t(w)] = "qw";
  fs.csv.write(dir.file("no_qw.csv"));
  std::vector<std::string> args = {"jacobian"};
  args.insert(args.end(), f.model_args.begin(), f.model_args.end());
  args.insert(args.end(), {"--frame", "R_SOLE", "--in", dir.file("no_qw.csv")});
  expect_error(dyn(args), 1, {"missing column 'q:floating_base:qw'", "free-flyer"});
  // The usage text lists both subcommands.
  const RunResult help = dyn({"--help"});
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("spatial-dyn jacobian"), std::string::npos);
  EXPECT_NE(help.out.find("spatial-dyn com"), std::string::npos);
  EXPECT_NE(help.out.find("local_world_aligned (default)"), std::string::npos);
}

#endif  // SPATIAL_DYN_EXE

}  // namespace
