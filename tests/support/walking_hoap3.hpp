#pragma once
// The floating HOAP-3 for the walking tests: the model type (the compile-time tree, except in the sanitizer build,
// support/compile_time_trees.hpp, which runs the same pipeline on the run-time twin) and the frames the whole-body
// pipeline needs.

#include <spatial/models/hoap3_floating.hpp>
#include <spatial/walking/whole_body.hpp>

#include "support/compile_time_trees.hpp"

namespace spatial::testing::walking_hoap3 {

namespace fb = spatial::models::hoap3_floating;
#if SPATIAL_TEST_COMPILE_TIME_TREES
using FM = spatial::FloatingModel<double, fb::Tree>;
inline FM make_model() { return fb::floating_model(); }
#else
using FM = spatial::FloatingModel<double>;
inline FM make_model() { return fb::floating_model().to_runtime(); }
#endif

inline spatial::walking::WholeBodyFrames hoap3_frames() {
  return {fb::frame_index("L_SOLE"), fb::frame_index("R_SOLE"), fb::frame_index("base_link")};
}

}  // namespace spatial::testing::walking_hoap3
