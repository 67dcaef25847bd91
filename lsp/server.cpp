#include "lsp/server.hpp"

#include <poll.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <iostream>
#include <new>

#include "lsp/features.hpp"

namespace snell::lsp {

Server::Server(ServerOptions options, Sink sink)
    : options_(std::move(options)), send_(std::move(sink)) {}

AnalysisOptions Server::analysis_options() const {
  AnalysisOptions o;
  o.include_dirs = options_.include_dirs;
  o.step_budget = options_.step_budget;
  o.unreadable_images = options_.unreadable_images;
  o.scene_warnings = options_.scene_warnings;
  // Unsaved buffers win over the disk for imports.
  o.overlay = [this](const std::string& canonical) -> const std::string* {
    for (const auto& [uri, d] : docs_)
      if (d.canonical == canonical) return &d.text;
    return nullptr;
  };
  o.open_documents = [this] {
    std::vector<std::string> paths;
    for (const auto& [uri, d] : docs_) paths.push_back(d.canonical);
    return paths;
  };
  return o;
}

void Server::handle(const json& message) {
  if (!message.is_object()) {
    send_(make_error(nullptr, kInvalidRequest, "a message must be a JSON object"));
    return;
  }
  auto method_it = message.find("method");
  auto id_it = message.find("id");
  bool is_request = id_it != message.end();
  json id = is_request ? *id_it : json();
  if (method_it == message.end() || !method_it->is_string()) {
    // A response to something we sent (we send no requests), or garbage.
    if (is_request && message.find("result") == message.end() &&
        message.find("error") == message.end())
      send_(make_error(id, kInvalidRequest, "a request needs a method"));
    return;
  }
  const std::string& method = method_it->get_ref<const std::string&>();
  static const json kNoParams = json::object();
  auto params_it = message.find("params");
  const json& params = params_it == message.end() ? kNoParams : *params_it;
  try {
    if (!initialized_ && method != "initialize" && method != "exit") {
      if (is_request) send_(make_error(id, kServerNotInitialized, "initialize first"));
      return;
    }
    if (shutdown_ && method != "exit") {
      if (is_request) send_(make_error(id, kInvalidRequest, "the server is shutting down"));
      return;
    }
    bool handled = false;
    json result = dispatch(method, params, handled);
    if (!is_request) return;
    if (!handled)
      send_(make_error(id, kMethodNotFound, "unsupported method " + method));
    else
      send_(make_response(id, std::move(result)));
  } catch (const std::bad_alloc&) {
    if (is_request) send_(make_error(id, kRequestFailed, "out of memory"));
  } catch (const json::exception& e) {
    // Without the library's "[json.exception.type_error.302] " before the words.
    std::string what = e.what();
    if (what.rfind("[json.exception.", 0) == 0)
      if (std::size_t end = what.find("] "); end != std::string::npos) what.erase(0, end + 2);
    if (is_request) send_(make_error(id, kInvalidParams, what));
  } catch (const std::exception& e) {
    if (is_request) send_(make_error(id, kInternalError, e.what()));
  }
}

json Server::dispatch(const std::string& method, const json& params, bool& handled) {
  handled = true;
  if (method == "initialize") return initialize(params);
  if (method == "initialized") return nullptr;
  if (method == "shutdown") {
    shutdown_ = true;
    return nullptr;
  }
  if (method == "exit") {
    exit_ = true;
    return nullptr;
  }
  if (method == "textDocument/didOpen") {
    did_open(params);
    return nullptr;
  }
  if (method == "textDocument/didChange") {
    did_change(params);
    return nullptr;
  }
  if (method == "textDocument/didClose") {
    did_close(params);
    return nullptr;
  }
  if (method == "textDocument/didSave") return nullptr;
  if (method == "workspace/didChangeWatchedFiles") {
    // A .scn file changed on disk (an import edited elsewhere): analyse again.
    invalidate_all();
    return nullptr;
  }
  if (method == "textDocument/hover" || method == "textDocument/definition" ||
      method == "textDocument/completion" || method == "textDocument/documentSymbol") {
    Document* doc = document(params);
    if (!doc) return nullptr;
    Document& d = fresh(*doc);
    Locator at{*d.analysis, encoding_, d.uri};
    if (method == "textDocument/documentSymbol") return document_symbols(at);
    std::uint32_t offset = offset_of(d, params);
    if (method == "textDocument/hover") return hover(at, offset);
    if (method == "textDocument/definition") return definition(at, offset);
    return completion(at, d.text, offset, analysis_options());
  }
  // $/cancelRequest and $/setTrace are notifications, ignored above; LSP 3.17: a
  // request whose method starts with $/ is MethodNotFound like any other unknown.
  handled = false;
  return nullptr;
}

json Server::initialize(const json& params) {
  initialized_ = true;
  // LSP 3.17: the client lists the encodings it can take; bytes are the compiler's own.
  encoding_ = Encoding::Utf16;
  if (params.is_object()) {
    auto caps = params.find("capabilities");
    if (caps != params.end() && caps->is_object()) {
      json encs = caps->value("/general/positionEncodings"_json_pointer, json::array());
      if (encs.is_array())
        for (const json& e : encs)
          if (e == "utf-8") encoding_ = Encoding::Utf8;
    }
  }
  return {{"capabilities",
           {{"positionEncoding", encoding_ == Encoding::Utf8 ? "utf-8" : "utf-16"},
            {"textDocumentSync", {{"openClose", true}, {"change", 1}}},
            {"hoverProvider", true},
            {"definitionProvider", true},
            {"documentSymbolProvider", true},
            {"completionProvider", {{"triggerCharacters", {"\"", "/"}}}}}},
          {"serverInfo", {{"name", "snell"}, {"version", "0.1.0"}}}};
}

Server::Document* Server::document(const json& params) {
  std::string uri = params.at("textDocument").at("uri").get<std::string>();
  auto it = docs_.find(uri);
  return it == docs_.end() ? nullptr : &it->second;
}

void Server::did_open(const json& params) {
  const json& td = params.at("textDocument");
  std::string uri = td.at("uri").get<std::string>();
  Document& d = docs_[uri];
  d.uri = uri;
  d.path = uri_to_path(uri);
  d.canonical = compile::canonical_path(d.path);
  d.text = td.value("text", std::string());
  d.version = td.value("version", std::int64_t(0));
  d.stale = true;
  // A newly opened file may be what another open document imports.
  for (auto& [u, other] : docs_)
    if (u != uri && !other.stale) {
      other.stale = other.unpublished = true;
      other.due = Clock::now() + std::chrono::milliseconds(options_.debounce_ms);
    }
  publish(fresh(d));
}

void Server::did_change(const json& params) {
  Document* doc = document(params);
  if (!doc) return;
  for (const json& change : params.at("contentChanges")) {
    std::string text = change.at("text").get<std::string>();
    auto range = change.find("range");
    if (range == change.end()) {
      doc->text = std::move(text);
      continue;
    }
    // Incremental edits are not announced, but cost nothing to take.
    LineIndex index(doc->text);
    auto pos = [&](const json& p) {
      return index.offset(
          {p.at("line").get<std::uint32_t>(), p.at("character").get<std::uint32_t>()}, encoding_);
    };
    std::uint32_t b = pos(range->at("start")), e = pos(range->at("end"));
    if (e < b) std::swap(b, e);
    doc->text.replace(b, e - b, text);
  }
  if (auto v = params["textDocument"].find("version");
      v != params["textDocument"].end() && v->is_number_integer())
    doc->version = v->get<std::int64_t>();
  invalidate_all();
}

void Server::invalidate_all() {
  auto due = Clock::now() + std::chrono::milliseconds(options_.debounce_ms);
  for (auto& [u, d] : docs_) {
    d.stale = d.unpublished = true;
    d.due = due;
  }
}

void Server::did_close(const json& params) {
  std::string uri = params.at("textDocument").at("uri").get<std::string>();
  if (docs_.erase(uri) == 0) return;
  send_(make_notification("textDocument/publishDiagnostics",
                          {{"uri", uri}, {"diagnostics", json::array()}}));
  invalidate_all();
}

Server::Document& Server::fresh(Document& doc) {
  if (doc.stale || !doc.analysis) {
    doc.analysis = analyze(doc.path, doc.text, analysis_options());
    doc.stale = false;
  }
  return doc;
}

void Server::publish(Document& doc) {
  doc.unpublished = false;
  Locator at{*doc.analysis, encoding_, doc.uri};
  send_(make_notification(
      "textDocument/publishDiagnostics",
      {{"uri", doc.uri}, {"version", doc.version}, {"diagnostics", diagnostics(at)}}));
}

std::optional<Server::Clock::duration> Server::tick(Clock::time_point now) {
  std::optional<Clock::duration> next;
  for (auto& [uri, d] : docs_) {
    if (!d.stale && !d.unpublished) continue;
    if (d.due <= now) {
      try {
        publish(fresh(d));
      } catch (const std::exception&) {
        d.stale = d.unpublished = false;  // never retry a document that cannot be analysed
      }
    } else if (!next || d.due - now < *next) {
      next = d.due - now;
    }
  }
  return next;
}

std::uint32_t Server::offset_of(const Document& doc, const json& params) const {
  const json& p = params.at("position");
  // LSP's uinteger: whole and below 2^31 (a larger one wrapped round to 0:0). A
  // json::exception is InvalidParams (handle).
  auto field = [&](const char* name) {
    const json& v = p.at(name);
    if (!v.is_number_integer() || v.get<std::int64_t>() < 0 ||
        v.get<std::int64_t>() > std::int64_t(INT32_MAX))
      throw json::type_error::create(
          302, std::string("position.") + name + " must be an integer from 0 to 2^31 - 1", &v);
    return std::uint32_t(v.get<std::int64_t>());
  };
  return LineIndex(doc.text).offset({field("line"), field("character")}, encoding_);
}

// A \uD800-\uDFFF escape that is not half of a pair becomes \uFFFD: RFC 8259
// allows it and an editor's text can hold one, but nlohmann::json refuses the
// whole message, and a didChange lost that way left the server's copy stale.
void mend_lone_surrogates(std::string& body) {
  auto hex4 = [&](std::size_t at, unsigned& v) {
    if (at + 4 > body.size()) return false;
    v = 0;
    for (std::size_t k = at; k < at + 4; ++k) {
      const char c = body[k];
      const int d = c >= '0' && c <= '9'   ? c - '0'
                    : c >= 'a' && c <= 'f' ? c - 'a' + 10
                    : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                           : -1;
      if (d < 0) return false;
      v = v * 16 + unsigned(d);
    }
    return true;
  };
  for (std::size_t i = 0; i + 1 < body.size();) {
    if (body[i] != '\\') {
      ++i;
      continue;
    }
    unsigned v = 0, w = 0;
    if (body[i + 1] != 'u' || !hex4(i + 2, v)) {
      i += 2;  // another escape (\\ among them)
      continue;
    }
    const bool high = v >= 0xD800 && v <= 0xDBFF, low = v >= 0xDC00 && v <= 0xDFFF;
    if (high && i + 7 < body.size() && body[i + 6] == '\\' && body[i + 7] == 'u' &&
        hex4(i + 8, w) && w >= 0xDC00 && w <= 0xDFFF) {
      i += 12;  // a pair
      continue;
    }
    if (high || low) body.replace(i + 2, 4, "FFFD");
    i += 6;
  }
}

int run_stdio(const ServerOptions& options) {
  std::signal(SIGPIPE, SIG_IGN);  // a vanished client ends the loop, not the process
  bool out_ok = true;
  auto send = [&](const json& m) {
    std::string bytes = frame(m);
    if (std::fwrite(bytes.data(), 1, bytes.size(), stdout) != bytes.size() || std::fflush(stdout))
      out_ok = false;
  };
  Server server(options, send);
  MessageReader reader;
  char buf[1 << 16];
  while (out_ok) {
    auto wait = server.tick(Server::Clock::now());
    int timeout = -1;
    if (wait)
      timeout = static_cast<int>(
          std::chrono::duration_cast<std::chrono::milliseconds>(*wait).count() + 1);
    pollfd pfd{STDIN_FILENO, POLLIN, 0};
    int r = poll(&pfd, 1, timeout);
    if (r < 0) {
      if (errno == EINTR) continue;
      return 1;
    }
    if (r == 0) continue;  // an analysis is due
    ssize_t n = read(STDIN_FILENO, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return 0;  // stdin closed: the client is gone
    reader.feed({buf, static_cast<std::size_t>(n)});
    std::string error;
    // What the reader dropped is said on stderr (the client's log of the server):
    // junk or a bad header was skipped silently.
    auto say_dropped = [&] {
      if (error.empty()) return;
      std::cerr << "snell lsp: " << error << "\n";
      error.clear();
    };
    while (auto body = reader.next(&error)) {
      say_dropped();
      mend_lone_surrogates(*body);
      json message = json::parse(*body, nullptr, /*allow_exceptions=*/false);
      if (message.is_discarded())
        send(make_error(nullptr, kParseError, "the message is not JSON"));
      else
        server.handle(message);
      if (server.exit_requested()) return server.exit_code();
    }
    say_dropped();
  }
  return 1;
}

}  // namespace snell::lsp
