// Compile-time trees (branched with every joint type, two roots, a 12-body chain) against their run-time twins:
// every algorithm gives the same numbers (support/static_trees.hpp).
#include "support/static_trees.hpp"

#include <gtest/gtest.h>

namespace {

using namespace spatial;
using namespace spatial::testing;
using namespace spatial::testing::static_trees;

Worst g_worst;

TEST(CompileTimeTree, Branched8EveryJointType) {
  for (unsigned seed : {1u, 2u, 3u}) compare_static_and_dynamic<Branched8>(seed, g_worst);
}
TEST(CompileTimeTree, Branched7TwoRoots) {
  for (unsigned seed : {4u, 5u}) compare_static_and_dynamic<Branched7>(seed, g_worst);
}
TEST(CompileTimeTree, Chain12) {
  for (unsigned seed : {6u, 7u}) compare_static_and_dynamic<Chain12>(seed, g_worst);
}
TEST(CompileTimeTree, FixedSizeBuffers) {
  static_assert(Data<double, Branched8>::VectorN::RowsAtCompileTime == 8);
  static_assert(Data<double, Branched8>::MatrixN::RowsAtCompileTime == 8);
  static_assert(Data<double, Chain66>::VectorN::RowsAtCompileTime == 66);
  static_assert(Data<double, Chain66>::MatrixN::RowsAtCompileTime == Eigen::Dynamic);
  static_assert(Model<double, Branched8>::parent(std::integral_constant<int, 7>{}) == 2);
  const Model<double> md = spatial::testing::build_model(bodies_for<Chain66>(1));
  const auto ms = Model<double, Chain66>::from(md);
  Data<double, Chain66> d(ms);
  EXPECT_EQ(d.H.rows(), 66);
  EXPECT_EQ(d.L.cols(), 66);
}

TEST(CompileTimeTree, PrintWorst) { g_worst.print("compile-time vs run-time trees"); }

}  // namespace
