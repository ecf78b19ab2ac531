// The generated models hoap3_stance_right and hoap3_stance_left (compile-time trees). The two stance models are
// mirror images with one tree type (the same parents and joint types, other numbers), so the engine for that type is
// instantiated once here for both: in two sources it cost the package build ~100 CPU-seconds twice over.
#include "engine_impl.hpp"

#include <spatial/models/hoap3_stance_left.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include <type_traits>

namespace spatial::python {

static_assert(std::is_same_v<models::hoap3_stance_right::Tree, models::hoap3_stance_left::Tree>,
              "the stance models no longer share a tree type: give each its own source again, so that they build "
              "in parallel");

SPATIAL_PY_GENERATED(hoap3_stance_right)
SPATIAL_PY_GENERATED(hoap3_stance_left)

std::shared_ptr<ModelBase> make_hoap3_stance_right() {
  return describe_generated(std::make_shared<Engine<Model<double, models::hoap3_stance_right::Tree>>>(models::hoap3_stance_right::model()), "hoap3_stance_right", hoap3_stance_right_info{});
}

std::shared_ptr<ModelBase> make_hoap3_stance_left() {
  return describe_generated(std::make_shared<Engine<Model<double, models::hoap3_stance_left::Tree>>>(models::hoap3_stance_left::model()), "hoap3_stance_left", hoap3_stance_left_info{});
}

}  // namespace spatial::python
