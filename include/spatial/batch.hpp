#pragma once
/// \file batch.hpp
/// Many states per call: the algorithms over B states at once, each SIMD lane one state.
///
///   #include <spatial/batch.hpp>          // needs xsimd (CMake target spatial::batch)
///   spatial::Batch<double, Tree> batch(model, /*threads=*/2);
///   batch.rnea(Q, V, A, Tau);             // Q, V, A, Tau: nv × B, column j = state j
///
/// ## How
/// The library's algorithms are written once for any scalar type. Here the scalar is `xsimd::batch<S>`, a SIMD
/// register of `lanes` values (xsimd's best instruction set enabled at compile time: 8 doubles with AVX-512, 4 with
/// AVX2, 2 with SSE2 or ARM NEON; twice as many floats), and the model is the same model with every number broadcast
/// to all lanes (`Model::cast`). One call of an algorithm on that model then runs `lanes` states at once, in
/// structure-of-arrays form: every operation of the scalar code becomes one vector instruction over the lanes, with
/// no shuffle and no horizontal sum, and the compile-time trees keep their unrolled code. Sines and cosines are the
/// library's own (sincos.hpp) computed on the lanes. B need not be a multiple of `lanes`: the last group's unused
/// lanes repeat its last state and their results are dropped. States are split over `threads` threads (a pool of the object's own, started once),
/// each with its own workspace; a state's result does not depend on B, on the thread count or on the other states
/// of its group, bit for bit (lanes never mix: a NaN in one state stays in that state).
///
/// ## Why xsimd
/// It is a maintained, header-only, Debian-packaged (libxsimd-dev) wrapper whose `batch<T>` is a value type with
/// the arithmetic operators and vectorised elementary functions (sincos, sqrt) of a scalar, so the library's
/// scalar-templated algorithms run on it unchanged, and the same source compiles to SSE2, AVX2, AVX-512 or NEON by
/// compiler flags alone. Google Highway dispatches at run time but its vectors are not value types with operators
/// (each operation names a tag), so every algorithm would have to be written a second time; Eigen's packet math is
/// internal API. The price of xsimd: the instruction set is fixed when the caller compiles (build with
/// -march=native, or -mavx2 -mfma, for wide lanes; the default x86-64 target gets SSE2's two doubles).
///
/// ## Numbers against the single-state calls
/// The operations are those of the scalar code path, but not bit for bit those of a single-state call: the
/// single-state double calls on compile-time trees of axis-aligned revolute joints take the AVX2 kernels of simd.hpp
/// (another order of the same sums), and the compiler contracts multiply-adds into FMAs at different places in
/// vector and in scalar code. In double they agree to a few units in the last place of the result's scale
/// (tests/support/batch_checks.hpp holds them to 1e-13 relative). Float lanes compute their sines and cosines in
/// float (`sincos_lanes`, within two float spacings of the correctly rounded values; the single-state float calls
/// round the double kernel's), which took 15 % off a batched float RNEA against the detour through double (README);
/// the float results are therefore other roundings of the same quantities, as accurate against the double calls as
/// the single-state float calls are (batch_checks.hpp: over all states, never more than twice as far; where H is
/// badly conditioned, q̈ of CRBA + LTDL on stance21, both are ~1e-3 from double in some states).
///
/// ## Cost and limits
/// Allocation-free after construction, no exception, no virtual call. Fixed-base trees (`Batch`) and floating-base
/// trees (`FloatingBatch`), compile-time or run-time, every joint type. Not batched (yet): external forces, the
/// derivatives.

#include "spatial/spatial.hpp"

#include <Eigen/Core>
#include <xsimd/xsimd.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace Eigen {
/// xsimd's batch as an Eigen scalar: a real number (per lane) that costs one instruction per operation.
template <class T, class A>
struct NumTraits<xsimd::batch<T, A>> : GenericNumTraits<T> {
  using Real = xsimd::batch<T, A>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 0,
    ReadCost = 1,
    AddCost = 1,
    MulCost = 1
  };
};
}  // namespace Eigen

namespace spatial {

/// The SIMD register type the batched algorithms compute in: `Lanes<S>::size` states of scalar S.
template <class S>
using Lanes = xsimd::batch<S>;

namespace detail {
/// `sincos_lanes`' rare path, out of line (inlined, it made the callers' code larger and slower): the entries of
/// entries x[l], l < n ≤ kMaxLanes, with |x[l]| ≥ limit, Inf or NaN get the single-state calls' sine and cosine
/// (`sincos_all`).
inline constexpr int kMaxLanes = 64;  // more than any register holds (16 floats with AVX-512)
template <class T>
[[gnu::cold, gnu::noinline]] void sincos_slow_lanes(const T* x, T limit, T* s, T* c, int n) {
  T s1[kMaxLanes], c1[kMaxLanes];
  sincos_all<T>(x, c1, s1, n);
  for (int l = 0; l < n; ++l)
    if (!(std::abs(x[l]) < limit)) {
      s[l] = s1[l];
      c[l] = c1[l];
    }
}

/// sin and cos of the lanes, every operation lane-wise (xsimd's own sin and cos pick their argument reduction by
/// testing all lanes, so a lane's result would depend on the other states of its group): sincos.hpp's kernels on
/// the batch, `sincos_reduce` for double lanes and `sincos_reduce_float` for float lanes (float throughout), then
/// `sincos_quadrant`. Lanes beyond the kernel's limit (kSincosFastLimit, kSincosFloatFastLimit), Inf or NaN take
/// the single-state calls' values (`sincos_all` on the register's lanes: in double, rounded to float for float lanes).
template <class T, class A>
SPATIAL_INLINE void sincos_lanes(const xsimd::batch<T, A>& x, xsimd::batch<T, A>& s, xsimd::batch<T, A>& c) {
  constexpr bool is_float = std::is_same_v<T, float>;
  using B = xsimd::batch<T, A>;
  using U = xsimd::batch<std::conditional_t<is_float, std::uint32_t, std::uint64_t>, A>;
  B t, sr, cr;
  if constexpr (is_float) sincos_reduce_float(x, t, sr, cr);
  else sincos_reduce(x, t, sr, cr);
  U sin_bits, cos_bits;
  sincos_quadrant<8 * sizeof(T)>(xsimd::bitwise_cast<U>(t), xsimd::bitwise_cast<U>(sr), xsimd::bitwise_cast<U>(cr),
                                 sin_bits, cos_bits);
  s = xsimd::bitwise_cast<B>(sin_bits);
  c = xsimd::bitwise_cast<B>(cos_bits);
  const T limit = is_float ? T(kSincosFloatFastLimit) : T(kSincosFastLimit);
  const auto slow = !(xsimd::abs(x) < B(limit));
  if (xsimd::any(slow)) {
    constexpr std::size_t n = B::size;
    alignas(A::alignment()) T xs[n], ss[n], cs[n];
    x.store_aligned(xs);
    s.store_aligned(ss);
    c.store_aligned(cs);
    static_assert(n <= kMaxLanes, "sincos_slow_lanes: more lanes than kMaxLanes");
    sincos_slow_lanes(xs, limit, ss, cs, static_cast<int>(n));
    s = B::load_aligned(ss);
    c = B::load_aligned(cs);
  }
}

/// sin and cos of all lanes (sincos.hpp's customisation point): `sincos_lanes`.
template <class T, class A>
struct SincosTraits<xsimd::batch<T, A>> {
  static_assert(std::is_same_v<T, double> || std::is_same_v<T, float>, "batch.hpp: lanes of float or double");
  static constexpr bool custom = true;
  static SPATIAL_INLINE void sincos(const xsimd::batch<T, A>& x, xsimd::batch<T, A>& s, xsimd::batch<T, A>& c) {
    sincos_lanes(x, s, c);
  }
};

/// Constants of `transpose_lanes` for the stage that swaps blocks of D lanes: lane i is in the upper block of its
/// pair when i & D, and moves D lanes down (`LaneShiftDown`) or up (`LaneShiftUp`).
template <std::size_t D>
struct LaneUpper {
  static constexpr bool get(std::size_t i, std::size_t) { return (i & D) != 0; }
};
template <std::size_t D>
struct LaneShiftDown {
  static constexpr std::size_t get(std::size_t i, std::size_t) { return (i & D) != 0 ? i - D : i; }
};
template <std::size_t D>
struct LaneShiftUp {
  static constexpr std::size_t get(std::size_t i, std::size_t) { return (i & D) != 0 ? i : i + D; }
};

/// Transposes the N × N block of values held by N registers of N lanes in place (N = the register's lane count, a
/// power of two): afterwards lane j of a[i] is what lane i of a[j] was. Stage D (N/2, N/4, …, 1) swaps, in each
/// pair of registers i and i + D (i & D = 0), the upper D lanes of each group of 2D lanes of register i with the
/// lower D lanes of register i + D: one constant permutation and one constant blend per register (xsimd's
/// `swizzle` and `select`, so the same code compiles to AVX2, AVX-512, SSE2 and NEON; with AVX-512 the blend
/// folds into a masked permutation). N log₂N permutations in all, where moving the block through memory takes N²
/// scalar stores.
template <class P, std::size_t D = P::size / 2>
SPATIAL_INLINE void transpose_lanes(P* a) {
  if constexpr (D >= 1) {
    using T = typename P::value_type;
    using Index = xsimd::batch<std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>, typename P::arch_type>;
    constexpr auto down = xsimd::make_batch_constant<Index, LaneShiftDown<D>>();
    constexpr auto up = xsimd::make_batch_constant<Index, LaneShiftUp<D>>();
    constexpr auto upper = xsimd::make_batch_bool_constant<P, LaneUpper<D>>();
    for (std::size_t i = 0; i < P::size; ++i) {
      if ((i & D) != 0) continue;
      const P x = a[i], y = a[i + D];
      a[i] = xsimd::select(upper, xsimd::swizzle(y, down), x);
      a[i + D] = xsimd::select(upper, y, xsimd::swizzle(x, up));
    }
    transpose_lanes<P, D / 2>(a);
  }
}

/// A fixed set of worker threads that run one function on task indices 0 … T−1 (the caller runs task 0): started
/// once, woken per call, no allocation per call. After a call a worker polls the call counter kSpin times, yielding
/// its core between polls (a millisecond or so), before it sleeps on a condition variable, so that calls in quick
/// succession (a batch of 10³ states takes a few hundred microseconds) do not pay the scheduler's wake-up latency
/// each time (on 2 cores it cut 2-thread RNEA on 1024 states from 1.4× to ~2× the 1-thread throughput); the caller
/// polls likewise before it sleeps until the others are done.
class WorkerPool {
 public:
  static constexpr int kSpin = 1 << 12;

  explicit WorkerPool(int threads) {
    for (int t = 1; t < threads; ++t) workers_.emplace_back([this, t] { loop(t); });
  }
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;
  ~WorkerPool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_.store(true, std::memory_order_relaxed);
      generation_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
  }
  int size() const { return static_cast<int>(workers_.size()) + 1; }

  /// Runs f(t) for t = 0 … tasks−1 (tasks ≤ size()), t = 0 on the calling thread; returns when all are done.
  template <class F>
  void run(int tasks, F& f) {
    if (tasks <= 1 || workers_.empty()) {
      f(0);
      return;
    }
    call_ = [](void* ctx, int t) { (*static_cast<F*>(ctx))(t); };
    ctx_ = &f;
    tasks_ = tasks;
    pending_.store(static_cast<int>(workers_.size()), std::memory_order_relaxed);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      generation_.fetch_add(1, std::memory_order_release);  // publishes call_, ctx_, tasks_ and pending_
    }
    wake_.notify_all();
    f(0);
    for (int i = 0; i < kSpin; ++i)
      if (pending_.load(std::memory_order_acquire) == 0) return;
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return pending_.load(std::memory_order_acquire) == 0; });
  }

 private:
  void loop(int t) {
    unsigned long long seen = 0;
    for (;;) {
      for (int i = 0; i < kSpin && generation_.load(std::memory_order_acquire) == seen; ++i) std::this_thread::yield();
      if (generation_.load(std::memory_order_acquire) == seen) {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return generation_.load(std::memory_order_acquire) != seen; });
      }
      seen = generation_.load(std::memory_order_acquire);
      if (stop_.load(std::memory_order_relaxed)) return;
      if (t < tasks_) call_(ctx_, t);
      if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
        std::lock_guard<std::mutex> lock(mutex_);  // so that the caller cannot miss the notification
        done_.notify_one();
      }
    }
  }

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::atomic<unsigned long long> generation_{0};
  std::atomic<bool> stop_{false};
  std::atomic<int> pending_{0};
  void (*call_)(void*, int) = nullptr;
  void* ctx_ = nullptr;
  int tasks_ = 0;
};

/// The debug assertion of a batch argument's shape (as sizes.hpp's for single states: prints and aborts unless
/// SPATIAL_CHECK_SIZES is 0, which NDEBUG makes the default).
template <class X>
inline void check_batch_shape(const Eigen::MatrixBase<X>& x, long long rows, long long cols, const char* function,
                              const char* argument) {
#if SPATIAL_CHECK_SIZES
  if (static_cast<long long>(x.rows()) != rows || static_cast<long long>(x.cols()) != cols) {
    std::fprintf(stderr, "spatial: Batch::%s: argument '%s' is %lld × %lld, expected %lld × %lld\n", function,
                 argument, static_cast<long long>(x.rows()), static_cast<long long>(x.cols()), rows, cols);
    std::fflush(stderr);
    std::abort();
  }
#else
  (void)x;
  (void)rows;
  (void)cols;
  (void)function;
  (void)argument;
#endif
}
}  // namespace detail

/// The batched algorithms of one model (see the file comment): `Batch<S, Tree>` for a fixed base (`Model<S, Tree>`),
/// `FloatingBatch<S, Tree>` for a floating base (`FloatingModel<S, Tree>`: q has nq = nv + 1 rows, the free-flyer's
/// seven first, and the results are those of floating.hpp's overloads: nv rows, τ's first six the root's wrench).
/// Arguments are matrices with one column per state (nq × B for q, nv × B for the others; any Eigen dense
/// expression of scalar S, e.g. a `Map` of a row-major B × nv array transposed); outputs are written through
/// `const MatrixBase&` (Eigen's convention, so blocks and maps can be passed) and must have their size already.
/// B = the number of columns of the first argument (≥ 0).
template <class S, class TreeT, bool Floating>
class BasicBatch {
 public:
  using Scalar = S;
  using Pack = Lanes<S>;
  static constexpr bool floating = Floating;
  /// The model it is built from, and the same in lane form.
  using SourceModel = std::conditional_t<Floating, FloatingModel<S, TreeT>, Model<S, TreeT>>;
  using LaneModel = std::conditional_t<Floating, FloatingModel<Pack, TreeT>, Model<Pack, TreeT>>;
  using LaneData = typename detail::ModelTraits<LaneModel>::DataType;
  /// States per SIMD register (per call of the underlying algorithm).
  static constexpr int lanes = static_cast<int>(Pack::size);

  /// Copies the model into lane form and allocates one workspace per thread (threads ≤ 0: all hardware threads).
  explicit BasicBatch(const SourceModel& model, int threads = 1)
      : model_(model.template cast<Pack>()), nv_(Traits::nv(model_)), nq_(Traits::nq(model_)),
        cols_(static_cast<std::size_t>(nv_)) {
    if (threads <= 0) threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    work_.reserve(static_cast<std::size_t>(threads));
    for (int t = 0; t < threads; ++t) work_.emplace_back(model_, nq_, nv_);
    pool_ = std::make_unique<detail::WorkerPool>(threads);
    // The non-zero pattern of H: (i, j) with j = i or j an ancestor of i, both triangles, column by column (a
    // floating base's six rows and columns: all of them).
    const auto& tree = detail::ModelTraits<SourceModel>::tree(model);
    constexpr int off = Traits::voff;
    for (int c = 0; c < nv_; ++c)
      for (int r = 0; r < nv_; ++r) {
        bool related = r < off || c < off;
        for (int a = std::max(r, c) - off; a >= 0 && !related; a = tree.parent(a)) related = a == std::min(r, c) - off;
        if (related) {
          h_rows_.push_back(r);
          h_cols_.push_back(c);
        }
      }
  }

  int nv() const { return nv_; }
  int nq() const { return nq_; }
  int threads() const { return pool_->size(); }
  const LaneModel& lane_model() const { return model_; }

  /// τ = RNEA(q, q̇, q̈) per state.
  template <class Q, class V, class A, class Out>
  void rnea(const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a,
            const Eigen::MatrixBase<Out>& tau) {
    check("rnea", q, "q", v, "qd", a, "qdd", tau, "tau");
    three_inputs(q, v, a, tau, [this](Work& w) -> const auto& { return spatial::rnea(model_, w.data, w.q, w.v, w.a); });
  }
  /// G(q) per state.
  template <class Q, class Out>
  void gravity(const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<Out>& tau) {
    check("gravity", q, "q", tau, "tau");
    each(q.cols(), [&](Work& w, int j0, int m) {
      gather(w, j0, m, q);
      put(spatial::gravity_torques(model_, w.data, w.q).data(), nv_, 1, j0, m, staging(w), tau);
    });
  }
  /// C(q, q̇) = RNEA(q, q̇, 0) per state.
  template <class Q, class V, class Out>
  void bias(const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<Out>& tau) {
    check("bias", q, "q", v, "qd", tau, "tau");
    each(q.cols(), [&](Work& w, int j0, int m) {
      gather(w, j0, m, q, v);
      put(spatial::bias_forces(model_, w.data, w.q, w.v).data(), nv_, 1, j0, m, staging(w), tau);
    });
  }
  /// q̈ = ABA(q, q̇, τ) per state.
  template <class Q, class V, class T, class Out>
  void aba(const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<T>& tau,
           const Eigen::MatrixBase<Out>& qdd) {
    check("aba", q, "q", v, "qd", tau, "tau", qdd, "qdd");
    three_inputs(q, v, tau, qdd, [this](Work& w) -> const auto& { return spatial::aba(model_, w.data, w.q, w.v, w.a); });
  }
  /// q̈ by CRBA + the tree's LTDL factorisation (`forward_dynamics_crba`) per state.
  template <class Q, class V, class T, class Out>
  void forward_dynamics_crba(const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v,
                             const Eigen::MatrixBase<T>& tau, const Eigen::MatrixBase<Out>& qdd) {
    check("forward_dynamics_crba", q, "q", v, "qd", tau, "tau", qdd, "qdd");
    three_inputs(q, v, tau, qdd, [this](Work& w) -> const auto& {
      return spatial::forward_dynamics_crba(model_, w.data, w.q, w.v, w.a);
    });
  }
  /// H(q) per state, both triangles: `H` is nv × (nv·B), state j's matrix in columns j·nv … j·nv + nv − 1.
  template <class Q, class Out>
  void crba(const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<Out>& H) {
    detail::check_batch_shape(q, nq_, q.cols(), "crba", "q");
    detail::check_batch_shape(H, nv_, static_cast<long long>(nv_) * q.cols(), "crba", "H");
    auto& y = const_cast<Eigen::MatrixBase<Out>&>(H);
    each(q.cols(), [&](Work& w, int j0, int m) {
      gather(w, j0, m, q);
      const auto& Hl = spatial::crba(model_, w.data, w.q);
      S* const t = staging(w);
      if (put_contiguous(Hl.data(), nv_, nv_, j0, m, t, y)) return;
      // Another layout: only the entries CRBA writes (i an ancestor of j or j of i; for the 21-DoF stance model, 171
      // of 441).
      put_entries(Hl, h_rows_.size(), [this](std::size_t k) { return std::pair(h_rows_[k], h_cols_[k]); }, j0, m, t, y);
    });
  }
  /// Placement of fixed frame `frame` (`frames()[frame]`) per state: `T` is 3 × (4·B), state j's [R p] in columns
  /// 4j … 4j + 3 (R: the frame's axes, p: its origin), as `frame_pose(model, data, frame).matrix().topRows(3)` after
  /// `forward_kinematics`: in base coordinates for a fixed base, in the world for a floating base.
  template <class Q, class Out>
  void frame_placement(const Eigen::MatrixBase<Q>& q, int frame, const Eigen::MatrixBase<Out>& T) {
    const FixedFrame<Pack>& fr = frames()[static_cast<std::size_t>(frame)];
    placement("frame_placement", q, fr.body, &fr.X, T);
  }
  /// Placement of body `body` (−1: the base or root body) per state, as `frame_placement` (`body_pose` after
  /// `forward_kinematics`).
  template <class Q, class Out>
  void body_placement(const Eigen::MatrixBase<Q>& q, int body, const Eigen::MatrixBase<Out>& T) {
    placement("body_placement", q, body, nullptr, T);
  }
  /// Jacobian of fixed frame `frame` in `rf` per state (`compute_frame_jacobian`): `J` is 6 × (nv·B), state j's in
  /// columns j·nv … j·nv + nv − 1, rows linear first (the library's Jacobian convention, kinematics.hpp); on a
  /// floating base its first six columns are the free-flyer's (body-frame velocity, linear first).
  template <class Q, class Out>
  void frame_jacobian(const Eigen::MatrixBase<Q>& q, int frame, ReferenceFrame rf, const Eigen::MatrixBase<Out>& J) {
    const FixedFrame<Pack>& fr = frames()[static_cast<std::size_t>(frame)];
    jacobian("frame_jacobian", q, fr.body, fr.X, rf, J);
  }
  /// Jacobian of body `body` in `rf` per state (`compute_body_jacobian`), as `frame_jacobian`.
  template <class Q, class Out>
  void body_jacobian(const Eigen::MatrixBase<Q>& q, int body, ReferenceFrame rf, const Eigen::MatrixBase<Out>& J) {
    jacobian("body_jacobian", q, body, Transform<Pack>::Identity(), rf, J);
  }
  /// The model's fixed frames (those of its tree on a floating base), in lane form.
  const std::vector<FixedFrame<Pack>>& frames() const { return Traits::tree(model_).frames(); }

 private:
  using Traits = detail::ModelTraits<LaneModel>;
  static constexpr int kNV = Traits::NV;
  static constexpr int kNQ = kNV == Eigen::Dynamic ? Eigen::Dynamic : kNV + Traits::qoff - Traits::voff;
  using VectorL = Eigen::Matrix<Pack, kNV, 1>;
  using VectorQ = Eigen::Matrix<Pack, kNQ, 1>;
  /// Values of S in one register's alignment: `staging` skips up to this many of w.tmp to align it.
  static constexpr std::size_t kStageSlack = Pack::arch_type::alignment() / sizeof(S);
  using JacobianL = Eigen::Matrix<Pack, 6, kNV>;
  struct Work {
    LaneData data;
    VectorQ q;
    VectorL v, a;
    JacobianL J;
    std::vector<S> tmp;  ///< lane-major staging of the inputs (gather) and of a result (put)
    Work(const LaneModel& m, int nq, int n)
        : data(m), q(nq), v(n), a(n), J(6, n),
          tmp(static_cast<std::size_t>(std::max(n * n, 6 * n) + 12) * lanes + kStageSlack) {}
  };

  /// [R p] of body `body` (−1: base or root), or of the fixed frame `*X` on it, per state (frame_placement): the
  /// joint transforms of the body's chain only, composed from the root (`detail::chain_placement`); a chain deeper
  /// than kMaxWalkDepth (run-time trees) takes forward kinematics.
  template <class Q, class Out>
  void placement(const char* function, const Eigen::MatrixBase<Q>& q, int body, const Transform<Pack>* X,
                 const Eigen::MatrixBase<Out>& T) {
    detail::check_batch_shape(q, nq_, q.cols(), function, "q");
    detail::check_batch_shape(T, 3, 4 * q.cols(), function, "T");
    const bool chain = detail::walk_fits(Traits::tree(model_), body);
    each(q.cols(), [&](Work& w, int j0, int m) {
      gather(w, j0, m, q);
      Transform<Pack> Xb;
      if (chain) {
        Xb = detail::chain_placement(detail::kin(model_, w.data), w.q, body);  // the body's chain only
      } else {
        spatial::forward_kinematics(model_, w.data, w.q);
        if constexpr (Floating)
          Xb = world_transform(w.data, body);
        else
          Xb = body >= 0 ? w.data.X_base[static_cast<std::size_t>(body)] : Transform<Pack>::Identity();
      }
      if (X) Xb = *X * Xb;
      Eigen::Matrix<Pack, 3, 4> P;
      P.template leftCols<3>() = Xb.E.transpose();
      P.col(3) = Xb.r;
      put(P.data(), 3, 4, j0, m, staging(w), T);
    });
  }
  /// The 6 × nv Jacobian of the frame ᶠX_body = X on `body` (identity: the body's own) in rf, per state
  /// (frame_jacobian, body_jacobian), by the root-first walk of the body's chain (`detail::jacobian_walk_down`): only
  /// the columns that move the body (the free-flyer's and its ancestors' joints, `cols_`) are computed and leave the
  /// lanes, the rest of each state's block is zeroed (on stance21's left sole, 6 of 21 columns). With more lanes
  /// than a column has rows (8 floats with AVX2, 8 doubles with AVX-512), the whole block leaves the lanes by
  /// `put`'s transpositions instead (scripts/ab.sh against cf68d17, float on AVX2: 0.84 of the old time under g++
  /// and clang, where copying the chain's columns entry by entry gave 0.93 and 1.05); so does a chain deeper than the
  /// walk's arrays (run-time trees only), by `jacobian_walk`.
  template <class Q, class Out>
  void jacobian(const char* function, const Eigen::MatrixBase<Q>& q, int body, const Transform<Pack>& X,
                ReferenceFrame rf, const Eigen::MatrixBase<Out>& J) {
    detail::check_batch_shape(q, nq_, q.cols(), function, "q");
    detail::check_batch_shape(J, 6, static_cast<long long>(nv_) * q.cols(), function, "J");
    const auto& tree = Traits::tree(model_);
    if (lanes > 6 || !detail::walk_fits(tree, body)) {
      each(q.cols(), [&](Work& w, int j0, int m) {
        gather(w, j0, m, q);
        detail::jacobian_walk(detail::kin(model_, w.data), w.q, body, X, rf, w.J);
        put(w.J.data(), 6, nv_, j0, m, staging(w), J);
      });
      return;
    }
    int nc = 0;
    detail::for_each_ancestor_column(detail::kin(model_, work_.front().data), body,
                                     [&](int c) { cols_[static_cast<std::size_t>(nc++)] = c; });
    auto& y = const_cast<Eigen::MatrixBase<Out>&>(J);
    each(q.cols(), [&](Work& w, int j0, int m) {
      gather(w, j0, m, q);
      detail::jacobian_walk_down(detail::kin(model_, w.data), w.q, body, X, rf, w.J);
      if (put_columns_contiguous(w.J, nc, j0, m, y)) return;
      put_entries(w.J, 6 * static_cast<std::size_t>(nc),
                  [this](std::size_t k) { return std::pair(static_cast<int>(k % 6), cols_[k / 6]); }, j0, m,
                  staging(w), y);
    });
  }

  /// `jacobian`'s output when J is a plain 6-row column-major matrix (or a map or block of whole columns of one) and
  /// a column holds at least `lanes` entries: each state's block zeroed, then each of the chain's columns (`cols_`,
  /// nc of them) leaves the lanes `lanes` rows at a time, transposed in registers as in `put_contiguous` (the last
  /// group of rows overlapping the one before). Returns false, writing nothing, otherwise.
  template <class Y>
  bool put_columns_contiguous(const JacobianL& Jl, int nc, int j0, int m, Eigen::MatrixBase<Y>& y) const {
    if constexpr ((int(Y::Flags) & Eigen::DirectAccessBit) != 0 && lanes <= 6) {
      if (y.rowStride() != 1 || y.colStride() != 6) return false;
      S* p[lanes];
      for (int l = 0; l < m; ++l) {
        p[l] = &y.coeffRef(0, static_cast<Eigen::Index>(j0 + l) * nv_);
        std::fill_n(p[l], 6 * static_cast<std::size_t>(nv_), S(0));
      }
      Pack a[lanes];
      for (int k = 0; k < nc; ++k) {
        const int c = cols_[static_cast<std::size_t>(k)];
        for (int f = 0; f < 6; f += lanes) {
          const int g = std::min(f, 6 - lanes);
          for (int i = 0; i < lanes; ++i) a[i] = Jl(g + i, c);
          detail::transpose_lanes(a);
          for (int l = 0; l < m; ++l) a[l].store_unaligned(p[l] + 6 * c + g);
        }
      }
      return true;
    } else {
      (void)Jl, (void)nc, (void)j0, (void)m, (void)y;
      return false;
    }
  }

  /// The outputs of `crba` and `jacobian` in a layout `put_contiguous` / `put_columns_contiguous` do not take: only
  /// the n entries (row, column) = entry(k) of the lane matrix Ml leave the lanes, one by one, through the staging
  /// area t; the rest of each state's block (nv columns of y from column (j0 + l)·nv) is zeroed.
  template <class M, class Entry, class Y>
  void put_entries(const M& Ml, std::size_t n, Entry entry, int j0, int m, S* t, Eigen::MatrixBase<Y>& y) const {
    for (std::size_t k = 0; k < n; ++k) {
      const auto [r, c] = entry(k);
      Ml(r, c).store_aligned(t + k * lanes);
    }
    for (int l = 0; l < m; ++l) {
      auto block = y.middleCols(static_cast<Eigen::Index>(j0 + l) * nv_, nv_);
      block.setZero();
      for (std::size_t k = 0; k < n; ++k) {
        const auto [r, c] = entry(k);
        block(r, c) = t[k * lanes + static_cast<std::size_t>(l)];
      }
    }
  }

  /// The shapes of q (nq × B) and of the other arguments (nv × B).
  template <class X, class... Rest>
  void check(const char* function, const Eigen::MatrixBase<X>& q, const char* name, const Rest&... rest) const {
    detail::check_batch_shape(q, nq_, q.cols(), function, name);
    check_each(function, q.cols(), rest...);
  }
  void check_each(const char*, Eigen::Index) const {}
  template <class X, class... Rest>
  void check_each(const char* function, Eigen::Index cols, const Eigen::MatrixBase<X>& x, const char* name,
                  const Rest&... rest) const {
    detail::check_batch_shape(x, nv_, cols, function, name);
    check_each(function, cols, rest...);
  }

  /// out = alg(work) per group of states, after gathering x, y, z into work.q, work.v, work.a (RNEA, ABA, CRBA
  /// forward dynamics: the three state-sized inputs and one state-sized result).
  template <class X, class Y, class Z, class Out, class Alg>
  void three_inputs(const Eigen::MatrixBase<X>& x, const Eigen::MatrixBase<Y>& y, const Eigen::MatrixBase<Z>& z,
                    const Eigen::MatrixBase<Out>& out, Alg&& alg) {
    each(x.cols(), [&](Work& w, int j0, int m) {
      gather(w, j0, m, x, y, z);
      put(alg(w).data(), nv_, 1, j0, m, staging(w), out);
    });
  }

  /// f(work, first state, count) for each group of `lanes` states, the groups split over the threads in contiguous
  /// runs (thread t: groups ⌊G t / T⌋ … ⌊G (t+1) / T⌋ − 1).
  template <class F>
  void each(Eigen::Index states, F&& f) {
    const int B = static_cast<int>(states);
    const int groups = (B + lanes - 1) / lanes;
    const int tasks = std::min(threads(), groups);
    auto task = [&](int t) {
      Work& w = work_[static_cast<std::size_t>(t)];
      const int g0 = static_cast<int>(static_cast<long long>(groups) * t / tasks);
      const int g1 = static_cast<int>(static_cast<long long>(groups) * (t + 1) / tasks);
      for (int g = g0; g < g1; ++g) {
        const int j0 = g * lanes;
        f(w, j0, std::min(lanes, B - j0));
      }
    };
    if (tasks > 0) pool_->run(tasks, task);
  }

  /// Lane-major copy of states j0 … j0 + m − 1 of x: t[i·lanes + l] = x(i, j0 + min(l, m − 1)) for every row i
  /// (the last state repeated into the unused lanes), read state by state (one contiguous column of a column-major
  /// x at a time).
  template <class X>
  static void stage(const Eigen::MatrixBase<X>& x, int j0, int m, S* t) {
    const Eigen::Index rows = x.rows();
    for (int l = 0; l < lanes; ++l) {
      const Eigen::Index j = j0 + std::min(l, m - 1);
      for (Eigen::Index i = 0; i < rows; ++i) t[i * lanes + l] = x(i, j);
    }
  }
  /// out[i] = the register of row i of a `stage`d copy.
  template <class V>
  static void load(const S* t, V& out) {
    for (Eigen::Index i = 0; i < out.size(); ++i) out[i] = Pack::load_aligned(t + i * lanes);
  }
  /// The start of w.tmp rounded up to the register alignment (tmp holds `kStageSlack` extra values for that).
  static S* staging(Work& w) {
    constexpr auto align = static_cast<std::uintptr_t>(Pack::arch_type::alignment());
    const auto p = reinterpret_cast<std::uintptr_t>(w.tmp.data());
    return w.tmp.data() + ((align - p % align) % align) / sizeof(S);
  }
  /// w.q, w.v, w.a = states j0 … j0 + m − 1 of x, y, z (one to three inputs). An input whose columns are
  /// contiguous in memory (`take_contiguous`) is read `lanes` rows of `lanes` states at a time and transposed in
  /// registers; the others are staged first and loaded after: filling a register's lanes with scalar stores and
  /// loading it right away stalls every row (the load overlaps stores still in flight, so the processor cannot
  /// forward them and waits for them to reach the cache); staged first, the stores of a row have long left by the
  /// time it is loaded (perf put those stalls at about a sixth of a batched RNEA's samples on stance21 with AVX-512).
  template <class... X>
  void gather(Work& w, int j0, int m, const X&... x) {
    static_assert(sizeof...(X) >= 1 && sizeof...(X) <= 3, "gather: one to three inputs");
    S* const t = staging(w);
    const std::size_t block = static_cast<std::size_t>(nv_) * lanes;
    bool staged[3] = {false, false, false};
    if constexpr (std::is_same_v<VectorQ, VectorL>) {  // fixed base: q has nv rows like the others
      VectorL* const outs[3] = {&w.q, &w.v, &w.a};
      const auto take = [&](const auto& xk, std::size_t k) {
        staged[k] = !take_contiguous(xk, j0, m, *outs[k]);
        if (staged[k]) stage(xk, j0, m, t + block * k);
      };
      std::size_t k = 0;
      (take(x, k++), ...);
      for (std::size_t r = 0; r < sizeof...(X); ++r)
        if (staged[r]) load(t + block * r, *outs[r]);
    } else {  // floating base: q's nq rows staged first, then nv rows per further input
      const std::size_t qblock = static_cast<std::size_t>(nq_) * lanes;
      const auto take = [&](const auto& xk, std::size_t k, auto& out) {
        staged[k] = !take_contiguous(xk, j0, m, out);
        if (staged[k]) stage(xk, j0, m, t + (k == 0 ? 0 : qblock + block * (k - 1)));
      };
      const auto take_all = [&](const auto& x0, const auto&... rest) {
        take(x0, 0, w.q);
        [[maybe_unused]] VectorL* const outs[2] = {&w.v, &w.a};  // (unused with q alone)
        [[maybe_unused]] std::size_t k = 1;
        ((take(rest, k, *outs[k - 1]), ++k), ...);
      };
      take_all(x...);
      if (staged[0]) load(t, w.q);
      for (std::size_t r = 1; r < sizeof...(X); ++r)
        if (staged[r]) load(t + qblock + block * (r - 1), r == 1 ? w.v : w.a);
    }
  }
  /// out = states j0 … j0 + m − 1 of x (the last repeated into the unused lanes) when x gives direct access to
  /// memory with contiguous columns (a plain matrix, a map, a block of rows of either) at least `lanes` rows long:
  /// `lanes` rows of every lane's state loaded at once and transposed in registers (`detail::transpose_lanes`); the
  /// last group of rows starts at rows − lanes (overlapping the one before, which it rewrites with the same values)
  /// so that nothing past a column is read. Returns false, reading nothing, for other inputs.
  template <class X, class V>
  static bool take_contiguous(const Eigen::MatrixBase<X>& x, int j0, int m, V& out) {
    if constexpr ((int(X::Flags) & Eigen::DirectAccessBit) != 0) {
      const Eigen::Index n = x.rows();
      if (x.rowStride() != 1 || n < lanes) return false;
      const S* p[lanes];
      for (int l = 0; l < lanes; ++l) p[l] = x.derived().data() + (j0 + std::min(l, m - 1)) * x.colStride();
      Pack a[lanes];
      for (Eigen::Index f = 0; f < n; f += lanes) {
        const Eigen::Index g = std::min(f, n - lanes);
        for (int l = 0; l < lanes; ++l) a[l] = Pack::load_unaligned(p[l] + g);
        detail::transpose_lanes(a);
        for (int i = 0; i < lanes; ++i) out[g + i] = a[i];
      }
      return true;
    } else {
      (void)x, (void)j0, (void)m, (void)out;
      return false;
    }
  }
  /// Writes a result of rows × cols registers (column-major at `src`) out of the lanes: lane l is state j0 + l, whose
  /// block is columns (j0 + l)·cols … (j0 + l + 1)·cols − 1 of y, for l < m. `tmp` holds rows·cols·lanes values.
  template <class Y>
  static void put(const Pack* src, Eigen::Index rows, Eigen::Index cols, int j0, int m, S* tmp,
                  const Eigen::MatrixBase<Y>& y_) {
    if (put_contiguous(src, rows, cols, j0, m, tmp, y_)) return;
    auto& y = const_cast<Eigen::MatrixBase<Y>&>(y_);
    const Eigen::Index n = rows * cols;
    for (Eigen::Index k = 0; k < n; ++k) src[k].store_unaligned(tmp + k * lanes);
    for (int l = 0; l < m; ++l) {
      const Eigen::Index c0 = static_cast<Eigen::Index>(j0 + l) * cols;
      for (Eigen::Index c = 0; c < cols; ++c)
        for (Eigen::Index r = 0; r < rows; ++r) y(r, c0 + c) = tmp[(c * rows + r) * lanes + l];
    }
  }
  /// `put` when y gives direct access to memory in which each state's block is contiguous and column-major (a
  /// plain matrix, a map, a block of whole columns of either; for a single column, any column stride): `lanes`
  /// entries of the block at a time, the `lanes` registers transposed in registers (`detail::transpose_lanes`),
  /// after which register l holds `lanes` consecutive entries of state l's block, stored at once. Every entry is
  /// written (structural zeros included). Returns false, writing nothing, for other layouts.
  template <class Y>
  static bool put_contiguous(const Pack* src, Eigen::Index rows, Eigen::Index cols, int j0, int m, S* tmp,
                             const Eigen::MatrixBase<Y>& y_) {
    if constexpr ((int(Y::Flags) & Eigen::DirectAccessBit) != 0) {
      auto& y = const_cast<Eigen::MatrixBase<Y>&>(y_);
      if (y.rowStride() != 1 || (cols > 1 && y.colStride() != rows)) return false;
      S* p[lanes];
      for (int l = 0; l < m; ++l) p[l] = &y.coeffRef(0, static_cast<Eigen::Index>(j0 + l) * cols);
      const Eigen::Index n = rows * cols;
      Pack a[lanes];
      if (n >= lanes) {
        // The last group starts at n − lanes, overlapping the one before (rewritten with the same values).
        for (Eigen::Index f = 0; f < n; f += lanes) {
          const Eigen::Index g = std::min(f, n - lanes);
          for (int i = 0; i < lanes; ++i) a[i] = src[g + i];
          detail::transpose_lanes(a);
          for (int l = 0; l < m; ++l) a[l].store_unaligned(p[l] + g);
        }
      } else {
        // Fewer entries than lanes: each state's through tmp.
        for (int i = 0; i < lanes; ++i) a[i] = i < n ? src[i] : Pack(S(0));
        detail::transpose_lanes(a);
        for (int l = 0; l < m; ++l) {
          a[l].store_unaligned(tmp);
          std::copy_n(tmp, n, p[l]);
        }
      }
      return true;
    } else {
      (void)src, (void)rows, (void)cols, (void)j0, (void)m, (void)tmp, (void)y_;
      return false;
    }
  }

  LaneModel model_;
  int nv_, nq_;
  std::vector<int> h_rows_, h_cols_;  ///< the entries of H that CRBA writes (see `crba`)
  std::vector<int> cols_;             ///< nv entries: the columns of the last `jacobian` call's chain
  std::vector<Work> work_;
  std::unique_ptr<detail::WorkerPool> pool_;
};

/// The batched algorithms of a fixed-base model (`Model<S, TreeT>`).
template <class S, class TreeT = DynamicTree>
using Batch = BasicBatch<S, TreeT, false>;
/// The batched algorithms of a floating-base model (`FloatingModel<S, TreeT>`).
template <class S, class TreeT = DynamicTree>
using FloatingBatch = BasicBatch<S, TreeT, true>;

}  // namespace spatial
