#pragma once
// Compile-time trees of every joint type (branched, two roots, chains of 12 and 66 bodies) and the comparison of
// every algorithm on a compile-time tree against its run-time twin. Shared by test_properties.cpp (Model::from input
// checks), test_static_trees.cpp and test_static_chain66.cpp (split so that the heavy instantiations compile in
// parallel).

#include <spatial/spatial.hpp>

#include "random_model.hpp"
#include "reference.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace spatial::testing {

/// Worst values seen across a test suite, printed at the end of it.
struct Worst {
  std::vector<std::pair<std::string, double>> items;
  void note(const std::string& what, double v) {
    for (auto& it : items)
      if (it.first == what) {
        it.second = std::max(it.second, v);
        return;
      }
    items.emplace_back(what, v);
  }
  void print(const char* title) const {
    std::printf("  %s, largest observed:\n", title);
    for (const auto& it : items) std::printf("    %-56s %.3e\n", it.first.c_str(), it.second);
  }
};

namespace static_trees {

using Vec = Eigen::VectorXd;
using V3 = Vector3<double>;


using J = JointType;
// 8 bodies, branched, one of every joint type (body: parent): 0: base, 1: 0, 2: 1, 3: 1, 4: 0, 5: 4, 6: 5, 7: 2.
using Branched8 = Tree<Parents<-1, 0, 1, 1, 0, 4, 5, 2>,
                       Joints<J::RevoluteX, J::RevoluteY, J::RevoluteZ, J::RevoluteAxis, J::PrismaticX, J::PrismaticY,
                              J::PrismaticZ, J::PrismaticAxis>>;
// 7 bodies, two branches from the root and a second root, mixed joints.
using Branched7 = Tree<Parents<-1, 0, 0, 1, 2, -1, 5>,
                       Joints<J::RevoluteZ, J::RevoluteAxis, J::PrismaticAxis, J::RevoluteY, J::RevoluteX,
                              J::PrismaticZ, J::RevoluteAxis>>;
// 12-body chain cycling through the joint types.
using Chain12 = Tree<Parents<-1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10>,
                     Joints<J::RevoluteZ, J::RevoluteY, J::RevoluteAxis, J::PrismaticX, J::RevoluteX, J::RevoluteZ,
                            J::PrismaticAxis, J::RevoluteY, J::RevoluteAxis, J::PrismaticZ, J::RevoluteX,
                            J::PrismaticY>>;
// A 66-body chain: above kMaxFixedMatrixSize, so H and L are dynamic-size even for a compile-time tree.
constexpr JointType kCycle[8] = {J::RevoluteZ, J::RevoluteAxis, J::RevoluteY, J::PrismaticAxis,
                                 J::RevoluteX, J::RevoluteZ,    J::PrismaticX, J::RevoluteAxis};
template <std::size_t... I>
auto make_chain(std::index_sequence<I...>) -> Tree<Parents<(static_cast<int>(I) - 1)...>, Joints<kCycle[I % 8]...>>;
using Chain66 = decltype(make_chain(std::make_index_sequence<66>{}));
static_assert(Chain66::size == 66 && Chain66::size > kMaxFixedMatrixSize);

/// Random bodies with the topology and joint types of a compile-time tree.
template <class TreeT>
std::vector<spatial::testing::RandomBody> bodies_for(unsigned seed) {
  auto bodies = spatial::testing::random_bodies(TreeT::size, spatial::testing::Shape::Chain, seed, true);
  for (int i = 0; i < TreeT::size; ++i) {
    auto& b = bodies[static_cast<std::size_t>(i)];
    b.parent = TreeT::parent[static_cast<std::size_t>(i)];
    b.type = TreeT::joint[static_cast<std::size_t>(i)];
    switch (b.type) {
      case J::RevoluteX: case J::PrismaticX: b.axis = V3::UnitX(); break;
      case J::RevoluteY: case J::PrismaticY: b.axis = V3::UnitY(); break;
      case J::RevoluteZ: case J::PrismaticZ: b.axis = V3::UnitZ(); break;
      default: break;
    }
  }
  return bodies;
}

struct StaticComparison {
  double max_rel = 0;
  int compared = 0, exact = 0;
  template <class A, class B>
  void operator()(const char* what, const Eigen::MatrixBase<A>& st, const Eigen::MatrixBase<B>& dyn) {
    ++compared;
    if ((st.template cast<double>() - dyn.template cast<double>()).cwiseAbs().maxCoeff() == 0.0) ++exact;
    const double e = rel_diff(st, dyn, 1e-300);
    EXPECT_LE(e, 1e-14) << what;
    max_rel = std::max(max_rel, e);
  }
  void operator()(const char* what, double st, double dyn) {
    Eigen::Matrix<double, 1, 1> a, b;
    a << st;
    b << dyn;
    (*this)(what, a, b);
  }
};

/// Every algorithm on a compile-time tree against the same algorithm on its run-time twin (≤ 1e-14 relative; most
/// results are bit-identical); the largest difference and the count of non-identical results go to `worst`.
/// `Full = false` compares only RNEA, CRBA, LTDL and both forward dynamics (the code paths that change with the
/// size of the tree), which keeps the instantiations for a large tree affordable to compile.
template <class TreeT, bool Full = true>
void compare_static_and_dynamic(unsigned seed, Worst& worst) {
  constexpr int N = TreeT::size;
  const Model<double> md = spatial::testing::build_model(bodies_for<TreeT>(seed));
  const Model<double, TreeT> ms = Model<double, TreeT>::from(md);
  ASSERT_EQ(ms.size(), N);
  for (int i = 0; i < N; ++i) {
    EXPECT_EQ(ms.parent(i), md.parent(i));
    EXPECT_EQ(ms.joint_type(i), md.joint_type(i));
    EXPECT_EQ(ms.body_name(i), md.body_name(i));
    EXPECT_EQ(ms.joint_name(i), md.joint_name(i));
  }
  Data<double> dd(md);
  Data<double, TreeT> ds(ms);
  std::mt19937 rng(seed);
  const Vec q = spatial::testing::random_vector(N, rng, 2.0), qd = spatial::testing::random_vector(N, rng),
            qdd = spatial::testing::random_vector(N, rng), tau = spatial::testing::random_vector(N, rng, 5.0);
  std::vector<Force<double>> fext;
  for (int i = 0; i < N; ++i) fext.emplace_back(V3(spatial::testing::random_vector(3, rng)), V3(spatial::testing::random_vector(3, rng)));
  // Fixed-size inputs for the compile-time model (the Data's own vector type).
  using VN = typename Data<double, TreeT>::VectorN;
  const VN qs = q, qds = qd, qdds = qdd, taus = tau;
  StaticComparison cmp;

  cmp("rnea", rnea(ms, ds, qs, qds, qdds), rnea(md, dd, q, qd, qdd));
  if constexpr (Full) {
    cmp("rnea fext body", rnea(ms, ds, qs, qds, qdds, fext, ForceFrame::Body),
        rnea(md, dd, q, qd, qdd, fext, ForceFrame::Body));
    cmp("rnea fext base", rnea(ms, ds, qs, qds, qdds, fext, ForceFrame::Base),
        rnea(md, dd, q, qd, qdd, fext, ForceFrame::Base));
    cmp("bias_forces", bias_forces(ms, ds, qs, qds), bias_forces(md, dd, q, qd));
    cmp("gravity_torques", gravity_torques(ms, ds, qs), gravity_torques(md, dd, q));
  }
  cmp("crba", crba(ms, ds, qs), crba(md, dd, q));
  ltdl(ms, ds);
  ltdl(md, dd);
  cmp("ltdl", ds.L, dd.L);
  VN xs = taus;
  Vec xd = tau;
  ltdl_solve(ms, ds, xs);
  ltdl_solve(md, dd, xd);
  cmp("ltdl_solve", xs, xd);
  cmp("forward_dynamics_crba", forward_dynamics_crba(ms, ds, qs, qds, taus), forward_dynamics_crba(md, dd, q, qd, tau));
  cmp("aba", aba(ms, ds, qs, qds, taus), aba(md, dd, q, qd, tau));
  if constexpr (Full) {
    cmp("aba fext body", aba(ms, ds, qs, qds, taus, fext, ForceFrame::Body), aba(md, dd, q, qd, tau, fext, ForceFrame::Body));
    cmp("aba fext base", aba(ms, ds, qs, qds, taus, fext, ForceFrame::Base), aba(md, dd, q, qd, tau, fext, ForceFrame::Base));
    // The same algorithms on the compile-time model with dynamic-size inputs.
    cmp("rnea (VectorXd inputs)", rnea(ms, ds, q, qd, qdd), rnea(md, dd, q, qd, qdd));
    forward_kinematics(ms, ds, qs);
    forward_kinematics(md, dd, q);
    for (int i = 0; i < N; ++i) {
      cmp("X_base.E", ds.X_base[static_cast<std::size_t>(i)].E, dd.X_base[static_cast<std::size_t>(i)].E);
      cmp("X_base.r", ds.X_base[static_cast<std::size_t>(i)].r, dd.X_base[static_cast<std::size_t>(i)].r);
    }
    cmp("kinetic_energy", kinetic_energy(ms, ds, qs, qds), kinetic_energy(md, dd, q, qd));
    cmp("potential_energy", potential_energy(ms, ds, qs), potential_energy(md, dd, q));
    cmp("center_of_mass", center_of_mass(ms, ds, qs), center_of_mass(md, dd, q));
    // Casting keeps the two in step too.
    const auto msl = ms.template cast<long double>();
    const auto mdl = md.cast<long double>();
    Data<long double, TreeT> dsl(msl);
    Data<long double> ddl(mdl);
    const Eigen::Matrix<long double, Eigen::Dynamic, 1> ql = q.cast<long double>(), qdl = qd.cast<long double>(),
                                                       taul = tau.cast<long double>();
    cmp("aba long double", aba(msl, dsl, ql, qdl, taul), aba(mdl, ddl, ql, qdl, taul));
  }

  const std::string name = "N=" + std::to_string(N) + " max relative difference";
  worst.note(name, cmp.max_rel);
  worst.note("N=" + std::to_string(N) + " results not bit-identical", cmp.compared - cmp.exact);
}

}  // namespace static_trees
}  // namespace spatial::testing
