// Body measurements as a tailor or an anthropometric survey takes them: stature, girths, lengths,
// breadth, surface area, volume and mass, each defined on the template by landmarks, joints and
// planes (measurements.cpp states each definition and its source).
//
// Bodies are measured in the rest pose (standing, arms slightly lowered from the horizontal), on
// their shape: surveys measure people standing, whatever pose a body is later shown in. Limb
// measurements are taken on the right side, as ISO 7250-1 and the large surveys (ANSUR, CAESAR) do.
#pragma once

#include "synthesis/body.hpp"
#include "synthesis/model.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace ssc::measure {

// Whole-body density used for mass = density x volume (kg/m^3): a typical adult value with normal
// lung volume; the training population uses the same figure to reach its BMI targets.
inline constexpr double kBodyDensity = 1010.0;

// The largest body measured (metres, along any axis of its rest pose): larger ones are refused
// with SSC_ERROR_INVALID_ARGUMENT.
inline constexpr double kMaxBodyExtent = 5.0;

enum class Unit { Metre, SquareMetre, CubicMetre, Kilogram };

struct Definition {
    const char* name;        // snake_case, stable: the C API and the CLI use it
    Unit unit;
    const char* definition;  // how it is taken, with its source
};

// Every measurement, in the order of the C API's ssc_measurement values.
const std::vector<Definition>& definitions();

// Index of a measurement by name, or -1.
int find_measurement(const std::string& name);

// A landmark's position on a body given as packed xyz vertices (metres).
Eigen::Vector3d landmark_position(const format::ModelData& data, uint32_t landmark, const float* xyz);

// What a measurement was taken along, for pictures: closed loops (girths) or open polylines.
struct Path {
    std::vector<Eigen::Vector3d> points;
    bool closed = false;
};

// Measures bodies of one model. Construction looks up the landmarks, joints and body-part vertex
// sets the definitions need and throws ssc::Error (SSC_ERROR_NOT_FOUND, naming what is missing) for
// a model without them. Immutable afterwards: one measurer may serve many threads.
class Measurer {
public:
    explicit Measurer(const Model& model);

    // All measurements (definitions() order, SI units) of a body given by its rest-pose vertices
    // (packed xyz, 3V floats) and rest joint positions (3J floats). `paths`, when given, receives
    // one path per measurement (empty for area, volume and mass).
    // `only`, when given (one flag per measurement), limits the work to the flagged measurements;
    // the others are returned as 0. Throws ssc::Error(SSC_ERROR_INVALID_ARGUMENT) for a body with
    // non-finite vertices or joints, or one larger than kMaxBodyExtent.
    std::vector<double> measure(const float* xyz, const float* joints, std::vector<Path>* paths = nullptr,
                                const std::vector<bool>* only = nullptr) const;
    // The same for a body's current shape (its pose does not matter).
    std::vector<double> measure(Body& body, std::vector<Path>* paths = nullptr, const std::vector<bool>* only = nullptr) const;

private:
    const Model& model_;
    std::vector<uint32_t> landmark_;  // indices of the landmarks the definitions use (kNeeded order)
    uint32_t upperarm_ = 0, lowerarm_ = 0, hand_ = 0, neck_ = 0, head_ = 0;  // right side joints, neck
    // Edge lists (girth.hpp) of the body parts sections are cut from.
    std::vector<uint32_t> torso_, trunk_legs_, right_leg_, right_arm_, neck_region_;
};

}  // namespace ssc::measure
