// JSON inputs: nesting cap, trailing content, paths that are not files, bounded excerpts
// (issue 17: a value nested 100,000 deep crashed every tool; `{...} xyz` was accepted).
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "vehs/core/error.hpp"
#include "vehs/io/json_file.hpp"

namespace fs = std::filesystem;

namespace {
std::string message_of(const std::string& text) {
  try {
    (void)vehs::parse_json_text(text, "c.json");
  } catch (const vehs::Error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("JSON nested deeper than the cap is refused before parsing, at any size", "[io][json][asan]") {
  const std::string deep = std::string(100000, '[') + "1" + std::string(100000, ']');
  const std::string m = message_of("{\"a\": " + deep + "}");
  CHECK(m.find("c.json: JSON nested deeper than 64 levels (line 1)") == 0);
  // 64 levels are fine, 65 are not; brackets inside strings do not count
  const std::string ok = std::string(63, '[') + "1" + std::string(63, ']');
  CHECK(vehs::parse_json_text("{\"a\": " + ok + "}", "c.json").is_object());
  CHECK(message_of("{\"a\": " + std::string(64, '[') + std::string(64, ']') + "}").find("nested deeper") !=
        std::string::npos);
  CHECK(vehs::parse_json_text("{\"a\": \"" + std::string(1000, '[') + "\\\"[\"}", "c.json").is_object());
  CHECK(message_of("\n\n" + std::string(70, '{')).find("(line 3)") != std::string::npos);
}

TEST_CASE("content after the JSON document is an error", "[io][json][asan]") {
  CHECK(message_of("{\"a\": 1} xyz").find("c.json: not valid JSON") == 0);
  CHECK(message_of("{\"a\": 1}{\"a\": 1}").find("not valid JSON") != std::string::npos);
  CHECK(message_of("").find("not valid JSON") != std::string::npos);
  CHECK(vehs::parse_json_text("{\"a\": 1}  \n\t", "c.json")["a"] == 1);
  // nlohmann reports a number beyond double as out_of_range, not parse_error (found by fuzz_json_config)
  CHECK(message_of("{\"a\": 1e400}").find("c.json: not valid JSON (number overflow") == 0);
}

TEST_CASE("read_json_file names the file, refuses directories, never waits on a pipe without writer",
          "[io][json][asan]") {
  const fs::path dir = fs::temp_directory_path() / "vehs_json_file";
  fs::remove_all(dir);
  fs::create_directories(dir / "sub");
  auto message = [](const std::string& path) {
    try {
      (void)vehs::read_json_file(path, "config file");
    } catch (const vehs::Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(message((dir / "sub").string()) == (dir / "sub").string() + ": is a directory, not a config file");
  CHECK(message((dir / "none.json").string()).find("cannot open config file (No such file") != std::string::npos);
  REQUIRE(::mkfifo((dir / "fifo").c_str(), 0600) == 0);  // a blocking open would wait for a writer forever
  CHECK(message((dir / "fifo").string()).find("fifo: not valid JSON") != std::string::npos);
  CHECK(message("/dev/null").find("/dev/null: not valid JSON") != std::string::npos);
  CHECK(message("/dev/zero").find("/dev/zero: larger than 64 MB") != std::string::npos);
  std::ofstream(dir / "bad.json") << "{\"a\": 1,\n \"b\": }";
  CHECK(message((dir / "bad.json").string()).find("bad.json: not valid JSON (parse error at line 2") !=
        std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("json_excerpt stays short and one line for any value", "[io][json][asan]") {
  CHECK(vehs::json_excerpt(nlohmann::json(3)) == "3");
  CHECK(vehs::json_excerpt(nlohmann::json::parse("[1, 2]")) == "[1, 2]");
  nlohmann::json big = nlohmann::json::array();
  for (int i = 0; i < 100000; ++i) big.push_back(i);
  const std::string e = vehs::json_excerpt(big);
  CHECK(e.size() <= 50);
  CHECK(e.find("...") != std::string::npos);
  nlohmann::json nested = 1;
  // built, not parsed; 2000 levels (far beyond the parser's cap of 64): each level copies the one
  // below recursively, and 10000 overflowed the stack under AddressSanitizer's larger frames
  for (int i = 0; i < 2000; ++i) nested = nlohmann::json::array({nested});
  CHECK(vehs::json_excerpt(nested).size() <= 50);
  CHECK(vehs::json_excerpt(nlohmann::json(std::string(1000, 'a'))).size() <= 50);
}

TEST_CASE("json_excerpt never cuts a UTF-8 character (fuzz_json_config finding: dump threw)", "[io][json][asan]") {
  // a cut inside a multi-byte character made the excerpt invalid UTF-8, and nlohmann's dump of it
  // threw type_error 316 out of the error path (std::terminate in the fuzz target); every cut
  // position of 2-, 3- and 4-byte characters, in a string and as an object key's value
  const std::string chars = "\xC3\xA9\xE2\x82\xAC\xF0\x9F\x98\x80";  // é € 😀
  for (std::size_t lead = 0; lead < 50; ++lead) {
    std::string s(lead, 'a');
    for (int i = 0; i < 10; ++i) s += chars;
    for (const nlohmann::json& v : {nlohmann::json(s), nlohmann::json{{"k" + s, s}}, nlohmann::json::array({s, s})}) {
      std::string e;
      REQUIRE_NOTHROW(e = vehs::json_excerpt(v));
      CHECK_NOTHROW(nlohmann::json(e).dump());  // valid UTF-8
      CHECK(e.size() <= 60);
    }
  }
}

TEST_CASE("a key given twice in one object is an error naming the key and where", "[io][json][asan]") {
  // nlohmann keeps the last value silently: a hand-edited model with "x" twice ran with k = 4
  CHECK(message_of(R"({"drift": {"x": -1, "x": -4}, "diffusion": {"1": 0.02}})") ==
        "c.json: key \"x\" appears twice in 'drift' (each key may appear once)");
  CHECK(message_of(R"({"output": "a.json", "data": "d.csv", "output": "b.json"})") ==
        "c.json: key \"output\" appears twice in the top-level object (each key may appear once)");
  CHECK(message_of(R"({"a": {"b": {"c": 1, "c": 2}}})").find("appears twice in 'a.b'") != std::string::npos);
  // the same key in different objects, in arrays of objects and as a value is fine
  CHECK(message_of(R"({"x": {"x": 1}, "l": [{"x": 1}, {"x": 2}], "y": "x"})").empty());
}
