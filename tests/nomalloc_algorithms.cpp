// The algorithms never allocate. Two independent guards watch every call:
//  1. Eigen's run-time check (EIGEN_RUNTIME_NO_MALLOC): with Eigen::internal::set_is_malloc_allowed(false), any
//     heap allocation by an Eigen object fails an eigen_assert and aborts the test binary;
//  2. every replaceable global operator new / new[] (plain, nothrow, aligned, aligned nothrow) is replaced below by
//     a counting version, so that std::vector, std::string, std::function … allocations are seen too.
// The last tests prove that both guards actually fire.
//
// Built as its own executable with -DEIGEN_RUNTIME_NO_MALLOC (and -UNDEBUG: eigen_assert is what reports the
// allocation). Everything is allocated before the guarded region: models, Data, and the inputs as preallocated
// Eigen::VectorXd (run-time model) or fixed-size vectors (compile-time model). Passing an expression that needs a
// temporary would allocate, and is caught.

#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "nomalloc tests must be compiled with -DEIGEN_RUNTIME_NO_MALLOC"
#endif
#ifdef NDEBUG
#error "nomalloc tests need eigen_assert: compile without NDEBUG (-UNDEBUG)"
#endif

#include <spatial/spatial.hpp>

#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <random>
#include <string>
#include <vector>

// ---- counting global allocation functions -------------------------------------------------------------------

namespace {
std::atomic<long> g_new_calls{0};

void* counted_alloc(std::size_t n) {
  ++g_new_calls;
  return std::malloc(n ? n : 1);
}
void* counted_aligned_alloc(std::size_t n, std::align_val_t al) {
  ++g_new_calls;
  const auto a = static_cast<std::size_t>(al);
  const std::size_t size = ((n ? n : 1) + a - 1) / a * a;  // aligned_alloc wants a multiple of the alignment
  return std::aligned_alloc(a, size);
}
// Out of line, so that the compiler does not pair an inlined std::free with the operator new it came through
// (GCC's -Wmismatched-new-delete); memory from both counted_alloc functions is released with std::free.
[[gnu::noinline]] void release(void* p) noexcept { std::free(p); }
void* or_throw(void* p) {
  if (!p) throw std::bad_alloc();
  return p;
}
}  // namespace

/// The count, for the other nomalloc_*.cpp files of this executable.
long spatial_nomalloc_new_calls() { return g_new_calls.load(); }

void* operator new(std::size_t n) { return or_throw(counted_alloc(n)); }
void* operator new[](std::size_t n) { return or_throw(counted_alloc(n)); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n); }
void* operator new(std::size_t n, std::align_val_t al) { return or_throw(counted_aligned_alloc(n, al)); }
void* operator new[](std::size_t n, std::align_val_t al) { return or_throw(counted_aligned_alloc(n, al)); }
void* operator new(std::size_t n, std::align_val_t al, const std::nothrow_t&) noexcept {
  return counted_aligned_alloc(n, al);
}
void* operator new[](std::size_t n, std::align_val_t al, const std::nothrow_t&) noexcept {
  return counted_aligned_alloc(n, al);
}
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete(void* p, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }

namespace {

using namespace spatial;
using Vec = Eigen::VectorXd;
using V3 = Vector3<double>;
using J = JointType;

volatile double g_sink = 0;       // keeps results observable
void* volatile g_ptr_sink = nullptr;  // keeps deliberate allocations observable

/// No Eigen heap allocation and no operator new between construction and destruction.
class NoAllocationRegion {
 public:
  NoAllocationRegion() : before_(g_new_calls.load()) { Eigen::internal::set_is_malloc_allowed(false); }
  ~NoAllocationRegion() { Eigen::internal::set_is_malloc_allowed(true); }
  long new_calls() const { return g_new_calls.load() - before_; }

 private:
  long before_;
};

// Every algorithm, on any model; returns a checksum so nothing is optimised away. Outputs go into preallocated
// vectors of the right size (assigning into them does not reallocate).
template <class S, class T, class V, class Fext>
double run_every_algorithm(const Model<S, T>& model, Data<S, T>& d, const V& q, const V& qd, const V& qdd,
                           const V& tau, const Fext& fext, V& out, V& x) {
  double sum = 0;
  out = rnea(model, d, q, qd, qdd);
  sum += out.sum();
  out = rnea(model, d, q, qd, qdd, fext, ForceFrame::Body);
  sum += out.sum();
  out = rnea(model, d, q, qd, qdd, fext, ForceFrame::Base);
  sum += out.sum();
  out = bias_forces(model, d, q, qd);
  sum += out.sum();
  out = gravity_torques(model, d, q);
  sum += out.sum();
  sum += crba(model, d, q).sum();
  ltdl(model, d);
  x = tau;
  ltdl_solve(model, d, x);
  sum += x.sum();
  out = forward_dynamics_crba(model, d, q, qd, tau);
  sum += out.sum();
  out = aba(model, d, q, qd, tau);
  sum += out.sum();
  out = aba(model, d, q, qd, tau, fext, ForceFrame::Body);
  sum += out.sum();
  out = aba(model, d, q, qd, tau, fext, ForceFrame::Base);
  sum += out.sum();
  // The compile-time options (options.hpp).
  out = rnea<Dyn::Static>(model, d, q, qd, qdd);
  sum += out.sum();
  out = rnea<Dyn::QuasiStatic | Dyn::BaseForces>(model, d, q, qd, qdd, fext, ForceFrame::Base);
  sum += out.sum() + d.f[0].n.sum();
  out = rnea<Dyn::NoGravity | Dyn::BaseForces>(model, d, q, qd, qdd, fext, ForceFrame::Body);
  sum += out.sum() + d.f[0].f.sum();
  out = aba<Dyn::Static>(model, d, q, qd, tau);
  sum += out.sum();
  out = aba<Dyn::Velocity>(model, d, q, qd, tau, fext, ForceFrame::Base);
  sum += out.sum();
  out = aba<Dyn::None>(model, d, q, qd, tau, fext, ForceFrame::Body);
  sum += out.sum();
  out = forward_dynamics_crba<Dyn::Static>(model, d, q, qd, tau);
  sum += out.sum();
  out = forward_dynamics_crba<Dyn::None>(model, d, q, qd, tau);
  sum += out.sum();
  forward_kinematics(model, d, q);
  sum += body_pose(d, model.size() - 1).translation().sum();
  for (int k = 0; k < static_cast<int>(model.frames().size()); ++k) sum += frame_pose(model, d, k).translation().sum();
  forward_velocities(model, d, q, qd);
  sum += kinetic_energy(model, d, q, qd);
  sum += potential_energy(model, d, q);
  sum += center_of_mass(model, d, q).sum();
  // Input checks (checks.hpp) and the checked entry points.
  sum += check_finite(model, q, qd, qdd).ok() ? 1 : 0;
  sum += rnea_checked(model, d, q, qd, qdd).ok() ? 1 : 0;
  sum += aba_checked(model, d, q, qd, tau).ok() ? 1 : 0;
  sum += forward_dynamics_crba_checked(model, d, q, qd, tau).ok() ? 1 : 0;
  return sum;
}

TEST(NoMalloc, RunTimeModel) {
  ModelBuilder<double> b;
  const auto bodies = spatial::testing::random_bodies(13, spatial::testing::Shape::Branched, 5);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const auto& r = bodies[i];
    b.add_body("body" + std::to_string(i), r.parent, r.type, r.X_tree,
               Inertia<double>::from_com(r.mass, r.com, r.inertia_com), r.axis);
  }
  b.add_fixed_body("tool", 12, xlt(V3(0.1, 0, 0)), Inertia<double>::from_com(0.2, V3::Zero(), Matrix3<double>::Zero()));
  const Model<double> model = b.build();
  Data<double> d(model);
  const int n = model.size();
  std::mt19937 rng(1);
  const Vec q = spatial::testing::random_vector(n, rng), qd = spatial::testing::random_vector(n, rng),
            qdd = spatial::testing::random_vector(n, rng), tau = spatial::testing::random_vector(n, rng);
  std::vector<Force<double>> fext(static_cast<std::size_t>(n), Force<double>(V3(1, 2, 3), V3(-1, 0.5, 2)));
  Vec out(n), x(n);
  double sum = 0;
  long news = 0;
  {
    NoAllocationRegion guard;
    for (int rep = 0; rep < 3; ++rep) sum += run_every_algorithm(model, d, q, qd, qdd, tau, fext, out, x);
    news = guard.new_calls();
  }
  g_sink = sum;
  EXPECT_EQ(news, 0) << "operator new was called inside the algorithms";
  EXPECT_TRUE(std::isfinite(sum));
}

// A tree with spherical joints and a free-flyer under its root (general.hpp): every algorithm there, twice.
TEST(NoMalloc, GeneralModelWithSphericalJoints) {
  const auto bodies = spatial::testing::random_bodies(9, spatial::testing::Shape::Branched, 8);
  GeneralModel<double> model;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const auto& r = bodies[i];
    const GeneralJoint<double> j = i == 0   ? GeneralJoint<double>::free_flyer()
                                   : i % 3 == 1 ? GeneralJoint<double>::spherical()
                                                : GeneralJoint<double>::one_dof(r.type, r.axis);
    model.add_body(r.parent, j, r.X_tree, Inertia<double>::from_com(r.mass, r.com, r.inertia_com),
                   "joint" + std::to_string(i), "body" + std::to_string(i));
  }
  GeneralData<double> d(model);
  std::mt19937 rng(2);
  const Vec lo = Vec::Constant(model.nq(), -1.0), hi = Vec::Constant(model.nq(), 1.0);
  const Vec q = random_configuration(model, lo, hi, rng);
  const int nv = model.nv();
  const Vec v = spatial::testing::random_vector(nv, rng), a = spatial::testing::random_vector(nv, rng),
            tau = spatial::testing::random_vector(nv, rng);
  std::vector<Force<double>> fext(bodies.size(), Force<double>(V3(1, 2, 3), V3(-1, 0.5, 2)));
  Vec q1(model.nq()), dv(nv);
  Eigen::MatrixXd Jb(6, nv), Jc(3, nv);
  double sum = 0;
  long news = 0;
  {
    NoAllocationRegion guard;
    for (int rep = 0; rep < 2; ++rep) {
      sum += rnea(model, d, q, v, a).sum() + rnea(model, d, q, v, a, fext, ForceFrame::Base).sum();
      sum += bias_forces(model, d, q, v).sum() + gravity_torques(model, d, q).sum();
      sum += crba(model, d, q).sum();
      sum += aba(model, d, q, v, tau).sum() + aba(model, d, q, v, tau, fext).sum();
      forward_kinematics(model, d, q, v);
      body_jacobian(model, d, 8, ReferenceFrame::LocalWorldAligned, Jb);
      sum += Jb.sum() + kinetic_energy(model, d) + potential_energy(model, d) + center_of_mass(model, d).sum();
      com_jacobian(model, d, Jc);
      sum += Jc.sum();
      integrate(model, q, v, 0.01, q1);
      difference(model, q, q1, dv);
      sum += dv.sum();
    }
    news = guard.new_calls();
  }
  g_sink = sum;
  EXPECT_EQ(news, 0) << "operator new was called inside the algorithms";
  EXPECT_TRUE(std::isfinite(sum));
}

using Tree8 = Tree<Parents<-1, 0, 1, 1, 0, 4, 5, 2>,
                   Joints<J::RevoluteX, J::RevoluteY, J::RevoluteZ, J::RevoluteAxis, J::PrismaticX, J::PrismaticY,
                          J::PrismaticZ, J::PrismaticAxis>>;

TEST(NoMalloc, CompileTimeModel) {
  auto bodies = spatial::testing::random_bodies(8, spatial::testing::Shape::Chain, 6);
  for (int i = 0; i < 8; ++i) {
    auto& r = bodies[static_cast<std::size_t>(i)];
    r.parent = Tree8::parent[static_cast<std::size_t>(i)];
    r.type = Tree8::joint[static_cast<std::size_t>(i)];
    if (r.type == J::RevoluteX || r.type == J::PrismaticX) r.axis = V3::UnitX();
    if (r.type == J::RevoluteY || r.type == J::PrismaticY) r.axis = V3::UnitY();
    if (r.type == J::RevoluteZ || r.type == J::PrismaticZ) r.axis = V3::UnitZ();
  }
  const Model<double, Tree8> model = Model<double, Tree8>::from(spatial::testing::build_model(bodies));
  Data<double, Tree8> d(model);
  using V8 = Data<double, Tree8>::VectorN;
  static_assert(V8::RowsAtCompileTime == 8, "fixed-size joint vectors");
  std::mt19937 rng(2);
  const V8 q = spatial::testing::random_vector(8, rng), qd = spatial::testing::random_vector(8, rng),
           qdd = spatial::testing::random_vector(8, rng), tau = spatial::testing::random_vector(8, rng);
  std::array<Force<double>, 8> fext;
  fext.fill(Force<double>(V3(0.5, -1, 0.25), V3(2, 1, -1)));
  V8 out, x;
  double sum = 0;
  long news = 0;
  {
    NoAllocationRegion guard;
    for (int rep = 0; rep < 3; ++rep) sum += run_every_algorithm(model, d, q, qd, qdd, tau, fext, out, x);
    news = guard.new_calls();
  }
  g_sink = sum;
  EXPECT_EQ(news, 0) << "operator new was called inside the algorithms";
  EXPECT_TRUE(std::isfinite(sum));
}

// The compile-time model with dynamic-size inputs (e.g. vectors from a simulator): still no allocation.
// A model reduced by lock_joints (reduce.hpp; the reduction itself runs before the guard) and the q mapping.
TEST(NoMalloc, ReducedModel) {
  const Model<double> full = spatial::testing::random_model(12, spatial::testing::Shape::Branched, 9);
  const ReducedModel<double> red = lock_joints(full, {{2, 0.3}, {"joint5", -0.2}, {11, 0.1}});
  const Model<double>& model = red.model;
  Data<double> d(model);
  const int n = model.size();
  std::mt19937 rng(3);
  const Vec q_full = spatial::testing::random_vector(full.size(), rng);
  Vec q(n);
  const Vec qd = spatial::testing::random_vector(n, rng), qdd = spatial::testing::random_vector(n, rng),
            tau = spatial::testing::random_vector(n, rng);
  std::vector<Force<double>> fext(static_cast<std::size_t>(n), Force<double>(V3(1, 0, 3), V3(0, 0.5, 2)));
  Vec out(n), x(n), back = Vec::Zero(full.size());
  double sum = 0;
  long news = 0;
  {
    NoAllocationRegion guard;
    red.gather(q_full, q);
    for (int rep = 0; rep < 2; ++rep) sum += run_every_algorithm(model, d, q, qd, qdd, tau, fext, out, x);
    red.scatter(out, back);
    sum += back.sum();
    news = guard.new_calls();
  }
  g_sink = sum;
  EXPECT_EQ(news, 0) << "operator new was called inside the algorithms";
  EXPECT_TRUE(std::isfinite(sum));
}

TEST(NoMalloc, CompileTimeModelWithDynamicInputs) {
  auto bodies = spatial::testing::random_bodies(8, spatial::testing::Shape::Chain, 7);
  for (int i = 0; i < 8; ++i) {
    auto& r = bodies[static_cast<std::size_t>(i)];
    r.parent = Tree8::parent[static_cast<std::size_t>(i)];
    r.type = Tree8::joint[static_cast<std::size_t>(i)];
    if (r.type == J::RevoluteX || r.type == J::PrismaticX) r.axis = V3::UnitX();
    if (r.type == J::RevoluteY || r.type == J::PrismaticY) r.axis = V3::UnitY();
    if (r.type == J::RevoluteZ || r.type == J::PrismaticZ) r.axis = V3::UnitZ();
  }
  const Model<double, Tree8> model = Model<double, Tree8>::from(spatial::testing::build_model(bodies));
  Data<double, Tree8> d(model);
  std::mt19937 rng(3);
  const Vec q = spatial::testing::random_vector(8, rng), qd = spatial::testing::random_vector(8, rng),
            qdd = spatial::testing::random_vector(8, rng), tau = spatial::testing::random_vector(8, rng);
  std::vector<Force<double>> fext(8, Force<double>(V3(0.5, -1, 0.25), V3(2, 1, -1)));
  Vec out(8), x(8);
  double sum = 0;
  long news = 0;
  {
    NoAllocationRegion guard;
    sum += run_every_algorithm(model, d, q, qd, qdd, tau, fext, out, x);
    news = guard.new_calls();
  }
  g_sink = sum;
  EXPECT_EQ(news, 0);
  EXPECT_TRUE(std::isfinite(sum));
}

// kinematics.hpp on fixed and floating bases: Jacobians, J̇, drifts, velocities and accelerations in the three
// reference frames, into a preallocated 6 × nv matrix (`frame` < 0: the model has no frame).
template <class M, class D, class Q, class V, class Out>
double run_kinematics(const M& model, D& d, const Q& q, const V& v, const V& a, Out& J, int body, int frame) {
  double sum = compute_joint_jacobians(model, d, q).sum();
  sum += compute_joint_jacobians_time_variation(model, d, q, v).sum();
  for (ReferenceFrame rf : {ReferenceFrame::Local, ReferenceFrame::World, ReferenceFrame::LocalWorldAligned}) {
    body_jacobian(model, d, body, rf, J);
    sum += J.sum();
    body_jacobian_time_variation(model, d, body, rf, J);
    sum += J.sum();
    compute_body_jacobian(model, d, q, body, rf, J);
    sum += J.sum();
    if (frame >= 0) {
      frame_jacobian(model, d, frame, rf, J);
      sum += J.sum();
      frame_jacobian_time_variation(model, d, frame, rf, J);
      sum += J.sum();
      compute_frame_jacobian(model, d, q, frame, rf, J);
      sum += J.sum();
      sum += frame_jdot_qdot(model, d, q, v, frame, rf).v.sum() + frame_classical_jdot_qdot(model, d, q, v, frame, rf).sum();
    }
    forward_kinematics(model, d, q, v, a);
    sum += body_velocity(model, d, body, rf).w.sum() + body_acceleration(model, d, body, rf).v.sum() +
           body_classical_acceleration(model, d, body, rf).sum();
    if (frame >= 0)
      sum += frame_velocity(model, d, frame, rf).v.sum() + frame_acceleration(model, d, frame, rf).w.sum() +
             frame_classical_acceleration(model, d, frame, rf).sum();
  }
  return sum;
}

// centroidal.hpp on fixed and floating bases: CoM with velocity and acceleration, subtree CoM, CoM Jacobians, A_G,
// h_G, ḣ_G, I_G, into preallocated 3 × nv and 6 × nv matrices.
template <class M, class D, class Q, class V, class J3, class J6>
double run_centroidal(const M& model, D& d, const Q& q, const V& v, const V& a, J3& Jc, J6& Ag, int body) {
  double sum = center_of_mass(model, d, q, v, a).sum() + d.vcom.sum() + d.acom.sum();
  sum += subtree_center_of_mass(model, d, q, body).com.sum();
  com_jacobian(model, d, q, Jc);
  sum += Jc.sum();
  subtree_com_jacobian(model, d, q, body, Jc);
  sum += Jc.sum();
  centroidal_momentum_matrix(model, d, q, Ag);
  sum += Ag.sum() + centroidal_momentum(model, d, q, v).sum();
  const auto r = centroidal_momentum_time_variation(model, d, q, v, a);
  sum += r.dhg.sum() + r.dAg_v.sum() + centroidal_composite_inertia(model, d, q).sum();
  return sum;
}

TEST(NoMalloc, Kinematics) {
  // Run-time fixed and floating bases with a frame, and the compile-time Tree8 on a floating base.
  ModelBuilder<double> b;
  const auto bodies = spatial::testing::random_bodies(9, spatial::testing::Shape::Branched, 8);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const auto& r = bodies[i];
    b.add_body("body" + std::to_string(i), r.parent, r.type, r.X_tree,
               Inertia<double>::from_com(r.mass, r.com, r.inertia_com), r.axis);
  }
  b.add_fixed_body("tool", 8, xlt(V3(0.1, 0, 0)), Inertia<double>::from_com(0.2, V3::Zero(), Matrix3<double>::Zero()));
  const Model<double> model = b.build();
  const Inertia<double> I0 = Inertia<double>::from_com(2.0, V3(0.1, 0, 0), 0.1 * Matrix3<double>::Identity());
  const FloatingModel<double> fmodel(model, I0);
  auto bodies8 = spatial::testing::random_bodies(8, spatial::testing::Shape::Chain, 6);
  for (int i = 0; i < 8; ++i) {
    auto& r = bodies8[static_cast<std::size_t>(i)];
    r.parent = Tree8::parent[static_cast<std::size_t>(i)];
    r.type = Tree8::joint[static_cast<std::size_t>(i)];
    if (r.type == J::RevoluteX || r.type == J::PrismaticX) r.axis = V3::UnitX();
    if (r.type == J::RevoluteY || r.type == J::PrismaticY) r.axis = V3::UnitY();
    if (r.type == J::RevoluteZ || r.type == J::PrismaticZ) r.axis = V3::UnitZ();
  }
  const FloatingModel<double, Tree8> cmodel(Model<double, Tree8>::from(spatial::testing::build_model(bodies8)), I0);
  Data<double> d(model);
  FloatingData<double> fd(fmodel);
  FloatingData<double, Tree8> cd(cmodel);
  std::mt19937 rng(4);
  const Vec q = spatial::testing::random_vector(9, rng), v = spatial::testing::random_vector(9, rng),
            a = spatial::testing::random_vector(9, rng);
  Vec fq = spatial::testing::random_vector(fmodel.nq(), rng);
  fq.segment<4>(3).normalize();
  const Vec fv = spatial::testing::random_vector(fmodel.nv(), rng), fa = spatial::testing::random_vector(fmodel.nv(), rng);
  using Q8 = FloatingModel<double, Tree8>::ConfigVector;
  using V8 = FloatingModel<double, Tree8>::TangentVector;
  Q8 cq = spatial::testing::random_vector(15, rng);
  cq.segment<4>(3).normalize();
  const V8 cv = spatial::testing::random_vector(14, rng), ca = spatial::testing::random_vector(14, rng);
  Eigen::MatrixXd J(6, 9), fJ(6, 15);
  Eigen::Matrix<double, 6, 14> cJ;
  Eigen::MatrixXd J3(3, 9), fJ3(3, 15);
  Eigen::Matrix<double, 3, 14> cJ3;
  double sum = 0;
  long news = 0;
  {
    NoAllocationRegion guard;
    sum += run_kinematics(model, d, q, v, a, J, 8, 0);
    sum += run_kinematics(model, d, q, v, a, J, -1, 0);
    sum += run_kinematics(fmodel, fd, fq, fv, fa, fJ, 8, 0);
    sum += run_kinematics(fmodel, fd, fq, fv, fa, fJ, -1, 0);
    sum += run_kinematics(cmodel, cd, cq, cv, ca, cJ, 7, -1);
    sum += run_centroidal(model, d, q, v, a, J3, J, 4);
    sum += run_centroidal(fmodel, fd, fq, fv, fa, fJ3, fJ, 4);
    sum += run_centroidal(cmodel, cd, cq, cv, ca, cJ3, cJ, 3);
    news = guard.new_calls();
  }
  g_sink = sum;
  EXPECT_EQ(news, 0) << "operator new was called inside the kinematics";
  EXPECT_TRUE(std::isfinite(sum));
}

// ---- the guards themselves ---------------------------------------------------------------------------------

TEST(NoMallocGuard, EigenAllocationInsideTheRegionAborts) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(
      {
        Eigen::internal::set_is_malloc_allowed(false);
        Eigen::VectorXd v(1000);  // a heap allocation by Eigen
        v.setOnes();
        g_sink = v.sum();
      },
      "heap allocation is forbidden");
  // And an expression that needs a temporary, passed to an algorithm.
  const Model<double> model = spatial::testing::random_model(5, spatial::testing::Shape::Chain, 8);
  Data<double> d(model);
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(5, 5);
  const Vec q = Vec::Ones(5);
  EXPECT_DEATH(
      {
        Eigen::internal::set_is_malloc_allowed(false);
        g_sink = rnea(model, d, A * q, q, q).sum();  // A * q is evaluated into a heap temporary
      },
      "heap allocation is forbidden");
}

TEST(NoMallocGuard, CounterSeesEveryAllocationFunction) {
  struct alignas(64) Overaligned {
    double x[8];
  };
  const long c0 = g_new_calls.load();
  void* p = ::operator new(24);
  g_ptr_sink = p;
  ::operator delete(p);
  EXPECT_EQ(g_new_calls.load(), c0 + 1) << "operator new(size_t)";
  int* arr = new int[16];
  g_ptr_sink = arr;
  delete[] arr;
  EXPECT_EQ(g_new_calls.load(), c0 + 2) << "operator new[](size_t)";
  Overaligned* o = new Overaligned;
  g_ptr_sink = o;
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(o) % 64, 0u);
  delete o;
  EXPECT_EQ(g_new_calls.load(), c0 + 3) << "operator new(size_t, align_val_t)";
  Overaligned* oa = new Overaligned[3];
  g_ptr_sink = oa;
  delete[] oa;
  EXPECT_EQ(g_new_calls.load(), c0 + 4) << "operator new[](size_t, align_val_t)";
  int* nt = new (std::nothrow) int(5);
  g_ptr_sink = nt;
  delete nt;
  EXPECT_EQ(g_new_calls.load(), c0 + 5) << "operator new(size_t, nothrow_t)";
  Overaligned* ont = new (std::nothrow) Overaligned;
  g_ptr_sink = ont;
  delete ont;
  EXPECT_EQ(g_new_calls.load(), c0 + 6) << "operator new(size_t, align_val_t, nothrow_t)";
  // A standard container in a guarded region is seen by the counter (the Eigen check ignores it).
  long news = 0;
  {
    NoAllocationRegion guard;
    std::vector<double> v(100, 1.0);
    g_ptr_sink = v.data();
    news = guard.new_calls();
  }
  EXPECT_EQ(news, 1);
}

}  // namespace
