// spatial-dyn: inverse dynamics, forward dynamics, joint-space inertia, frame Jacobians and the centre of mass of a
// URDF robot on CSV files of states.
//
//   spatial-dyn id   --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo]
//   spatial-dyn fd   --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo] [--method aba|crba]
//   spatial-dyn crba --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo]
//   spatial-dyn jacobian --urdf FILE [MODEL OPTIONS] --frame LINK [--reference local|world|local_world_aligned]
//                        --in STATES.csv [--out OUT.csv] [--echo]
//   spatial-dyn com  --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo]
//   spatial-dyn derivatives id|fd --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo]
//   spatial-dyn zmp  --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo]
//   spatial-dyn info --urdf FILE [MODEL OPTIONS]
//   spatial-dyn scene NAME|all [--out DIR]      the reference study's experiments (tools/scenes.hpp)
//   spatial-dyn walk [--steps N ... --out DIR]  the HOAP-3's closed-loop walk (tools/walk_run.hpp)
//   MODEL OPTIONS: --root LINK  --subtree LINK  --lock JOINT=ANGLE,...  --gravity gx,gy,gz  --gravity-frame root|urdf
//                  --floating (the root link flies free: free-flyer columns floating_base:x … qw, :vx … wz)
//                  --strict-inertia
//
// CSV rules (also in README.md, "Command-line tool"):
//  - The first line is the header. Columns are named `q:<joint>`, `qd:<joint>`, `qdd:<joint>`, `tau:<joint>` with
//    the URDF joint names, in any order; every later non-empty line is one sample. Plain comma-separated values:
//    fields are trimmed, a header name in double quotes is unquoted, there is no other quoting. Blank lines are
//    skipped.
//  - id (and derivatives id, zmp) needs q, qd, qdd of every joint of the model; fd (and derivatives fd) needs q, qd, tau; crba, jacobian and com need q. Columns of
//    the four kinds that the subcommand does not use are not read (but their joint names are checked).
//  - A q:/qd:/qdd:/tau: column naming a joint that the URDF does not have is an error. Columns of URDF joints that
//    the model does not move (fixed, --lock'ed, or outside the --subtree) are ignored, with a note on stderr: a
//    whole-body trajectory can be fed to a model with locked joints; the lock positions come from --lock only.
//  - Columns with any other name (`time`, ...) are ignored, or copied to the output with --echo.
//  - Output: a header and one line per sample, `tau:<joint>` (id), `qdd:<joint>` (fd), `H:<jointA>:<jointB>`
//    row-major (crba), `J:<row>:<joint>` row-major with rows vx vy vz wx wy wz (jacobian), `com:x|y|z` then
//    `Jcom:<x|y|z>:<joint>` (com), `dtau_dq:<row>:<column>` then `dtau_dv:…` (derivatives id) or `dqdd_dq:…`,
//    `dqdd_dv:…`, `dqdd_dtau:…` (derivatives fd), `F:x F:y F:z M:x M:y M:z zmp:x zmp:y` (zmp), row-major, rows and columns named like the qd: columns; joints (velocity coordinates, the free-flyer's first) in model order
//    (`spatial-dyn info`), numbers with up to 17 significant digits (the shortest text that reads back as the same
//    double). --echo puts the input's columns first (except those that the output recomputes). --out - or no
//    --out: stdout. Nothing is written unless every sample is good.
//  - Errors: exit status 1 (bad input, model or file) or 2 (bad command line), and one line on stderr naming the
//    file, line, row and column at fault.
//  - Warnings: link inertias breaking the triangle inequality are loaded, with one line per link on stderr,
//    "spatial-dyn: warning: FILE: link 'x': ..."; --strict-inertia refuses them (exit status 1).
//
// zmp (zmp.hpp): the resultant force F and moment M (about the root frame's origin, root frame's axes) that the
// ground must apply to the robot for the motion, the joints supplying their torques (the base wrench of RNEA: a fixed
// base's reaction on the bodies hanging from it, the base's own weight excluded; with --floating the free-flyer's
// wrench τ[0:6]), and the ZMP on the root frame's z = 0 plane, ((−M_y) / F_z, M_x / F_z); `nan` when F_z ≤ 0 (no
// ZMP). For a model rooted at a stance sole (--root R_SOLE) that plane is the ground.
//
// jacobian and com (kinematics.hpp, centroidal.hpp):
//  - --frame names any URDF link the model keeps: a moving link (a body) or a link merged into one (a fixed frame,
//    fixed or --lock'ed joint; links merged into the base hang from the base, i.e. the free-flyer with --floating).
//    The Jacobian is that of the link's own frame (its URDF axes and origin), which may differ from the body frame
//    (reversed joints, axes turned by π for −x/−y/−z joints): the link is added to the model as a FixedFrame.
//  - --reference: local_world_aligned (the default: world axes, velocity of the frame's origin, as KDL's
//    Jacobians), world (world axes, velocity of the body-fixed point at the world origin: Pinocchio's WORLD, its
//    default) or local (the frame's axes and origin). "World" is the base frame for a fixed base.
//  - com: the centre of mass and its Jacobian, over every body and in world coordinates with --floating; for a
//    fixed base over the moving bodies only (the links merged into the base move nothing) in base coordinates
//    (center_of_mass / com_jacobian's conventions). `spatial-dyn info`'s com also counts the base's links.

#include "cli_common.hpp"
#include "scene_run.hpp"
#include "walk_run.hpp"

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace {

using namespace spatial;
namespace uio = spatial::urdf_io;
using cli::InputError;
using cli::UsageError;

const char* kUsage =
    "usage: spatial-dyn id   --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo]\n"
    "       spatial-dyn fd   --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo] [--method aba|crba]\n"
    "       spatial-dyn crba --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo]\n"
    "       spatial-dyn jacobian --urdf FILE [MODEL OPTIONS] --frame LINK\n"
    "                        [--reference local_world_aligned|world|local] --in STATES.csv [--out OUT.csv] [--echo]\n"
    "       spatial-dyn com  --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo]\n"
    "       spatial-dyn derivatives id|fd --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo]\n"
    "       spatial-dyn zmp  --urdf FILE [MODEL OPTIONS] --in STATES.csv [--out OUT.csv] [--echo]\n"
    "       spatial-dyn info --urdf FILE [MODEL OPTIONS]\n"
    "       spatial-dyn scene NAME|all [--out DIR]\n"
    "       spatial-dyn walk [--steps N --length M --width M --period S --double-support F --turn RAD\n"
    "                        --second-stage N --com-height M --zmp-model multibody|double-pendulum --out DIR]\n"
    "MODEL OPTIONS: --root LINK  --subtree LINK  --lock JOINT=ANGLE,...  --gravity gx,gy,gz  --gravity-frame root|urdf\n"
    "               --floating  --strict-inertia\n"
    "\n"
    "  id    inverse dynamics (RNEA): columns q:<joint>, qd:<joint>, qdd:<joint> -> tau:<joint>\n"
    "  fd    forward dynamics (ABA, or CRBA + LTDL with --method crba): q:, qd:, tau: -> qdd:<joint>\n"
    "  crba  joint-space inertia matrix: q: -> H:<jointA>:<jointB>, row-major\n"
    "  jacobian  Jacobian of the frame of link LINK (any link of the model: moving, or merged into a body or the\n"
    "        base; the link's own frame): q: -> J:<row>:<joint>, row-major, rows vx vy vz wx wy wz (linear first),\n"
    "        one column per velocity coordinate (the qd: columns' names: J:vz:<joint>, J:wx:floating_base:vy).\n"
    "        --reference:\n"
    "          local_world_aligned (default)  world axes, velocity of the frame's origin (KDL's Jacobians)\n"
    "          world                          world axes, velocity of the body-fixed point at the world origin\n"
    "                                         (Pinocchio's WORLD, its default)\n"
    "          local                          the frame's own axes, velocity of its origin\n"
    "        (for a fixed base, world means the base frame)\n"
    "  com   centre of mass and its Jacobian: q: -> com:x, com:y, com:z, Jcom:<x|y|z>:<joint> (row-major); with\n"
    "        --floating over every body in world coordinates, with a fixed base over the moving bodies in base\n"
    "        coordinates (the links merged into the base move nothing; info's com counts them)\n"
    "  derivatives id  analytical derivatives of inverse dynamics: q:, qd:, qdd: -> dtau_dq:<row>:<column>, then\n"
    "        dtau_dv:<row>:<column> (row-major; rows = tau's coordinates, columns = the velocity coordinates, named\n"
    "        like the qd: columns; with --floating the free-flyer's q columns are in the tangent space, a body-frame\n"
    "        twist of the root, Pinocchio's convention)\n"
    "  derivatives fd  analytical derivatives of forward dynamics: q:, qd:, tau: -> dqdd_dq:<row>:<column>,\n"
    "        dqdd_dv:<row>:<column>, dqdd_dtau:<row>:<column> (= the inverse of H)\n"
    "  zmp   the ground's wrench and the ZMP: q:, qd:, qdd: -> F:x, F:y, F:z, M:x, M:y, M:z (the force and the moment\n"
    "        about the root frame's origin that the ground must apply, root axes; the base's reaction, or with\n"
    "        --floating the free-flyer's wrench) and zmp:x, zmp:y (on the root frame's z = 0 plane; nan when F:z <= 0)\n"
    "  info  joints in model order, limits, mass, centre of mass, massless joints, frames\n"
    "  scene the reference study's experiments on the HOAP-3 reference models (no URDF needed): torso_arms,\n"
    "        torso_strokes, circles, step, pendulum, or all; writes DIR/NAME.csv and DIR/NAME.json (default DIR:\n"
    "        build/report/scenes)\n"
    "  walk  the HOAP-3 walks (no URDF needed): a footstep plan (--steps 8, --length 0.05 m, --width 0.088 m,\n"
    "        --period 1 s, --double-support 0.2 of the period, --turn 0 rad per step), the two-stage ZMP preview\n"
    "        control (--second-stage 3 passes, 0: the first stage alone; --com-height 0.29 m; --zmp-model: the ZMP the\n"
    "        second stage feeds back, the full model's or the double inverted pendulum's) and the whole-body motion,\n"
    "        then the closed-loop simulation (1 ms, contacts at the plan's instants, feed-forward + joint PD). Writes\n"
    "        DIR/walk.csv (per 2 ms tick: q, qd, qdd, tau, contact wrenches, reference / cart-table / multibody ZMP,\n"
    "        CoP, CoM, pelvis), DIR/walk.json (margins, errors, torque ratios, timings) and the PNGs of\n"
    "        tools/plot_walk.py (run with $SPATIAL_PYTHON, default python3; needs matplotlib) (default DIR:\n"
    "        build/report/walk). Exit status 0 when the walk was simulated, whether or not the robot walked.\n"
    "\n"
    "CSV: a header row, one sample per line, columns in any order named by the URDF joint names; other columns are\n"
    "ignored (--echo copies them to the output); columns of joints the model does not move (fixed, locked, outside\n"
    "the subtree) are ignored. --in - reads stdin; --out - (default) writes stdout. Numbers are written with up to 17\n"
    "significant digits. Gravity defaults to (0, 0, -9.81) in the root link's frame (--gravity-frame urdf: in the\n"
    "URDF root link's frame). A link inertia whose principal moments break the triangle inequality (I1 + I2 < I3:\n"
    "impossible, but harmless to the algorithms; common in CAD exports) is loaded with a warning on stderr;\n"
    "--strict-inertia refuses the file instead. Exit status: 0 ok, 1 bad input, 2 bad command line.\n"
    "\n"
    "--floating: the root link flies free (free-flyer 'floating_base'; also implied by a URDF floating joint from a\n"
    "massless world link). Its columns: q:floating_base:x, :y, :z (root origin in the world), :qx, :qy, :qz, :qw\n"
    "(unit quaternion, root axes to world axes) and qd:/qdd:/tau:floating_base:vx, :vy, :vz, :wx, :wy, :wz (linear\n"
    "then angular velocity, acceleration or wrench, in root coordinates; Pinocchio's free-flyer convention). Gravity\n"
    "is then in world coordinates.\n";

enum class Command { Id, Fd, Crba, Jacobian, Com, DerivativesId, DerivativesFd, Zmp, Info };

// ---------------------------------------------------------------------------------------------------------------
// The model

struct Robot {
  uio::LoadedModel loaded;
  std::string urdf;
  std::set<std::string> urdf_joints;  // every <joint> of the file, moving or not
  bool floating = false;
  std::vector<std::string> q_names, v_names;  // configuration and velocity coordinates (column names less "q:" etc.)
  int nq() const { return static_cast<int>(q_names.size()); }
  int nv() const { return static_cast<int>(v_names.size()); }
};

/// The free-flyer's coordinate names, after "floating_base:".
const std::array<const char*, 7> kFreeFlyerQ = {"x", "y", "z", "qx", "qy", "qz", "qw"};
const std::array<const char*, 6> kFreeFlyerV = {"vx", "vy", "vz", "wx", "wy", "wz"};

Robot load_robot(const cli::Options& opts) {
  Robot r;
  r.urdf = opts.required("--urdf");
  const uio::LoadOptions load = cli::load_options(opts);
  r.loaded = uio::load_file(r.urdf, load);  // throws ModelError naming the file (and checks it can be read)
  cli::print_warnings(r.loaded, "spatial-dyn");
  std::ifstream in(r.urdf, std::ios::binary);
  const std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const std::string& name : uio::detail::joint_document_order(xml)) r.urdf_joints.insert(name);
  r.floating = r.loaded.floating;
  if (r.floating) {
    for (const char* c : kFreeFlyerQ) r.q_names.push_back(std::string(kFreeFlyerName) + ":" + c);
    for (const char* c : kFreeFlyerV) r.v_names.push_back(std::string(kFreeFlyerName) + ":" + c);
  }
  for (int i = 0; i < r.loaded.model.size(); ++i) {
    r.q_names.push_back(r.loaded.model.joint_name(i));
    r.v_names.push_back(r.loaded.model.joint_name(i));
  }
  return r;
}

/// --reference's value.
ReferenceFrame parse_reference(const std::string& text) {
  if (text == "local_world_aligned") return ReferenceFrame::LocalWorldAligned;
  if (text == "world") return ReferenceFrame::World;
  if (text == "local") return ReferenceFrame::Local;
  throw UsageError("--reference: expected 'local_world_aligned', 'world' or 'local', got '" + text + "'");
}

/// Index in the model's frames of the frame of URDF link `link`. A link merged into a body (fixed or locked joint,
/// or the base link) already is a frame of the model; a moving link is its body, whose frame may differ from the
/// link's (reversed joint, axis turned by π), so its frame ˡX_body is added to `robot`'s model as a FixedFrame.
/// Throws InputError naming the link and listing some of the model's links when there is none of that name.
int link_frame(Robot& robot, const std::string& link, const cli::Options& opts) {
  auto& frames = spatial::detail::ModelAccess::frames(robot.loaded.model);
  for (std::size_t k = 0; k < frames.size(); ++k)
    if (frames[k].name == link) return static_cast<int>(k);
  const int li = robot.loaded.link_index(link);
  if (li >= 0) {
    const uio::LinkInfo& info = robot.loaded.links[static_cast<std::size_t>(li)];
    frames.push_back({info.name, info.body, info.X});
    return static_cast<int>(frames.size()) - 1;
  }
  const auto& links = robot.loaded.links;
  std::string some;
  const std::size_t shown = std::min<std::size_t>(links.size(), 8);
  for (std::size_t k = 0; k < shown; ++k) some += (k ? ", " : "") + links[k].name;
  if (shown < links.size()) some += ", …";
  std::string why;
  if (robot.urdf_joints.count(link))
    why = "; '" + link + "' is a joint: name the link it moves";
  else if (opts.has("--subtree"))
    why = "; links outside --subtree " + *opts.get("--subtree") + " are not part of the model";
  throw InputError("--frame: the model of " + robot.urdf + " has no link or frame '" + link + "' (it has " +
                   std::to_string(links.size()) + " links: " + some + "; spatial-dyn info lists them)" + why);
}

// ---------------------------------------------------------------------------------------------------------------
// CSV input

struct Line {
  int number;  // 1-based line number in the file
  std::vector<std::string_view> fields;
};

struct Table {
  std::string source;  // file name, or "<stdin>"
  std::string text;    // owns the characters the fields point into
  Line header;
  std::vector<Line> rows;
};

Table read_table(const std::string& path) {
  Table t;
  if (path == "-") {
    t.source = "<stdin>";
    t.text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
  } else {
    t.source = path;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open the file for reading (no such file, or no permission)");
    t.text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (in.bad()) throw InputError(path + ": error while reading the file");
  }
  const std::string_view all(t.text);
  bool have_header = false;
  int number = 0;
  std::size_t start = 0;
  while (start < all.size()) {
    std::size_t end = all.find('\n', start);
    if (end == std::string_view::npos) end = all.size();
    const std::string_view line = all.substr(start, end - start);
    start = end + 1;
    ++number;
    if (cli::trim(line).empty()) continue;
    Line l{number, cli::split(line, ',')};
    for (auto& f : l.fields) f = cli::trim(f);
    if (!have_header) {
      t.header = std::move(l);
      have_header = true;
    } else {
      t.rows.push_back(std::move(l));
    }
  }
  if (!have_header) throw InputError(t.source + ": empty input (expected a header row naming the columns)");
  return t;
}

std::string where(const Table& t, const Line& l) {
  if (&l == &t.header) return t.source + " line " + std::to_string(l.number) + " (header)";
  const auto row = static_cast<std::size_t>(&l - t.rows.data()) + 1;
  return t.source + " line " + std::to_string(l.number) + " (row " + std::to_string(row) + ")";
}

std::string column_text(const std::string& name, std::size_t index) {
  return "column " + std::to_string(index + 1) + " '" + name + "'";
}

const std::array<std::string, 4> kKinds = {"q", "qd", "qdd", "tau"};

struct Columns {
  std::vector<std::string> names;                  // header, unquoted
  std::array<std::vector<int>, 4> of;              // per kind, per coordinate (q: nq, others: nv): column or -1
  std::vector<std::string> ignored_joints;         // URDF joints not in the model that had columns
};

/// Index of `name` in the coordinate list of `kind` (q: configuration, the others: velocity), or -1.
int coordinate_index(const Robot& robot, std::size_t kind, const std::string& name) {
  const auto& list = kind == 0 ? robot.q_names : robot.v_names;
  const auto it = std::find(list.begin(), list.end(), name);
  return it == list.end() ? -1 : static_cast<int>(it - list.begin());
}

Columns map_columns(const Table& t, const Robot& robot) {
  Columns c;
  for (std::size_t kind = 0; kind < c.of.size(); ++kind)
    c.of[kind].assign(static_cast<std::size_t>(kind == 0 ? robot.nq() : robot.nv()), -1);
  std::set<std::string> seen;
  for (std::size_t k = 0; k < t.header.fields.size(); ++k) {
    std::string name(t.header.fields[k]);
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = name.substr(1, name.size() - 2);
    c.names.push_back(name);
    if (name.empty()) continue;
    if (!seen.insert(name).second)
      throw InputError(where(t, t.header) + ", " + column_text(name, k) + ": duplicate column name");
    const std::size_t colon = name.find(':');
    if (colon == std::string::npos) continue;
    const std::string kind = name.substr(0, colon), joint = name.substr(colon + 1);
    const auto kit = std::find(kKinds.begin(), kKinds.end(), kind);
    if (kit == kKinds.end()) continue;  // some other column (H:..., x:..., ...): ignored
    const auto kind_index = static_cast<std::size_t>(kit - kKinds.begin());
    const int i = coordinate_index(robot, kind_index, joint);
    const std::string ff = std::string(kFreeFlyerName) + ":";
    if (i >= 0) {
      c.of[kind_index][static_cast<std::size_t>(i)] = static_cast<int>(k);
    } else if (joint.rfind(ff, 0) == 0) {
      if (!robot.floating)
        throw InputError(where(t, t.header) + ", " + column_text(name, k) +
                         ": the model has no free-flyer (load it with --floating)");
      std::string expected;
      for (const auto& e : kind_index == 0 ? robot.q_names : robot.v_names)
        if (e.rfind(ff, 0) == 0) expected += (expected.empty() ? "" : ", ") + kind + ":" + e;
      throw InputError(where(t, t.header) + ", " + column_text(name, k) + ": unknown free-flyer coordinate (" +
                       kind + ": columns of the free-flyer are " + expected + ")");
    } else if (robot.urdf_joints.count(joint)) {
      if (std::find(c.ignored_joints.begin(), c.ignored_joints.end(), joint) == c.ignored_joints.end())
        c.ignored_joints.push_back(joint);
    } else {
      throw InputError(where(t, t.header) + ", " + column_text(name, k) + ": unknown joint '" + joint + "' (" +
                       robot.urdf + " has no joint of that name)");
    }
  }
  return c;
}

void require(const Table& t, const Columns& c, const Robot& robot, const std::vector<int>& kinds,
             const std::string& command) {
  const Model<double>& model = robot.loaded.model;
  std::vector<std::string> missing;
  for (int kind : kinds) {
    const auto& names = kind == 0 ? robot.q_names : robot.v_names;
    for (std::size_t i = 0; i < names.size(); ++i)
      if (c.of[static_cast<std::size_t>(kind)][i] < 0)
        missing.push_back(kKinds[static_cast<std::size_t>(kind)] + ":" + names[i]);
  }
  if (missing.empty()) return;
  std::string needs;
  for (int kind : kinds) needs += (needs.empty() ? "" : ", ") + kKinds[static_cast<std::size_t>(kind)] + ":";
  throw InputError(where(t, t.header) + ": missing column '" + missing.front() + "'" +
                   (missing.size() > 1 ? " (and " + std::to_string(missing.size() - 1) + " more)" : "") + "; " +
                   command + " needs " + needs + " columns for each of the " + std::to_string(model.size()) +
                   " joints of the model" + (robot.floating ? " and the free-flyer floating_base" : "") +
                   " (spatial-dyn info lists them)");
}

double cell(const Table& t, const Line& l, const Columns& c, int k) {
  const auto col = static_cast<std::size_t>(k);
  const std::string_view text = l.fields[col];
  const auto x = cli::parse_double(text);
  if (!x) {
    const std::string what = text.empty() ? std::string("empty cell") : "'" + std::string(text) + "'";
    throw InputError(where(t, l) + ", " + column_text(c.names[col], col) + ": " + what + " is not a finite number");
  }
  return *x;
}

void check_width(const Table& t, const Line& l, const Columns& c) {
  const std::size_t want = c.names.size(), got = l.fields.size();
  if (got == want) return;
  if (got < want)
    throw InputError(where(t, l) + ", " + column_text(c.names[got], got) + ": missing (the row has " +
                     std::to_string(got) + " fields, the header " + std::to_string(want) + ")");
  throw InputError(where(t, l) + ", column " + std::to_string(want + 1) + ": extra field (the row has " +
                   std::to_string(got) + " fields, the header " + std::to_string(want) + ")");
}

// ---------------------------------------------------------------------------------------------------------------
// Subcommands

std::string output_path(const cli::Options& opts) { return opts.get("--out").value_or("-"); }

void write_output(const std::string& path, const std::string& text) {
  if (path == "-") {
    std::cout << text;
    std::cout.flush();
    if (!std::cout) throw InputError("error writing to stdout");
    return;
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError(path + ": cannot open the file for writing");
  out << text;
  out.close();
  if (!out) throw InputError(path + ": error while writing the file");
}

std::string command_name(Command cmd) {
  switch (cmd) {
    case Command::Id: return "id";
    case Command::Fd: return "fd";
    case Command::Crba: return "crba";
    case Command::Jacobian: return "jacobian";
    case Command::Com: return "com";
    case Command::DerivativesId: return "derivatives id";
    case Command::DerivativesFd: return "derivatives fd";
    case Command::Zmp: return "zmp";
    case Command::Info: break;
  }
  return "info";
}

/// Rows of the jacobian's and com's outputs.
const std::array<const char*, 6> kJacobianRows = {"vx", "vy", "vz", "wx", "wy", "wz"};
const std::array<const char*, 3> kComRows = {"x", "y", "z"};

int run_dynamics(Command cmd, const cli::Options& opts) {
  Robot robot = load_robot(opts);
  const std::string name = command_name(cmd);
  // jacobian: the frame (added to the model if it is a moving link) and the reference frame, before the model is
  // used.
  int frame = -1;
  ReferenceFrame reference = ReferenceFrame::LocalWorldAligned;
  if (cmd == Command::Jacobian) {
    if (auto r = opts.get("--reference")) reference = parse_reference(*r);
    frame = link_frame(robot, opts.required("--frame"), opts);
  }
  const Model<double>& model = robot.loaded.model;
  const int n = model.size();

  std::string method = "aba";
  if (auto m = opts.get("--method")) {
    if (cmd != Command::Fd) throw UsageError("--method is an option of fd only");
    if (*m != "aba" && *m != "crba") throw UsageError("--method: expected 'aba' or 'crba', got '" + *m + "'");
    method = *m;
  }
  const bool derivatives = cmd == Command::DerivativesId || cmd == Command::DerivativesFd;
  const bool inverse = cmd == Command::Id || cmd == Command::DerivativesId || cmd == Command::Zmp;
  const bool forward = cmd == Command::Fd || cmd == Command::DerivativesFd;
  if (forward) {
    try {
      uio::check_nonsingular(robot.loaded);
    } catch (const ModelError& e) {
      std::string lock;
      for (int i : model.massless_joints()) lock += (lock.empty() ? "" : ",") + model.joint_name(i) + "=0";
      throw InputError(std::string(e.what()) + "; on the command line: --lock " + lock);
    }
  }
  if (cmd == Command::Com) {
    const double mass = model.total_mass() + (robot.floating ? robot.loaded.base_inertia.m : 0.0);
    if (!(mass > 0))
      throw InputError(robot.urdf + ": " + (robot.floating ? "the robot has" : "the moving bodies of the model have") +
                       " no mass, so the centre of mass is undefined");
  }

  const Table table = read_table(opts.required("--in"));
  const Columns cols = map_columns(table, robot);
  const std::vector<int> kinds = inverse ? std::vector<int>{0, 1, 2}
                                 : forward ? std::vector<int>{0, 1, 3}
                                           : std::vector<int>{0};
  require(table, cols, robot, kinds, "spatial-dyn " + name);
  if (!cols.ignored_joints.empty()) {
    std::string list;
    for (const auto& j : cols.ignored_joints) list += (list.empty() ? "" : ", ") + j;
    std::cerr << "spatial-dyn: note: ignoring the columns of joints that the model does not move: " << list << "\n";
  }

  // Output header.
  const int nq = robot.nq(), nv = robot.nv();
  std::vector<std::string> out_names;
  if (cmd == Command::Crba) {
    for (int i = 0; i < nv; ++i)
      for (int j = 0; j < nv; ++j)
        out_names.push_back("H:" + robot.v_names[std::size_t(i)] + ":" + robot.v_names[std::size_t(j)]);
  } else if (cmd == Command::Jacobian) {
    for (const char* r : kJacobianRows)
      for (int j = 0; j < nv; ++j) out_names.push_back(std::string("J:") + r + ":" + robot.v_names[std::size_t(j)]);
  } else if (cmd == Command::Com) {
    for (const char* r : kComRows) out_names.push_back(std::string("com:") + r);
    for (const char* r : kComRows)
      for (int j = 0; j < nv; ++j) out_names.push_back(std::string("Jcom:") + r + ":" + robot.v_names[std::size_t(j)]);
  } else if (cmd == Command::Zmp) {
    for (const char* c : {"F:x", "F:y", "F:z", "M:x", "M:y", "M:z", "zmp:x", "zmp:y"}) out_names.emplace_back(c);
  } else if (derivatives) {
    const std::vector<std::string> blocks = cmd == Command::DerivativesId
                                                ? std::vector<std::string>{"dtau_dq", "dtau_dv"}
                                                : std::vector<std::string>{"dqdd_dq", "dqdd_dv", "dqdd_dtau"};
    for (const std::string& b : blocks)
      for (int i = 0; i < nv; ++i)
        for (int j = 0; j < nv; ++j)
          out_names.push_back(b + ":" + robot.v_names[std::size_t(i)] + ":" + robot.v_names[std::size_t(j)]);
  } else {
    const std::string prefix = cmd == Command::Id ? "tau:" : "qdd:";
    for (int i = 0; i < nv; ++i) out_names.push_back(prefix + robot.v_names[std::size_t(i)]);
  }
  const bool echo = opts.has("--echo");
  std::vector<std::size_t> echoed;  // input columns copied to the output
  if (echo)
    for (std::size_t k = 0; k < cols.names.size(); ++k)
      if (std::find(out_names.begin(), out_names.end(), cols.names[k]) == out_names.end()) echoed.push_back(k);

  std::string out;
  {
    bool first = true;
    for (std::size_t k : echoed) {
      out += (first ? "" : ",") + std::string(table.header.fields[k]);
      first = false;
    }
    for (const auto& s : out_names) {
      out += (first ? "" : ",") + s;
      first = false;
    }
    out += '\n';
  }

  Data<double> data(model);
  const FloatingModel<double> fmodel =
      robot.floating ? uio::floating_model(robot.loaded) : FloatingModel<double>(model, Inertia<double>::Zero());
  FloatingData<double> fdata(fmodel);
  // Derivative buffers (nv × nv matrices), sized only for the derivatives subcommands.
  DerivativeData<double> dd(derivatives && !robot.floating ? model : Model<double>());
  FloatingDerivativeData<double> fdd(derivatives && robot.floating ? fmodel : FloatingModel<double>());
  Eigen::VectorXd q(nq), qd(nv), x(nv);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(nv);
  Eigen::MatrixXd J(cmd == Command::Com ? 3 : 6, nv);
  const auto& qc = cols.of[0];
  const auto& qdc = cols.of[1];
  const auto& xc = cols.of[forward ? 3 : 2];
  for (const Line& row : table.rows) {
    check_width(table, row, cols);
    for (int i = 0; i < nq; ++i) q[i] = cell(table, row, cols, qc[static_cast<std::size_t>(i)]);
    if (inverse || forward)
      for (int i = 0; i < nv; ++i) {
        const auto k = static_cast<std::size_t>(i);
        qd[i] = cell(table, row, cols, qdc[k]);
        x[i] = cell(table, row, cols, xc[k]);
      }
    if (robot.floating) {
      // The quaternion must be a rotation: within 1e-6 of unit length (rounding of a written file), then normalised.
      const double norm = q.segment<4>(3).norm();
      if (!(std::abs(norm - 1.0) <= 1e-6))
        throw InputError(where(table, row) + ", columns q:floating_base:qx … qw: the quaternion has length " +
                         cli::format_double(norm) + ", not 1 (it must be a unit quaternion)");
      q.segment<4>(3) /= norm;
    }
    bool first = true;
    for (std::size_t k : echoed) {
      out += (first ? "" : ",") + std::string(row.fields[k]);
      first = false;
    }
    auto put = [&](double v) {
      if (!first) out += ',';
      out += cli::format_double(v);
      first = false;
    };
    if (derivatives) {
      // Row-major blocks: ∂τ/∂q, ∂τ/∂v (id) or ∂q̈/∂q, ∂q̈/∂v, ∂q̈/∂τ (fd).
      const auto put_block = [&](const Eigen::MatrixXd& M) {
        for (int i = 0; i < nv; ++i)
          for (int j = 0; j < nv; ++j) put(M(i, j));
      };
      const auto write = [&](auto& m, auto& d, auto& derivs) {
        if (cmd == Command::DerivativesId) {
          rnea_derivatives(m, d, derivs, q, qd, x);
          put_block(derivs.dtau_dq);
          put_block(derivs.dtau_dv);
        } else {
          aba_derivatives(m, d, derivs, q, qd, x);
          put_block(derivs.dqdd_dq);
          put_block(derivs.dqdd_dv);
          put_block(derivs.dqdd_dtau);
        }
      };
      if (robot.floating) write(fmodel, fdata, fdd);
      else write(model, data, dd);
    } else if (cmd == Command::Zmp) {
      const Force<double> w = robot.floating ? base_wrench(fmodel, fdata, q, qd, x) : base_wrench(model, data, q, qd, x);
      const Eigen::Vector3d p = zmp_on_plane(w, 0.0);
      for (int r = 0; r < 3; ++r) put(w.f[r]);
      for (int r = 0; r < 3; ++r) put(w.n[r]);
      put(p.x());
      put(p.y());
    } else if (cmd == Command::Jacobian || cmd == Command::Com) {
      // J: linear rows first (vx vy vz wx wy wz), the velocity coordinates' columns; com: c then J_c.
      if (cmd == Command::Jacobian) {
        if (robot.floating) compute_frame_jacobian(fmodel, fdata, q, frame, reference, J);
        else compute_frame_jacobian(model, data, q, frame, reference, J);
      } else {
        const Eigen::Vector3d c = robot.floating ? center_of_mass(fmodel, fdata, q, zero)
                                                 : center_of_mass(model, data, q, zero);
        for (int r = 0; r < 3; ++r) put(c[r]);
        if (robot.floating) com_jacobian(fmodel, fdata, q, J);
        else com_jacobian(model, data, q, J);
      }
      for (int r = 0; r < J.rows(); ++r)
        for (int j = 0; j < nv; ++j) put(J(r, j));
    } else if (robot.floating) {
      if (cmd == Command::Id) {
        const auto& tau = rnea(fmodel, fdata, q, qd, x);
        for (int i = 0; i < nv; ++i) put(tau[i]);
      } else if (cmd == Command::Fd) {
        const auto& qdd =
            method == "aba" ? aba(fmodel, fdata, q, qd, x) : forward_dynamics_crba(fmodel, fdata, q, qd, x);
        for (int i = 0; i < nv; ++i) put(qdd[i]);
      } else {
        crba(fmodel, fdata, q);
        for (int i = 0; i < nv; ++i)
          for (int j = 0; j < nv; ++j) put(i >= j ? fdata.H(i, j) : fdata.H(j, i));
      }
    } else if (cmd == Command::Id) {
      const auto& tau = rnea(model, data, q, qd, x);
      for (int i = 0; i < n; ++i) put(tau[i]);
    } else if (cmd == Command::Fd) {
      const auto& qdd = method == "aba" ? aba(model, data, q, qd, x) : forward_dynamics_crba(model, data, q, qd, x);
      for (int i = 0; i < n; ++i) put(qdd[i]);
    } else {
      crba(model, data, q);
      // H is symmetric; read every entry from the lower triangle.
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) put(i >= j ? data.H(i, j) : data.H(j, i));
    }
    out += '\n';
  }
  write_output(output_path(opts), out);
  return 0;
}

std::string pad(std::string s, std::size_t width) {
  if (s.size() < width) s.append(width - s.size(), ' ');
  return s;
}

/// Numbers in `info` are for people: 12 significant digits (the CSV outputs keep every digit).
std::string human(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.12g", x);
  return buf;
}

std::string vec3(const Eigen::Vector3d& v) { return human(v.x()) + " " + human(v.y()) + " " + human(v.z()); }

int run_info(const cli::Options& opts) {
  const Robot robot = load_robot(opts);
  const uio::LoadedModel& m = robot.loaded;
  const Model<double>& model = m.model;
  const int n = model.size();
  std::ostringstream o;
  o << "urdf:      " << robot.urdf << "\n"
    << "root:      " << m.root
    << (robot.floating ? " (free-flying: free-flyer floating_base, nq = " + std::to_string(robot.nq()) +
                             ", nv = " + std::to_string(robot.nv()) + ")"
                       : std::string(" (the fixed base)"))
    << "\n"
    << "dof:       " << n << (robot.floating ? " joints + 6 (free-flyer)" : "") << "\n"
    << "gravity:   " << vec3(model.gravity()) << " m/s^2 (" << (robot.floating ? "world" : "base frame") << ")\n"
    << "locked:    ";
  if (m.locked.empty()) o << "none";
  for (std::size_t k = 0; k < m.locked.size(); ++k)
    o << (k ? ", " : "") << m.locked[k].first << "=" << human(m.locked[k].second);
  o << "\n";

  const std::vector<int> massless = model.massless_joints();
  std::size_t wj = 5, wl = 4;
  for (int i = 0; i < n; ++i) {
    wj = std::max(wj, model.joint_name(i).size());
    wl = std::max(wl, model.body_name(i).size());
  }
  o << "joints (model order; q, qd, qdd, tau follow it):\n"
    << "  " << pad("#", 4) << pad("joint", wj + 2) << pad("link", wl + 2) << pad("parent", 8) << pad("type", 15)
    << pad("lower", 12) << pad("upper", 12) << pad("effort", 10) << pad("velocity", 10) << "notes\n";
  for (int i = 0; i < n; ++i) {
    const uio::JointInfo& j = m.joints[static_cast<std::size_t>(i)];
    std::string notes;
    if (j.reversed) notes += "reversed";
    if (std::find(massless.begin(), massless.end(), i) != massless.end()) notes += notes.empty() ? "massless" : " massless";
    o << "  " << pad(std::to_string(i), 4) << pad(model.joint_name(i), wj + 2) << pad(model.body_name(i), wl + 2)
      << pad(std::to_string(model.parent(i)), 8) << pad(std::string(joint_type_name(model.joint_type(i))), 15)
      << pad(human(j.lower), 12) << pad(human(j.upper), 12)
      << pad(human(j.effort), 10) << pad(human(j.velocity), 10) << notes << "\n";
  }
  Data<double> data(model);
  const Eigen::Vector3d com = uio::whole_body_com(m, data, Eigen::VectorXd::Zero(n));
  o << "mass:      " << human(uio::whole_body_mass(m)) << " kg (moving bodies "
    << human(model.total_mass()) << " kg, fixed base " << human(model.base_mass())
    << " kg)\n"
    << "com:       " << (uio::whole_body_mass(m) > 0 ? vec3(com) + " m at q = 0 (whole body, base frame)" : "none (no mass)")
    << "\n"
    << "massless:  ";
  if (massless.empty()) {
    o << "none";
  } else {
    std::string lock;
    for (std::size_t k = 0; k < massless.size(); ++k) {
      o << (k ? ", " : "") << model.joint_name(massless[k]);
      lock += (k ? "," : "") + model.joint_name(massless[k]) + "=0";
    }
    o << " (they move no mass: H is singular and fd refuses the model; lock them, e.g. --lock " << lock << ")";
  }
  o << "\nframes:    ";
  const auto& frames = model.frames();
  for (std::size_t k = 0; k < frames.size(); ++k)
    o << (k ? ", " : "") << frames[k].name << " ("
      << (frames[k].body < 0 ? std::string("base") : model.body_name(frames[k].body)) << ")";
  o << "\n";
  std::cout << o.str();
  return 0;
}

int run_scenes(int argc, char** argv) {
  if (argc < 3 || std::string(argv[2]).rfind("--", 0) == 0)
    throw UsageError("scene needs a NAME (torso_arms, torso_strokes, circles, step, pendulum or all)");
  const std::string name = argv[2];
  const cli::Options opts(argc, argv, 3, {"--out"}, {});
  std::vector<std::string> names;
  if (name == "all") {
    names = scenes::scene_names();
  } else {
    const auto& all = scenes::scene_names();
    if (std::find(all.begin(), all.end(), name) == all.end())
      throw UsageError("unknown scene '" + name + "' (torso_arms, torso_strokes, circles, step, pendulum or all)");
    names = {name};
  }
  const std::string dir = opts.get("--out").value_or("build/report/scenes");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create the directory (" + ec.message() + ")");
  for (const std::string& n : names) {
    const scenes::SceneResult r = scenes::run_scene(n, dir);
    std::printf("%-14s %5d samples  max |tau|/rated %.3f  max |tau|/max %.3f  max |dqdd| crba %.2e aba %.2e  "
                "%.2f us per sample (RNEA + FD CRBA + ABA)\n",
                n.c_str(), r.samples, r.max_tau_over_rated, r.max_tau_over_max, r.max_qdd_diff_crba,
                r.max_qdd_diff_aba, r.sample_ns * 1e-3);
    if (n == "step" || n == "pendulum")
      std::printf("%-14s start F = (%.3f, %.3f, %.3f) N, static Fz %.3f N = m g %.3f N; ZMP %s the sole (min margin "
                  "%.1f mm)%s\n",
                  "", r.fx_start, r.fy_start, r.fz_start, r.static_fz, r.weight,
                  r.zmp_inside ? "inside" : "OUTSIDE", r.min_zmp_margin * 1e3,
                  n == "pendulum" ? (" ; pendulum start Fz " + std::to_string(r.pendulum_fz_start) + " N").c_str()
                                  : "");
  }
  for (const std::string& n : names) std::printf("wrote %s/%s.csv and %s.json\n", dir.c_str(), n.c_str(), n.c_str());
  return 0;
}

/// Whether --help or -h is among argv[first …].
bool asks_help(int argc, char** argv, int first) {
  for (int i = first; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") return true;
  return false;
}

/// `spatial-dyn walk`: the HOAP-3's closed-loop walk (walk_run.hpp).
int run_walk(int argc, char** argv) {
  const cli::Options opts(argc, argv, 2,
                          {"--steps", "--length", "--width", "--period", "--double-support", "--turn", "--second-stage",
                           "--com-height", "--zmp-model", "--out"},
                          {});
  walk_cli::WalkRequest req;
  const auto number = [&](const char* name, double& out) {
    if (const auto v = opts.get(name)) {
      const auto x = cli::parse_double(*v);
      if (!x) throw UsageError(std::string(name) + ": '" + *v + "' is not a number");
      out = *x;
    }
  };
  const auto integer = [&](const char* name, int& out) {
    double x = out;
    number(name, x);
    if (x != std::floor(x) || x < 0 || x > 1000)
      throw UsageError(std::string(name) + ": expected a whole number in [0, 1000], got " + cli::format_double(x));
    out = static_cast<int>(x);
  };
  integer("--steps", req.gait.steps);
  number("--length", req.gait.step_length);
  number("--width", req.gait.step_width);
  number("--period", req.gait.period);
  number("--double-support", req.gait.double_support_ratio);
  number("--turn", req.gait.turn);
  integer("--second-stage", req.second_stage);
  number("--com-height", req.com_height);
  if (opts.get("--com-height") && !(req.com_height > 0.0)) throw UsageError("--com-height: expected a height > 0 (m)");
  const std::string zmp_model = opts.get("--zmp-model").value_or("multibody");
  if (zmp_model != "multibody" && zmp_model != "double-pendulum")
    throw UsageError("--zmp-model: expected 'multibody' or 'double-pendulum', got '" + zmp_model + "'");
  req.double_pendulum = zmp_model == "double-pendulum";
  req.dir = opts.get("--out").value_or("build/report/walk");
  try {
    walk_cli::run_walk(req);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("walk: ") + e.what());
  }
  const int rc = walk_cli::plot_walk(req.dir, SPATIAL_PLOT_WALK);
  if (rc != 0) throw InputError("walk: tools/plot_walk.py failed (exit status " + std::to_string(rc) + ")");
  return 0;
}

int run(int argc, char** argv) {
  if (argc < 2)
    throw UsageError("no subcommand (id, fd, crba, jacobian, com, derivatives, zmp, info, scene or walk; try --help)");
  const std::string sub = argv[1];
  if (sub == "--help" || sub == "-h" || sub == "help") {
    std::cout << kUsage;
    return 0;
  }
  if (sub == "scene" || sub == "walk") {
    if (asks_help(argc, argv, 2)) {
      std::cout << kUsage;
      return 0;
    }
    return sub == "scene" ? run_scenes(argc, argv) : run_walk(argc, argv);
  }
  Command cmd;
  int first_option = 2;
  if (sub == "derivatives") {
    const std::string what = argc > 2 ? argv[2] : "";
    if (what == "--help" || what == "-h") {
      std::cout << kUsage;
      return 0;
    }
    if (what == "id") cmd = Command::DerivativesId;
    else if (what == "fd") cmd = Command::DerivativesFd;
    else if (what.empty()) throw UsageError("derivatives: say which dynamics to differentiate: 'derivatives id' or 'derivatives fd'");
    else throw UsageError("derivatives: expected 'id' or 'fd' after 'derivatives', got '" + what + "'");
    first_option = 3;
  } else if (sub == "id") cmd = Command::Id;
  else if (sub == "fd") cmd = Command::Fd;
  else if (sub == "crba") cmd = Command::Crba;
  else if (sub == "jacobian") cmd = Command::Jacobian;
  else if (sub == "com") cmd = Command::Com;
  else if (sub == "zmp") cmd = Command::Zmp;
  else if (sub == "info") cmd = Command::Info;
  else
    throw UsageError("unknown subcommand '" + sub +
                     "' (id, fd, crba, jacobian, com, derivatives, zmp, info, scene or walk; try --help)");
  if (asks_help(argc, argv, first_option)) {
    std::cout << kUsage;
    return 0;
  }
  std::vector<std::string> with_value = cli::model_option_names();
  std::vector<std::string> flags = cli::model_flag_names();
  if (cmd != Command::Info) {
    for (const char* s : {"--in", "--out", "--method"}) with_value.emplace_back(s);
    flags.emplace_back("--echo");
  }
  if (cmd == Command::Jacobian)
    for (const char* s : {"--frame", "--reference"}) with_value.emplace_back(s);
  const cli::Options opts(argc, argv, first_option, with_value, flags);
  if (cmd == Command::Info) return run_info(opts);
  opts.required("--urdf");
  if (cmd == Command::Jacobian) opts.required("--frame");
  opts.required("--in");
  return run_dynamics(cmd, opts);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const UsageError& e) {
    std::cerr << "spatial-dyn: " << cli::one_line(e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "spatial-dyn: " << cli::one_line(e.what()) << "\n";
    return 1;
  }
}
