// snell watch SCENE: compile, render progressively (1 sample per pixel, then 4,
// 16, ... up to the scene's samples, each pass adding to the last), show each pass
// on a page served on localhost (cli/watch_http.hpp) and optionally in tev
// (cli/tev.hpp), and start again whenever the scene or a file it reads changes
// (cli/file_watch.hpp), cancelling the render in flight. A scene with errors shows
// them on the page and waits for the next change; nothing in a scene ends the
// watch. Ends on SIGINT or SIGTERM (exit 0).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "cli/options.hpp"

namespace snell::cli {

// The passes' sample ranges [a, b) for `spp` samples per pixel: [0, 1), [1, 4),
// [4, 16), ... the last ending at spp. The sampler is a pure function of the
// sample index, so the passes together are the samples of one full render.
std::vector<std::pair<std::uint32_t, std::uint32_t>> watch_passes(std::uint32_t spp);

int run_watch(const CliArgs& o);

}  // namespace snell::cli
