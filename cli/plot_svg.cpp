#include "cli/plot_svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace snell::cli {
namespace {

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '&')
      o += "&amp;";
    else
      o += c;
  }
  return o;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// Tick text for 10^k.
std::string decade(int k) {
  if (k >= -3 && k <= 3) {
    double v = std::pow(10.0, k);
    return k < 0 ? fmt("%g", v) : fmt("%.0f", v);
  }
  return "1e" + std::to_string(k);
}

const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                          "#ff7f0e", "#17becf", "#8c564b", "#e377c2"};

}  // namespace

std::string render_svg(const Plot& plot) {
  constexpr double W = 640, H = 420, L = 78, R = 170, T = 40, B = 56;
  double x0 = std::numeric_limits<double>::max(), x1 = 0, y0 = x0, y1 = 0;
  for (const PlotSeries& s : plot.series)
    for (const PlotPoint& p : s.points) {
      if (!(p.x > 0) || !(p.y > 0)) continue;
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y),
      y1 = std::max(y1, p.y);
    }
  if (x1 == 0) x0 = 1, x1 = 10, y0 = 1, y1 = 10;
  // Whole decades around the data, at least one decade wide.
  int dx0 = static_cast<int>(std::floor(std::log10(x0))),
      dx1 = static_cast<int>(std::ceil(std::log10(x1)));
  int dy0 = static_cast<int>(std::floor(std::log10(y0))),
      dy1 = static_cast<int>(std::ceil(std::log10(y1)));
  if (dx1 == dx0) ++dx1;
  if (dy1 == dy0) ++dy1;
  auto px = [&](double x) { return L + (std::log10(x) - dx0) / (dx1 - dx0) * (W - L - R); };
  auto py = [&](double y) { return H - B - (std::log10(y) - dy0) / (dy1 - dy0) * (H - T - B); };

  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt("%.0f", W) +
                  "\" height=\"" + fmt("%.0f", H) +
                  "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  s += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s += "<text x=\"" + fmt("%.0f", (L + W - R) / 2) +
       "\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">" + esc(plot.title) + "</text>\n";
  // Grid and ticks: decades labelled, 2..9 as light lines.
  for (int k = dx0; k <= dx1; ++k) {
    for (int m = 1; m <= 9 && (k < dx1 || m == 1); ++m) {
      double x = px(m * std::pow(10.0, k));
      s += "<line x1=\"" + fmt("%.1f", x) + "\" y1=\"" + fmt("%.0f", T) + "\" x2=\"" +
           fmt("%.1f", x) + "\" y2=\"" + fmt("%.0f", H - B) + "\" stroke=\"" +
           (m == 1 ? "#bbb" : "#eee") + "\"/>\n";
    }
    s += "<text x=\"" + fmt("%.1f", px(std::pow(10.0, k))) + "\" y=\"" + fmt("%.0f", H - B + 16) +
         "\" text-anchor=\"middle\">" + decade(k) + "</text>\n";
  }
  for (int k = dy0; k <= dy1; ++k) {
    for (int m = 1; m <= 9 && (k < dy1 || m == 1); ++m) {
      double y = py(m * std::pow(10.0, k));
      s += "<line x1=\"" + fmt("%.0f", L) + "\" y1=\"" + fmt("%.1f", y) + "\" x2=\"" +
           fmt("%.0f", W - R) + "\" y2=\"" + fmt("%.1f", y) + "\" stroke=\"" +
           (m == 1 ? "#bbb" : "#eee") + "\"/>\n";
    }
    s += "<text x=\"" + fmt("%.0f", L - 6) + "\" y=\"" + fmt("%.1f", py(std::pow(10.0, k)) + 4) +
         "\" text-anchor=\"end\">" + decade(k) + "</text>\n";
  }
  s += "<rect x=\"" + fmt("%.0f", L) + "\" y=\"" + fmt("%.0f", T) + "\" width=\"" +
       fmt("%.0f", W - L - R) + "\" height=\"" + fmt("%.0f", H - T - B) +
       "\" fill=\"none\" stroke=\"#333\"/>\n";
  s += "<text x=\"" + fmt("%.0f", (L + W - R) / 2) + "\" y=\"" + fmt("%.0f", H - 14) +
       "\" text-anchor=\"middle\">" + esc(plot.x_label) + "</text>\n";
  s += "<text transform=\"translate(18," + fmt("%.0f", (T + H - B) / 2) +
       ") rotate(-90)\" text-anchor=\"middle\">" + esc(plot.y_label) + "</text>\n";
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& ser = plot.series[i];
    const char* c = kColours[i % std::size(kColours)];
    std::string path;
    for (const PlotPoint& p : ser.points) {
      if (!(p.x > 0) || !(p.y > 0)) continue;
      path += (path.empty() ? "M" : " L") + fmt("%.1f", px(p.x)) + "," + fmt("%.1f", py(p.y));
    }
    if (!path.empty())
      s += "<path d=\"" + path + "\" fill=\"none\" stroke=\"" + c + "\" stroke-width=\"2\"/>\n";
    for (const PlotPoint& p : ser.points) {
      if (!(p.x > 0) || !(p.y > 0)) continue;
      s += "<circle cx=\"" + fmt("%.1f", px(p.x)) + "\" cy=\"" + fmt("%.1f", py(p.y)) +
           "\" r=\"3.5\" fill=\"" + c + "\"/>\n";
      if (!p.label.empty())
        s += "<text x=\"" + fmt("%.1f", px(p.x) + 6) + "\" y=\"" + fmt("%.1f", py(p.y) - 6) +
             "\" font-size=\"10\" fill=\"" + c + "\">" + esc(p.label) + "</text>\n";
    }
    double ly = T + 14 + 18 * static_cast<double>(i);
    s += "<line x1=\"" + fmt("%.0f", W - R + 12) + "\" y1=\"" + fmt("%.0f", ly - 4) + "\" x2=\"" +
         fmt("%.0f", W - R + 32) + "\" y2=\"" + fmt("%.0f", ly - 4) + "\" stroke=\"" + c +
         "\" stroke-width=\"2\"/>\n";
    s += "<text x=\"" + fmt("%.0f", W - R + 38) + "\" y=\"" + fmt("%.0f", ly) + "\">" +
         esc(ser.name) + "</text>\n";
  }
  return s + "</svg>\n";
}

}  // namespace snell::cli
