// Which models a bootstrap starts from and unposes with: a decision of learning, taken here so that
// every caller (the C API, hence the command line and the Python pipeline) takes it the same way.
#pragma once

#include "learning/learn_model.hpp"

#include <optional>
#include <string>
#include <vector>

namespace ssc::learning {

// The starting model's file bytes: the file at `path`, or `builtin` (the default model's file)
// without one; reduced to its template (template_only) on request. Throws ssc::Error for an
// unreadable or invalid model, so that a bad model is refused before any work.
std::vector<unsigned char> starting_model_file(const std::optional<std::string>& path, bool template_only,
                                               const std::vector<unsigned char>& builtin);

// The posture model's file bytes for Posture::Skeleton (LearnSpec::posture_model); empty: each
// round's own fits. A path: that model, which must share the starting model's mesh, skeleton and
// skinning (INVALID_ARGUMENT otherwise); an empty path: none; no path: the built-in model where it
// shares them, else none (a starting model of another template). Other postures: none.
std::vector<unsigned char> posture_model_file(Posture posture, const std::optional<std::string>& path,
                                              const std::vector<unsigned char>& start, const std::vector<unsigned char>& builtin);

}  // namespace ssc::learning
