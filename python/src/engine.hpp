#pragma once
/// \file engine.hpp
/// The C++ side of the Python module, apart from the bindings themselves: one `Engine` per model kind (run-time
/// fixed or floating base, and each generated compile-time HOAP-3 model), behind one abstract interface so that
/// Python sees a single `Model` class. A Python call is one virtual call into `Engine<M>::run`, which loops over the
/// states of a batch (and splits it over threads) inside the templated code: the library's algorithms themselves
/// are called directly, specialised for the model, as from C++.
///
/// Arrays cross the interface as raw pointers with a per-state stride (0: the same input for every state); inputs
/// are C-contiguous float64 (the bindings convert anything else once), outputs are the fresh NumPy arrays the
/// bindings allocate, written row-major.

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "contacts.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace spatial::python {

enum class Op : int {
  Rnea,
  Gravity,
  Bias,
  Crba,
  Aba,
  ForwardDynamics,
  KineticEnergy,
  PotentialEnergy,
  FramePlacement,
  FrameJacobian,
  FrameVelocity,
  FrameAcceleration,
  FrameClassicalAcceleration,
  FrameJacobianTimeVariation,
  CenterOfMass,
  ComJacobian,
  CentroidalMatrix,
  CentroidalMomentum,
  CentroidalMomentumRate,
  Integrate,
  Difference,
  Normalize,
  RneaDerivatives,
  AbaDerivatives,
  InverseInertia,
  MultibodyZmp,
};

struct In {
  const double* p = nullptr;
  std::ptrdiff_t stride = 0;  ///< doubles from one state to the next (0: shared by all states)
  const double* at(std::ptrdiff_t b) const { return p ? p + b * stride : nullptr; }
};
struct Out {
  double* p = nullptr;
  std::ptrdiff_t stride = 0;
  double* at(std::ptrdiff_t b) const { return p + b * stride; }
};

/// How many threads a batch of `count` states runs on when `threads` are asked for: each must get at least
/// `min_per_thread` states, since starting a thread costs tens of microseconds (a 100-state RNEA batch on two
/// threads was measured 2.6 times slower than on one).
inline std::ptrdiff_t threads_for(std::ptrdiff_t count, int threads, std::ptrdiff_t min_per_thread) {
  const std::ptrdiff_t most = count / min_per_thread;
  return std::max<std::ptrdiff_t>(1, std::min<std::ptrdiff_t>(threads, most));
}
/// States per thread at least, for the algorithms (engine_impl.hpp, contacts_impl.hpp) and for IK starts.
inline constexpr std::ptrdiff_t kMinStatesPerThread = 256;
inline constexpr std::ptrdiff_t kMinIkStartsPerThread = 4;

/// One call: an operation over `count` states.
struct Call {
  Op op = Op::Rnea;
  std::ptrdiff_t count = 1;
  In in[4];     ///< the operation's array inputs in its argument order (q, v, a|tau, fext)
  Out out[3];   ///< its outputs in order
  int target = -1;       ///< frame or body index (the Frame* operations)
  bool target_is_body = false;
  ReferenceFrame reference = ReferenceFrame::LocalWorldAligned;
  double dt = 1.0;       ///< Integrate
  double height = 0.0;   ///< MultibodyZmp: the ground plane z = height
  /// Rnea, Aba, ForwardDynamics: the terms computed (options.hpp's `Dyn` flags Gravity | Velocity | Acceleration;
  /// Aba and ForwardDynamics ignore Acceleration). Anything but Full only on fixed-base models (the bindings check).
  unsigned dyn = unsigned(Dyn::Full);
};

/// Per-thread buffers of one model kind (the library's Data and what the derivatives need).
struct Workspace {
  virtual ~Workspace() = default;
};

/// An inverse-kinematics task as given from Python (ik.hpp's IkTask; rotation row-major).
struct IkTaskSpec {
  IkTaskKind kind = IkTaskKind::Pose;
  int frame = -1;
  double position[3] = {0, 0, 0};
  double rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double weight = 1;
  double axes[6] = {1, 1, 1, 1, 1, 1};
};
/// IkOptions as given from Python (limits: one per joint, empty: none).
struct IkOptionsSpec {
  int max_iterations = 200;
  double tolerance = 1e-12, step_tolerance = 1e-15, damping = 1e-6;
  bool adaptive = true;
  std::vector<double> lower, upper;
  std::vector<int> active;
};
/// IkStatus.
struct IkResult {
  bool converged = false;
  IkReason reason = IkReason::MaxIterations;
  int iterations = 0, accepted = 0;
  double residual = 0, damping = 0;
};
/// An IkSolver of one model kind, behind a model-independent interface.
class IkBase {
 public:
  virtual ~IkBase() = default;
  virtual int rows() const = 0;
  virtual int tasks() const = 0;
  /// Solves from each of `count` starts (q0 + b * nq), writing q (q + b * nq) and the status; threads > 1 runs
  /// copies of the solver on more threads.
  virtual void solve(const double* q0, std::ptrdiff_t q0_stride, double* q, IkResult* status, std::ptrdiff_t count,
                     int threads) = 0;
  virtual void set_task(int i, const IkTaskSpec& t) = 0;
  virtual double residual(const double* q, double* r) = 0;
};

/// batch.hpp's `Batch<double, Tree>` (fixed base) or `FloatingBatch<double, Tree>` of one model, behind a
/// model-independent interface (Python's `spatial.Batch`): many states per call on SIMD lanes, on a pool of threads
/// of its own started once.
class BatchBase {
 public:
  virtual ~BatchBase() = default;
  /// States per SIMD register, and the threads of the pool.
  virtual int lanes() const = 0;
  virtual int threads() const = 0;
  /// `op` (Rnea, Gravity, Bias, Aba, ForwardDynamics or Crba) on `count` states: in[k] the operation's k-th input
  /// as `count` contiguous rows of nq (q, k = 0) or nv (row-major (count, n), as NumPy holds a C-contiguous array),
  /// out the output row-major (count, nv), or (count, nv, nv) for Crba. Throws std::invalid_argument for another
  /// operation.
  virtual void run(Op op, std::ptrdiff_t count, const double* const* in, double* out) = 0;
  /// FramePlacement or FrameJacobian of fixed frame `target` (of body `target` when `body`) on `count` states: q as
  /// in `run`, out row-major (count, 4, 4) ([R p; 0 0 0 1]) or (count, 6, nv) (rows linear first, in `reference`).
  /// Throws std::invalid_argument for another operation.
  virtual void frame(Op op, std::ptrdiff_t count, const double* q, int target, bool body,
                     spatial::ReferenceFrame reference, double* out) = 0;
};

/// What Python's `Model` holds: the model's description and its engine.
class ModelBase {
 public:
  virtual ~ModelBase() = default;

  std::string name, root;
  bool floating = false, compile_time = false;
  int nq = 0, nv = 0, njoints = 0;
  std::vector<std::string> joint_names, body_names, frame_names, warnings;
  std::vector<int> source_joints;  ///< a reduced model: its joints' indices in the model it was reduced from
  std::vector<double> lower, upper, effort, velocity;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  double total_mass = 0;

  virtual std::unique_ptr<Workspace> workspace() const = 0;
  /// Runs `call` with `ws` (the calling thread's workspace) and, when threads > 1, with threads − 1 more threads,
  /// each with a workspace of its own; every state is computed by the same code whatever the split.
  virtual void run(const Call& call, Workspace& ws, int threads) const = 0;
  virtual void neutral(double* q) const = 0;
  /// An inverse-kinematics solver on this model (throws std::invalid_argument for bad frames, limits, active).
  virtual std::unique_ptr<IkBase> make_ik(const std::vector<IkTaskSpec>& tasks, const IkOptionsSpec& opt) const = 0;
  /// Model reduction (reduce.hpp), fixed base only: `kind` 0 lock_joints(names at positions), 1 keep_joints(names,
  /// the others held at q), 2 keep_branches(body names, the others held at q). Throws ModelError naming the joint.
  virtual std::shared_ptr<ModelBase> reduce(int kind, const std::vector<std::string>& names,
                                            const std::vector<double>& positions, const double* q) const = 0;
  /// A contact set on this model (contacts.hpp, contacts_impl.hpp).
  virtual std::unique_ptr<ContactsBase> make_contacts(const std::vector<ContactSpec>& specs, double damping) const = 0;
  /// The batched algorithms on this model with `threads` threads (≥ 1).
  virtual std::unique_ptr<BatchBase> make_batch(int threads) const = 0;

  /// The model's own workspace, for calls made without `data=` (the lock guards it against two Python threads
  /// that released the GIL in a batch; a caller that finds it busy gets a fresh one).
  mutable std::mutex default_lock;
  std::unique_ptr<Workspace> default_ws;
};

std::shared_ptr<ModelBase> make_runtime_model(const urdf_io::LoadedModel& loaded, const std::string& name);
/// The engine of a reduced model, its description taken from the model it was reduced from (models_runtime.cpp).
std::shared_ptr<ModelBase> make_reduced_model(const ModelBase& from, const ReducedModel<double>& reduced);
std::shared_ptr<ModelBase> make_hoap3_stance_right();
std::shared_ptr<ModelBase> make_hoap3_stance_left();
std::shared_ptr<ModelBase> make_hoap3_torso();
std::shared_ptr<ModelBase> make_hoap3_double_pendulum();
std::shared_ptr<ModelBase> make_hoap3_floating();

}  // namespace spatial::python
