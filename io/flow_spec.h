// The flow a solver case is set up for: free stream, fluid and turbulence model.
#pragma once

#include <string>

#include "hexmesh/core/types.h"

namespace hexmesh {

// Case key "flow". The Reynolds number on a body of length L is density |velocity| L /
// viscosity: the defaults give Re = 100 on a body of unit length (laminar, steady).
struct FlowSpec {
    Vec3 velocity = Vec3(1, 0, 0);  // free stream, geometry units per second
    double density = 1;
    double viscosity = 0.01;  // dynamic; the kinematic one is viscosity / density
    // "laminar", or "k-omega-sst" (Menter's SST: k and omega from turbulence_intensity and
    // turbulence_length, wall functions that also hold at y+ ~ 1).
    std::string turbulence = "laminar";
    double turbulence_intensity = 0.01;  // k = 1.5 (intensity |velocity|)^2
    double turbulence_length = 0;        // mixing length; 0: a tenth of the wall's largest extent
};

}  // namespace hexmesh
