// Units of measurement files: the names a user gives (m, cm, mm), and the check that points read
// in some units span a body at all (the usual mistake: millimetres read as metres).
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace ssc::io {

// "m", "cm", "mm" in metres; ssc::Error (INVALID_ARGUMENT) for anything else.
double units_to_metres(const std::string& units);

// The largest extent of the points (metres, read from `path` in units of to_metres, `given` by the
// user or each format's default). Throws ssc::Error (INVALID_ARGUMENT) when it is not 5 cm to 3 m
// (a hand or a face scan .. a tall person with arms raised), naming the units that would fit and,
// when given, the option that sets them (the command line's "--units").
double checked_body_span(const std::string& path, const std::vector<Eigen::Vector3d>& metres, double to_metres, bool given,
                         const std::string& option = "");

}  // namespace ssc::io
