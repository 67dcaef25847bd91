#include "cli/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace snell::cli {
namespace {

void check_sizes(const rt::Image& a, const rt::Image& b) {
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size())
    throw std::invalid_argument("images of different sizes");
}

double srgb_encode(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055;
}

std::vector<double> display_luma(const rt::Image& img) {
  std::vector<double> y(std::size_t(img.width) * img.height);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const float* p = &img.rgb[3 * i];
    y[i] = 0.2126 * srgb_encode(p[0]) + 0.7152 * srgb_encode(p[1]) + 0.0722 * srgb_encode(p[2]);
  }
  return y;
}

}  // namespace

double rmse(const rt::Image& a, const rt::Image& r) {
  check_sizes(a, r);
  double sum = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    double d = double(a.rgb[i]) - r.rgb[i];
    sum += d * d;
  }
  return a.rgb.empty() ? 0 : std::sqrt(sum / a.rgb.size());
}

double relative_mse(const rt::Image& a, const rt::Image& r) {
  check_sizes(a, r);
  double sum = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    double d = double(a.rgb[i]) - r.rgb[i];
    sum += d * d / (double(r.rgb[i]) * r.rgb[i] + 0.01);
  }
  return a.rgb.empty() ? 0 : sum / a.rgb.size();
}

double ssim(const rt::Image& a, const rt::Image& r) {
  check_sizes(a, r);
  const int w = static_cast<int>(a.width), h = static_cast<int>(a.height);
  if (w == 0 || h == 0) return 1;
  std::vector<double> x = display_luma(a), y = display_luma(r);
  constexpr int R = 5;  // 11x11 window
  double g[2 * R + 1], gsum = 0;
  for (int i = -R; i <= R; ++i) gsum += g[i + R] = std::exp(-(i * i) / (2 * 1.5 * 1.5));
  for (double& v : g) v /= gsum;
  // Separable Gaussian blur with clamped borders.
  auto blur = [&](const std::vector<double>& in) {
    std::vector<double> tmp(in.size()), out(in.size());
    for (int py = 0; py < h; ++py)
      for (int px = 0; px < w; ++px) {
        double s = 0;
        for (int k = -R; k <= R; ++k) s += g[k + R] * in[py * w + std::clamp(px + k, 0, w - 1)];
        tmp[py * w + px] = s;
      }
    for (int py = 0; py < h; ++py)
      for (int px = 0; px < w; ++px) {
        double s = 0;
        for (int k = -R; k <= R; ++k) s += g[k + R] * tmp[std::clamp(py + k, 0, h - 1) * w + px];
        out[py * w + px] = s;
      }
    return out;
  };
  std::vector<double> xx(x.size()), yy(x.size()), xy(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    xx[i] = x[i] * x[i], yy[i] = y[i] * y[i], xy[i] = x[i] * y[i];
  std::vector<double> mx = blur(x), my = blur(y), sxx = blur(xx), syy = blur(yy), sxy = blur(xy);
  constexpr double C1 = 0.01 * 0.01, C2 = 0.03 * 0.03;
  double total = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i], cxy = sxy[i] - mx[i] * my[i];
    total += ((2 * mx[i] * my[i] + C1) * (2 * cxy + C2)) /
             ((mx[i] * mx[i] + my[i] * my[i] + C1) * (vx + vy + C2));
  }
  return total / x.size();
}

}  // namespace snell::cli
