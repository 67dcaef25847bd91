#include "cli/watch_http.hpp"

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

namespace snell::cli {

struct WatchPage::Impl {
  std::string scene;
  httplib::Server server;
  std::thread thread;
  std::atomic<bool> listen_returned{false};
  int port = 0;

  std::mutex mutex;
  // `revision` counts every change of the state, `image_revision` every new image:
  // the page polls /state and reloads the image only when the latter moved.
  std::uint64_t revision = 0, image_revision = 0;
  std::string status = "starting", diagnostics, stats;
  bool errors = false;
  std::shared_ptr<const rt::Image> linear;  // shared, so a reader copies no pixels
  std::shared_ptr<const std::vector<unsigned char>> png;
  std::uint32_t spp = 0, target_spp = 0;

  void routes();
};

namespace {
void no_store(httplib::Response& res) {
  // Every answer is the state of the moment: never cached.
  res.set_header("Cache-Control", "no-store");
}

// Whole numbers only, each within the image (the page sends what the cursor is
// over; anything else is a 400, never a crash).
bool parse_coord(const std::string& s, std::uint32_t limit, std::uint32_t& out) {
  if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos)
    return false;
  unsigned long v = std::stoul(s);
  if (v >= limit) return false;
  out = std::uint32_t(v);
  return true;
}

// JSON has no NaN or infinity; a non-finite pixel is sent as null.
nlohmann::json number(float v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}
}  // namespace

void WatchPage::Impl::routes() {
  server.Get("/", [](const httplib::Request&, httplib::Response& res) {
    no_store(res);
    res.set_content(watch_page_html(), "text/html; charset=utf-8");
  });
  server.Get("/state", [this](const httplib::Request&, httplib::Response& res) {
    nlohmann::json j;
    {
      std::lock_guard lock(mutex);
      j["scene"] = scene;
      j["revision"] = revision;
      j["image_revision"] = image_revision;
      j["status"] = status;
      j["diagnostics"] = diagnostics;
      j["errors"] = errors;
      j["stats"] = stats;
      j["spp"] = spp;
      j["target_spp"] = target_spp;
      j["width"] = linear ? linear->width : 0;
      j["height"] = linear ? linear->height : 0;
    }
    no_store(res);
    // Diagnostics quote the scene's text, which need not be valid UTF-8.
    res.set_content(j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                    "application/json");
  });
  server.Get("/image.png", [this](const httplib::Request&, httplib::Response& res) {
    std::shared_ptr<const std::vector<unsigned char>> p;
    {
      std::lock_guard lock(mutex);
      p = png;
    }
    no_store(res);
    if (!p) {
      res.status = 404;
      res.set_content("no image yet\n", "text/plain");
      return;
    }
    res.set_content(reinterpret_cast<const char*>(p->data()), p->size(), "image/png");
  });
  server.Get("/image.f32", [this](const httplib::Request&, httplib::Response& res) {
    std::shared_ptr<const rt::Image> im;
    {
      std::lock_guard lock(mutex);
      im = linear;
    }
    no_store(res);
    if (!im) {
      res.status = 404;
      res.set_content("no image yet\n", "text/plain");
      return;
    }
    res.set_header("X-Width", std::to_string(im->width));
    res.set_header("X-Height", std::to_string(im->height));
    res.set_content(reinterpret_cast<const char*>(im->rgb.data()), im->rgb.size() * sizeof(float),
                    "application/octet-stream");
  });
  server.Get("/pixel", [this](const httplib::Request& req, httplib::Response& res) {
    std::shared_ptr<const rt::Image> im;
    std::uint32_t n = 0;
    {
      std::lock_guard lock(mutex);
      im = linear;
      n = spp;
    }
    no_store(res);
    std::uint32_t x = 0, y = 0;
    nlohmann::json j;
    if (!im) {
      res.status = 404;
      j["error"] = "no image yet";
    } else if (!parse_coord(req.get_param_value("x"), im->width, x) ||
               !parse_coord(req.get_param_value("y"), im->height, y)) {
      res.status = 400;
      j["error"] = "x and y must be whole numbers inside the " + std::to_string(im->width) + "x" +
                   std::to_string(im->height) + " image";
    } else {
      const float* p = im->at(x, y);
      j = {{"x", x}, {"y", y}, {"rgb", {number(p[0]), number(p[1]), number(p[2])}}, {"spp", n}};
    }
    res.set_content(j.dump(), "application/json");
  });
}

WatchPage::WatchPage(std::string scene) : impl_(std::make_unique<Impl>()) {
  impl_->scene = std::move(scene);
  impl_->routes();
  // cpp-httplib's default is SO_REUSEPORT, with which a second snell watch on the
  // same port would bind too and the kernel would share the browsers between the
  // two. SO_REUSEADDR alone: a port in use is an error, a port just freed is not.
  impl_->server.set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  // A connection holds a worker while it is idle (a browser's keep-alive sockets,
  // a client that connects and sends nothing) for up to the timeouts below.
  // cpp-httplib's 8 workers and 5 s let a few tabs, or 8 idle sockets, stall every
  // other request for 5 s at a time; 64 workers and 2 s keep the page answering
  // (tests/watch/test_connections.py). Idle workers cost no CPU.
  impl_->server.new_task_queue = [] { return new httplib::ThreadPool(64); };
  impl_->server.set_keep_alive_timeout(2);
  impl_->server.set_read_timeout(2, 0);
}

WatchPage::~WatchPage() {
  stop();
}

bool WatchPage::start(int port, std::string& error) {
  Impl& m = *impl_;
  // Only this machine: the page shows the scene's text and paths.
  if (port == 0) {
    m.port = m.server.bind_to_any_port("127.0.0.1");
  } else if (m.server.bind_to_port("127.0.0.1", port)) {
    m.port = port;
  } else {
    m.port = -1;
  }
  if (m.port <= 0) {
    error = "cannot listen on 127.0.0.1:" + std::to_string(port) +
            " (in use? --port picks another; --port 0 any free one)";
    return false;
  }
  m.thread = std::thread([&m] {
    m.server.listen_after_bind();
    m.listen_returned = true;
  });
  return true;
}

int WatchPage::port() const {
  return impl_->port;
}

void WatchPage::stop() {
  if (!impl_->thread.joinable()) return;
  // httplib's stop() does nothing until listen has begun: a watch that ended at
  // once (a usage error in its options) hung in the join now and then.
  while (!impl_->server.is_running() && !impl_->listen_returned)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  impl_->server.stop();
  impl_->thread.join();
}

void WatchPage::set_status(const std::string& status) {
  std::lock_guard lock(impl_->mutex);
  impl_->status = status;
  ++impl_->revision;
}

void WatchPage::set_diagnostics(const std::string& text, bool errors) {
  std::lock_guard lock(impl_->mutex);
  impl_->diagnostics = text;
  impl_->errors = errors;
  ++impl_->revision;
}

void WatchPage::set_image(rt::Image linear, std::vector<unsigned char> png, std::uint32_t spp,
                          std::uint32_t target_spp, const std::string& stats) {
  auto im = std::make_shared<const rt::Image>(std::move(linear));
  auto p = std::make_shared<const std::vector<unsigned char>>(std::move(png));
  std::lock_guard lock(impl_->mutex);
  impl_->linear = std::move(im);
  impl_->png = std::move(p);
  impl_->spp = spp;
  impl_->target_spp = target_spp;
  impl_->stats = stats;
  ++impl_->image_revision;
  ++impl_->revision;
}

}  // namespace snell::cli
