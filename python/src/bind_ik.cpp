/// \file bind_ik.cpp
/// Inverse kinematics from Python: `spatial._IkSolver`, wrapped by `spatial.IkSolver` (spatial/__init__.py), which
/// resolves frame names and default limits and builds the status objects.

#include "bind_common.hpp"

namespace spatial::python {

namespace {

/// A solver and its model; the lock keeps two Python threads (in a batch without the GIL) off one solver.
struct PyIk {
  std::shared_ptr<ModelBase> model;
  std::unique_ptr<IkBase> ik;
  std::mutex lock;
};

IkTaskSpec task_spec(nb::handle t, std::size_t k) {
  IkTaskSpec s;
  const std::string where = "IkSolver: task " + std::to_string(k);
  const std::string kind = nb::cast<std::string>(t.attr("kind"));
  if (kind == "position") s.kind = IkTaskKind::Position;
  else if (kind == "orientation") s.kind = IkTaskKind::Orientation;
  else if (kind == "pose") s.kind = IkTaskKind::Pose;
  else if (kind == "center_of_mass") s.kind = IkTaskKind::CenterOfMass;
  else throw nb::value_error((where + ": unknown kind '" + kind + "'").c_str());
  s.frame = nb::cast<int>(t.attr("frame"));
  const auto copy = [&](const char* name, double* out, std::size_t n) {
    Array a = to_array(t.attr(name), where.c_str(), name);
    if (a.size() != n)
      throw nb::value_error((where + ": '" + name + "' has " + std::to_string(a.size()) + " entries, expected " +
                             std::to_string(n)).c_str());
    std::copy(a.data(), a.data() + n, out);
  };
  copy("position", s.position, 3);
  copy("rotation", s.rotation, 9);
  copy("axes", s.axes, 6);
  s.weight = nb::cast<double>(t.attr("weight"));
  return s;
}

std::vector<double> doubles(nb::handle h, const char* arg) {
  if (h.is_none()) return {};
  Array a = to_array(h, "IkSolver", arg);
  return std::vector<double>(a.data(), a.data() + a.size());
}

}  // namespace

void bind_ik(nb::module_& m) {
  nb::class_<PyIk>(m, "_IkSolver")
      .def("__init__",
           [](PyIk* self, std::shared_ptr<ModelBase> model, nb::list tasks, int max_iterations, double tolerance,
              double step_tolerance, double damping, bool adaptive, nb::handle lower, nb::handle upper,
              std::vector<int> active) {
             std::vector<IkTaskSpec> specs;
             for (std::size_t k = 0; k < tasks.size(); ++k) specs.push_back(task_spec(tasks[k], k));
             IkOptionsSpec o;
             o.max_iterations = max_iterations, o.tolerance = tolerance, o.step_tolerance = step_tolerance;
             o.damping = damping, o.adaptive = adaptive;
             o.lower = doubles(lower, "lower"), o.upper = doubles(upper, "upper"), o.active = std::move(active);
             new (self) PyIk();
             self->ik = model->make_ik(specs, o);  // std::invalid_argument (bad frame, limits) -> ValueError
             self->model = std::move(model);
           },
           "model"_a, "tasks"_a, "max_iterations"_a, "tolerance"_a, "step_tolerance"_a, "damping"_a, "adaptive"_a,
           "lower"_a.none(), "upper"_a.none(), "active"_a)
      .def_prop_ro("rows", [](const PyIk& s) { return s.ik->rows(); })
      .def("set_task", [](PyIk& s, int i, nb::handle t) {
        if (i < 0 || i >= s.ik->tasks()) throw nb::index_error("IkSolver: no such task");
        std::unique_lock<std::mutex> lock(s.lock, std::try_to_lock);
        if (!lock.owns_lock()) throw nb::value_error("IkSolver: in use by another thread");
        s.ik->set_task(i, task_spec(t, std::size_t(i)));
      })
      .def("residual", [](PyIk& s, ArrayLike q) {
        Args args(*s.model, "IkSolver.residual");
        const In in = args.vector(q.h, "q", s.model->nq, "nq");
        if (args.batched()) throw nb::value_error("IkSolver.residual: one configuration (nq,) at a time");
        Output r(args, {std::size_t(s.ik->rows())});
        std::unique_lock<std::mutex> lock(s.lock, std::try_to_lock);
        if (!lock.owns_lock()) throw nb::value_error("IkSolver: in use by another thread");
        const double norm = s.ik->residual(in.p, r.data);
        return std::make_pair(norm, r.array());
      })
      .def("solve", [](PyIk& s, ArrayLike q0, int threads) {
        Args args(*s.model, "IkSolver.solve");
        const In in = args.vector(q0.h, "q0", s.model->nq, "nq");
        Output q(args, {std::size_t(s.model->nq)});
        std::vector<IkResult> st(std::size_t(args.count()));
        const int t = thread_count(threads);
        {
          std::unique_lock<std::mutex> lock(s.lock, std::try_to_lock);
          if (!lock.owns_lock()) throw nb::value_error("IkSolver: in use by another thread");
          nb::gil_scoped_release release;
          s.ik->solve(in.p, in.stride, q.data, st.data(), args.count(), t);
        }
        nb::list status;
        for (const IkResult& r : st)
          status.append(nb::make_tuple(r.converged, ik_reason_name(r.reason), r.iterations, r.accepted, r.residual,
                                       r.damping));
        return std::make_pair(q.array(), status);
      }, "q0"_a, "threads"_a = 1);
}

}  // namespace spatial::python
