// The generated model hoap3_stance_right (compile-time tree): its own source so that the models compile in parallel.
#include "engine_impl.hpp"

#include <spatial/models/hoap3_stance_right.hpp>

namespace spatial::python {

SPATIAL_PY_GENERATED(hoap3_stance_right)

std::shared_ptr<ModelBase> make_hoap3_stance_right() {
  return describe_generated(std::make_shared<Engine<Model<double, models::hoap3_stance_right::Tree>>>(models::hoap3_stance_right::model()), "hoap3_stance_right", hoap3_stance_right_info{});
}

}  // namespace spatial::python
