// The training population's attributes (stature, mass, girths, sex, age, ...) and shape
// coefficients as one Gaussian (the model file's AttributeModel): the conditional mean of the
// coefficients given any known attributes is the regression that starts a body made to measure,
// and the same conditioning on the slider attributes gives the semantic sliders.
//
// Sliders. With S the slider attributes and C the covariances, the directions are
// D = C_cS C_SS^-1 (K x S): coefficients per unit of each slider with the other sliders held.
// A body's slider values are read back with the least-squares inverse R = (D^T D)^-1 D^T, so
// R D = I: moving one slider changes exactly that slider's read-back value, whatever else the
// shape holds. Coefficients are in standard deviations, whose population covariance is identity.
#pragma once

#include "sscape_format/model_data.hpp"

#include <Eigen/Core>

#include <cmath>

#include <string>
#include <utility>
#include <vector>

namespace ssc::semantics {

class AttributeModel {
public:
    // Throws ssc::Error(SSC_ERROR_MODEL_CORRUPT) when the slider covariance is singular.
    explicit AttributeModel(const format::ModelData& data);

    bool empty() const { return attributes_.empty(); }
    const std::vector<format::Attribute>& attributes() const { return attributes_; }
    int find(const std::string& name) const;  // -1 when absent
    // The population's standard deviation of an attribute.
    double standard_deviation(int attribute) const { return std::sqrt(covariance_(attribute, attribute)); }

    // The values accepted for an attribute (slider values, made-to-measure targets): the
    // population's range (0.5th to 99.5th percentile) widened by its own width on each side, and
    // not below zero for a quantity with a unit (m, kg, years).
    std::pair<double, double> accepted_range(int attribute) const;
    // Throws ssc::Error(SSC_ERROR_INVALID_ARGUMENT) for a value outside accepted_range, giving the range.
    void check_accepted(int attribute, double value) const;

    // E[coefficients | the given attributes] (pairs of attribute index and value), K entries;
    // all zeros (the mean body) when nothing is given or the model has no attributes.
    Eigen::VectorXd conditional_shape(const std::vector<std::pair<int, double>>& known) const;

    const std::vector<int>& sliders() const { return sliders_; }  // attribute index per slider
    const Eigen::MatrixXd& slider_directions() const { return directions_; }  // K x S
    // Coefficients of the body with the given slider values (S values): D (values - means).
    Eigen::VectorXd sliders_to_shape(const Eigen::VectorXd& values) const;
    // Slider values of a shape (K coefficients): means + R coefficients.
    Eigen::VectorXd shape_to_sliders(const Eigen::VectorXd& coefficients) const;

private:
    std::vector<format::Attribute> attributes_;
    Eigen::MatrixXd covariance_;        // A x A
    Eigen::MatrixXd shape_covariance_;  // A x K
    uint32_t K_ = 0;
    std::vector<int> sliders_;
    Eigen::VectorXd slider_means_;
    Eigen::MatrixXd directions_, readback_;  // K x S, S x K
};

}  // namespace ssc::semantics
