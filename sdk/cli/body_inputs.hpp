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

// `sscape fit --params` output: the shape, and frame 0's joint rotations (by joint name; joints
// not named keep the rest pose) and translation.
struct FitParams {
    std::vector<float> shape, pose, translation;
};
// UsageError naming the file for anything that is not such a file of this model (another model's,
// values no fit gives: not finite, shape beyond 20 SD, rotations not unit quaternions).
FitParams read_params(ssc_model* model, const std::string& path);
// The same from the file's text; `path` names it in messages (the fuzz target's entry).
FitParams parse_params(ssc_model* model, const std::string& text, const std::string& path);

}  // namespace ssc::cli
