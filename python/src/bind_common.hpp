#pragma once
/// \file bind_common.hpp
/// What every binding source shares: the stub-only argument and result types, the conversion of arguments to
/// C-contiguous float64 NumPy arrays (NumPy's C API: no copy when an argument already is one), the shape checks
/// with their error messages, fresh result arrays, and the call of an engine on the right workspace (without the
/// GIL for batches, on `threads` threads).

#include "engine.hpp"

#include <nanobind/nanobind.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/shared_ptr.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

// One NumPy C-API table for the whole extension: module.cpp imports it (SPATIAL_PY_IMPORT_ARRAY), the other
// sources use it.
#define PY_ARRAY_UNIQUE_SYMBOL spatial_python_ARRAY_API
#ifndef SPATIAL_PY_IMPORT_ARRAY
#define NO_IMPORT_ARRAY
#endif
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>
#include <type_traits>
#include <vector>

namespace nb = nanobind;
using namespace nb::literals;

/// Argument and result types that only name themselves in the generated stubs (_spatial.pyi): array arguments are
/// converted by to_array() below, results are the NumPy arrays made by Output.
struct ArrayLike {
  nb::handle h;
};
struct NDArray {
  nb::object o;
};
struct FloatOrArray {
  nb::object o;
};
struct FrameArg {
  nb::handle h;
};
namespace nanobind::detail {
template <>
struct type_caster<ArrayLike> {
  NB_TYPE_CASTER(ArrayLike, const_name("numpy.typing.ArrayLike"))
  bool from_python(handle src, uint8_t, cleanup_list*) noexcept {
    value.h = src;
    return true;
  }
};
template <>
struct type_caster<NDArray> {
  NB_TYPE_CASTER(NDArray, const_name("numpy.typing.NDArray[numpy.float64]"))
  static handle from_cpp(const NDArray& v, rv_policy, cleanup_list*) noexcept { return v.o.inc_ref(); }
};
template <>
struct type_caster<FloatOrArray> {
  NB_TYPE_CASTER(FloatOrArray, const_name("float | numpy.typing.NDArray[numpy.float64]"))
  static handle from_cpp(const FloatOrArray& v, rv_policy, cleanup_list*) noexcept { return v.o.inc_ref(); }
};
template <>
struct type_caster<FrameArg> {
  NB_TYPE_CASTER(FrameArg, const_name("str | int"))
  bool from_python(handle src, uint8_t, cleanup_list*) noexcept {
    value.h = src;
    return true;
  }
};
}  // namespace nanobind::detail

namespace spatial::python {


/// A private workspace for one model (Python's `Data`): pass it as `data=` to keep a thread's calls off the model's
/// own workspace.
struct PyData {
  std::shared_ptr<ModelBase> model;
  std::unique_ptr<Workspace> ws;
  std::mutex lock;
};

/// An input array: a C-contiguous, aligned float64 NumPy array (the argument itself when it is one; a converted
/// copy otherwise), held for the duration of the call.
struct Array {
  nb::object obj;
  PyArrayObject* arr() const { return reinterpret_cast<PyArrayObject*>(obj.ptr()); }
  int ndim() const { return PyArray_NDIM(arr()); }
  std::size_t shape(int k) const { return std::size_t(PyArray_DIM(arr(), k)); }
  std::size_t size() const { return std::size_t(PyArray_SIZE(arr())); }
  const double* data() const { return static_cast<const double*>(PyArray_DATA(arr())); }
};

inline std::string shape_str(const Array& a) {
  std::ostringstream s;
  s << '(';
  for (int k = 0; k < a.ndim(); ++k) s << (k ? ", " : "") << a.shape(k);
  s << (a.ndim() == 1 ? ",)" : ")");
  return s.str();
}

/// Converts an argument to a C-contiguous float64 array: no copy when it already is one; other real arrays and
/// array-likes (lists, float32, integers, Fortran order, strided views) are converted by NumPy with its "safe"
/// casting rule, so complex numbers, strings and objects are refused with a TypeError naming the argument.
inline Array to_array(nb::handle h, const char* fn, const char* arg) {
  PyObject* o = h.ptr();
  if (PyArray_Check(o)) {
    auto* a = reinterpret_cast<PyArrayObject*>(o);
    if (PyArray_TYPE(a) == NPY_DOUBLE && PyArray_IS_C_CONTIGUOUS(a) && PyArray_ISALIGNED(a) && PyArray_ISNOTSWAPPED(a))
      return {nb::borrow(h)};
  }
  PyObject* c = PyArray_FromAny(o, PyArray_DescrFromType(NPY_DOUBLE), 0, 0,
                                NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED, nullptr);
  if (!c) {
    nb::python_error e;  // takes NumPy's error
    throw nb::type_error((std::string(fn) + ": argument '" + arg +
                          "' must be an array of real numbers, convertible to float64 (" + e.what() + ")").c_str());
  }
  return {nb::steal(c)};
}

/// The arguments of one call: their arrays and the batch size they agree on.
class Args {
 public:
  Args(const ModelBase& m, const char* fn) : m_(m), fn_(fn) {}

  /// A per-state vector of `n` entries ((n,) or (B, n)); `what` names the size in errors ("nq", "nv").
  spatial::python::In vector(nb::handle h, const char* arg, int n, const char* what) {
    Array a = to_array(h, fn_, arg);
    const bool ok = (a.ndim() == 1 && a.shape(0) == std::size_t(n)) || (a.ndim() == 2 && a.shape(1) == std::size_t(n));
    if (!ok) {
      std::ostringstream s;
      s << fn_ << ": argument '" << arg << "' has shape " << shape_str(a) << "; the model '" << m_.name
        << "' has " << what << " = " << n << ", so expected (" << n << ",) or (B, " << n << ")";
      throw nb::value_error(s.str().c_str());
    }
    const bool batch = a.ndim() == 2;
    return keep(std::move(a), arg, batch, n);
  }
  /// Per-body wrenches: (nf, 6) or (B, nf, 6).
  spatial::python::In forces(nb::handle h, const char* arg, int nf) {
    Array a = to_array(h, fn_, arg);
    const bool ok = (a.ndim() == 2 || a.ndim() == 3) && a.shape(a.ndim() - 2) == std::size_t(nf) &&
                    a.shape(a.ndim() - 1) == 6;
    if (!ok) {
      std::ostringstream s;
      s << fn_ << ": argument '" << arg << "' has shape " << shape_str(a) << "; expected (" << nf << ", 6) or (B, "
        << nf << ", 6): one wrench [fx fy fz nx ny nz] per " << (m_.floating ? "body, the root first" : "body");
      throw nb::value_error(s.str().c_str());
    }
    const bool batch = a.ndim() == 3;
    return keep(std::move(a), arg, batch, 6 * nf);
  }

  bool batched() const { return batch_ >= 0; }
  const ModelBase& model() const { return m_; }
  std::ptrdiff_t count() const { return batch_ >= 0 ? batch_ : 1; }

  /// check=True: every entry finite, else ValueError naming the argument, state and entry.
  void check_finite() const {
    for (std::size_t j = 0; j < nkept_; ++j) {
      const Kept& k = kept_[j];
      const double* p = k.array.data();
      const std::size_t size = k.array.size();
      for (std::size_t i = 0; i < size; ++i) {
        if (std::isfinite(p[i])) continue;
        std::ostringstream s;
        s << fn_ << ": argument '" << k.name << "' has a non-finite entry (" << p[i] << ")";
        if (k.batched) s << " in state " << i / std::size_t(k.width) << ",";
        s << " at index " << i % std::size_t(k.width);
        throw nb::value_error(s.str().c_str());
      }
    }
  }

 private:
  struct Kept {
    Array array;
    const char* name = nullptr;
    bool batched = false;
    int width = 1;
  };
  spatial::python::In keep(Array a, const char* arg, bool batched, int width) {
    if (batched) {
      const auto b = static_cast<std::ptrdiff_t>(a.shape(0));
      if (batch_ >= 0 && b != batch_) {
        std::ostringstream s;
        s << fn_ << ": argument '" << arg << "' has " << b << " states, an earlier argument " << batch_;
        throw nb::value_error(s.str().c_str());
      }
      batch_ = b;
    }
    spatial::python::In in{a.data(), batched ? std::ptrdiff_t(width) : 0};
    kept_[nkept_++] = {std::move(a), arg, batched, width};
    return in;
  }
  const ModelBase& m_;
  const char* fn_;
  std::ptrdiff_t batch_ = -1;
  Kept kept_[4];
  std::size_t nkept_ = 0;
};

/// A fresh NumPy array of `nd` dimensions `shape` and elements T (double: float64, bool: NumPy's bool), and a
/// pointer to its data.
template <class T>
std::pair<nb::object, T*> new_array(int nd, const npy_intp* shape) {
  static_assert(std::is_same_v<T, double> || std::is_same_v<T, bool>, "new_array: float64 or bool");
  constexpr int type = std::is_same_v<T, double> ? NPY_DOUBLE : NPY_BOOL;  // (a macro argument cannot hold T's comma)
  PyObject* a = PyArray_SimpleNew(nd, const_cast<npy_intp*>(shape), type);
  if (!a) throw nb::python_error();
  return {nb::steal(a), static_cast<T*>(PyArray_DATA(reinterpret_cast<PyArrayObject*>(a)))};
}
template <class T>
std::pair<nb::object, T*> new_array(std::initializer_list<npy_intp> shape) {
  return new_array<T>(int(shape.size()), shape.begin());
}

/// A fresh float64 NumPy array of shape (B, dims...) or (dims...).
struct Output {
  Output(const Args& args, std::initializer_list<std::size_t> dims) {
    npy_intp shape[4];
    int nd = 0;
    if (args.batched()) shape[nd++] = npy_intp(args.count());
    per_state = 1;
    for (std::size_t d : dims) shape[nd++] = npy_intp(d), per_state *= std::ptrdiff_t(d);
    std::tie(obj, data) = new_array<double>(nd, shape);
  }
  spatial::python::Out out() const { return {data, per_state}; }
  NDArray array() const { return {obj}; }
  /// A scalar per state: a Python float for one state.
  FloatOrArray scalar(const Args& args) const { return {args.batched() ? obj : nb::cast(data[0])}; }

  nb::object obj;
  double* data = nullptr;
  std::ptrdiff_t per_state = 1;
};

inline int thread_count(int threads) {
  if (threads < 0) throw nb::value_error("threads must be >= 0 (0: all cores)");
  if (threads == 0) return std::max(1, int(std::thread::hardware_concurrency()));
  return threads;
}

/// Runs a call on the right workspace, without the GIL for batches.
inline void execute(const ModelBase& m, Call& call, const Args& args, PyData* data, int threads, bool check) {
  if (check) args.check_finite();
  call.count = args.count();
  const int t = thread_count(threads);
  auto go = [&](Workspace& ws) {
    if (args.batched()) {
      nb::gil_scoped_release release;
      m.run(call, ws, t);
    } else {
      m.run(call, ws, 1);
    }
  };
  if (data) {
    if (data->model.get() != &m) throw nb::value_error("data: this Data belongs to another model");
    std::unique_lock<std::mutex> lock(data->lock, std::try_to_lock);
    if (!lock.owns_lock()) throw nb::value_error("data: this Data is in use by another thread");
    return go(*data->ws);
  }
  std::unique_lock<std::mutex> lock(m.default_lock, std::try_to_lock);
  if (lock.owns_lock()) return go(*m.default_ws);
  std::unique_ptr<Workspace> own = m.workspace();  // the model's workspace is busy in another thread
  go(*own);
}

inline std::string name_error(const char* what, const std::string& name, const std::vector<std::string>& names) {
  return std::string("unknown ") + what + " '" + name + "'" + spatial::detail::did_you_mean(name, names);
}

inline int index_of(const std::vector<std::string>& names, const std::string& name) {
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return int(k);
  return -1;
}

/// A frame or body given by name (frames first, then bodies) or by frame index.
inline void resolve_target(const ModelBase& m, nb::handle frame, const char* fn, Call& c) {
  if (nb::isinstance<nb::str>(frame)) {
    const std::string name = nb::cast<std::string>(frame);
    if (int k = index_of(m.frame_names, name); k >= 0) {
      c.target = k, c.target_is_body = false;
      return;
    }
    if (int k = index_of(m.body_names, name); k >= 0) {
      c.target = k, c.target_is_body = true;
      return;
    }
    std::vector<std::string> all = m.frame_names;
    all.insert(all.end(), m.body_names.begin(), m.body_names.end());
    throw nb::key_error((std::string(fn) + ": " + name_error("frame or body", name, all)).c_str());
  }
  int k = 0;
  if (!nb::try_cast<int>(frame, k) || k < 0 || k >= int(m.frame_names.size()))
    throw nb::value_error((std::string(fn) + ": 'frame' must be a frame or body name, or a frame index in [0, " +
                           std::to_string(m.frame_names.size()) + ")").c_str());
  c.target = k, c.target_is_body = false;
}

inline spatial::ReferenceFrame reference_of(const std::string& r, const char* fn) {
  if (r == "local") return spatial::ReferenceFrame::Local;
  if (r == "world") return spatial::ReferenceFrame::World;
  if (r == "local_world_aligned") return spatial::ReferenceFrame::LocalWorldAligned;
  throw nb::value_error((std::string(fn) + ": reference '" + r +
                         "' is not one of 'local', 'world', 'local_world_aligned'").c_str());
}

}  // namespace spatial::python
