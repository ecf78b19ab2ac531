// The batched algorithms on this target's default lanes (x86-64: SSE2; aarch64: NEON): tests/support/batch_suite.hpp.
#include "support/batch_suite.hpp"

namespace {
TEST(Batch, LanesOfTheDefaultTarget) {
  // 16-byte registers on both targets this file is built for: 2 doubles, 4 floats.
  EXPECT_EQ(spatial::Batch<double>::lanes, static_cast<int>(16 / sizeof(double)));
  EXPECT_EQ(spatial::Batch<float>::lanes, 2 * spatial::Batch<double>::lanes);
}
}  // namespace
