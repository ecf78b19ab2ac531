#pragma once
/// \file kdl_bridge.hpp
/// The one place that converts between spatial's conventions and KDL's (orocos-kdl 1.5), for the KDL
/// cross-check tests. Everything that knows about a KDL convention lives here.
///
/// Conventions side by side:
///  - Spatial vectors. Ours are angular first: Motion [ω; v_O], Force [n_O; f]. KDL's are linear first:
///    Twist(vel, rot) = [v_O; ω], Wrench(force, torque) = [f; n_O]. In both, the linear part of a twist is the
///    velocity of the body-fixed point at the reference point and the moment of a wrench is taken about it.
///  - Frames. Our Transform{E, r} is the PASSIVE Plücker transform ᴮX_A (E maps A coordinates to B coordinates,
///    r = B's origin in A coordinates). A KDL::Frame{M, p} is the ACTIVE pose of B in A (M = B's axes in A
///    coordinates, p = B's origin in A coordinates). Hence M = Eᵀ, p = r, and
///      ours X.apply(m)            == KDL F.Inverse(twist)     (A coordinates -> B coordinates)
///      ours X.apply_inverse(m)    == KDL F * twist            (B coordinates -> A coordinates)
///      ours X2 * X1 (ᶜX_B ᴮX_A)   == KDL F1 * F2              (poses compose in the opposite order)
///  - Inertia. KDL::RigidBodyInertia(m, c, Ic) takes the rotational inertia about the CENTRE OF MASS (like our
///    Inertia::from_com); getRotationalInertia() returns it about the reference point (our Inertia::I).
///    KDL::RotationalInertia(Ixx, Iyy, Izz, Ixy, Ixz, Iyz) takes the matrix entries (not negated products).
///  - Segments. A KDL Segment is (joint at its root, rigid body, tip frame); pose(q) = joint.pose(q) * f_tip, and
///    the solvers express the segment's velocity, acceleration, inertia and external wrench in its TIP frame, about
///    the tip origin. The `f_tip` given to the Segment constructor is the tip pose relative to the segment ROOT at
///    q = 0 (KDL stores joint.pose(0)⁻¹ * f_tip), not relative to the joint's end, which matters for joints with a
///    non-zero origin.
///  - Joint numbering. Chains number the moving joints in segment order. A Tree numbers them (q_nr) in the order
///    segments were added, but copying a KDL::Tree (copy constructor or assignment) renumbers them depth-first,
///    and some solvers keep a copy (TreeFkSolverPos_recursive) while others keep a reference (TreeIdSolver_RNE):
///    on a tree not built depth-first, the same JntArray means different joint positions to the two. KdlTree adds
///    the segments depth-first, so every copy numbers alike, and reads the numbering back from the tree.
///  - Lifetimes. ChainIdSolver_RNE, ChainDynParam, ChainFdSolver_RNE and TreeIdSolver_RNE keep a REFERENCE to
///    the chain or tree they were built from (although the chain solvers' comments promise "an internal copy"):
///    `KdlChain` and `KdlTree` own it and can be neither copied nor moved, so a solver built on one stays valid as
///    long as the object lives. TreeFkSolverPos_recursive keeps a copy (see joint numbering).
///  - External wrenches. Chain solvers take one wrench per SEGMENT (fixed ones included), in the segment's tip
///    frame, about the tip origin; TreeIdSolver_RNE takes them by segment name. ChainDynParam::JntToCoriolis
///    returns the vector C(q, q̇) q̇ (not the matrix), JntToGravity the vector G(q).
///  - Sanitizers. See the EIGEN_MALLOC_ALREADY_ALIGNED note below: include this header first.
///  - The base. The root of a KDL::Tree is a name with neither joint nor inertia: the fixed base, like our body -1.

// liborocos-kdl is built without AddressSanitizer, where Eigen (Memory.h) trusts glibc's malloc to be 16-byte
// aligned and allocates with plain malloc. Under -fsanitize=address (__SANITIZE_ADDRESS__) Eigen switches to its
// own over-allocating aligned allocator, so inline KDL code compiled in a test (e.g. ~ChainFdSolver_RNE, which frees
// Eigen vectors the library allocated) would free with the wrong allocator: ASan reports a heap-buffer-overflow.
// Keep the library's choice. (Eigen must not have been included before this header in a sanitized build.)
#if defined(__SANITIZE_ADDRESS__) && !defined(EIGEN_MALLOC_ALREADY_ALIGNED)
#ifdef EIGEN_CORE_H
#error "include kdl_bridge.hpp before any Eigen header (it must set EIGEN_MALLOC_ALREADY_ALIGNED under ASan)"
#endif
#define EIGEN_MALLOC_ALREADY_ALIGNED 1
#endif

#include <spatial/spatial.hpp>

#include "support/random_model.hpp"

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>
#include <kdl/joint.hpp>
#include <kdl/rigidbodyinertia.hpp>
#include <kdl/rotationalinertia.hpp>
#include <kdl/segment.hpp>
#include <kdl/tree.hpp>
#include <kdl/treefksolverpos_recursive.hpp>
#include <kdl/treeidsolver.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace spatial::kdl_bridge {

// ---------------------------------------------------------------------------------------------------------------
// 3D vectors and rotation matrices: the same numbers in both libraries.

inline KDL::Vector to_kdl(const Vector3<double>& v) { return KDL::Vector(v.x(), v.y(), v.z()); }
inline Vector3<double> from_kdl(const KDL::Vector& v) { return Vector3<double>(v.x(), v.y(), v.z()); }

/// The same 3×3 matrix as a KDL::Rotation (KDL's constructor takes the entries row by row).
inline KDL::Rotation to_kdl_rotation(const Matrix3<double>& R) {
  return KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2));
}
inline Matrix3<double> from_kdl(const KDL::Rotation& R) {
  Matrix3<double> out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(i, j) = R(i, j);
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Frames: passive ᴮX_A = (E, r)  <->  active pose of B in A = (M = Eᵀ, p = r).

inline KDL::Frame to_kdl(const Transform<double>& X) {
  return KDL::Frame(to_kdl_rotation(X.E.transpose()), to_kdl(X.r));
}
inline Transform<double> from_kdl(const KDL::Frame& F) {
  return Transform<double>(from_kdl(F.M).transpose(), from_kdl(F.p));
}

// ---------------------------------------------------------------------------------------------------------------
// Spatial vectors: angular first (ours) <-> linear first (KDL).

inline KDL::Twist to_kdl(const Motion<double>& m) { return KDL::Twist(to_kdl(m.v), to_kdl(m.w)); }
inline Motion<double> from_kdl(const KDL::Twist& t) { return Motion<double>(from_kdl(t.rot), from_kdl(t.vel)); }
inline KDL::Wrench to_kdl(const Force<double>& f) { return KDL::Wrench(to_kdl(f.f), to_kdl(f.n)); }
inline Force<double> from_kdl(const KDL::Wrench& w) { return Force<double>(from_kdl(w.torque), from_kdl(w.force)); }

// ---------------------------------------------------------------------------------------------------------------
// Inertia.

/// A symmetric 3×3 rotational inertia as KDL's (Ixx, Iyy, Izz, Ixy, Ixz, Iyz) = matrix entries.
inline KDL::RotationalInertia to_kdl_rotational_inertia(const Matrix3<double>& I) {
  return KDL::RotationalInertia(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
}
inline Matrix3<double> from_kdl(const KDL::RotationalInertia& I) {
  // RotationalInertia only exposes its (row-major, symmetric) data array and the product with a vector.
  Matrix3<double> out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(i, j) = I.data[3 * i + j];
  return out;
}

/// KDL inertia from mass, centre of mass and rotational inertia about the centre of mass (all in one frame).
inline KDL::RigidBodyInertia to_kdl_inertia(double mass, const Vector3<double>& com, const Matrix3<double>& Ic) {
  return KDL::RigidBodyInertia(mass, to_kdl(com), to_kdl_rotational_inertia(Ic));
}
/// Our spatial inertia as a KDL inertia in the same frame (massless: the rotational inertia about the origin).
inline KDL::RigidBodyInertia to_kdl(const Inertia<double>& I) {
  if (I.m == 0.0) return KDL::RigidBodyInertia(0.0, KDL::Vector::Zero(), to_kdl_rotational_inertia(I.I));
  return to_kdl_inertia(I.m, I.com(), I.inertia_com());
}
inline Inertia<double> from_kdl(const KDL::RigidBodyInertia& I) {
  return Inertia<double>(I.getMass(), I.getMass() * from_kdl(I.getCOG()), from_kdl(I.getRotationalInertia()));
}

// ---------------------------------------------------------------------------------------------------------------
// Joints.

/// A KDL joint for one of our joint types, placed at the segment root (the root frame is our joint frame, so the
/// joint's end frame is our body frame). `axis` is used by the *Axis types.
inline KDL::Joint to_kdl_joint(JointType type, const Vector3<double>& axis, const std::string& name) {
  switch (type) {
    case JointType::RevoluteX: return KDL::Joint(name, KDL::Joint::RotX);
    case JointType::RevoluteY: return KDL::Joint(name, KDL::Joint::RotY);
    case JointType::RevoluteZ: return KDL::Joint(name, KDL::Joint::RotZ);
    case JointType::RevoluteAxis: return KDL::Joint(name, KDL::Vector::Zero(), to_kdl(axis), KDL::Joint::RotAxis);
    case JointType::PrismaticX: return KDL::Joint(name, KDL::Joint::TransX);
    case JointType::PrismaticY: return KDL::Joint(name, KDL::Joint::TransY);
    case JointType::PrismaticZ: return KDL::Joint(name, KDL::Joint::TransZ);
    case JointType::PrismaticAxis:
      return KDL::Joint(name, KDL::Vector::Zero(), to_kdl(axis), KDL::Joint::TransAxis);
  }
  throw std::invalid_argument("unknown joint type");
}

/// Our joint i as one KDL joint that also does our tree transform: joint origin = the joint frame's origin in
/// parent coordinates, axis = the joint axis in parent coordinates (always RotAxis or TransAxis). Used with
/// f_tip = the joint frame's pose in the parent, it gives a segment whose tip frame is our body frame.
inline KDL::Joint to_kdl_joint_with_origin(JointType type, const Vector3<double>& axis, const Transform<double>& X_tree,
                                           const std::string& name) {
  const Vector3<double> axis_in_parent = X_tree.E.transpose() * axis;
  return KDL::Joint(name, to_kdl(X_tree.r), to_kdl(axis_in_parent),
                    is_revolute(type) ? KDL::Joint::RotAxis : KDL::Joint::TransAxis);
}

// ---------------------------------------------------------------------------------------------------------------
// Joint-space vectors and matrices. `q_index[i]` is the KDL joint number of our joint i.

inline KDL::JntArray to_kdl_joints(const Eigen::VectorXd& x, const std::vector<unsigned>& q_index) {
  KDL::JntArray out(static_cast<unsigned>(x.size()));
  for (Eigen::Index i = 0; i < x.size(); ++i) out(q_index[static_cast<std::size_t>(i)]) = x[i];
  return out;
}
inline Eigen::VectorXd from_kdl_joints(const KDL::JntArray& x, const std::vector<unsigned>& q_index) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(q_index.size()));
  for (std::size_t i = 0; i < q_index.size(); ++i) out[static_cast<Eigen::Index>(i)] = x(q_index[i]);
  return out;
}
inline Eigen::MatrixXd from_kdl_joints(const KDL::JntSpaceInertiaMatrix& H, const std::vector<unsigned>& q_index) {
  const auto n = static_cast<Eigen::Index>(q_index.size());
  Eigen::MatrixXd out(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      out(i, j) = H(q_index[static_cast<std::size_t>(i)], q_index[static_cast<std::size_t>(j)]);
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Whole trees.

/// How our bodies become KDL segments. In every layout, each of our joints is exactly one moving KDL joint.
enum class Layout {
  /// Per body: a fixed segment "<body>_placement" whose tip is our joint frame (f_tip = X_tree), then a segment
  /// "<body>" with the joint (native RotX/…/TransAxis type at its root) and f_tip = identity. Tip = body frame.
  FixedThenJoint,
  /// Per body: one segment "<body>" whose RotAxis/TransAxis joint has its origin and axis in the parent's tip frame
  /// (see to_kdl_joint_with_origin) and f_tip = X_tree. Tip = body frame.
  JointOrigin,
  /// Chains only, the classic "DH-like" KDL layout: a leading fixed segment "base_placement" carries body 0's
  /// X_tree; segment "<body i>" has the native joint at its root and its tip at body i+1's joint frame
  /// (f_tip = X_tree(i+1); identity for the last body). Inertia and wrenches are re-expressed in that tip frame.
  TipAtNextJoint,
};

inline const char* layout_name(Layout l) {
  switch (l) {
    case Layout::FixedThenJoint: return "FixedThenJoint";
    case Layout::JointOrigin: return "JointOrigin";
    case Layout::TipAtNextJoint: return "TipAtNextJoint";
  }
  return "?";
}

inline std::string body_segment_name(std::size_t i) { return "body" + std::to_string(i); }

namespace detail {
/// The segments of body i: its fixed placement segment (if any), then its moving segment. Fills the frame in
/// which KDL sees the body (the moving segment's tip) as tipX_body.
inline std::vector<KDL::Segment> body_segments(const std::vector<testing::RandomBody>& bodies, std::size_t i,
                                               Layout layout, Transform<double>& tip_from_body) {
  const testing::RandomBody& b = bodies[i];
  const std::string name = body_segment_name(i);
  const KDL::RigidBodyInertia I_body = to_kdl_inertia(b.mass, b.com, b.inertia_com);
  std::vector<KDL::Segment> out;
  switch (layout) {
    case Layout::FixedThenJoint:
      out.emplace_back(name + "_placement", KDL::Joint(name + "_placement", KDL::Joint::Fixed), to_kdl(b.X_tree));
      out.emplace_back(name, to_kdl_joint(b.type, b.axis, "joint" + std::to_string(i)), KDL::Frame::Identity(),
                       I_body);
      tip_from_body = Transform<double>::Identity();
      break;
    case Layout::JointOrigin:
      out.emplace_back(name, to_kdl_joint_with_origin(b.type, b.axis, b.X_tree, "joint" + std::to_string(i)),
                       to_kdl(b.X_tree), I_body);
      tip_from_body = Transform<double>::Identity();
      break;
    case Layout::TipAtNextJoint: {
      if (i == 0)
        out.emplace_back("base_placement", KDL::Joint("base_placement", KDL::Joint::Fixed), to_kdl(b.X_tree));
      tip_from_body = i + 1 < bodies.size() ? bodies[i + 1].X_tree : Transform<double>::Identity();
      // The body's inertia in the tip frame, by KDL's own transform: I_tip = (pose of the body frame in the tip
      // frame) * I_body.
      const KDL::Frame body_in_tip = to_kdl(tip_from_body).Inverse();
      out.emplace_back(name, to_kdl_joint(b.type, b.axis, "joint" + std::to_string(i)), to_kdl(tip_from_body),
                       body_in_tip * I_body);
      break;
    }
  }
  return out;
}
}  // namespace detail

/// A KDL::Chain built from random chain bodies (body i's parent is i − 1). Neither copyable nor movable, so solvers
/// built on `chain()` never dangle.
class KdlChain {
 public:
  KdlChain(const std::vector<testing::RandomBody>& bodies, Layout layout) : layout_(layout) {
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      if (bodies[i].parent != static_cast<int>(i) - 1)
        throw std::invalid_argument("KdlChain: body " + std::to_string(i) + " is not the child of the previous one");
      Transform<double> tip_from_body;
      for (const KDL::Segment& s : detail::body_segments(bodies, i, layout, tip_from_body)) chain_.addSegment(s);
      segment_of_body_.push_back(chain_.getNrOfSegments() - 1);
      tip_from_body_.push_back(tip_from_body);
      q_index_.push_back(static_cast<unsigned>(i));  // chains number moving joints in segment order
    }
  }
  KdlChain(const KdlChain&) = delete;
  KdlChain& operator=(const KdlChain&) = delete;

  const KDL::Chain& chain() const { return chain_; }
  Layout layout() const { return layout_; }
  const std::vector<unsigned>& q_index() const { return q_index_; }
  /// Index of body i's moving segment in the chain.
  unsigned segment(std::size_t i) const { return segment_of_body_[i]; }
  /// ᵗⁱᵖX_body: from body i's coordinates to its KDL segment's tip coordinates.
  const Transform<double>& tip_from_body(std::size_t i) const { return tip_from_body_[i]; }

  KDL::JntArray joints(const Eigen::VectorXd& x) const { return to_kdl_joints(x, q_index_); }
  Eigen::VectorXd joints(const KDL::JntArray& x) const { return from_kdl_joints(x, q_index_); }

  /// KDL external wrenches (one per segment, in tip coordinates) from forces on our bodies in body coordinates.
  /// The change of frame is done by KDL (pose of the body frame in the tip frame * wrench).
  KDL::Wrenches wrenches(const std::vector<Force<double>>& f_body) const {
    KDL::Wrenches out(chain_.getNrOfSegments(), KDL::Wrench::Zero());
    for (std::size_t i = 0; i < f_body.size(); ++i)
      out[segment(i)] = to_kdl(tip_from_body(i)).Inverse() * to_kdl(f_body[i]);
    return out;
  }
  /// KDL external wrenches from forces on our bodies given in BASE coordinates (moment about the base origin), at
  /// joint positions q: each is carried into its segment's tip frame with the tip pose from KDL's own forward
  /// kinematics (tip wrench = pose⁻¹ · base wrench).
  KDL::Wrenches wrenches_from_base(const std::vector<Force<double>>& f_base, const Eigen::VectorXd& q) const {
    KDL::ChainFkSolverPos_recursive fk(chain_);
    const KDL::JntArray qk = joints(q);
    KDL::Wrenches out(chain_.getNrOfSegments(), KDL::Wrench::Zero());
    for (std::size_t i = 0; i < f_base.size(); ++i) {
      KDL::Frame tip;
      if (fk.JntToCart(qk, tip, static_cast<int>(segment(i)) + 1) < 0)
        throw std::runtime_error("KdlChain: forward kinematics failed");
      out[segment(i)] = tip.Inverse(to_kdl(f_base[i]));
    }
    return out;
  }

 private:
  Layout layout_;
  KDL::Chain chain_;
  std::vector<unsigned> segment_of_body_;
  std::vector<Transform<double>> tip_from_body_;
  std::vector<unsigned> q_index_;
};

/// A KDL::Tree built from random bodies, rooted at the massless segment "base" (our fixed base, body −1).
/// Layouts FixedThenJoint and JointOrigin only. Neither copyable nor movable (solvers keep a reference to the
/// tree).
class KdlTree {
 public:
  static constexpr const char* kRoot = "base";

  KdlTree(const std::vector<testing::RandomBody>& bodies, Layout layout) : layout_(layout), tree_(kRoot) {
    if (layout == Layout::TipAtNextJoint)
      throw std::invalid_argument("KdlTree: TipAtNextJoint needs a chain (a body with two children has no single "
                                  "next joint frame)");
    std::vector<std::vector<std::size_t>> children(bodies.size() + 1);  // children[p + 1]: children of body p
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const int p = bodies[i].parent;
      if (p < -1 || p >= static_cast<int>(i)) throw std::invalid_argument("KdlTree: parents must precede children");
      children[static_cast<std::size_t>(p + 1)].push_back(i);
      names_.push_back(body_segment_name(i));
    }
    // Add the bodies depth-first (children in index order): a KDL::Tree numbers its joints in the order segments
    // are added, and its copies (TreeFkSolverPos_recursive keeps one) renumber them depth-first; built depth-first,
    // the tree and all its copies agree.
    std::vector<std::size_t> stack(children[0].rbegin(), children[0].rend());
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      const int p = bodies[i].parent;
      std::string hook = p < 0 ? std::string(kRoot) : body_segment_name(static_cast<std::size_t>(p));
      Transform<double> tip_from_body;
      for (const KDL::Segment& s : detail::body_segments(bodies, i, layout, tip_from_body)) {
        if (!tree_.addSegment(s, hook)) throw std::runtime_error("KdlTree: could not add segment " + s.getName());
        hook = s.getName();
      }
      const auto& c = children[i + 1];
      stack.insert(stack.end(), c.rbegin(), c.rend());
    }
    // Read the joint numbering back from the tree itself, and check that a copy numbers the joints alike.
    const KDL::Tree copy(tree_);
    for (const std::string& name : names_) {
      q_index_.push_back(GetTreeElementQNr(tree_.getSegment(name)->second));
      if (GetTreeElementQNr(copy.getSegment(name)->second) != q_index_.back())
        throw std::logic_error("KdlTree: a copy of the tree numbers joint '" + name + "' differently");
    }
  }
  KdlTree(const KdlTree&) = delete;
  KdlTree& operator=(const KdlTree&) = delete;

  const KDL::Tree& tree() const { return tree_; }
  Layout layout() const { return layout_; }
  const std::vector<unsigned>& q_index() const { return q_index_; }
  /// Name of body i's moving segment (its tip frame is body i's frame).
  const std::string& segment(std::size_t i) const { return names_[i]; }

  KDL::JntArray joints(const Eigen::VectorXd& x) const { return to_kdl_joints(x, q_index_); }
  Eigen::VectorXd joints(const KDL::JntArray& x) const { return from_kdl_joints(x, q_index_); }

  /// KDL external wrenches by segment name from forces on our bodies in body coordinates (= tip coordinates).
  KDL::WrenchMap wrenches(const std::vector<Force<double>>& f_body) const {
    KDL::WrenchMap out;
    for (std::size_t i = 0; i < f_body.size(); ++i) out[segment(i)] = to_kdl(f_body[i]);
    return out;
  }
  /// As KdlChain::wrenches_from_base, with KDL's tree forward kinematics.
  KDL::WrenchMap wrenches_from_base(const std::vector<Force<double>>& f_base, const Eigen::VectorXd& q) const {
    KDL::TreeFkSolverPos_recursive fk(tree_);
    const KDL::JntArray qk = joints(q);
    KDL::WrenchMap out;
    for (std::size_t i = 0; i < f_base.size(); ++i) {
      KDL::Frame tip;
      if (fk.JntToCart(qk, tip, segment(i)) < 0) throw std::runtime_error("KdlTree: forward kinematics failed");
      out[segment(i)] = tip.Inverse(to_kdl(f_base[i]));
    }
    return out;
  }

 private:
  Layout layout_;
  KDL::Tree tree_;
  std::vector<std::string> names_;
  std::vector<unsigned> q_index_;
};

}  // namespace spatial::kdl_bridge
