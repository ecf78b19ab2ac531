// The generated model hoap3_double_pendulum (compile-time tree): its own source so that the models compile in parallel.
#include "engine_impl.hpp"

#include <spatial/models/hoap3_double_pendulum.hpp>

namespace spatial::python {

SPATIAL_PY_GENERATED(hoap3_double_pendulum)

std::shared_ptr<ModelBase> make_hoap3_double_pendulum() {
  return describe_generated(std::make_shared<Engine<Model<double, models::hoap3_double_pendulum::Tree>>>(models::hoap3_double_pendulum::model()), "hoap3_double_pendulum", hoap3_double_pendulum_info{});
}

}  // namespace spatial::python
