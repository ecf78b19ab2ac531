// The ground's wrench and the ZMP (zmp.hpp) on fixed and floating bases: zmp_on_plane on hand-made wrenches, the
// base wrench against Newton–Euler for the whole robot through an independent code path (the centroidal momentum
// rate of centroidal.hpp), compile-time against run-time trees, and the ZMP of a point mass.

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include "support/compile_time_trees.hpp"  // SPATIAL_TEST_COMPILE_TIME_TREES: 0 in the sanitizer build
#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

using namespace spatial;
using spatial::testing::random_vector;
using Vec = Eigen::VectorXd;
using V3 = Vector3<double>;

TEST(Zmp, OnPlaneOfHandMadeWrenches) {
  // A vertical force of 10 N at (0.1, −0.2, 0): moment about the origin p × f.
  const V3 p(0.1, -0.2, 0.0), f(0, 0, 10);
  EXPECT_LT((zmp_on_plane(Force<double>(p.cross(f), f)) - p).norm(), 1e-15);
  // A slanted force through (0.3, 0.1, 0.5): its ZMP on z = 0 is where its line of action crosses the plane.
  const V3 p2(0.3, 0.1, 0.5), f2(2, -1, 10);
  const V3 expected = p2 - f2 * (p2.z() / f2.z());
  EXPECT_LT((zmp_on_plane(Force<double>(p2.cross(f2), f2)) - expected).norm(), 1e-15);
  // On the plane z = 0.5 it is the point of application itself.
  EXPECT_LT((zmp_on_plane(Force<double>(p2.cross(f2), f2), 0.5) - p2).norm(), 1e-15);
  // No upward force: no ZMP.
  EXPECT_TRUE(std::isnan(zmp_on_plane(Force<double>(V3::Zero(), V3(1, 0, -1))).x()));
}

/// Newton–Euler for the moving bodies: the base's wrench about the base origin is the momentum rate about it minus
/// the bodies' weight: [k̇_G + c × ṗ − c × m g; ṗ − m g].
template <class M, class D, class VQ, class VV>
void check_against_momentum_rate(const M& model, D& data, const VQ& q, const VV& v, const VV& a) {
  const Force<double> w = base_wrench(model, data, q, v, a);
  const auto rate = centroidal_momentum_time_variation(model, data, q, v, a);
  const double m = model.total_mass();  // the moving bodies
  const V3 c = data.com, pdot = rate.dhg.template head<3>(), kdot = rate.dhg.template tail<3>();
  const V3 g = model.gravity();
  const double scale = 1.0 + pdot.norm() + kdot.norm();
  EXPECT_LT((w.f - (pdot - m * g)).norm(), 1e-12 * scale);
  EXPECT_LT((w.n - (kdot + c.cross(pdot) - c.cross(m * g))).norm(), 1e-12 * scale);
}

TEST(Zmp, FixedBaseWrenchIsNewtonEulerForTheWholeRobot) {
  namespace sr = models::hoap3_stance_right;
  const auto ct = sr::model();
  const auto rt = ct.to_runtime();
  Data<double> dr(rt);
#if SPATIAL_TEST_COMPILE_TIME_TREES
  Data<double, sr::Tree> dc(ct);
#endif
  std::mt19937 rng(1);
  for (int k = 0; k < 5; ++k) {
    const Eigen::Matrix<double, sr::dof, 1> q = random_vector(sr::dof, rng, 1.0), v = random_vector(sr::dof, rng, 1.0),
                                            a = random_vector(sr::dof, rng, 3.0);
    check_against_momentum_rate(rt, dr, Vec(q), Vec(v), Vec(a));
    const Force<double> wr = base_wrench(rt, dr, Vec(q), Vec(v), Vec(a));
#if SPATIAL_TEST_COMPILE_TIME_TREES
    // The compile-time tree (AVX2 RNEA where enabled) gives the same wrench.
    const Force<double> wc = base_wrench(ct, dc, q, v, a);
    EXPECT_LT((wc.f - wr.f).norm() + (wc.n - wr.n).norm(), 1e-12 * (1.0 + wr.f.norm()));
#endif
    // The ZMP on the sole's plane has zero horizontal moment there.
    const V3 p = multibody_zmp(rt, dr, Vec(q), Vec(v), Vec(a));
    const V3 np = wr.n - p.cross(wr.f);
    if (wr.f.z() > 0) {
      EXPECT_LT(np.head<2>().norm(), 1e-12 * (1.0 + wr.n.norm()));
    }
  }
}

TEST(Zmp, FloatingBaseWrenchIsNewtonEulerForTheWholeRobot) {
  const auto model = models::hoap3_floating::floating_model<double>().to_runtime();
  FloatingData<double> data(model);
  std::mt19937 rng(2);
  const int n = model.njoints();
  for (int k = 0; k < 5; ++k) {
    const Vec q = random_configuration(model, Vec::Constant(n, -1.0), Vec::Constant(n, 1.0), rng);
    const Vec v = random_vector(model.nv(), rng, 1.0), a = random_vector(model.nv(), rng, 3.0);
    // World wrench against the world momentum rate of the whole robot (root body included).
    const Force<double> w = base_wrench_world(model, data, q, v, a);
    const auto rate = centroidal_momentum_time_variation(model, data, q, v, a);
    const double m = model.total_mass();
    const V3 c = data.com, pdot = rate.dhg.head<3>(), kdot = rate.dhg.tail<3>(), g = model.gravity();
    const double scale = 1.0 + pdot.norm() + kdot.norm();
    EXPECT_LT((w.f - (pdot - m * g)).norm(), 1e-12 * scale);
    EXPECT_LT((w.n - (kdot + c.cross(pdot) - c.cross(m * g))).norm(), 1e-12 * scale);
  }
}

TEST(Zmp, PointMassOnAMasslessLegIsTheCartTable) {
  // A 1 kg point mass on a massless prismatic-x / prismatic-y / prismatic-z stack above the base, at height z:
  // with horizontal acceleration a the ZMP is x − z a / g (the cart-table model).
  ModelBuilder<double> b;
  const Inertia<double> none = Inertia<double>::from_com(1e-12, V3::Zero(), Matrix3<double>::Zero());
  b.add_body("x", -1, JointType::PrismaticX, Transform<double>::Identity(), none, V3::UnitX(), "jx");
  b.add_body("y", 0, JointType::PrismaticY, Transform<double>::Identity(), none, V3::UnitY(), "jy");
  b.add_body("z", 1, JointType::PrismaticZ, Transform<double>::Identity(),
             Inertia<double>::from_com(1.0, V3::Zero(), Matrix3<double>::Zero()), V3::UnitZ(), "jz");
  const Model<double> model = b.build();
  Data<double> data(model);
  const Vec q = (Vec(3) << 0.1, -0.05, 0.8).finished(), v = Vec::Zero(3);
  const Vec a = (Vec(3) << 1.5, -0.7, 0.0).finished();
  const V3 p = multibody_zmp(model, data, q, v, a);
  EXPECT_NEAR(p.x(), 0.1 - 0.8 * 1.5 / 9.81, 1e-9);
  EXPECT_NEAR(p.y(), -0.05 - 0.8 * -0.7 / 9.81, 1e-9);
}

}  // namespace
