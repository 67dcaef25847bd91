// What several benchmarks write or read: resident memory, and a tessellated
// sphere as an OBJ file.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace snell::bench {

// Resident memory now, in MiB (Linux /proc/self/statm).
inline double rss_mib() {
  std::ifstream f("/proc/self/statm");
  long pages = 0, resident = 0;
  f >> pages >> resident;
  return double(resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

// The rings of write_sphere_obj for about `tris` triangles.
inline int sphere_obj_rings(long tris) {
  return std::max(4, int(std::sqrt(double(tris) / 2)));
}

// A closed unit sphere as a latitude-longitude grid of n = sphere_obj_rings(tris)
// rings of n segments, 2n(n-1) triangles: fans at the poles and, between rings,
// quads (`f` with four corners, split by the reader) or two triangles each.
inline std::string write_sphere_obj(const std::filesystem::path& dir, long tris, bool quads = true,
                                    const char* name = "sphere.obj") {
  int n = sphere_obj_rings(tris);
  std::string path = (dir / name).string();
  std::ofstream f(path);
  const double pi = 3.14159265358979323846;
  f << "v 0 1 0\nv 0 -1 0\n";
  for (int i = 1; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double th = pi * i / n, ph = 2 * pi * j / n;
      f << "v " << std::sin(th) * std::cos(ph) << " " << std::cos(th) << " "
        << std::sin(th) * std::sin(ph) << "\n";
    }
  auto v = [&](int i, int j) { return 3 + (i - 1) * n + (j % n); };  // 1-based, rings 1..n-1
  for (int j = 0; j < n; ++j) f << "f 1 " << v(1, j + 1) << " " << v(1, j) << "\n";
  for (int i = 1; i + 1 < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (quads)
        f << "f " << v(i, j) << " " << v(i, j + 1) << " " << v(i + 1, j + 1) << " " << v(i + 1, j)
          << "\n";
      else
        f << "f " << v(i, j) << " " << v(i, j + 1) << " " << v(i + 1, j + 1) << "\n"
          << "f " << v(i, j) << " " << v(i + 1, j + 1) << " " << v(i + 1, j) << "\n";
    }
  for (int j = 0; j < n; ++j) f << "f 2 " << v(n - 1, j) << " " << v(n - 1, j + 1) << "\n";
  return path;
}

}  // namespace snell::bench
