// The generated model hoap3_stance_left (compile-time tree): its own source so that the models compile in parallel.
#include "engine_impl.hpp"

#include <spatial/models/hoap3_stance_left.hpp>

namespace spatial::python {

SPATIAL_PY_GENERATED(hoap3_stance_left)

std::shared_ptr<ModelBase> make_hoap3_stance_left() {
  return describe_generated(std::make_shared<Engine<Model<double, models::hoap3_stance_left::Tree>>>(models::hoap3_stance_left::model()), "hoap3_stance_left", hoap3_stance_left_info{});
}

}  // namespace spatial::python
