// A 66-body compile-time chain (beyond kMaxFixedMatrixSize: H and L are dynamic-size, ancestor walks are not
// unrolled) against its run-time twin (support/static_trees.hpp). Its own file: the instantiations are the heaviest
// of the suite, and a separate translation unit compiles in parallel with the rest.
#include "support/static_trees.hpp"

#include <gtest/gtest.h>

namespace {

using namespace spatial;
using namespace spatial::testing;
using namespace spatial::testing::static_trees;

TEST(CompileTimeTree, Chain66DynamicMatrices) {
  Worst worst;
  compare_static_and_dynamic<Chain66, false>(8, worst);
  worst.print("compile-time vs run-time trees, 66-body chain");
}

}  // namespace
