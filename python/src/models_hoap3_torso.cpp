// The generated model hoap3_torso (compile-time tree): its own source so that the models compile in parallel.
#include "engine_impl.hpp"

#include <spatial/models/hoap3_torso.hpp>

namespace spatial::python {

SPATIAL_PY_GENERATED(hoap3_torso)

std::shared_ptr<ModelBase> make_hoap3_torso() {
  return describe_generated(std::make_shared<Engine<Model<double, models::hoap3_torso::Tree>>>(models::hoap3_torso::model()), "hoap3_torso", hoap3_torso_info{});
}

}  // namespace spatial::python
