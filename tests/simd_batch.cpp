// The batched algorithms on AVX2 lanes (this executable is built with -mavx2 -mfma): tests/support/batch_suite.hpp.
#include "support/batch_suite.hpp"

namespace {
TEST(Batch, AvxLanes) {
  EXPECT_EQ(spatial::Batch<double>::lanes, 4);
  EXPECT_EQ(spatial::Batch<float>::lanes, 8);
}
}  // namespace
