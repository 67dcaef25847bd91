// The language server in memory: the framing, positions, and the server driven
// message by message (its answers captured), including a 1000-line scene's
// latency and random input it must survive. tests/lsp/pytest drives the real
// `snell lsp` process with a real client (pytest-lsp).
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <map>
#include <random>

#include "lsp/jsonrpc.hpp"
#include "lsp/server.hpp"
#include "lsp/text.hpp"

using namespace snell::lsp;

TEST_CASE("framing: whole, split and back-to-back messages", "[lsp]") {
  MessageReader r;
  std::string a = frame({{"x", 1}}), b = frame({{"y", "é"}});
  std::string all = a + b;
  r.feed(all.substr(0, 5));
  CHECK_FALSE(r.next());
  r.feed(all.substr(5, a.size() + 3 - 5));
  auto first = r.next();
  REQUIRE(first);
  CHECK(json::parse(*first)["x"] == 1);
  CHECK_FALSE(r.next());
  r.feed(all.substr(a.size() + 3));
  auto second = r.next();
  REQUIRE(second);
  CHECK(json::parse(*second)["y"] == "é");
}

TEST_CASE("jsonrpc: every problem skipped on the way is said, in order", "[lsp][jsonrpc]") {
  // The server prints them on stderr; only the last one was kept (and none said).
  MessageReader r;
  r.feed(
      "garbage\x01"
      "Content-Length: abc\r\n\r\nContent-Length: 99999999999999\r\n\r\nxx"
      "Content-Length: 2\r\n\r\n{}");
  std::string error;
  auto m = r.next(&error);
  REQUIRE(m);  // the next header ends the skip of the huge body
  CHECK(*m == "{}");
  const std::size_t junk = error.find("bytes outside any message"),
                    header = error.find("without a valid Content-Length"),
                    large = error.find("99999999999999 bytes (too large)");
  INFO(error);
  CHECK(junk != std::string::npos);
  CHECK(header != std::string::npos);
  CHECK(large != std::string::npos);
  CHECK((junk < header && header < large));
}

TEST_CASE("framing: headers in any case, extra headers, bad headers skipped", "[lsp]") {
  MessageReader r;
  r.feed("content-length: 2\r\nContent-Type: application/vscode-jsonrpc\r\n\r\n{}");
  auto m = r.next();
  REQUIRE(m);
  CHECK(*m == "{}");
  std::string error;
  r.feed("Content-Length: x\r\n\r\nContent-Length: 2\r\n\r\n[]");
  m = r.next(&error);
  REQUIRE(m);
  CHECK(*m == "[]");
  CHECK_FALSE(error.empty());
}

TEST_CASE("framing: a Content-Length a byte off loses a message, not every later one", "[lsp]") {
  // The rest of a body (or a byte taken from the next header) used to be glued to
  // the next header, whose Content-Length was then never found again.
  for (int off : {-1, 1}) {
    INFO("off by " << off);
    MessageReader r;
    std::string body = json{{"id", 1}}.dump();
    std::string bad =
        "Content-Length: " + std::to_string(int(body.size()) + off) + "\r\n\r\n" + body;
    r.feed(bad + frame({{"id", 2}}) + frame({{"id", 3}}));
    std::vector<int> ids;
    std::string error;
    while (auto m = r.next(&error)) {
      json j = json::parse(*m, nullptr, false);
      if (!j.is_discarded() && j.is_object() && j.contains("id")) ids.push_back(j["id"]);
    }
    REQUIRE_FALSE(ids.empty());
    CHECK(ids.back() == 3);
    CHECK_FALSE(error.empty());
  }
  // A header arriving a few bytes at a time is waited for, not skipped.
  MessageReader r;
  std::string whole = frame({{"id", 4}});
  for (char c : whole.substr(0, whole.size() - 1)) {
    r.feed(std::string(1, c));
    CHECK_FALSE(r.next());
  }
  r.feed(whole.substr(whole.size() - 1));
  auto m = r.next();
  REQUIRE(m);
  CHECK(json::parse(*m)["id"] == 4);
}

TEST_CASE("framing: a body larger than the limit is dropped", "[lsp]") {
  MessageReader r;
  std::string error;
  r.feed("Content-Length: 99999999999\r\n\r\nabc");
  CHECK_FALSE(r.next(&error));
  CHECK_FALSE(error.empty());
}

TEST_CASE("framing: a header inside an oversized body ends its skip", "[lsp]") {
  // A Content-Length of 10^14 waited for its bytes forever, swallowing every
  // later message.
  MessageReader r;
  std::string error;
  r.feed("Content-Length: 100000000000000\r\n\r\n{\"a\":");
  CHECK_FALSE(r.next(&error));
  r.feed("1}Content-Length: 2\r\n\r\n{}");
  auto m = r.next(&error);
  REQUIRE(m);
  CHECK(*m == "{}");
}

TEST_CASE("lone surrogate escapes become U+FFFD, pairs and other escapes stay", "[lsp]") {
  std::string body = R"({"t":"a\ud800b \udc00 \ud83d\ude00 \\ud800 \u0041"})";
  mend_lone_surrogates(body);
  CHECK(body == R"({"t":"a\uFFFDb \uFFFD \ud83d\ude00 \\ud800 \u0041"})");
  CHECK_FALSE(json::parse(body, nullptr, false).is_discarded());
}

TEST_CASE("positions: UTF-16 columns found one after another agree with a fresh count", "[lsp]") {
  // The index counts on from the last position on the same line: every offset,
  // in any order, must give what a fresh index gives (multibyte letters, offsets
  // inside them, several lines).
  std::string text = "let é = \"𝛼𝛼\"; // ü\nabc 😀 déf\n\n";
  LineIndex reused(text);
  std::mt19937 rng(7);
  for (int k = 0; k < 2000; ++k) {
    std::uint32_t off = rng() % std::uint32_t(text.size() + 1);
    if (k % 3 == 0 && off > 0) off = std::min<std::uint32_t>(off + 1, std::uint32_t(text.size()));
    Position a = reused.position(off, Encoding::Utf16),
             b = LineIndex(text).position(off, Encoding::Utf16);
    INFO("offset " << off);
    REQUIRE(a.line == b.line);
    REQUIRE(a.character == b.character);
  }
}

TEST_CASE("positions: UTF-16 and UTF-8 columns", "[lsp]") {
  std::string text = "let é = 1;\nlet 𝛼 = 2;\n";
  LineIndex idx(text);
  std::uint32_t one = static_cast<std::uint32_t>(text.find('1'));
  CHECK(idx.position(one, Encoding::Utf16).character == 8);
  CHECK(idx.position(one, Encoding::Utf8).character == 9);
  std::uint32_t two = static_cast<std::uint32_t>(text.find('2'));
  Position p = idx.position(two, Encoding::Utf16);
  CHECK(p.line == 1);
  CHECK(p.character == 9);  // the astral letter is two UTF-16 units
  CHECK(idx.offset(p, Encoding::Utf16) == two);
  CHECK(idx.offset({1, 999}, Encoding::Utf16) == text.size() - 1);  // clamped to the line
  CHECK(idx.offset({99, 0}, Encoding::Utf16) == text.size());
}

TEST_CASE("positions: a lone CR ends a line, as LSP counts lines", "[lsp]") {
  std::string text = "let a = 1;\rlet b = 2;\r\n\rlet c = 3;\n";
  LineIndex idx(text);
  Position b = idx.position(std::uint32_t(text.find('b')), Encoding::Utf16);
  CHECK(b.line == 1);
  CHECK(b.character == 4);
  Position c = idx.position(std::uint32_t(text.find('c')), Encoding::Utf16);
  CHECK(c.line == 3);  // \r\n is one end, the \r after it another
  CHECK(c.character == 4);
  CHECK(idx.offset({3, 4}, Encoding::Utf16) == text.find('c'));
}

TEST_CASE("uris", "[lsp]") {
  CHECK(uri_to_path("file:///tmp/a%20b/c.scn") == "/tmp/a b/c.scn");
  CHECK(path_to_uri("/tmp/a b/c.scn") == "file:///tmp/a%20b/c.scn");
}

namespace {
struct Client {
  std::vector<json> out;
  Server server{ServerOptions{{}, 5'000'000, 0, {}, {}},
                [this](const json& m) { out.push_back(m); }};
  int next_id = 1;
  json request(const std::string& method, json params) {
    int id = next_id++;
    server.handle({{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", params}});
    for (const json& m : out)
      if (m.contains("id") && m["id"] == id) return m;
    return nullptr;
  }
  void notify(const std::string& method, json params) {
    server.handle({{"jsonrpc", "2.0"}, {"method", method}, {"params", params}});
  }
  // initialize and initialized, with no capabilities.
  void start() {
    request("initialize", {{"capabilities", json::object()}});
    notify("initialized", json::object());
  }
  void open(const std::string& uri, const std::string& text, int version = 1) {
    notify("textDocument/didOpen",
           {{"textDocument",
             {{"uri", uri}, {"languageId", "snell"}, {"version", version}, {"text", text}}}});
  }
  json last_diagnostics() {
    for (auto it = out.rbegin(); it != out.rend(); ++it)
      if (it->value("method", "") == "textDocument/publishDiagnostics") return (*it)["params"];
    return nullptr;
  }
};
json pos(int line, int ch) {
  return {{"line", line}, {"character", ch}};
}
const char* kUri = "file:///tmp/snell-lsp-unit/scene.scn";
}  // namespace

TEST_CASE("server: diagnostics, hover and definition in memory", "[lsp]") {
  Client c;
  REQUIRE(c.request("initialize", {{"capabilities",
                                    json::object()}})["result"]["capabilities"]["hoverProvider"] ==
          true);
  c.notify("initialized", json::object());
  c.open(kUri, "let r = 2;\nsphere { radus r }\n");
  json d = c.last_diagnostics();
  REQUIRE(d["diagnostics"].size() >= 1);
  json first = d["diagnostics"][0];
  CHECK(first["code"] == "UnknownProperty");
  CHECK(first["range"]["start"] == pos(1, 9));
  CHECK(first["range"]["end"] == pos(1, 14));
  json hover = c.request("textDocument/hover",
                         {{"textDocument", {{"uri", kUri}}}, {"position", pos(1, 16)}});
  std::string text = hover["result"]["contents"]["value"];
  CHECK(text.find("number") != std::string::npos);
  json def = c.request("textDocument/definition",
                       {{"textDocument", {{"uri", kUri}}}, {"position", pos(1, 16)}});
  CHECK(def["result"]["range"]["start"] == pos(0, 4));
  CHECK(c.request("shutdown", nullptr)["result"].is_null());
  c.notify("exit", nullptr);
  CHECK(c.server.exit_requested());
  CHECK(c.server.exit_code() == 0);
}

// A position beyond LSP's uinteger (or not whole) is InvalidParams: 2^32 wrapped
// round to line 0 and answered there.
TEST_CASE("server: a position out of range is an InvalidParams error", "[lsp]") {
  Client c;
  c.start();
  c.open(kUri, "let r = 2;\n");
  for (json p : {json{{"line", 4294967296ll}, {"character", 0}},
                 json{{"line", 0}, {"character", -1}}, json{{"line", 0.5}, {"character", 0}}}) {
    INFO(p.dump());
    json r = c.request("textDocument/hover", {{"textDocument", {{"uri", kUri}}}, {"position", p}});
    REQUIRE(r.contains("error"));
    CHECK(r["error"]["code"] == -32602);
    // The words alone, without the JSON library's "[json.exception...]" tag.
    CHECK(r["error"]["message"].get<std::string>().rfind("position.", 0) == 0);
  }
  // A missing field likewise.
  json r = c.request("textDocument/hover", {{"textDocument", {{"uri", kUri}}}});
  REQUIRE(r.contains("error"));
  CHECK(r["error"]["code"] == -32602);
  CHECK(r["error"]["message"].get<std::string>().find("json.exception") == std::string::npos);
  json ok =
      c.request("textDocument/hover", {{"textDocument", {{"uri", kUri}}}, {"position", pos(0, 4)}});
  CHECK(ok["result"].is_object());
}

// A string value in a hover stays one code span whatever it holds (backticks and
// line breaks ended the span, and the rest rendered as Markdown).
TEST_CASE("server: a hover shows a string value as one code span", "[lsp]") {
  Client c;
  c.start();
  c.open(kUri, "let s = \"x``y\\n# z\";\n");
  json hover =
      c.request("textDocument/hover", {{"textDocument", {{"uri", kUri}}}, {"position", pos(0, 4)}});
  const std::string v = hover["result"]["contents"]["value"];
  INFO(v);
  CHECK(v.find("= ``` \"x``y\\n# z\" ```") != std::string::npos);
}

// A body whose '}' is not typed yet (an editor that does not close braces) keeps
// its names: hover and definition answered null inside an unclosed for, fn, if
// or CSG body, whose statement was dropped as broken.
TEST_CASE("server: names inside a body still missing its '}' hover and resolve", "[lsp]") {
  Client c;
  c.start();
  int version = 1;
  for (const char* text : {"for idx in 0 .. 3 {\n  sphere { radius idx + 1 }\n",
                           "fn f(idx) {\n  sphere { radius idx + 1 }\n",
                           "if true {\n  let idx = 1;\n  sphere { radius idx + 1 }\n",
                           "union {\n  let idx = 1;\n  sphere { radius idx + 1 }\n"}) {
    INFO(text);
    c.open(kUri, text, version++);
    const std::string t = text;
    const int line = int(std::count(t.begin(), t.end(), '\n')) - 1;
    json hover = c.request("textDocument/hover",
                           {{"textDocument", {{"uri", kUri}}}, {"position", pos(line, 19)}});
    REQUIRE(hover["result"].is_object());
    CHECK(std::string(hover["result"]["contents"]["value"]).find("idx") != std::string::npos);
    json def = c.request("textDocument/definition",
                         {{"textDocument", {{"uri", kUri}}}, {"position", pos(line, 19)}});
    CHECK(def["result"].is_object());
    c.notify("textDocument/didClose", {{"textDocument", {{"uri", kUri}}}});
  }
}

// A request right after a change analyses the new text at once; the change's
// diagnostics are still owed and sent when the debounce ends (they were not: the
// editor kept showing the fixed error after a completion or outline request).
TEST_CASE("server: a request after a change does not swallow its diagnostics", "[lsp]") {
  Client c;
  c.start();
  c.open(kUri, "let a = nope;\n");
  REQUIRE(c.last_diagnostics()["diagnostics"].size() == 1);
  for (const char* method :
       {"textDocument/hover", "textDocument/completion", "textDocument/documentSymbol"}) {
    INFO(method);
    static int version = 1;
    ++version;
    const bool fixed = version % 2 == 0;
    c.notify("textDocument/didChange",
             {{"textDocument", {{"uri", kUri}, {"version", version}}},
              {"contentChanges",
               json::array({{{"text", fixed ? "let a = 1;\nlet b = a;\n" : "let b = zzz;\n"}}})}});
    c.request(method, {{"textDocument", {{"uri", kUri}}}, {"position", pos(1, 8)}});
    c.server.tick(Server::Clock::now() + std::chrono::seconds(1));
    json d = c.last_diagnostics();
    CHECK(d["version"] == version);
    CHECK(d["diagnostics"].size() == (fixed ? 0u : 1u));
  }
}

TEST_CASE("server: the predeclared clock and frame hover and complete (§18)", "[lsp]") {
  Client c;
  c.start();
  c.open(kUri, "sphere { radius 1 + clock translate <frame, 0, 0> }\n");
  CHECK(c.last_diagnostics()["diagnostics"].empty());
  json hover = c.request("textDocument/hover",
                         {{"textDocument", {{"uri", kUri}}}, {"position", pos(0, 22)}});
  REQUIRE(hover["result"].is_object());
  std::string text = hover["result"]["contents"]["value"];
  CHECK(text.find("--frames") != std::string::npos);
  json items = c.request("textDocument/completion",
                         {{"textDocument", {{"uri", kUri}}}, {"position", pos(0, 20)}})["result"];
  if (items.is_object()) items = items["items"];
  bool clock = false, frame = false;
  for (const json& i : items) clock |= i["label"] == "clock", frame |= i["label"] == "frame";
  CHECK(clock);
  CHECK(frame);
  // A name that is a builtin and a pattern constructor (noise, fbm, cells) is one
  // item, not two; a constructor alone (marble) is still there.
  std::map<std::string, int> count;
  for (const json& i : items) ++count[i["label"].get<std::string>()];
  for (const char* name : {"noise", "fbm", "cells", "marble", "sin"}) {
    INFO(name);
    CHECK(count[name] == 1);
  }
}

TEST_CASE("server: a 1000-line scene is analysed well under 100 ms", "[lsp]") {
  std::string text = "import \"colors.scn\";\nlet m = diffuse <0.8, 0.8, 0.8>;\n";
  for (int i = 0; i < 1000; ++i)
    text += "sphere { center <" + std::to_string(i % 37) + ", 1, " + std::to_string(i / 37) +
            "> radius 0.4 material m }\n";
  Client c;
  c.request("initialize", {{"capabilities", json::object()}});
  c.notify("textDocument/didOpen",
           {{"textDocument", {{"uri", kUri}, {"version", 1}, {"text", text}}}});
  auto t0 = std::chrono::steady_clock::now();
  c.notify("textDocument/didChange", {{"textDocument", {{"uri", kUri}, {"version", 2}}},
                                      {"contentChanges", {{{"text", text + "\n"}}}}});
  json h = c.request("textDocument/hover",
                     {{"textDocument", {{"uri", kUri}}}, {"position", pos(500, 2)}});
  double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  CHECK(h["result"]["contents"]["value"].get<std::string>().find("sphere") != std::string::npos);
  WARN("re-analysis and hover of a 1000-line scene: " << ms << " ms");
#ifndef __SANITIZE_ADDRESS__  // the sanitizers' build is several times slower by design
  CHECK(ms < 100);
#endif
}

TEST_CASE("server: random edits and bytes never crash it", "[lsp]") {
  std::mt19937 rng(20);
  Client c;
  c.request("initialize", {{"capabilities", json::object()}});
  std::string text = "let a = 1;\nfn f(x) = x * a;\nsphere { center <f(1), 0, 0> radius 1 }\n";
  c.notify("textDocument/didOpen",
           {{"textDocument", {{"uri", kUri}, {"version", 1}, {"text", text}}}});
  const std::string pieces[] = {"{",
                                "}",
                                "<",
                                ">",
                                "sphere",
                                "let",
                                "fn",
                                "(",
                                ")",
                                "\"",
                                "/*",
                                "import \"x.scn\";",
                                "for i in 0 .. 1e9 { box {} }",
                                "\xff",
                                "\n",
                                ";",
                                "radius",
                                "1e400",
                                "object {",
                                "union {"};
  for (int i = 0; i < 300; ++i) {
    std::size_t at = text.empty() ? 0 : rng() % (text.size() + 1);
    if (rng() % 3 == 0 && !text.empty())
      text.erase(at, rng() % 8);
    else
      text.insert(at, pieces[rng() % std::size(pieces)]);
    c.notify("textDocument/didChange", {{"textDocument", {{"uri", kUri}, {"version", i + 2}}},
                                        {"contentChanges", {{{"text", text}}}}});
    int line = static_cast<int>(rng() % 6), ch = static_cast<int>(rng() % 40);
    for (const char* m : {"textDocument/hover", "textDocument/completion",
                          "textDocument/definition", "textDocument/documentSymbol"}) {
      json r = c.request(m, {{"textDocument", {{"uri", kUri}}}, {"position", pos(line, ch)}});
      REQUIRE(r.contains("result"));
    }
  }
  // Malformed messages get errors, not crashes.
  CHECK(c.request("textDocument/hover", {{"textDocument", 5}}).contains("error"));
  c.server.handle(json::array());
  c.server.handle("text");
  CHECK(c.request("no/such", json::object())["error"]["code"] == kMethodNotFound);
  // LSP 3.17: a request starting with $/ is MethodNotFound (it had a null result);
  // such notifications are ignored.
  CHECK(c.request("$/foo", json::object())["error"]["code"] == kMethodNotFound);
  std::size_t before = c.out.size();
  c.notify("$/setTrace", {{"value", "off"}});
  CHECK(c.out.size() == before);
}
