#pragma once

// Text spelled exactly as the coordinator's Go code spells it, so that a message or a log
// line reads the same whichever side of the farm wrote it:
//
//   GoNumber(v)     strconv.FormatFloat(v, 'g', -1, 64): 16384, 0.1, 1e+12, NaN, +Inf
//   GoQuote(s)      strconv.Quote (what %q prints): "a \"b\"\n"
//   SlogText(s)     a string value as log/slog's TextHandler writes it: bare when it
//                   needs no quoting (plain, back\slash), else GoQuote(s)
//   Truncate(s, n)  contract/rules.Truncate: at most n bytes, cut on a UTF-8 boundary and
//                   marked with "…"
//
// Go's strconv.IsPrint knows every Unicode category; this file knows the ASCII ones, the
// C1 controls, the spaces and format characters, the line and paragraph separators,
// private use and the non-characters U+FFFE and U+FFFF. Other code points Go would escape
// (unassigned ones) are kept as they are here.

#include <cstddef>
#include <string>
#include <string_view>

namespace farm::contract {

std::string GoNumber(double v);
std::string GoQuote(std::string_view s);
std::string SlogText(std::string_view s);
std::string Truncate(std::string_view s, std::size_t n);

}  // namespace farm::contract
