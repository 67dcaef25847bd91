#include "runtime/pattern/noise.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace snell::pattern {

namespace {

// Perlin's reference permutation of 0..255 (the 2002 paper's implementation;
// tests/runtime/test_noise.cpp checks it is one).
constexpr std::uint8_t kPerm[256] = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,  103,
    30,  69,  142, 8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,  0,   26,
    197, 62,  94,  252, 219, 203, 117, 35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174,
    20,  125, 136, 171, 168, 68,  175, 74,  165, 71,  134, 139, 48,  27,  166, 77,  146, 158, 231,
    83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,  55,  46,  245, 40,  244, 102, 143,
    54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187, 208, 89,  18,  169, 200, 196,
    135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250, 124,
    123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212, 207, 206, 59,  227, 47,  16,  58,  17,
    182, 189, 28,  42,  223, 183, 170, 213, 119, 248, 152, 2,   44,  154, 163, 70,  221, 153, 101,
    155, 167, 43,  172, 9,   129, 22,  39,  253, 19,  98,  108, 110, 79,  113, 224, 232, 178, 185,
    112, 104, 218, 246, 97,  228, 251, 34,  242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,
    51,  145, 235, 249, 14,  239, 107, 49,  192, 214, 31,  181, 199, 106, 157, 184, 84,  204, 176,
    115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,  222, 114, 67,  29,  24,  72,  243,
    141, 128, 195, 78,  66,  215, 61,  156, 180};

inline int perm(int i) {
  return kPerm[i & 255];
}

// The paper's fade curve: zero first and second derivatives at 0 and 1.
inline double fade(double t) {
  return t * t * t * (t * (t * 6 - 15) + 10);
}

inline double lerp(double t, double a, double b) {
  return a + t * (b - a);
}

// The dot product with one of the 12 cube-edge directions (16 cases, four of them
// repeated, so the low 4 bits of the hash pick one without a division): ±u ± v,
// u = x (h < 8) or y, v = y (h < 4), x (h = 12, 14) or z, minus where bit 0 (u)
// or bit 1 (v) is set. By tables, without a branch: the hash is random, so the
// branches of the paper's form mispredicted about half the time (a third of
// noise's cost). A product by ±1 is the negation, bit for bit.
struct GradTable {
  std::uint8_t u[16] = {}, v[16] = {};
  double su[16] = {}, sv[16] = {};
  constexpr GradTable() {
    for (int h = 0; h < 16; ++h) {
      u[h] = h < 8 ? 0 : 1;
      v[h] = h < 4 ? 1 : (h == 12 || h == 14 ? 0 : 2);
      su[h] = (h & 1) == 0 ? 1.0 : -1.0;
      sv[h] = (h & 2) == 0 ? 1.0 : -1.0;
    }
  }
};
inline constexpr GradTable kGrad{};

inline double grad(int hash, double x, double y, double z) {
  const int h = hash & 15;
  const double c[3] = {x, y, z};
  return c[kGrad.u[h]] * kGrad.su[h] + c[kGrad.v[h]] * kGrad.sv[h];
}

// The lattice cell of x modulo 256 and the fraction within it. fmod is exact for
// every double, so this is right at any magnitude (past 2^52 the fraction is 0);
// below 2^31 the integer's low byte is the same residue without fmod's call (three
// per noise value, 3 % of a render of noise patterns).
inline void split(double x, int& cell, double& frac) {
  double f = std::floor(x);
  frac = x - f;
  if (std::fabs(f) < 0x1p31) {
    cell = int(f) & 255;
    return;
  }
  double m = std::fmod(f, 256.0);
  if (m < 0) m += 256;
  cell = int(m);
}

// The next octave's amplitude, amp · gain. Where that would overflow (a gain of
// 1e10 over 32 octaves reaches 1e310) the sums so far are scaled down with it
// first: only their ratio is used, and it stays the sum weighted towards the last
// octaves, where inf / inf was NaN. Gains up to 2^500 or so never take that path,
// so every ordinary sum keeps its bits.
inline void next_amplitude(double& amp, double gain, double& sum, double& norm) {
  if (amp > 0x1p1000 / gain) {
    const double s = 1 / amp;
    sum *= s, norm *= s, amp = 1;
  }
  amp *= gain;
}

double signed_fbm(ir::Vec3 p, int octaves, double lacunarity, double gain) {
  octaves = std::clamp(octaves, 1, kMaxOctaves);
  double sum = 0, norm = 0, amp = 1;
  for (int i = 0; i < octaves; ++i) {
    sum += amp * perlin(p);
    norm += amp;
    next_amplitude(amp, gain, sum, norm);
    p = p * lacunarity;
  }
  return norm > 0 ? sum / norm : 0;
}

// splitmix64's finaliser: a bijective mix of 64 bits (Steele, Lea & Flood 2014).
inline std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

inline double unit(std::uint64_t h) {
  return double(h >> 11) * 0x1.0p-53;  // [0, 1) from the top 53 bits
}

}  // namespace

double perlin(ir::Vec3 p) {
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return 0;
  int X, Y, Z;
  double x, y, z;
  split(p.x, X, x), split(p.y, Y, y), split(p.z, Z, z);
  double u = fade(x), v = fade(y), w = fade(z);
  int A = perm(X) + Y, AA = perm(A) + Z, AB = perm(A + 1) + Z;
  int B = perm(X + 1) + Y, BA = perm(B) + Z, BB = perm(B + 1) + Z;
  return lerp(
      w,
      lerp(v, lerp(u, grad(perm(AA), x, y, z), grad(perm(BA), x - 1, y, z)),
           lerp(u, grad(perm(AB), x, y - 1, z), grad(perm(BB), x - 1, y - 1, z))),
      lerp(v, lerp(u, grad(perm(AA + 1), x, y, z - 1), grad(perm(BA + 1), x - 1, y, z - 1)),
           lerp(u, grad(perm(AB + 1), x, y - 1, z - 1), grad(perm(BB + 1), x - 1, y - 1, z - 1))));
}

double noise(ir::Vec3 p) {
  return std::clamp(0.5 + 0.5 * perlin(p), 0.0, 1.0);
}

double fbm(ir::Vec3 p, int octaves, double lacunarity, double gain) {
  return std::clamp(0.5 + 0.5 * signed_fbm(p, octaves, lacunarity, gain), 0.0, 1.0);
}

double turbulence(ir::Vec3 p, int octaves, double lacunarity, double gain) {
  octaves = std::clamp(octaves, 1, kMaxOctaves);
  double sum = 0, norm = 0, amp = 1;
  for (int i = 0; i < octaves; ++i) {
    sum += amp * std::fabs(perlin(p));
    norm += amp;
    next_amplitude(amp, gain, sum, norm);
    p = p * lacunarity;
  }
  return norm > 0 ? std::clamp(sum / norm, 0.0, 1.0) : 0;
}

ir::Vec3 vector_fbm(ir::Vec3 p, int octaves, double lacunarity, double gain) {
  // Three sums at points far apart in the lattice (offsets that are not integers,
  // so no component is 0 wherever another is).
  return {signed_fbm(p, octaves, lacunarity, gain),
          signed_fbm(p + ir::Vec3(31.41, 17.73, 5.29), octaves, lacunarity, gain),
          signed_fbm(p + ir::Vec3(-11.87, 43.61, 23.19), octaves, lacunarity, gain)};
}

double cells(ir::Vec3 p) {
  // Past 2^52 every point is its own cell corner; a distance of 0 is as good as any.
  constexpr double kLimit = 4503599627370496.0;
  if (!(std::fabs(p.x) < kLimit && std::fabs(p.y) < kLimit && std::fabs(p.z) < kLimit)) return 0;
  double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
  auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy),
       iz = static_cast<std::int64_t>(fz);
  ir::Vec3 local{p.x - fx, p.y - fy, p.z - fz};
  double best = 1e300;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        std::uint64_t h = mix64(
            std::uint64_t(ix + dx) * 0x9e3779b97f4a7c15ull ^
            mix64(std::uint64_t(iy + dy) * 0xc2b2ae3d27d4eb4full ^ mix64(std::uint64_t(iz + dz))));
        ir::Vec3 f{dx + unit(h), dy + unit(mix64(h + 1)), dz + unit(mix64(h + 2))};
        ir::Vec3 d = f - local;
        best = std::fmin(best, ir::dot(d, d));
      }
  return std::sqrt(best);
}

}  // namespace snell::pattern
