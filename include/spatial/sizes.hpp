#pragma once
/// \file sizes.hpp
/// Size checks of the algorithms' vector arguments (q, q̇, q̈, τ), in one place. Every public entry point of
/// algorithms.hpp and options.hpp starts with one line
///
///   detail::check_sizes(model, "rnea", "q", q, "qd", qd, "qdd", qdd);
///
/// which costs nothing in a release build and does, per argument:
///  - compile-time tree and fixed-size argument: a `static_assert` that the argument has one entry per joint (so a
///    `Matrix<double, 20, 1>` given to a 21-DoF compile-time model does not compile);
///  - otherwise, unless NDEBUG is defined (or when SPATIAL_CHECK_SIZES=1 is defined), a run-time assertion: on a
///    wrong size it prints `spatial: rnea: argument 'q' has 20 entries, the model has 21 joints` to stderr and
///    aborts. With NDEBUG (release builds) nothing is checked at run time (define SPATIAL_CHECK_SIZES=1 to keep the
///    check, or use the `*_checked` entry points of checks.hpp, which return an `InputCheck` instead of aborting).
/// A wrong size is otherwise undefined behaviour: the algorithms read q[i] for every joint i.

#include "spatial/model.hpp"

#include <Eigen/Core>

#include <cstdio>
#include <cstdlib>

#ifndef SPATIAL_CHECK_SIZES
#ifdef NDEBUG
#define SPATIAL_CHECK_SIZES 0
#else
#define SPATIAL_CHECK_SIZES 1
#endif
#endif

namespace spatial {
namespace detail {

/// Prints which argument of which entry point has the wrong size, then aborts (the debug size assertion).
[[noreturn]] inline void size_assertion_failed(const char* function, const char* argument, long long given,
                                               long long expected) {
  std::fprintf(stderr, "spatial: %s: argument '%s' has %lld entries, the model has %lld joints (one entry per joint)\n",
               function, argument, given, expected);
  std::fflush(stderr);
  std::abort();
}

/// The check of one argument (see the file comment).
template <class S, class T, class V>
inline void check_size(const Model<S, T>& model, const Eigen::MatrixBase<V>& v, const char* function,
                       const char* argument) {
  constexpr int fixed = int(V::SizeAtCompileTime);
  if constexpr (Model<S, T>::is_static && fixed != int(Eigen::Dynamic)) {
    static_assert(fixed == Model<S, T>::NB,
                  "spatial: a fixed-size vector argument (q, qd, qdd or tau) does not have one entry per joint of the "
                  "compile-time tree");
  }
#if SPATIAL_CHECK_SIZES
  if (static_cast<long long>(v.size()) != static_cast<long long>(model.size()))
    size_assertion_failed(function, argument, static_cast<long long>(v.size()), model.size());
#else
  (void)model;
  (void)v;
  (void)function;
  (void)argument;
#endif
}

template <class S, class T>
inline void check_sizes(const Model<S, T>&, const char*) {}

/// check_sizes(model, "function", "q", q, "qd", qd, …): `check_size` for every (name, vector) pair.
template <class S, class T, class V, class... Rest>
inline void check_sizes(const Model<S, T>& model, const char* function, const char* argument,
                        const Eigen::MatrixBase<V>& v, const Rest&... rest) {
  check_size(model, v, function, argument);
  check_sizes(model, function, rest...);
}

}  // namespace detail
}  // namespace spatial
