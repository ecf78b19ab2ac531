#pragma once
/// \file walking.hpp
/// Umbrella header of the walking pattern generator (issue 12): footstep plans, swing-foot trajectories, the
/// reference ZMP and support polygons (walking/footsteps.hpp), ZMP preview control on the cart-table model
/// (walking/preview.hpp), the whole-body stage (walking/whole_body.hpp: IK, inverse dynamics with contacts, the
/// multibody ZMP and the second preview stage) and the rigid-contact simulator of the closed loop
/// (walking/simulation.hpp). Not included by spatial.hpp: a dynamics user does not compile it. See docs/walking.md.

#include "spatial/walking/footsteps.hpp"
#include "spatial/walking/preview.hpp"
#include "spatial/walking/simulation.hpp"
#include "spatial/walking/whole_body.hpp"
#include "spatial/walking/closed_loop.hpp"
