#include "image/accumulation_exr.h"

#include <gtest/gtest.h>

#include "image/image_error.h"

namespace farm {
namespace {

TEST(AccumulationExr, RoundTripsEveryValueAndTheRoundCount) {
  const std::vector<std::string> channels = {"R", "G", "B", "A", "depth.Z", "edge.Y"};
  const PixelRect whole{0, 0, 7, 5};
  Accumulation a{4, Image(whole, channels), Image(whole, {"R", "G", "B"}), Image(whole, {"W"}), 0.75, 0.3125};
  for (std::size_t i = 0; i < a.sums.data().size(); ++i) a.sums.data()[i] = 0.37f * i - 3;
  for (std::size_t i = 0; i < a.squares.data().size(); ++i) a.squares.data()[i] = 1.5f * i;
  for (std::size_t i = 0; i < a.weights.data().size(); ++i) a.weights.data()[i] = 4.0f + 0.5f * i;
  const std::string bytes = EncodeAccumulationExr(a);
  EXPECT_EQ(bytes, EncodeAccumulationExr(a));  // deterministic
  const Accumulation b = DecodeAccumulationExr(bytes, {7, 5}, channels, 4);
  EXPECT_EQ(b.rounds, 4);
  EXPECT_EQ(b.sums, a.sums);
  EXPECT_EQ(b.squares, a.squares);
  EXPECT_EQ(b.weights, a.weights);
  EXPECT_EQ(b.deviations, 0.75);
  EXPECT_EQ(b.deviation_squares, 0.3125);
  EXPECT_THROW(DecodeAccumulationExr(bytes, {7, 5}, channels, 3), ImageError);
}

TEST(AccumulationExr, ChannelsAreSumsOfEveryChannelAndSquaresOfTheBeauty) {
  EXPECT_EQ(AccumulationChannels({"R", "G", "B", "A", "edge.Y"}),
            (std::vector<std::string>{"sum.R", "sum.G", "sum.B", "sum.A", "sum.edge.Y", "sumsq.R",
                                      "sumsq.G", "sumsq.B", "weight"}));
}

}  // namespace
}  // namespace farm
