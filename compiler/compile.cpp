#include "compiler/compile.hpp"

#include <pthread.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <unordered_map>

#include "compiler/properties.hpp"
#include "language/lexer.hpp"
#include "language/parser.hpp"

namespace snell::compile {

namespace fs = std::filesystem;
using lang::DiagKind;

std::string not_a_file(const std::string& path) {
  std::error_code ec;
  fs::file_status st = fs::status(path, ec);
  switch (st.type()) {
    case fs::file_type::regular:
      return "";
    case fs::file_type::not_found:
      return "does not exist";
    case fs::file_type::directory:
      return "is a folder, not a file";
    case fs::file_type::fifo:
      return "is a named pipe (FIFO), not a file";
    case fs::file_type::socket:
      return "is a socket, not a file";
    case fs::file_type::block:
    case fs::file_type::character:
      return "is a device, not a file";
    default:
      return ec ? "cannot be read: " + ec.message() : "is not a regular file";
  }
}

bool read_file(const std::string& path, std::string& text, std::string& message) {
  if (std::string why = not_a_file(path); !why.empty()) {
    message = "'" + path + "' " + why;
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    message = "cannot read '" + path + "': " + std::strerror(errno);
    return false;
  }
  // Read at most one byte past the lexer's limit: the lexer reports the size.
  text.clear();
  char buf[1 << 16];
  while (in && text.size() <= lang::kMaxSourceBytes) {
    in.read(buf, sizeof buf);
    text.append(buf, static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) {
    message = "error while reading '" + path + "'";
    return false;
  }
  return true;
}

void run_with_large_stack(const std::function<void()>& fn) {
  constexpr std::size_t kStack = std::size_t(1) << 30;  // reserved, touched only as used
  // An exception (out of memory) is carried to the calling thread and rethrown
  // there: escaping a thread's start routine would abort the program.
  struct Job {
    const std::function<void()>* fn;
    std::exception_ptr error;
  } job{&fn, nullptr};
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, kStack);
  pthread_t thread;
  auto trampoline = [](void* arg) -> void* {
    Job* j = static_cast<Job*>(arg);
    try {
      (*j->fn)();
    } catch (...) {
      j->error = std::current_exception();
    }
    return nullptr;
  };
  if (pthread_create(&thread, &attr, trampoline, &job) != 0) {
    pthread_attr_destroy(&attr);
    fn();  // no thread available: run here
    return;
  }
  pthread_attr_destroy(&attr);
  pthread_join(thread, nullptr);
  if (job.error) std::rethrow_exception(job.error);
}

std::string stdlib_dir(const CompileOptions& options) {
  if (!options.stdlib_dir.empty()) return options.stdlib_dir;
  if (const char* env = std::getenv("SNELL_STDLIB"); env && *env) return env;
  std::error_code ec;
  // Installed layout: <prefix>/bin/snell and <prefix>/share/snell/stdlib.
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    fs::path p = exe.parent_path().parent_path() / "share" / "snell" / "stdlib";
    if (fs::is_directory(p, ec)) return p.string();
  }
  if (fs::is_directory(SNELL_STDLIB_INSTALL_DIR, ec)) return SNELL_STDLIB_INSTALL_DIR;
  return SNELL_STDLIB_BUILD_DIR;
}

std::vector<std::string_view> setting_keys() {
  std::vector<std::string_view> keys;
  for (const PropInfo* p : find_block("settings")->props) keys.push_back(p->name);
  return keys;
}

std::string canonical_path(const std::string& path) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(path, ec);
  return ec ? fs::path(path).lexically_normal().string() : c.string();
}

// §17 writes `background sky_gradient`: a gradient along y over the unit
// direction, (y + 1) · 0.4995 (the pattern point is the direction moved up by 1),
// so the nadir is 0, the horizon 0.4995 and the zenith 0.999, never wrapping.
ir::Texture sky_gradient() {
  ir::Texture t;
  t.pattern = ir::Gradient{ir::Vec3(0, 0.4995, 0)};
  t.world_from_pattern = ir::Transform::translate(ir::Vec3(0, -1, 0));
  t.color_map = {{0, ir::Vec3(0.3, 0.28, 0.26)},
                 {0.4995, ir::Vec3(0.9, 0.93, 1)},
                 {0.999, ir::Vec3(0.22, 0.42, 0.85)}};
  return t;
}

std::string find_import(const std::string& name, const std::string& from,
                        const CompileOptions& options, std::vector<std::string>* searched,
                        bool* skipped_self) {
  std::vector<fs::path> dirs;
  if (!from.empty()) dirs.push_back(fs::path(from).parent_path());
  for (const std::string& d : options.include_dirs) dirs.push_back(d);
  dirs.push_back(stdlib_dir(options));
  if (searched)
    for (const fs::path& d : dirs) searched->push_back(d.string());
  // An open editor buffer counts as a file even before it is saved.
  auto exists = [&](const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec) || (options.overlay && options.overlay(canonical_path(p)));
  };
  if (fs::path(name).is_absolute()) return exists(name) ? name : "";
  // A file never means to import itself: `materials.scn` in a user's folder
  // that imports "materials.scn" gets the standard library's.
  std::string self = from.empty() ? "" : canonical_path(from);
  for (const fs::path& d : dirs) {
    fs::path p = d / name;
    if (!exists(p)) continue;
    if (canonical_path(p) == self) {
      if (skipped_self) *skipped_self = true;
      continue;
    }
    return p.string();
  }
  return "";
}

namespace {

class Driver {
 public:
  Driver(Compilation& c, const CompileOptions& o) : c_(c), opts_(o) {}

  const lang::Program* parse_file(const std::string& path, const std::string& text) {
    lang::FileId id = c_.sources.add(path, text);
    c_.programs.push_back(std::make_unique<lang::Program>(lang::parse(c_.sources, id, c_.diags)));
    return c_.programs.back().get();
  }

  const ImportedFile* load_import(const std::string& name, lang::Span span) {
    std::string from = span.file < c_.sources.size() ? c_.sources.file(span.file).path() : "";
    std::vector<std::string> dirs;
    bool skipped_self = false;
    fs::path found = find_import(name, from, opts_, &dirs, &skipped_self);
    if (found.empty() && skipped_self) {
      // Only the importing file itself has that name (a file of another folder
      // by its name would have been taken): the file, which the evaluator finds
      // running, so the import does nothing (§9).
      if (auto it = cache_.find(canonical(from)); it != cache_.end() && it->second.program)
        return &it->second;
      return nullptr;
    }
    if (found.empty()) {
      // Something by that name that is not a file (a folder, a FIFO): say what it
      // is, rather than that nothing was found (exit 3 either way).
      for (const std::string& dir : dirs) {
        fs::path p = fs::path(name).is_absolute() ? fs::path(name) : fs::path(dir) / name;
        std::error_code ec;
        if (!fs::exists(fs::symlink_status(p, ec)) || fs::is_regular_file(p, ec)) continue;
        c_.diags.report(DiagKind::FileUnreadable, span,
                        "cannot import '" + name + "': '" + p.lexically_normal().string() + "' " +
                            not_a_file(p.string()));
        return nullptr;
      }
      auto d = c_.diags.report(DiagKind::ImportNotFound, span, "cannot find '" + name + "'");
      std::string where;
      for (const std::string& dir : dirs)
        where += (where.empty() ? "" : ", ") + (dir.empty() ? std::string(".") : dir);
      d.note("searched: " + where);
      return nullptr;
    }
    std::string key = canonical(found);
    if (auto it = cache_.find(key); it != cache_.end()) return &it->second;
    std::string text, message;
    const std::string* open = opts_.overlay ? opts_.overlay(key) : nullptr;
    if (open) {
      text = *open;
    } else if (!read_file(found.string(), text, message)) {
      c_.diags.report(DiagKind::FileUnreadable, span, message);
      cache_[key] = {0, nullptr, {}, true};  // what it would bind is unknown
      return nullptr;
    }
    std::size_t before = c_.diags.error_count();
    const lang::Program* program = parse_file(found.lexically_normal().string(), text);
    // A file with syntax errors is not run: its errors are already reported, and
    // the names it might have bound are not reported undefined where it is imported.
    if (c_.diags.error_count() == before) {
      cache_[key] = {program->file, program, {}, false};
      return &cache_[key];
    }
    ImportedFile broken{program->file, nullptr, {}, false};
    for (const lang::StmtPtr& s : program->statements) {
      if (s->kind == lang::StmtKind::Let || s->kind == lang::StmtKind::Fn)
        broken.binds.push_back(s->name);
      if (s->kind == lang::StmtKind::Import) broken.binds_unknown = true;
    }
    broken.binds.insert(broken.binds.end(), program->unsure_names.begin(),
                        program->unsure_names.end());
    cache_[key] = std::move(broken);
    return &cache_[key];
  }

  static std::string canonical(const fs::path& p) { return canonical_path(p.string()); }

  // The main file is in the import cache too, so importing it is a cycle, not a
  // second run.
  void register_main(const std::string& path, const lang::Program* program) {
    cache_[canonical(path)] = {program->file, program, {}, false};
  }

  // --set KEY=VALUE: false (status UsageError) when the key or value is bad.
  bool apply_overrides(SceneBuilder& builder, Evaluator& eval) {
    const BlockInfo* settings = find_block("settings");
    for (std::size_t i = 0; i < opts_.overrides.size(); ++i) {
      const auto& [key, text] = opts_.overrides[i];
      const std::string written =
          i < opts_.override_labels.size() && !opts_.override_labels[i].empty()
              ? opts_.override_labels[i]
              : "--set " + key + "=" + text;
      const PropInfo* prop = find_prop(*settings, key);
      if (!prop) {
        std::string guess = lang::closest_match(key, setting_keys());
        std::string keys;
        for (std::string_view k : setting_keys())
          keys += (keys.empty() ? "" : ", ") + std::string(k);
        const bool labelled = i < opts_.override_labels.size() && !opts_.override_labels[i].empty();
        fail((labelled ? written : std::string("--set")) + ": unknown settings key '" + key + "'" +
             (guess.empty() ? "" : " (did you mean '" + guess + "'?)") + "; keys are " + keys);
        return false;
      }
      std::string expr = text;
      bool word = is_enum(prop->type) && !expr.empty() && expr.front() != '"';
      if (word) expr = "\"" + expr + "\"";
      // Parsed and evaluated as a .scn expression in a file of its own.
      lang::SourceManager src;
      lang::DiagnosticEngine diags(src);
      lang::FileId id = src.add("--set " + key, "let value = " + expr + ";");
      lang::Program p = lang::parse(src, id, diags);
      Value v = Value::error();
      if (!diags.has_errors() && p.statements.size() == 1 &&
          p.statements[0]->kind == lang::StmtKind::Let) {
        lang::DiagnosticEngine eval_diags(src);
        SceneBuilder scratch(src, eval_diags);
        Evaluator e(src, eval_diags, scratch, [](const std::string&, lang::Span) {
          return static_cast<const ImportedFile*>(nullptr);
        });
        (void)eval;
        v = e.eval_standalone(*p.statements[0]->exprs[0]);
        if (eval_diags.has_errors()) v = Value::error();
      }
      if (v.is_error()) {
        fail(written + ": cannot read '" + text + "' as a value; " + std::string(key) + " takes " +
             describe(*prop));
        return false;
      }
      std::string msg = check_value(*prop, v);
      if (!msg.empty()) {
        fail(written + ": " + msg);
        return false;
      }
      builder.override_setting(*prop, v);
    }
    return true;
  }

  void fail(std::string message) {
    c_.status = CompileStatus::UsageError;
    c_.message = std::move(message);
  }

 private:
  Compilation& c_;
  const CompileOptions& opts_;
  std::unordered_map<std::string, ImportedFile> cache_;
};

}  // namespace

namespace {
// What the compiler's own checks cannot see until the scene is whole: the runtime's
// ranges measured from the camera (ir::validate). Each becomes an error at the
// keyword of the item that has it.
void report_runtime_limits(Compilation& c) {
  for (const ir::Problem& p : ir::validate(c.scene)) {
    lang::Span span{};
    if (p.src.line > 0 && p.src.file < c.sources.size()) {
      const lang::SourceFile& f = c.sources.file(p.src.file);
      std::uint32_t b = f.offset_of({p.src.line, p.src.col}), e = b;
      std::string_view t = f.text();
      while (e < t.size() && (std::isalnum(static_cast<unsigned char>(t[e])) || t[e] == '_')) ++e;
      span = {p.src.file, b, e};
    }
    c.diags.report(lang::DiagKind::InvalidValue, span, p.what);
  }
}
// An image the texture system could not read, as an error at its `file` (the caret
// under the whole "name" when the place is the string), the reader's reason on one
// line (libpng's come as several).
// (`readable`: `why` is a note on an image that can be read, said as a warning.)
void report_unreadable_image(Compilation& c, const std::vector<ir::ImageFile>& images,
                             std::size_t image, const std::string& why, bool readable) {
  if (image >= images.size()) return;
  const ir::ImageFile& f = images[image];
  std::string reason = why;
  while (!reason.empty() && (reason.back() == '\n' || reason.back() == ' ')) reason.pop_back();
  for (std::size_t i = 0; (i = reason.find('\n', i)) != std::string::npos;)
    reason.replace(i, 1, "; ");
  if (reason.empty()) reason = "the image reader gave no reason (a damaged or cut-short file?)";
  lang::Span span{lang::FileId(-1), 0, 0};
  if (f.src.line > 0 && f.src.file < c.sources.size()) {
    const lang::SourceFile& file = c.sources.file(f.src.file);
    std::uint32_t at = file.offset_of({f.src.line, f.src.col}), end = at + 1;
    std::string_view text = file.text();
    if (at < text.size() && text[at] == '"')
      if (std::size_t close = text.find('"', at + 1); close != std::string_view::npos)
        end = std::uint32_t(close + 1);
    span = {f.src.file, at, end};
  }
  if (readable)
    c.diags.report(lang::DiagKind::MendedImage, span, "image '" + f.path + "': " + reason);
  else
    c.diags.report(lang::DiagKind::FileUnreadable, span,
                   "cannot read image '" + f.path + "': " + reason);
}

}  // namespace

std::unique_ptr<Compilation> compile_file(const std::string& path, const CompileOptions& options) {
  std::string text, message;
  if (!read_file(path, text, message)) {
    auto c = std::make_unique<Compilation>();
    c->status = CompileStatus::IoError;
    c->message = message;
    return c;
  }
  return compile_source(path, std::move(text), options);
}

std::unique_ptr<Compilation> compile_source(const std::string& path, std::string text,
                                            const CompileOptions& options) {
  auto c = std::make_unique<Compilation>();
  c->diags.set_max_errors(options.max_errors);
  run_with_large_stack([&] {
    Driver driver(*c, options);
    const lang::Program* program = driver.parse_file(path, text);
    driver.register_main(path, program);
    // Syntax errors do not stop evaluation: the statements that parsed are still
    // checked (§10: every independent error), the broken ones are skipped and the
    // names in them are not reported undefined (Program::unsure_names). The scene
    // is not finished below when anything was reported.
    SceneBuilder builder(c->sources, c->diags);
    Evaluator eval(
        c->sources, c->diags, builder,
        [&](const std::string& name, lang::Span span) { return driver.load_import(name, span); },
        options.step_budget);
    if (options.on_define) eval.set_define_observer(options.on_define);
    static_assert(std::size(kPredeclared) == 3, "a predeclared name without its value here");
    eval.predeclare(kPredeclared[0].name, Value::number(options.clock));
    eval.predeclare(kPredeclared[1].name, Value::number(options.frame));
    eval.predeclare(kPredeclared[2].name, Value::of_pattern(sky_gradient()));
    // The main file counts as imported: importing it again is a cycle.
    eval.run_file(*program);
    if (options.unreadable_images && !builder.images().empty())
      for (const CompileOptions::ImageVerdict& v : options.unreadable_images(builder.images()))
        report_unreadable_image(*c, builder.images(), v.image, v.why, v.readable);
    if (c->diags.has_errors()) {
      // The runtime's limits (ir::validate: reach from the camera, an instance's
      // scale, ...) of what was placed are independent errors too (§10): they were
      // found only once the others were fixed. A scene with errors is not handed on.
      c->scene = builder.finish();
      report_runtime_limits(*c);
      c->scene = ir::Scene{};
      return;
    }
    if (!driver.apply_overrides(builder, eval)) return;
    c->scene = builder.finish();
    report_runtime_limits(*c);
  });
  if (c->status == CompileStatus::Ok && c->diags.has_errors()) {
    // §10: exit 3 is "a file could not be read". When that is all that went wrong
    // (a missing import or mesh file, one too large to read), say so with the
    // status; any other error makes it a scene error.
    bool only_files = true;
    for (const lang::Diagnostic& d : c->diags.diagnostics())
      if (d.severity == lang::Severity::Error && d.kind != lang::DiagKind::FileUnreadable &&
          d.kind != lang::DiagKind::ImportNotFound && d.kind != lang::DiagKind::FileTooLarge)
        only_files = false;
    c->status = only_files ? CompileStatus::FileErrors : CompileStatus::SceneErrors;
  }
  return c;
}

}  // namespace snell::compile
