#pragma once
// The guard of the no-allocation tests (tests/nomalloc_*.cpp, one executable built with EIGEN_RUNTIME_NO_MALLOC and
// without NDEBUG): Eigen's run-time check plus the count of global operator new calls that
// nomalloc_algorithms.cpp keeps.

#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "nomalloc tests must be compiled with -DEIGEN_RUNTIME_NO_MALLOC"
#endif
#ifdef NDEBUG
#error "nomalloc tests need eigen_assert: compile without NDEBUG (-UNDEBUG)"
#endif

#include <Eigen/Core>

/// Calls of the global operator new so far (nomalloc_algorithms.cpp counts them).
long spatial_nomalloc_new_calls();

namespace spatial::testing {

/// No Eigen heap allocation and no operator new between construction and destruction.
class NoAllocationRegion {
 public:
  NoAllocationRegion() : before_(spatial_nomalloc_new_calls()) { Eigen::internal::set_is_malloc_allowed(false); }
  ~NoAllocationRegion() { Eigen::internal::set_is_malloc_allowed(true); }
  long new_calls() const { return spatial_nomalloc_new_calls() - before_; }

 private:
  long before_;
};

}  // namespace spatial::testing
