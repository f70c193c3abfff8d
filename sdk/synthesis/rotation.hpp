// Conversion and checking of caller rotations (pose input of bodies and batches).
#pragma once

#include <sscape/sscape.h>

#include <cstdint>
#include <string>

namespace ssc {

// Converts count rotations of the given format to unit quaternions xyzw in out (4 * count).
// Returns false and describes the first bad rotation (non-finite, zero quaternion) in error.
bool to_unit_quaternions(ssc_rotation_format format, const float* in, uint32_t count, float* out, std::string& error);
// The same checks alone, converting nothing: a batch checks every body's pose before it makes any
// body, then each worker converts its own bodies' poses.
bool check_rotations(ssc_rotation_format format, const float* in, uint32_t count, std::string& error);

}  // namespace ssc
