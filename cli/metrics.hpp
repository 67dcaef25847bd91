// Image error metrics for the accuracy-versus-time study (snell sweep).
// All take a test image and a reference of the same size (linear radiance).
#pragma once

#include "runtime/render.hpp"

namespace snell::cli {

// Root mean squared error over every pixel and channel, in radiance units.
double rmse(const rt::Image& image, const rt::Image& reference);

// Relative MSE: mean over pixels and channels of (x − r)² / (r² + 0.01), as in
// Rousselle et al. 2011; the 0.01 keeps black pixels from dominating.
double relative_mse(const rt::Image& image, const rt::Image& reference);

// Structural similarity (Wang et al. 2004) of the display-referred luminance:
// both images are clamped to [0, 1], sRGB-encoded, reduced to Rec.709 luma, and
// compared with an 11x11 Gaussian window (σ = 1.5), C1 = (0.01)², C2 = (0.03)².
// 1 means identical; the sweep reports 1 − SSIM as the perceptual error ("DSSIM").
double ssim(const rt::Image& image, const rt::Image& reference);

}  // namespace snell::cli
