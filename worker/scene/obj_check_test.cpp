// The OBJ rules the shared vectors (tests/vectors/meshes) cannot hold: lines at the length
// limit, and numbers at the edges of a double. The vectors cover the rest.
#include "scene/obj_check.h"

#include <gtest/gtest.h>

#include <string>

#include "contract/go_text.h"
#include "contract/rules.h"

namespace farm {
namespace {

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

std::size_t LongestLine() { return contract::SceneLimits().max_mesh_line_bytes(); }

// The line, at the given length without its break, of a comment.
// (Built by append: GCC 12 warns falsely about "literal" + std::string temporaries.)
std::string CommentOfLength(std::size_t n) {
  std::string line = "#";
  line.append(n - 1, 'x');
  return line;
}

TEST(CheckObj, ALineAndItsBreakMayFillTheLongestLine) {
  EXPECT_EQ(CheckObj(CommentOfLength(LongestLine() - 1) + "\n" + kTriangle).triangles, 1u);
}

TEST(CheckObj, ALineOneByteLongerIsRefusedAtItsLine) {
  try {
    CheckObj(kTriangle + CommentOfLength(LongestLine()) + "\n");
    FAIL() << "accepted";
  } catch (const ObjError& e) {
    EXPECT_EQ(e.line(), 5u);
    EXPECT_EQ(e.reason(), "is longer than " + std::to_string(LongestLine()) + " bytes");
  }
}

TEST(CheckObj, ALastLineWithoutABreakCountsTheBreakItLacks) {
  EXPECT_THROW(CheckObj(kTriangle + CommentOfLength(LongestLine())), ObjError);
  EXPECT_EQ(CheckObj(kTriangle + CommentOfLength(LongestLine() - 1)).triangles, 1u);
}

TEST(CheckObj, ALongLineCutInsideACharacterIsTooLongNotBinary) {
  // "é" is two bytes: the cut at the longest line falls inside one.
  std::string line = "#";
  while (line.size() < LongestLine() + 1) line += "\xc3\xa9";
  try {
    line += "\n";
    CheckObj(line.append(kTriangle));
    FAIL() << "accepted";
  } catch (const ObjError& e) {
    EXPECT_EQ(e.line(), 1u);
    EXPECT_EQ(e.reason(), "is longer than " + std::to_string(LongestLine()) + " bytes");
  }
}

TEST(CheckObj, NumbersTooSmallForADoubleAreZeroAndSignsAreAllowed) {
  EXPECT_EQ(CheckObj("v 1e-999 +1.5 -.5\nv 1. 0 0\nv 0 1 0\nf 1 2 3\n").vertices, 3u);
}

TEST(CheckObj, TheLargestMagnitudeIsAllowedAndNoMore) {
  const std::string max = contract::GoNumber(contract::SceneLimits().max_magnitude());
  EXPECT_EQ(CheckObj("v " + max + " 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").vertices, 3u);
  EXPECT_THROW(CheckObj("v 1.0000001e12 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), ObjError);
}

TEST(CheckObj, AFaceMayNameAVertexDeclaredAfterIt) {
  EXPECT_EQ(CheckObj("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n").triangles, 1u);
}

TEST(CheckObj, PolygonsCountTheirFanTriangles) {
  EXPECT_EQ(CheckObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 2 0\nf 1 2 3 4 5\n").triangles, 3u);
}

}  // namespace
}  // namespace farm
