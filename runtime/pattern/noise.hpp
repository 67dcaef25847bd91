// The noise functions of §15, one definition for the whole project: the compiler's
// builtins (`noise(p)`, `fbm`, `turbulence`, `cells` at scene-build time), the
// patterns and the shading-function programs at render time all call these, so a
// value is the same wherever it is computed. Double precision, no tables but the
// reference permutation, no state: the same bits on every machine and thread.
//
// The exact formulas are in docs/language.md ("Patterns"); in short:
// - perlin: Perlin's improved noise (SIGGRAPH 2002): the quintic fade
//   6t⁵ − 15t⁴ + 10t³, the 12 cube-edge gradients picked by the reference
//   permutation; 0 at every integer lattice point, C² continuous, in [-1, 1].
// - fbm: Σ gain^i · perlin(lacunarity^i · p) over `octaves`, divided by Σ gain^i,
//   then 0.5 + 0.5·s (mean 0.5; 0.5 at the origin).
// - turbulence: the same sum of |perlin|, in [0, 1] (POV-Ray's turbulence).
// - cells: Worley's F1, the distance to the nearest of one feature point per unit
//   cell (placed by a 64-bit hash of the cell), at most √3.
// Inputs of magnitude past 2^52 have no fractional part left in double: noise is 0
// there (a lattice point), never undefined behaviour.
#pragma once

#include "runtime/ir/math.hpp"

namespace snell::pattern {

double perlin(ir::Vec3 p);
// perlin remapped to [0, 1]: 0.5 + 0.5·perlin, 0.5 at lattice points.
double noise(ir::Vec3 p);
double fbm(ir::Vec3 p, int octaves, double lacunarity = 2, double gain = 0.5);
double turbulence(ir::Vec3 p, int octaves, double lacunarity = 2, double gain = 0.5);
// A vector of three independent signed fbm sums (each in [-1, 1], mean 0): what
// `turbulence T` displaces a pattern's point by, times T.
ir::Vec3 vector_fbm(ir::Vec3 p, int octaves, double lacunarity = 2, double gain = 0.5);
double cells(ir::Vec3 p);

// The octave counts the functions accept: more only adds detail below double's
// resolution (2^-52 of the first octave) and costs time.
inline constexpr int kMaxOctaves = 32;

}  // namespace snell::pattern
