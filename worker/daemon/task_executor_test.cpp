#include "daemon/task_executor.h"

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "contract/failure.h"
#include "daemon/blob_cache.h"
#include "daemon/options.h"
#include "daemon/sha256.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

// An executor whose blob client finds the job's scene in its cache: no coordinator is
// reached (the channel points nowhere and connects only when used).
class TaskExecutorTest : public ::testing::Test {
 protected:
  TaskExecutorTest()
      : dir_(std::filesystem::temp_directory_path() / ("task_executor_test_" + std::to_string(::getpid()))),
        cache_(dir_, kDefaultCacheMaxBytes),
        blobs_(grpc::CreateChannel("127.0.0.1:1", grpc::InsecureChannelCredentials()), &cache_),
        executor_(blobs_) {}
  ~TaskExecutorTest() override { std::filesystem::remove_all(dir_); }

  // A leased render tile of `scene`, stored in the cache.
  pb::LeaseTaskResponse RenderTile(const pb::Scene& scene, uint32_t x, uint32_t width) {
    const std::string bytes = scene.SerializeAsString();
    pb::LeaseTaskResponse leased;
    leased.set_scene_digest(Sha256Digest(bytes));
    cache_.Put(leased.scene_digest(), bytes);
    leased.mutable_task()->set_id("J.3");
    pb::PixelRect* rect = leased.mutable_task()->mutable_render_tile()->mutable_rect();
    rect->set_x(x);
    rect->set_width(width);
    rect->set_height(4);
    return leased;
  }

  // The error Execute throws, with its kind.
  std::pair<std::string, pb::FailureKind> Failure(const pb::LeaseTaskResponse& leased) {
    try {
      executor_.Execute(leased, std::stop_token());
    } catch (const std::exception& e) {
      return {e.what(), FailureKindOf(e)};
    }
    return {"done", pb::FAILURE_KIND_UNSPECIFIED};
  }

  static pb::Scene ValidScene() {
    pb::Scene s = MakeScene(8, 8, {0, 0, -5}, {0, 0, 0}, {0, 1, 0}, 40);
    AddLambert(s, "grey", Rgb(0.5f));
    AddSphere(s, "grey", {0, 0, 0}, 1);
    AddPointLight(s, {0, 3, 0}, Rgb(1));
    return s;
  }

  std::filesystem::path dir_;
  BlobCache cache_;
  BlobClient blobs_;
  TaskExecutor executor_;
};

TEST_F(TaskExecutorTest, ACoordinatorsTaskIsUnsupported) {
  pb::LeaseTaskResponse leased;
  leased.mutable_task()->set_id("J.9");
  leased.mutable_task()->mutable_build_photon_map();
  EXPECT_EQ(Failure(leased), std::pair(std::string("task J.9 is a Build photon map task, which workers do not run"),
                                       pb::FAILURE_KIND_UNSUPPORTED));
}

TEST_F(TaskExecutorTest, ASceneThatBreaksTheContractIsBadInput) {
  pb::Scene scene = ValidScene();
  scene.mutable_sampling()->set_light_samples(4096);
  EXPECT_EQ(Failure(RenderTile(scene, 0, 4)),
            std::pair(std::string("sampling.light_samples: must be <= 1024 (0 selects 16), got 4096"),
                      pb::FAILURE_KIND_BAD_INPUT));
}

TEST_F(TaskExecutorTest, ARectOutsideTheFilmIsBadInput) {
  const auto [error, kind] = Failure(RenderTile(ValidScene(), 6, 4));
  EXPECT_EQ(kind, pb::FAILURE_KIND_BAD_INPUT);
  EXPECT_EQ(error.rfind("render_tile.rect (x 6, y 0, 4x4) is empty or outside the 8x8 film", 0), 0u) << error;
}

}  // namespace
}  // namespace farm
