#pragma once
// SPATIAL_TEST_COMPILE_TIME_TREES: 1, except in the sanitizer build (AddressSanitizer), where it is 0. Tests guard
// their compile-time-tree cases (the generated HOAP-3 models) with it: those cases unroll every algorithm over 8–27
// coordinates, and unoptimised and instrumented, one such translation unit needs ~10 GB and minutes to compile.
// The run-time-tree cases, which run the same templates over the same per-body code, cover the memory and UB
// checks there. Defined beforehand (e.g. -DSPATIAL_TEST_COMPILE_TIME_TREES=1), the definition is kept.
#ifndef SPATIAL_TEST_COMPILE_TIME_TREES
#if defined(__SANITIZE_ADDRESS__)
#define SPATIAL_TEST_COMPILE_TIME_TREES 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SPATIAL_TEST_COMPILE_TIME_TREES 0
#endif
#endif
#endif
#ifndef SPATIAL_TEST_COMPILE_TIME_TREES
#define SPATIAL_TEST_COMPILE_TIME_TREES 1
#endif
