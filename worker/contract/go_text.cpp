#include "contract/go_text.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <system_error>

namespace farm::contract {
namespace {

struct Rune {
  char32_t value = 0;
  std::size_t size = 1;  // bytes it takes
};

// Decodes the UTF-8 sequence at the start of s as Go's utf8.DecodeRuneInString does;
// nothing for an invalid (overlong, surrogate, out of range or cut) sequence.
std::optional<Rune> DecodeRune(std::string_view s) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  const unsigned char b0 = byte(0);
  if (b0 < 0x80) return Rune{b0, 1};
  std::size_t size;
  char32_t min;
  if ((b0 & 0xE0) == 0xC0) {
    size = 2, min = 0x80;
  } else if ((b0 & 0xF0) == 0xE0) {
    size = 3, min = 0x800;
  } else if ((b0 & 0xF8) == 0xF0) {
    size = 4, min = 0x10000;
  } else {
    return std::nullopt;
  }
  if (s.size() < size) return std::nullopt;
  char32_t r = b0 & (0x7F >> size);
  for (std::size_t i = 1; i < size; ++i) {
    if ((byte(i) & 0xC0) != 0x80) return std::nullopt;
    r = (r << 6) | (byte(i) & 0x3F);
  }
  if (r < min || r > 0x10FFFF || (r >= 0xD800 && r <= 0xDFFF)) return std::nullopt;
  return Rune{r, size};
}

// strconv.IsPrint for the code points listed in the header; the rest count as printable.
bool IsPrint(char32_t r) {
  if (r < 0x80) return r >= 0x20 && r < 0x7F;
  const auto in = [r](char32_t lo, char32_t hi) { return r >= lo && r <= hi; };
  return !(in(0x80, 0xA0) || r == 0xAD || in(0x600, 0x605) || r == 0x61C || r == 0x6DD ||
           r == 0x70F || r == 0x1680 || r == 0x180E || in(0x2000, 0x200F) ||
           in(0x2028, 0x202F) || in(0x205F, 0x206F) || r == 0x3000 || in(0xE000, 0xF8FF) ||
           r == 0xFEFF || in(0xFFF9, 0xFFFB) || in(0xFFFE, 0xFFFF) || in(0xF0000, 0x10FFFF));
}

void AppendHex(std::string& out, const char* prefix, std::uint32_t v, int digits) {
  static constexpr char kHex[] = "0123456789abcdef";
  out += prefix;
  for (int shift = 4 * (digits - 1); shift >= 0; shift -= 4) out += kHex[(v >> shift) & 0xF];
}

// Go's appendEscapedRune for one rune of a double-quoted string.
void AppendEscaped(std::string& out, char32_t r, std::string_view bytes) {
  if (r == '"' || r == '\\') {
    out += '\\';
    out += static_cast<char>(r);
    return;
  }
  if (IsPrint(r)) {
    out += bytes;
    return;
  }
  switch (r) {
    case '\a': out += "\\a"; return;
    case '\b': out += "\\b"; return;
    case '\f': out += "\\f"; return;
    case '\n': out += "\\n"; return;
    case '\r': out += "\\r"; return;
    case '\t': out += "\\t"; return;
    case '\v': out += "\\v"; return;
  }
  if (r < ' ' || r == 0x7F) {
    AppendHex(out, "\\x", r, 2);
  } else if (r < 0x10000) {
    AppendHex(out, "\\u", r, 4);
  } else {
    AppendHex(out, "\\U", r, 8);
  }
}

// log/slog's needsQuoting: empty, a space, '=', '"', an ASCII control character, or a
// non-ASCII rune that is invalid, U+FFFD, a space or not printable.
bool SlogNeedsQuoting(std::string_view s) {
  if (s.empty()) return true;
  for (std::size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    if (b < 0x80) {
      if (b == ' ' || b == '=' || b == '"' || b < 0x20) return true;
      ++i;
      continue;
    }
    const std::optional<Rune> r = DecodeRune(s.substr(i));
    if (!r || r->value == 0xFFFD || !IsPrint(r->value)) return true;
    i += r->size;
  }
  return false;
}

}  // namespace

std::string GoNumber(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  if (v == 0) return std::signbit(v) ? "-0" : "0";
  // The shortest digits that round-trip, as d.ddde±x; then Go's choice of %e or %f.
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, std::abs(v), std::chars_format::scientific);
  if (ec != std::errc()) return "NaN";  // cannot happen: 64 bytes hold any double
  const std::string_view text(buf, static_cast<std::size_t>(end - buf));
  const std::size_t e_at = text.find('e');
  std::string digits;
  for (char c : text.substr(0, e_at))
    if (c != '.') digits += c;
  const int exp = std::atoi(std::string(text.substr(e_at + 1)).c_str());
  const int nd = static_cast<int>(digits.size());
  const int dp = exp + 1;  // digits[0, dp) are the integer part

  // Appends only: GCC 12 warns falsely (-Wrestrict) about "x" + std::string temporaries.
  std::string out = v < 0 ? "-" : "";
  const auto dpos = static_cast<std::size_t>(std::max(dp, 0));
  if (exp < -4 || exp >= 6) {
    out += digits[0];
    if (nd > 1) out.append(".").append(digits, 1);
    out += exp < 0 ? "e-" : "e+";
    const int a = std::abs(exp);
    if (a < 10) out += '0';
    out += std::to_string(a);
  } else if (dp <= 0) {
    out.append("0.").append(static_cast<std::size_t>(-dp), '0').append(digits);
  } else if (dp >= nd) {
    out.append(digits).append(dpos - digits.size(), '0');
  } else {
    out.append(digits, 0, dpos).append(".").append(digits, dpos);
  }
  return out;
}

std::string GoQuote(std::string_view s) {
  std::string out = "\"";
  for (std::size_t i = 0; i < s.size();) {
    const std::optional<Rune> r = DecodeRune(s.substr(i));
    if (!r) {
      AppendHex(out, "\\x", static_cast<unsigned char>(s[i]), 2);
      ++i;
      continue;
    }
    AppendEscaped(out, r->value, s.substr(i, r->size));
    i += r->size;
  }
  return out + "\"";
}

std::string SlogText(std::string_view s) {
  return SlogNeedsQuoting(s) ? GoQuote(s) : std::string(s);
}

std::string Truncate(std::string_view s, std::size_t n) {
  if (s.size() <= n) return std::string(s);
  while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;
  return std::string(s.substr(0, n)) + "…";
}

}  // namespace farm::contract
