// A chi-square goodness-of-fit test of a direction sampler against a density, in the
// manner of pbrt-v4's bsdfs_test (after Jakob's Mitsuba test): bin N sampled
// directions on a spherical grid, integrate the claimed pdf over each bin for the
// expected counts, pool the bins expected to hold fewer than 5 samples (the
// chi-square approximation needs that), and turn the statistic into a p-value.
//
// The grid is built around an axis (the normal for a diffuse lobe, the mirror
// direction for a glossy one): `cap_rings` rings of equal solid angle inside the cap
// of half-angle `cap`, then `out_rings` rings of equal angular width out to the
// antipode, each cut into `nphi` sectors. A cap fitted to the lobe puts resolution
// where the mass is; the outer rings still cover the whole sphere, so misplaced
// samples (below the surface, folded, on the wrong side) land in some bin.
//
// Bin integrals are adaptive 3×3 Gauss–Legendre over (cos α, φ), in which the solid
// angle element is exactly dcos α·dφ. Densities with jumps (the glossy square's edge,
// the fold's edge, the horizon) are refined along the jump down to 1/256 of a bin's
// side. The error left is far below the Poisson deviation of a count: with 2e7
// samples (10× the tests') every glossy configuration below gives a statistic
// within 0.1 of the one from 1/1024 refinement and consistent with its dof, and
// the integrated mass is 1 + the edge allowance bsdf.hpp states (1.9e-6/blur).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "runtime/shading/bsdf.hpp"

namespace snell::test {

inline constexpr double kPiD = 3.14159265358979323846;

// Upper regularised incomplete gamma Q(a, x) = Γ(a, x)/Γ(a): series for P below
// x = a + 1, Lentz's continued fraction above (the textbook split; both converge to
// 1e-15 there). The chi-square p-value of statistic s with k degrees of freedom is
// Q(k/2, s/2).
inline double gamma_q(double a, double x) {
  if (!(x > 0)) return 1;
  double front = std::exp(-x + a * std::log(x) - std::lgamma(a));
  if (x < a + 1) {
    double ap = a, term = 1 / a, sum = term;
    for (int i = 0; i < 100000 && std::fabs(term) > std::fabs(sum) * 1e-16; ++i) {
      ap += 1;
      term *= x / ap;
      sum += term;
    }
    return std::fmax(0.0, 1 - sum * front);
  }
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    double del = d * c;
    h *= del;
    if (std::fabs(del - 1) < 1e-16) break;
  }
  return front * h;
}

inline double chi2_pvalue(double stat, int dof) {
  return gamma_q(0.5 * dof, 0.5 * stat);
}

// Šidák: the per-test level that keeps the chance of any false rejection among
// `tests` independent tests at `alpha`.
inline double sidak(double alpha, int tests) {
  return 1 - std::pow(1 - alpha, 1.0 / tests);
}

struct D3 {
  double x = 0, y = 0, z = 0;
};
inline D3 operator+(D3 a, D3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline D3 operator*(D3 a, double s) {
  return {a.x * s, a.y * s, a.z * s};
}
inline double dot(D3 a, D3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline D3 unit(D3 a) {
  return a * (1 / std::sqrt(dot(a, a)));
}
inline D3 to_d3(rt::Vec3f v) {
  return {v.x, v.y, v.z};
}
inline rt::Vec3f to_f(D3 v) {
  return {float(v.x), float(v.y), float(v.z)};
}

class SphereGrid {
 public:
  SphereGrid(rt::Vec3f axis, double cap, int cap_rings, int out_rings, int nphi)
      : cap_rings_(cap_rings), nphi_(nphi) {
    a_ = unit(to_d3(axis));
    // Duff et al.'s basis, in double.
    double sign = std::copysign(1.0, a_.z), k = -1 / (sign + a_.z), m = a_.x * a_.y * k;
    b1_ = {1 + sign * a_.x * a_.x * k, sign * m, -sign * a_.x};
    b2_ = {m, sign + a_.y * a_.y * k, -a_.y};
    double c0 = std::cos(cap);
    for (int i = 0; i <= cap_rings; ++i) edges_.push_back(1 - (1 - c0) * i / cap_rings);
    for (int i = 1; i <= out_rings; ++i)
      edges_.push_back(i == out_rings ? -1.0 : std::cos(cap + (kPiD - cap) * i / out_rings));
  }
  std::string to_string() const {
    return "sphere_grid { axis (" + std::to_string(a_.x) + ", " + std::to_string(a_.y) + ", " +
           std::to_string(a_.z) + ") cap_cos " + std::to_string(edges_[cap_rings_]) +
           " cap_rings " + std::to_string(cap_rings_) + " out_rings " +
           std::to_string(rings() - cap_rings_) + " sectors " + std::to_string(nphi_) + " }";
  }
  int rings() const { return int(edges_.size()) - 1; }
  int bins() const { return rings() * nphi_; }
  int bin(D3 w) const {
    w = unit(w);
    double c = std::clamp(dot(w, a_), -1.0, 1.0);
    // edges_ descend: the ring is the last i with c <= edges_[i].
    int lo = 0, hi = rings() - 1;
    while (lo < hi) {
      int mid = (lo + hi + 1) / 2;
      if (c <= edges_[mid])
        lo = mid;
      else
        hi = mid - 1;
    }
    double phi = std::atan2(dot(w, b2_), dot(w, b1_));
    if (phi < 0) phi += 2 * kPiD;
    int j = std::min(nphi_ - 1, int(phi / (2 * kPiD) * nphi_));
    return lo * nphi_ + j;
  }
  D3 dir(double c, double phi) const {
    double s = std::sqrt(std::fmax(0.0, 1 - c * c));
    return b1_ * (s * std::cos(phi)) + b2_ * (s * std::sin(phi)) + a_ * c;
  }
  // ∫ pdf dω over every bin. `region` names the piece of a piecewise-smooth density
  // a direction falls in (default: pdf > 0 or not); cells whose sample points see
  // more than one region hold a jump and are refined to full depth.
  std::vector<double> integrate(const std::function<double(D3)>& pdf,
                                const std::function<int(D3)>& region, double tol) const {
    std::vector<double> out(bins());
    auto f = [&](double c, double phi, Quad& q) {
      D3 w = dir(c, phi);
      double v = pdf(w);
      q.see(region ? region(w) : int(v > 0));
      return v;
    };
    for (int i = 0; i < rings(); ++i)
      for (int j = 0; j < nphi_; ++j) {
        double c1 = edges_[i], c0 = edges_[i + 1];
        double p0 = 2 * kPiD * j / nphi_, p1 = 2 * kPiD * (j + 1) / nphi_, sum = 0;
        constexpr int kPre = 4;  // pre-split: small features are not skipped over
        constexpr int kDepth = 6;
        for (int a = 0; a < kPre; ++a)
          for (int b = 0; b < kPre; ++b) {
            double ca = c0 + (c1 - c0) * a / kPre, cb = c0 + (c1 - c0) * (a + 1) / kPre;
            double pa = p0 + (p1 - p0) * b / kPre, pb = p0 + (p1 - p0) * (b + 1) / kPre;
            sum += adapt(f, ca, cb, pa, pb, gl3(f, ca, cb, pa, pb), tol, kDepth);
          }
        out[i * nphi_ + j] = sum;
      }
    return out;
  }

 private:
  // A 3×3 Gauss–Legendre estimate, and whether its points saw more than one region.
  struct Quad {
    double sum = 0;
    int region = -1;
    bool mixed = false;
    void see(int r) {
      if (region < 0)
        region = r;
      else if (r != region)
        mixed = true;
    }
    void merge(const Quad& o) {
      if (o.region >= 0) see(o.region);
      mixed |= o.mixed;
    }
  };
  template <class F>
  static Quad gl3(const F& f, double c0, double c1, double p0, double p1) {
    static const double x[3] = {-0.77459666924148338, 0.0, 0.77459666924148338};
    static const double w[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    double hc = 0.5 * (c1 - c0), mc = 0.5 * (c1 + c0), hp = 0.5 * (p1 - p0), mp = 0.5 * (p1 + p0);
    Quad q;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) q.sum += w[i] * w[j] * f(mc + hc * x[i], mp + hp * x[j], q);
    q.sum *= hc * hp;
    return q;
  }
  // Refine where the children disagree with the parent by more than tol, and always
  // (down to `depth`) where the cell's corners or nodes straddle a jump. Without
  // the second rule a cell whose nodes all miss a sliver of support stops with the
  // sliver uncounted, biasing every edge bin the same way (measured before it: a
  // 1.7e-5 mass deficit and a chi-square excess growing with n; for a folded
  // glossy lobe the jump from g(w) to g(w) + g(Mw) lies inside the support, which
  // is why regions, not just zero/nonzero, are compared).
  template <class F>
  static double adapt(const F& f, double c0, double c1, double p0, double p1, Quad coarse,
                      double tol, int depth) {
    double cm = 0.5 * (c0 + c1), pm = 0.5 * (p0 + p1);
    Quad q[4] = {gl3(f, c0, cm, p0, pm), gl3(f, cm, c1, p0, pm), gl3(f, c0, cm, pm, p1),
                 gl3(f, cm, c1, pm, p1)};
    double fine = q[0].sum + q[1].sum + q[2].sum + q[3].sum;
    Quad all = coarse;
    for (const Quad& k : q) all.merge(k);
    for (double c : {c0, c1})
      for (double p : {p0, p1}) f(c, p, all);
    if (depth == 0 || (!all.mixed && std::fabs(fine - coarse.sum) <= tol)) return fine;
    return adapt(f, c0, cm, p0, pm, q[0], tol / 2, depth - 1) +
           adapt(f, cm, c1, p0, pm, q[1], tol / 2, depth - 1) +
           adapt(f, c0, cm, pm, p1, q[2], tol / 2, depth - 1) +
           adapt(f, cm, c1, pm, p1, q[3], tol / 2, depth - 1);
  }

  D3 a_, b1_, b2_;
  std::vector<double> edges_;  // cos α at ring boundaries, from 1 down to -1
  int cap_rings_, nphi_;
};

struct Chi2Result {
  double stat = 0, p = 0;
  int dof = 0;
  double mass = 0;      // ∫ pdf over the sphere, from the bins
  long continuous = 0;  // samples binned (non-delta, valid)
  bool rejected = false;
  std::string why;
};

inline std::string to_string(const Chi2Result& r) {
  return "chi2 { stat " + std::to_string(r.stat) + " dof " + std::to_string(r.dof) + " p " +
         std::to_string(r.p) + " mass " + std::to_string(r.mass) + " binned " +
         std::to_string(r.continuous) + (r.rejected ? " REJECTED: " + r.why : "") + " }";
}

// `sample` draws one BsdfSample from the random numbers given; delta and invalid
// samples are not binned but counted in one "remainder" cell whose expectation is
// n·(1 − mass), so a lobe that mixes a delta (the glazed coat) is tested whole.
// `region`: see SphereGrid::integrate.
inline Chi2Result chi2_test(const SphereGrid& grid,
                            const std::function<rt::BsdfSample(rt::BsdfU)>& sample,
                            const std::function<double(D3)>& pdf, long n, double level,
                            std::uint64_t seed, const std::function<int(D3)>& region = {}) {
  std::mt19937_64 rng(seed);
  auto u24 = [&] { return float(rng() >> 40) * (1.0f / 16777216.0f); };
  std::vector<double> obs(grid.bins() + 1, 0.0);
  Chi2Result r;
  for (long i = 0; i < n; ++i) {
    rt::BsdfU u;
    u.c = u24();
    u.u = u24();
    u.v = u24();
    rt::BsdfSample s = sample(u);
    if (!s.ok() || s.kind == rt::LobeKind::Delta) {
      obs.back() += 1;
      continue;
    }
    obs[grid.bin(to_d3(s.wi))] += 1;
    ++r.continuous;
  }
  // Per-bin integration tolerance: 0.01 expected samples.
  std::vector<double> ex = grid.integrate(pdf, region, 0.01 / double(n));
  for (double& e : ex) {
    r.mass += e;
    e *= double(n);
  }
  double rest = double(n) * (1 - r.mass);
  // The remainder cell is only a cell when something is expected there; otherwise
  // its expectation is integration noise (|1 - mass| ~ 1e-6) and it must be empty.
  ex.push_back(rest >= 1 ? rest : 0.0);
  std::vector<int> order(ex.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = int(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return ex[a] < ex[b]; });
  double pool_o = 0, pool_e = 0;
  int cells = 0;
  for (int i : order) {
    if (ex[i] == 0) {
      // pbrt's lenience for rounding: a few samples where the density is 0.
      if (obs[i] > double(n) * 1e-5) {
        r.rejected = true;
        r.why = std::to_string(obs[i]) + " samples in bin " + std::to_string(i) +
                " whose expected count is 0";
        return r;
      }
    } else if (ex[i] < 5 || (pool_e > 0 && pool_e < 5)) {
      pool_o += obs[i];
      pool_e += ex[i];
    } else {
      double d = obs[i] - ex[i];
      r.stat += d * d / ex[i];
      ++cells;
    }
  }
  if (pool_e > 0) {
    double d = pool_o - pool_e;
    r.stat += d * d / pool_e;
    ++cells;
  }
  r.dof = cells - 1;
  if (r.dof < 1) {
    r.rejected = true;
    r.why = "too few cells";
    return r;
  }
  r.p = chi2_pvalue(r.stat, r.dof);
  if (!(r.p >= level)) {
    r.rejected = true;
    r.why = "p-value below " + std::to_string(level);
  }
  return r;
}

}  // namespace snell::test
