// Registration options from a def, and a registration's report into the caller's
// ssc_registration_report (its struct_size bytes): for ssc_registration_run and the offline tools
// (capi_offline/).
#pragma once

#include "registration/register_scan.hpp"
#include "registration/registration_quality.hpp"
#include <sscape/sscape.h>

namespace ssc::capi {

void copy_quality(const registration::DistanceSummary& d, const std::array<double, 4>& below, ssc_registration_quality& q);

// The options a def asks for (checked: INVALID_ARGUMENT for unknown enums); the registrar checks
// the numbers. Everything that registers for the C API takes its options from here, so the same
// def gives the same registration to the bit (the def's floats included).
registration::RegistrationOptions registration_options(const ssc_registration_def& def);

// report->struct_size must have been checked (>= 4).
void write_report(uint32_t rounds, uint32_t solves, std::size_t valid, double seconds, double fit_seconds,
                  const registration::RegistrationQuality& quality, std::size_t scan_points, std::size_t landmarks,
                  ssc_registration_report* report);

}  // namespace ssc::capi
