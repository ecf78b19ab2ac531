// libFuzzer target for the URDF loader (scripts/fuzz.sh builds and runs it with clang, ASan and UBSan).
//
// Each input is URDF text. It is loaded with the default options; when that succeeds it is loaded again re-rooted
// at its last link, cut to the subtree below its second link, with its first joint locked and with axis_aligned
// off, and every model obtained is run through the algorithms once (RNEA, CRBA + LTDL, ABA, kinematics, energy) on a
// state made from the input's bytes. The loader's documented failure is `spatial::ModelError`; any other exception,
// a crash, a sanitizer report, a leak or a hang is a finding.

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace {

using spatial::ModelError;
namespace uio = spatial::urdf_io;

/// A state from the input's bytes (not physical, but finite): exercises the algorithms on the loaded model.
void run_algorithms(const spatial::Model<double>& model, const std::uint8_t* data, std::size_t size) {
  spatial::Data<double> d(model);
  const int n = model.size();
  Eigen::VectorXd q(n), qd(n), x(n);
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double b = size > 0 ? double(data[k % size]) : 0.0;
    q[i] = (b - 128.0) / 16.0;
    qd[i] = (b - 100.0) / 32.0;
    x[i] = (b - 64.0) / 8.0;
  }
  (void)spatial::rnea(model, d, q, qd, x);
  (void)spatial::crba(model, d, q);
  spatial::ltdl(model, d);
  (void)spatial::aba(model, d, q, qd, x);
  (void)spatial::forward_dynamics_crba(model, d, q, qd, x);
  (void)spatial::kinetic_energy(model, d, q, qd);
  (void)spatial::potential_energy(model, d, q);
  if (n > 0) (void)spatial::center_of_mass(model, d, q);
  (void)spatial::check_finite(model, q, qd, x);
}

void load_and_run(const std::string& xml, const uio::LoadOptions& options, const std::uint8_t* data,
                  std::size_t size, uio::LoadedModel* out = nullptr) {
  try {
    uio::LoadedModel m = uio::load_string(xml, options, "fuzz");
    run_algorithms(m.model, data, size);
    try {
      uio::check_nonsingular(m);
    } catch (const ModelError&) {
    }
    if (out) *out = std::move(m);
  } catch (const ModelError&) {
    // The documented rejection of a bad file or option.
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string xml(reinterpret_cast<const char*>(data), size);
  uio::LoadedModel first;
  first.model = spatial::Model<double>();
  load_and_run(xml, {}, data, size, &first);
  if (first.links.empty()) return 0;

  uio::LoadOptions reroot;
  reroot.root = first.links.back().name;
  reroot.gravity_frame = uio::GravityFrame::UrdfRoot;
  load_and_run(xml, reroot, data, size);

  if (first.links.size() > 1) {
    uio::LoadOptions sub;
    sub.subtree = first.links[1].name;
    load_and_run(xml, sub, data, size);
  }
  if (!first.joints.empty()) {
    uio::LoadOptions lock;
    lock.locked = {{first.joints.front().name, size > 0 ? double(data[0]) / 50.0 : 0.0}};
    lock.axis_aligned = false;
    load_and_run(xml, lock, data, size);
  }
  return 0;
}
