// The run-time models (URDF loaded in Python): fixed and floating base.
#include "engine_impl.hpp"

namespace spatial::python {

std::shared_ptr<ModelBase> make_runtime_model(const urdf_io::LoadedModel& loaded, const std::string& name) {
  std::shared_ptr<ModelBase> e;
  if (loaded.floating) e = std::make_shared<Engine<FloatingModel<double>>>(urdf_io::floating_model(loaded));
  else e = std::make_shared<Engine<Model<double>>>(loaded.model);
  e->name = name;
  e->root = loaded.root;
  e->warnings = loaded.warnings;
  for (const auto& j : loaded.joints) {
    e->lower.push_back(j.lower);
    e->upper.push_back(j.upper);
    e->effort.push_back(j.effort);
    e->velocity.push_back(j.velocity);
  }
  e->total_mass = urdf_io::whole_body_mass(loaded);
  return e;
}

std::shared_ptr<ModelBase> make_reduced_model(const ModelBase& from, const ReducedModel<double>& reduced) {
  auto e = std::make_shared<Engine<Model<double>>>(reduced.model);
  e->name = from.name + " (reduced)";
  e->root = from.root;
  e->warnings = from.warnings;
  e->total_mass = from.total_mass;
  for (int j : reduced.joints) {
    const auto k = static_cast<std::size_t>(j);
    e->lower.push_back(from.lower[k]);
    e->upper.push_back(from.upper[k]);
    e->effort.push_back(from.effort[k]);
    e->velocity.push_back(from.velocity[k]);
    e->source_joints.push_back(j);
  }
  return e;
}

}  // namespace spatial::python
