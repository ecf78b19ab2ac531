/// \file bind_batch.cpp
/// Many states per call on SIMD lanes from Python: `spatial.Batch` (batch.hpp's `Batch<double, Tree>` or
/// `FloatingBatch<double, Tree>` through engine.hpp's BatchBase). The functions (`spatial.rnea(model, Q, ...)`) loop
/// over the states with the single-state code, so that a batch row equals the single call bit for bit; a Batch computes `lanes` states per
/// instruction instead (about twice the states per second), to within a few units in the last place of them.

#include "bind_common.hpp"

namespace spatial::python {

namespace {

/// A Batch and its model; the lock keeps two Python threads (each without the GIL) off one Batch's workspaces.
struct PyBatch {
  std::shared_ptr<ModelBase> model;
  std::unique_ptr<BatchBase> batch;
  std::mutex lock;
};

/// A frame method's target (resolve_target) and reference frame.
struct FrameSpec {
  int target = -1;
  bool body = false;
  spatial::ReferenceFrame reference = spatial::ReferenceFrame::LocalWorldAligned;
};

/// Runs `op` on the arguments `xs` (q first; each (n,), shared by every state, or (B, n), n = nq for q, nv for the
/// others); returns (B, nv), (B, nv, nv) for Crba, (B, 4, 4) for FramePlacement or (B, 6, nv) for FrameJacobian (of
/// `frame`), without the leading B when every argument is one state.
NDArray call(PyBatch& s, Op op, const char* fn, std::initializer_list<std::pair<nb::handle, const char*>> xs,
             const FrameSpec& frame = {}) {
  const int nv = s.model->nv;
  Array arrays[3];
  int widths[3] = {s.model->nq, nv, nv};
  std::ptrdiff_t count = -1;
  std::size_t k = 0;
  for (const auto& [h, arg] : xs) {
    Array a = to_array(h, fn, arg);
    const int n = widths[k];
    const bool one = a.ndim() == 1 && a.shape(0) == std::size_t(n);
    const bool many = a.ndim() == 2 && a.shape(1) == std::size_t(n);
    if (!one && !many) {
      std::ostringstream m;
      m << fn << ": argument '" << arg << "' has shape " << shape_str(a) << "; the model '" << s.model->name
        << "' has " << (k == 0 ? "nq" : "nv") << " = " << n << ", so expected (" << n << ",) or (B, " << n << ")";
      throw nb::value_error(m.str().c_str());
    }
    if (many) {
      const auto b = std::ptrdiff_t(a.shape(0));
      if (count >= 0 && b != count) {
        std::ostringstream m;
        m << fn << ": argument '" << arg << "' has " << b << " states, an earlier argument " << count;
        throw nb::value_error(m.str().c_str());
      }
      count = b;
    }
    arrays[k++] = std::move(a);
  }
  const bool batched = count >= 0;
  if (!batched) count = 1;
  // An argument shared by the states is repeated into a (B, nv) buffer: Batch reads one column per state.
  std::vector<double> shared[3];
  const double* in[3] = {nullptr, nullptr, nullptr};
  for (std::size_t j = 0; j < k; ++j) {
    in[j] = arrays[j].data();
    if (batched && arrays[j].ndim() == 1) {
      const std::ptrdiff_t n = widths[j];
      shared[j].resize(std::size_t(count) * std::size_t(n));
      for (std::ptrdiff_t b = 0; b < count; ++b) std::copy(in[j], in[j] + n, shared[j].begin() + b * n);
      in[j] = shared[j].data();
    }
  }
  npy_intp shape[3];
  int nd = 0;
  if (batched) shape[nd++] = npy_intp(count);
  if (op == Op::FramePlacement) {
    shape[nd++] = 4;
    shape[nd++] = 4;
  } else if (op == Op::FrameJacobian) {
    shape[nd++] = 6;
    shape[nd++] = nv;
  } else {
    shape[nd++] = nv;
    if (op == Op::Crba) shape[nd++] = nv;
  }
  auto [obj, out] = new_array<double>(nd, shape);
  std::unique_lock<std::mutex> lock(s.lock, std::try_to_lock);
  if (!lock.owns_lock()) throw nb::value_error((std::string(fn) + ": this Batch is in use by another thread").c_str());
  {
    nb::gil_scoped_release release;
    if (op == Op::FramePlacement || op == Op::FrameJacobian)
      s.batch->frame(op, count, in[0], frame.target, frame.body, frame.reference, out);
    else
      s.batch->run(op, count, in, out);
  }
  return {obj};
}

/// The target of a frame method: a fixed frame or a body, by name or frame index (as the functions take it).
FrameSpec frame_of(const PyBatch& s, nb::handle frame, const char* fn, const std::string& reference = {}) {
  Call c;
  resolve_target(*s.model, frame, fn, c);
  FrameSpec f;
  f.target = c.target;
  f.body = c.target_is_body;
  if (!reference.empty()) f.reference = reference_of(reference, fn);
  return f;
}

}  // namespace

void bind_batch(nb::module_& m) {
  nb::class_<PyBatch>(m, "Batch",
                      "Many states per call on SIMD lanes (C++ batch.hpp): each lane of a register one state, "
                      "lanes states per instruction, on a pool of `threads` threads started once (0: all cores). "
                      "Fixed or floating base. Arguments (n,) (shared by every state) or (B, n), n = nq for q and "
                      "nv for the others; results (B, nv), "
                      "crba (B, nv, nv). A state's result does not depend on B, on the threads or on the other "
                      "states (bit for bit; a NaN stays in its state); it is the single call's to within a few "
                      "units in the last place (another order of the same operations), where spatial.rnea(model, "
                      "Q, ...) equals the single calls bit for bit at about half the states per second.")
      .def("__init__",
           [](PyBatch* self, std::shared_ptr<ModelBase> model, int threads) {
             const int t = thread_count(threads);
             new (self) PyBatch();
             self->batch = model->make_batch(t);
             self->model = std::move(model);
           },
           "model"_a, "threads"_a = 1)
      .def_prop_ro("lanes", [](const PyBatch& s) { return s.batch->lanes(); },
                   "States per SIMD register (4 doubles with AVX2, 8 with AVX-512, 2 with SSE2 or NEON).")
      .def_prop_ro("threads", [](const PyBatch& s) { return s.batch->threads(); })
      .def_prop_ro("model", [](const PyBatch& s) { return s.model; })
      .def("rnea",
           [](PyBatch& s, ArrayLike q, ArrayLike v, ArrayLike a) {
             return call(s, Op::Rnea, "Batch.rnea", {{q.h, "q"}, {v.h, "v"}, {a.h, "a"}});
           },
           "q"_a, "v"_a, "a"_a, "Inverse dynamics (RNEA) per state: tau = H(q) a + C(q, v).")
      .def("gravity", [](PyBatch& s, ArrayLike q) { return call(s, Op::Gravity, "Batch.gravity", {{q.h, "q"}}); },
           "q"_a, "Gravity torques G(q) per state.")
      .def("bias",
           [](PyBatch& s, ArrayLike q, ArrayLike v) {
             return call(s, Op::Bias, "Batch.bias", {{q.h, "q"}, {v.h, "v"}});
           },
           "q"_a, "v"_a, "Bias forces C(q, v) = rnea(q, v, 0) per state.")
      .def("aba",
           [](PyBatch& s, ArrayLike q, ArrayLike v, ArrayLike tau) {
             return call(s, Op::Aba, "Batch.aba", {{q.h, "q"}, {v.h, "v"}, {tau.h, "tau"}});
           },
           "q"_a, "v"_a, "tau"_a, "Forward dynamics (ABA) per state.")
      .def("forward_dynamics",
           [](PyBatch& s, ArrayLike q, ArrayLike v, ArrayLike tau) {
             return call(s, Op::ForwardDynamics, "Batch.forward_dynamics", {{q.h, "q"}, {v.h, "v"}, {tau.h, "tau"}});
           },
           "q"_a, "v"_a, "tau"_a, "Forward dynamics by CRBA + the tree's LTDL factorisation per state.")
      .def("crba", [](PyBatch& s, ArrayLike q) { return call(s, Op::Crba, "Batch.crba", {{q.h, "q"}}); }, "q"_a,
           "Joint-space inertia H(q) per state, both triangles filled (exactly symmetric).")
      .def("frame_placement",
           [](PyBatch& s, ArrayLike q, FrameArg frame) {
             const FrameSpec f = frame_of(s, frame.h, "Batch.frame_placement");
             return call(s, Op::FramePlacement, "Batch.frame_placement", {{q.h, "q"}}, f);
           },
           "q"_a, "frame"_a,
           "Pose (4, 4) per state of a frame or body (name or frame index), as spatial.frame_placement: "
           "[R p; 0 1], world (fixed base: base) coordinates.")
      .def("frame_jacobian",
           [](PyBatch& s, ArrayLike q, FrameArg frame, const std::string& reference) {
             const FrameSpec f = frame_of(s, frame.h, "Batch.frame_jacobian", reference);
             return call(s, Op::FrameJacobian, "Batch.frame_jacobian", {{q.h, "q"}}, f);
           },
           "q"_a, "frame"_a, "reference"_a = "local_world_aligned",
           "Jacobian (6, nv) per state of a frame or body, as spatial.frame_jacobian: rows [v_lin; omega]; "
           "reference 'local', 'world' or 'local_world_aligned'.");
}

}  // namespace spatial::python
