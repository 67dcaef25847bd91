// A small log-log line plot written as SVG (error versus time for snell sweep).
// No dependencies: the atlas regenerates without Python or plotting packages.
#pragma once

#include <string>
#include <vector>

namespace snell::cli {

struct PlotPoint {
  double x = 0, y = 0;
  std::string label;  // printed beside the point (e.g. "16 spp")
};

struct PlotSeries {
  std::string name;
  std::vector<PlotPoint> points;
};

struct Plot {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<PlotSeries> series;
};

// Both axes logarithmic; non-positive values are left out. Returns the SVG text.
std::string render_svg(const Plot& plot);

}  // namespace snell::cli
