// The floating-base algorithms (floating.hpp) in a translation unit built with -mavx2 -mfma, where the tree passes
// take the AVX2 kernels (simd.hpp) wherever the scalar path is not forced: CRBA with the free-flyer's columns,
// RNEA, ABA and CRBA + LTDL forward dynamics against the same calls with the scalar path (`<false>`), on the HOAP-3
// floating model and random trees, with no allocation (EIGEN_RUNTIME_NO_MALLOC).
#include "support/simd_compare.hpp"

#include <spatial/models/hoap3_floating.hpp>

namespace {
using namespace spatial;
using namespace spatial::testing::simd;

template <class TreeT, class S>
void compare_floating(const FloatingModel<S, TreeT>& model, unsigned seed) {
  using FM = FloatingModel<S, TreeT>;
  using VQ = Eigen::Matrix<S, FM::NQ, 1>;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Matrix<S, Eigen::Dynamic, 1> lo = Eigen::Matrix<S, Eigen::Dynamic, 1>::Constant(TreeT::size, S(-3.2));
  const Eigen::Matrix<S, Eigen::Dynamic, 1> hi = -lo;
  const double tol = tolerance<TreeT, S>();
  for (int trial = 0; trial < 20; ++trial) {
    const VQ q = random_configuration(model, lo, hi, rng);
    FloatingData<S, TreeT> ds(model), dr(model);
    Eigen::internal::set_is_malloc_allowed(false);
    const auto qj = q.template tail<TreeT::size>();
    detail::crba_inputs<true>(model.tree(), ds.tree, qj);
    detail::crba_floating<true>(model, ds);
    detail::crba_inputs<false>(model.tree(), dr.tree, qj);
    detail::crba_floating<false>(model, dr);
    Eigen::internal::set_is_malloc_allowed(true);
    const double sH = double(dr.H.cwiseAbs().maxCoeff());
    EXPECT_LE((ds.H - dr.H).cwiseAbs().maxCoeff(), tol * sH);
    EXPECT_EQ(ds.H.transpose(), ds.H) << "H is symmetric by construction";
    // The public entry point takes the AVX2 CRBA and gives the same H.
    EXPECT_LE((crba(model, dr, q) - ds.H).cwiseAbs().maxCoeff(), tol * sH);
  }
}

TEST(SimdFloating, CrbaHoap3) { compare_floating(models::hoap3_floating::floating_model(), 70); }

TEST(SimdFloating, CrbaRandomTrees) {
  std::mt19937 rng(71);
  for (unsigned seed = 72; seed < 75; ++seed) {
    const Inertia<double> I0 = test_root_inertia();
    compare_floating(FloatingModel<double, Rev9>(random_static<Rev9>(seed), I0), seed);
#if SPATIAL_SIMD_TEST_ALL_TREES
    compare_floating(FloatingModel<double, RevChain24>(random_static<RevChain24>(seed), I0), seed);
#endif
  }
}

}  // namespace

namespace {
using namespace spatial;
using namespace spatial::testing::simd;

/// RNEA (every term combination) and ABA on a floating base: the AVX2 tree passes against the scalar ones.
template <class TreeT, class S>
void compare_floating_dynamics(const FloatingModel<S, TreeT>& model, unsigned seed) {
  using FM = FloatingModel<S, TreeT>;
  using VQ = Eigen::Matrix<S, FM::NQ, 1>;
  using VV = Eigen::Matrix<S, FM::NV, 1>;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Matrix<S, Eigen::Dynamic, 1> lo = Eigen::Matrix<S, Eigen::Dynamic, 1>::Constant(TreeT::size, S(-3.2));
  const Eigen::Matrix<S, Eigen::Dynamic, 1> hi = -lo;
  const double tol = tolerance<TreeT, S>();
  for (int trial = 0; trial < 20; ++trial) {
    const VQ q = random_configuration(model, lo, hi, rng);
    VV v, a;
    for (int i = 0; i < FM::NV; ++i) v[i] = S(2 * u(rng)), a[i] = S(2 * u(rng));
    FloatingData<S, TreeT> ds(model), dr(model);
    VV ts, tr;
    Eigen::internal::set_is_malloc_allowed(false);
    auto both = [&](auto terms) {
      constexpr unsigned Terms = decltype(terms)::value;
      detail::rnea_floating<Terms, true>(model, ds, q, v, a, NoExternalForces{}, ForceFrame::Body, ts);
      detail::rnea_floating<Terms, false>(model, dr, q, v, a, NoExternalForces{}, ForceFrame::Body, tr);
      Eigen::internal::set_is_malloc_allowed(true);
      EXPECT_LE((ts - tr).cwiseAbs().maxCoeff(), tol * std::max(1.0, double(tr.cwiseAbs().maxCoeff()))) << Terms;
      Eigen::internal::set_is_malloc_allowed(false);
    };
    both(std::integral_constant<unsigned, 7u>{});
    if constexpr (kEveryTermCombination<TreeT, S>) {
      both(std::integral_constant<unsigned, 3u>{});
      both(std::integral_constant<unsigned, 1u>{});
      both(std::integral_constant<unsigned, 6u>{});
    }
    detail::aba_floating<true>(model, ds, q, v, a, NoExternalForces{}, ForceFrame::Body);
    detail::aba_floating<false>(model, dr, q, v, a, NoExternalForces{}, ForceFrame::Body);
    Eigen::internal::set_is_malloc_allowed(true);
    EXPECT_LE((ds.qdd - dr.qdd).cwiseAbs().maxCoeff(), 1e3 * tol * std::max(1.0, double(dr.qdd.cwiseAbs().maxCoeff())));
    // The round trip through the public entry points (both AVX2): RNEA(ABA(τ)) = τ.
    const VV qdd = aba(model, ds, q, v, a);
    const VV back = rnea(model, ds, q, v, qdd);
    EXPECT_LE((back - a).cwiseAbs().maxCoeff(), 1e3 * tol * std::max(1.0, double(a.cwiseAbs().maxCoeff())));
  }
}

TEST(SimdFloating, DynamicsHoap3) { compare_floating_dynamics(models::hoap3_floating::floating_model(), 80); }

// float on Rev9 (the HOAP-3's fixed-base kernels run in float in simd_rnea.cpp, simd_crba.cpp and simd_aba.cpp; a
// 27-body floating model in float would be three more large unrolled instantiations).
TEST(SimdFloating, Float) {
  const Inertia<double> I0 = test_root_inertia();
  const auto model = FloatingModel<double, Rev9>(random_static<Rev9>(86), I0).cast<float>();
  compare_floating(model, 71);
  compare_floating_dynamics(model, 85);
}

TEST(SimdFloating, DynamicsRandomTrees) {
  for (unsigned seed = 81; seed < 84; ++seed) {
    const Inertia<double> I0 = test_root_inertia();
    compare_floating_dynamics(FloatingModel<double, Rev9>(random_static<Rev9>(seed), I0), seed);
#if SPATIAL_SIMD_TEST_ALL_TREES
    compare_floating_dynamics(FloatingModel<double, RevChain24>(random_static<RevChain24>(seed), I0), seed);
#endif
  }
}

}  // namespace
