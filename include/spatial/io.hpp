#pragma once
/// \file io.hpp
/// Printing: `operator<<` for the spatial types, in the notation of algebra.hpp, and `describe(model)`, a model
/// summary like `spatial-dyn info` (joints in model order, limits when given, mass, centre of mass, massless joints,
/// frames). Numbers follow the stream's precision and flags (`describe` uses 12 significant digits).
///
///   Motion    [w (wx, wy, wz); v (vx, vy, vz)]          angular first: [ω; v_O]
///   Force     [n (nx, ny, nz); f (fx, fy, fz)]          moment about the origin first: [n_O; f]
///   Transform rot(E) xlt(r): E [e00 e01 e02; e10 e11 e12; e20 e21 e22], r (x, y, z)     ᴮX_A, passive
///   Inertia   {m 1.5; h (hx, hy, hz); I [Ixx Ixy Ixz; Iyx Iyy Iyz; Izx Izy Izz]}   h = m c, I about the origin

#include "spatial/algebra.hpp"
#include "spatial/algorithms.hpp"
#include "spatial/floating.hpp"
#include "spatial/joints.hpp"
#include "spatial/model.hpp"

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <ostream>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace spatial {

namespace detail {
template <class V>
void print_vec3(std::ostream& os, const V& v) {
  os << '(' << v[0] << ", " << v[1] << ", " << v[2] << ')';
}
template <class M>
void print_mat3(std::ostream& os, const M& m) {
  os << '[';
  for (int r = 0; r < 3; ++r) {
    if (r) os << "; ";
    os << m(r, 0) << ' ' << m(r, 1) << ' ' << m(r, 2);
  }
  os << ']';
}
}  // namespace detail

/// [w (ωx, ωy, ωz); v (vx, vy, vz)]
template <class S>
std::ostream& operator<<(std::ostream& os, const Motion<S>& m) {
  os << "[w ";
  detail::print_vec3(os, m.w);
  os << "; v ";
  detail::print_vec3(os, m.v);
  return os << ']';
}

/// [n (nx, ny, nz); f (fx, fy, fz)]
template <class S>
std::ostream& operator<<(std::ostream& os, const Force<S>& f) {
  os << "[n ";
  detail::print_vec3(os, f.n);
  os << "; f ";
  detail::print_vec3(os, f.f);
  return os << ']';
}

/// rot(E) xlt(r): E [row; row; row], r (x, y, z)
template <class S>
std::ostream& operator<<(std::ostream& os, const Transform<S>& X) {
  os << "rot(E) xlt(r): E ";
  detail::print_mat3(os, X.E);
  os << ", r ";
  detail::print_vec3(os, X.r);
  return os;
}

/// {m mass; h (first moment m c); I [rotational inertia about the origin]}
template <class S>
std::ostream& operator<<(std::ostream& os, const Inertia<S>& I) {
  os << "{m " << I.m << "; h ";
  detail::print_vec3(os, I.h);
  os << "; I ";
  detail::print_mat3(os, I.I);
  return os << '}';
}

/// Per-joint limits for `describe` (empty vectors: not printed). From a generated model header:
/// `JointLimits::from(stance::lower, stance::upper, stance::effort, stance::velocity)`.
struct JointLimits {
  std::vector<double> lower, upper, effort, velocity;

  template <class A, class B, class C, class D>
  static JointLimits from(const A& lower, const B& upper, const C& effort, const D& velocity) {
    JointLimits l;
    l.lower.assign(std::begin(lower), std::end(lower));
    l.upper.assign(std::begin(upper), std::end(upper));
    l.effort.assign(std::begin(effort), std::end(effort));
    l.velocity.assign(std::begin(velocity), std::end(velocity));
    return l;
  }
};

namespace detail {
inline std::string human(double x) {
  std::ostringstream os;
  os.precision(12);
  os << x;
  return os.str();
}
inline std::string pad(std::string s, std::size_t width) {
  if (s.size() < width) s.append(width - s.size(), ' ');
  return s;
}
inline std::string limit_cell(const std::vector<double>& v, std::size_t k) {
  return k < v.size() ? human(v[k]) : std::string("-");
}

/// `describe` with the base's inertia (mass and first moment, base coordinates) added to the whole body, when known.
/// `floating`: the base is the free-flying root body of a `FloatingModel` (gravity in world coordinates).
template <class S, class T>
std::string describe_impl(const Model<S, T>& model, const JointLimits& limits, const Inertia<double>* base,
                          bool floating = false) {
  const char* base_name = floating ? "root body" : "fixed base";
  const char* base_frame = floating ? "root frame" : "base frame";
  const int n = model.size();
  std::ostringstream o;
  o << "model:     " << n << " joints (dof), " << (Model<S, T>::is_static ? "compile-time" : "run-time") << " tree\n"
    << "gravity:   " << human(double(model.gravity().x())) << " " << human(double(model.gravity().y())) << " "
    << human(double(model.gravity().z())) << " m/s^2 (" << (floating ? "world frame" : "base frame") << ")\n";
  const std::vector<int> massless = model.massless_joints();
  std::size_t wj = 5, wb = 4;
  for (int i = 0; i < n; ++i) {
    wj = std::max(wj, model.joint_name(i).size());
    wb = std::max(wb, model.body_name(i).size());
  }
  const bool with_limits =
      !limits.lower.empty() || !limits.upper.empty() || !limits.effort.empty() || !limits.velocity.empty();
  o << "joints (model order; q, qd, qdd, tau follow it):\n"
    << "  " << pad("#", 4) << pad("joint", wj + 2) << pad("body", wb + 2) << pad("parent", 8) << pad("type", 15);
  if (with_limits) o << pad("lower", 12) << pad("upper", 12) << pad("effort", 10) << pad("velocity", 10);
  o << "notes\n";
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    std::string row = "  " + pad(std::to_string(i), 4) + pad(model.joint_name(i), wj + 2) +
                      pad(model.body_name(i), wb + 2) + pad(std::to_string(model.parent(i)), 8) +
                      pad(std::string(joint_type_name(model.joint_type(i))), 15);
    if (with_limits)
      row += pad(limit_cell(limits.lower, k), 12) + pad(limit_cell(limits.upper, k), 12) +
             pad(limit_cell(limits.effort, k), 10) + pad(limit_cell(limits.velocity, k), 10);
    if (std::find(massless.begin(), massless.end(), i) != massless.end()) row += "massless";
    row.erase(row.find_last_not_of(' ') + 1);
    o << row << "\n";
  }
  // Centre of mass at q = 0: moving bodies, plus the base's first moment when known.
  Data<S, T> data(model);
  const typename Data<S, T>::VectorN q = Data<S, T>::VectorN::Zero(n);
  const double moving = double(model.total_mass());
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  if (n > 0 && moving > 0) first_moment = moving * center_of_mass(model, data, q).template cast<double>();
  double whole = moving + double(model.base_mass());
  if (base) {
    // base_mass() already holds the base's mass; only its first moment is added.
    first_moment += base->h;
    whole = moving + base->m;
  }
  o << "mass:      " << human(whole) << " kg (moving bodies " << human(moving) << " kg, " << base_name << " "
    << human(base ? base->m : double(model.base_mass())) << " kg)\n";
  const double com_mass = base ? whole : moving;
  o << "com:       ";
  if (com_mass > 0) {
    const Eigen::Vector3d c = first_moment / com_mass;
    o << human(c.x()) << " " << human(c.y()) << " " << human(c.z()) << " m at q = 0 ("
      << (base ? "whole body" : "moving bodies") << ", " << base_frame << ")\n";
  } else {
    o << "none (no mass)\n";
  }
  o << "massless:  ";
  if (massless.empty()) o << "none";
  for (std::size_t k = 0; k < massless.size(); ++k) o << (k ? ", " : "") << model.joint_name(massless[k]);
  if (!massless.empty()) o << " (they move no mass: H is singular; lock them)";
  o << "\nframes:    ";
  if (model.frames().empty()) o << "none";
  for (std::size_t k = 0; k < model.frames().size(); ++k) {
    const auto& f = model.frames()[k];
    o << (k ? ", " : "") << f.name << " ("
      << (f.body < 0 ? std::string(floating ? "root" : "base") : model.body_name(f.body)) << ")";
  }
  o << "\n";
  return o.str();
}

template <class L, class = void>
struct is_loaded_model : std::false_type {};
template <class L>
struct is_loaded_model<L, std::void_t<decltype(std::declval<const L&>().model),
                                      decltype(std::declval<const L&>().joints[0].lower),
                                      decltype(std::declval<const L&>().base_inertia),
                                      decltype(std::declval<const L&>().floating)>> : std::true_type {};

template <class S, class T>
std::string floating_header(const FloatingModel<S, T>& model) {
  return "root:      " + model.root_name() + " (free-flying: joint '" + kFreeFlyerName + "', nq = " +
         std::to_string(model.nq()) + ", nv = " + std::to_string(model.nv()) +
         "; q = [x y z qx qy qz qw, joints], v = [v w in root coordinates, joints])\n";
}
}  // namespace detail

/// A summary of the model for people, like `spatial-dyn info`: one line per joint in model order (joint, body,
/// parent, type, and the limits when given), the masses, the centre of mass of the moving bodies at q = 0 (base
/// frame), the joints that move no mass, and the fixed frames with their bodies. Allocates; not for control loops.
template <class S, class T>
std::string describe(const Model<S, T>& model, const JointLimits& limits = {}) {
  return detail::describe_impl(model, limits, nullptr);
}

/// The same for a floating-base model: the free-flyer (root body, nq, nv), then the tree's joints, the whole mass
/// (root body included), the centre of mass of the whole robot at the neutral configuration (root frame).
template <class S, class T>
std::string describe(const FloatingModel<S, T>& model, const JointLimits& limits = {}) {
  const Inertia<double> root = model.root_inertia().template cast<double>();
  return detail::floating_header(model) + detail::describe_impl(model.tree(), limits, &root, true);
}

/// The same for a URDF model (`urdf_io::LoadedModel`): with the URDF limits, and the whole-body centre of mass
/// (the links merged into the fixed base included), as `spatial-dyn info` prints them. A model loaded floating
/// (`LoadOptions::floating`) is described as `describe(urdf_io::floating_model(loaded))` with the URDF limits.
template <class Loaded, std::enable_if_t<detail::is_loaded_model<Loaded>::value, int> = 0>
std::string describe(const Loaded& loaded) {
  JointLimits l;
  for (const auto& j : loaded.joints) {
    l.lower.push_back(j.lower);
    l.upper.push_back(j.upper);
    l.effort.push_back(j.effort);
    l.velocity.push_back(j.velocity);
  }
  const Inertia<double> base = loaded.base_inertia;
  if (loaded.floating)
    return detail::floating_header(FloatingModel<double>(loaded.model, loaded.base_inertia, loaded.root)) +
           detail::describe_impl(loaded.model, l, &base, true);
  return "root:      " + loaded.root + " (the fixed base)\n" + detail::describe_impl(loaded.model, l, &base);
}

}  // namespace spatial
