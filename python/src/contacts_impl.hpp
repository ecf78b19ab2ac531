#pragma once
/// \file contacts_impl.hpp
/// `make_contacts_for<M>`: the contact set of a model of type M (included by engine_impl.hpp): `ContactsEngine<M>`
/// runs contact.hpp's and zmp.hpp's algorithms, specialised for the model, over the states of a call.

#include "contacts.hpp"
#include "engine.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>

namespace spatial::python {

template <class M>
struct ContactsFloating : std::false_type {};
template <class S, class T>
struct ContactsFloating<FloatingModel<S, T>> : std::true_type {};

template <class M>
class ContactsEngine final : public ContactsBase {
 public:
  static constexpr bool kFloating = ContactsFloating<M>::value;
  using Traits = spatial::detail::ModelTraits<M>;
  using DataT = typename Traits::DataType;
  using CD = ContactData<M>;
  static constexpr int NV = Traits::NV;
  static constexpr int NQ = NV == Eigen::Dynamic ? Eigen::Dynamic : NV + (kFloating ? 1 : 0);
  using MapQ = Eigen::Map<const Eigen::Matrix<double, NQ, 1>>;
  using MapV = Eigen::Map<const Eigen::Matrix<double, NV, 1>>;
  using List = std::vector<RigidContact<double>>;

  /// `model` must outlive the contact set (the bindings keep the Python model alive). Throws ModelError (from
  /// ContactData) for a bad contact.
  ContactsEngine(const M& model, List list, double mu) : model_(model) {
    damping = mu;
    ws_ = std::make_unique<Ws>(model_, list, damping, 0);  // checks the contacts and names them
    contacts_ = ws_->cd.contacts;
    rows = ws_->cd.m;
    for (const RigidContact<double>& c : contacts_) {
      offsets.push_back(static_cast<int>(dims.empty() ? 0 : offsets.back() + dims.back()));
      names.push_back(c.name);
      frames.push_back(c.frame);
      dims.push_back(c.dim());
    }
    nq_ = Traits::nq(model_);
    nv_ = Traits::nv(model_);
  }

  void run(const ContactCall& c, int threads) override {
    std::unique_lock<std::mutex> lock(busy_, std::try_to_lock);
    std::unique_ptr<Ws> fresh;
    Ws* ws = ws_.get();
    if (lock.owns_lock()) {
      sync(*ws);
    } else {  // another Python thread is using the set's own workspace
      fresh = make_ws();
      ws = fresh.get();
    }
    split(c, *ws, threads);
  }

  void set_targets(const double* q) override {
    std::unique_lock<std::mutex> lock(busy_, std::try_to_lock);
    std::unique_ptr<DataT> fresh;
    DataT* d = &ws_->data;
    if (!lock.owns_lock()) {
      fresh = std::make_unique<DataT>(model_);
      d = fresh.get();
    }
    forward_kinematics(model_, *d, MapQ(q, nq_));
    const auto k = spatial::detail::kin(model_, *d);
    std::lock_guard<std::mutex> g(config_);
    for (RigidContact<double>& c : contacts_) {  // set_contact_targets on the configuration
      int body;
      const Transform<double> X = spatial::detail::frame_world(k, c.frame, body);
      c.target_position = X.r;
      c.target_rotation = X.E.transpose();
    }
    ++version_;
  }

  void targets(double* out) const override {
    std::lock_guard<std::mutex> g(config_);
    for (const RigidContact<double>& c : contacts_) {
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) out[4 * i + j] = c.target_rotation(i, j);
        out[4 * i + 3] = c.target_position[i];
      }
      out[12] = out[13] = out[14] = 0.0;
      out[15] = 1.0;
      out += 16;
    }
  }

 private:
  struct Ws {
    Ws(const M& m, const List& list, double mu, std::uint64_t v) : data(m), cd(m, list), version(v) {
      cd.damping = mu;
    }
    DataT data;
    CD cd;
    std::uint64_t version;
  };

  const M& model_;
  int nq_ = 0, nv_ = 0;
  mutable std::mutex busy_;    ///< guards ws_
  std::unique_ptr<Ws> ws_;
  mutable std::mutex config_;  ///< guards contacts_ and version_
  List contacts_;              ///< the contacts' configuration (targets change with set_targets)
  std::uint64_t version_ = 0;

  void sync(Ws& ws) const {
    std::lock_guard<std::mutex> g(config_);
    if (ws.version != version_) {
      ws.cd.contacts = contacts_;
      ws.version = version_;
    }
  }
  std::unique_ptr<Ws> make_ws() const {
    std::lock_guard<std::mutex> g(config_);
    return std::make_unique<Ws>(model_, contacts_, damping, version_);
  }

  /// Contiguous chunks, one per thread; the first on the calling thread with `ws`, the others with a workspace of
  /// their own built from ws's contacts (which the calls only read).
  void split(const ContactCall& c, Ws& ws, int threads) const {
    const std::ptrdiff_t n = c.count;
    const std::ptrdiff_t t = threads_for(n, threads, kMinStatesPerThread);
    if (t == 1) return range(c, ws, 0, n);
    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(t - 1));
    const std::ptrdiff_t chunk = n / t, extra = n % t;
    const std::ptrdiff_t first = chunk + (extra > 0 ? 1 : 0);
    std::ptrdiff_t begin = first;
    for (std::ptrdiff_t k = 1; k < t; ++k) {
      const std::ptrdiff_t end = begin + chunk + (k < extra ? 1 : 0);
      pool.emplace_back([this, &c, &ws, begin, end] {
        Ws own(model_, ws.cd.contacts, damping, ws.version);
        range(c, own, begin, end);
      });
      begin = end;
    }
    range(c, ws, 0, first);
    for (auto& th : pool) th.join();
  }

  /// Not inlined: one compiled copy of the per-state code serves every thread and the single-threaded path, so that
  /// a state's result does not depend on how the batch was split (see Engine::range).
  __attribute__((noinline)) void range(const ContactCall& c, Ws& ws, std::ptrdiff_t begin,
                                       std::ptrdiff_t end) const {
    for (std::ptrdiff_t b = begin; b < end; ++b) one(c, ws, b);
  }

  MapQ q_at(const StridedIn& in, std::ptrdiff_t b) const { return MapQ(in.at(b), nq_); }
  MapV v_at(const StridedIn& in, std::ptrdiff_t b) const { return MapV(in.at(b), nv_); }

  /// Element loops rather than Eigen assignments into maps (GCC 12's false -Warray-bounds on masked AVX-512 copies
  /// of small vectors, as in Engine::put_vector); NaN instead of the values when `valid` is false.
  template <class Vec>
  static void put_vector(const StridedOut& o, std::ptrdiff_t b, const Vec& x, bool valid = true) {
    double* p = o.at(b);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (Eigen::Index k = 0; k < x.size(); ++k) p[k] = valid ? double(x[k]) : nan;
  }

  /// cd.lambda from the call's lambda input (state b).
  void load_lambda(const StridedIn& in, std::ptrdiff_t b, CD& cd) const {
    const double* p = in.at(b);
    for (int k = 0; k < cd.m; ++k) cd.lambda[k] = p[k];
  }

  void one(const ContactCall& c, Ws& ws, std::ptrdiff_t b) const {
    DataT& d = ws.data;
    CD& cd = ws.cd;
    const M& m = model_;
    switch (c.op) {
      case ContactOp::ForwardDynamics:
        constrained_forward_dynamics(m, d, cd, q_at(c.in[0], b), v_at(c.in[1], b), v_at(c.in[2], b));
        put_vector(c.out[0], b, cd.qdd, cd.ok);
        put_vector(c.out[1], b, cd.lambda, cd.ok);
        break;
      case ContactOp::Impulse:
        impulse_dynamics(m, d, cd, q_at(c.in[0], b), v_at(c.in[1], b), c.restitution);
        put_vector(c.out[0], b, cd.v_after, cd.ok);
        put_vector(c.out[1], b, cd.lambda, cd.ok);
        break;
      case ContactOp::InverseDynamics:
        if constexpr (kFloating) {
          contact_inverse_dynamics(m, d, cd, q_at(c.in[0], b), v_at(c.in[1], b), v_at(c.in[2], b));
          put_vector(c.out[0], b, cd.tau);
          put_vector(c.out[1], b, cd.lambda);
          c.flag[b] = cd.ok;
        }
        break;
      case ContactOp::Jacobian: {
        compute_joint_jacobians(m, d, q_at(c.in[0], b));
        spatial::detail::contact_rows<false>(m, d, cd);
        double* p = c.out[0].at(b);
        for (int i = 0; i < cd.m; ++i)
          for (int j = 0; j < nv_; ++j) *p++ = cd.J(i, j);
        break;
      }
      case ContactOp::Wrench:
      case ContactOp::CenterOfPressure: {
        forward_kinematics(m, d, q_at(c.in[0], b));
        load_lambda(c.in[1], b, cd);
        if (c.op == ContactOp::Wrench) {
          const Force<double> w = contact_wrench(m, d, cd);
          double* p = c.out[0].at(b);
          for (int k = 0; k < 3; ++k) p[k] = w.f[k], p[3 + k] = w.n[k];
        } else {
          put_vector(c.out[0], b, center_of_pressure(m, d, cd, c.height));
        }
        break;
      }
    }
  }
};

template <class M>
std::unique_ptr<ContactsBase> make_contacts_for(const M& model, const std::vector<ContactSpec>& specs,
                                                double damping) {
  std::vector<RigidContact<double>> list;
  list.reserve(specs.size());
  for (const ContactSpec& s : specs) {
    RigidContact<double> c;
    c.name = s.name;
    c.frame = s.frame;
    c.type = s.six_d ? ContactType::Contact6D : ContactType::Contact3D;
    c.reference = s.reference;
    c.kp = s.kp;
    c.kd = s.kd;
    c.friction = s.friction;
    c.sole_x_min = s.sole_x_min;
    c.sole_x_max = s.sole_x_max;
    c.sole_y_min = s.sole_y_min;
    c.sole_y_max = s.sole_y_max;
    list.push_back(std::move(c));
  }
  return std::make_unique<ContactsEngine<M>>(model, std::move(list), damping);
}

}  // namespace spatial::python
