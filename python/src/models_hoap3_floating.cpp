// The generated model hoap3_floating (compile-time tree): its own source so that the models compile in parallel.
#include "engine_impl.hpp"

#include <spatial/models/hoap3_floating.hpp>

namespace spatial::python {

SPATIAL_PY_GENERATED(hoap3_floating)

std::shared_ptr<ModelBase> make_hoap3_floating() {
  return describe_generated(std::make_shared<Engine<FloatingModel<double, models::hoap3_floating::Tree>>>(models::hoap3_floating::floating_model()), "hoap3_floating", hoap3_floating_info{});
}

}  // namespace spatial::python
