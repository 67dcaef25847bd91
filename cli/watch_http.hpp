// snell watch's page: a small HTTP server on 127.0.0.1 (cpp-httplib) serving the
// newest state of the watch loop. The loop publishes into it; the server's
// threads only read copies under its lock, so a slow browser never holds up a
// render.
//   GET /            the page (cli/watch_page.cpp)
//   GET /state       JSON: revisions, status, diagnostics, statistics, image size and spp
//   GET /image.png   the newest pass through the display transform (as snell render's PNG)
//   GET /image.f32   its linear RGB as raw little-endian float32, row-major (X-Width, X-Height)
//   GET /pixel?x=&y= JSON: the linear RGB of one pixel
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "runtime/render.hpp"

namespace snell::cli {

class WatchPage {
 public:
  explicit WatchPage(std::string scene);
  ~WatchPage();
  WatchPage(const WatchPage&) = delete;
  WatchPage& operator=(const WatchPage&) = delete;

  // Binds 127.0.0.1:`port` (0: any free port) and serves on a thread of its own.
  // False with `error` set when the port cannot be had.
  bool start(int port, std::string& error);
  int port() const;
  void stop();

  // What the loop is doing: "compiling", "rendering pass 2/4 (4 spp)", ...
  void set_status(const std::string& status);
  // The compiler's diagnostics as text (file:line:col: ...), and whether they stop
  // the render (the image shown is then the last good one).
  void set_diagnostics(const std::string& text, bool errors);
  // A finished pass: its linear pixels, their PNG, the samples per pixel so far
  // and the statistics text.
  void set_image(rt::Image linear, std::vector<unsigned char> png, std::uint32_t spp,
                 std::uint32_t target_spp, const std::string& stats);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The page's HTML (with its script and style).
const char* watch_page_html();

}  // namespace snell::cli
