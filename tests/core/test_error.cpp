// vehs::Error keeps control bytes from files visible: what() is a C string, a raw NUL would cut it.
#include <catch2/catch.hpp>

#include <string>

#include "vehs/core/error.hpp"

TEST_CASE("errors show control bytes escaped and stay one line", "[core][error]") {
  const vehs::Error e(std::string("f.csv: line 3: '2\0x' is not a number\r\n\x1b[1m\x7f", 43));
  CHECK(std::string(e.what()) == "f.csv: line 3: '2\\x00x' is not a number\\r\\n\\x1b[1m\\x7f");
  // UTF-8 and backslashes are kept; escaping twice changes nothing (errors rethrown with context)
  const std::string text = "m\xC2\xB2 \\x00 ok";
  CHECK(std::string(vehs::Error(text).what()) == text);
  CHECK(std::string(vehs::Error(e.what()).what()) == e.what());
}
