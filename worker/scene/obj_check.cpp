#include "scene/obj_check.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

#include "contract/go_text.h"
#include "contract/rules.h"

namespace farm {
namespace {

// A line's refusal, before Scan knows which line it is.
class Refusal : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A word of the file in a message: quoted and cut short, since it may be anything.
std::string Quoted(std::string_view token) { return contract::GoQuote(contract::Truncate(token, 40)); }

// The length of the valid UTF-8 sequence at the start of s, or 0 if none is there (as
// Go's utf8 package decides: no overlong forms, surrogates or code points past U+10FFFF).
std::size_t Utf8Sequence(std::string_view s) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  const unsigned char b = byte(0);
  if (b < 0x80) return 1;
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // bounds of the second byte
  if (b >= 0xC2 && b <= 0xDF) {
    n = 2;
  } else if (b >= 0xE0 && b <= 0xEF) {
    n = 3;
    if (b == 0xE0) lo = 0xA0;
    if (b == 0xED) hi = 0x9F;
  } else if (b >= 0xF0 && b <= 0xF4) {
    n = 4;
    if (b == 0xF0) lo = 0x90;
    if (b == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (s.size() < n) return 0;
  if (byte(1) < lo || byte(1) > hi) return 0;
  for (std::size_t i = 2; i < n; ++i)
    if (byte(i) < 0x80 || byte(i) > 0xBF) return 0;
  return n;
}

// Why a line is not text, or "" if it is. A partial line (cut at the longest line) may end
// inside a character.
std::string NotText(std::string_view line, bool partial) {
  for (const char c : line) {
    const auto b = static_cast<unsigned char>(c);
    if (b == 0) return "contains a NUL byte: not a text file";
    if ((b < ' ' && b != '\t') || b == 0x7f) {
      static constexpr char kHex[] = "0123456789abcdef";
      return std::string("contains the control character 0x") + kHex[b >> 4] + kHex[b & 15] + ": not a text file";
    }
  }
  for (std::size_t at = 0; at < line.size();) {
    const std::size_t n = Utf8Sequence(line.substr(at));
    if (n == 0) {
      // A character the cut split: its lead byte is within the last 4 and announces more.
      const bool cut = partial && line.size() - at < 4 && static_cast<unsigned char>(line[at]) >= 0xC2;
      if (cut) break;
      return "is not UTF-8 text: not a text file";
    }
    at += n;
  }
  return "";
}

// Calls statement(words) for every line that is text (its words up to a comment), and
// returns the number of lines. Stops with ObjError at a line that is not text, is too long
// or whose statement throws.
std::size_t Scan(std::string_view text, const std::function<void(const std::vector<std::string_view>&)>& statement) {
  const std::uint64_t longest = contract::SceneLimits().max_mesh_line_bytes();
  std::vector<std::string_view> words;  // of the current line, reused: a big mesh has millions
  std::size_t number = 0;
  for (std::size_t at = 0; at < text.size();) {
    ++number;
    const std::size_t newline = text.find('\n', at);
    const std::size_t end = newline == std::string_view::npos ? text.size() : newline;
    std::string_view line = text.substr(at, end - at);
    at = newline == std::string_view::npos ? text.size() : newline + 1;
    // The line and its break must fit the longest line (a last line without a break too).
    const bool too_long = line.size() + 1 > longest;
    if (too_long) line = line.substr(0, longest);
    if (!too_long && !line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (const std::string why = NotText(line, too_long); !why.empty()) throw ObjError(number, why);
    if (too_long) throw ObjError(number, "is longer than " + std::to_string(longest) + " bytes");
    words.clear();
    for (std::size_t i = 0; i < line.size();) {
      i = line.find_first_not_of(" \t", i);
      if (i == std::string_view::npos) break;
      const std::size_t j = std::min(line.find_first_of(" \t", i), line.size());
      if (line[i] == '#') break;  // a word that starts a comment
      words.push_back(line.substr(i, j - i));
      i = j;
    }
    if (words.empty()) continue;
    try {
      statement(words);
    } catch (const Refusal& r) {
      throw ObjError(number, r.what());
    }
  }
  return number;
}

// [+-] digits [. digits] [e [+-] digits], with digits on at least one side of the point.
bool Decimal(std::string_view t) {
  std::size_t i = 0;
  const auto sign = [&] {
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
  };
  const auto digits = [&] {
    const std::size_t start = i;
    while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i;
    return i - start;
  };
  sign();
  std::size_t n = digits();
  if (i < t.size() && t[i] == '.') {
    ++i;
    n += digits();
  }
  if (n == 0) return false;
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    sign();
    if (digits() == 0) return false;
  }
  return i == t.size();
}

// A decimal number, finite and within the scene's largest magnitude; throws the reason.
double Number(std::string_view token) {
  if (!Decimal(token)) throw Refusal(Quoted(token) + " is not a number");
  // strtod, unlike from_chars, reads a number too small for a double as 0 (as Go does).
  const double x = std::strtod(std::string(token).c_str(), nullptr);
  if (std::isinf(x)) throw Refusal(Quoted(token) + " is not a finite number");
  const double limit = contract::SceneLimits().max_magnitude();
  if (std::abs(x) > limit)
    throw Refusal(std::string(contract::Truncate(token, 40)) + " is out of range: numbers are at most ±" +
        contract::GoNumber(limit));
  return x;
}

// [+-] digits, without overflow.
std::optional<std::int64_t> Integer(std::string_view t) {
  bool negative = false;
  if (!t.empty() && (t[0] == '+' || t[0] == '-')) {
    negative = t[0] == '-';
    t.remove_prefix(1);
  }
  if (t.empty()) return std::nullopt;
  std::int64_t v = 0;
  for (const char c : t) {
    if (c < '0' || c > '9' || v > (std::numeric_limits<std::int64_t>::max() - (c - '0')) / 10) return std::nullopt;
    v = 10 * v + (c - '0');
  }
  return negative ? -v : v;
}

std::string Plural(std::uint64_t n, const std::string& name) {
  if (n == 1) return name;
  return name == "vertex" ? "vertices" : name + "s";
}

std::string BadReference(std::string_view ref) {
  return Quoted(ref) + " is not a vertex reference (v, v/vt, v//vn or v/vt/vn, whole numbers)";
}

struct Counts {
  std::uint64_t v = 0, vt = 0, vn = 0;
};

// Checks statements, knowing how many of each kind the whole file declares.
class Checker {
 public:
  explicit Checker(Counts totals) : totals_(totals) {}

  void Statement(const std::vector<std::string_view>& words) {
    const std::string_view kind = words[0];
    const std::size_t n = words.size() - 1;
    if (kind == "v") {
      if (n != 3 && n != 4 && n != 6)
        throw Refusal("a vertex has 3 coordinates (then optionally w, or a colour r g b), got " + std::to_string(n) +
            " numbers");
      Numbers(words);
      const std::uint64_t limit = contract::SceneLimits().max_mesh_vertices();
      if (++seen_.v > limit)
        throw Refusal("the mesh has more than " + std::to_string(limit) + " " + Plural(limit, "vertex") +
            " (the limit of one mesh)");
    } else if (kind == "vt") {
      if (n < 1 || n > 3) throw Refusal("a texture coordinate has 1 to 3 numbers, got " + std::to_string(n));
      Numbers(words);
      ++seen_.vt;
    } else if (kind == "vn") {
      if (n != 3) throw Refusal("a normal has 3 numbers, got " + std::to_string(n));
      Numbers(words);
      ++seen_.vn;
    } else if (kind == "f") {
      Face(words);
    }
  }

  std::uint64_t vertices() const { return seen_.v; }
  std::uint64_t triangles() const { return triangles_; }

 private:
  static void Numbers(const std::vector<std::string_view>& words) {
    for (std::size_t i = 1; i < words.size(); ++i) Number(words[i]);
  }

  void Face(const std::vector<std::string_view>& words) {
    const std::size_t corners = words.size() - 1;
    if (corners < 3) throw Refusal("a face needs at least 3 vertices, got " + std::to_string(corners));
    const struct {
      const char* name;
      std::uint64_t total, seen;
    } kinds[3] = {{"vertex", totals_.v, seen_.v},
                  {"texture coordinate", totals_.vt, seen_.vt},
                  {"normal", totals_.vn, seen_.vn}};
    for (std::size_t w = 1; w < words.size(); ++w) {
      const std::string_view ref = words[w];
      std::string_view parts[3];
      std::size_t n = 0;
      for (std::string_view rest = ref;; ++n) {
        if (n == 3) throw Refusal(BadReference(ref));
        const std::size_t slash = rest.find('/');
        if (slash == std::string_view::npos) {
          parts[n++] = rest;
          break;
        }
        parts[n] = rest.substr(0, slash);
        rest = rest.substr(slash + 1);
      }
      if ((n == 3 && parts[2].empty()) || (n == 2 && parts[1].empty())) throw Refusal(BadReference(ref));
      for (std::size_t i = 0; i < n; ++i) {
        if (i > 0 && parts[i].empty()) continue;  // v//vn: no texture coordinate
        const std::optional<std::int64_t> index = Integer(parts[i]);
        if (!index) throw Refusal(BadReference(ref));
        const auto& k = kinds[i];
        if (*index == 0) throw Refusal(std::string("face refers to ") + k.name + " 0, but OBJ counts from 1");
        if (*index > 0 && static_cast<std::uint64_t>(*index) > k.total)
          throw Refusal(std::string("face refers to ") + k.name + " " + std::to_string(*index) + " but the file has " +
              std::to_string(k.total) + " " + Plural(k.total, k.name));
        if (*index < 0 && static_cast<std::uint64_t>(-*index) > k.seen)
          throw Refusal(std::string("face refers to ") + k.name + " " + std::to_string(*index) + " but only " +
              std::to_string(k.seen) + " " + Plural(k.seen, k.name) + " come before it");
      }
    }
    triangles_ += corners - 2;
    const std::uint64_t limit = contract::SceneLimits().max_mesh_triangles();
    if (triangles_ > limit)
      throw Refusal("the mesh has more than " + std::to_string(limit) + " " + Plural(limit, "triangle") +
          " (the limit of one mesh)");
  }

  Counts totals_;
  Counts seen_;  // declared so far: negative indices count back from them
  std::uint64_t triangles_ = 0;
};

}  // namespace

ObjError::ObjError(std::size_t line, const std::string& reason)
    : BadInputError(line ? "line " + std::to_string(line) + ": " + reason : reason),
      line_(line),
      reason_(reason) {}

ObjCounts CheckObj(std::string_view text) {
  const std::uint64_t largest = contract::SceneLimits().max_asset_bytes();
  if (text.size() > largest)
    throw ObjError(0, "the file is " + std::to_string(text.size()) + " bytes, larger than the limit of " +
                          std::to_string(largest) + " bytes");
  // Positive indices may name what is declared further down: count it all first, up to a
  // line that is not text (the second pass stops there too, unless a line before it is
  // wrong first).
  Counts totals;
  try {
    Scan(text, [&](const std::vector<std::string_view>& words) {
      totals.v += words[0] == "v";
      totals.vt += words[0] == "vt";
      totals.vn += words[0] == "vn";
    });
  } catch (const ObjError&) {
  }
  Checker checker(totals);
  const std::size_t lines = Scan(text, [&](const std::vector<std::string_view>& words) { checker.Statement(words); });
  if (checker.triangles() == 0) throw ObjError(std::max<std::size_t>(lines, 1), "the mesh has no triangles (the file has no face)");
  return {checker.vertices(), checker.triangles()};
}

}  // namespace farm
