// The batched algorithms on AVX2 lanes (this executable is built with -mavx2 -mfma): tests/support/batch_suite.hpp,
// over its run-time trees (random trees of every joint type, double and float). The compile-time HOAP-3 cases run
// on SSE2 lanes in test_batch.cpp, and on AVX-512 (or AVX2) lanes in bench_batch's check before timing
// (scripts/main.sh); here they would add ~60 CPU seconds to every CI build for the same per-body code.
#define SPATIAL_TEST_COMPILE_TIME_TREES 0
#include "support/batch_suite.hpp"

namespace {
TEST(Batch, AvxLanes) {
  EXPECT_EQ(spatial::Batch<double>::lanes, 4);
  EXPECT_EQ(spatial::Batch<float>::lanes, 8);
}
}  // namespace
