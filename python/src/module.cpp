/// \file module.cpp
/// The extension module `spatial._spatial` (nanobind): models, array conversion and checks, and one function per
/// algorithm. Every algorithm takes one state ((n,) arrays) or a batch ((B, n) arrays; an unbatched argument is
/// shared by all states), returns fresh NumPy arrays, and runs batches without the GIL, on `threads` threads.

#define SPATIAL_PY_IMPORT_ARRAY  // this source imports NumPy's C API (bind_common.hpp)
#include "bind_common.hpp"


namespace spatial::python {
/// bind_contacts.cpp: contact dynamics, impulses, whole-body inverse dynamics with contacts, ZMP and CoP.
void bind_contacts(nb::module_& m);
/// bind_ik.cpp: inverse kinematics.
void bind_ik(nb::module_& m);
/// bind_walking.cpp: the walking pattern generator and its closed-loop simulation.
void bind_walking(nb::module_& m);
/// bind_batch.cpp: many states per call on SIMD lanes (spatial.Batch).
void bind_batch(nb::module_& m);
}  // namespace spatial::python

using namespace spatial::python;

namespace {

NDArray as_numpy(const std::vector<double>& x) {
  auto [a, p] = new_array<double>({npy_intp(x.size())});
  std::copy(x.begin(), x.end(), p);
  return {a};
}

spatial::urdf_io::LoadOptions load_options(std::optional<std::string> root, bool floating, nb::handle lock,
                                           std::optional<std::string> subtree, nb::handle gravity,
                                           bool strict_inertia, bool axis_aligned) {
  spatial::urdf_io::LoadOptions opt;
  if (root) opt.root = *root;
  if (subtree) opt.subtree = *subtree;
  opt.floating = floating;
  opt.strict_inertia = strict_inertia;
  opt.axis_aligned = axis_aligned;
  if (!lock.is_none()) {
    if (!nb::isinstance<nb::dict>(lock)) throw nb::type_error("load_urdf: 'lock' must be a dict {joint name: position}");
    for (auto [k, v] : nb::borrow<nb::dict>(lock)) opt.locked.emplace_back(nb::cast<std::string>(k), nb::cast<double>(v));
  }
  if (!gravity.is_none()) {
    Array g = to_array(gravity, "load_urdf", "gravity");
    if (g.ndim() != 1 || g.shape(0) != 3) throw nb::value_error("load_urdf: 'gravity' must have 3 entries");
    opt.gravity = Eigen::Vector3d(g.data()[0], g.data()[1], g.data()[2]);
  }
  return opt;
}

std::string stem(const std::string& path) {
  std::string s = path.substr(path.find_last_of("/\\") == std::string::npos ? 0 : path.find_last_of("/\\") + 1);
  const auto dot = s.rfind('.');
  return dot == std::string::npos ? s : s.substr(0, dot);
}

}  // namespace

NB_MODULE(_spatial, m) {
  if (_import_array() < 0) throw nb::python_error();
  m.doc() = "spatial: rigid-body dynamics of kinematic trees (Featherstone's spatial algebra), C++ core.";
  nb::exception<spatial::ModelError>(m, "ModelError", PyExc_ValueError);

  nb::class_<ModelBase>(m, "Model",
                        "A robot model: a tree of one-DoF joints on a fixed or free-flying base. Build one with "
                        "load_urdf() or a generated model (hoap3_stance_right(), ...).")
      .def_ro("name", &ModelBase::name, "The model's name (the URDF file's stem or the generated model's name).")
      .def_ro("root", &ModelBase::root, "The link the tree is rooted at (the base, or the free-flying root).")
      .def_ro("floating", &ModelBase::floating,
              "True for a free-flying base: q = [x y z qx qy qz qw, joints], v = [v_lin, omega (root frame), joint "
              "rates].")
      .def_ro("compile_time", &ModelBase::compile_time,
              "True for a generated model (compile-time tree: the fastest code paths).")
      .def_ro("nq", &ModelBase::nq, "Size of q (njoints, + 7 for a floating base).")
      .def_ro("nv", &ModelBase::nv, "Size of v, a and tau (njoints, + 6 for a floating base).")
      .def_ro("njoints", &ModelBase::njoints, "Number of one-DoF joints (= moving bodies) of the tree.")
      .def_ro("joint_names", &ModelBase::joint_names, "URDF joint names in model order.")
      .def_ro("body_names", &ModelBase::body_names, "Body names (the URDF link each joint moves), model order.")
      .def_ro("frame_names", &ModelBase::frame_names,
              "Fixed frames: links merged into a body or the base (soles, hands, ...).")
      .def_ro("source_joints", &ModelBase::source_joints,
              "A reduced model (lock_joints, keep_joints, keep_branches): the index of each of its joints in the "
              "model it was reduced from; empty otherwise.")
      .def_ro("warnings", &ModelBase::warnings, "What the URDF loader accepted with a warning (one per link).")
      .def_prop_ro("lower", [](const ModelBase& b) { return as_numpy(b.lower); }, "Lower position limits (-inf: none).")
      .def_prop_ro("upper", [](const ModelBase& b) { return as_numpy(b.upper); }, "Upper position limits (inf: none).")
      .def_prop_ro("effort", [](const ModelBase& b) { return as_numpy(b.effort); }, "Effort limits [N m or N] (0: unknown).")
      .def_prop_ro("velocity", [](const ModelBase& b) { return as_numpy(b.velocity); }, "Velocity limits (0: unknown).")
      .def_prop_ro("gravity", [](const ModelBase& b) { return as_numpy({b.gravity[0], b.gravity[1], b.gravity[2]}); },
                   "Gravity [m/s^2]: base coordinates (fixed base), world coordinates (floating base).")
      .def_ro("total_mass", &ModelBase::total_mass, "Mass of the whole robot, base included [kg].")
      .def("joint_index",
           [](const ModelBase& b, const std::string& n) {
             const int k = index_of(b.joint_names, n);
             if (k < 0) throw nb::key_error(name_error("joint", n, b.joint_names).c_str());
             return k;
           },
           "name"_a, "Model order of a joint (its entry in q is nq - njoints + index).")
      .def("body_index",
           [](const ModelBase& b, const std::string& n) {
             const int k = index_of(b.body_names, n);
             if (k < 0) throw nb::key_error(name_error("body", n, b.body_names).c_str());
             return k;
           },
           "name"_a)
      .def("frame_index",
           [](const ModelBase& b, const std::string& n) {
             const int k = index_of(b.frame_names, n);
             if (k < 0) throw nb::key_error(name_error("frame", n, b.frame_names).c_str());
             return k;
           },
           "name"_a)
      .def("data",
           [](std::shared_ptr<ModelBase> b) {
             auto d = std::make_unique<PyData>();
             d->ws = b->workspace();
             d->model = std::move(b);
             return d.release();
           },
           nb::rv_policy::take_ownership,
           "A private workspace for this model: pass it as data= to use it instead of the model's own.")
      .def("__repr__", [](const ModelBase& b) {
        std::ostringstream s;
        s << "<spatial.Model '" << b.name << "': " << (b.floating ? "floating" : "fixed") << " base, " << b.njoints
          << " joints, nq = " << b.nq << ", nv = " << b.nv << (b.compile_time ? ", compile-time tree" : "") << ">";
        return s.str();
      });

  nb::class_<PyData>(m, "Data", "A model's private workspace (Model.data()).")
      .def_prop_ro("model", [](const PyData& d) { return d.model; });

  m.def("_load_urdf",
        [](const std::string& path, std::optional<std::string> root, bool floating, nb::handle lock,
           std::optional<std::string> subtree, nb::handle gravity, bool strict_inertia, bool axis_aligned) {
          auto opt = load_options(root, floating, lock, subtree, gravity, strict_inertia, axis_aligned);
          spatial::urdf_io::LoadedModel loaded = spatial::urdf_io::load_file(path, opt);
          return spatial::python::make_runtime_model(loaded, stem(path));
        },
        "path"_a, "root"_a.none(), "floating"_a, "lock"_a.none(), "subtree"_a.none(), "gravity"_a.none(),
        "strict_inertia"_a, "axis_aligned"_a);
  m.def("_load_urdf_string",
        [](const std::string& xml, const std::string& name, std::optional<std::string> root, bool floating,
           nb::handle lock, std::optional<std::string> subtree, nb::handle gravity, bool strict_inertia,
           bool axis_aligned) {
          auto opt = load_options(root, floating, lock, subtree, gravity, strict_inertia, axis_aligned);
          spatial::urdf_io::LoadedModel loaded = spatial::urdf_io::load_string(xml, opt, name);
          return spatial::python::make_runtime_model(loaded, name);
        },
        "xml"_a, "name"_a, "root"_a.none(), "floating"_a, "lock"_a.none(), "subtree"_a.none(), "gravity"_a.none(),
        "strict_inertia"_a, "axis_aligned"_a);

  m.def("hoap3_stance_right", &spatial::python::make_hoap3_stance_right,
        "The HOAP-3 standing on its right sole (21 joints; head and wrists locked), compile-time tree.");
  m.def("hoap3_stance_left", &spatial::python::make_hoap3_stance_left,
        "The HOAP-3 standing on its left sole (21 joints; head and wrists locked), compile-time tree.");
  m.def("hoap3_torso", &spatial::python::make_hoap3_torso,
        "The HOAP-3's torso and arms (8 joints, the chest fixed), compile-time tree.");
  m.def("hoap3_double_pendulum", &spatial::python::make_hoap3_double_pendulum,
        "The double inverted pendulum of the reference study (2 joints), compile-time tree.");
  m.def("hoap3_floating", &spatial::python::make_hoap3_floating,
        "The HOAP-3 on a free-flyer at the pelvis + the 21 joints of the stance models, compile-time tree.");

  // ---- model reduction (reduce.hpp) ----------------------------------------------------------------------------
  m.def("lock_joints",
        [](const ModelBase& b, nb::dict locks) {
          std::vector<std::string> names;
          std::vector<double> positions;
          for (auto [k, v] : locks) names.push_back(nb::cast<std::string>(k)), positions.push_back(nb::cast<double>(v));
          return b.reduce(0, names, positions, nullptr);
        },
        "model"_a, "locks"_a,
        "A run-time model with the joints {name: position} held there, their bodies merged exactly into their moving "
        "parents (fixed base only). Its source_joints map its joints to the model's.");
  const auto bind_keep = [&m](const char* fn, int kind, const char* what, const char* doc) {
    m.def(fn,
          [fn, kind](const ModelBase& b, std::vector<std::string> names, ArrayLike q) {
            Args args(b, fn);
            const In in = args.vector(q.h, "q", b.nq, "nq");
            if (args.batched()) throw nb::value_error((std::string(fn) + ": one configuration q (nq,)").c_str());
            return b.reduce(kind, names, {}, in.p);
          },
          "model"_a, nb::arg(what), "q"_a, doc);
  };
  bind_keep("keep_joints", 1, "joints",
            "A run-time model with only these joints moving, every other joint held at its entry of q (fixed base).");
  bind_keep("keep_branches", 2, "bodies",
            "A run-time model with only the subtrees of these bodies moving (each body's own joint included), every "
            "other joint held at its entry of q (fixed base).");

  m.def("_neutral", [](const ModelBase& b) -> NDArray {
    std::vector<double> q(std::size_t(b.nq));
    b.neutral(q.data());
    return as_numpy(q);
  });

  // ---- algorithms ----------------------------------------------------------------------------------------------
  // Each: (model, arrays..., keywords) → fresh arrays. `fext` rows [fx fy fz nx ny nz] per body, body coordinates.
#define SPATIAL_PY_KW "data"_a.none() = nb::none(), "threads"_a = 1, "check"_a = false
  // ---- the terms of the dynamics (options.hpp's Dyn flags) ----------------------------------------------------
  nb::enum_<spatial::Dyn>(m, "Dyn", nb::is_flag(), nb::is_arithmetic(),
                          "Terms of tau = H a + C v + G - sum J^T fext that rnea, aba and forward_dynamics compute "
                          "(the C++ options.hpp flags; combine with |). Left out, a term generates no code: "
                          "rnea(..., dyn=Dyn.Gravity | Dyn.Acceleration) is H a + G and never reads v. Dyn(0): none "
                          "(rnea: -sum J^T fext; aba and forward_dynamics: H^-1 tau). Fixed-base models only "
                          "(floating: Full).")
      .value("Gravity", spatial::Dyn::Gravity, "G(q): gravity (base acceleration -g).")
      .value("Velocity", spatial::Dyn::Velocity, "Every term in v: Coriolis, centrifugal, gyroscopic.")
      .value("Acceleration", spatial::Dyn::Acceleration, "rnea: the H a term (aba, forward_dynamics: ignored).")
      .value("Full", spatial::Dyn::Full, "Gravity | Velocity | Acceleration: the default.")
      .value("Static", spatial::Dyn::Static, "Gravity alone: G(q); aba: the acceleration from rest.")
      .value("QuasiStatic", spatial::Dyn::QuasiStatic, "Gravity | Acceleration: H a + G (v = 0).")
      .value("NoGravity", spatial::Dyn::NoGravity, "Velocity | Acceleration.");

  // RNEA, ABA and forward dynamics by CRBA: (q, v, a or tau[, fext]) -> (nv,), with the terms of `dyn`. An input
  // that `dyn` does not read (v without Velocity, rnea's a without Acceleration) may be None.
  const auto bind_dynamics = [&m](const char* fn, Op op, const char* third, bool with_fext, const char* doc) {
    auto body = [fn, op, third](const ModelBase& b, ArrayLike q, ArrayLike v, ArrayLike x, ArrayLike fext,
                                spatial::Dyn dyn, PyData* data, int threads, bool check) {
      const unsigned terms = unsigned(dyn);
      const unsigned mask = op == Op::Rnea ? 7u : 3u;  // aba and forward_dynamics ignore Acceleration
      const bool partial = (terms & mask) != (7u & mask);  // a set other than Full
      if ((terms & ~7u) != 0u)
        throw nb::value_error((std::string(fn) + ": dyn = " + std::to_string(terms) +
                               " has flags other than Gravity, Velocity and Acceleration (C++'s BaseForces is not "
                               "available from Python)").c_str());
      if (!fext.h.is_none() && partial)
        throw nb::value_error((std::string(fn) + ": fext= works with dyn=Dyn.Full only (C++ has the other sets with "
                               "external forces; from Python add the forces' part, which is linear: rnea(q, v, a, "
                               "fext) - rnea(q, v, a))").c_str());
      if (b.floating && partial)
        throw nb::value_error((std::string(fn) + ": dyn= other than Dyn.Full works on fixed-base models only; '" +
                               b.name + "' has a floating base").c_str());
      Args args(b, fn);
      Call c;
      c.op = op;
      c.dyn = terms;
      // An input the terms do not read may be None: it is then a shared vector of zeros (never read).
      std::vector<double> zeros;
      const auto optional = [&](ArrayLike h, const char* name, bool read) -> In {
        if (!h.h.is_none()) return args.vector(h.h, name, b.nv, "nv");
        if (read)
          throw nb::type_error((std::string(fn) + ": argument '" + name + "' is None, but dyn includes the term that "
                                "reads it").c_str());
        zeros.assign(std::size_t(b.nv), 0.0);
        return In{zeros.data(), 0};
      };
      c.in[0] = args.vector(q.h, "q", b.nq, "nq");
      c.in[1] = optional(v, "v", (terms & unsigned(spatial::Dyn::Velocity)) != 0u);
      c.in[2] = optional(x, third, op != Op::Rnea || (terms & unsigned(spatial::Dyn::Acceleration)) != 0u);
      if (!fext.h.is_none()) c.in[3] = args.forces(fext.h, "fext", b.njoints + (b.floating ? 1 : 0));
      Output out(args, {std::size_t(b.nv)});
      c.out[0] = out.out();
      execute(b, c, args, data, threads, check);
      return out.array();
    };
    // rnea's a may be None (unread without Acceleration); aba's and forward_dynamics' tau is always read.
    if (op == Op::Rnea) {
      m.def(fn, body, "model"_a, "q"_a, "v"_a.none(), nb::arg(third).none(), "fext"_a.none() = nb::none(),
            nb::kw_only(), "dyn"_a.sig("Dyn.Full") = spatial::Dyn::Full, SPATIAL_PY_KW, doc);
    } else if (with_fext) {
      m.def(fn, body, "model"_a, "q"_a, "v"_a.none(), nb::arg(third), "fext"_a.none() = nb::none(), nb::kw_only(),
            "dyn"_a.sig("Dyn.Full") = spatial::Dyn::Full, SPATIAL_PY_KW, doc);
    } else {
      m.def(fn,
            [body](const ModelBase& b, ArrayLike q, ArrayLike v, ArrayLike x, spatial::Dyn dyn, PyData* data,
                   int threads, bool check) {
              return body(b, q, v, x, ArrayLike{nb::none()}, dyn, data, threads, check);
            },
            "model"_a, "q"_a, "v"_a.none(), nb::arg(third), nb::kw_only(), "dyn"_a.sig("Dyn.Full") = spatial::Dyn::Full,
            SPATIAL_PY_KW, doc);
    }
  };
  bind_dynamics("rnea", Op::Rnea, "a", true,
                "Inverse dynamics (RNEA): tau (nv,) or (B, nv) = H(q) a + C(q, v) - sum J^T fext, with the terms of "
                "dyn (a Dyn flag set; v or a may be None when dyn does not read them).");
  bind_dynamics("aba", Op::Aba, "tau", true,
                "Forward dynamics (ABA): a (nv,) or (B, nv), with the terms of dyn (a Dyn flag set; v may be None "
                "without Dyn.Velocity).");
  bind_dynamics("forward_dynamics", Op::ForwardDynamics, "tau", false,
                "Forward dynamics by CRBA + the tree's LTDL factorisation: a = H^-1 (tau - C), with the terms of dyn "
                "(a Dyn flag set; v may be None without Dyn.Velocity).");

  // Ops whose inputs are vectors only: described by (name, inputs (argument name, nq or nv), output shape).
  struct VecIn {
    const char* name;
    bool config;
  };
  const auto bind_vec = [&m](const char* fn, Op op, std::vector<VecIn> ins, int out_kind, const char* doc) {
    // out_kind: 0 vector nv, 1 matrix nv x nv, 2 scalar, 3 vector nq, 4 vector 3, 5 matrix 3 x nv, 6 matrix 6 x nv,
    // 7 vector 6
    auto body = [fn, op, ins, out_kind](const ModelBase& b, const std::vector<ArrayLike>& hs, PyData* data,
                                        int threads, bool check) -> nb::object {
      Args args(b, fn);
      Call c;
      c.op = op;
      for (std::size_t k = 0; k < ins.size(); ++k)
        c.in[k] = args.vector(hs[k].h, ins[k].name, ins[k].config ? b.nq : b.nv, ins[k].config ? "nq" : "nv");
      const std::size_t nv = std::size_t(b.nv);
      std::optional<Output> o;
      switch (out_kind) {
        case 0: o.emplace(args, std::initializer_list<std::size_t>{nv}); break;
        case 1: o.emplace(args, std::initializer_list<std::size_t>{nv, nv}); break;
        case 2: o.emplace(args, std::initializer_list<std::size_t>{}); break;
        case 3: o.emplace(args, std::initializer_list<std::size_t>{std::size_t(b.nq)}); break;
        case 4: o.emplace(args, std::initializer_list<std::size_t>{3}); break;
        case 5: o.emplace(args, std::initializer_list<std::size_t>{3, nv}); break;
        case 6: o.emplace(args, std::initializer_list<std::size_t>{6, nv}); break;
        default: o.emplace(args, std::initializer_list<std::size_t>{6}); break;
      }
      c.out[0] = o->out();
      execute(b, c, args, data, threads, check);
      return out_kind == 2 ? o->scalar(args).o : o->array().o;
    };
    // The result's type in the stubs: a float per state for the energies, arrays otherwise.
    const auto defs = [&](auto tag) {
      using R = typename decltype(tag)::type;
      if (ins.size() == 1) {
        m.def(fn,
              [body](const ModelBase& b, ArrayLike x, PyData* data, int threads, bool check) {
                return R{body(b, {x}, data, threads, check)};
              },
              "model"_a, nb::arg(ins[0].name), nb::kw_only(), SPATIAL_PY_KW, doc);
      } else if (ins.size() == 2) {
        m.def(fn,
              [body](const ModelBase& b, ArrayLike x, ArrayLike y, PyData* data, int threads, bool check) {
                return R{body(b, {x, y}, data, threads, check)};
              },
              "model"_a, nb::arg(ins[0].name), nb::arg(ins[1].name), nb::kw_only(), SPATIAL_PY_KW, doc);
      } else {
        m.def(fn,
              [body](const ModelBase& b, ArrayLike x, ArrayLike y, ArrayLike z, PyData* data, int threads,
                     bool check) { return R{body(b, {x, y, z}, data, threads, check)}; },
              "model"_a, nb::arg(ins[0].name), nb::arg(ins[1].name), nb::arg(ins[2].name), nb::kw_only(),
              SPATIAL_PY_KW, doc);
      }
    };
    if (out_kind == 2) defs(std::common_type<FloatOrArray>{});
    else defs(std::common_type<NDArray>{});
  };
  bind_vec("gravity", Op::Gravity, {{"q", true}}, 0, "Gravity torques G(q) = rnea(q, 0, 0): (nv,) or (B, nv).");
  bind_vec("bias", Op::Bias, {{"q", true}, {"v", false}}, 0,
           "Bias forces C(q, v) = rnea(q, v, 0): Coriolis, centrifugal and gravity terms.");
  bind_vec("crba", Op::Crba, {{"q", true}}, 1, "Joint-space inertia H(q) (CRBA): (nv, nv), both triangles filled.");
  bind_vec("kinetic_energy", Op::KineticEnergy, {{"q", true}, {"v", false}}, 2, "1/2 v^T H v: float or (B,).");
  bind_vec("potential_energy", Op::PotentialEnergy, {{"q", true}}, 2, "-m g . c: float or (B,).");
  bind_vec("center_of_mass", Op::CenterOfMass, {{"q", true}}, 4,
           "Centre of mass (3,): fixed base: of the moving bodies, base coordinates; floating: whole robot, world.");
  bind_vec("com_jacobian", Op::ComJacobian, {{"q", true}}, 5, "CoM Jacobian (3, nv): c_dot = Jc v.");
  bind_vec("centroidal_momentum_matrix", Op::CentroidalMatrix, {{"q", true}}, 6,
           "Centroidal momentum matrix A_G (6, nv): h_G = A_G v = [linear; angular about the CoM], world axes.");
  bind_vec("centroidal_momentum", Op::CentroidalMomentum, {{"q", true}, {"v", false}}, 7,
           "Centroidal momentum h_G (6,): [linear; angular about the CoM], world axes.");
  bind_vec("difference", Op::Difference, {{"q0", true}, {"q1", true}}, 0,
           "v such that integrate(q0, v) = q1 (floating base: the SE(3) logarithm, root body frame).");
  bind_vec("normalize", Op::Normalize, {{"q", true}}, 3, "q with its quaternion normalised (a copy).");
  bind_vec("inverse_inertia", Op::InverseInertia, {{"q", true}}, 1,
           "H(q)^-1 (nv, nv) computed without forming H (ABA on unit torques), both triangles filled.");

  m.def("integrate",
        [](const ModelBase& b, ArrayLike q, ArrayLike v, double dt, PyData* data, int threads, bool check) {
          Args args(b, "integrate");
          Call c;
          c.op = Op::Integrate;
          c.dt = dt;
          c.in[0] = args.vector(q.h, "q", b.nq, "nq");
          c.in[1] = args.vector(v.h, "v", b.nv, "nv");
          Output o(args, {std::size_t(b.nq)});
          c.out[0] = o.out();
          execute(b, c, args, data, threads, check);
          return o.array();
        },
        "model"_a, "q"_a, "v"_a, "dt"_a = 1.0, nb::kw_only(), SPATIAL_PY_KW,
        "q (+) v dt on the configuration manifold (floating base: SE(3) exponential of the root's body twist).");

  m.def("frame_placement",
        [](const ModelBase& b, ArrayLike q, FrameArg frame, PyData* data, int threads, bool check) {
          Args args(b, "frame_placement");
          Call c;
          c.op = Op::FramePlacement;
          resolve_target(b, frame.h, "frame_placement", c);
          c.in[0] = args.vector(q.h, "q", b.nq, "nq");
          Output o(args, {4, 4});
          c.out[0] = o.out();
          execute(b, c, args, data, threads, check);
          return o.array();
        },
        "model"_a, "q"_a, "frame"_a, nb::kw_only(), SPATIAL_PY_KW,
        "Pose (4, 4) of a frame or body (name or frame index): [R p; 0 1], world (fixed base: base) coordinates.");
  m.def("frame_jacobian",
        [](const ModelBase& b, ArrayLike q, FrameArg frame, const std::string& reference, PyData* data,
           int threads, bool check) {
          Args args(b, "frame_jacobian");
          Call c;
          c.op = Op::FrameJacobian;
          resolve_target(b, frame.h, "frame_jacobian", c);
          c.reference = reference_of(reference, "frame_jacobian");
          c.in[0] = args.vector(q.h, "q", b.nq, "nq");
          Output o(args, {6, std::size_t(b.nv)});
          c.out[0] = o.out();
          execute(b, c, args, data, threads, check);
          return o.array();
        },
        "model"_a, "q"_a, "frame"_a, "reference"_a = "local_world_aligned", nb::kw_only(), SPATIAL_PY_KW,
        "Jacobian (6, nv) of a frame or body, rows [v_lin; omega]; reference 'local', 'world' or "
        "'local_world_aligned' (Pinocchio's LOCAL, WORLD, LOCAL_WORLD_ALIGNED).");
  m.def("frame_velocity",
        [](const ModelBase& b, ArrayLike q, ArrayLike v, FrameArg frame, const std::string& reference,
           PyData* data, int threads, bool check) {
          Args args(b, "frame_velocity");
          Call c;
          c.op = Op::FrameVelocity;
          resolve_target(b, frame.h, "frame_velocity", c);
          c.reference = reference_of(reference, "frame_velocity");
          c.in[0] = args.vector(q.h, "q", b.nq, "nq");
          c.in[1] = args.vector(v.h, "v", b.nv, "nv");
          Output o(args, {6});
          c.out[0] = o.out();
          execute(b, c, args, data, threads, check);
          return o.array();
        },
        "model"_a, "q"_a, "v"_a, "frame"_a, "reference"_a = "local_world_aligned", nb::kw_only(), SPATIAL_PY_KW,
        "Spatial velocity (6,) of a frame or body, [v_lin; omega], in the reference frame (= J v).");
  // The frame's accelerations after forward kinematics (q, v, a); a = 0 gives the drift J̇ v (kinematics.hpp).
  const auto bind_frame_acceleration = [&](const char* fn, Op op, std::size_t rows, const char* doc) {
    m.def(fn,
          [fn, op, rows](const ModelBase& b, ArrayLike q, ArrayLike v, ArrayLike a, FrameArg frame,
                         const std::string& reference, PyData* data, int threads, bool check) {
            Args args(b, fn);
            Call c;
            c.op = op;
            resolve_target(b, frame.h, fn, c);
            c.reference = reference_of(reference, fn);
            c.in[0] = args.vector(q.h, "q", b.nq, "nq");
            c.in[1] = args.vector(v.h, "v", b.nv, "nv");
            c.in[2] = args.vector(a.h, "a", b.nv, "nv");
            Output o(args, {rows});
            c.out[0] = o.out();
            execute(b, c, args, data, threads, check);
            return o.array();
          },
          "model"_a, "q"_a, "v"_a, "a"_a, "frame"_a, "reference"_a = "local_world_aligned", nb::kw_only(),
          SPATIAL_PY_KW, doc);
  };
  bind_frame_acceleration(
      "frame_acceleration", Op::FrameAcceleration, 6,
      "Spatial acceleration (6,) of a frame or body, [a_lin; omega_dot], gravity not included, in the reference "
      "frame: the time derivative of frame_velocity for 'local' and 'world'; 'local_world_aligned' rotates the "
      "'local' vector to world axes (Pinocchio's getFrameAcceleration). a = 0 gives the drift J_dot v (local, world). "
      "Not the classical acceleration of the origin: see frame_classical_acceleration.");
  bind_frame_acceleration(
      "frame_classical_acceleration", Op::FrameClassicalAcceleration, 3,
      "Classical acceleration (3,) of the frame's origin, p_ddot = a_lin + omega x v_lin, gravity not included: "
      "frame axes for 'local', world axes for 'world' and 'local_world_aligned' (both the origin's acceleration; "
      "Pinocchio's getFrameClassicalAcceleration for LOCAL and LOCAL_WORLD_ALIGNED). a = 0 gives the linear rows of "
      "frame_jacobian_time_variation('local_world_aligned') @ v.");
  m.def("frame_jacobian_time_variation",
        [](const ModelBase& b, ArrayLike q, ArrayLike v, FrameArg frame, const std::string& reference,
           PyData* data, int threads, bool check) {
          const char* fn = "frame_jacobian_time_variation";
          Args args(b, fn);
          Call c;
          c.op = Op::FrameJacobianTimeVariation;
          resolve_target(b, frame.h, fn, c);
          c.reference = reference_of(reference, fn);
          c.in[0] = args.vector(q.h, "q", b.nq, "nq");
          c.in[1] = args.vector(v.h, "v", b.nv, "nv");
          Output o(args, {6, std::size_t(b.nv)});
          c.out[0] = o.out();
          execute(b, c, args, data, threads, check);
          return o.array();
        },
        "model"_a, "q"_a, "v"_a, "frame"_a, "reference"_a = "local_world_aligned", nb::kw_only(), SPATIAL_PY_KW,
        "d/dt of frame_jacobian(q, frame, reference) along v: (6, nv), rows [v_lin; omega] (Pinocchio's "
        "getFrameJacobianTimeVariation). J_dot v is frame_acceleration(q, v, 0) for 'local' and 'world'; for "
        "'local_world_aligned' its linear rows are the classical acceleration of the origin.");
  m.def("centroidal_momentum_time_variation",
        [](const ModelBase& b, ArrayLike q, ArrayLike v, ArrayLike a, PyData* data, int threads, bool check) {
          const char* fn = "centroidal_momentum_time_variation";
          Args args(b, fn);
          Call c;
          c.op = Op::CentroidalMomentumRate;
          c.in[0] = args.vector(q.h, "q", b.nq, "nq");
          c.in[1] = args.vector(v.h, "v", b.nv, "nv");
          c.in[2] = args.vector(a.h, "a", b.nv, "nv");
          Output dh(args, {6}), drift(args, {6});
          c.out[0] = dh.out(), c.out[1] = drift.out();
          execute(b, c, args, data, threads, check);
          return std::make_tuple(dh.array(), drift.array());
        },
        "model"_a, "q"_a, "v"_a, "a"_a, nb::kw_only(), SPATIAL_PY_KW,
        "(dh_G, dA_G v), each (6,): the rate of the centroidal momentum for acceleration a and its velocity part "
        "(a = 0), [linear; angular about the CoM], world axes (fixed base: base axes), gravity not included "
        "(Pinocchio's computeCentroidalMomentumTimeVariation: data.dhg).");

  m.def("rnea_derivatives",
        [](const ModelBase& b, ArrayLike q, ArrayLike v, ArrayLike a, PyData* data, int threads, bool check) {
          Args args(b, "rnea_derivatives");
          Call c;
          c.op = Op::RneaDerivatives;
          c.in[0] = args.vector(q.h, "q", b.nq, "nq");
          c.in[1] = args.vector(v.h, "v", b.nv, "nv");
          c.in[2] = args.vector(a.h, "a", b.nv, "nv");
          const std::size_t nv = std::size_t(b.nv);
          Output dq(args, {nv, nv}), dv(args, {nv, nv});
          c.out[0] = dq.out(), c.out[1] = dv.out();
          execute(b, c, args, data, threads, check);
          return std::make_tuple(dq.array(), dv.array());
        },
        "model"_a, "q"_a, "v"_a, "a"_a, nb::kw_only(), SPATIAL_PY_KW,
        "(dtau_dq, dtau_dv), each (nv, nv); floating base: q-columns in the tangent space (Pinocchio's convention).");
  m.def("aba_derivatives",
        [](const ModelBase& b, ArrayLike q, ArrayLike v, ArrayLike tau, PyData* data, int threads, bool check) {
          Args args(b, "aba_derivatives");
          Call c;
          c.op = Op::AbaDerivatives;
          c.in[0] = args.vector(q.h, "q", b.nq, "nq");
          c.in[1] = args.vector(v.h, "v", b.nv, "nv");
          c.in[2] = args.vector(tau.h, "tau", b.nv, "nv");
          const std::size_t nv = std::size_t(b.nv);
          Output dq(args, {nv, nv}), dv(args, {nv, nv}), dt(args, {nv, nv});
          c.out[0] = dq.out(), c.out[1] = dv.out(), c.out[2] = dt.out();
          execute(b, c, args, data, threads, check);
          return std::make_tuple(dq.array(), dv.array(), dt.array());
        },
        "model"_a, "q"_a, "v"_a, "tau"_a, nb::kw_only(), SPATIAL_PY_KW,
        "(dqdd_dq, dqdd_dv, dqdd_dtau = H^-1), each (nv, nv).");
#undef SPATIAL_PY_KW

  spatial::python::bind_ik(m);
  spatial::python::bind_walking(m);
  spatial::python::bind_contacts(m);
  spatial::python::bind_batch(m);
}
