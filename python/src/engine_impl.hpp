#pragma once
/// \file engine_impl.hpp
/// `Engine<M>`: the operations of engine.hpp for one model type M (`Model<double, T>` or `FloatingModel<double, T>`,
/// T a compile-time tree or `DynamicTree`). Included by one source file per model kind, so that the kinds compile in
/// parallel.

#include "engine.hpp"
#include "contacts_impl.hpp"

#include <spatial/batch.hpp>

#include <algorithm>
#include <thread>
#include <type_traits>

namespace spatial::python {

/// f(std::integral_constant<Dyn, O>) for the flag set O = `dyn` restricted to `Mask` (one instantiation of f per
/// set: the algorithms of options.hpp take the set at compile time, so that what a scene leaves out generates no
/// code). `Floating`: only Full (the options are fixed-base only; the bindings refuse the others).
template <unsigned Mask, bool Floating, class F>
void with_dyn(unsigned dyn, F&& f) {
  const unsigned d = dyn & Mask;
  if constexpr (!Floating) {
    if (d != (unsigned(Dyn::Full) & Mask)) {
      switch (d) {
        case 0u: return f(std::integral_constant<Dyn, Dyn::None>{});
        case 1u: return f(std::integral_constant<Dyn, Dyn::Gravity>{});
        case 2u: return f(std::integral_constant<Dyn, Dyn::Velocity>{});
        default: break;
      }
      if constexpr ((Mask & 4u) != 0u) {
        switch (d) {
          case 3u: return f(std::integral_constant<Dyn, Dyn::Gravity | Dyn::Velocity>{});
          case 4u: return f(std::integral_constant<Dyn, Dyn::Acceleration>{});
          case 5u: return f(std::integral_constant<Dyn, Dyn::QuasiStatic>{});
          case 6u: return f(std::integral_constant<Dyn, Dyn::NoGravity>{});
          default: break;
        }
      }
    }
  }
  (void)d;
  f(std::integral_constant<Dyn, Dyn::Full>{});
}

template <class M>
struct IsFloating : std::false_type {};
template <class S, class T>
struct IsFloating<FloatingModel<S, T>> : std::true_type {};

/// ik.hpp's IkSolver for a model of type M; the model is the engine's (it outlives the solver: Python's IkSolver
/// holds the model).
template <class M>
class IkEngine final : public IkBase {
 public:
  IkEngine(const M& model, const std::vector<IkTaskSpec>& tasks, const IkOptionsSpec& o)
      : solver_(model, convert(tasks), options(o)), nq_(detail::ModelTraits<M>::nq(model)) {}

  int rows() const override { return solver_.rows(); }
  int tasks() const override { return solver_.tasks(); }
  void solve(const double* q0, std::ptrdiff_t q0_stride, double* q, IkResult* status, std::ptrdiff_t count,
             int threads) override {
    const std::ptrdiff_t t = threads_for(count, threads, kMinIkStartsPerThread);
    if (t == 1) return range(solver_, q0, q0_stride, q, status, 0, count);
    std::vector<std::thread> pool;
    const std::ptrdiff_t chunk = count / t, extra = count % t;
    std::ptrdiff_t begin = chunk + (extra > 0 ? 1 : 0);
    for (std::ptrdiff_t k = 1; k < t; ++k) {
      const std::ptrdiff_t end = begin + chunk + (k < extra ? 1 : 0);
      pool.emplace_back([=] {
        IkSolver<M> own = solver_;
        range(own, q0, q0_stride, q, status, begin, end);
      });
      begin = end;
    }
    range(solver_, q0, q0_stride, q, status, 0, chunk + (extra > 0 ? 1 : 0));
    for (auto& th : pool) th.join();
  }
  void set_task(int i, const IkTaskSpec& t) override {
    const IkTask<double> k = convert(t);
    solver_.set_target(i, k.position, k.rotation);
    solver_.set_weight(i, k.weight);
    solver_.set_axes(i, k.axes);
  }
  double residual(const double* q, double* r) override {
    const double res = solver_.residual(Eigen::Map<const Eigen::VectorXd>(q, nq_));
    Eigen::Map<Eigen::VectorXd>(r, solver_.rows()) = solver_.residual_vector();
    return res;
  }

 private:
  /// Not inlined, for the same reason as Engine::range: one copy of the per-start code for every thread.
  __attribute__((noinline)) void range(IkSolver<M>& s, const double* q0, std::ptrdiff_t q0_stride, double* q,
                                       IkResult* status, std::ptrdiff_t begin, std::ptrdiff_t end) const {
    for (std::ptrdiff_t b = begin; b < end; ++b) {
      Eigen::Map<Eigen::VectorXd> qb(q + b * nq_, nq_);
      qb = Eigen::Map<const Eigen::VectorXd>(q0 + b * q0_stride, nq_);
      const IkStatus<double> st = s.solve(qb);
      status[b] = {st.converged, st.reason, st.iterations, st.accepted, st.residual, st.damping};
    }
  }
  static IkTask<double> convert(const IkTaskSpec& t) {
    IkTask<double> k;
    k.kind = t.kind;
    k.frame = t.frame;
    k.position = Eigen::Vector3d(t.position[0], t.position[1], t.position[2]);
    k.rotation = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(t.rotation);
    k.weight = t.weight;
    k.axes = Eigen::Map<const Vector6<double>>(t.axes);
    return k;
  }
  static std::vector<IkTask<double>> convert(const std::vector<IkTaskSpec>& tasks) {
    std::vector<IkTask<double>> out;
    for (const auto& t : tasks) out.push_back(convert(t));
    return out;
  }
  static IkOptions<double> options(const IkOptionsSpec& o) {
    IkOptions<double> opt;
    opt.max_iterations = o.max_iterations;
    opt.tolerance = o.tolerance;
    opt.step_tolerance = o.step_tolerance;
    opt.damping = o.damping;
    opt.adaptive = o.adaptive;
    opt.lower = Eigen::Map<const Eigen::VectorXd>(o.lower.data(), Eigen::Index(o.lower.size()));
    opt.upper = Eigen::Map<const Eigen::VectorXd>(o.upper.data(), Eigen::Index(o.upper.size()));
    opt.active = o.active;
    return opt;
  }
  IkSolver<M> solver_;
  int nq_;
};

/// batch.hpp's `Batch<double, Tree>` or `FloatingBatch<double, Tree>` behind BatchBase (engine.hpp): NumPy's
/// row-major (count, nq) and (count, nv) arrays are the column-major nq × count and nv × count matrices the batch
/// takes, one column per state, so they are passed as maps, without a copy.
template <class Tree, bool Floating>
class BatchEngine final : public BatchBase {
 public:
  using BatchT = spatial::BasicBatch<double, Tree, Floating>;
  BatchEngine(const typename BatchT::SourceModel& model, int threads) : batch_(model, threads) {}
  int lanes() const override { return BatchT::lanes; }
  int threads() const override { return batch_.threads(); }
  void run(Op op, std::ptrdiff_t count, const double* const* in, double* out) override {
    using Cols = Eigen::Map<const Eigen::MatrixXd>;
    const auto n = static_cast<Eigen::Index>(count);
    const Eigen::Index nv = batch_.nv();
    const auto arg = [&](int k) { return Cols(in[k], k == 0 ? batch_.nq() : nv, n); };
    Eigen::Map<Eigen::MatrixXd> y(out, nv, op == Op::Crba ? nv * n : n);
    switch (op) {
      case Op::Rnea: return batch_.rnea(arg(0), arg(1), arg(2), y);
      case Op::Gravity: return batch_.gravity(arg(0), y);
      case Op::Bias: return batch_.bias(arg(0), arg(1), y);
      case Op::Aba: return batch_.aba(arg(0), arg(1), arg(2), y);
      case Op::ForwardDynamics: return batch_.forward_dynamics_crba(arg(0), arg(1), arg(2), y);
      case Op::Crba: return batch_.crba(arg(0), y);  // H symmetric: its row-major blocks are its column-major ones
      default: break;
    }
    throw std::invalid_argument("Batch: rnea, gravity, bias, aba, forward_dynamics and crba only");
  }
  void frame(Op op, std::ptrdiff_t count, const double* q, int target, bool body, spatial::ReferenceFrame reference,
             double* out) override {
    const auto n = static_cast<Eigen::Index>(count);
    const Eigen::Index nv = batch_.nv();
    const Eigen::Map<const Eigen::MatrixXd> Q(q, batch_.nq(), n);
    // The batch writes column-major blocks per state; NumPy's are row-major: through a buffer, then transposed.
    if (op == Op::FramePlacement) {
      buffer_.resize(3, 4 * n);
      if (body) batch_.body_placement(Q, target, buffer_);
      else batch_.frame_placement(Q, target, buffer_);
      for (Eigen::Index j = 0; j < n; ++j) {
        Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> P(out + 16 * j);
        P.topRows<3>() = buffer_.middleCols<4>(4 * j);
        P.row(3) << 0, 0, 0, 1;
      }
      return;
    }
    if (op == Op::FrameJacobian) {
      buffer_.resize(6, nv * n);
      if (body) batch_.body_jacobian(Q, target, reference, buffer_);
      else batch_.frame_jacobian(Q, target, reference, buffer_);
      for (Eigen::Index j = 0; j < n; ++j)
        Eigen::Map<Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor>>(out + 6 * nv * j, 6, nv) =
            buffer_.middleCols(nv * j, nv);
      return;
    }
    throw std::invalid_argument("Batch: frame_placement and frame_jacobian only");
  }

 private:
  BatchT batch_;
  Eigen::MatrixXd buffer_;  ///< the frame methods' column-major results (grown when a call needs more)
};

template <class M>
struct TreeOf;
template <class S, class T>
struct TreeOf<Model<S, T>> {
  using type = T;
};
template <class S, class T>
struct TreeOf<FloatingModel<S, T>> {
  using type = T;
};

template <class M>
class Engine final : public ModelBase {
 public:
  static constexpr bool kFloating = IsFloating<M>::value;
  using Traits = spatial::detail::ModelTraits<M>;
  using DataT = typename Traits::DataType;
  using Tree = typename TreeOf<M>::type;
  using TreeT = Model<double, Tree>;
  static constexpr int NV = Traits::NV;
  static constexpr int NQ = NV == Eigen::Dynamic ? Eigen::Dynamic : NV + (kFloating ? 1 : 0);
  using DerivT = std::conditional_t<kFloating, FloatingDerivativeData<double, Tree>, DerivativeData<double, Tree>>;
  using MinvT = std::conditional_t<kFloating, FloatingMinvData<double, Tree>, MinvData<double, Tree>>;
  using VecQ = Eigen::Matrix<double, NQ, 1>;
  using VecV = Eigen::Matrix<double, NV, 1>;
  using MapQ = Eigen::Map<const VecQ>;
  using MapV = Eigen::Map<const VecV>;
  using Mat6 = Eigen::Matrix<double, 6, NV>;
  using Mat3 = Eigen::Matrix<double, 3, NV>;
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  struct Ws final : Workspace {
    explicit Ws(const M& m)
        : data(m), J(Mat6::Zero(6, m.nv())), Jc(Mat3::Zero(3, m.nv())), zero(VecV::Zero(m.nv())),
          fext(static_cast<std::size_t>(Traits::tree(m).size() + (kFloating ? 1 : 0)), Force<double>::Zero()),
          qtmp(VecQ::Zero(Traits::nq(m))), vtmp(VecV::Zero(m.nv())) {}
    DataT data;
    Mat6 J;
    Mat3 Jc;
    VecV zero;
    std::vector<Force<double>> fext;
    VecQ qtmp;
    VecV vtmp;
    std::unique_ptr<DerivT> deriv;  // built on first use
    std::unique_ptr<MinvT> minv;
  };

  explicit Engine(M model) : model_(std::move(model)) {
    const auto& tree = Traits::tree(model_);
    floating = kFloating;
    compile_time = TreeT::is_static;
    nq = Traits::nq(model_);
    nv = Traits::nv(model_);
    njoints = tree.size();
    for (int i = 0; i < njoints; ++i) {
      joint_names.push_back(tree.joint_name(i));
      body_names.push_back(tree.body_name(i));
    }
    for (const auto& f : tree.frames()) frame_names.push_back(f.name);
    gravity = tree.gravity();
    default_ws = workspace();
  }

  std::unique_ptr<Workspace> workspace() const override { return std::make_unique<Ws>(model_); }

  void neutral(double* q) const override {
    Eigen::Map<Eigen::VectorXd> out(q, nq);
    out.setZero();
    if constexpr (kFloating) out[6] = 1.0;
  }

  std::unique_ptr<IkBase> make_ik(const std::vector<IkTaskSpec>& tasks, const IkOptionsSpec& opt) const override {
    return std::make_unique<IkEngine<M>>(model_, tasks, opt);
  }
  std::shared_ptr<ModelBase> reduce(int kind, const std::vector<std::string>& names,
                                    const std::vector<double>& positions, const double* q) const override {
    if constexpr (kFloating) {
      (void)kind, (void)names, (void)positions, (void)q;
      throw ModelError(name + ": model reduction (lock_joints, keep_joints, keep_branches) works on fixed-base "
                       "models; load the URDF with lock= instead");
    } else {
      const Model<double> rt = model_.to_runtime();
      const Eigen::Map<const Eigen::VectorXd> qm(q ? q : positions.data(), q ? nq : 0);
      std::vector<JointRef> refs(names.begin(), names.end());
      if (kind == 0) {
        std::vector<JointLock> locks;
        for (std::size_t k = 0; k < names.size(); ++k) locks.push_back({JointRef(names[k]), positions[k]});
        return make_reduced_model(*this, lock_joints(rt, locks));
      }
      if (kind == 1) return make_reduced_model(*this, keep_joints(rt, refs, qm));
      return make_reduced_model(*this, keep_branches(rt, refs, qm));
    }
  }
  std::unique_ptr<ContactsBase> make_contacts(const std::vector<ContactSpec>& specs, double damping) const override {
    return make_contacts_for<M>(model_, specs, damping);
  }
  std::unique_ptr<BatchBase> make_batch(int threads) const override {
    return std::make_unique<BatchEngine<Tree, kFloating>>(model_, threads);
  }

  void run(const Call& c, Workspace& ws, int threads) const override {
    switch (c.op) {
#define SPATIAL_PY_OP(name) \
  case Op::name: return split<Op::name>(c, static_cast<Ws&>(ws), threads);
      SPATIAL_PY_OP(Rnea)
      SPATIAL_PY_OP(Gravity)
      SPATIAL_PY_OP(Bias)
      SPATIAL_PY_OP(Crba)
      SPATIAL_PY_OP(Aba)
      SPATIAL_PY_OP(ForwardDynamics)
      SPATIAL_PY_OP(KineticEnergy)
      SPATIAL_PY_OP(PotentialEnergy)
      SPATIAL_PY_OP(FramePlacement)
      SPATIAL_PY_OP(FrameJacobian)
      SPATIAL_PY_OP(FrameVelocity)
      SPATIAL_PY_OP(FrameAcceleration)
      SPATIAL_PY_OP(FrameClassicalAcceleration)
      SPATIAL_PY_OP(FrameJacobianTimeVariation)
      SPATIAL_PY_OP(CenterOfMass)
      SPATIAL_PY_OP(ComJacobian)
      SPATIAL_PY_OP(CentroidalMatrix)
      SPATIAL_PY_OP(CentroidalMomentum)
      SPATIAL_PY_OP(CentroidalMomentumRate)
      SPATIAL_PY_OP(Integrate)
      SPATIAL_PY_OP(Difference)
      SPATIAL_PY_OP(Normalize)
      SPATIAL_PY_OP(RneaDerivatives)
      SPATIAL_PY_OP(AbaDerivatives)
      SPATIAL_PY_OP(InverseInertia)
      SPATIAL_PY_OP(MultibodyZmp)
#undef SPATIAL_PY_OP
    }
  }

 private:
  M model_;

  /// Not inlined: one compiled copy of the per-state code serves every thread and the single-threaded path, so that
  /// a state's result does not depend on how the batch was split (copies inlined at different call sites may be
  /// contracted into FMAs differently under -march=native: 1-ulp differences in center_of_mass were measured).
  template <Op O>
  __attribute__((noinline)) void range(const Call& c, Ws& ws, std::ptrdiff_t begin, std::ptrdiff_t end) const {
    for (std::ptrdiff_t b = begin; b < end; ++b) one<O>(c, ws, b);
  }

  /// Contiguous chunks, one per thread; the first on the calling thread with its workspace.
  template <Op O>
  void split(const Call& c, Ws& ws, int threads) const {
    const std::ptrdiff_t n = c.count;
    const std::ptrdiff_t t = threads_for(n, threads, kMinStatesPerThread);
    if (t == 1) return range<O>(c, ws, 0, n);
    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(t - 1));
    const std::ptrdiff_t chunk = n / t, extra = n % t;
    std::ptrdiff_t begin = chunk + (extra > 0 ? 1 : 0);  // the calling thread's share: [0, begin)
    for (std::ptrdiff_t k = 1; k < t; ++k) {
      const std::ptrdiff_t end = begin + chunk + (k < extra ? 1 : 0);
      pool.emplace_back([this, &c, begin, end] {
        Ws own(model_);
        range<O>(c, own, begin, end);
      });
      begin = end;
    }
    range<O>(c, ws, 0, chunk + (extra > 0 ? 1 : 0));
    for (auto& th : pool) th.join();
  }

  MapQ q_at(const In& in, std::ptrdiff_t b) const { return MapQ(in.at(b), nq); }
  MapV v_at(const In& in, std::ptrdiff_t b) const { return MapV(in.at(b), nv); }
  /// An element loop rather than an Eigen assignment: GCC 12 warns (-Warray-bounds, falsely) about the masked
  /// AVX-512 loads Eigen uses to copy a 3- or 6-vector into a dynamic-size map under -march=native.
  template <class Vec>
  static void put_vector(const Out& o, std::ptrdiff_t b, const Vec& x) {
    double* p = o.at(b);
    for (Eigen::Index k = 0; k < x.size(); ++k) p[k] = x[k];
  }
  template <class Mat>
  static void put_matrix(const Out& o, std::ptrdiff_t b, const Mat& x) {
    Eigen::Map<RowMajor>(o.at(b), x.rows(), x.cols()) = x;
  }
  /// A Motion as 6 numbers, linear first.
  static void put_motion(const Out& o, std::ptrdiff_t b, const Motion<double>& m) {
    double* p = o.at(b);
    for (int k = 0; k < 3; ++k) p[k] = m.v[k], p[3 + k] = m.w[k];
  }
  /// External forces of state b: rows [fx fy fz nx ny nz] (linear first), in body coordinates.
  void load_fext(const In& in, std::ptrdiff_t b, Ws& ws) const {
    const double* p = in.at(b);
    for (std::size_t k = 0; k < ws.fext.size(); ++k, p += 6)
      ws.fext[k] = Force<double>(Vector3<double>(p[3], p[4], p[5]), Vector3<double>(p[0], p[1], p[2]));
  }
  DerivT& deriv(Ws& ws) const {
    if (!ws.deriv) ws.deriv = std::make_unique<DerivT>(model_);
    return *ws.deriv;
  }
  MinvT& minv(Ws& ws) const {
    if (!ws.minv) ws.minv = std::make_unique<MinvT>(model_);
    return *ws.minv;
  }

  template <Op O>
  void one(const Call& c, Ws& ws, std::ptrdiff_t b) const {
    auto& d = ws.data;
    const M& m = model_;
    if constexpr (O == Op::Rnea) {
      const auto q = q_at(c.in[0], b);
      const auto v = v_at(c.in[1], b);
      const auto a = v_at(c.in[2], b);
      if (c.in[3].p) {  // external forces: Full only (the bindings refuse the other sets with fext)
        load_fext(c.in[3], b, ws);
        put_vector(c.out[0], b, rnea(m, d, q, v, a, ws.fext));
        return;
      }
      // G and G + C v are gravity_torques and bias_forces (the same terms; no further copy of the code).
      with_dyn<7u, kFloating>(c.dyn, [&](auto D) {
        constexpr Dyn terms = decltype(D)::value;
        if constexpr (terms == Dyn::Full) put_vector(c.out[0], b, rnea(m, d, q, v, a));
        else if constexpr (terms == Dyn::Gravity) put_vector(c.out[0], b, gravity_torques(m, d, q));
        else if constexpr (terms == (Dyn::Gravity | Dyn::Velocity)) put_vector(c.out[0], b, bias_forces(m, d, q, v));
        else put_vector(c.out[0], b, rnea<terms>(m, d, q, v, a));
      });
    } else if constexpr (O == Op::Gravity) {
      put_vector(c.out[0], b, gravity_torques(m, d, q_at(c.in[0], b)));
    } else if constexpr (O == Op::Bias) {
      put_vector(c.out[0], b, bias_forces(m, d, q_at(c.in[0], b), v_at(c.in[1], b)));
    } else if constexpr (O == Op::Crba) {
      put_matrix(c.out[0], b, crba(m, d, q_at(c.in[0], b)));
    } else if constexpr (O == Op::Aba) {
      const auto q = q_at(c.in[0], b);
      const auto v = v_at(c.in[1], b);
      const auto tau = v_at(c.in[2], b);
      if (c.in[3].p) {  // external forces: Full only, as for rnea
        load_fext(c.in[3], b, ws);
        put_vector(c.out[0], b, aba(m, d, q, v, tau, ws.fext));
        return;
      }
      with_dyn<3u, kFloating>(c.dyn, [&](auto D) {
        constexpr Dyn terms = decltype(D)::value;
        if constexpr (terms == Dyn::Full) put_vector(c.out[0], b, aba(m, d, q, v, tau));
        else put_vector(c.out[0], b, aba<terms>(m, d, q, v, tau));
      });
    } else if constexpr (O == Op::ForwardDynamics) {
      const auto q = q_at(c.in[0], b);
      const auto v = v_at(c.in[1], b);
      const auto tau = v_at(c.in[2], b);
      with_dyn<3u, kFloating>(c.dyn, [&](auto D) {
        constexpr Dyn terms = decltype(D)::value;
        if constexpr (terms == Dyn::Full) put_vector(c.out[0], b, forward_dynamics_crba(m, d, q, v, tau));
        else put_vector(c.out[0], b, forward_dynamics_crba<terms>(m, d, q, v, tau));
      });
    } else if constexpr (O == Op::KineticEnergy) {
      *c.out[0].at(b) = kinetic_energy(m, d, q_at(c.in[0], b), v_at(c.in[1], b));
    } else if constexpr (O == Op::PotentialEnergy) {
      *c.out[0].at(b) = potential_energy(m, d, q_at(c.in[0], b));
    } else if constexpr (O == Op::FramePlacement) {
      forward_kinematics(m, d, q_at(c.in[0], b));
      Eigen::Isometry3d pose;
      if (c.target_is_body) {
        if constexpr (kFloating) pose = body_pose(m, d, c.target);
        else pose = body_pose(d, c.target);
      } else {
        pose = frame_pose(m, d, c.target);
      }
      put_matrix(c.out[0], b, pose.matrix());
    } else if constexpr (O == Op::FrameJacobian) {
      if (c.target_is_body) compute_body_jacobian(m, d, q_at(c.in[0], b), c.target, c.reference, ws.J);
      else compute_frame_jacobian(m, d, q_at(c.in[0], b), c.target, c.reference, ws.J);
      put_matrix(c.out[0], b, ws.J);
    } else if constexpr (O == Op::FrameVelocity) {
      forward_kinematics(m, d, q_at(c.in[0], b), v_at(c.in[1], b), ws.zero);
      put_motion(c.out[0], b,
                 c.target_is_body ? body_velocity(m, d, c.target, c.reference)
                                  : frame_velocity(m, d, c.target, c.reference));
    } else if constexpr (O == Op::FrameAcceleration) {
      forward_kinematics(m, d, q_at(c.in[0], b), v_at(c.in[1], b), v_at(c.in[2], b));
      put_motion(c.out[0], b,
                 c.target_is_body ? body_acceleration(m, d, c.target, c.reference)
                                  : frame_acceleration(m, d, c.target, c.reference));
    } else if constexpr (O == Op::FrameClassicalAcceleration) {
      forward_kinematics(m, d, q_at(c.in[0], b), v_at(c.in[1], b), v_at(c.in[2], b));
      const Eigen::Vector3d x = c.target_is_body ? body_classical_acceleration(m, d, c.target, c.reference)
                                                 : frame_classical_acceleration(m, d, c.target, c.reference);
      put_vector(c.out[0], b, x);
    } else if constexpr (O == Op::FrameJacobianTimeVariation) {
      compute_joint_jacobians_time_variation(m, d, q_at(c.in[0], b), v_at(c.in[1], b));
      if (c.target_is_body) body_jacobian_time_variation(m, d, c.target, c.reference, ws.J);
      else frame_jacobian_time_variation(m, d, c.target, c.reference, ws.J);
      put_matrix(c.out[0], b, ws.J);
    } else if constexpr (O == Op::CenterOfMass) {
      const Eigen::Vector3d x = center_of_mass(m, d, q_at(c.in[0], b));
      put_vector(c.out[0], b, x);
    } else if constexpr (O == Op::ComJacobian) {
      com_jacobian(m, d, q_at(c.in[0], b), ws.Jc);
      put_matrix(c.out[0], b, ws.Jc);
    } else if constexpr (O == Op::CentroidalMatrix) {
      centroidal_momentum_matrix(m, d, q_at(c.in[0], b), ws.J);
      put_matrix(c.out[0], b, ws.J);
    } else if constexpr (O == Op::CentroidalMomentum) {
      const Vector6<double> h = centroidal_momentum(m, d, q_at(c.in[0], b), v_at(c.in[1], b));
      put_vector(c.out[0], b, h);
    } else if constexpr (O == Op::CentroidalMomentumRate) {
      const CentroidalMomentumRate<double> r =
          centroidal_momentum_time_variation(m, d, q_at(c.in[0], b), v_at(c.in[1], b), v_at(c.in[2], b));
      put_vector(c.out[0], b, r.dhg);
      put_vector(c.out[1], b, r.dAg_v);
    } else if constexpr (O == Op::Integrate) {
      Eigen::Map<VecQ> out(c.out[0].at(b), nq);
      if constexpr (kFloating) {
        integrate(m, q_at(c.in[0], b), v_at(c.in[1], b), c.dt, ws.qtmp);
        out = ws.qtmp;
      } else {
        out = q_at(c.in[0], b) + c.dt * v_at(c.in[1], b);
      }
    } else if constexpr (O == Op::Difference) {
      Eigen::Map<VecV> out(c.out[0].at(b), nv);
      if constexpr (kFloating) {
        difference(m, q_at(c.in[0], b), q_at(c.in[1], b), ws.vtmp);
        out = ws.vtmp;
      } else {
        out = q_at(c.in[1], b) - q_at(c.in[0], b);
      }
    } else if constexpr (O == Op::Normalize) {
      ws.qtmp = q_at(c.in[0], b);
      if constexpr (kFloating) normalize(m, ws.qtmp);
      Eigen::Map<VecQ>(c.out[0].at(b), nq) = ws.qtmp;
    } else if constexpr (O == Op::RneaDerivatives) {
      auto& dd = deriv(ws);
      rnea_derivatives(m, d, dd, q_at(c.in[0], b), v_at(c.in[1], b), v_at(c.in[2], b));
      put_matrix(c.out[0], b, dd.dtau_dq);
      put_matrix(c.out[1], b, dd.dtau_dv);
    } else if constexpr (O == Op::AbaDerivatives) {
      auto& dd = deriv(ws);
      aba_derivatives(m, d, dd, q_at(c.in[0], b), v_at(c.in[1], b), v_at(c.in[2], b));
      put_matrix(c.out[0], b, dd.dqdd_dq);
      put_matrix(c.out[1], b, dd.dqdd_dv);
      put_matrix(c.out[2], b, dd.dqdd_dtau);
    } else if constexpr (O == Op::InverseInertia) {
      put_matrix(c.out[0], b, inverse_inertia(m, d, minv(ws), q_at(c.in[0], b)));
    } else if constexpr (O == Op::MultibodyZmp) {
      put_vector(c.out[0], b, multibody_zmp(m, d, q_at(c.in[0], b), v_at(c.in[1], b), v_at(c.in[2], b), c.height));
    }
  }
};

/// Fills what a generated model's namespace knows beyond the model itself (limits, masses, name, root).
template <class E, class NS>
std::shared_ptr<ModelBase> describe_generated(std::shared_ptr<E> e, const char* name, NS) {
  e->name = name;
  e->root = std::string(NS::root_link());
  e->lower.assign(NS::lower().begin(), NS::lower().end());
  e->upper.assign(NS::upper().begin(), NS::upper().end());
  e->effort.assign(NS::effort().begin(), NS::effort().end());
  e->velocity.assign(NS::velocity().begin(), NS::velocity().end());
  e->total_mass = NS::whole_body_mass();
  return e;
}

/// The generated namespace's constants as static functions (a namespace cannot be a template argument).
#define SPATIAL_PY_GENERATED(ns)                                             \
  struct ns##_info {                                                        \
    static std::string_view root_link() { return models::ns::root_link; }   \
    static const auto& lower() { return models::ns::lower; }                \
    static const auto& upper() { return models::ns::upper; }                \
    static const auto& effort() { return models::ns::effort; }              \
    static const auto& velocity() { return models::ns::velocity; }          \
    static double whole_body_mass() { return models::ns::whole_body_mass; } \
  };

}  // namespace spatial::python
