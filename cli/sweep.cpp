#include "cli/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/metrics.hpp"
#include "cli/plot_svg.hpp"
#include "compiler/compile.hpp"
#include "language/diagnostics.hpp"
#include "runtime/atomic_file.hpp"
#include "runtime/render.hpp"

namespace snell::cli {

namespace fs = std::filesystem;

bool parse_axis(const std::string& text, SweepAxis& axis) {
  auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) return false;
  axis.key = text.substr(0, eq);
  axis.values.clear();
  // Values are separated by commas outside <...> (a value may be a vector).
  std::string cur;
  int depth = 0;
  for (char c : text.substr(eq + 1)) {
    if (c == '<') ++depth;
    if (c == '>') --depth;
    if (c == ',' && depth == 0) {
      axis.values.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  axis.values.push_back(cur);
  for (const std::string& v : axis.values)
    if (v.empty()) return false;
  return true;
}

namespace {

struct Config {
  std::vector<std::pair<std::string, std::string>> settings;  // compile overrides
  int area_samples = 0;                                       // 0: as written
  bool general_kernel = false;
};

// Applies one knob value to a configuration; false for an unknown knob value.
bool apply(Config& c, const std::string& key, const std::string& value, std::string& error) {
  if (key == "area_samples") {
    char* end = nullptr;
    long n = std::strtol(value.c_str(), &end, 10);
    if (*end || n < 1 || n > 256) {
      error = "area_samples takes an integer from 1 to 256, not '" + value + "'";
      return false;
    }
    c.area_samples = static_cast<int>(n);
  } else if (key == "kernel") {
    if (value != "specialised" && value != "general") {
      error = "kernel takes 'specialised' or 'general', not '" + value + "'";
      return false;
    }
    c.general_kernel = value == "general";
  } else {
    // Checked here, not by the compiler, so the message lists sweep's own knobs.
    std::vector<std::string_view> keys = compile::setting_keys();
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      keys.push_back("area_samples"), keys.push_back("kernel");
      const std::string guess = lang::closest_match(key, keys);
      error = "--vary " + key + "=" + value + ": unknown key '" + key + "'" +
              (guess.empty() ? "" : " (did you mean '" + guess + "'?)") + "; keys are ";
      for (std::size_t i = 0; i < keys.size(); ++i) error += (i ? ", " : "") + std::string(keys[i]);
      return false;
    }
    c.settings.push_back({key, value});
  }
  return true;
}

std::string label(const std::string& key, const std::string& value) {
  if (key == "samples") return value + " spp";
  if (key == "area_samples") return value + "x" + value;
  return value;
}

std::string slug(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-') c = '_';
  return s;
}

// The files a sweep writes per axis, in --out: a configuration's image (value v,
// series value sv) and the axis's plot.
std::string image_name(const std::string& stem, const std::string& key, const std::string& v,
                       const std::string& sv) {
  return "images/" + slug(stem + "-" + key + "-" + v + (sv.empty() ? "" : "-" + sv)) + ".png";
}
std::string plot_name(const std::string& stem, const std::string& key) {
  return slug(stem + "-" + key) + ".svg";
}

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : s) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

// Whole or not at all (atomic_file.hpp); an error message naming the file, or "".
std::string save_raw(const std::string& path, const rt::Image& img) {
  std::string bytes = "SNELLREF";
  bytes.append(reinterpret_cast<const char*>(&img.width), 4);
  bytes.append(reinterpret_cast<const char*>(&img.height), 4);
  bytes.append(reinterpret_cast<const char*>(img.rgb.data()), img.rgb.size() * 4);
  return rt::write_file_atomically(path, bytes.data(), bytes.size());
}

// The folder `dir` made (with its parents); an error message naming it, or "".
std::string make_folder(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return "cannot create the folder " + dir.string() + ": " + ec.message();
  return {};
}

bool load_raw(const std::string& path, rt::Image& img) {
  std::ifstream in(path, std::ios::binary);
  char magic[8];
  if (!in.read(magic, 8) || std::string(magic, 8) != "SNELLREF") return false;
  in.read(reinterpret_cast<char*>(&img.width), 4);
  in.read(reinterpret_cast<char*>(&img.height), 4);
  img.rgb.resize(std::size_t(img.width) * img.height * 3);
  in.read(reinterpret_cast<char*>(img.rgb.data()), std::streamsize(img.rgb.size() * 4));
  return bool(in);
}

class Sweeper {
 public:
  explicit Sweeper(const SweepOptions& o) : o_(o) {}

  // Compiles the scene with a configuration's settings; prints diagnostics.
  bool compile(const Config& c, ir::Scene& out, int& code) {
    compile::CompileOptions copts = o_.compile;
    // Its errors name the sweep's own option (the user wrote no --set).
    copts.override_labels.resize(copts.overrides.size());
    for (const auto& kv : c.settings) {
      copts.overrides.push_back(kv);
      copts.override_labels.push_back("--vary " + kv.first + "=" + kv.second);
    }
    auto comp = compile::compile_file(o_.scene, copts);
    comp->diags.print(std::cerr);
    switch (comp->status) {
      case compile::CompileStatus::Ok:
        break;
      case compile::CompileStatus::SceneErrors:
      case compile::CompileStatus::FileErrors:
        std::cerr << error_count_line(comp->diags, o_.scene);
        code = comp->status == compile::CompileStatus::FileErrors ? kExitIo : kExitScene;
        return false;
      case compile::CompileStatus::UsageError:
        std::cerr << "snell sweep: error: " << comp->message << "\n";
        code = kExitUsage;
        return false;
      case compile::CompileStatus::IoError:
        std::cerr << "snell sweep: error: " << comp->message << "\n";
        code = kExitIo;
        return false;
    }
    out = std::move(comp->scene);
    if (c.area_samples > 0)
      for (ir::AreaLight& l : out.area_lights)
        l.samples_u = l.samples_v = static_cast<std::uint32_t>(c.area_samples);
    return true;
  }

  rt::RenderResult render(const ir::Scene& scene, bool general, double& seconds) {
    rt::RenderOptions ro;
    ro.threads = o_.threads;
    ro.general_kernel = general;
    auto t0 = std::chrono::steady_clock::now();
    rt::RenderResult r = rt::render(scene, ro);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }

  // The converged reference: many samples, exact Fresnel, the split tree, a deep
  // tree, dense area-light grids, and a seed of its own so its noise is
  // independent of the renders it judges. Weak branches end by Russian roulette
  // below 0.01, which is unbiased (tests/runtime/test_branching.cpp) and keeps
  // the tree finite: with no pruning at all, stacked glass grows towards 2^depth
  // nodes per sample. Cached by the hash of its IR dump.
  bool reference(rt::Image& ref, int& code) {
    Config c;
    c.settings = {{"samples", std::to_string(o_.reference_spp)},
                  {"fresnel", "exact"},
                  {"branching", "split"},
                  {"termination", "roulette"},
                  {"min_weight", "0.01"}};
    ir::Scene scene;
    if (!compile(c, scene, code)) return false;
    scene.settings.max_depth = std::max<std::uint32_t>(scene.settings.max_depth, 16);
    scene.settings.seed ^= 0x5eed5eedull;
    for (ir::AreaLight& l : scene.area_lights) {
      l.samples_u = std::max<std::uint32_t>(l.samples_u, 4);
      l.samples_v = std::max<std::uint32_t>(l.samples_v, 4);
    }
    if (std::string e = make_folder(fs::path(o_.out_dir) / "cache"); !e.empty()) {
      std::cerr << "snell sweep: error: " << e << "\n";
      code = kExitIo;
      return false;
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx",
                  static_cast<unsigned long long>(fnv1a(ir::to_string(scene))));
    std::string path =
        (fs::path(o_.out_dir) / "cache" / ("ref-" + std::string(hex) + ".bin")).string();
    if (load_raw(path, ref)) {
      if (!o_.quiet) std::cerr << "reference: cached " << path << "\n";
      return true;
    }
    if (!o_.quiet)
      std::cerr << "reference: rendering at " << o_.reference_spp << " spp (cached afterwards)\n";
    double secs;
    ref = render(scene, false, secs).image;
    if (!o_.quiet) std::cerr << "reference: " << secs << " s\n";
    if (std::string e = save_raw(path, ref); !e.empty()) {
      std::cerr << "snell sweep: error: " << e << "\n";
      code = kExitIo;
      return false;
    }
    return true;
  }

  int run() {
    int code = kExitOk;
    std::vector<std::string> series_values =
        o_.series.key.empty() ? std::vector<std::string>{""} : o_.series.values;
    // Every configuration of every axis compiled first: a value the scene refuses
    // (`--vary max_depth=2,-1`) or one that changes the image's size is wrong
    // usage found before the reference's seconds of rendering, and nothing is
    // written (the reference's cache and the images folder were left behind).
    struct Job {
      Config config;
      ir::Scene scene;
      SweepRow row;
      std::vector<double> times;
      rt::RenderResult first;
    };
    ir::Scene plain;
    if (!compile(Config{}, plain, code)) return code;
    std::vector<std::vector<Job>> axes;
    for (const SweepAxis& axis : o_.vary) {
      std::vector<Job>& jobs = axes.emplace_back();
      for (const std::string& sv : series_values)
        for (const std::string& v : axis.values) {
          Job j;
          std::string err;
          if ((!o_.series.key.empty() && !apply(j.config, o_.series.key, sv, err)) ||
              !apply(j.config, axis.key, v, err)) {
            std::cerr << "snell sweep: error: " << err << "\n";
            return kExitUsage;
          }
          if (!compile(j.config, j.scene, code)) return code;
          if (j.scene.settings.width != plain.settings.width ||
              j.scene.settings.height != plain.settings.height) {
            std::cerr << "snell sweep: error: '" << axis.key
                      << "' changes the resolution; sweep resolution with --res instead\n";
            return kExitUsage;
          }
          j.row.knob = axis.key;
          j.row.value = v;
          j.row.series_value = sv;
          jobs.push_back(std::move(j));
        }
    }
    rt::Image ref;
    if (!reference(ref, code)) return code;
    if (std::string e = make_folder(fs::path(o_.out_dir) / "images"); !e.empty()) {
      std::cerr << "snell sweep: error: " << e << "\n";
      return kExitIo;
    }
    std::string stem = o_.name.empty() ? fs::path(o_.scene).stem().string() : o_.name;
    for (std::size_t ai = 0; ai < o_.vary.size(); ++ai) {
      const SweepAxis& axis = o_.vary[ai];
      std::vector<Job>& jobs = axes[ai];
      // Repeats are interleaved: round r renders every configuration once, so a
      // change in the machine's load during the run falls on all of them alike
      // and the ratios between configurations hold.
      for (int rep = 0; rep < std::max(1, o_.repeats); ++rep)
        for (Job& j : jobs) {
          double secs;
          rt::RenderResult r = render(j.scene, j.config.general_kernel, secs);
          j.times.push_back(secs);
          if (rep == 0) j.first = std::move(r);
        }
      for (Job& j : jobs) {
        SweepRow& row = j.row;
        std::sort(j.times.begin(), j.times.end());
        row.seconds = j.times[j.times.size() / 2];
        row.seconds_min = j.times.front();
        const rt::Image& img = j.first.image;
        if (img.width != ref.width || img.height != ref.height) {  // a stale cached reference
          std::cerr << "snell sweep: error: the reference is " << ref.width << "x" << ref.height
                    << " and the render " << img.width << "x" << img.height << "\n";
          return kExitIo;
        }
        row.rmse = rmse(img, ref);
        row.relmse = relative_mse(img, ref);
        row.dssim = 1 - ssim(img, ref);
        const rt::RenderStats& st = j.first.stats;
        row.rays = st.camera_rays + st.shadow_rays + st.reflection_rays + st.refraction_rays +
                   st.glossy_rays;
        const std::string& v = row.value;
        const std::string& sv = row.series_value;
        if (o_.images) {
          row.image = image_name(stem, axis.key, v, sv);
          rt::OutputInfo info;
          info.scene_path = o_.scene;
          info.samples = j.scene.settings.samples;
          info.seed = j.scene.settings.seed;
          std::string e =
              rt::write_image((fs::path(o_.out_dir) / row.image).string(), img, info, {});
          if (!e.empty()) {
            std::cerr << "snell sweep: error: " << e << "\n";
            return kExitIo;
          }
        }
        if (!o_.quiet)
          std::fprintf(stderr, "%-14s %-12s %-12s %8.3f s  rmse %.5f  relmse %.5f  dssim %.5f\n",
                       axis.key.c_str(), v.c_str(), sv.c_str(), row.seconds, row.rmse, row.relmse,
                       row.dssim);
        rows_.push_back(row);
      }
    }
    if (std::string e = write_outputs(stem); !e.empty()) {
      std::cerr << "snell sweep: error: " << e << "\n";
      return kExitIo;
    }
    return kExitOk;
  }

 private:
  // Each file whole or not at all; the first failure's message, or "".
  std::string write_outputs(const std::string& stem);
  std::string reading(const SweepAxis& axis) const;

  const SweepOptions& o_;
  std::vector<SweepRow> rows_;
  std::string link_;  // from the Markdown's folder to --out, "" or ending in '/'
};

std::string pct(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.0f %%", x * 100);
  return b;
}

std::string num(double x, const char* f = "%.3g") {
  char b[32];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

// A plain reading of one knob's rows, computed from the numbers.
std::string Sweeper::reading(const SweepAxis& axis) const {
  std::vector<const SweepRow*> rows;
  for (const SweepRow& r : rows_)
    if (r.knob == axis.key) rows.push_back(&r);
  std::string out;
  if (!o_.series.key.empty() && o_.series.values.size() >= 2) {
    // Each later series value against the first, value by value.
    const std::string& base = o_.series.values[0];
    for (std::size_t s = 1; s < o_.series.values.size(); ++s) {
      const std::string& other = o_.series.values[s];
      double tr = 0, er = 0;
      int n = 0;
      for (const SweepRow* a : rows)
        for (const SweepRow* b : rows)
          if (a->series_value == base && b->series_value == other && a->value == b->value &&
              a->seconds > 0 && a->rmse > 0) {
            tr += std::log(b->seconds / a->seconds);
            er += std::log(b->rmse / a->rmse);
            ++n;
          }
      if (n == 0) continue;
      double t = std::exp(tr / n), e = std::exp(er / n);
      out += "- `" + o_.series.key + " " + other + "` against `" + base +
             "` (geometric mean over the " + std::to_string(n) + " values of `" + axis.key +
             "`): " + (t < 1 ? pct(1 - t) + " less time" : pct(t - 1) + " more time") +
             ", RMSE × " + num(e) + ".\n";
    }
  }
  // A comparison at about equal time: the pair (first curve, other curve) whose
  // times are closest, among the slowest configurations, shown side by side. The
  // sweep's steps (sample counts doubling) leave them up to about 2x apart.
  if (o_.images && !o_.series.key.empty() && o_.series.values.size() >= 2) {
    const SweepRow *pa = nullptr, *pb = nullptr;
    double best = 1e300;
    for (const SweepRow* a : rows)
      for (const SweepRow* b : rows)
        if (a->series_value == o_.series.values[0] && b->series_value == o_.series.values[1] &&
            a->seconds > 0 && b->seconds > 0) {
          // Prefer close times, then long renders (less timing noise).
          double score = std::fabs(std::log(a->seconds / b->seconds)) - 0.01 * std::log(a->seconds);
          if (score < best) best = score, pa = a, pb = b;
        }
    if (pa && pb && !pa->image.empty() && !pb->image.empty())
      out += "- Nearest in time (" + num(pa->seconds) + " s and " + num(pb->seconds) +
             " s): left `" + o_.series.key + " " + pa->series_value + "`, `" + axis.key + " " +
             pa->value + "` (RMSE " + num(pa->rmse) + "); right `" + o_.series.key + " " +
             pb->series_value + "`, `" + axis.key + " " + pb->value + "` (RMSE " + num(pb->rmse) +
             ").\n\n  ![](" + link_ + pa->image + ") ![](" + link_ + pb->image + ")\n";
  }
  // Slope of log error against log time along each curve.
  std::map<std::string, std::vector<const SweepRow*>> curves;
  for (const SweepRow* r : rows) curves[r->series_value].push_back(r);
  for (const auto& [sv, pts] : curves) {
    if (pts.size() < 3) continue;
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (const SweepRow* r : pts) {
      if (!(r->seconds > 0) || !(r->rmse > 0)) continue;
      double x = std::log(r->seconds), y = std::log(r->rmse);
      sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
    }
    if (n < 3 || sxx * n - sx * sx <= 0) continue;
    double k = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    out += "- " +
           (sv.empty() ? std::string("Along `") + axis.key + "`"
                       : "`" + o_.series.key + " " + sv + "`") +
           ": RMSE ∝ time^" + num(k, "%.2f") +
           (std::fabs(k + 0.5) < 0.15 ? " (the Monte Carlo rate, 1/√time)" : "") + ".\n";
  }
  // Monte Carlo efficiency is 1 / (MSE × time): halving the error by averaging
  // costs four times the time, so this ranks configurations fairly.
  const SweepRow* best = nullptr;
  auto cost = [](const SweepRow* r) { return r->rmse * r->rmse * r->seconds; };
  for (const SweepRow* r : rows)
    if (!best || cost(r) < cost(best)) best = r;
  if (best)
    out +=
        "- Most efficient (lowest MSE × time): `" + axis.key + " " + best->value + "`" +
        (best->series_value.empty() ? ""
                                    : " with `" + o_.series.key + " " + best->series_value + "`") +
        " (" + num(best->seconds) + " s, RMSE " + num(best->rmse) + ").\n";
  return out;
}

std::string Sweeper::write_outputs(const std::string& stem) {
  fs::path dir(o_.out_dir);
  auto save = [](const fs::path& path, const std::string& text) {
    return rt::write_file_atomically(path.string(), text.data(), text.size());
  };
  // Texts as written (a path, `sampler="sobol"`) may hold quotes and commas: CSV
  // fields are quoted where they need it (RFC 4180: "" for a quote), and the JSON
  // is nlohmann's (escaped strings; a non-finite number is null).
  auto field = [](const std::string& s) {
    if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  };
  std::ostringstream csv;
  csv << "scene,knob,value,series_key,series_value,seconds_median,seconds_min,rays,rmse,relmse,"
         "dssim,image\n";
  for (const SweepRow& r : rows_)
    csv << field(o_.scene) << ',' << field(r.knob) << ',' << field(r.value) << ','
        << field(o_.series.key) << ',' << field(r.series_value) << ',' << r.seconds << ','
        << r.seconds_min << ',' << r.rays << ',' << r.rmse << ',' << r.relmse << ',' << r.dssim
        << ',' << field(r.image) << '\n';
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const SweepRow& r : rows_)
    rows.push_back({{"knob", r.knob},
                    {"value", r.value},
                    {"series", r.series_value},
                    {"seconds", r.seconds},
                    {"seconds_min", r.seconds_min},
                    {"rays", r.rays},
                    {"rmse", r.rmse},
                    {"relmse", r.relmse},
                    {"dssim", r.dssim},
                    {"image", r.image}});
  const nlohmann::ordered_json doc = {{"scene", o_.scene},
                                      {"reference_spp", o_.reference_spp},
                                      {"repeats", o_.repeats},
                                      {"rows", std::move(rows)}};
  std::ostringstream json;
  json << doc.dump(2) << '\n';
  // The Markdown's links to the plots and images in --out, from its own folder
  // (it may lie elsewhere: docs/accuracy/ beside build/sweeps/).
  if (!o_.markdown.empty()) {
    std::error_code ec;
    const fs::path from = fs::weakly_canonical(fs::absolute(o_.markdown), ec).parent_path();
    const fs::path rel = fs::weakly_canonical(fs::absolute(dir), ec).lexically_relative(from);
    link_ = rel.empty() || rel == "." ? "" : rel.generic_string() + "/";
  }
  std::ostringstream md;
  for (const SweepAxis& axis : o_.vary) {
    Plot plot;
    plot.title = stem + ": error versus time, varying " + axis.key;
    plot.x_label = "render time (s, median of " + std::to_string(o_.repeats) + ")";
    plot.y_label = "RMSE against the reference";
    std::vector<std::string> svs =
        o_.series.key.empty() ? std::vector<std::string>{""} : o_.series.values;
    for (const std::string& sv : svs) {
      PlotSeries s;
      s.name = sv.empty() ? axis.key : o_.series.key + " " + sv;
      // Points are labelled on the first curve only: curves often lie close.
      bool first = plot.series.empty();
      for (const SweepRow& r : rows_)
        if (r.knob == axis.key && r.series_value == sv)
          s.points.push_back({r.seconds, r.rmse, first ? label(axis.key, r.value) : ""});
      plot.series.push_back(std::move(s));
    }
    std::string svg_name = plot_name(stem, axis.key);
    if (std::string e = save(dir / svg_name, render_svg(plot)); !e.empty()) return e;
    md << "### " << stem << ": " << axis.key << (o_.series.key.empty() ? "" : " × " + o_.series.key)
       << "\n\n";
    md << "![" << plot.title << "](" << link_ << svg_name << ")\n\n";
    md << "| " << axis.key << " |" << (o_.series.key.empty() ? "" : " " + o_.series.key + " |")
       << " time (s) | RMSE | relMSE | 1 − SSIM | rays |\n|---|"
       << (o_.series.key.empty() ? "" : "---|") << "---|---|---|---|---|\n";
    for (const SweepRow& r : rows_)
      if (r.knob == axis.key)
        md << "| " << r.value << " |" << (o_.series.key.empty() ? "" : " " + r.series_value + " |")
           << " " << num(r.seconds) << " | " << num(r.rmse) << " | " << num(r.relmse) << " | "
           << num(r.dssim) << " | " << r.rays << " |\n";
    md << "\n" << reading(axis) << "\n";
  }
  for (const auto& [path, text] :
       {std::pair{dir / (stem + ".csv"), csv.str()}, std::pair{dir / (stem + ".json"), json.str()}})
    if (std::string e = save(path, text); !e.empty()) return e;
  if (!o_.markdown.empty())
    if (std::string e = save(o_.markdown, md.str()); !e.empty()) return e;
  if (!o_.quiet) std::cerr << "wrote " << (dir / (stem + ".csv")).string() << ", .json and plots\n";
  return {};
}

}  // namespace

int run_sweep(const SweepOptions& options) {
  if (options.vary.empty()) {
    std::cerr << "snell sweep: error: give at least one --vary KEY=V1,V2,...\n";
    return kExitUsage;
  }
  // --name is a prefix of file names in --out, not a path (a '/' in it sent the
  // CSV and JSON to a folder that was never made, after every render).
  const std::string& name = options.name;
  if (name.find_first_of("/\\") != std::string::npos || name == "." || name == "..")
    return usage_error("--name " + name + " is a prefix of the files in --out, not a path");
  // Nothing it writes may be a file it reads (§10): the scene by its own stem
  // beside the CSV, --markdown onto the scene, an image of it onto a texture.
  {
    std::vector<std::string> inputs{options.scene};
    auto comp = compile::compile_file(options.scene, options.compile);
    if (comp->status == compile::CompileStatus::Ok) inputs = scene_inputs(comp->scene);
    const fs::path dir(options.out_dir);
    const std::string stem = name.empty() ? fs::path(options.scene).stem().string() : name;
    std::vector<std::string> outputs{(dir / (stem + ".csv")).string(),
                                     (dir / (stem + ".json")).string()};
    if (!options.markdown.empty()) outputs.push_back(options.markdown);
    const std::vector<std::string> none{""};
    const std::vector<std::string>& series =
        options.series.key.empty() ? none : options.series.values;
    for (const SweepAxis& axis : options.vary) {
      outputs.push_back((dir / plot_name(stem, axis.key)).string());
      for (const std::string& sv : series)
        for (const std::string& v : axis.values)
          outputs.push_back((dir / image_name(stem, axis.key, v, sv)).string());
    }
    if (int code = check_not_an_input(outputs, inputs); code >= 0) return code;
    // --markdown may lie outside --out: a folder that is not there (or a folder
    // given as the file) is said now, not after every render.
    if (!options.markdown.empty())
      if (int code = check_output_folder(options.markdown); code >= 0) return code;
  }
  Sweeper s(options);
  return s.run();
}

}  // namespace snell::cli
