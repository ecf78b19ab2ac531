// Run-time trees (`Model<S>`: loaded from a URDF, reduced, built body by body) whose joints are all revolute about
// coordinate axes take the AVX2 kernels of simd.hpp, like compile-time trees: the kernels loop over the bodies and
// switch once per body on the joint's axis, with their per-body records in `Data::work`. They run the same
// operations in the same order, so every result and every per-body output equals the compile-time kernel's bit for
// bit: through every public entry point (RNEA and its scene options, bias forces, gravity torques, CRBA, ABA,
// forward kinematics, forward dynamics by CRBA + LTDL), fixed and floating base, double and float, with no
// allocation (EIGEN_RUNTIME_NO_MALLOC). Run-time trees with another joint type take the scalar path.
#include "support/simd_compare.hpp"

namespace {
using namespace spatial;
using namespace spatial::testing::simd;

template <class S>
using VecX = Eigen::Matrix<S, Eigen::Dynamic, 1>;

template <class A, class B>
void same(const char* what, int body, const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.cols(), b.cols());
  EXPECT_TRUE((a.array() == b.array()).all()) << what << " of body " << body << "\ncompile-time tree:\n"
                                              << a << "\nrun-time tree:\n" << b;
}
template <class S, class T, class U>
void same_transforms(const char* what, const Data<S, T>& ds, const Data<S, U>& dr, int n, bool base) {
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const Transform<S>& xs = base ? ds.X_base[k] : ds.X_up[k];
    const Transform<S>& xr = base ? dr.X_base[k] : dr.X_up[k];
    same(what, i, xs.E, xr.E);
    same(what, i, xs.r, xr.r);
  }
}

template <class S>
VecX<S> random_vector(std::mt19937& rng, int n, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  VecX<S> x(n);
  for (int i = 0; i < n; ++i) x[i] = S(u(rng));
  return x;
}

/// The compile-time model and its run-time twin through every public entry point.
template <class S, class TreeT>
void expect_same_kernels(const Model<S, TreeT>& ms, unsigned seed) {
  const Model<S> mr = ms.to_runtime();
  ASSERT_TRUE(detail::simd_applies(mr));
  const int n = ms.size();
  Data<S, TreeT> ds(ms);
  Data<S> dr(mr);
  std::mt19937 rng(seed);
  auto per_body = [&](const char* what, auto get) {
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      same(what, i, get(ds)[k].vector(), get(dr)[k].vector());
    }
  };
  for (int trial = 0; trial < 5; ++trial) {
    SCOPED_TRACE(::testing::Message() << "trial " << trial);
    const VecX<S> q = random_vector<S>(rng, n, 3.2), qd = random_vector<S>(rng, n, 3.0),
                  qdd = random_vector<S>(rng, n, 10.0), tau = random_vector<S>(rng, n, 5.0);
    VecX<S> t_full_s(n), t_full_r(n);
    Eigen::internal::set_is_malloc_allowed(false);
    t_full_s = rnea(ms, ds, q, qd, qdd);
    t_full_r = rnea(mr, dr, q, qd, qdd);
    Eigen::internal::set_is_malloc_allowed(true);
    same("tau", -1, t_full_s, t_full_r);
    same_transforms("X_up", ds, dr, n, false);
    per_body("v", [](const auto& d) -> const auto& { return d.v; });
    per_body("a", [](const auto& d) -> const auto& { return d.a; });
    per_body("f", [](const auto& d) -> const auto& { return d.f; });

    VecX<S> b_s(n), b_r(n);
    VecX<S> g_s(n), g_r(n);
    VecX<S> qs_s(n), qs_r(n);
    VecX<S> ng_s(n), ng_r(n);
    Eigen::internal::set_is_malloc_allowed(false);
    b_s = bias_forces(ms, ds, q, qd);
    b_r = bias_forces(mr, dr, q, qd);
    g_s = gravity_torques(ms, ds, q);
    g_r = gravity_torques(mr, dr, q);
    qs_s = rnea<Dyn::QuasiStatic>(ms, ds, q, qd, qdd);
    qs_r = rnea<Dyn::QuasiStatic>(mr, dr, q, qd, qdd);
    ng_s = rnea<Dyn::NoGravity>(ms, ds, q, qd, qdd);
    ng_r = rnea<Dyn::NoGravity>(mr, dr, q, qd, qdd);
    Eigen::internal::set_is_malloc_allowed(true);
    same("bias forces", -1, b_s, b_r);
    same("gravity torques", -1, g_s, g_r);
    same("rnea<QuasiStatic>", -1, qs_s, qs_r);
    same("rnea<NoGravity>", -1, ng_s, ng_r);

    Eigen::internal::set_is_malloc_allowed(false);
    crba(ms, ds, q);
    crba(mr, dr, q);
    Eigen::internal::set_is_malloc_allowed(true);
    same("H", -1, ds.H, dr.H);
    same_transforms("X_base", ds, dr, n, true);
    per_body("S_base", [](const auto& d) -> const auto& { return d.S_base; });
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      same("Ic.I", i, ds.Ic[k].I, dr.Ic[k].I);
      same("Ic.h", i, ds.Ic[k].h, dr.Ic[k].h);
      EXPECT_EQ(ds.Ic[k].m, dr.Ic[k].m) << i;
    }

    VecX<S> a_s(n), a_r(n);
    Eigen::internal::set_is_malloc_allowed(false);
    a_s = aba(ms, ds, q, qd, tau);
    a_r = aba(mr, dr, q, qd, tau);
    Eigen::internal::set_is_malloc_allowed(true);
    same("aba qdd", -1, a_s, a_r);
    per_body("v (aba)", [](const auto& d) -> const auto& { return d.v; });
    per_body("c", [](const auto& d) -> const auto& { return d.c; });
    per_body("a (aba)", [](const auto& d) -> const auto& { return d.a; });
    per_body("pA", [](const auto& d) -> const auto& { return d.pA; });
    per_body("U", [](const auto& d) -> const auto& { return d.U; });
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      same("IA", i, ds.IA[k].A, dr.IA[k].A);
      same("IA", i, ds.IA[k].B, dr.IA[k].B);
      same("IA", i, ds.IA[k].C, dr.IA[k].C);
      EXPECT_EQ(ds.Dinv[k], dr.Dinv[k]) << i;
      EXPECT_EQ(ds.u[k], dr.u[k]) << i;
    }
    VecX<S> a0_s(n), a0_r(n);
    Eigen::internal::set_is_malloc_allowed(false);
    a0_s = aba<Dyn::Gravity>(ms, ds, q, qd, tau);
    a0_r = aba<Dyn::Gravity>(mr, dr, q, qd, tau);
    Eigen::internal::set_is_malloc_allowed(true);
    same("aba<Gravity>", -1, a0_s, a0_r);

    VecX<S> f_s(n), f_r(n);
    Eigen::internal::set_is_malloc_allowed(false);
    forward_kinematics(ms, ds, q);
    forward_kinematics(mr, dr, q);
    f_s = forward_dynamics_crba(ms, ds, q, qd, tau);
    f_r = forward_dynamics_crba(mr, dr, q, qd, tau);
    Eigen::internal::set_is_malloc_allowed(true);
    same_transforms("X_base (forward kinematics)", ds, dr, n, true);
    same("forward_dynamics_crba", -1, f_s, f_r);
  }
}

// Bit for bit against the compile-time kernels (each compile-time tree here is another set of large unrolled
// instantiations, ~60 CPU-s of compilation for stance21, so only Rev9: two roots, branches and every axis, which is
// all the kernels' run-time loops distinguish; every HOAP-3 model runs below against the scalar path, which costs no
// instantiation per tree).
TEST(SimdRuntime, SameAsTheCompileTimeKernels) {
  for (unsigned seed = 10; seed < 13; ++seed) expect_same_kernels(random_static<Rev9>(seed), seed);
  expect_same_kernels(random_static<Rev9>(5).cast<float>(), 5);
}

/// Depth of a run-time tree (the longest chain of bodies from a root).
int depth(const Model<double>& m) {
  int d = 0;
  for (int i = 0; i < m.size(); ++i) {
    int k = 0;
    for (int j = i; j >= 0; j = m.parent(j)) ++k;
    d = std::max(d, k);
  }
  return d;
}

/// The run-time kernels against the run-time scalar path (rnea_impl, crba_impl, aba_impl with Simd = false), with
/// simd_compare.hpp's bound: a few roundings per level of the tree relative to the largest value of each output.
template <class S>
void expect_near_scalar(const Model<double>& md, unsigned seed) {
  const Model<S> m = md.cast<S>();
  ASSERT_TRUE(detail::simd_applies(m));
  const double tol = 16.0 * (depth(md) + 1) * double(std::numeric_limits<S>::epsilon());
  const int n = m.size();
  Data<S> d(m), dr(m);
  std::mt19937 rng(seed);
  auto near = [&](const char* what, const VecX<S>& simd, const VecX<S>& scalar, double scale) {
    EXPECT_LE(double((simd - scalar).cwiseAbs().maxCoeff()), tol * std::max(1.0, scale)) << what;
  };
  for (int trial = 0; trial < 10; ++trial) {
    const VecX<S> q = random_vector<S>(rng, n, 3.2), qd = random_vector<S>(rng, n, 3.0),
                  qdd = random_vector<S>(rng, n, 10.0), tau = random_vector<S>(rng, n, 5.0);
    Eigen::internal::set_is_malloc_allowed(false);
    rnea(m, d, q, qd, qdd);
    detail::rnea_impl<7u, false>(m, dr, q, qd, qdd, NoExternalForces{}, ForceFrame::Body, dr.tau);
    Eigen::internal::set_is_malloc_allowed(true);
    double sf = 0;
    for (int i = 0; i < n; ++i) sf = std::max(sf, double(dr.f[static_cast<std::size_t>(i)].vector().cwiseAbs().maxCoeff()));
    near("rnea", d.tau, dr.tau, sf);
    Eigen::internal::set_is_malloc_allowed(false);
    crba(m, d, q);
    detail::crba_inputs<false>(m, dr, q);
    detail::crba_impl<false>(m, dr);
    Eigen::internal::set_is_malloc_allowed(true);
    EXPECT_LE(double((d.H - dr.H).cwiseAbs().maxCoeff()), tol * double(dr.H.cwiseAbs().maxCoeff())) << "H";
    // q̈: the differences in the articulated inertias are amplified by their conditioning; compare the round trip.
    VecX<S> a(n);
    Eigen::internal::set_is_malloc_allowed(false);
    a = aba(m, d, q, qd, tau);
    Eigen::internal::set_is_malloc_allowed(true);
    detail::rnea_impl<7u, false>(m, dr, q, qd, a, NoExternalForces{}, ForceFrame::Body, dr.tau);
    EXPECT_LE(double((dr.tau - tau).cwiseAbs().maxCoeff()), 1e3 * tol * 5.0) << "rnea(aba(tau)) = tau";
  }
}

TEST(SimdRuntime, Hoap3ModelsAgainstTheScalarPath) {
  for (const Model<double>& m : {models::hoap3_stance_right::model().to_runtime(),
                                 models::hoap3_stance_left::model().to_runtime(),
                                 models::hoap3_torso::model().to_runtime(),
                                 models::hoap3_double_pendulum::model().to_runtime()}) {
    expect_near_scalar<double>(m, 2);
    expect_near_scalar<float>(m, 3);
  }
}

// The float kernel ran, not the scalar path (which rounds differently in float).
TEST(SimdRuntime, FloatTakesTheKernels) {
  const Model<float> m = models::hoap3_stance_right::model().cast<float>().to_runtime();
  Data<float> d(m), dr(m);
  std::mt19937 rng(6);
  const VecX<float> q = random_vector<float>(rng, m.size(), 1.5), qd = random_vector<float>(rng, m.size(), 1.0);
  rnea(m, d, q, qd, qd);
  detail::rnea_impl<7u, false>(m, dr, q, qd, qd, NoExternalForces{}, ForceFrame::Body, dr.tau);
  EXPECT_NE(d.tau, dr.tau);
}

// Another joint type anywhere in a run-time tree: the scalar path, bit for bit.
TEST(SimdRuntime, OtherJointTypesTakeTheScalarPath) {
  const Model<double> m = random_static<static_trees::Branched8>(7).to_runtime();
  ASSERT_FALSE(detail::simd_applies(m));
  const int n = m.size();
  Data<double> d(m), dr(m);
  std::mt19937 rng(8);
  const VecX<double> q = random_vector<double>(rng, n, 1.5), qd = random_vector<double>(rng, n, 1.0);
  rnea(m, d, q, qd, qd);
  detail::rnea_impl<7u, false>(m, dr, q, qd, qd, NoExternalForces{}, ForceFrame::Body, dr.tau);
  same("tau", -1, d.tau, dr.tau);
  crba(m, d, q);
  detail::crba_inputs<false>(m, dr, q);
  detail::crba_impl<false>(m, dr);
  same("H", -1, d.H, dr.H);
  aba(m, d, q, qd, qd);
  detail::aba_impl<true, true, false>(m, dr, q, qd, qd, NoExternalForces{}, ForceFrame::Body);
  same("aba", -1, d.qdd, dr.qdd);
}

// A floating base: the tree passes of RNEA, CRBA and ABA over the run-time twin of a floating model.
template <class TreeT>
void expect_same_floating(const FloatingModel<double, TreeT>& ms, unsigned seed) {
  const FloatingModel<double> mr = ms.to_runtime();
  ASSERT_TRUE(detail::simd_applies(mr.tree()));
  FloatingData<double, TreeT> ds(ms);
  FloatingData<double> dr(mr);
  std::mt19937 rng(seed);
  const VecX<double> lo = VecX<double>::Constant(ms.tree().size(), -3.2), hi = -lo;
  for (int trial = 0; trial < 5; ++trial) {
    const VecX<double> q = random_configuration(ms, lo, hi, rng);
    const VecX<double> v = random_vector<double>(rng, ms.nv(), 2.0), a = random_vector<double>(rng, ms.nv(), 2.0);
    VecX<double> t_s(ms.nv()), t_r(ms.nv());
    VecX<double> b_s(ms.nv()), b_r(ms.nv());
    VecX<double> x_s(ms.nv()), x_r(ms.nv());
    Eigen::internal::set_is_malloc_allowed(false);
    t_s = rnea(ms, ds, q, v, a);
    t_r = rnea(mr, dr, q, v, a);
    b_s = bias_forces(ms, ds, q, v);
    b_r = bias_forces(mr, dr, q, v);
    crba(ms, ds, q);
    crba(mr, dr, q);
    x_s = aba(ms, ds, q, v, a);
    x_r = aba(mr, dr, q, v, a);
    Eigen::internal::set_is_malloc_allowed(true);
    same("tau", -1, t_s, t_r);
    same("bias forces", -1, b_s, b_r);
    same("H", -1, ds.H, dr.H);
    same("aba", -1, x_s, x_r);
  }
}

TEST(SimdRuntime, FloatingBase) {
  const Inertia<double> I0 = test_root_inertia();
  expect_same_floating(FloatingModel<double, Rev9>(random_static<Rev9>(9), I0), 9);
}

}  // namespace
