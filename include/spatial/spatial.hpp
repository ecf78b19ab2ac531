#pragma once
// umbrella header; replaced by the library
#include <Eigen/Core>
