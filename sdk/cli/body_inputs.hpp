// What a body is made from on the command line, shared by the commands that make one (synth,
// measure): named values (--sliders, --measure), semantic sliders set on a body, and a fit read
// back from the parameters `sscape fit --params` wrote.
#pragma once

#include <sscape/sscape.h>

#include <string>
#include <utility>
#include <vector>

namespace ssc::cli {

// "name=value,name=value" (SI units); UsageError naming option on anything else.
std::vector<std::pair<std::string, float>> parse_named(const std::string& text, const std::string& option);

// Moves each named slider of the body from its present shape; UsageError listing the model's
// sliders for a name it does not have.
void set_sliders(ssc_model* model, ssc_body* body, const std::vector<std::pair<std::string, float>>& sliders);

// A fit's parameters (scan_files/fit_params.hpp: `sscape fit --params` output, or the model fit in a
// registration's report, `sscape register --report`): the whole-body shape, the segments' coefficients when fitted with them, and
// frame 0's joint rotations (joints not named keep the rest pose) and translation.
struct FitParams {
    std::vector<float> shape, segment_shape, pose, translation;
};
// UsageError naming the file for anything that is not such a file of this model (another model's,
// values no fit gives: not finite, shape beyond 20 SD, rotations not unit quaternions).
FitParams read_params(ssc_model* model, const std::string& path);
// The same from the file's text; `path` names it in messages (the fuzz target's entry).
FitParams parse_params(ssc_model* model, const std::string& text, const std::string& path);
// Sets the fit's segment coefficients on the body, segment by segment (none: nothing changes).
void set_fit_segments(ssc_model* model, ssc_body* body, const FitParams& params);

}  // namespace ssc::cli
