// RGB primaries: the matrix that takes linear RGB of a file's primaries and white
// point (OpenEXR's `chromaticities`, as OIIO reports it) to Snell's working
// space, linear Rec.709 primaries with a D65 white (the primaries of the shipped
// OCIO config's scene_linear and of sRGB). A white other than D65 is adapted with
// the Bradford transform, as ACES and most colour pipelines do. Limit: the target
// is Rec.709 whatever the OCIO config's scene_linear is; a config whose
// scene_linear has other primaries should tag its files by colour-space name.
#pragma once

#include <array>
#include <string>

namespace snell::rt {

// xy of red, green, blue and white, in OpenEXR's order.
using Chromaticities = std::array<float, 8>;
// Row-major 3×3: rec709 = M · file_rgb.
using Mat3f = std::array<float, 9>;

inline constexpr Chromaticities kRec709Chromaticities = {0.64f, 0.33f, 0.30f,   0.60f,
                                                         0.15f, 0.06f, 0.3127f, 0.3290f};

// The matrix from `c` to Rec.709/D65, or false with `error` when `c` is not a set
// of primaries (a non-finite value, y <= 0, or primaries on one line).
bool rec709_from(const Chromaticities& c, Mat3f& m, std::string& error);
// Whether `c` is Rec.709/D65 to within 1e-4 in x and y (files written with
// rounded primaries, e.g. 0.3127 stored as a float, still count).
bool is_rec709(const Chromaticities& c);
std::string to_string(const Chromaticities& c);

}  // namespace snell::rt
