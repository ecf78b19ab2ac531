// Spatial vector algebra (algebra.hpp) against Featherstone's 6×6 matrix definitions, written out independently
// in tests/support/reference.hpp, on random inputs with fixed seeds. The key identities are checked in float,
// double and long double with tolerances that are a small multiple of the scalar's machine epsilon (all inputs
// are O(1), so absolute and relative errors coincide up to a factor of a few).

#include <spatial/spatial.hpp>

#include "support/reference.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <utility>

namespace {

using namespace spatial;
using spatial::testing::crossmat;
using spatial::testing::inertia_6x6;
using spatial::testing::motion_transform_6x6;

constexpr int kTrials = 200;

/// Random O(1) inputs in scalar S (drawn in double, then rounded to S, so every scalar sees the same numbers).
template <class S>
struct Random {
  explicit Random(unsigned seed) : rng(seed) {}
  std::mt19937 rng;
  double uniform(double lo = -1.0, double hi = 1.0) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  S scalar(double lo = -1.0, double hi = 1.0) { return S(uniform(lo, hi)); }
  Vector3<S> vec3() { return Vector3<S>(scalar(), scalar(), scalar()); }
  Matrix3<S> rotation() {
    // Orthonormalise in S itself, so that E is a rotation to the precision of S.
    Eigen::Quaternion<S> qt(scalar(), scalar(), scalar(), scalar());
    qt.normalize();
    return qt.toRotationMatrix();
  }
  Motion<S> motion() { return Motion<S>(vec3(), vec3()); }
  Force<S> force() { return Force<S>(vec3(), vec3()); }
  Transform<S> transform() { return Transform<S>(rotation(), vec3()); }
  Matrix3<S> inertia_com(S m) {
    // Principal moments a+b, b+c, a+c (triangle inequality holds) in random principal axes.
    const S a = scalar(0.05, 1.0), b = scalar(0.05, 1.0), c = scalar(0.05, 1.0);
    const Vector3<S> d(a + b, b + c, a + c);
    const Matrix3<S> R = rotation();
    return m * R * d.asDiagonal() * R.transpose();
  }
  struct Body {
    S m;
    Vector3<S> c;
    Matrix3<S> Ic;
  };
  Body body() {
    Body b;
    b.m = scalar(0.2, 3.0);
    b.c = vec3();
    b.Ic = inertia_com(b.m);
    return b;
  }
};

template <class S>
S eps() {
  return std::numeric_limits<S>::epsilon();
}

/// Max-norm of the difference, in long double.
template <class A, class B>
long double maxdiff(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a.template cast<long double>() - b.template cast<long double>()).cwiseAbs().maxCoeff();
}

template <class S>
class AlgebraTyped : public ::testing::Test {
 protected:
  // Inputs are O(1); 6×6 products and an inverse of a well-conditioned 6×6 lose at most a few tens of ulps.
  static long double tol(double k = 64.0) { return static_cast<long double>(k) * eps<S>(); }
};
using Scalars = ::testing::Types<float, double, long double>;
struct ScalarNames {
  template <class S>
  static std::string GetName(int) {
    if (std::is_same_v<S, float>) return "float";
    if (std::is_same_v<S, double>) return "double";
    return "long_double";
  }
};
TYPED_TEST_SUITE(AlgebraTyped, Scalars, ScalarNames);

// ---- transforms ------------------------------------------------------------------------------------------------

TYPED_TEST(AlgebraTyped, MatrixIsRotTimesXlt) {
  using S = TypeParam;
  Random<S> R(11);
  for (int t = 0; t < kTrials; ++t) {
    const Transform<S> X = R.transform();
    EXPECT_LE(maxdiff(X.matrix(), motion_transform_6x6(X.E, X.r)), this->tol()) << "trial " << t;
  }
}

TYPED_TEST(AlgebraTyped, ForceMatrixIsInverseTranspose) {
  using S = TypeParam;
  Random<S> R(12);
  for (int t = 0; t < kTrials; ++t) {
    const Transform<S> X = R.transform();
    const Matrix6<S> M = motion_transform_6x6(X.E, X.r);
    const Matrix6<S> Minv_T = M.inverse().transpose();
    EXPECT_LE(maxdiff(X.force_matrix(), Minv_T), this->tol(256)) << "trial " << t;
    // Invariance of the scalar product (Featherstone's notes, slide 28): Xᵀ X* = 1.
    EXPECT_LE(maxdiff(M.transpose() * X.force_matrix(), Matrix6<S>::Identity()), this->tol()) << "trial " << t;
  }
}

TYPED_TEST(AlgebraTyped, ApplyAgreesWithMatrices) {
  using S = TypeParam;
  Random<S> R(13);
  for (int t = 0; t < kTrials; ++t) {
    const Transform<S> X = R.transform();
    const Motion<S> m = R.motion();
    const Force<S> f = R.force();
    const Matrix6<S> M = motion_transform_6x6(X.E, X.r);
    const Matrix6<S> Minv = M.inverse();
    EXPECT_LE(maxdiff(X.apply(m).vector(), M * m.vector()), this->tol()) << "apply, trial " << t;
    EXPECT_LE(maxdiff((X * m).vector(), M * m.vector()), this->tol()) << "operator*(Motion), trial " << t;
    EXPECT_LE(maxdiff(X.apply_inverse(m).vector(), Minv * m.vector()), this->tol(256)) << "apply_inverse " << t;
    EXPECT_LE(maxdiff(X.apply_force(f).vector(), Minv.transpose() * f.vector()), this->tol(256))
        << "apply_force, trial " << t;
    EXPECT_LE(maxdiff((X * f).vector(), Minv.transpose() * f.vector()), this->tol(256))
        << "operator*(Force), trial " << t;
    EXPECT_LE(maxdiff(X.apply_force_inverse(f).vector(), M.transpose() * f.vector()), this->tol())
        << "apply_force_inverse, trial " << t;
  }
}

TYPED_TEST(AlgebraTyped, CompositionIsMatrixProduct) {
  using S = TypeParam;
  Random<S> R(14);
  for (int t = 0; t < kTrials; ++t) {
    const Transform<S> X1 = R.transform(), X2 = R.transform();
    const Transform<S> X12 = X1 * X2;
    const Matrix6<S> M12 = motion_transform_6x6(X1.E, X1.r) * motion_transform_6x6(X2.E, X2.r);
    EXPECT_LE(maxdiff(motion_transform_6x6(X12.E, X12.r), M12), this->tol()) << "trial " << t;
    const Motion<S> m = R.motion();
    EXPECT_LE(maxdiff(X12.apply(m).vector(), X1.apply(X2.apply(m)).vector()), this->tol()) << "trial " << t;
  }
}

TYPED_TEST(AlgebraTyped, InverseIsMatrixInverse) {
  using S = TypeParam;
  Random<S> R(15);
  for (int t = 0; t < kTrials; ++t) {
    const Transform<S> X = R.transform();
    const Transform<S> Xi = X.inverse();
    EXPECT_LE(maxdiff(motion_transform_6x6(Xi.E, Xi.r), motion_transform_6x6(X.E, X.r).inverse()), this->tol(256))
        << "trial " << t;
    const Transform<S> I1 = X * Xi, I2 = Xi * X;
    EXPECT_LE(maxdiff(I1.E, Matrix3<S>::Identity()), this->tol()) << "trial " << t;
    EXPECT_LE(I1.r.cwiseAbs().maxCoeff(), this->tol()) << "trial " << t;
    EXPECT_LE(maxdiff(I2.E, Matrix3<S>::Identity()), this->tol()) << "trial " << t;
    EXPECT_LE(I2.r.cwiseAbs().maxCoeff(), this->tol()) << "trial " << t;
  }
}

TYPED_TEST(AlgebraTyped, AxisRotationsAreFeatherstoneEq2_20) {
  using S = TypeParam;
  Random<S> R(16);
  for (int t = 0; t < kTrials; ++t) {
    const S th = R.scalar(-4.0, 4.0);
    const S c = std::cos(th), s = std::sin(th);
    Matrix3<S> Ex, Ey, Ez;  // RBDA eq. 2.20, written out
    Ex << 1, 0, 0,  //
        0, c, s,    //
        0, -s, c;
    Ey << c, 0, -s,  //
        0, 1, 0,     //
        s, 0, c;
    Ez << c, s, 0,  //
        -s, c, 0,   //
        0, 0, 1;
    EXPECT_LE(maxdiff(rotx(th).E, Ex), this->tol(4)) << "rotx, theta " << th;
    EXPECT_LE(maxdiff(roty(th).E, Ey), this->tol(4)) << "roty, theta " << th;
    EXPECT_LE(maxdiff(rotz(th).E, Ez), this->tol(4)) << "rotz, theta " << th;
    EXPECT_EQ(rotx(th).r, Vector3<S>::Zero());
    // Passive = transpose of the active rotation of the frame.
    EXPECT_LE(maxdiff(rotz(th).E, Eigen::AngleAxis<S>(th, Vector3<S>::UnitZ()).toRotationMatrix().transpose()),
              this->tol(8));
    // rot_axis_matrix about a coordinate axis is the same rotation; about any axis, the passive form of
    // Eigen's (active) AngleAxis.
    EXPECT_LE(maxdiff(rot_axis_matrix<S>(Vector3<S>::UnitX(), th), Ex), this->tol(8));
    EXPECT_LE(maxdiff(rot_axis_matrix<S>(Vector3<S>::UnitY(), th), Ey), this->tol(8));
    EXPECT_LE(maxdiff(rot_axis_matrix<S>(Vector3<S>::UnitZ(), th), Ez), this->tol(8));
    const Vector3<S> a = R.vec3().normalized();
    EXPECT_LE(maxdiff(rot_axis_matrix<S>(a, th), Eigen::AngleAxis<S>(th, a).toRotationMatrix().transpose()),
              this->tol(16));
  }
}

TYPED_TEST(AlgebraTyped, XltMovesTheReferencePoint) {
  using S = TypeParam;
  Random<S> R(17);
  for (int t = 0; t < kTrials; ++t) {
    // A body moving with [ω; v_O]: the body-fixed point at p moves with v_O + ω × p, and a force f through O
    // has moment −p × f about p.
    const Vector3<S> p = R.vec3();
    const Motion<S> m = R.motion();
    const Motion<S> mp = xlt(p).apply(m);
    EXPECT_LE(maxdiff(mp.w, m.w), this->tol(2));
    EXPECT_LE(maxdiff(mp.v, Vector3<S>(m.v + m.w.cross(p))), this->tol(8));
    const Force<S> f(Vector3<S>::Zero(), R.vec3());
    const Force<S> fp = xlt(p).apply_force(f);
    EXPECT_LE(maxdiff(fp.n, Vector3<S>(-p.cross(f.f))), this->tol(8));
  }
}

// ---- cross products --------------------------------------------------------------------------------------------

TYPED_TEST(AlgebraTyped, CrossProductsMatchTheir6x6Matrices) {
  using S = TypeParam;
  Random<S> R(21);
  for (int t = 0; t < kTrials; ++t) {
    const Motion<S> a = R.motion(), b = R.motion();
    const Force<S> f = R.force();
    Matrix6<S> vx = Matrix6<S>::Zero();  // [ω̃ 0; ṽ ω̃] (notes, slide 33)
    vx.template block<3, 3>(0, 0) = crossmat(a.w);
    vx.template block<3, 3>(3, 0) = crossmat(a.v);
    vx.template block<3, 3>(3, 3) = crossmat(a.w);
    Matrix6<S> vxf = Matrix6<S>::Zero();  // [ω̃ ṽ; 0 ω̃]
    vxf.template block<3, 3>(0, 0) = crossmat(a.w);
    vxf.template block<3, 3>(0, 3) = crossmat(a.v);
    vxf.template block<3, 3>(3, 3) = crossmat(a.w);
    EXPECT_LE(maxdiff(cross(a, b).vector(), vx * b.vector()), this->tol(8)) << "trial " << t;
    EXPECT_LE(maxdiff(cross(a, f).vector(), vxf * f.vector()), this->tol(8)) << "trial " << t;
    EXPECT_LE(maxdiff(cross_matrix(a), vx), this->tol(1)) << "trial " << t;
    EXPECT_LE(maxdiff(cross_force_matrix(a), vxf), this->tol(1)) << "trial " << t;
    // (v×*) = −(v×)ᵀ.
    EXPECT_LE(maxdiff(vxf, Matrix6<S>(-vx.transpose())), this->tol(1));
    EXPECT_LE(maxdiff(cross_force_matrix(a), Matrix6<S>(-cross_matrix(a).transpose())), this->tol(1));
    // a × a = 0; and (a×b)·f = −b·(a×*f) (the adjoint relation).
    EXPECT_LE(cross(a, a).vector().cwiseAbs().maxCoeff(), this->tol(4));
    EXPECT_LE(std::abs(static_cast<long double>(dot(cross(a, b), f)) + dot(b, cross(a, f))), this->tol(32));
  }
}

TYPED_TEST(AlgebraTyped, CrossProductsCommuteWithTransforms) {
  using S = TypeParam;
  Random<S> R(22);
  for (int t = 0; t < kTrials; ++t) {
    const Transform<S> X = R.transform();
    const Motion<S> a = R.motion(), b = R.motion();
    const Force<S> f = R.force();
    // X (a × b) = (X a) × (X b)
    EXPECT_LE(maxdiff(X.apply(cross(a, b)).vector(), cross(X.apply(a), X.apply(b)).vector()), this->tol(64))
        << "trial " << t;
    // X* (a ×* f) = (X a) ×* (X* f)
    EXPECT_LE(maxdiff(X.apply_force(cross(a, f)).vector(), cross(X.apply(a), X.apply_force(f)).vector()),
              this->tol(64))
        << "trial " << t;
  }
}

// ---- scalar product --------------------------------------------------------------------------------------------

TYPED_TEST(AlgebraTyped, DotProductAndFrameInvariance) {
  using S = TypeParam;
  Random<S> R(31);
  for (int t = 0; t < kTrials; ++t) {
    const Motion<S> m = R.motion();
    const Force<S> f = R.force();
    const Transform<S> X = R.transform();
    const long double ref = static_cast<long double>(m.w(0)) * f.n(0) + static_cast<long double>(m.w(1)) * f.n(1) +
                            static_cast<long double>(m.w(2)) * f.n(2) + static_cast<long double>(m.v(0)) * f.f(0) +
                            static_cast<long double>(m.v(1)) * f.f(1) + static_cast<long double>(m.v(2)) * f.f(2);
    EXPECT_LE(std::abs(static_cast<long double>(dot(m, f)) - ref), this->tol(8));
    EXPECT_EQ(dot(m, f), dot(f, m));
    // m · f is the same in every frame: (X m) · (X* f) = m · f.
    EXPECT_LE(std::abs(static_cast<long double>(dot(X.apply(m), X.apply_force(f))) - dot(m, f)), this->tol(64))
        << "trial " << t;
    EXPECT_LE(std::abs(static_cast<long double>(dot(X.apply_inverse(m), X.apply_force_inverse(f))) - dot(m, f)),
              this->tol(64))
        << "trial " << t;
  }
}

// ---- rigid-body inertia ----------------------------------------------------------------------------------------

TYPED_TEST(AlgebraTyped, FromComIsParallelAxisTheorem) {
  using S = TypeParam;
  Random<S> R(41);
  for (int t = 0; t < kTrials; ++t) {
    const auto b = R.body();
    const Inertia<S> I = Inertia<S>::from_com(b.m, b.c, b.Ic);
    // Ī = Ic + m (cᵀc 1 − c cᵀ), written without any cross-product matrix.
    const Matrix3<S> Ibar = b.Ic + b.m * (b.c.dot(b.c) * Matrix3<S>::Identity() - b.c * b.c.transpose());
    EXPECT_EQ(I.m, b.m);
    EXPECT_LE(maxdiff(I.h, Vector3<S>(b.m * b.c)), this->tol(4));
    EXPECT_LE(maxdiff(I.I, Ibar), this->tol(16)) << "trial " << t;
    EXPECT_LE(maxdiff(I.com(), b.c), this->tol(8));
    EXPECT_LE(maxdiff(I.inertia_com(), b.Ic), this->tol(64));
    EXPECT_LE(maxdiff(I.matrix(), inertia_6x6(b.m, b.c, b.Ic)), this->tol(16));
    // A physical spatial inertia is symmetric positive definite (notes, slide 42).
    EXPECT_EQ(Eigen::LLT<Matrix6<S>>(I.matrix()).info(), Eigen::Success);
  }
}

TYPED_TEST(AlgebraTyped, InertiaTimesMotion) {
  using S = TypeParam;
  Random<S> R(42);
  for (int t = 0; t < kTrials; ++t) {
    const auto b = R.body();
    const Inertia<S> I = Inertia<S>::from_com(b.m, b.c, b.Ic);
    const Motion<S> v = R.motion();
    const Force<S> p = I * v;
    EXPECT_LE(maxdiff(p.vector(), inertia_6x6(b.m, b.c, b.Ic) * v.vector()), this->tol(32)) << "trial " << t;
    // Momentum from first principles: linear m ċ with ċ = v_O + ω × c, angular about O = c × m ċ + Ic ω.
    const Vector3<S> cdot = v.v + v.w.cross(b.c);
    EXPECT_LE(maxdiff(p.f, Vector3<S>(b.m * cdot)), this->tol(32));
    EXPECT_LE(maxdiff(p.n, Vector3<S>(b.c.cross(b.m * cdot) + b.Ic * v.w)), this->tol(32));
  }
}

TYPED_TEST(AlgebraTyped, InertiaAddition) {
  using S = TypeParam;
  Random<S> R(43);
  for (int t = 0; t < kTrials; ++t) {
    const auto b1 = R.body(), b2 = R.body();
    const Inertia<S> I1 = Inertia<S>::from_com(b1.m, b1.c, b1.Ic), I2 = Inertia<S>::from_com(b2.m, b2.c, b2.Ic);
    const Matrix6<S> sum = inertia_6x6(b1.m, b1.c, b1.Ic) + inertia_6x6(b2.m, b2.c, b2.Ic);
    EXPECT_LE(maxdiff((I1 + I2).matrix(), sum), this->tol(32));
    Inertia<S> acc = I1;
    acc += I2;
    EXPECT_LE(maxdiff(acc.matrix(), sum), this->tol(32));
    // The combined body: mass adds, the centre of mass is the mass-weighted mean.
    EXPECT_LE(maxdiff((I1 + I2).com(), Vector3<S>((b1.m * b1.c + b2.m * b2.c) / (b1.m + b2.m))), this->tol(32));
  }
}

TYPED_TEST(AlgebraTyped, InertiaTransformsAreCongruences) {
  using S = TypeParam;
  Random<S> R(44);
  for (int t = 0; t < kTrials; ++t) {
    const auto b = R.body();
    const Inertia<S> I = Inertia<S>::from_com(b.m, b.c, b.Ic);
    const Transform<S> X = R.transform();
    const Matrix6<S> M = motion_transform_6x6(X.E, X.r);
    const Matrix6<S> Minv = M.inverse();
    const Matrix6<S> IA = inertia_6x6(b.m, b.c, b.Ic);
    // transformed: ᴮI = X* ᴬI X⁻¹ = X⁻ᵀ I X⁻¹.
    EXPECT_LE(maxdiff(I.transformed(X).matrix(), Matrix6<S>(Minv.transpose() * IA * Minv)), this->tol(1024))
        << "trial " << t;
    // transformed_inverse: ᴬI = Xᵀ ᴮI X.
    EXPECT_LE(maxdiff(I.transformed_inverse(X).matrix(), Matrix6<S>(M.transpose() * IA * M)), this->tol(256))
        << "trial " << t;
    // The same body seen from B: centre of mass E (c − r), same inertia about the centre of mass rotated.
    const Inertia<S> IB = I.transformed(X);
    EXPECT_LE(maxdiff(IB.com(), Vector3<S>(X.E * (b.c - X.r))), this->tol(64));
    EXPECT_LE(maxdiff(IB.inertia_com(), Matrix3<S>(X.E * b.Ic * X.E.transpose())), this->tol(256));
    // Round trip.
    EXPECT_LE(maxdiff(IB.transformed_inverse(X).matrix(), IA), this->tol(1024));
  }
}

TYPED_TEST(AlgebraTyped, KineticEnergyIsFrameInvariant) {
  using S = TypeParam;
  Random<S> R(45);
  for (int t = 0; t < kTrials; ++t) {
    const auto b = R.body();
    const Inertia<S> IA = Inertia<S>::from_com(b.m, b.c, b.Ic);
    const Transform<S> X = R.transform();
    const Motion<S> vA = R.motion();
    const Motion<S> vB = X.apply(vA);
    const Inertia<S> IB = IA.transformed(X);
    const long double eA = static_cast<long double>(dot(vA, IA * vA)) / 2;
    const long double eB = static_cast<long double>(dot(vB, IB * vB)) / 2;
    // ½ vᵀ I v from first principles: ½ m |ċ|² + ½ ωᵀ Ic ω.
    const Vector3<S> cdot = vA.v + vA.w.cross(b.c);
    const long double ref = static_cast<long double>(b.m) * cdot.squaredNorm() / 2 +
                            static_cast<long double>(vA.w.dot(b.Ic * vA.w)) / 2;
    EXPECT_LE(std::abs(eA - ref), this->tol(64) * (1 + ref)) << "trial " << t;
    EXPECT_LE(std::abs(eB - eA), this->tol(256) * (1 + ref)) << "trial " << t;
  }
}

// ---- articulated-body inertia ----------------------------------------------------------------------------------

/// A random symmetric positive-definite 6×6 (an articulated inertia need not be a rigid-body inertia).
template <class S>
Matrix6<S> random_spd6(Random<S>& R) {
  Matrix6<S> A;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) A(i, j) = R.scalar();
  Matrix6<S> M = A * A.transpose() + S(0.5) * Matrix6<S>::Identity();
  // Exactly symmetric (a vectorised product need not round both triangles alike).
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < i; ++j) M(i, j) = M(j, i);
  return M;
}

TYPED_TEST(AlgebraTyped, ArticulatedInertia) {
  using S = TypeParam;
  Random<S> R(51);
  for (int t = 0; t < kTrials; ++t) {
    const Matrix6<S> M = random_spd6(R);
    const ArticulatedInertia<S> IA(M.template block<3, 3>(0, 0), M.template block<3, 3>(0, 3),
                                   M.template block<3, 3>(3, 3));
    EXPECT_LE(maxdiff(IA.matrix(), M), this->tol(1));
    const Motion<S> v = R.motion();
    EXPECT_LE(maxdiff((IA * v).vector(), M * v.vector()), this->tol(16));
    // Xᵀ M X with the independent 6×6 X.
    const Transform<S> X = R.transform();
    const Matrix6<S> Xm = motion_transform_6x6(X.E, X.r);
    EXPECT_LE(maxdiff(IA.transformed_inverse(X).matrix(), Matrix6<S>(Xm.transpose() * M * Xm)), this->tol(256))
        << "trial " << t;
    // M − U Uᵀ / d.
    const Force<S> U = R.force();
    const S d = R.scalar(0.5, 2.0);
    ArticulatedInertia<S> sub = IA;
    sub.subtract_outer(U, S(1) / d);
    EXPECT_LE(maxdiff(sub.matrix(), Matrix6<S>(M - U.vector() * U.vector().transpose() / d)), this->tol(32));
    // The revolute-joint specialisation: U = M e_K (angular K), d = U_K; the update then maps e_K to exactly zero
    // and the transform that skips row/column K agrees with the dense reference.
    const auto revolute_update = [&](auto axis) {
      constexpr int K = decltype(axis)::value;
      Motion<S> eK = Motion<S>::Zero();
      eK.w[K] = S(1);
      const Force<S> UK = IA * eK;
      const S dK = UK.n[K];
      const Matrix6<S> ref = M - UK.vector() * UK.vector().transpose() / dK;
      ArticulatedInertia<S> red = IA;
      red.template subtract_outer<K>(UK, S(1) / dK);
      EXPECT_LE(maxdiff(red.matrix(), ref), this->tol(32)) << "K = " << K << ", trial " << t;
      EXPECT_EQ((red * eK).vector(), Vector6<S>::Zero()) << "K = " << K << ", trial " << t;
      Motion<S> c = R.motion();  // a velocity product v × e_K q̇: zero K components
      c.w[K] = S(0);
      c.v[K] = S(0);
      EXPECT_LE(maxdiff(red.template mul_null<K>(c).vector(), Vector6<S>(ref * c.vector())), this->tol(32))
          << "K = " << K << ", trial " << t;
      EXPECT_LE(maxdiff(red.template transformed_inverse<K>(X).matrix(), Matrix6<S>(Xm.transpose() * ref * Xm)),
                this->tol(256))
          << "K = " << K << ", trial " << t;
    };
    revolute_update(std::integral_constant<int, 0>{});
    revolute_update(std::integral_constant<int, 1>{});
    revolute_update(std::integral_constant<int, 2>{});
    ArticulatedInertia<S> acc = IA;
    acc += IA;
    EXPECT_LE(maxdiff(acc.matrix(), Matrix6<S>(2 * M)), this->tol(4));
    // From a rigid-body inertia.
    const auto b = R.body();
    const Inertia<S> I = Inertia<S>::from_com(b.m, b.c, b.Ic);
    EXPECT_LE(maxdiff(ArticulatedInertia<S>(I).matrix(), inertia_6x6(b.m, b.c, b.Ic)), this->tol(16));
    EXPECT_LE(maxdiff(ArticulatedInertia<S>(I).transformed_inverse(X).matrix(), I.transformed_inverse(X).matrix()),
              this->tol(256));
  }
}

// ---- Motion / Force arithmetic ---------------------------------------------------------------------------------

TYPED_TEST(AlgebraTyped, MotionAndForceArithmetic) {
  using S = TypeParam;
  Random<S> R(61);
  for (int t = 0; t < 20; ++t) {
    const Motion<S> a = R.motion(), b = R.motion();
    const Force<S> f = R.force(), g = R.force();
    const S s = R.scalar();
    const Vector6<S> av = a.vector(), bv = b.vector(), fv = f.vector(), gv = g.vector();
    EXPECT_EQ(av.template head<3>(), a.w);  // angular first
    EXPECT_EQ(av.template tail<3>(), a.v);
    EXPECT_EQ(fv.template head<3>(), f.n);
    EXPECT_EQ(fv.template tail<3>(), f.f);
    EXPECT_EQ(Motion<S>(av).vector(), av);
    EXPECT_EQ(Force<S>(fv).vector(), fv);
    EXPECT_EQ((a + b).vector(), Vector6<S>(av + bv));
    EXPECT_EQ((a - b).vector(), Vector6<S>(av - bv));
    EXPECT_EQ((-a).vector(), Vector6<S>(-av));
    EXPECT_EQ((s * a).vector(), Vector6<S>(s * av));
    EXPECT_EQ((a * s).vector(), Vector6<S>(s * av));
    EXPECT_EQ((f + g).vector(), Vector6<S>(fv + gv));
    EXPECT_EQ((f - g).vector(), Vector6<S>(fv - gv));
    EXPECT_EQ((-f).vector(), Vector6<S>(-fv));
    EXPECT_EQ((s * f).vector(), Vector6<S>(s * fv));
    EXPECT_EQ((f * s).vector(), Vector6<S>(s * fv));
    Motion<S> m = a;
    m += b;
    EXPECT_EQ(m.vector(), Vector6<S>(av + bv));
    m -= b;
    m -= b;
    EXPECT_EQ(m.vector(), Vector6<S>((av + bv) - bv - bv));
    Force<S> h = f;
    h += g;
    EXPECT_EQ(h.vector(), Vector6<S>(fv + gv));
    h -= g;
    h -= g;
    EXPECT_EQ(h.vector(), Vector6<S>((fv + gv) - gv - gv));
    EXPECT_EQ(Motion<S>::Zero().vector(), Vector6<S>::Zero());
    EXPECT_EQ(Force<S>::Zero().vector(), Vector6<S>::Zero());
    EXPECT_EQ(a.angular(), a.w);
    EXPECT_EQ(a.linear(), a.v);
    EXPECT_EQ(f.angular(), f.n);
    EXPECT_EQ(f.linear(), f.f);
    EXPECT_EQ(a.template cast<long double>().vector(), av.template cast<long double>());
    EXPECT_EQ(f.template cast<long double>().vector(), fv.template cast<long double>());
  }
}

TEST(Algebra, SkewIsCrossProduct) {
  Random<double> R(71);
  for (int t = 0; t < kTrials; ++t) {
    const Vector3<double> r = R.vec3(), p = R.vec3();
    EXPECT_LE((skew(r) * p - r.cross(p)).cwiseAbs().maxCoeff(), 4 * eps<double>());
    EXPECT_EQ(skew(r), crossmat(r));
  }
}

TEST(Algebra, CastPreservesTransformsAndInertias) {
  Random<double> R(72);
  const Transform<double> X = R.transform();
  const auto b = R.body();
  const Inertia<double> I = Inertia<double>::from_com(b.m, b.c, b.Ic);
  const Transform<long double> Xl = X.cast<long double>();
  const Inertia<long double> Il = I.cast<long double>();
  EXPECT_EQ(Xl.E, X.E.cast<long double>());
  EXPECT_EQ(Xl.r, X.r.cast<long double>());
  EXPECT_EQ(Il.m, static_cast<long double>(I.m));
  EXPECT_EQ(Il.h, I.h.cast<long double>());
  EXPECT_EQ(Il.I, I.I.cast<long double>());
}

// ---- compile-time type safety ----------------------------------------------------------------------------------
// Motion and force are different vector spaces; the only scalar product is m · f (notes, slide 3).

template <class A, class B, class = void>
struct has_dot : std::false_type {};
template <class A, class B>
struct has_dot<A, B, std::void_t<decltype(dot(std::declval<const A&>(), std::declval<const B&>()))>>
    : std::true_type {};

template <class A, class B, class = void>
struct has_plus : std::false_type {};
template <class A, class B>
struct has_plus<A, B, std::void_t<decltype(std::declval<const A&>() + std::declval<const B&>())>> : std::true_type {
};

template <class A, class B, class = void>
struct has_cross : std::false_type {};
template <class A, class B>
struct has_cross<A, B, std::void_t<decltype(cross(std::declval<const A&>(), std::declval<const B&>()))>>
    : std::true_type {};

static_assert(has_dot<Motion<double>, Force<double>>::value, "m · f must compile");
static_assert(has_dot<Force<double>, Motion<double>>::value, "f · m must compile");
static_assert(!has_dot<Motion<double>, Motion<double>>::value, "m · m must not compile");
static_assert(!has_dot<Force<double>, Force<double>>::value, "f · f must not compile");
static_assert(!has_plus<Motion<double>, Force<double>>::value, "motion + force must not compile");
static_assert(has_plus<Motion<double>, Motion<double>>::value, "motion + motion must compile");
static_assert(has_cross<Motion<double>, Motion<double>>::value, "v × m must compile");
static_assert(has_cross<Motion<double>, Force<double>>::value, "v ×* f must compile");
static_assert(!has_cross<Force<double>, Motion<double>>::value, "f × m must not compile");
static_assert(!std::is_convertible_v<Vector6<double>, Motion<double>>, "Motion from 6 numbers must be explicit");
static_assert(!std::is_convertible_v<Motion<double>, Force<double>>, "no motion → force conversion");

TEST(Algebra, TypeSafetyIsCheckedAtCompileTime) {
  // The static_asserts above are the test; this records them in the test report.
  EXPECT_FALSE((has_dot<Motion<double>, Motion<double>>::value));
  EXPECT_TRUE((has_dot<Motion<double>, Force<double>>::value));
}

}  // namespace
