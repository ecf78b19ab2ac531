#pragma once
/// \file contacts.hpp
/// Rigid contacts from Python: the contact description the bindings build and the interface of a model's contact
/// set (implemented per model kind in contacts_impl.hpp, bound in bind_contacts.cpp).
///
/// A contact set owns its model's `ContactData` and `Data` (the calling thread's workspace, guarded by a mutex: a
/// second Python thread that finds it busy computes with a fresh one) and the contacts' configuration (frames, gains,
/// targets; guarded by another mutex). A batch split over threads gives each extra thread a workspace of its own;
/// every state is computed by the same non-inlined per-state loop, so the results do not depend on the split.

#include <spatial/spatial.hpp>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace spatial::python {

/// One contact as given from Python (see contact.hpp's RigidContact).
struct ContactSpec {
  std::string name;
  int frame = -1;
  bool six_d = true;
  ReferenceFrame reference = ReferenceFrame::Local;
  double kp = 0, kd = 0, friction = 0.6;
  double sole_x_min = 0, sole_x_max = 0, sole_y_min = 0, sole_y_max = 0;
};

/// What a contact-set call computes (arguments in `ContactCall::in`, results in `out`, in this order).
enum class ContactOp : int {
  ForwardDynamics,   ///< in q, v, tau → out a (nv), lambda (m); NaN when cd.ok is false
  Impulse,           ///< in q, v → out v_after (nv), impulses (m); NaN when cd.ok is false
  InverseDynamics,   ///< in q, v, a → out tau (nv), lambda (m), flag ok (floating base only)
  Jacobian,          ///< in q → out J (m × nv, row-major)
  Wrench,            ///< in q, lambda → out [f; n about the world origin] (6), world axes
  CenterOfPressure,  ///< in q, lambda → out point (3) on the plane z = height
};

/// A strided array of doubles: state b at p + b * stride (stride 0: shared by every state).
struct StridedIn {
  const double* p = nullptr;
  std::ptrdiff_t stride = 0;
  const double* at(std::ptrdiff_t b) const { return p + b * stride; }
};
struct StridedOut {
  double* p = nullptr;
  std::ptrdiff_t stride = 0;
  double* at(std::ptrdiff_t b) const { return p + b * stride; }
};

/// One call of a contact set over `count` states.
struct ContactCall {
  ContactOp op = ContactOp::ForwardDynamics;
  std::ptrdiff_t count = 1;
  StridedIn in[3];
  StridedOut out[2];
  bool* flag = nullptr;      ///< InverseDynamics: one bool per state (ok)
  double restitution = 0;    ///< Impulse
  double height = 0;         ///< CenterOfPressure
};

/// A model's contact set with its buffers (ContactData), behind a model-independent interface.
class ContactsBase {
 public:
  virtual ~ContactsBase() = default;

  /// Constraint rows m, and per contact: name (the frame's), frame index, dimension (6 or 3) and first row.
  int rows = 0;
  std::vector<std::string> names;
  std::vector<int> frames, dims, offsets;
  double damping = 0;

  /// Runs `call` (thread-safe: see the top of this file); `threads` > 1 splits the batch over that many threads.
  virtual void run(const ContactCall& call, int threads) = 0;
  /// set_contact_targets at q (nq doubles): every contact's target becomes its frame's current world pose.
  virtual void set_targets(const double* q) = 0;
  /// The targets as homogeneous transforms, row-major 4 × 4 per contact (len(names) × 16 doubles).
  virtual void targets(double* out) const = 0;
};

}  // namespace spatial::python
