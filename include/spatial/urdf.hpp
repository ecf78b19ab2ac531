#pragma once
/// \file urdf.hpp
/// Loading run-time models from URDF robot descriptions (through urdfdom, Debian's `liburdfdom-dev`).
///
/// ```cpp
/// #include <spatial/urdf.hpp>
/// using namespace spatial;
/// urdf_io::LoadOptions opt;
/// opt.root = "R_SOLE";                                          // single support on the right foot
/// opt.locked = {{"R_EB_R_WR_joint", 0.0}, {"L_EB_L_WR_joint", 0.0}};  // wrists move no mass: lock them
/// urdf_io::LoadedModel robot = urdf_io::load_file("urdf/hoap3.urdf", opt);
/// Data<double> data(robot.model);
/// rnea(robot.model, data, q, qd, qdd);                          // q, qd, qdd in robot.model's body order
/// ```
///
/// What the loader does, in order:
///  1. Parses the file with urdfdom. urdfdom returns null and prints to stderr on some errors, and on others
///     (a malformed `<inertial>`, for instance) only logs an error and drops the element. The loader captures
///     urdfdom's log while it parses, and any logged error rejects the file with urdfdom's own words.
///  2. Checks every number itself (NaN/Inf, negative mass, an inertia that is not positive semi-definite, a zero or
///     non-finite axis, inverted limits) and the graph (one root, no link with two parent joints, no loop). A link
///     inertia whose principal moments break the triangle inequality (I1 + I2 < I3: physically impossible, but the
///     spatial inertia stays positive semi-definite, so the algorithms are unaffected; common in CAD exports) is
///     loaded with a message in `LoadedModel::warnings`, or refused with `LoadOptions::strict_inertia`.
///  3. Roots the tree at `LoadOptions::root` (any link), keeps only the subtree below `LoadOptions::subtree` if
///     asked, and walks it depth first from the root, children in the order their joints appear in the file.
///     Joints walked against their URDF direction are *reversed* (`JointInfo::reversed`): the same q moves the
///     same two links relative to each other, with the axis negated.
///  4. Fixed joints and locked joints (`LoadOptions::locked`) are merged: the child link's inertia is added
///     exactly into the body it is rigidly attached to, and its frame is recorded as a `FixedFrame` of the model
///     (`Model::frames()`; links merged into the fixed base get body −1).
///  5. Builds a `Model<double>` with `ModelBuilder`: one body per moving joint, named after the link it moves,
///     with the joint's URDF name.
/// Any failure throws `spatial::ModelError` whose message starts with the file (or source) name and names the
/// link, joint or option at fault; nothing half-built is ever returned.
///
/// Conventions (see also README.md):
///  - URDF `<origin xyz rpy>` is the pose of the joint frame J in the parent link frame P: x_P = R x_J + xyz with
///    R = Rz(yaw) Ry(pitch) Rx(roll) (fixed-axis roll, pitch, yaw). Our transforms are passive, so the joint's
///    tree transform is ᴶX_P = (E = Rᵀ, r = xyz).
///  - The child link frame C coincides with J at q = 0; a revolute joint rotates C about the axis a (in J) by +q,
///    a prismatic joint translates it by a q. The axis is normalised.
///  - Body frames. For a joint walked in its URDF direction the body frame is the child link's frame. For a
///    reversed joint it is the joint frame J, which is fixed in the old parent link (the link that now moves).
///    With `LoadOptions::axis_aligned` (the default), a joint whose axis is a negative coordinate axis (−x, −y, −z,
///    which every reversed axis-aligned joint is) gets a body frame turned by π about another coordinate axis,
///    so that it becomes the fast `RevoluteX/Y/Z` or `PrismaticX/Y/Z` joint with the same q. The pose of every
///    link relative to its body is in `LoadedModel::links` (`link_pose` evaluates it).
///  - Gravity: (0, 0, −9.81) m/s² in the root link's frame unless `LoadOptions::gravity` says otherwise
///    (see `LoadOptions::gravity_frame`).
///
/// Threading: urdfdom logs through console_bridge's process-wide output handler, which the loader swaps for a
/// capturing one while it parses (under a mutex, so concurrent loads are safe; messages that other threads log
/// through console_bridge during those microseconds are captured too).

#include "spatial/spatial.hpp"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace spatial::urdf_io {

/// The frame in which `LoadOptions::gravity` (or the default (0, 0, −9.81)) is given.
enum class GravityFrame {
  Root,      ///< the frame of the link the model is rooted at (its base frame)
  UrdfRoot,  ///< the URDF's own root link frame, with every joint at 0 (locked joints at their lock angle); the
             ///< loader turns it into the model's root frame. Handy when rooting at a foot whose frame is tilted.
};

/// How to turn a URDF into a model. The defaults load the URDF as written.
struct LoadOptions {
  /// Link to root the tree at (it becomes the fixed base); empty: the URDF's root link.
  std::string root;
  /// Joints locked at the given position (rad or m): they become fixed and are merged into their parent body.
  std::vector<std::pair<std::string, double>> locked;
  /// Keep only this link and the links below it (with the tree rooted at `root`); this link becomes the base.
  /// Empty: keep everything.
  std::string subtree;
  /// Gravity in `gravity_frame`; default (0, 0, −9.81) m/s².
  std::optional<Eigen::Vector3d> gravity;
  GravityFrame gravity_frame = GravityFrame::Root;
  /// Turn body frames by π where needed so that joints about/along −x, −y, −z become the axis-aligned joint types
  /// (same q, same physics, fewer flops). false: keep the body frames and use RevoluteAxis/PrismaticAxis for them.
  bool axis_aligned = true;
  /// Make the base link (`root`, or `subtree` when given) free-flying: `LoadedModel::floating` is set and
  /// `floating_model(loaded)` gives the `FloatingModel` (free-flyer `floating_base` at the base link's frame, its
  /// inertia = `base_inertia`, gravity in world coordinates). A URDF whose root link is massless and attached to the
  /// rest by a single `floating` joint (the "world" link convention) is loaded floating from that joint's child
  /// whatever this option says.
  bool floating = false;
  /// Refuse (`ModelError`) link inertias whose principal moments break the triangle inequality, instead of loading
  /// them with a warning (`LoadedModel::warnings`). Inertias the algorithms cannot work with (negative mass, not
  /// positive semi-definite about the centre of mass, NaN/Inf, …) are refused either way.
  bool strict_inertia = false;
};

/// What the model keeps of a URDF joint that moves a body (one per body, model order).
struct JointInfo {
  std::string name;       ///< URDF joint name (= `Model::joint_name(i)`)
  std::string urdf_type;  ///< "revolute", "continuous" or "prismatic"
  double lower = -std::numeric_limits<double>::infinity();  ///< position limits (±inf when the URDF gives none)
  double upper = std::numeric_limits<double>::infinity();
  double effort = 0;      ///< URDF effort limit [N·m or N] (0 when absent; HOAP-3: 0 = unknown)
  double velocity = 0;    ///< URDF velocity limit [rad/s or m/s] (0 when absent; HOAP-3: 0 = unknown)
  bool has_limits = false;  ///< the URDF joint has a <limit> element
  bool reversed = false;  ///< walked against its URDF direction (the model was re-rooted across it)
};

/// Where a URDF link ended up: the body it is rigidly attached to and its frame relative to that body.
struct LinkInfo {
  std::string name;
  int body = -1;         ///< model body (−1: the fixed base)
  /// ˡX_body: from the body's coordinates to the link's (identity when the body frame is the link frame).
  Transform<double> X = Transform<double>::Identity();
  bool moving = false;   ///< the link is the one its body's joint moves (otherwise it was merged)
};

/// A loaded model and what it keeps of the URDF.
struct LoadedModel {
  Model<double> model;
  std::vector<JointInfo> joints;  ///< per body, in model order
  std::vector<LinkInfo> links;    ///< every link kept, in traversal order (the root link first)
  std::vector<std::pair<std::string, double>> locked;  ///< joints locked (and merged), as applied
  /// Inertia of the links merged into the fixed base (the root link and everything rigidly attached to it), in
  /// base coordinates. It moves nothing, but belongs to the robot's total mass and centre of mass.
  Inertia<double> base_inertia = Inertia<double>::Zero();
  std::string root;    ///< the link the model is rooted at
  std::string source;  ///< file name or the name given to `load_string`
  /// The base link is free-flying (`LoadOptions::floating`, or a URDF `floating` joint from a massless root link):
  /// use `floating_model(*this)`.
  bool floating = false;
  /// What was loaded although it is suspect (today: link inertias breaking the triangle inequality), one message
  /// per link of the file (also links outside `LoadOptions::subtree`: strict mode refuses those too) in link-name
  /// order, each starting like the errors with the source and naming the link, e.g.
  /// "robot.urdf: link 'foot': principal moments violate the triangle inequality: I1 + I2 = 0.02 < I3 = 0.03 kg m^2
  /// (short by 0.01, 33.3 %)". Empty for a clean file; never filled with `LoadOptions::strict_inertia`.
  std::vector<std::string> warnings;

  /// Index in `links` of the link with that name, or −1.
  int link_index(const std::string& name) const {
    for (std::size_t k = 0; k < links.size(); ++k)
      if (links[k].name == name) return static_cast<int>(k);
    return -1;
  }
  /// Model order of the joint with that URDF name, or −1.
  int joint_index(const std::string& name) const { return model.joint_index(name); }
};

namespace detail {

using Pose = Eigen::Isometry3d;  // active pose of a frame F in a frame A: x_A = R x_F + p

inline Pose identity_pose() { return Pose::Identity(); }

/// The passive transform ᶠX_A of a frame F whose pose in A is T.
inline Transform<double> passive(const Pose& T) {
  return Transform<double>(T.linear().transpose(), T.translation());
}

inline bool finite(double x) { return std::isfinite(x); }
inline bool finite(const urdf::Vector3& v) { return finite(v.x) && finite(v.y) && finite(v.z); }
inline bool finite(const urdf::Rotation& r) { return finite(r.x) && finite(r.y) && finite(r.z) && finite(r.w); }
inline bool finite(const urdf::Pose& p) { return finite(p.position) && finite(p.rotation); }

/// The pose of a urdfdom origin (the quaternion urdfdom computed from rpy, R = Rz(yaw) Ry(pitch) Rx(roll)).
inline Pose to_pose(const urdf::Pose& p) {
  Eigen::Quaterniond q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  q.normalize();
  Pose T = Pose::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return T;
}

struct LinkRec {
  std::string name;
  Inertia<double> inertia = Inertia<double>::Zero();  // in link coordinates
};

enum class Kind { Revolute, Continuous, Prismatic, Fixed, Floating, Planar, Unknown };

inline const char* kind_name(Kind k) {
  switch (k) {
    case Kind::Revolute: return "revolute";
    case Kind::Continuous: return "continuous";
    case Kind::Prismatic: return "prismatic";
    case Kind::Fixed: return "fixed";
    case Kind::Floating: return "floating";
    case Kind::Planar: return "planar";
    case Kind::Unknown: break;
  }
  return "unknown";
}

struct JointRec {
  std::string name;
  Kind kind = Kind::Unknown;
  int parent = -1, child = -1;  // link indices
  Pose origin = Pose::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // unit, in the joint frame
  JointInfo info;
  std::string mimic;  // joint it mimics, if any
};

/// Captures console_bridge (urdfdom) messages while alive; errors are kept, lower levels are passed on to the
/// handler that was installed before.
class CaptureLog : public console_bridge::OutputHandler {
 public:
  CaptureLog() : lock_(mutex()) {
    prev_handler_ = console_bridge::getOutputHandler();
    prev_level_ = console_bridge::getLogLevel();
    console_bridge::useOutputHandler(this);
    if (prev_level_ > console_bridge::CONSOLE_BRIDGE_LOG_ERROR)
      console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_ERROR);
  }
  ~CaptureLog() override {
    console_bridge::useOutputHandler(prev_handler_);
    console_bridge::setLogLevel(prev_level_);
  }
  CaptureLog(const CaptureLog&) = delete;
  CaptureLog& operator=(const CaptureLog&) = delete;

  void log(const std::string& text, console_bridge::LogLevel level, const char* file, int line) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) {
      errors_.push_back(text);
    } else if (prev_handler_ != nullptr && level >= prev_level_) {
      prev_handler_->log(text, level, file, line);
    }
  }
  const std::vector<std::string>& errors() const { return errors_; }

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  console_bridge::OutputHandler* prev_handler_ = nullptr;
  console_bridge::LogLevel prev_level_ = console_bridge::CONSOLE_BRIDGE_LOG_WARN;
  std::vector<std::string> errors_;
};

/// Names of the <joint> elements of the document, in document order (empty if the XML does not parse).
inline std::vector<std::string> joint_document_order(const std::string& xml) {
  std::vector<std::string> out;
  TiXmlDocument doc;
  doc.Parse(xml.c_str());
  if (doc.Error()) return out;
  const TiXmlElement* robot = doc.FirstChildElement("robot");
  if (robot == nullptr) return out;
  for (const TiXmlElement* j = robot->FirstChildElement("joint"); j != nullptr; j = j->NextSiblingElement("joint")) {
    const char* name = j->Attribute("name");
    if (name != nullptr) out.emplace_back(name);
  }
  return out;
}

[[noreturn]] inline void fail(const std::string& source, const std::string& what) {
  throw ModelError(source + ": " + what);
}

inline std::string quote(const std::string& s) { return "'" + s + "'"; }

inline std::string number(double x) {
  std::ostringstream os;
  os.precision(17);
  os << x;
  return os.str();
}

/// The rotation by π about the coordinate axis after k that turns −e_k into +e_k (exact entries).
inline Eigen::Matrix3d flip_matrix(int k) {
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  F(k, k) = -1.0;
  F((k + 1) % 3, (k + 1) % 3) = 1.0;
  F((k + 2) % 3, (k + 2) % 3) = -1.0;
  return F;
}

/// The child link's pose in the parent link at joint position q (URDF direction).
inline Pose joint_motion(const JointRec& j, double q) {
  Pose M = Pose::Identity();
  if (j.kind == Kind::Revolute || j.kind == Kind::Continuous) M.linear() = Eigen::AngleAxisd(q, j.axis).toRotationMatrix();
  else if (j.kind == Kind::Prismatic) M.translation() = j.axis * q;
  return M;
}

/// Everything read from urdfdom, checked.
struct Description {
  std::vector<LinkRec> links;
  std::vector<JointRec> joints;      // in document order (or name order)
  std::map<std::string, int> link_id, joint_id;
  std::vector<int> parent_joint;     // per link, −1 for the root
  std::vector<std::vector<int>> adjacent;  // per link, joints touching it, in joint order
  int root = -1;
  std::vector<std::string> warnings;  // "source: link 'x': …", in link order
};

/// `strict_inertia`: refuse link inertias that break the triangle inequality (otherwise: `warnings`).
inline Description describe(const urdf::ModelInterface& urdf, const std::vector<std::string>& order,
                            const std::string& source, bool strict_inertia = false) {
  Description d;
  // Links, in name order (urdfdom keeps them in a map).
  for (const auto& [name, link] : urdf.links_) {
    if (!link) fail(source, "link " + quote(name) + " is null in the parsed model");
    LinkRec rec;
    rec.name = name;
    if (link->inertial) {
      const urdf::Inertial& in = *link->inertial;
      const std::string what = "link " + quote(name) + ": ";
      if (!finite(in.mass) || !finite(in.origin) || !finite(in.ixx) || !finite(in.ixy) || !finite(in.ixz) ||
          !finite(in.iyy) || !finite(in.iyz) || !finite(in.izz))
        fail(source, what + "<inertial> contains NaN or Inf");
      if (in.mass < 0) fail(source, what + "negative mass (" + number(in.mass) + " kg)");
      Eigen::Matrix3d Ic;
      Ic << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      const Pose T = to_pose(in.origin);
      const Eigen::Matrix3d I_link = T.linear() * Ic * T.linear().transpose();
      rec.inertia = Inertia<double>::from_com(in.mass, T.translation(), I_link);
      // Check the inertia as given (about the CoM), then the one derived from it (overflow to Inf; its warning, if
      // any, is the same as the first one's).
      const spatial::detail::InertiaProblem com =
          spatial::detail::inertia_problem(Inertia<double>(in.mass, Eigen::Vector3d::Zero(), Ic));
      if (const std::string refused = com.refusal(strict_inertia); !refused.empty()) fail(source, what + refused);
      const std::string bad = spatial::detail::inertia_problem(rec.inertia).error;
      if (!bad.empty()) fail(source, what + "inertia about the link origin: " + bad);
      if (!com.warning.empty()) d.warnings.push_back(source + ": " + what + com.warning);
    }
    d.link_id[name] = static_cast<int>(d.links.size());
    d.links.push_back(rec);
  }

  // Joints, in document order when known (then any the order missed, by name).
  std::vector<std::string> names;
  for (const std::string& n : order)
    if (urdf.joints_.count(n) && std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
  for (const auto& [name, joint] : urdf.joints_)
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);

  for (const std::string& name : names) {
    const urdf::JointSharedPtr& j = urdf.joints_.at(name);
    const std::string what = "joint " + quote(name) + ": ";
    if (!j) fail(source, what + "null in the parsed model");
    JointRec rec;
    rec.name = name;
    switch (j->type) {
      case urdf::Joint::REVOLUTE: rec.kind = Kind::Revolute; break;
      case urdf::Joint::CONTINUOUS: rec.kind = Kind::Continuous; break;
      case urdf::Joint::PRISMATIC: rec.kind = Kind::Prismatic; break;
      case urdf::Joint::FIXED: rec.kind = Kind::Fixed; break;
      case urdf::Joint::FLOATING: rec.kind = Kind::Floating; break;
      case urdf::Joint::PLANAR: rec.kind = Kind::Planar; break;
      default: rec.kind = Kind::Unknown; break;
    }
    const auto p = d.link_id.find(j->parent_link_name);
    const auto c = d.link_id.find(j->child_link_name);
    if (p == d.link_id.end()) fail(source, what + "parent link " + quote(j->parent_link_name) + " does not exist");
    if (c == d.link_id.end()) fail(source, what + "child link " + quote(j->child_link_name) + " does not exist");
    rec.parent = p->second;
    rec.child = c->second;
    if (rec.parent == rec.child) fail(source, what + "connects link " + quote(j->child_link_name) + " to itself");
    if (!finite(j->parent_to_joint_origin_transform)) fail(source, what + "<origin> contains NaN or Inf");
    rec.origin = to_pose(j->parent_to_joint_origin_transform);
    const bool moves = rec.kind == Kind::Revolute || rec.kind == Kind::Continuous || rec.kind == Kind::Prismatic;
    if (moves) {
      if (!finite(j->axis)) fail(source, what + "<axis> contains NaN or Inf");
      const Eigen::Vector3d a(j->axis.x, j->axis.y, j->axis.z);
      if (!(a.norm() > 0)) fail(source, what + "the joint axis is zero");
      rec.axis = a.normalized();
    }
    rec.info.name = name;
    rec.info.urdf_type = kind_name(rec.kind);
    if (j->limits) {
      const urdf::JointLimits& l = *j->limits;
      if (!finite(l.lower) || !finite(l.upper) || !finite(l.effort) || !finite(l.velocity))
        fail(source, what + "<limit> contains NaN or Inf");
      if (l.effort < 0) fail(source, what + "negative effort limit");
      if (l.velocity < 0) fail(source, what + "negative velocity limit");
      rec.info.has_limits = true;
      rec.info.effort = l.effort;
      rec.info.velocity = l.velocity;
      if (rec.kind == Kind::Revolute || rec.kind == Kind::Prismatic) {
        if (l.lower > l.upper) fail(source, what + "lower limit is above the upper limit");
        rec.info.lower = l.lower;
        rec.info.upper = l.upper;
      }
    }
    if (j->mimic) rec.mimic = j->mimic->joint_name.empty() ? std::string("?") : j->mimic->joint_name;
    d.joint_id[name] = static_cast<int>(d.joints.size());
    d.joints.push_back(rec);
  }

  // Graph: one parent joint per link, one root, everything reachable from it (no loop).
  const std::size_t nl = d.links.size();
  if (nl == 0) fail(source, "the robot has no link");
  d.parent_joint.assign(nl, -1);
  d.adjacent.assign(nl, {});
  for (std::size_t k = 0; k < d.joints.size(); ++k) {
    const JointRec& j = d.joints[k];
    int& pj = d.parent_joint[static_cast<std::size_t>(j.child)];
    if (pj >= 0)
      fail(source, "link " + quote(d.links[static_cast<std::size_t>(j.child)].name) + " is the child of two joints, " +
                       quote(d.joints[static_cast<std::size_t>(pj)].name) + " and " + quote(j.name) +
                       " (a kinematic loop or a duplicated joint)");
    pj = static_cast<int>(k);
    d.adjacent[static_cast<std::size_t>(j.parent)].push_back(static_cast<int>(k));
    d.adjacent[static_cast<std::size_t>(j.child)].push_back(static_cast<int>(k));
  }
  std::vector<std::string> roots;
  for (std::size_t l = 0; l < nl; ++l)
    if (d.parent_joint[l] < 0) {
      roots.push_back(d.links[l].name);
      d.root = static_cast<int>(l);
    }
  if (roots.size() != 1) {
    std::string list;
    for (const std::string& r : roots) list += (list.empty() ? "" : ", ") + quote(r);
    fail(source, roots.empty() ? std::string("no root link (every link has a parent joint: a kinematic loop)")
                               : "several root links (" + list + "): the links do not form one tree");
  }
  // Reachability from the root, following joints in their URDF direction.
  std::vector<char> seen(nl, 0);
  std::vector<int> stack{d.root};
  seen[static_cast<std::size_t>(d.root)] = 1;
  while (!stack.empty()) {
    const int l = stack.back();
    stack.pop_back();
    for (int k : d.adjacent[static_cast<std::size_t>(l)]) {
      const JointRec& j = d.joints[static_cast<std::size_t>(k)];
      if (j.parent == l && !seen[static_cast<std::size_t>(j.child)]) {
        seen[static_cast<std::size_t>(j.child)] = 1;
        stack.push_back(j.child);
      }
    }
  }
  for (std::size_t l = 0; l < nl; ++l)
    if (!seen[l])
      fail(source, "link " + quote(d.links[l].name) + " is not connected to the root link " +
                       quote(d.links[static_cast<std::size_t>(d.root)].name) + " (the joints form a kinematic loop)");
  return d;
}

/// Builds the model from a checked description.
inline LoadedModel build(const Description& d, const LoadOptions& opt, const std::string& source) {
  const std::size_t nl = d.links.size();
  auto find_link = [&](const std::string& name, const char* option) {
    const auto it = d.link_id.find(name);
    if (it == d.link_id.end())
      fail(source, std::string(option) + ": unknown link " + quote(name) +
                       spatial::detail::did_you_mean(name, spatial::detail::keys_of(d.link_id)));
    return it->second;
  };
  const int root = opt.root.empty() ? d.root : find_link(opt.root, "root");

  // Locked joints.
  std::vector<std::optional<double>> lock(d.joints.size());
  for (const auto& [name, value] : opt.locked) {
    const auto it = d.joint_id.find(name);
    if (it == d.joint_id.end())
      fail(source, "locked: unknown joint " + quote(name) +
                       spatial::detail::did_you_mean(name, spatial::detail::keys_of(d.joint_id)));
    const JointRec& j = d.joints[static_cast<std::size_t>(it->second)];
    if (!std::isfinite(value))
      fail(source, "locked: joint " + quote(name) + " locked at a non-finite position (" + number(value) + ")");
    if (j.kind == Kind::Floating || j.kind == Kind::Planar || j.kind == Kind::Unknown)
      fail(source, "locked: joint " + quote(name) + " is of type " + kind_name(j.kind) + ", which is not supported");
    auto& slot = lock[static_cast<std::size_t>(it->second)];
    if (slot && *slot != value) fail(source, "locked: joint " + quote(name) + " locked twice at different positions");
    slot = value;
  }

  // The tree oriented from `root`: each link's neighbour towards the root.
  std::vector<int> towards_root(nl, -1);  // joint index
  std::vector<int> order;                  // links, parents first
  {
    std::vector<char> seen(nl, 0);
    std::vector<int> stack{root};
    seen[static_cast<std::size_t>(root)] = 1;
    while (!stack.empty()) {
      const int l = stack.back();
      stack.pop_back();
      order.push_back(l);
      for (int k : d.adjacent[static_cast<std::size_t>(l)]) {
        const JointRec& j = d.joints[static_cast<std::size_t>(k)];
        const int other = j.parent == l ? j.child : j.parent;
        if (seen[static_cast<std::size_t>(other)]) continue;
        seen[static_cast<std::size_t>(other)] = 1;
        towards_root[static_cast<std::size_t>(other)] = k;
        stack.push_back(other);
      }
    }
  }
  // Links kept: everything, or the subtree below `subtree`.
  std::vector<char> kept(nl, 1);
  int base = root;
  if (!opt.subtree.empty()) {
    base = find_link(opt.subtree, "subtree");
    std::fill(kept.begin(), kept.end(), 0);
    kept[static_cast<std::size_t>(base)] = 1;
    for (int l : order) {  // parents before children
      const int k = towards_root[static_cast<std::size_t>(l)];
      if (k < 0) continue;
      const JointRec& j = d.joints[static_cast<std::size_t>(k)];
      const int up = j.parent == l ? j.child : j.parent;
      if (kept[static_cast<std::size_t>(up)]) kept[static_cast<std::size_t>(l)] = 1;
    }
  }

  // A URDF `floating` joint from a massless root link (a "world" link) to the rest: free-flying from its child.
  bool floating = opt.floating;
  if (opt.root.empty() && opt.subtree.empty()) {
    const auto& adj = d.adjacent[static_cast<std::size_t>(base)];
    const LinkRec& world = d.links[static_cast<std::size_t>(base)];
    if (adj.size() == 1 && d.joints[static_cast<std::size_t>(adj[0])].kind == Kind::Floating) {
      const JointRec& j = d.joints[static_cast<std::size_t>(adj[0])];
      if (world.inertia.m != 0.0 || world.inertia.I.norm() != 0.0)
        fail(source, "joint " + quote(j.name) + " is of type floating but its parent link " + quote(world.name) +
                         " has mass: a floating joint is supported only from a massless root link (the world)");
      base = j.child;
      floating = true;
      std::fill(kept.begin(), kept.end(), 0);
      kept[static_cast<std::size_t>(base)] = 1;
      for (int l : order) {
        const int k = towards_root[static_cast<std::size_t>(l)];
        if (k < 0) continue;
        const JointRec& jk = d.joints[static_cast<std::size_t>(k)];
        const int up = jk.parent == l ? jk.child : jk.parent;
        if (kept[static_cast<std::size_t>(up)] && up != root) kept[static_cast<std::size_t>(l)] = 1;
      }
    }
  }

  // Gravity, in the base frame.
  Eigen::Vector3d g = opt.gravity ? *opt.gravity : Eigen::Vector3d(0, 0, -9.81);
  if (!g.allFinite()) fail(source, "gravity contains NaN or Inf");
  if (opt.gravity_frame == GravityFrame::UrdfRoot) {
    // Orientation of the base link in the URDF root frame at q = 0 (locked joints at their position).
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    for (int l = base; d.parent_joint[static_cast<std::size_t>(l)] >= 0;) {
      const auto k = static_cast<std::size_t>(d.parent_joint[static_cast<std::size_t>(l)]);
      const JointRec& j = d.joints[k];
      R = (j.origin * joint_motion(j, lock[k].value_or(0.0))).linear() * R;
      l = j.parent;
    }
    g = R.transpose() * g;
  }

  LoadedModel out;
  out.source = source;
  out.floating = floating;
  out.root = d.links[static_cast<std::size_t>(base)].name;
  out.warnings = d.warnings;
  ModelBuilder<double> builder;
  // The builder sees the same link inertias, moved into body frames: its warnings repeat those of `describe` and
  // are not copied (one warning per link).
  builder.set_strict_inertia(opt.strict_inertia);
  builder.set_gravity(g);

  // Depth-first walk from the base over the kept links, children in joint order.
  struct Placed {
    int body = -2;          // -2: not placed yet
    Pose T = Pose::Identity();  // the link's pose in its body frame
  };
  std::vector<Placed> placed(nl);
  std::vector<char> pushed(nl, 0);
  std::vector<std::pair<int, int>> stack{{base, -1}};  // (link, joint it is reached through)
  pushed[static_cast<std::size_t>(base)] = 1;
  try {
    while (!stack.empty()) {
      const auto [link, k] = stack.back();
      stack.pop_back();
      const LinkRec& L = d.links[static_cast<std::size_t>(link)];
      Placed& here = placed[static_cast<std::size_t>(link)];
      LinkInfo info;
      info.name = L.name;
      if (k < 0) {  // the base link
        here.body = -1;
        here.T = Pose::Identity();
        builder.add_fixed_body(L.name, -1, Transform<double>::Identity(), L.inertia);
        out.base_inertia += L.inertia;
      } else {
        const JointRec& j = d.joints[static_cast<std::size_t>(k)];
        const bool forward = j.child == link;
        const int from = forward ? j.parent : j.child;
        const Placed& up = placed[static_cast<std::size_t>(from)];
        const auto& locked_at = lock[static_cast<std::size_t>(k)];
        if (j.kind == Kind::Fixed || locked_at) {
          const Pose M = j.origin * joint_motion(j, locked_at.value_or(0.0));  // child link in parent link
          here.body = up.body;
          here.T = up.T * (forward ? M : M.inverse());
          builder.add_fixed_body(L.name, here.body, passive(here.T), L.inertia);
          if (here.body == -1) out.base_inertia += L.inertia.transformed_inverse(passive(here.T));
        } else {
          if (j.kind != Kind::Revolute && j.kind != Kind::Continuous && j.kind != Kind::Prismatic)
            fail(source, "joint " + quote(j.name) + " is of type " + kind_name(j.kind) +
                             ", which is not supported (supported: revolute, continuous, prismatic, fixed; floating "
                             "only from a massless root link, or LoadOptions::floating for the base link)");
          if (!j.mimic.empty())
            fail(source, "joint " + quote(j.name) + " mimics joint " + quote(j.mimic) +
                             ": mimic joints are not supported (lock it, or remove the <mimic> element to make it "
                             "independent)");
          // Predecessor frame in the new parent link, axis in it, and the successor frame in the moving link.
          const Pose pred0 = forward ? j.origin : Pose::Identity();
          const Pose succ0 = forward ? Pose::Identity() : j.origin;
          Eigen::Vector3d a = forward ? j.axis : Eigen::Vector3d(-j.axis);
          Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
          int aligned = -1;  // coordinate axis, if a = ±e_k exactly
          for (int c = 0; c < 3; ++c)
            if (a[(c + 1) % 3] == 0.0 && a[(c + 2) % 3] == 0.0) aligned = c;
          if (aligned >= 0 && a[aligned] < 0 && opt.axis_aligned) {
            F = flip_matrix(aligned);
            a = F.transpose() * a;
          }
          const bool revolute = j.kind != Kind::Prismatic;
          JointType type = revolute ? JointType::RevoluteAxis : JointType::PrismaticAxis;
          if (aligned >= 0 && a[aligned] == 1.0) {
            static const JointType rev[] = {JointType::RevoluteX, JointType::RevoluteY, JointType::RevoluteZ};
            static const JointType pri[] = {JointType::PrismaticX, JointType::PrismaticY, JointType::PrismaticZ};
            type = revolute ? rev[aligned] : pri[aligned];
          }
          Pose Fp = Pose::Identity();
          Fp.linear() = F;
          const Pose pred_in_parent_body = up.T * pred0 * Fp;
          here.T = (succ0 * Fp).inverse();  // the link in its new body frame
          const Transform<double> X_link = passive(here.T);  // ˡX_body
          here.body = builder.add_body(L.name, up.body, type, passive(pred_in_parent_body),
                                       L.inertia.transformed_inverse(X_link), a, j.name);
          JointInfo ji = j.info;
          ji.reversed = !forward;
          out.joints.push_back(ji);
          info.moving = true;
        }
      }
      info.body = here.body;
      info.X = passive(here.T);
      out.links.push_back(info);

      // Children, so that they pop in joint order.
      const auto& adj = d.adjacent[static_cast<std::size_t>(link)];
      for (auto it = adj.rbegin(); it != adj.rend(); ++it) {
        const JointRec& j = d.joints[static_cast<std::size_t>(*it)];
        const int other = j.parent == link ? j.child : j.parent;
        if (!kept[static_cast<std::size_t>(other)] || pushed[static_cast<std::size_t>(other)]) continue;
        pushed[static_cast<std::size_t>(other)] = 1;
        stack.emplace_back(other, *it);
      }
    }
  } catch (const ModelError& e) {
    const std::string msg = e.what();
    if (msg.rfind(source + ": ", 0) == 0) throw;
    fail(source, msg);
  }

  for (std::size_t k = 0; k < d.joints.size(); ++k)
    if (lock[k]) {
      const JointRec& j = d.joints[k];
      if (kept[static_cast<std::size_t>(j.parent)] && kept[static_cast<std::size_t>(j.child)])
        out.locked.emplace_back(j.name, *lock[k]);
    }
  out.model = builder.build();
  return out;
}

/// urdfdom links each link to its children with shared pointers, so a file with a loop makes a cycle that is never
/// freed. Cutting those links frees a model the loader owns.
inline void cut_cycles(urdf::ModelInterface& model) {
  for (auto& entry : model.links_)
    if (entry.second) {
      entry.second->child_links.clear();
      entry.second->child_joints.clear();
    }
}

/// Rejects, before urdfdom sees the file, joint graphs in which urdfdom's links would point at each other in a cycle
/// of shared pointers: a link that is the child of two joints, or a loop of parent joints. When urdfdom then fails on
/// something else (a second root, say) it returns null and the cycle leaks inside it, out of our reach (found by
/// the fuzzer, tests/fuzz/). Files that tinyxml cannot read are left to urdfdom's error message.
inline void check_joint_graph(const std::string& xml, const std::string& source) {
  TiXmlDocument doc;
  doc.Parse(xml.c_str());
  if (doc.Error()) return;
  const TiXmlElement* robot = doc.FirstChildElement("robot");
  if (robot == nullptr) return;
  std::map<std::string, std::pair<std::string, std::string>> parent_of;  // child link -> (parent link, joint)
  for (const TiXmlElement* j = robot->FirstChildElement("joint"); j != nullptr; j = j->NextSiblingElement("joint")) {
    const TiXmlElement* p = j->FirstChildElement("parent");
    const TiXmlElement* c = j->FirstChildElement("child");
    const char* name = j->Attribute("name");
    const char* parent = p ? p->Attribute("link") : nullptr;
    const char* child = c ? c->Attribute("link") : nullptr;
    if (!name || !parent || !child) continue;  // urdfdom reports these
    const auto [it, inserted] = parent_of.emplace(child, std::make_pair(std::string(parent), std::string(name)));
    if (!inserted)
      fail(source, "link " + quote(child) + " is the child of two joints, " + quote(it->second.second) + " and " +
                       quote(name) + " (a kinematic loop or a duplicated joint)");
  }
  for (const TiXmlElement* l = robot->FirstChildElement("link"); l != nullptr; l = l->NextSiblingElement("link")) {
    const char* name = l->Attribute("name");
    if (!name) continue;
    std::string at = name;
    for (std::size_t steps = 0; steps <= parent_of.size(); ++steps) {
      const auto it = parent_of.find(at);
      if (it == parent_of.end()) break;
      at = it->second.first;
      if (at == name)
        fail(source, "link " + quote(name) + " is not connected to the root link: its parent joints lead back to it "
                                             "(the joints form a kinematic loop)");
    }
  }
}

inline urdf::ModelInterfaceSharedPtr parse(const std::string& xml, const std::string& source) {
  check_joint_graph(xml, source);
  urdf::ModelInterfaceSharedPtr m;
  std::vector<std::string> errors;
  std::string thrown;
  {
    CaptureLog capture;
    try {
      m = urdf::parseURDF(xml);
    } catch (const std::exception& e) {
      thrown = e.what();
    }
    errors = capture.errors();
  }
  if (!thrown.empty()) errors.push_back(thrown);
  if (!m || !errors.empty()) {
    if (m) cut_cycles(*m);
    std::string msg = "not a valid URDF";
    for (std::size_t i = 0; i < errors.size(); ++i) msg += (i == 0 ? ": " : "; ") + errors[i];
    if (errors.empty()) msg += " (urdfdom gave no reason)";
    fail(source, msg);
  }
  return m;
}

}  // namespace detail

/// A model from a URDF already parsed by urdfdom (children are walked in joint-name order, since urdfdom does not
/// keep the document order). Throws `ModelError`.
inline LoadedModel load_model(const urdf::ModelInterface& urdf, const LoadOptions& options = {},
                              const std::string& source_name = "<urdf model>") {
  const detail::Description d = detail::describe(urdf, {}, source_name, options.strict_inertia);
  return detail::build(d, options, source_name);
}

/// A model from URDF text; `source_name` prefixes every error message. Throws `ModelError`.
inline LoadedModel load_string(const std::string& xml, const LoadOptions& options = {},
                               const std::string& source_name = "<string>") {
  const urdf::ModelInterfaceSharedPtr m = detail::parse(xml, source_name);
  struct CutCycles {  // we own this model: free it whatever happens
    urdf::ModelInterface& model;
    ~CutCycles() { detail::cut_cycles(model); }
  } cut{*m};
  const detail::Description d =
      detail::describe(*m, detail::joint_document_order(xml), source_name, options.strict_inertia);
  return detail::build(d, options, source_name);
}

/// A model from a URDF file. Throws `ModelError` (naming the file) if it cannot be read or is not a valid URDF.
inline LoadedModel load_file(const std::string& path, const LoadOptions& options = {}) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) detail::fail(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) detail::fail(path, "is a directory, not a URDF file");
  std::ifstream in(path, std::ios::binary);
  if (!in) detail::fail(path, "cannot open the file for reading");
  std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) detail::fail(path, "error while reading the file");
  return load_string(xml, options, path);
}

/// The compile-time model `Model<double, TreeT>` of a loaded model: its size, parents and joint types must match
/// the tree's, otherwise `ModelError` naming the source and the first mismatch.
template <class TreeT>
Model<double, TreeT> to_static(const LoadedModel& loaded) {
  try {
    return Model<double, TreeT>::from(loaded.model);
  } catch (const ModelError& e) {
    throw ModelError(loaded.source + ": " + e.what());
  }
}

/// The floating-base model of a model loaded with `LoadOptions::floating` (or from a URDF floating joint): the
/// free-flyer at the base link's frame, its inertia `base_inertia`, the joints' tree `model` (whose gravity is read
/// as world coordinates). Throws `ModelError` if the model was not loaded floating.
inline FloatingModel<double> floating_model(const LoadedModel& loaded) {
  if (!loaded.floating)
    throw ModelError(loaded.source + ": the model was loaded with a fixed base (set LoadOptions::floating)");
  return FloatingModel<double>(loaded.model, loaded.base_inertia, loaded.root);
}

/// Throws `ModelError` if some joint moves no mass (its whole subtree is massless), which makes the joint-space
/// inertia matrix H singular so that forward dynamics is undefined; the message names the joints and suggests
/// locking them.
inline void check_nonsingular(const LoadedModel& loaded) {
  const std::vector<int> bad = loaded.model.massless_joints();
  if (bad.empty()) return;
  std::string list;
  for (int i : bad) list += (list.empty() ? "" : ", ") + detail::quote(loaded.model.joint_name(i));
  throw ModelError(loaded.source + ": joint" + (bad.size() > 1 ? "s " : " ") + list + (bad.size() > 1 ? " move" : " moves") +
                   " no mass (the whole subtree is massless), so the joint-space inertia matrix is singular and "
                   "forward dynamics is undefined; lock " + (bad.size() > 1 ? "them" : "it") +
                   " (LoadOptions::locked, e.g. at 0)");
}

/// Mass of the whole robot as loaded: the moving bodies and the links merged into the fixed base.
inline double whole_body_mass(const LoadedModel& loaded) {
  return loaded.model.total_mass() + loaded.base_inertia.m;
}

/// Centre of mass of the whole robot as loaded (moving bodies and the links merged into the base), in base
/// coordinates, at configuration q. Runs `forward_kinematics` into `data`.
template <class Q>
Eigen::Vector3d whole_body_com(const LoadedModel& loaded, Data<double>& data, const Eigen::MatrixBase<Q>& q) {
  forward_kinematics(loaded.model, data, q);
  Eigen::Vector3d first_moment = loaded.base_inertia.h;
  double mass = loaded.base_inertia.m;
  for (int i = 0; i < loaded.model.size(); ++i) {
    const Transform<double>& X = data.X_base[static_cast<std::size_t>(i)];
    const Inertia<double>& I = loaded.model.inertia(i);
    first_moment += I.m * X.r + X.E.transpose() * I.h;
    mass += I.m;
  }
  return first_moment / mass;
}

/// Pose of a URDF link in the base frame after `forward_kinematics(loaded.model, data, q)` (rotation: link axes in
/// base coordinates; translation: link origin). `data` may also belong to the compile-time model made by
/// `to_static` (same body numbering). Throws `ModelError` for an unknown link.
template <class TreeT>
Eigen::Isometry3d link_pose(const LoadedModel& loaded, const Data<double, TreeT>& data, const std::string& link) {
  const int k = loaded.link_index(link);
  if (k < 0) throw ModelError(loaded.source + ": unknown link " + detail::quote(link));
  const LinkInfo& info = loaded.links[static_cast<std::size_t>(k)];
  const Transform<double> X = info.body >= 0 ? info.X * data.X_base[static_cast<std::size_t>(info.body)] : info.X;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = X.E.transpose();
  pose.translation() = X.r;
  return pose;
}

}  // namespace spatial::urdf_io
