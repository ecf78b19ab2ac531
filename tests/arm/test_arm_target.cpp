// What the aarch64 build (tests/arm/CMakeLists.txt, scripts/arm.sh) really builds: 64-bit ARM code with NEON, with
// Eigen's fixed-size types vectorised by its NEON packets (two doubles per register) and xsimd's default
// architecture NEON64, so that the other tests of this binary run the library's vectorised paths as an ARM
// computer does, not a scalar fallback.

#include <Eigen/Core>

#include <gtest/gtest.h>

#include <string>
#include <type_traits>

#if __has_include(<xsimd/xsimd.hpp>)
#include <xsimd/xsimd.hpp>
#define SPATIAL_ARM_HAVE_XSIMD 1
#endif

TEST(ArmTarget, IsAarch64WithNeon) {
#if !defined(__aarch64__) || !defined(__ARM_NEON)
  FAIL() << "this binary is not built for aarch64 with NEON";
#endif
  EXPECT_EQ(sizeof(void*), 8u);
}

TEST(ArmTarget, EigenVectorisesWithNeon) {
#ifndef EIGEN_VECTORIZE_NEON
  FAIL() << "Eigen does not use NEON here";
#endif
  EXPECT_NE(std::string(Eigen::SimdInstructionSetsInUse()).find("NEON"), std::string::npos)
      << Eigen::SimdInstructionSetsInUse();
  EXPECT_EQ(Eigen::internal::packet_traits<double>::size, 2);
  EXPECT_TRUE(bool(Eigen::internal::packet_traits<double>::Vectorizable));
}

#ifdef SPATIAL_ARM_HAVE_XSIMD
TEST(ArmTarget, XsimdDefaultArchitectureIsNeon64) {
  EXPECT_TRUE((std::is_same<xsimd::default_arch, xsimd::neon64>::value)) << xsimd::default_arch::name();
  EXPECT_EQ(xsimd::batch<double>::size, 2u);
  EXPECT_EQ(xsimd::batch<float>::size, 4u);
  const double in[2] = {1.5, -2.0};
  const auto a = xsimd::batch<double>::load_unaligned(in);
  const xsimd::batch<double> b = xsimd::fma(a, a, xsimd::batch<double>(0.25));
  alignas(16) double out[2];
  b.store_aligned(out);
  EXPECT_EQ(out[0], 2.5);
  EXPECT_EQ(out[1], 4.25);
}
#endif
