#pragma once
/// \file peer_check.hpp
/// The numerical check every peer benchmark runs once, before timing: the peer's result must match ours on the
/// same model and inputs, or the benchmark aborts (a timing of a peer that computes something else is meaningless).

#include <Eigen/Core>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace spatial::peers {

/// ‖a − b‖∞ / max(‖b‖∞, tiny): normwise relative difference of any two Eigen objects of the same shape.
template <class A, class B>
double relative_difference(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  const double scale = b.template cast<double>().cwiseAbs().maxCoeff();
  const double diff = (a.template cast<double>() - b.template cast<double>()).cwiseAbs().maxCoeff();
  return diff / (scale > 1e-300 ? scale : 1e-300);
}

/// Keeps the largest relative difference seen for one quantity and aborts the program if it exceeds `tolerance`.
struct PeerCheck {
  std::string what;
  double tolerance;
  double worst = 0.0;

  template <class A, class B>
  void compare(const Eigen::MatrixBase<A>& peer, const Eigen::MatrixBase<B>& ours) {
    const double d = relative_difference(peer, ours);
    if (!(d <= tolerance)) {
      std::fprintf(stderr, "peer check FAILED: %s differs from spatial by %.3e (relative; tolerance %.1e)\n",
                   what.c_str(), d, tolerance);
      std::abort();
    }
    if (d > worst) worst = d;
  }
  void report() const { std::fprintf(stderr, "peer check ok: %-48s max relative difference %.2e\n", what.c_str(), worst); }
};

}  // namespace spatial::peers
