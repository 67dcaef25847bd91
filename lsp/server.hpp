// The language server: LSP lifecycle, open documents and their analyses, and
// the dispatch of requests to features.hpp. Transport-free (handle() takes a
// parsed message and answers through a sink) so tests can drive it in memory;
// run_stdio() is the event loop `snell lsp` runs.
//
// Diagnostics are debounced: a change marks its document stale and the
// analysis runs once the client has been quiet for `debounce_ms` (every open
// document is re-analysed too, since any may import the changed one). A request
// about a stale document analyses it first, so answers always match the text.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lsp/analysis.hpp"
#include "lsp/jsonrpc.hpp"
#include "lsp/text.hpp"

namespace snell::lsp {

struct ServerOptions {
  std::vector<std::string> include_dirs;  // -I, as the CLI takes them
  std::uint64_t step_budget = 5'000'000;
  int debounce_ms = 150;
  // §17: as AnalysisOptions' (`snell lsp` reads each image once per version of its
  // file: see cli's cached_image_check).
  decltype(AnalysisOptions::unreadable_images) unreadable_images;
  decltype(AnalysisOptions::scene_warnings) scene_warnings;  // as AnalysisOptions'
};

class Server {
 public:
  using Clock = std::chrono::steady_clock;
  using Sink = std::function<void(const json&)>;

  Server(ServerOptions options, Sink sink);

  // One message from the client (a request, a notification or a response).
  void handle(const json& message);
  // Runs the analyses that are due; returns how long until the next is due.
  std::optional<Clock::duration> tick(Clock::time_point now);
  bool exit_requested() const { return exit_; }
  // The process's exit status after `exit` (1 when no `shutdown` came first).
  int exit_code() const { return shutdown_ ? 0 : 1; }

 private:
  struct Document {
    std::string uri, path, canonical;
    std::string text;
    std::int64_t version = 0;
    std::unique_ptr<Analysis> analysis;
    bool stale = true;  // the analysis is not of the current text (and imports)
    // Its diagnostics are owed to the client at `due`: a change set both, and a
    // request may freshen the analysis before then, which must not cancel them
    // (the editor kept the old errors after a completion right after a change).
    bool unpublished = false;
    Clock::time_point due;
  };
  // Marks every open document's analysis out of date, its diagnostics due after
  // the debounce.
  void invalidate_all();

  json dispatch(const std::string& method, const json& params, bool& handled);
  json initialize(const json& params);
  void did_open(const json& params);
  void did_change(const json& params);
  void did_close(const json& params);
  Document* document(const json& params);
  Document& fresh(Document& doc);  // analysed for its current text
  void publish(Document& doc);
  std::uint32_t offset_of(const Document& doc, const json& params) const;
  AnalysisOptions analysis_options() const;

  ServerOptions options_;
  Sink send_;
  Encoding encoding_ = Encoding::Utf16;
  bool initialized_ = false, shutdown_ = false, exit_ = false;
  std::map<std::string, Document> docs_;  // by URI
};

// Serves LSP on stdin/stdout until `exit` or until stdin closes; returns the
// process's exit status.
int run_stdio(const ServerOptions& options);
// A message body's lone UTF-16 surrogate escapes replaced by \uFFFD (in place).
void mend_lone_surrogates(std::string& body);

}  // namespace snell::lsp
