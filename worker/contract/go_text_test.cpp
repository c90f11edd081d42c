#include "contract/go_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace farm::contract {
namespace {

// Every expectation below is what Go 1.26 prints for the same input (strconv.FormatFloat
// with 'g' and -1, strconv.Quote, slog.TextHandler).

struct TextCase {
  std::string_view in;
  const char* go;
};

TEST(GoNumber, SpellsNumbersAsStrconvFormatFloatG) {
  const struct {
    double v;
    const char* go;
  } cases[] = {
      {0, "0"},           {-0.0, "-0"},          {1, "1"},
      {-1, "-1"},         {0.1, "0.1"},          {16384, "16384"},
      {100000, "100000"}, {1e6, "1e+06"},        {1e12, "1e+12"},
      {-1e12, "-1e+12"},  {1.1, "1.1"},          {1e-4, "0.0001"},
      {1e-5, "1e-05"},    {123456.789, "123456.789"}, {1234567, "1.234567e+06"},
      {2.5e-7, "2.5e-07"}, {1e21, "1e+21"},      {1e300, "1e+300"},
      {5e-324, "5e-324"}, {65536, "65536"},      {4294967296, "4.294967296e+09"},
      {0.000123, "0.000123"},
  };
  for (const auto& c : cases) EXPECT_EQ(GoNumber(c.v), c.go) << c.go;
  EXPECT_EQ(GoNumber(std::numeric_limits<double>::quiet_NaN()), "NaN");
  EXPECT_EQ(GoNumber(INFINITY), "+Inf");
  EXPECT_EQ(GoNumber(-INFINITY), "-Inf");
}

TEST(GoQuote, EscapesAsStrconvQuote) {
  const TextCase cases[] = {
      {"", R"("")"},
      {"plain", R"("plain")"},
      {"with space", R"("with space")"},
      {"quote\"d", R"("quote\"d")"},
      {"back\\slash", R"("back\\slash")"},
      {"tab\tnl\n", R"("tab\tnl\n")"},
      {std::string_view("\x00\x07\x7f", 3), R"("\x00\a\x7f")"},
      {"é ü", R"("é ü")"},
      {"\xff\xfe", R"("\xff\xfe")"},
      {"\u00a0nbsp", R"("\u00a0nbsp")"},
      {"\u2028", R"("\u2028")"},
      {"\ufeff", R"("\ufeff")"},
      {"😀", R"("😀")"},
      {"\u200b", R"("\u200b")"},
      {"\u0085", R"("\u0085")"},
      {"\ue000", R"("\ue000")"},
      {"日本", R"("日本")"},
      {"\U000F0000", R"("\U000f0000")"},
  };
  for (const TextCase& c : cases) EXPECT_EQ(GoQuote(c.in), c.go) << c.go;
}

TEST(SlogText, QuotesOnlyWhatTheTextHandlerQuotes) {
  const TextCase cases[] = {
      {"", R"("")"},
      {"plain", "plain"},
      {"with space", R"("with space")"},
      {"quote\"d", R"("quote\"d")"},
      {"back\\slash", R"(back\slash)"},
      {"tab\tnl\n", R"("tab\tnl\n")"},
      {"a=b", R"("a=b")"},
      {"é ü", R"("é ü")"},
      {"\xff\xfe", R"("\xff\xfe")"},
      {"\u00a0nbsp", R"("\u00a0nbsp")"},
      {"😀", "😀"},
      {"\ufffd", "\"\ufffd\""},
      {"日本", "日本"},
      {"x:y/z-1.2_3", "x:y/z-1.2_3"},
  };
  for (const TextCase& c : cases) EXPECT_EQ(SlogText(c.in), c.go) << c.go;
}

TEST(Truncate, CutsOnARuneBoundaryAndMarksTheCut) {
  EXPECT_EQ(Truncate("short", 80), "short");
  EXPECT_EQ(Truncate("abcdef", 3), "abc…");
  // "é" is two bytes: a cut inside it backs off to before it.
  EXPECT_EQ(Truncate("aébc", 2), "a…");
  EXPECT_EQ(Truncate("aébc", 3), "aé…");
}

}  // namespace
}  // namespace farm::contract
