#pragma once
/// \file spatial.hpp
/// Umbrella header of the spatial library: spatial vector algebra, joints, kinematic trees and the dynamics
/// algorithms (RNEA, CRBA, LTDL, ABA), floating bases, kinematics, centroidal quantities, input checks, printing
/// (io.hpp), derivatives, H⁻¹, rigid contacts, ZMP, trees with spherical joints (general.hpp). See README.md for the conventions.

#include "spatial/algebra.hpp"
#include "spatial/joints.hpp"
#include "spatial/model.hpp"
#include "spatial/sincos.hpp"
#include "spatial/algorithms.hpp"
#include "spatial/floating.hpp"
#include "spatial/general.hpp"
#include "spatial/centroidal.hpp"
#include "spatial/checks.hpp"
#include "spatial/options.hpp"
#include "spatial/reduce.hpp"
#include "spatial/kinematics.hpp"
#include "spatial/ik.hpp"
#include "spatial/derivatives.hpp"
#include "spatial/minv.hpp"
#include "spatial/contact.hpp"
#include "spatial/zmp.hpp"
#include "spatial/io.hpp"
