// Anatomy's tables (joint ranges, named poses, finger closure) are written in degrees, as
// clinicians tabulate them; kDeg turns them into the radians the rig uses.
#pragma once

#include <cmath>

namespace ssc::anatomy {

inline constexpr double kDeg = M_PI / 180;

}  // namespace ssc::anatomy
