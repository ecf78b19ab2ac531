// Part of the stress suite (spatial_stress_tests, label "stress").
// Bad numbers into the algorithms (checks.hpp): NaN and Inf in q, q̇, q̈ or τ never crash, throw or corrupt the
// model or a later call; the checks name the argument, the index and the joint; the checked entry points refuse
// bad input without touching `data`; and NaN in qᵢ spreads exactly to the joints the README says.

#include "support/random_model.hpp"

#include <spatial/spatial.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace st = spatial::testing;
using Vec = Eigen::VectorXd;
using J = JointType;

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

/// Every output of every algorithm for one state, concatenated (NaN compares equal to NaN bit for bit here).
template <class T, class V>
Vec all_outputs(const Model<double, T>& m, Data<double, T>& d, const V& q, const V& qd, const V& qdd,
                const V& tau) {
  std::vector<double> out;
  auto add = [&](const auto& v) {
    for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(v.data()[i]);
  };
  add(rnea(m, d, q, qd, qdd));
  add(bias_forces(m, d, q, qd));
  add(gravity_torques(m, d, q));
  add(crba(m, d, q));
  ltdl(m, d);
  add(d.L);
  add(forward_dynamics_crba(m, d, q, qd, tau));
  add(aba(m, d, q, qd, tau));
  forward_kinematics(m, d, q);
  add(body_pose(d, m.size() - 1).matrix());
  out.push_back(kinetic_energy(m, d, q, qd));
  out.push_back(potential_energy(m, d, q));
  add(center_of_mass(m, d, q));
  return Eigen::Map<Vec>(out.data(), static_cast<Eigen::Index>(out.size()));
}

bool same_bits(const Vec& a, const Vec& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * std::size_t(a.size())) == 0;
}

template <class S, class T>
bool same_model(const Model<S, T>& a, const Model<S, T>& b) {
  if (a.size() != b.size() || a.gravity() != b.gravity()) return false;
  for (int i = 0; i < a.size(); ++i)
    if (a.inertia(i).m != b.inertia(i).m || a.inertia(i).h != b.inertia(i).h || a.inertia(i).I != b.inertia(i).I ||
        a.tree_transform(i).E != b.tree_transform(i).E || a.tree_transform(i).r != b.tree_transform(i).r ||
        a.axis(i) != b.axis(i) || a.parent(i) != b.parent(i))
      return false;
  return true;
}

/// For every argument, index and bad value: the algorithms run (no crash, no throw), the model is unchanged, and
/// the next call with good input gives bit for bit what a fresh Data gives.
template <class T, class V>
void bad_values_do_no_harm(const Model<double, T>& model, const V& q, const V& qd, const V& qdd, const V& tau) {
  const Model<double, T> copy = model;
  Data<double, T> fresh(model);
  const Vec good = all_outputs(model, fresh, q, qd, qdd, tau);
  ASSERT_TRUE(good.allFinite());
  Data<double, T> d(model);
  for (int arg = 0; arg < 4; ++arg)
    for (int i = 0; i < model.size(); ++i)
      for (double bad : {kNaN, kInf, -kInf, 1e308}) {
        V in[4] = {q, qd, qdd, tau};
        in[arg][i] = bad;
        const Vec out = all_outputs(model, d, in[0], in[1], in[2], in[3]);
        if (bad != 1e308) {
          EXPECT_FALSE(out.allFinite()) << "arg " << arg << " index " << i;
        }
        const InputCheck c = check_finite(model, in[0], in[1], arg == 3 ? in[3] : in[2], arg == 3 ? "tau" : "qdd");
        if (bad == 1e308) {
          EXPECT_TRUE(c.ok());
        } else {
          ASSERT_FALSE(c.ok());
          static const char* const names[] = {"q", "qd", "qdd", "tau"};
          EXPECT_STREQ(c.argument, names[arg]);
          EXPECT_EQ(c.index, i);
          EXPECT_EQ(std::string(c.joint), model.joint_name(i));
          EXPECT_STREQ(c.reason, std::isnan(bad) ? "NaN" : bad > 0 ? "+Inf" : "-Inf");
        }
        ASSERT_TRUE(same_model(model, copy));
        ASSERT_TRUE(same_bits(all_outputs(model, d, q, qd, qdd, tau), good))
            << "a good call after bad input (arg " << arg << ", index " << i << ", " << bad << ") differs";
      }
}

TEST(BadInput, RunTimeModelSurvivesNaNAndInf) {
  const Model<double> m = st::random_model(9, st::Shape::Branched, 17);
  std::mt19937 rng(3);
  const int n = m.size();
  bad_values_do_no_harm(m, st::random_vector(n, rng), st::random_vector(n, rng), st::random_vector(n, rng),
                        st::random_vector(n, rng));
}

using Tree5 = Tree<Parents<-1, 0, 1, 0, 3>, Joints<J::RevoluteZ, J::RevoluteY, J::PrismaticX, J::RevoluteAxis, J::RevoluteX>>;

TEST(BadInput, CompileTimeModelSurvivesNaNAndInf) {
  const Model<double> md = st::build_model([] {
    auto b = st::random_bodies(5, st::Shape::Chain, 23);
    const int parents[] = {-1, 0, 1, 0, 3};
    const J types[] = {J::RevoluteZ, J::RevoluteY, J::PrismaticX, J::RevoluteAxis, J::RevoluteX};
    for (int i = 0; i < 5; ++i) {
      b[std::size_t(i)].parent = parents[i];
      b[std::size_t(i)].type = types[i];
    }
    return b;
  }());
  const auto m = Model<double, Tree5>::from(md);
  using V5 = Eigen::Matrix<double, 5, 1>;
  const V5 q(0.3, -1, 0.2, 2, 0.5), qd(1, -0.5, 0.3, 0.1, 2), qdd(-1, 2, 0.5, 0, 1), tau(0.1, -0.2, 3, 0.5, -1);
  bad_values_do_no_harm(m, q, qd, qdd, tau);
}

TEST(BadInput, NaNInAJointAngleReachesItsSubtreeAndAncestorsOnly) {
  // Body 0 has children 1 and 4; 1 has 2 and 3; 4 has 5. NaN in q₁ makes ¹X₀ NaN: bodies 1, 2, 3 move by NaN,
  // their forces are NaN, and so are the torques of joints 1, 2, 3 and of the ancestor 0. Joints 4 and 5 are
  // untouched in RNEA.
  auto b = st::random_bodies(6, st::Shape::Chain, 29, false);
  const int parents[] = {-1, 0, 1, 1, 0, 4};
  for (int i = 0; i < 6; ++i) b[std::size_t(i)].parent = parents[i];
  const Model<double> m = st::build_model(b);
  Data<double> d(m);
  std::mt19937 rng(4);
  Vec q = st::random_vector(6, rng);
  const Vec qd = st::random_vector(6, rng), qdd = st::random_vector(6, rng);
  q[1] = kNaN;
  const Vec tau = rnea(m, d, q, qd, qdd);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(std::isnan(tau[i]), i <= 3) << "tau[" << i << "] = " << tau[i];
  // CRBA forms H(a, k) = S⁰ₐ · F⁰ₖ in base coordinates (a ancestor of k): ⁰X₁ is NaN, so are the base-frame
  // axes and composite forces of bodies 1–3 and the composite inertia of body 0. H(a, k) is NaN exactly when the
  // pair is related and k (the descendant) is related to 1; the 4–5 branch except H(0, 0) stays finite.
  const Eigen::MatrixXd H = crba(m, d, q);
  auto related1 = [&](int k) { return m.is_ancestor_or_self(k, 1) || m.is_ancestor_or_self(1, k); };
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const bool related = m.is_ancestor_or_self(i, j) || m.is_ancestor_or_self(j, i);
      const int a = std::min(i, j), k = std::max(i, j);  // in a related pair, the ancestor has the lower index
      (void)a;
      // the diagonal of the subtree of 1 is formed in body coordinates: finite
      const bool expect = related && related1(k) && !(i == j && m.is_ancestor_or_self(1, k));
      EXPECT_EQ(std::isnan(H(i, j)), expect) << "H(" << i << ", " << j << ")";
    }
}

TEST(BadInput, ChecksReportSizeAndArgument) {
  const Model<double> m = st::random_model(4, st::Shape::Chain, 31);
  const Vec good = Vec::Constant(4, 0.5), shorter = Vec::Zero(3);
  EXPECT_TRUE(check_finite(m, good).ok());
  EXPECT_TRUE(check_finite(m, good, good).ok());
  EXPECT_TRUE(bool(check_finite(m, good, good, good)));
  InputCheck c = check_finite(m, good, shorter);
  ASSERT_FALSE(c.ok());
  EXPECT_STREQ(c.argument, "qd");
  EXPECT_EQ(c.index, 3);
  EXPECT_EQ(c.joint, nullptr);
  EXPECT_NE(std::string(c.reason).find("size"), std::string::npos);
  // The first bad argument wins, then the first bad index.
  Vec a = good, b = good;
  a[2] = kNaN;
  b[0] = kInf;
  c = check_finite(m, good, a, b, "tau");
  EXPECT_STREQ(c.argument, "qd");
  EXPECT_EQ(c.index, 2);
  EXPECT_STREQ(c.joint, "joint2");
  c = check_finite(m, good, good, b, "tau");
  EXPECT_STREQ(c.argument, "tau");
  EXPECT_EQ(c.index, 0);
  EXPECT_EQ(c.value, kInf);
  a[1] = -kInf;
  c = check_finite(m, a);
  EXPECT_EQ(c.index, 1);
  EXPECT_STREQ(c.reason, "-Inf");
}

TEST(BadInput, CheckedEntryPointsRefuseWithoutTouchingData) {
  const Model<double> m = st::random_model(7, st::Shape::Branched, 37);
  Data<double> d(m), ref(m);
  std::mt19937 rng(5);
  const Vec q = st::random_vector(7, rng), qd = st::random_vector(7, rng), x = st::random_vector(7, rng);
  // Good input: exactly the unchecked result.
  ASSERT_TRUE(rnea_checked(m, d, q, qd, x).ok());
  EXPECT_TRUE(same_bits(d.tau, rnea(m, ref, q, qd, x)));
  ASSERT_TRUE(aba_checked(m, d, q, qd, x).ok());
  EXPECT_TRUE(same_bits(d.qdd, aba(m, ref, q, qd, x)));
  ASSERT_TRUE(forward_dynamics_crba_checked(m, d, q, qd, x).ok());
  EXPECT_TRUE(same_bits(d.qdd, forward_dynamics_crba(m, ref, q, qd, x)));
  // Bad input: refused, outputs left as they were.
  const Vec tau_before = d.tau, qdd_before = d.qdd;
  Vec bad = x;
  bad[6] = kNaN;
  InputCheck c = rnea_checked(m, d, q, qd, bad);
  EXPECT_STREQ(c.argument, "qdd");
  EXPECT_EQ(c.index, 6);
  c = aba_checked(m, d, bad, qd, x);
  EXPECT_STREQ(c.argument, "q");
  c = forward_dynamics_crba_checked(m, d, q, qd, bad);
  EXPECT_STREQ(c.argument, "tau");
  EXPECT_STREQ(c.joint, "joint6");
  EXPECT_TRUE(same_bits(d.tau, tau_before));
  EXPECT_TRUE(same_bits(d.qdd, qdd_before));
}

TEST(BadInput, CheckedForwardDynamicsNamesAJointThatMovesNoInertia) {
  ModelBuilder<double> b;
  const Inertia<double> link = Inertia<double>::from_com(1.0, {0.2, 0, 0}, Matrix3<double>::Identity() * 1e-3);
  b.add_body("upper", -1, J::RevoluteZ, Transform<double>::Identity(), link, Vector3<double>::Zero(), "shoulder");
  b.add_body("ghost", 0, J::RevoluteY, xlt<double>({0.4, 0, 0}), Inertia<double>::Zero(), Vector3<double>::Zero(), "wrist");
  const Model<double> m = b.build();
  Data<double> d(m);
  const Eigen::Vector2d q(0.1, 0.2), qd(0, 0), tau(0, 0);
  for (const InputCheck& c : {aba_checked(m, d, q, qd, tau), forward_dynamics_crba_checked(m, d, q, qd, tau)}) {
    ASSERT_FALSE(c.ok());
    EXPECT_STREQ(c.argument, "result");
    EXPECT_EQ(c.index, 1);
    EXPECT_STREQ(c.joint, "wrist");
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
// URDF: regressions found by the fuzzer (tests/fuzz/). Under ASan (LeakSanitizer) a leak fails the test binary.
// ---------------------------------------------------------------------------------------------------------------

#include <spatial/urdf.hpp>
#include "support/urdf_reference.hpp"

namespace {

TEST(FuzzRegression, LoopWithASecondRootIsRejectedWithoutLeaking) {
  // A link that is the child of two joints, in a file that urdfdom rejects for another reason (two roots): urdfdom
  // returned null after linking the loop's links to each other with shared pointers, and they leaked.
  for (const char* file : {"test/bad/loop_two_roots.urdf", "../tests/fuzz/corpus/regress_leak_loop_two_roots.urdf"}) {
    SCOPED_TRACE(file);
    try {
      (void)spatial::urdf_io::load_file(spatial::testing::urdf_path(file));
      ADD_FAILURE() << "accepted";
    } catch (const spatial::ModelError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("child of two joints"), std::string::npos) << msg;
    }
  }
}

}  // namespace
