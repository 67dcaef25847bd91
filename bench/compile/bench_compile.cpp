// Compile-time benchmark (issue: "a loop creating 1 000 000 spheres with random
// colours and radii: compile time and peak memory; target < 1 s and < 1 GiB").
// Runs the whole compiler in-process (parse, evaluate, lower) on a generated
// program; prints wall time per phase and peak resident memory.
//   bench_compile [N]      N spheres, default 1 000 000
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

#include "compiler/compile.hpp"

int main(int argc, char** argv) {
  long n = argc > 1 ? std::atol(argv[1]) : 1000000;
  std::string src = "for i in 0 .. " + std::to_string(n) + R"( {
  sphere {
    center <random(i) * 100 - 50, random(i + 0.5) * 10, random(i + 0.25) * 100 - 50>
    radius 0.05 + random(i + 0.75) * 0.2
    material diffuse <random(i * 3), random(i * 3 + 1), random(i * 3 + 2)>
  }
}
)";
  snell::compile::CompileOptions opts;
  auto t0 = std::chrono::steady_clock::now();
  auto c = snell::compile::compile_source("bench.scn", src, opts);
  auto t1 = std::chrono::steady_clock::now();
  if (c->status != snell::compile::CompileStatus::Ok) {
    c->diags.print(std::cerr);
    return 1;
  }
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  double secs = std::chrono::duration<double>(t1 - t0).count();
  std::printf("spheres            %ld\n", n);
  std::printf("materials          %zu (deduplicated)\n", c->scene.materials.size());
  std::printf("compile time       %.3f s  (%.0f ns per sphere)\n", secs, secs * 1e9 / n);
  std::printf("peak memory        %.1f MiB (%.0f bytes per sphere)\n", ru.ru_maxrss / 1024.0,
              ru.ru_maxrss * 1024.0 / n);
  std::printf("target             < 1 s and < 1024 MiB for 1e6 spheres: %s\n",
              secs < 1 && ru.ru_maxrss < 1024 * 1024 ? "met" : "NOT met");
  return 0;
}
