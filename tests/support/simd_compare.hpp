#pragma once
// Shared by the AVX2 kernel tests (tests/simd_*.cpp, built with -mavx2 -mfma): trees of revolute joints about
// coordinate axes, the comparison bound, random compile-time models.
#include <spatial/models/hoap3_double_pendulum.hpp>
#include <spatial/models/hoap3_stance_left.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/models/hoap3_torso.hpp>
#include <spatial/spatial.hpp>

#include "support/compile_time_trees.hpp"
#include "support/random_model.hpp"
#include "support/reference.hpp"
#include "support/static_trees.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <type_traits>

// SPATIAL_SIMD_TEST_ALL_TREES (= SPATIAL_TEST_COMPILE_TIME_TREES): 1 in the release build, where the kernels run on
// every HOAP-3 model and both random shapes; 0 in the sanitizer build, where each kernel is one large unrolled
// instantiation per tree and per term combination compiled unoptimised and instrumented (the three heaviest files
// took ~9 CPU minutes there): the fixed-base kernels run on hoap3_stance_right, Rev9 (two roots, branches, every
// axis) and RevChain24 (deeper than any HOAP-3 branch), the floating-base ones on hoap3_floating and Rev9. The other
// HOAP-3 models run the same kernels on smaller and shallower trees.
//
// Every combination of RNEA's terms (gravity, velocity, acceleration) and of ABA's runs on Rev9 in both builds, and
// in the release build on the reference model hoap3_stance_right too (kEveryTermCombination); every other tree runs
// all terms at once. A term is an `if constexpr` branch of the kernel's per-body step, the same code on every tree,
// while each combination on each tree is one more large unrolled instantiation of it, which takes no path that Rev9
// and stance_right (whose tree type hoap3_stance_left shares) do not take.
#define SPATIAL_SIMD_TEST_ALL_TREES SPATIAL_TEST_COMPILE_TIME_TREES

#if !SPATIAL_SIMD_AVX2
#error "the simd_*.cpp tests must be compiled with AVX2 and FMA (tests/CMakeLists.txt adds -mavx2 -mfma)"
#endif

namespace spatial::testing::simd {

using namespace spatial;
namespace static_trees = spatial::testing::static_trees;
using J = JointType;

// Revolute joints about coordinate axes only: two roots, branches, every axis.
using Rev9 = Tree<Parents<-1, 0, 1, 0, 3, -1, 5, 2, 2>,
                  Joints<J::RevoluteX, J::RevoluteY, J::RevoluteZ, J::RevoluteZ, J::RevoluteX, J::RevoluteY,
                         J::RevoluteZ, J::RevoluteX, J::RevoluteY>>;
constexpr JointType kAxes[3] = {J::RevoluteZ, J::RevoluteX, J::RevoluteY};
template <std::size_t... I>
auto make_chain(std::index_sequence<I...>) -> Tree<Parents<(static_cast<int>(I) - 1)...>, Joints<kAxes[I % 3]...>>;
// A chain deeper than any branch of the reference models (every H entry of it is an ancestor pair).
using RevChain24 = decltype(make_chain(std::make_index_sequence<24>{}));

/// Whether the kernel tests run every combination of RNEA's (and ABA's) terms on TreeT in scalar S, or only all of
/// them at once (see SPATIAL_SIMD_TEST_ALL_TREES): on Rev9 always, on hoap3_stance_right in double in the release
/// build. float runs the same kernels over the same memory layout (four floats per 128-bit register).
template <class TreeT, class S = double>
inline constexpr bool kEveryTermCombination =
    std::is_same_v<TreeT, Rev9> ||
    (SPATIAL_SIMD_TEST_ALL_TREES && std::is_same_v<S, double> &&
     std::is_same_v<TreeT, models::hoap3_stance_right::Tree>);

static_assert(detail::simd_enabled<double, Rev9>());
static_assert(detail::simd_enabled<double, models::hoap3_stance_right::Tree>());
static_assert(detail::simd_enabled<float, Rev9>(), "float takes the same kernels (four floats in 128-bit registers)");
static_assert(!detail::simd_enabled<double, DynamicTree>() && detail::simd_candidate<double, DynamicTree>(),
              "run-time trees take the kernels when simd_applies says so, per call (simd_runtime.cpp)");
static_assert(!detail::simd_enabled<double, static_trees::Branched8>(), "other joint types: scalar path");

/// The number of bodies on the longest path from a root, of n bodies with parent(j) (−1 for a root).
template <class Parent>
int tree_depth(int n, Parent parent) {
  int d = 0;
  for (int i = 0; i < n; ++i) {
    int k = 0;
    for (int j = i; j >= 0; j = parent(j)) ++k;
    d = std::max(d, k);
  }
  return d;
}
template <class TreeT>
int depth() {
  return tree_depth(TreeT::size, [](int j) { return TreeT::parent[static_cast<std::size_t>(j)]; });
}

/// Both paths evaluate the same expressions in a different order (and with fused multiply–adds), so every output
/// may differ by a few roundings per level of the tree relative to the largest value it is built from: the bound
/// is 16 (depth + 1) u times the largest magnitude of that output over all bodies (u of the scalar S).
template <class TreeT, class S = double>
double tolerance() {
  return 16.0 * (depth<TreeT>() + 1) * double(std::numeric_limits<S>::epsilon());
}
/// The same bound from a model's own parents (compile-time tree or not).
template <class M, class S = double>
double tolerance_of(const M& model) {
  return 16.0 * (tree_depth(model.size(), [&](int j) { return model.parent(j); }) + 1) *
         double(std::numeric_limits<S>::epsilon());
}

template <class TreeT, class S = double>
struct Compare {
  double tol = tolerance<TreeT, S>();
  Compare() = default;
  explicit Compare(double t) : tol(t) {}
  template <class A, class B>
  void operator()(const char* what, int body, const Eigen::MatrixBase<A>& simd, const Eigen::MatrixBase<B>& scalar,
                  double scale) const {
    const double diff = double((simd - scalar).cwiseAbs().maxCoeff());
    EXPECT_LE(diff, tol * std::max(scale, 1.0)) << what << " of body " << body << "\nsimd:   " << simd.transpose()
                                                << "\nscalar: " << scalar.transpose();
  }
};

template <class TreeT>
Model<double, TreeT> random_static(unsigned seed) {
  return Model<double, TreeT>::from(spatial::testing::build_model(static_trees::bodies_for<TreeT>(seed)));
}

/// The root body of the floating-base trees of these tests (2 kg, CoM off the origin, unequal principal moments).
inline Inertia<double> test_root_inertia() {
  return Inertia<double>::from_com(2.0, Vector3<double>(0.1, -0.05, 0.02),
                                   Vector3<double>(0.02, 0.03, 0.04).asDiagonal());
}

/// The run-time twin of `m` with every RevoluteX/Y/Z joint written as a RevoluteAxis joint about the same unit
/// axis: the same model (numbers, names, frames, base mass, gravity) that `simd_applies` refuses, so every call on
/// it takes the scalar path with the general-axis joint code — a reference independent of the kernels, for
/// compile-time trees and for run-time trees (which take the kernels).
template <class S, class T>
Model<S> scalar_twin(const Model<S, T>& m) {
  ModelBuilder<S> b;
  b.set_gravity(m.gravity());
  for (int i = 0; i < m.size(); ++i) {
    const JointType t = m.joint_type(i);
    const int axis = detail::revolute_axis(t);
    b.add_body(m.body_name(i), m.parent(i), axis >= 0 ? JointType::RevoluteAxis : t, m.tree_transform(i),
               m.inertia(i), axis >= 0 ? Vector3<S>(Vector3<S>::Unit(axis)) : m.axis(i), m.joint_name(i));
  }
  Model<S> out = b.build();
  detail::ModelAccess::frames(out) = m.frames();
  detail::ModelAccess::base_mass(out) = m.base_mass();
  EXPECT_FALSE(detail::simd_applies(out));
  return out;
}
template <class S, class T>
FloatingModel<S> scalar_twin(const FloatingModel<S, T>& m) {
  return FloatingModel<S>(scalar_twin(m.tree()), m.root_inertia(), m.root_name());
}

}  // namespace spatial::testing::simd
