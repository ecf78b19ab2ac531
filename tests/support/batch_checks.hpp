#pragma once
// The batched algorithms (batch.hpp) against the single-state calls, shared by test_batch.cpp (the default x86-64
// target: SSE2 lanes, 2 doubles / 4 floats; NEON on aarch64) and simd_batch.cpp (-mavx2 -mfma: 4 doubles / 8 floats).
//
// What is checked, per model (fixed base: Batch; floating base: FloatingBatch, whose q has nq = nv + 1 rows, the
// quaternion of each random state normalised), for double and float, for every B from 1 to 3 × lanes + 1, threads 1
// and 2:
//  - in double, every batched result equals the single-state call on the same state: to 1e-13 relative to the
//    result's largest entry (2e-12 for ABA and CRBA + LTDL, whose q̈ carries the conditioning of H);
//  - in float, the batched results are as accurate as the single-state float calls: over all the states of a
//    method, the largest distance of a batched result from the double single-state call is at most 4e-5 or twice
//    the single-state float call's largest (the float lanes compute their sines and cosines in float, a float
//    spacing or so from the single-state call's, so the two float results are not the same numbers; where H is
//    badly conditioned, q̈ of CRBA + LTDL on stance21, both are ~1e-3 from the double result in some states);
//  - a state's result is the same bits whatever B, the thread count and its neighbours: state j of the 3L+1 batch
//    on one thread = on two threads = state j alone (B = 1, where the group's other lanes repeat it);
//  - a NaN in one state stays in that state: the other states' results keep their bits (and RNEA's result of the
//    NaN state has a NaN).

#include <spatial/batch.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

namespace spatial::testing {

template <class S>
using BatchMatrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;

/// nv × B uniform in [−scale, scale].
template <class S>
BatchMatrix<S> random_states(int nv, int B, std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  BatchMatrix<S> X(nv, B);
  for (int j = 0; j < B; ++j)
    for (int i = 0; i < nv; ++i) X(i, j) = static_cast<S>(u(rng));
  return X;
}

/// |batched − single|∞ / max(|single|∞, 1e-300), in double.
template <class A, class B>
double batch_rel_diff(const Eigen::MatrixBase<A>& batched, const Eigen::MatrixBase<B>& single) {
  const auto b = batched.template cast<double>().eval();
  const auto s = single.template cast<double>().eval();
  const double scale = std::max(s.cwiseAbs().maxCoeff(), 1e-300);
  return (b - s).cwiseAbs().maxCoeff() / scale;
}

template <class A, class B>
bool same_bits(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index j = 0; j < a.cols(); ++j)
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      const auto x = a(i, j), y = b(i, j);
      if (!(x == y || (std::isnan(x) && std::isnan(y)))) return false;
    }
  return true;
}

/// The batch, model and data types of a model type: Batch for `Model<S, T>`, FloatingBatch for `FloatingModel<S, T>`.
template <class M>
struct BatchTypes;
template <class S, class T>
struct BatchTypes<Model<S, T>> {
  using BatchT = Batch<S, T>;
  using DataT = Data<S, T>;
};
template <class S, class T>
struct BatchTypes<FloatingModel<S, T>> {
  using BatchT = FloatingBatch<S, T>;
  using DataT = FloatingData<S, T>;
};

/// One batched algorithm as a function of the state matrices: `run(batch, Q, V, A, Out)`, and its single-state
/// twin `single(model, data, q, v, a) → result` (columns of Out per state: `width`). MT: the model type.
template <class MT>
struct BatchCase {
  using S = typename MT::Scalar;
  using BatchT = typename BatchTypes<MT>::BatchT;
  using DataT = typename BatchTypes<MT>::DataT;
  std::string name;
  int rows, width;  ///< the output is rows × (width · B)
  double tol_double;
  /// The output as a map with a run-time column stride: a plain matrix (each state's block contiguous: written
  /// through the lanes' transposition) or a block of rows of a larger matrix (written entry by entry).
  std::function<void(BatchT&, const BatchMatrix<S>&, const BatchMatrix<S>&, const BatchMatrix<S>&,
                     Eigen::Ref<BatchMatrix<S>, 0, Eigen::OuterStride<>>)>
      run;
  std::function<BatchMatrix<S>(const MT&, DataT&, const Eigen::Matrix<S, Eigen::Dynamic, 1>&,
                               const Eigen::Matrix<S, Eigen::Dynamic, 1>&, const Eigen::Matrix<S, Eigen::Dynamic, 1>&)>
      single;
};

template <class MT>
std::vector<BatchCase<MT>> batch_cases(const MT& model) {
  using S = typename MT::Scalar;
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using M = BatchMatrix<S>;
  using Out = Eigen::Ref<M, 0, Eigen::OuterStride<>>;
  using B = typename BatchCase<MT>::BatchT;
  using D = typename BatchCase<MT>::DataT;
  const int n = detail::ModelTraits<MT>::nv(model);
  std::vector<BatchCase<MT>> cases;
  cases.push_back({"rnea", n, 1, 1e-13,
                   [](B& b, const M& q, const M& v, const M& a, Out out) { b.rnea(q, v, a, out); },
                   [](const MT& m, D& d, const Vec& q, const Vec& v, const Vec& a) -> M {
                     return rnea(m, d, q, v, a);
                   }});
  cases.push_back({"gravity", n, 1, 1e-13,
                   [](B& b, const M& q, const M&, const M&, Out out) { b.gravity(q, out); },
                   [](const MT& m, D& d, const Vec& q, const Vec&, const Vec&) -> M {
                     return gravity_torques(m, d, q);
                   }});
  cases.push_back({"bias", n, 1, 1e-13,
                   [](B& b, const M& q, const M& v, const M&, Out out) { b.bias(q, v, out); },
                   [](const MT& m, D& d, const Vec& q, const Vec& v, const Vec&) -> M {
                     return bias_forces(m, d, q, v);
                   }});
  cases.push_back({"aba", n, 1, 2e-12,
                   [](B& b, const M& q, const M& v, const M& a, Out out) { b.aba(q, v, a, out); },
                   [](const MT& m, D& d, const Vec& q, const Vec& v, const Vec& a) -> M {
                     return aba(m, d, q, v, a);
                   }});
  cases.push_back({"forward_dynamics_crba", n, 1, 2e-12,
                   [](B& b, const M& q, const M& v, const M& a, Out out) {
                     b.forward_dynamics_crba(q, v, a, out);
                   },
                   [](const MT& m, D& d, const Vec& q, const Vec& v, const Vec& a) -> M {
                     return forward_dynamics_crba(m, d, q, v, a);
                   }});
  cases.push_back({"crba", n, n, 1e-13,
                   [](B& b, const M& q, const M&, const M&, Out out) { b.crba(q, out); },
                   [](const MT& m, D& d, const Vec& q, const Vec&, const Vec&) -> M {
                     return crba(m, d, q);
                   }});
  {
    // Up to three fixed frames: the first, a middle one and the last (a floating base's: its tree's, placed in
    // the world).
    const auto& all_frames = detail::ModelTraits<MT>::tree(model).frames();
    const int frames = static_cast<int>(all_frames.size());
    std::vector<int> picked;
    for (const int k : {0, frames / 2, frames - 1})
      if (k >= 0 && k < frames && std::find(picked.begin(), picked.end(), k) == picked.end()) picked.push_back(k);
    for (const int k : picked) {
      const std::string& name = all_frames[static_cast<std::size_t>(k)].name;
      cases.push_back({"frame_placement " + name, 3, 4, 1e-13,
                       [k](B& b, const M& q, const M&, const M&, Out out) { b.frame_placement(q, k, out); },
                       [k](const MT& m, D& d, const Vec& q, const Vec&, const Vec&) -> M {
                         forward_kinematics(m, d, q);
                         return frame_pose(m, d, k).matrix().topRows(3);
                       }});
      for (const ReferenceFrame rf :
           {ReferenceFrame::Local, ReferenceFrame::World, ReferenceFrame::LocalWorldAligned}) {
        cases.push_back({"frame_jacobian " + name + " rf " +
                             std::to_string(static_cast<int>(rf)),
                         6, n, 1e-13,
                         [k, rf](B& b, const M& q, const M&, const M&, Out out) {
                           b.frame_jacobian(q, k, rf, out);
                         },
                         [k, rf, n](const MT& m, D& d, const Vec& q, const Vec&, const Vec&) -> M {
                           M J = M::Zero(6, n);
                           compute_frame_jacobian(m, d, q, k, rf, J);
                           return J;
                         }});
      }
    }
  }
  {
    // A body's placement and Jacobian (the last body; a body is a frame with the identity on it).
    const int body = detail::ModelTraits<MT>::tree(model).size() - 1;
    cases.push_back({"body_placement " + std::to_string(body), 3, 4, 1e-13,
                     [body](B& b, const M& q, const M&, const M&, Out out) { b.body_placement(q, body, out); },
                     [body](const MT& m, D& d, const Vec& q, const Vec&, const Vec&) -> M {
                       forward_kinematics(m, d, q);
                       if constexpr (B::floating)
                         return body_pose(m, d, body).matrix().topRows(3);
                       else
                         return body_pose(d, body).matrix().topRows(3);
                     }});
    cases.push_back({"body_jacobian " + std::to_string(body), 6, n, 1e-13,
                     [body](B& b, const M& q, const M&, const M&, Out out) {
                       b.body_jacobian(q, body, ReferenceFrame::World, out);
                     },
                     [body, n](const MT& m, D& d, const Vec& q, const Vec&, const Vec&) -> M {
                       M J = M::Zero(6, n);
                       compute_body_jacobian(m, d, q, body, ReferenceFrame::World, J);
                       return J;
                     }});
  }
  return cases;
}

/// nq × B random configurations: uniform in [−scale, scale], a floating base's quaternion (rows 3 … 6) normalised.
template <class S, bool Floating>
BatchMatrix<S> random_configurations(int nq, int B, std::mt19937& rng, double scale) {
  BatchMatrix<S> Q = random_states<S>(nq, B, rng, scale);
  if constexpr (Floating)
    for (int j = 0; j < B; ++j) Q.col(j).template segment<4>(3).normalize();
  return Q;
}

/// Every check of the file comment for one model (given in double, `Model<double, T>` or `FloatingModel<double, T>`;
/// float runs its `cast<float>()`).
template <class S, class M64>
void check_batch(const M64& model64, const std::string& label, unsigned seed) {
  const auto model = model64.template cast<S>();
  using MT = std::remove_const_t<decltype(model)>;
  using BatchT = typename BatchTypes<MT>::BatchT;
  typename BatchTypes<MT>::DataT data(model);
  BatchT one(model, 1), two(model, 2);
  ASSERT_EQ(two.threads(), 2);
  constexpr int L = BatchT::lanes;
  const int n = detail::ModelTraits<MT>::nv(model), nq = detail::ModelTraits<MT>::nq(model);
  ASSERT_EQ(one.nv(), n);
  ASSERT_EQ(one.nq(), nq);
  const bool is_float = std::is_same_v<S, float>;
  std::mt19937 rng(seed);
  // The double calls, for the float single-state call's own error (the float tolerance).
  typename BatchTypes<M64>::DataT data64(model64);
  const auto cases64 = batch_cases(model64);
  const auto cases = batch_cases(model);
  for (std::size_t ci = 0; ci < cases.size(); ++ci) {
    const auto& c = cases[ci];
    double worst = 0;                                 // double: largest distance from the single-state call
    double worst_single = 0, worst_batched = 0;       // float: largest distances from the double call
    for (int B = 1; B <= 3 * L + 1; ++B) {
      const BatchMatrix<S> Q = random_configurations<S, BatchT::floating>(nq, B, rng, 2.0),
                           V = random_states<S>(n, B, rng, 2.0), A = random_states<S>(n, B, rng, 2.0);
      BatchMatrix<S> out1(c.rows, c.width * B), out2(c.rows, c.width * B);
      out1.setConstant(S(-7));
      out2.setConstant(S(-7));
      c.run(one, Q, V, A, out1);
      c.run(two, Q, V, A, out2);
      EXPECT_TRUE(same_bits(out1, out2)) << label << " " << c.name << ": B = " << B << ", 1 and 2 threads differ";
      for (int j = 0; j < B; ++j) {
        const auto got = out1.middleCols(j * c.width, c.width);
        const BatchMatrix<S> want = c.single(model, data, Q.col(j), V.col(j), A.col(j));
        if (is_float) {
          const Eigen::VectorXd q64 = Q.col(j).template cast<double>(), v64 = V.col(j).template cast<double>(),
                                a64 = A.col(j).template cast<double>();
          const BatchMatrix<double> exact = cases64[ci].single(model64, data64, q64, v64, a64);
          worst_single = std::max(worst_single, batch_rel_diff(want, exact));
          worst_batched = std::max(worst_batched, batch_rel_diff(got, exact));
          EXPECT_TRUE(got.allFinite()) << label << " " << c.name << " (float): B = " << B << ", state " << j;
        } else {
          const double e = batch_rel_diff(got, want);
          worst = std::max(worst, e);
          EXPECT_LE(e, c.tol_double) << label << " " << c.name << " (double): B = " << B << ", state " << j;
        }
      }
      if (B == 3 * L + 1) {
        // Each state alone (B = 1) gives the bits it has in the full batch.
        for (int j = 0; j < B; ++j) {
          BatchMatrix<S> alone(c.rows, c.width);
          c.run(one, Q.col(j), V.col(j), A.col(j), alone);
          EXPECT_TRUE(same_bits(alone, out1.middleCols(j * c.width, c.width)))
              << label << " " << c.name << ": state " << j << " alone differs from its value in the batch";
        }
        // The same bits into outputs whose states' blocks are not contiguous (written entry by entry instead of
        // through the lanes' transposition): rows 1 … rows of a larger matrix, whose other rows stay as they were.
        BatchMatrix<S> big(c.rows + 2, c.width * B);
        big.setConstant(S(-7));
        c.run(one, Q, V, A, big.middleRows(1, c.rows));
        EXPECT_TRUE(same_bits(big.middleRows(1, c.rows), out1)) << label << " " << c.name << ": into a block";
        EXPECT_TRUE((big.row(0).array() == S(-7)).all() && (big.row(c.rows + 1).array() == S(-7)).all())
            << label << " " << c.name << ": wrote outside its block";
        // A NaN in state 1's q (and in state 2's q̇ or τ) stays there.
        BatchMatrix<S> Qn = Q, Vn = V;
        Qn(nq / 2, 1) = std::numeric_limits<S>::quiet_NaN();
        Vn(0, 2) = std::numeric_limits<S>::quiet_NaN();
        BatchMatrix<S> outn(c.rows, c.width * B);
        c.run(two, Qn, Vn, A, outn);
        // And it does reach its own state's result: RNEA's τ of the NaN joint depends on its q (state 1), and τ of
        // joint 0 on the velocity of body 0 (state 2). (Which other entries turn NaN depends on the code path: the
        // single-state AVX2 kernels spread it further, so the NaN pattern is not compared with theirs.)
        if (c.name == "rnea") {
          for (const int j : {1, 2})
            EXPECT_TRUE(outn.middleCols(j * c.width, c.width).hasNaN()) << label << ": NaN state " << j;
        }
        for (int j = 0; j < B; ++j) {
          if (j == 1 || j == 2) continue;
          EXPECT_TRUE(same_bits(outn.middleCols(j * c.width, c.width), out1.middleCols(j * c.width, c.width)))
              << label << " " << c.name << ": a NaN in states 1 and 2 changed state " << j;
        }
      }
    }
    if (is_float) {
      EXPECT_LE(worst_batched, std::max(4e-5, 2 * worst_single))
          << label << " " << c.name << " (float): the batched results are further from the double results than the "
          << "single-state float calls";
      std::printf("[ batch ] %-16s %-40s float  lanes %2d: max rel. diff from the double call %.1e (single-state "
                  "float call: %.1e)\n",
                  label.c_str(), c.name.c_str(), L, worst_batched, worst_single);
    } else {
      std::printf("[ batch ] %-16s %-40s double lanes %2d: max rel. diff from the single-state call %.1e\n",
                  label.c_str(), c.name.c_str(), L, worst);
    }
  }
}

}  // namespace spatial::testing
