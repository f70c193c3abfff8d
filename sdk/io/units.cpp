#include "io/units.hpp"

#include "common/error.hpp"

#include <string>

namespace ssc::io {

namespace {

const char* units_name(double to_metres) { return to_metres == 1 ? "m" : to_metres == 1e-2 ? "cm" : to_metres == 1e-3 ? "mm" : "its units"; }

}  // namespace

double units_to_metres(const std::string& u) {
    if (u == "m") return 1.0;
    if (u == "cm") return 1e-2;
    if (u == "mm") return 1e-3;
    throw Error(SSC_ERROR_INVALID_ARGUMENT, "units '" + u + "' are none of m, cm, mm");
}

double checked_body_span(const std::string& path, const std::vector<Eigen::Vector3d>& metres, double to_metres, bool given,
                         const std::string& option) {
    constexpr double kSmallest = 0.05, kLargest = 3.0;
    if (metres.size() < 2) return 0.0;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const auto& p : metres) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const double span = (hi - lo).maxCoeff();
    if (span >= kSmallest && span <= kLargest) return span;
    const std::string how = given ? " (" + (option.empty() ? std::string("as given") : option) + ")" : " (the default for this kind of file)";
    std::string message = path + ": read in " + units_name(to_metres) + how + " it spans " + std::to_string(span) + " m, but a body or body part spans " + std::to_string(kSmallest) + " to " +
                          std::to_string(kLargest) + " m";
    std::string hint = option.empty() ? "; give its units (m, cm or mm)" : "; give its units with " + option + " m|cm|mm";
    for (const std::string u : {"m", "cm", "mm"}) {
        const double other = span * units_to_metres(u) / to_metres;
        if (units_to_metres(u) != to_metres && other >= 0.3 && other <= 2.6)
            hint = (option.empty() ? "; in " : "; with " + option + " ") + u + " it would span " + std::to_string(other) + " m";
    }
    throw Error(SSC_ERROR_INVALID_ARGUMENT, message + hint);
}

}  // namespace ssc::io
