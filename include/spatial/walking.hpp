#pragma once
/// \file walking.hpp
/// Umbrella header of the walking pattern generator (issue 12): footstep plans, swing-foot trajectories, the
/// reference ZMP and support polygons (walking/footsteps.hpp), and ZMP preview control on the cart-table model
/// (walking/preview.hpp), and the rigid-contact simulator of the closed loop (walking/simulation.hpp). Not included by
/// spatial.hpp: a dynamics user does not compile it. See docs/walking.md.

#include "spatial/walking/footsteps.hpp"
#include "spatial/walking/preview.hpp"
#include "spatial/walking/simulation.hpp"
