// tern/aero/pipeline.hpp: the aerodynamic modelling pipeline of `tern aero import|linearize|gains`
// (issues 11, 22), one header per step:
//  * import.hpp: VSPAERO / XFLR5 stability derivatives -> a tern aircraft file
//    (import_vspaero.cpp, import_xflr5.cpp, aircraft_build.cpp);
//  * linear_model.hpp: uavbook ch. 5 state-space models and transfer functions (linearize.cpp);
//  * modes.hpp: the dynamic modes of those models and the textbook approximations (modes.cpp);
//  * gain_design.hpp: uavbook ch. 6 successive loop closure (gain_design.cpp).
#pragma once

#include "tern/aero/import.hpp"
#include "tern/aero/gain_design.hpp"
#include "tern/aero/linear_model.hpp"
#include "tern/aero/modes.hpp"
