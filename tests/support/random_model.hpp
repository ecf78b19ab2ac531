#pragma once
// Random kinematic trees and states for the test suites (not part of the installed library).

#include <spatial/spatial.hpp>

#include <random>
#include <string>
#include <vector>

namespace spatial::testing {

enum class Shape { Chain, Branched };

/// The numbers of one random body, kept so that other libraries (KDL) can be fed exactly the same tree.
struct RandomBody {
  int parent;
  JointType type;
  Vector3<double> axis;        // unit axis in the joint/body frame
  Transform<double> X_tree;    // parent coordinates -> joint frame
  double mass;
  Vector3<double> com;         // in body coordinates
  Matrix3<double> inertia_com; // about the CoM, body axes
};

// The draws are sequenced (a function call's arguments are evaluated in an unspecified order: GCC goes right to
// left, clang left to right, so the same seed gave the two compilers different trees). They are taken last argument
// first, the order GCC's builds always used, so that the GCC build's random trees are those they were.

/// Three draws of `u` (any distribution), in the order described above: z, then y, then x.
template <class Distribution>
Vector3<double> draw3(Distribution& u, std::mt19937& rng) {
  const double z = u(rng);
  const double y = u(rng);
  const double x = u(rng);
  return Vector3<double>(x, y, z);
}

inline Matrix3<double> random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const double z = n(rng);
  const double y = n(rng);
  const double x = n(rng);
  const double w = n(rng);
  Eigen::Quaterniond qt(w, x, y, z);
  qt.normalize();
  return qt.toRotationMatrix();
}

/// A physically valid rotational inertia about the CoM: principal moments satisfying the triangle inequality,
/// in random principal axes.
inline Matrix3<double> random_inertia_com(std::mt19937& rng, double mass) {
  std::uniform_real_distribution<double> u(0.05, 1.0);
  // Principal moments from a random mass distribution: I1 = b + c, I2 = a + c, I3 = a + b with a, b, c >= 0.
  const double a = u(rng), b = u(rng), c = u(rng);
  Vector3<double> d(b + c, a + c, a + b);
  d *= 0.01 * mass;
  const Matrix3<double> R = random_rotation(rng);
  return R * d.asDiagonal() * R.transpose();
}

/// `n` random bodies: chains (each body's parent is the previous one) or branched trees (random earlier parent),
/// every supported joint type when `all_joint_types`, otherwise revolute joints only.
inline std::vector<RandomBody> random_bodies(int n, Shape shape, unsigned seed, bool all_joint_types = true) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> mass(0.2, 3.0);
  static const JointType all[] = {JointType::RevoluteX,  JointType::RevoluteY,  JointType::RevoluteZ,
                                  JointType::RevoluteAxis, JointType::PrismaticX, JointType::PrismaticY,
                                  JointType::PrismaticZ, JointType::PrismaticAxis};
  static const JointType revolute[] = {JointType::RevoluteX, JointType::RevoluteY, JointType::RevoluteZ,
                                       JointType::RevoluteAxis};
  std::vector<RandomBody> out;
  for (int i = 0; i < n; ++i) {
    RandomBody b;
    b.parent = shape == Shape::Chain || i == 0 ? i - 1 : std::uniform_int_distribution<int>(-1, i - 1)(rng);
    b.type = all_joint_types ? all[std::uniform_int_distribution<int>(0, 7)(rng)]
                             : revolute[std::uniform_int_distribution<int>(0, 3)(rng)];
    b.axis = draw3(u, rng).normalized();
    switch (b.type) {
      case JointType::RevoluteX: case JointType::PrismaticX: b.axis = Vector3<double>::UnitX(); break;
      case JointType::RevoluteY: case JointType::PrismaticY: b.axis = Vector3<double>::UnitY(); break;
      case JointType::RevoluteZ: case JointType::PrismaticZ: b.axis = Vector3<double>::UnitZ(); break;
      default: break;
    }
    const Vector3<double> r = 0.3 * draw3(u, rng);
    b.X_tree = Transform<double>(random_rotation(rng), r);
    b.mass = mass(rng);
    b.com = 0.2 * draw3(u, rng);
    b.inertia_com = random_inertia_com(rng, b.mass);
    out.push_back(b);
  }
  return out;
}

/// Adds random bodies to a builder; bodies are named "body<i>", joints "joint<i>".
inline void add_bodies(ModelBuilder<double>& b, const std::vector<RandomBody>& bodies) {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const RandomBody& r = bodies[i];
    b.add_body("body" + std::to_string(i), r.parent, r.type, r.X_tree,
               Inertia<double>::from_com(r.mass, r.com, r.inertia_com), r.axis, "joint" + std::to_string(i));
  }
}

/// A run-time model from random bodies (`add_bodies`).
inline Model<double> build_model(const std::vector<RandomBody>& bodies, const Vector3<double>& gravity = {0, 0, -9.81}) {
  ModelBuilder<double> b;
  b.set_gravity(gravity);
  add_bodies(b, bodies);
  return b.build();
}

/// The same with three massless frames "frame_on_<body>" at random placements (within 0.4 of the body's origin) on
/// the base (root), the last body and a middle body: frames 0, 1, 2.
inline Model<double> build_model_with_frames(const std::vector<RandomBody>& bodies, unsigned seed,
                                             const Vector3<double>& gravity = {0, 0, -9.81}) {
  ModelBuilder<double> b;
  b.set_gravity(gravity);
  add_bodies(b, bodies);
  std::mt19937 rng(seed + 99);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  const int n = static_cast<int>(bodies.size());
  for (int body : {-1, n - 1, n / 2}) {
    const Matrix3<double> E = random_rotation(rng);
    Vector3<double> r;
    for (int k = 0; k < 3; ++k) r[k] = u(rng);
    b.add_fixed_body("frame_on_" + std::to_string(body), body, Transform<double>(E, r), Inertia<double>::Zero());
  }
  return b.build();
}

inline Model<double> random_model(int n, Shape shape, unsigned seed, bool all_joint_types = true) {
  return build_model(random_bodies(n, shape, seed, all_joint_types));
}

/// A random root-body inertia (mass 1–3 kg, CoM within 0.1 of the origin).
inline Inertia<double> random_root_inertia(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double m = 2.0 + u(rng);
  const Matrix3<double> Ic = random_inertia_com(rng, m);
  return Inertia<double>::from_com(m, 0.1 * draw3(u, rng), Ic);
}

/// A floating-base model: the random tree of `random_model` (every joint type) under a random root body "root".
inline FloatingModel<double> random_floating(int n, Shape shape, unsigned seed,
                                             const Vector3<double>& gravity = {0, 0, -9.81}) {
  std::mt19937 rng(seed + 1000);
  return FloatingModel<double>(build_model(random_bodies(n, shape, seed), gravity), random_root_inertia(rng), "root");
}

/// A random vector of n entries uniform in [-scale, scale].
inline Eigen::VectorXd random_vector(int n, std::mt19937& rng, double scale = 1.0) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = u(rng);
  return v;
}

/// n random spatial forces, each coordinate uniform in [-3, 3].
inline std::vector<Force<double>> random_forces(int n, std::mt19937& rng) {
  std::vector<Force<double>> f;
  for (int i = 0; i < n; ++i) f.emplace_back(Vector6<double>(random_vector(6, rng, 3.0)));
  return f;
}

}  // namespace spatial::testing
