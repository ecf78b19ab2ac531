/// \file bind_contacts.cpp
/// Contact dynamics from Python: the contact descriptions `Contact6D` / `Contact3D`, the contact set `Contacts`, and
/// `constrained_forward_dynamics`, `impulse_dynamics`, `contact_inverse_dynamics`, `contact_jacobian`,
/// `contact_wrench`, `center_of_pressure`, `multibody_zmp`. Same conventions as module.cpp (bind_common.hpp): one
/// state ((n,) arrays) or a batch ((B, n)), fresh outputs, batches without the GIL on `threads` threads,
/// `check=True` refuses non-finite inputs, errors name the function and the argument.

#include "bind_common.hpp"

namespace spatial::python::contacts_py {

/// Argument and result types that only name themselves in the generated stubs.
struct SoleArg {
  nb::handle h;
};
struct ContactsArg {
  nb::handle h;
};
struct BoolOrArray {
  nb::object o;
};
struct FrameOut {
  nb::object o;
};
struct SoleOut {
  nb::object o;
};
struct ContactListOut {
  nb::object o;
};

}  // namespace spatial::python::contacts_py

namespace nanobind::detail {
namespace cp = spatial::python::contacts_py;
template <>
struct type_caster<cp::SoleArg> {
  NB_TYPE_CASTER(cp::SoleArg, const_name("tuple[float, float, float, float]"))
  bool from_python(handle src, uint8_t, cleanup_list*) noexcept {
    value.h = src;
    return true;
  }
};
template <>
struct type_caster<cp::ContactsArg> {
  NB_TYPE_CASTER(cp::ContactsArg, const_name("Contact | collections.abc.Sequence[Contact]"))
  bool from_python(handle src, uint8_t, cleanup_list*) noexcept {
    value.h = src;
    return true;
  }
};
#define SPATIAL_PY_TYPED_RESULT(T, name)                                                            \
  template <>                                                                                       \
  struct type_caster<T> {                                                                           \
    NB_TYPE_CASTER(T, const_name(name))                                                             \
    static handle from_cpp(const T& v, rv_policy, cleanup_list*) noexcept { return v.o.inc_ref(); } \
  };
SPATIAL_PY_TYPED_RESULT(cp::BoolOrArray, "bool | numpy.typing.NDArray[numpy.bool_]")
SPATIAL_PY_TYPED_RESULT(cp::FrameOut, "str | int")
SPATIAL_PY_TYPED_RESULT(cp::SoleOut, "tuple[float, float, float, float] | None")
SPATIAL_PY_TYPED_RESULT(cp::ContactListOut, "list[Contact]")
#undef SPATIAL_PY_TYPED_RESULT
}  // namespace nanobind::detail

namespace spatial::python {
namespace contacts_py {
namespace {

StridedIn strided(const In& in) { return {in.p, in.stride}; }
StridedOut strided(const Out& out) { return {out.p, out.stride}; }

/// A fresh NumPy bool array of shape (B,) or () (contact_inverse_dynamics' ok).
struct Flags {
  explicit Flags(const Args& args) {
    const npy_intp shape[1] = {npy_intp(args.count())};
    std::tie(obj, data) = new_array<bool>(args.batched() ? 1 : 0, shape);
  }
  BoolOrArray result(const Args& args) const { return {args.batched() ? obj : nb::bool_(data[0])}; }
  nb::object obj;
  bool* data = nullptr;
};

// ---- contact descriptions and contact sets ---------------------------------------------------------------------

/// A contact as described from Python (resolved against a model by Contacts).
struct Contact {
  nb::object frame;  // str or int
  bool six_d = true;
  std::string reference;
  double kp = 0, kd = 0, friction = 0.6;
  bool has_sole = false;
  double sole[4] = {0, 0, 0, 0};
};
struct Contact6D : Contact {};
struct Contact3D : Contact {};

ReferenceFrame contact_reference(const std::string& r, const char* fn) {
  if (r == "local") return ReferenceFrame::Local;
  if (r == "local_world_aligned") return ReferenceFrame::LocalWorldAligned;
  if (r == "world") return ReferenceFrame::World;  // refused by ContactData (ModelError naming the contact)
  throw nb::value_error((std::string(fn) + ": reference '" + r +
                         "' is not one of 'local', 'local_world_aligned' (the axes lambda is reported in)").c_str());
}

void init_contact(Contact& c, const char* fn, bool six_d, nb::handle frame, const std::string& reference, double kp,
                  double kd, double friction, nb::handle sole) {
  if (!nb::isinstance<nb::str>(frame)) {
    int k = 0;
    if (nb::isinstance<nb::bool_>(frame) || !nb::try_cast<int>(frame, k))
      throw nb::type_error((std::string(fn) + ": 'frame' must be a frame name (str) or a frame index (int), not " +
                            nb::inst_name(frame).c_str()).c_str());
  }
  if (reference == "world")
    throw nb::value_error((std::string(fn) + ": reference 'world' is not offered (the moment would be about the "
                           "world origin): use 'local' or 'local_world_aligned'").c_str());
  contact_reference(reference, fn);
  const auto check = [fn](double x, const char* what) {
    if (!std::isfinite(x) || x < 0)
      throw nb::value_error((std::string(fn) + ": '" + what + "' must be finite and >= 0, not " +
                             std::to_string(x)).c_str());
  };
  check(kp, "kp");
  check(kd, "kd");
  check(friction, "friction");
  c.frame = nb::borrow(frame);
  c.six_d = six_d;
  c.reference = reference;
  c.kp = kp, c.kd = kd, c.friction = friction;
  if (!sole.is_none()) {
    std::vector<double> s;
    bool ok = nb::isinstance<nb::sequence>(sole) && !nb::isinstance<nb::str>(sole);
    if (ok) {
      for (nb::handle x : sole) {
        double d;
        if (!nb::try_cast<double>(x, d)) {
          ok = false;
          break;
        }
        s.push_back(d);
      }
    }
    if (!ok || s.size() != 4 || !std::all_of(s.begin(), s.end(), [](double x) { return std::isfinite(x); }))
      throw nb::value_error((std::string(fn) + ": 'sole' must be 4 finite numbers (x_min, x_max, y_min, y_max) in "
                             "metres, in the frame's x-y plane").c_str());
    if (s[0] > s[1] || s[2] > s[3])
      throw nb::value_error((std::string(fn) + ": 'sole' (x_min, x_max, y_min, y_max) needs x_min <= x_max and "
                             "y_min <= y_max").c_str());
    c.has_sole = true;
    std::copy(s.begin(), s.end(), c.sole);
  }
}

std::string describe(const Contact& c) {
  std::ostringstream s;
  s << (c.six_d ? "Contact6D(" : "Contact3D(") << nb::repr(c.frame).c_str() << ", reference='" << c.reference
    << "', kp=" << c.kp << ", kd=" << c.kd << ", friction=" << c.friction;
  if (c.six_d && c.has_sole)
    s << ", sole=(" << c.sole[0] << ", " << c.sole[1] << ", " << c.sole[2] << ", " << c.sole[3] << ")";
  s << ")";
  return s.str();
}

/// What Python's `Contacts` holds.
struct PyContacts {
  std::shared_ptr<ModelBase> model;  // declared first: destroyed after impl, which refers to its C++ model
  std::unique_ptr<ContactsBase> impl;
  std::vector<nb::object> descriptions;
};

PyContacts make_contact_set(std::shared_ptr<ModelBase> model, nb::handle list, double damping) {
  const char* fn = "Contacts";
  if (!std::isfinite(damping) || damping < 0)
    throw nb::value_error(("Contacts: 'damping' must be finite and >= 0, not " + std::to_string(damping)).c_str());
  std::vector<nb::object> items;
  if (nb::isinstance<Contact>(list)) {
    items.push_back(nb::borrow(list));
  } else if (nb::isinstance<nb::sequence>(list) && !nb::isinstance<nb::str>(list)) {
    for (nb::handle h : list) items.push_back(nb::borrow(h));
  } else {
    throw nb::type_error("Contacts: 'contacts' must be a list of Contact6D / Contact3D");
  }
  std::vector<ContactSpec> specs;
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (!nb::isinstance<Contact>(items[k]))
      throw nb::type_error(("Contacts: contacts[" + std::to_string(k) + "] is a " +
                            nb::inst_name(items[k]).c_str() + ", not a Contact6D or Contact3D").c_str());
    const Contact& c = nb::cast<const Contact&>(items[k]);
    ContactSpec s;
    if (nb::isinstance<nb::str>(c.frame)) {
      const std::string name = nb::cast<std::string>(c.frame);
      s.frame = index_of(model->frame_names, name);
      if (s.frame < 0) {
        std::string msg = std::string(fn) + ": contacts[" + std::to_string(k) + "]: unknown frame '" + name +
                          "' in the model '" + model->name + "'";
        if (index_of(model->body_names, name) >= 0)
          msg += " ('" + name + "' is a body; contacts hold the model's frames, model.frame_names)";
        msg += spatial::detail::did_you_mean(name, model->frame_names);
        throw nb::key_error(msg.c_str());
      }
    } else {
      s.frame = nb::cast<int>(c.frame);  // out of range: ModelError from ContactData
    }
    s.six_d = c.six_d;
    s.reference = contact_reference(c.reference, fn);
    s.kp = c.kp, s.kd = c.kd, s.friction = c.friction;
    s.sole_x_min = c.sole[0], s.sole_x_max = c.sole[1], s.sole_y_min = c.sole[2], s.sole_y_max = c.sole[3];
    specs.push_back(s);
  }
  PyContacts pc;
  pc.impl = model->make_contacts(specs, damping);
  if (!pc.impl) throw std::runtime_error("Contacts: this model kind has no contact engine");
  pc.model = std::move(model);
  pc.descriptions = std::move(items);
  return pc;
}

/// Runs a contact call, without the GIL for batches.
void run_contacts(ContactsBase& impl, ContactCall& call, const Args& args, int threads, bool check) {
  if (check) args.check_finite();
  call.count = args.count();
  const int t = thread_count(threads);
  if (args.batched()) {
    nb::gil_scoped_release release;
    impl.run(call, t);
  } else {
    impl.run(call, 1);
  }
}

StridedIn q_arg(Args& args, nb::handle h) { return strided(args.vector(h, "q", args.model().nq, "nq")); }
StridedIn v_arg(Args& args, nb::handle h, const char* arg) {
  return strided(args.vector(h, arg, args.model().nv, "nv"));
}
/// Contact forces (m,) or (B, m): checked here for a message about the contact set rather than the model.
StridedIn lambda_arg(Args& args, const PyContacts& pc, nb::handle h, const char* fn, const char* arg) {
  const Array a = to_array(h, fn, arg);
  const std::size_t m = std::size_t(pc.impl->rows);
  if (!((a.ndim() == 1 && a.shape(0) == m) || (a.ndim() == 2 && a.shape(1) == m))) {
    std::ostringstream s;
    s << fn << ": argument '" << arg << "' has shape " << shape_str(a) << "; the contact set has " << m
      << " rows (contacts.rows), so expected (" << m << ",) or (B, " << m << ")";
    throw nb::value_error(s.str().c_str());
  }
  return strided(args.vector(a.obj, arg, pc.impl->rows, "rows"));
}

}  // namespace
}  // namespace contacts_py

void bind_contacts(nb::module_& m) {
  using namespace contacts_py;

  nb::class_<Contact>(m, "Contact",
                      "A rigid contact description (Contact6D or Contact3D), to be placed in a Contacts set.")
      .def_prop_ro("frame", [](const Contact& c) { return FrameOut{c.frame}; },
                   "The frame: a name or an index of the model's frame_names.")
      .def_prop_ro("type", [](const Contact& c) { return std::string(c.six_d ? "6d" : "3d"); },
                   "'6d' (Contact6D) or '3d' (Contact3D).")
      .def_prop_ro("reference", [](const Contact& c) { return c.reference; },
                   "Axes lambda is reported in: 'local' (the frame's) or 'local_world_aligned' (world axes).")
      .def_prop_ro("kp", [](const Contact& c) { return c.kp; }, "Baumgarte position gain [1/s^2].")
      .def_prop_ro("kd", [](const Contact& c) { return c.kd; }, "Baumgarte velocity gain [1/s].")
      .def_prop_ro("friction", [](const Contact& c) { return c.friction; },
                   "Friction coefficient mu (contact_inverse_dynamics' friction pyramid).")
      .def_prop_ro("sole",
                   [](const Contact& c) {
                     if (!c.has_sole) return SoleOut{nb::none()};
                     return SoleOut{nb::make_tuple(c.sole[0], c.sole[1], c.sole[2], c.sole[3])};
                   },
                   "(x_min, x_max, y_min, y_max) [m] in the frame's x-y plane, or None (6D only).")
      .def("__repr__", &describe);

  nb::class_<Contact6D, Contact>(
      m, "Contact6D",
      "A 6D contact (a flat foot, a weld): the frame's whole spatial velocity is held at zero.\n\n"
      "Constraint rows: the 6 rows of frame_jacobian(frame, reference='local'), linear first, in the frame's axes.\n"
      "lambda (6,): what the ground applies to the robot at the frame's origin, [fx fy fz nx ny nz] (force, then\n"
      "moment about the frame's origin), in the axes of `reference`: 'local' (the frame's, default) or\n"
      "'local_world_aligned' (world axes). frame: a name or index of model.frame_names.\n"
      "kp [1/s^2], kd [1/s]: Baumgarte gains on the pose error against the target (Contacts.set_targets) and the\n"
      "velocity (default 0: the pure acceleration constraint). friction (mu) and sole (x_min, x_max, y_min, y_max)\n"
      "[m], the rectangle of the frame's x-y plane the foot rests on (z: the normal, from the ground into the robot),\n"
      "are used by contact_inverse_dynamics only: the wrench is a non-negative combination of forces at the sole's\n"
      "four corners inside the friction pyramid |fx|, |fy| <= mu fz. sole=None: a point at the frame's origin.")
      .def("__init__",
           [](Contact6D* self, FrameArg frame, const std::string& reference, double kp, double kd, double friction,
              SoleArg sole) {
             new (self) Contact6D();
             init_contact(*self, "Contact6D", true, frame.h, reference, kp, kd, friction, sole.h);
           },
           "frame"_a, nb::kw_only(), "reference"_a = "local", "kp"_a = 0.0, "kd"_a = 0.0, "friction"_a = 0.6,
           "sole"_a.none() = nb::none());

  nb::class_<Contact3D, Contact>(
      m, "Contact3D",
      "A 3D (point) contact: the velocity of the frame's origin is held at zero.\n\n"
      "Constraint rows: the 3 linear rows of frame_jacobian(frame, reference='local_world_aligned') (world axes).\n"
      "lambda (3,): the force [fx fy fz] the ground applies to the robot at the frame's origin, in the axes of\n"
      "`reference`: 'local_world_aligned' (world axes, default) or 'local' (the frame's). kp, kd: Baumgarte gains\n"
      "(see Contact6D). friction: contact_inverse_dynamics' pyramid about the world's +z.")
      .def("__init__",
           [](Contact3D* self, FrameArg frame, const std::string& reference, double kp, double kd, double friction) {
             new (self) Contact3D();
             init_contact(*self, "Contact3D", false, frame.h, reference, kp, kd, friction, nb::none());
           },
           "frame"_a, nb::kw_only(), "reference"_a = "local_world_aligned", "kp"_a = 0.0, "kd"_a = 0.0,
           "friction"_a = 0.6);

  nb::class_<PyContacts>(
      m, "Contacts",
      "A set of rigid contacts on a model, with its buffers: Contacts(model, [Contact6D(...), Contact3D(...)],\n"
      "damping=0.0).\n\n"
      "The constraint rows (m = contacts.rows) and the forces lambda (m,) stack the contacts in the list's order,\n"
      "each contact's block at contacts.offsets[k] (6 rows for a 6D contact, linear first; 3 for a 3D one).\n"
      "damping mu > 0: damped least squares for redundant contacts (lambda = (J H^-1 J^T + mu I)^-1 (...)).\n"
      "contacts: a list of Contact6D / Contact3D (or one of them). Raises KeyError for an unknown frame name\n"
      "(with the closest names), ModelError for a frame index out of range.\n"
      "A set may be used from several Python threads (a thread that finds its buffers busy uses fresh ones).")
      .def("__init__",
           [](PyContacts* self, std::shared_ptr<ModelBase> model, ContactsArg contacts, double damping) {
             PyContacts made = make_contact_set(std::move(model), contacts.h, damping);
             new (self) PyContacts(std::move(made));
           },
           "model"_a, "contacts"_a, "damping"_a = 0.0)
      .def_prop_ro("model", [](const PyContacts& c) { return c.model; }, "The model.")
      .def_prop_ro("rows", [](const PyContacts& c) { return c.impl->rows; }, "m: constraint rows (sum of 6 / 3).")
      .def_prop_ro("names", [](const PyContacts& c) { return c.impl->names; }, "The contacts' frame names.")
      .def_prop_ro("frames", [](const PyContacts& c) { return c.impl->frames; },
                   "The contacts' frame indices (into model.frame_names).")
      .def_prop_ro("sizes", [](const PyContacts& c) { return c.impl->dims; }, "Rows per contact (6 or 3).")
      .def_prop_ro("offsets", [](const PyContacts& c) { return c.impl->offsets; },
                   "First row of each contact in lambda and in the Jacobian.")
      .def_prop_ro("damping", [](const PyContacts& c) { return c.impl->damping; }, "The damping mu.")
      .def_prop_ro("contacts",
                   [](const PyContacts& c) {
                     nb::list l;
                     for (const nb::object& d : c.descriptions) l.append(d);
                     return ContactListOut{l};
                   },
                   "The contact descriptions (Contact6D / Contact3D), in order.")
      .def_prop_ro("targets",
                   [](const PyContacts& c) {
                     auto [a, p] = new_array<double>({npy_intp(c.impl->names.size()), 4, 4});
                     c.impl->targets(p);
                     return NDArray{a};
                   },
                   "The Baumgarte targets (k, 4, 4): each contact's world pose [R p; 0 1] (default identity).")
      .def("set_targets",
           [](PyContacts& c, ArrayLike q) {
             Args args(*c.model, "Contacts.set_targets");
             const StridedIn in = q_arg(args, q.h);
             if (args.batched()) throw nb::value_error("Contacts.set_targets: 'q' must be one configuration (nq,)");
             args.check_finite();
             c.impl->set_targets(in.p);
           },
           "q"_a,
           "Sets every contact's target to its frame's current world pose at q (nq,), so that the Baumgarte position "
           "error starts at zero (set_contact_targets).")
      .def("__len__", [](const PyContacts& c) { return c.impl->names.size(); })
      .def("__repr__", [](const PyContacts& c) {
        std::ostringstream s;
        s << "<spatial.Contacts on '" << c.model->name << "': ";
        for (std::size_t k = 0; k < c.impl->names.size(); ++k)
          s << (k ? ", " : "") << c.impl->names[k] << " (" << c.impl->dims[k] << "D)";
        s << "; rows = " << c.impl->rows << ", damping = " << c.impl->damping << ">";
        return s.str();
      });

#define SPATIAL_PY_KW "threads"_a = 1, "check"_a = false
  m.def("constrained_forward_dynamics",
        [](PyContacts& pc, ArrayLike q, ArrayLike v, ArrayLike tau, int threads, bool check) {
          Args args(*pc.model, "constrained_forward_dynamics");
          ContactCall c;
          c.op = ContactOp::ForwardDynamics;
          c.in[0] = q_arg(args, q.h);
          c.in[1] = v_arg(args, v.h, "v");
          c.in[2] = v_arg(args, tau.h, "tau");
          const std::size_t nv = std::size_t(pc.model->nv), rows = std::size_t(pc.impl->rows);
          Output a(args, {nv}), lam(args, {rows});
          c.out[0] = strided(a.out()), c.out[1] = strided(lam.out());
          run_contacts(*pc.impl, c, args, threads, check);
          return std::make_tuple(a.array(), lam.array());
        },
        "contacts"_a, "q"_a, "v"_a, "tau"_a, nb::kw_only(), SPATIAL_PY_KW,
        "Forward dynamics with the contacts held: (a, lam), a (nv,) and lam (m,) (or (B, nv), (B, m)) solving\n"
        "  H a + C(q, v) = tau + J^T lam,   J a + Jdot v = -kd J v - kp e\n"
        "(J: the contacts' stacked rows, see Contact6D / Contact3D; e: the pose error against the targets; zero gains:\n"
        "the frames' accelerations are held at zero). lam: each contact's force (6D: [f; n about the frame's origin])\n"
        "that the ground applies to the robot, in its reference axes, in the contacts' order (contacts.offsets).\n"
        "NaN for a state where J H^-1 J^T (+ damping) is singular (redundant contacts: set damping > 0).");

  m.def("impulse_dynamics",
        [](PyContacts& pc, ArrayLike q, ArrayLike v, double restitution, int threads, bool check) {
          if (!(restitution >= 0.0 && restitution <= 1.0))
            throw nb::value_error(("impulse_dynamics: 'restitution' must be in [0, 1], not " +
                                   std::to_string(restitution)).c_str());
          Args args(*pc.model, "impulse_dynamics");
          ContactCall c;
          c.op = ContactOp::Impulse;
          c.restitution = restitution;
          c.in[0] = q_arg(args, q.h);
          c.in[1] = v_arg(args, v.h, "v");
          const std::size_t nv = std::size_t(pc.model->nv), rows = std::size_t(pc.impl->rows);
          Output va(args, {nv}), imp(args, {rows});
          c.out[0] = strided(va.out()), c.out[1] = strided(imp.out());
          run_contacts(*pc.impl, c, args, threads, check);
          return std::make_tuple(va.array(), imp.array());
        },
        "contacts"_a, "q"_a, "v"_a, "restitution"_a = 0.0, nb::kw_only(), SPATIAL_PY_KW,
        "An impact at the contacts (q does not change): (v_after, impulses), (nv,) and (m,) (or batched), with\n"
        "  H (v_after - v) = J^T impulses,   J v_after = -restitution J v\n"
        "(restitution in [0, 1]; 0: inelastic, the contacts stop). impulses [N s, N m s]: as lam of\n"
        "constrained_forward_dynamics (per contact, its reference axes). The kinetic energy does not grow.\n"
        "NaN for a state where J H^-1 J^T (+ damping) is singular.");

  m.def("contact_inverse_dynamics",
        [](PyContacts& pc, ArrayLike q, ArrayLike v, ArrayLike a, int threads, bool check) {
          if (!pc.model->floating)
            throw nb::value_error(("contact_inverse_dynamics: the model '" + pc.model->name +
                                   "' has a fixed base; whole-body inverse dynamics with contacts needs a floating "
                                   "base (load_urdf(..., floating=True), hoap3_floating())").c_str());
          Args args(*pc.model, "contact_inverse_dynamics");
          ContactCall c;
          c.op = ContactOp::InverseDynamics;
          c.in[0] = q_arg(args, q.h);
          c.in[1] = v_arg(args, v.h, "v");
          c.in[2] = v_arg(args, a.h, "a");
          const std::size_t nv = std::size_t(pc.model->nv), rows = std::size_t(pc.impl->rows);
          Output tau(args, {nv}), lam(args, {rows});
          Flags ok(args);
          c.out[0] = strided(tau.out()), c.out[1] = strided(lam.out());
          c.flag = ok.data;
          run_contacts(*pc.impl, c, args, threads, check);
          return std::make_tuple(tau.array(), lam.array(), ok.result(args));
        },
        "contacts"_a, "q"_a, "v"_a, "a"_a, nb::kw_only(), SPATIAL_PY_KW,
        "Whole-body inverse dynamics of a floating base with contacts: (tau, lam, ok), tau (nv,), lam (m,), ok a\n"
        "bool (or (B, nv), (B, m), (B,)). rnea(q, v, a) = tau + J^T lam, with tau[:6] = 0 when ok: the contacts\n"
        "supply the whole root wrench. The split between contacts: each 6D contact's wrench a non-negative\n"
        "combination of forces at its sole's corners inside the friction pyramid (Contact6D's sole and friction), a\n"
        "3D contact's inside the pyramid about the world's +z; among those, the least sum of squared generator\n"
        "weights. ok is False when no such split exists (the ZMP outside the support polygon, a pulling contact, too\n"
        "much friction needed): tau[:6] is then the part of the root wrench the contacts leave missing.\n"
        "lam: per contact, its reference axes, what the ground applies to the robot. Floating base only.");

  m.def("contact_jacobian",
        [](PyContacts& pc, ArrayLike q, int threads, bool check) {
          Args args(*pc.model, "contact_jacobian");
          ContactCall c;
          c.op = ContactOp::Jacobian;
          c.in[0] = q_arg(args, q.h);
          Output J(args, {std::size_t(pc.impl->rows), std::size_t(pc.model->nv)});
          c.out[0] = strided(J.out());
          run_contacts(*pc.impl, c, args, threads, check);
          return J.array();
        },
        "contacts"_a, "q"_a, nb::kw_only(), SPATIAL_PY_KW,
        "The contacts' constraint Jacobian J (m, nv) (or (B, m, nv)): per contact, 6D: the rows of\n"
        "frame_jacobian(reference='local') (linear first, the frame's axes); 3D: the linear rows of\n"
        "frame_jacobian(reference='local_world_aligned') (world axes), whatever the contact's reference.");

  m.def("contact_wrench",
        [](PyContacts& pc, ArrayLike q, ArrayLike lam, int threads, bool check) {
          Args args(*pc.model, "contact_wrench");
          ContactCall c;
          c.op = ContactOp::Wrench;
          c.in[0] = q_arg(args, q.h);
          c.in[1] = lambda_arg(args, pc, lam.h, "contact_wrench", "lam");
          Output w(args, {6});
          c.out[0] = strided(w.out());
          run_contacts(*pc.impl, c, args, threads, check);
          return w.array();
        },
        "contacts"_a, "q"_a, "lam"_a, nb::kw_only(), SPATIAL_PY_KW,
        "The sum of the contact forces lam (m,) at q (as returned by constrained_forward_dynamics or\n"
        "contact_inverse_dynamics): [fx fy fz nx ny nz] (6,) (or (B, 6)), world axes, moment about the world origin\n"
        "(fixed base: the base frame).");

  m.def("center_of_pressure",
        [](PyContacts& pc, ArrayLike q, ArrayLike lam, double height, int threads, bool check) {
          Args args(*pc.model, "center_of_pressure");
          ContactCall c;
          c.op = ContactOp::CenterOfPressure;
          c.height = height;
          c.in[0] = q_arg(args, q.h);
          c.in[1] = lambda_arg(args, pc, lam.h, "center_of_pressure", "lam");
          Output p(args, {3});
          c.out[0] = strided(p.out());
          run_contacts(*pc.impl, c, args, threads, check);
          return p.array();
        },
        "contacts"_a, "q"_a, "lam"_a, "height"_a = 0.0, nb::kw_only(), SPATIAL_PY_KW,
        "The centre of pressure (3,) (or (B, 3)) of the contact forces lam (m,) at q on the plane z = height (world;\n"
        "fixed base: base frame): the point where the moment of contact_wrench has no horizontal component,\n"
        "((h fx - ny) / fz, (nx + h fy) / fz, h). NaN when fz <= 0 (nothing pushes the robot up).");

  m.def("multibody_zmp",
        [](const ModelBase& model, ArrayLike q, ArrayLike v, ArrayLike a, double height, PyData* data, int threads,
           bool check) {
          Args args(model, "multibody_zmp");
          Call c;
          c.op = Op::MultibodyZmp;
          c.height = height;
          c.in[0] = args.vector(q.h, "q", model.nq, "nq");
          c.in[1] = args.vector(v.h, "v", model.nv, "nv");
          c.in[2] = args.vector(a.h, "a", model.nv, "nv");
          Output p(args, {3});
          c.out[0] = p.out();
          execute(model, c, args, data, threads, check);  // the model's own workspace, as rnea
          return p.array();
        },
        "model"_a, "q"_a, "v"_a, "a"_a, "height"_a = 0.0, nb::kw_only(), "data"_a.none() = nb::none(), SPATIAL_PY_KW,
        "The zero-moment point (3,) (or (B, 3)) of the motion (q, v, a) on the plane z = height: where the ground\n"
        "wrench the motion needs (RNEA's root wrench, gravity included) has no horizontal moment. Floating base:\n"
        "world coordinates; fixed base: the base frame (the base's reaction on the moving bodies). NaN when that\n"
        "wrench does not push up. With contacts as the only external forces it equals center_of_pressure.");
#undef SPATIAL_PY_KW
}

}  // namespace spatial::python
