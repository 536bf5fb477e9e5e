// Each effect's physics is written once: in its type under include/vehs/effects/. A parameter
// of an effect used in arithmetic anywhere else in the product's code (src/, include/, apps/,
// python/) is a second copy of its force and fails this test; a line that uses such a name for
// something else says so with a comment "physics-ok: <why>".
#include <catch2/catch.hpp>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "read_text.hpp"

namespace fs = std::filesystem;

namespace {

using vehs_test::slurp;

/// The text with comments, string and character literals blanked (newlines kept).
std::string code_only(const std::string& s) {
  std::string out = s;
  enum { Code, Line, Block, Str, Chr } st = Code;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i], n = i + 1 < s.size() ? s[i + 1] : '\0';
    switch (st) {
      case Code:
        if (c == '/' && n == '/') st = Line, out[i] = ' ';
        else if (c == '/' && n == '*') st = Block, out[i] = ' ';
        else if (c == '"') st = Str, out[i] = ' ';
        else if (c == '\'' && !(i > 0 && std::isalnum(static_cast<unsigned char>(s[i - 1])))) st = Chr, out[i] = ' ';
        break;
      case Line:
        if (c == '\n') st = Code;
        else out[i] = ' ';
        break;
      case Block:
        if (c == '*' && n == '/') st = Code, out[i] = out[i + 1] = ' ', ++i;
        else if (c != '\n') out[i] = ' ';
        break;
      case Str:
      case Chr:
        if (c == '\\') out[i] = ' ', out[i + 1] = ' ', ++i;
        else {
          if (c == (st == Str ? '"' : '\'')) st = Code;
          out[i] = c == '\n' ? '\n' : ' ';
        }
        break;
    }
  }
  return out;
}

/// The parameter names of an effect header: the first field of each entry of its params table.
std::set<std::string> parameter_names(const std::string& header) {
  std::set<std::string> names;
  const std::regex entry(R"re(\{"(\w+)", ")re");
  for (auto it = std::sregex_iterator(header.begin(), header.end(), entry); it != std::sregex_iterator(); ++it)
    names.insert((*it)[1]);
  return names;
}

bool is_ident(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
bool is_arith(char c) { return c == '*' || c == '/' || c == '+' || c == '-'; }

/// The lines (1-based, with their text; each once) where one of `names` (or the same with a trailing '_') is an
/// operand of + − * /.
std::vector<std::string> arithmetic_uses(const std::string& source, const std::set<std::string>& names) {
  const std::string code = code_only(source);
  std::vector<std::string> found;
  std::size_t i = 0;
  while (i < code.size()) {
    if (!is_ident(code[i]) || (i > 0 && is_ident(code[i - 1]))) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < code.size() && is_ident(code[j])) ++j;
    std::string tok = code.substr(i, j - i);
    const std::string bare = !tok.empty() && tok.back() == '_' ? tok.substr(0, tok.size() - 1) : tok;
    if (names.count(tok) || names.count(bare)) {
      std::size_t a = j;  // next significant character
      while (a < code.size() && (code[a] == ' ' || code[a] == '\t')) ++a;
      const char next = a < code.size() ? code[a] : '\0', next2 = a + 1 < code.size() ? code[a + 1] : '\0';
      const bool call = next == '(';
      bool after = is_arith(next) && next2 != '>' && next2 != next && next2 != '=';
      // previous significant character before the member-access chain (a.b, a->b, a_.b)
      std::size_t b = i;
      while (b > 0) {
        if (code[b - 1] == '.') --b;
        else if (b > 1 && code[b - 1] == '>' && code[b - 2] == '-') b -= 2;
        else if (is_ident(code[b - 1])) --b;
        else break;
      }
      while (b > 0 && (code[b - 1] == ' ' || code[b - 1] == '\t')) --b;
      const char prev = b > 0 ? code[b - 1] : '\0', prev2 = b > 1 ? code[b - 2] : '\0';
      // a '*' or '&' without spaces on both sides is a pointer, a dereference or an address
      const bool spaced = b >= 2 && (code[b - 2] == ' ') == (b < code.size() && code[b] == ' ');
      const bool before = is_arith(prev) && prev2 != prev && (prev != '*' || spaced);
      const std::size_t line_end = source.find('\n', i);
      const std::size_t line_start = source.rfind('\n', i) == std::string::npos ? 0 : source.rfind('\n', i) + 1;
      const bool allowed = source.substr(line_start, line_end - line_start).find("physics-ok:") != std::string::npos;
      if (!call && !allowed && (after || before)) {
        const std::size_t line = static_cast<std::size_t>(std::count(code.begin(), code.begin() + static_cast<long>(i), '\n')) + 1;
        const std::size_t ls = source.rfind('\n', i) == std::string::npos ? 0 : source.rfind('\n', i) + 1;
        const std::string hit = std::to_string(line) + ": " + source.substr(ls, source.find('\n', i) - ls);
        if (found.empty() || found.back() != hit) found.push_back(hit);
      }
    }
    i = j;
  }
  return found;
}

}  // namespace

TEST_CASE("the scanner finds a force written outside its effect type", "[effects][one_place]") {
  const std::set<std::string> names{"k_stop", "gap", "gap_neg"};
  CHECK(arithmetic_uses("if (x > gap) f -= k_stop * (x - gap);\n", names).size() == 1);
  CHECK(arithmetic_uses("r -= m_.k_stop * ((x - m_.gap).max(0.0));\n", names).size() == 1);
  CHECK(arithmetic_uses("b += -e->k_stop;\n", names).size() == 1);
  CHECK(arithmetic_uses("u += 0.5 * k_stop_ * d;\n", names).size() == 1);
  CHECK(arithmetic_uses("double v = gap_neg_/2;\n", names).size() == 1);
  // reading, passing, naming and commenting are not arithmetic
  CHECK(arithmetic_uses("s.gap = get(\"gap\") - 1; // k_stop * x\nf(stop.gap, stop.gap_neg);\n", names).empty());
  CHECK(arithmetic_uses("p->gap = 3; if (x > gap) ++n; gap(1) * 2;\n", names).empty());
  CHECK(arithmetic_uses("f(const T* gap, *o.gap_neg);\n", names).empty());
  CHECK(arithmetic_uses("y = 2 * gap;  // physics-ok: a data gap\n", names).empty());
  CHECK(arithmetic_uses("y = 2*gap;\n", names).size() == 1);
}

TEST_CASE("every effect's force is written once in its type", "[effects][one_place]") {
  const fs::path root = VEHS_SOURCE_DIR;
  const fs::path effects = root / "include" / "vehs" / "effects";
  std::vector<std::pair<std::string, std::set<std::string>>> types;
  for (const auto& f : fs::directory_iterator(effects)) {
    const auto names = parameter_names(slurp(f.path()));
    if (!names.empty()) types.emplace_back(f.path().filename().string(), names);
  }
  REQUIRE(!types.empty());
  std::size_t scanned = 0;
  for (const char* dir : {"src", "include", "apps", "python"}) {
    if (!fs::exists(root / dir)) continue;
    for (const auto& f : fs::recursive_directory_iterator(root / dir)) {
      const auto ext = f.path().extension();
      if (ext != ".cpp" && ext != ".hpp" && ext != ".inc" && ext != ".h") continue;
      const std::string rel = fs::relative(f.path(), root).generic_string();
      if (rel.rfind("include/vehs/effects/", 0) == 0 || rel.rfind("src/effects/", 0) == 0) continue;
      const std::string text = slurp(f.path());
      ++scanned;
      for (const auto& [type, names] : types)
        for (const auto& use : arithmetic_uses(text, names)) FAIL_CHECK(rel << ":" << use << "  (physics of " << type << ")");
    }
  }
  CHECK(scanned > 100);
}
