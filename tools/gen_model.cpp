// spatial-gen: URDF -> a header with a compile-time model (spatial::Tree and every number as a constant).
//
//   spatial-gen --urdf FILE [--root LINK] [--subtree LINK] [--lock JOINT=ANGLE,...] [--gravity gx,gy,gz]
//               [--gravity-frame root|urdf] [--floating] [--strict-inertia] --name NAME [--namespace NS] [--title TEXT]
//               [--out FILE|-]
//
// The loader's warnings (link inertias breaking the triangle inequality) go to stderr as
// "spatial-gen: warning: FILE: ..."; --strict-inertia refuses such a file instead.
//
// The model options mean what they mean to spatial::urdf_io::load_file (LoadOptions) and to spatial-dyn; the header
// holds exactly the numbers the loader computes (printed as the shortest decimals that read back as the same
// doubles), so the generated model and the loaded one are the same model. The header declares, in namespace NS::NAME
// (NS defaults to spatial::models): the `Tree` alias, `model<S>()`, joint and body names, joint limits, locked
// joints, fixed frames, masses, `base_inertia<S>()`, `whole_body_com(...)` and index look-ups. Paths given on the
// command line are recorded as given: run it from the source root with relative paths to get a header that does
// not depend on where the checkout is (the build does).

#include "cli_common.hpp"

#include <spatial/urdf.hpp>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace uio = spatial::urdf_io;
using cli::UsageError;

const char* kUsage =
    "usage: spatial-gen --urdf FILE [--root LINK] [--subtree LINK] [--lock JOINT=ANGLE,...]\n"
    "                   [--gravity gx,gy,gz] [--gravity-frame root|urdf] [--floating] [--strict-inertia]\n"
    "                   --name NAME [--namespace NS] [--title TEXT] [--out FILE|-]\n"
    "Writes a C++ header with the compile-time model of the URDF (spatial::Tree alias, NS::NAME::model<S>(),\n"
    "names, limits, frames, masses; with --floating also NS::NAME::floating_model<S>(), the free-flying base link\n"
    "carrying that tree). NS defaults to spatial::models; --out - (default) writes to stdout.\n";

/// A C++ double literal that reads back as exactly x (finite x).
std::string lit(double x) {
  std::string s = cli::format_double(x);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

/// A limit: ±infinity spelled out.
std::string limit_lit(double x) {
  if (std::isinf(x)) return x > 0 ? "kInf" : "-kInf";
  return lit(x);
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

bool is_identifier(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

bool is_namespace(const std::string& s) {
  std::size_t start = 0;
  for (;;) {
    const std::size_t k = s.find("::", start);
    if (!is_identifier(s.substr(start, k == std::string::npos ? std::string::npos : k - start))) return false;
    if (k == std::string::npos) return true;
    start = k + 2;
  }
}

std::string joint_type_code(JointType t) {
  switch (t) {
    case JointType::RevoluteX: return "JointType::RevoluteX";
    case JointType::RevoluteY: return "JointType::RevoluteY";
    case JointType::RevoluteZ: return "JointType::RevoluteZ";
    case JointType::RevoluteAxis: return "JointType::RevoluteAxis";
    case JointType::PrismaticX: return "JointType::PrismaticX";
    case JointType::PrismaticY: return "JointType::PrismaticY";
    case JointType::PrismaticZ: return "JointType::PrismaticZ";
    case JointType::PrismaticAxis: return "JointType::PrismaticAxis";
  }
  return "?";
}

std::string transform_args(const Transform<double>& X) {
  std::string s;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) s += lit(X.E(r, c)) + ", ";
  return s + lit(X.r.x()) + ", " + lit(X.r.y()) + ", " + lit(X.r.z());
}

std::string inertia_args(const Inertia<double>& I) {
  std::string s = lit(I.m) + ", " + lit(I.h.x()) + ", " + lit(I.h.y()) + ", " + lit(I.h.z());
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) s += ", " + lit(I.I(r, c));
  return s;
}

/// One item per line, each followed by a comma and, if `comment` is true, by "// <index>".
template <class F>
std::string list(int n, F&& item, bool comment = false) {
  std::string s;
  for (int i = 0; i < n; ++i) {
    s += "    " + item(i) + ",";
    if (comment) s += "  // " + std::to_string(i);
    s += "\n";
  }
  return s;
}

/// A number for comments: 6 significant digits.
std::string approx(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

std::string generate(const uio::LoadedModel& m, const std::string& name, const std::string& ns,
                     const std::string& title, const std::string& command) {
  const Model<double>& model = m.model;
  const int n = model.size();
  const auto& frames = model.frames();
  const int nf = static_cast<int>(frames.size());
  const int nl = static_cast<int>(m.locked.size());
  const double whole_mass = uio::whole_body_mass(m);
  std::ostringstream o;
  auto J = [&](int i) -> const uio::JointInfo& { return m.joints[static_cast<std::size_t>(i)]; };

  o << "#pragma once\n"
    << "/// \\file " << name << ".hpp\n";
  if (!title.empty()) o << "/// " << title << "\n///\n";
  o << "/// GENERATED by spatial-gen from " << m.source << " -- do not edit. Regenerate with\n"
    << "///   " << command << "\n"
    << "/// (the build regenerates it when the URDF or the generator changes: src/models/CMakeLists.txt).\n"
    << "///\n"
    << "/// " << n << " DoF, rooted at link '" << m.root << "'. Mass: " << approx(model.total_mass())
    << " kg moving, " << approx(model.base_mass()) << " kg on the fixed base, " << approx(whole_mass)
    << " kg in all.\n"
    << "///\n"
    << "///   #include <spatial/models/" << name << ".hpp>\n"
    << "///   const auto model = " << ns << "::" << name << "::model();          // spatial::Model<double, Tree>\n"
    << "///   spatial::Data<double, " << ns << "::" << name << "::Tree> data(model);\n"
    << "///   spatial::rnea(model, data, q, qd, qdd);  // q, qd, qdd: " << n << " entries, in joint_names order\n"
    << "\n"
    << "#include <spatial/spatial.hpp>\n"
    << "\n"
    << "#include <array>\n"
    << "#include <limits>\n"
    << "#include <string>\n"
    << "#include <string_view>\n"
    << "#include <type_traits>\n"
    << "#include <utility>\n"
    << "#include <vector>\n"
    << "\n"
    << "namespace " << ns << "::" << name << " {\n"
    << "\n"
    << "/// Degrees of freedom (= bodies = joints).\n"
    << "inline constexpr int dof = " << n << ";\n"
    << "/// The URDF file and the link the model is rooted at (the fixed base).\n"
    << "inline constexpr std::string_view source = " << quoted(m.source) << ";\n"
    << "inline constexpr std::string_view root_link = " << quoted(m.root) << ";\n"
    << "\n"
    << "/// The topology: parent of each body (-1: the fixed base) and each joint's type.\n"
    << "using Tree = spatial::Tree<\n"
    << "    spatial::Parents<";
  for (int i = 0; i < n; ++i) o << (i ? ", " : "") << model.parent(i);
  o << ">,\n    spatial::Joints<";
  for (int i = 0; i < n; ++i) o << (i ? ",\n                    " : "") << "spatial::" << joint_type_code(model.joint_type(i));
  o << ">>;\n\n";

  o << "/// URDF names of the joints, in model order (= Model::joint_name(i)): q, qd, qdd and tau follow this order.\n"
    << "inline constexpr std::array<std::string_view, dof> joint_names = {{\n"
    << list(n, [&](int i) { return quoted(model.joint_name(i)); }, true) << "}};\n"
    << "/// The link each joint moves (= Model::body_name(i)).\n"
    << "inline constexpr std::array<std::string_view, dof> body_names = {{\n"
    << list(n, [&](int i) { return quoted(model.body_name(i)); }, true) << "}};\n"
    << "/// Joints walked against their URDF direction (the model is re-rooted across them): same q, axis negated.\n"
    << "inline constexpr std::array<bool, dof> reversed = {{";
  for (int i = 0; i < n; ++i) o << (i ? ", " : "") << (J(i).reversed ? "true" : "false");
  o << "}};\n\n";

  o << "inline constexpr double kInf = std::numeric_limits<double>::infinity();\n"
    << "/// Joint limits from the URDF <limit> elements: position [rad or m] (+-kInf: none), effort [N m or N] and\n"
    << "/// velocity [rad/s or m/s] (0: absent or unknown).\n";
  const char* names[] = {"lower", "upper", "effort", "velocity"};
  for (int k = 0; k < 4; ++k) {
    o << "inline constexpr std::array<double, dof> " << names[k] << " = {{";
    for (int i = 0; i < n; ++i) {
      const double v = k == 0 ? J(i).lower : k == 1 ? J(i).upper : k == 2 ? J(i).effort : J(i).velocity;
      o << (i ? ", " : "") << limit_lit(v);
    }
    o << "}};\n";
  }
  o << "\n/// Joints locked (made rigid and merged) and their positions.\n"
    << "inline constexpr std::array<std::string_view, " << nl << "> locked_joints = {{";
  for (int k = 0; k < nl; ++k) o << (k ? ", " : "") << quoted(m.locked[static_cast<std::size_t>(k)].first);
  o << "}};\n"
    << "inline constexpr std::array<double, " << nl << "> locked_positions = {{";
  for (int k = 0; k < nl; ++k) o << (k ? ", " : "") << lit(m.locked[static_cast<std::size_t>(k)].second);
  o << "}};\n\n";

  o << "/// Fixed frames (the links merged into bodies: feet, soles, hands, ...), as in Model::frames(): name and body\n"
    << "/// (-1: the fixed base).\n"
    << "inline constexpr std::array<std::string_view, " << nf << "> frame_names = {{\n"
    << list(nf, [&](int k) { return quoted(frames[static_cast<std::size_t>(k)].name); }) << "}};\n"
    << "inline constexpr std::array<int, " << nf << "> frame_bodies = {{";
  for (int k = 0; k < nf; ++k) o << (k ? ", " : "") << frames[static_cast<std::size_t>(k)].body;
  o << "}};\n\n";

  const Eigen::Vector3d g = model.gravity();
  o << "/// Masses [kg]: of the moving bodies, of the links merged into the fixed base, and of the whole robot.\n"
    << "inline constexpr double moving_mass = " << lit(model.total_mass()) << ";\n"
    << "inline constexpr double base_mass = " << lit(model.base_mass()) << ";\n"
    << "inline constexpr double whole_body_mass = " << lit(whole_mass) << ";\n"
    << "/// Gravity [m/s^2] in base coordinates.\n"
    << "inline constexpr std::array<double, 3> gravity = {{" << lit(g.x()) << ", " << lit(g.y()) << ", "
    << lit(g.z()) << "}};\n\n";

  o << "/// Index of a joint, body or frame by name, or -1.\n"
    << "constexpr int joint_index(std::string_view joint) {\n"
    << "  for (int i = 0; i < dof; ++i)\n"
    << "    if (joint_names[static_cast<std::size_t>(i)] == joint) return i;\n"
    << "  return -1;\n"
    << "}\n"
    << "constexpr int body_index(std::string_view body) {\n"
    << "  for (int i = 0; i < dof; ++i)\n"
    << "    if (body_names[static_cast<std::size_t>(i)] == body) return i;\n"
    << "  return -1;\n"
    << "}\n"
    << "constexpr int frame_index(std::string_view frame) {\n"
    << "  for (std::size_t k = 0; k < frame_names.size(); ++k)\n"
    << "    if (frame_names[k] == frame) return static_cast<int>(k);\n"
    << "  return -1;\n"
    << "}\n\n";

  o << "namespace detail {\n"
    << "/// Transform from E (row by row) and r.\n"
    << "inline Transform<double> X(double e00, double e01, double e02, double e10, double e11, double e12, double e20,\n"
    << "                           double e21, double e22, double rx, double ry, double rz) {\n"
    << "  Matrix3<double> E;\n"
    << "  E << e00, e01, e02, e10, e11, e12, e20, e21, e22;\n"
    << "  return Transform<double>(E, Vector3<double>(rx, ry, rz));\n"
    << "}\n"
    << "/// Inertia from m, h = m c and the rotational inertia about the frame origin (row by row).\n"
    << "inline Inertia<double> I(double m, double hx, double hy, double hz, double i00, double i01, double i02,\n"
    << "                         double i10, double i11, double i12, double i20, double i21, double i22) {\n"
    << "  Matrix3<double> Io;\n"
    << "  Io << i00, i01, i02, i10, i11, i12, i20, i21, i22;\n"
    << "  return Inertia<double>(m, Vector3<double>(hx, hy, hz), Io);\n"
    << "}\n"
    << "inline Vector3<double> v(double x, double y, double z) { return Vector3<double>(x, y, z); }\n"
    << "}  // namespace detail\n\n";

  o << "/// The compile-time model in scalar type S. The numbers are doubles: the model is built (and checked) in double,\n"
    << "/// then cast (long double holds them exactly, float rounds them). Throws spatial::ModelError only if the\n"
    << "/// numbers were edited into something unphysical.\n"
    << "template <class S = double>\n"
    << "Model<S, Tree> model() {\n"
    << "  using detail::I;\n"
    << "  using detail::v;\n"
    << "  using detail::X;\n"
    << "  // X_tree(i): parent coordinates -> joint i's frame; E row by row, then r.\n"
    << "  const std::array<Transform<double>, dof> X_tree = {{\n"
    << list(n, [&](int i) { return "X(" + transform_args(model.tree_transform(i)) + ")"; }, true) << "  }};\n"
    << "  // Body inertias in body coordinates (fixed children merged): m, h = m c, then I about the origin row by row.\n"
    << "  const std::array<Inertia<double>, dof> inertia = {{\n"
    << list(n, [&](int i) { return "I(" + inertia_args(model.inertia(i)) + ")"; }, true) << "  }};\n"
    << "  const std::array<Vector3<double>, dof> axis = {{\n"
    << list(n, [&](int i) {
         const Eigen::Vector3d& a = model.axis(i);
         return "v(" + lit(a.x()) + ", " + lit(a.y()) + ", " + lit(a.z()) + ")";
       }, true)
    << "  }};\n"
    << "  std::array<std::string, dof> bodies, joints;\n"
    << "  for (std::size_t k = 0; k < std::size_t(dof); ++k) {\n"
    << "    bodies[k] = std::string(body_names[k]);\n"
    << "    joints[k] = std::string(joint_names[k]);\n"
    << "  }\n"
    << "  // Fixed frames: name, body, frame <- body transform.\n"
    << "  std::vector<FixedFrame<double>> frames = {\n"
    << list(nf, [&](int k) {
         const auto& f = frames[static_cast<std::size_t>(k)];
         return "{" + quoted(f.name) + ", " + std::to_string(f.body) + ", X(" + transform_args(f.X) + ")}";
       })
    << "  };\n"
    << "  Model<double, Tree> m = Model<double, Tree>::from_arrays(\n"
    << "      X_tree, inertia, axis, bodies, joints, v(gravity[0], gravity[1], gravity[2]), std::move(frames), base_mass);\n"
    << "  if constexpr (std::is_same_v<S, double>) return m;\n"
    << "  else return m.template cast<S>();\n"
    << "}\n\n";

  o << "/// Inertia of the links merged into the fixed base, in base coordinates (it moves nothing, but belongs to the\n"
    << "/// robot's mass and centre of mass).\n"
    << "template <class S = double>\n"
    << "Inertia<S> base_inertia() {\n"
    << "  return detail::I(" << inertia_args(m.base_inertia) << ").template cast<S>();\n"
    << "}\n\n";

  o << "/// Centre of mass of the whole robot (moving bodies and base) in base coordinates at q; runs forward_kinematics.\n"
    << "template <class S, class Q>\n"
    << "Vector3<S> whole_body_com(const Model<S, Tree>& model, Data<S, Tree>& data, const Eigen::MatrixBase<Q>& q) {\n"
    << "  forward_kinematics(model, data, q);\n"
    << "  const Inertia<S> base = base_inertia<S>();\n"
    << "  Vector3<S> first_moment = base.h;\n"
    << "  S mass = base.m;\n"
    << "  for (int i = 0; i < dof; ++i) {\n"
    << "    const Transform<S>& Xb = data.X_base[static_cast<std::size_t>(i)];\n"
    << "    const Inertia<S>& Ii = model.inertia(i);\n"
    << "    first_moment += Ii.m * Xb.r + Xb.E.transpose() * Ii.h;\n"
    << "    mass += Ii.m;\n"
    << "  }\n"
    << "  return first_moment / mass;\n"
    << "}\n\n";
  if (m.floating)
    o << "/// Velocity coordinates (the free-flyer's six, then the joints) and configuration coordinates (its seven).\n"
      << "inline constexpr int nv = dof + 6;\n"
      << "inline constexpr int nq = dof + 7;\n"
      << "\n"
      << "/// The floating-base model: the free-flyer `floating_base` at link '" << m.root << "' (inertia base_inertia()),\n"
      << "/// carrying the tree of model(); gravity in world coordinates. q: [x y z qx qy qz qw, joints], v: [v w, q̇]\n"
      << "/// (floating.hpp).\n"
      << "template <class S = double>\n"
      << "FloatingModel<S, Tree> floating_model() {\n"
      << "  return FloatingModel<S, Tree>(model<S>(), base_inertia<S>(), " << quoted(m.root) << ");\n"
      << "}\n\n";
  o << "}  // namespace " << ns << "::" << name << "\n";
  return o.str();
}

int run(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      std::cout << kUsage;
      return 0;
    }
  std::vector<std::string> with_value = cli::model_option_names();
  for (const char* s : {"--name", "--namespace", "--title", "--out"}) with_value.emplace_back(s);
  const cli::Options opts(argc, argv, 1, with_value, cli::model_flag_names());
  const std::string urdf = opts.required("--urdf");
  const std::string name = opts.required("--name");
  const std::string ns = opts.get("--namespace").value_or("spatial::models");
  const std::string out = opts.get("--out").value_or("-");
  if (!is_identifier(name)) throw UsageError("--name: '" + name + "' is not a C++ identifier");
  if (!is_namespace(ns)) throw UsageError("--namespace: '" + ns + "' is not a C++ namespace name");
  const uio::LoadOptions load = cli::load_options(opts);

  // The command that regenerates the header, recorded in it (without --out, which is where this copy went).
  std::string command = "spatial-gen --urdf " + urdf;
  for (const char* o : {"--root", "--subtree", "--lock", "--gravity", "--gravity-frame", "--name", "--namespace",
                        "--title"})
    if (auto v = opts.get(o)) {
      const bool quote = v->find_first_of(" \t()'\"*?$;&|<>") != std::string::npos;
      command += std::string(" ") + o + " " + (quote ? "'" + *v + "'" : *v);
    }
  if (opts.has("--floating")) command += " --floating";
  command += " --out " + name + ".hpp";

  const uio::LoadedModel loaded = uio::load_file(urdf, load);
  cli::print_warnings(loaded, "spatial-gen");  // stderr: the header on stdout stays clean
  const std::string text = generate(loaded, name, ns, opts.get("--title").value_or(""), command);

  if (out == "-") {
    std::cout << text;
    std::cout.flush();
    if (!std::cout) throw cli::InputError("error writing to stdout");
    return 0;
  }
  // Write next to the target and rename, so that a failed run never leaves a half-written header.
  const std::string tmp = out + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw cli::InputError("cannot open '" + tmp + "' for writing");
    f << text;
    f.close();
    if (!f) throw cli::InputError("error writing '" + tmp + "'");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, out, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw cli::InputError("cannot rename '" + tmp + "' to '" + out + "'");
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const UsageError& e) {
    std::cerr << "spatial-gen: " << cli::one_line(e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "spatial-gen: " << cli::one_line(e.what()) << "\n";
    return 1;
  }
}
