#include "scene/photon_settings.h"

#include <gtest/gtest.h>

#include "renderfarm/v1/scene.pb.h"

namespace farm {
namespace {

TEST(PhotonSettings, DefaultsFollowSceneProto) {
  const PhotonSettings s = PhotonSettings::FromProto({}, 200);
  EXPECT_EQ(s.global_photons, 200'000u);
  EXPECT_EQ(s.caustic_photons, 200'000u);
  EXPECT_EQ(s.photons_per_shard, 100'000u);
  EXPECT_EQ(s.global_estimate.neighbours, 100);
  EXPECT_EQ(s.caustic_estimate.neighbours, 50);
  EXPECT_FLOAT_EQ(s.global_estimate.max_radius, 10);   // 1/20 of the diagonal
  EXPECT_FLOAT_EQ(s.caustic_estimate.max_radius, 2);   // 1/100
  EXPECT_EQ(s.global_estimate.filter, EstimateFilter::kBox);
  EXPECT_EQ(s.caustic_estimate.filter, EstimateFilter::kCone);
  EXPECT_FLOAT_EQ(s.caustic_estimate.cone_k, 1.1f);
}

TEST(PhotonSettings, ExplicitValuesWin) {
  renderfarm::v1::PhotonMapping p;
  p.set_global_photons(7);
  p.mutable_caustic_estimate()->set_neighbours(20);
  p.mutable_caustic_estimate()->set_max_radius(0.5);
  p.mutable_caustic_estimate()->set_filter(renderfarm::v1::FILTER_GAUSSIAN);
  const PhotonSettings s = PhotonSettings::FromProto(p, 200);
  EXPECT_EQ(s.global_photons, 7u);
  EXPECT_EQ(s.caustic_estimate.neighbours, 20);
  EXPECT_FLOAT_EQ(s.caustic_estimate.max_radius, 0.5f);
  EXPECT_EQ(s.caustic_estimate.filter, EstimateFilter::kGaussian);
}

}  // namespace
}  // namespace farm
