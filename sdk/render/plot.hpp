// Line plots as PNG, drawn by the project's own rasterizer (raster.hpp, text.hpp): the training
// report's compactness, generalization and specificity curves, the registration benchmark's
// comparison of starts.
#pragma once

#include <string>
#include <vector>

namespace ssc::render {

struct LineSeries {
    std::string name;          // in the legend
    std::vector<double> x, y;  // one point each, in order; at least one
};

struct LinePlot {
    std::string title, x_label, y_label;
    std::vector<double> x, y;  // one point each, in order; at least one
    // Further curves, each in its own colour; with any, a legend names `name` (the first curve's)
    // and theirs.
    std::string name;
    std::vector<LineSeries> more;
};

// Draws the curves with their points marked, a grid at round values, tick labels, the title and the
// axis labels, 640 x 420 pixels. Throws ssc::Error (SSC_ERROR_INVALID_ARGUMENT for no points,
// mismatched or non-finite values; SSC_ERROR_IO when the file cannot be written).
void write_line_plot(const std::string& path, const LinePlot& plot);

}  // namespace ssc::render
