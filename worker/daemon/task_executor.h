#pragma once

// What the worker does with a leased task: trace a photon emission shard, precompute
// irradiance at global photons, render a tile (with the round's photon snapshot, if the
// job has one) or composite a round into the image so far, with the blobs and the scene
// that takes. Knows nothing of leases and reports (worker.cpp does). Internal to daemon/.

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <stop_token>
#include <string>
#include <vector>

#include "daemon/blob_client.h"
#include "renderfarm/v1/worker.pb.h"
#include "texture/texture_system.h"
#include "util/progress.h"

namespace farm {

class Scene;
class PhotonSnapshot;

// The task was stopped before it finished (shutdown or a revoked lease); it has no result.
class TaskCancelled : public std::runtime_error {
 public:
  TaskCancelled() : std::runtime_error("task cancelled") {}
};

// A short description for logs: "emit_photons (global 0+100000 of 200000)",
// "render_tile (x 0, y 32, 32x32)", "composite (12 tiles)".
std::string DescribeTask(const renderfarm::v1::Task& task);

// What a finished task reports: its artifacts (already uploaded); for a composite, the
// error metrics of the image so far; for a render tile, how its samples came out.
struct TaskResult {
  std::vector<renderfarm::v1::Artifact> outputs;
  std::optional<renderfarm::v1::RoundMetrics> metrics;
  std::optional<renderfarm::v1::TileSamples> samples;
};

class TaskExecutor {
 public:
  // Without texture options, a scene whose materials name textures cannot be built.
  explicit TaskExecutor(BlobClient& blobs);
  // Textures read through a texture system made with these options when a scene first
  // names one, kept for the process (its prepared files and tile cache outlive jobs).
  TaskExecutor(BlobClient& blobs, TextureSystemOptions textures);
  ~TaskExecutor();

  // Performs the task and returns what to report. Throws TaskCancelled if `stop` was
  // requested, any other exception if the task failed: its message is the reason to report
  // and FailureKindOf (contract/failure.h) its kind (a bad scene or spec is bad input, a
  // task this worker cannot run unsupported). Advances `progress` as the work goes: bytes of blobs moved, camera samples
  // rendered, photon paths traced, photons' irradiance computed, tiles stitched (one unit
  // for all, since the coordinator only watches it grow).
  TaskResult Execute(const renderfarm::v1::LeaseTaskResponse& leased, std::stop_token stop,
                     Progress progress = {});

  // Bytes of texture tiles the texture system's cache holds now (0 before a scene with
  // textures): at most about --texture-cache-mib MiB.
  std::uint64_t TextureCacheBytes() const { return textures_ ? textures_->CacheBytes() : 0; }

 private:
  // The job's scene description, fetched by digest; the last one is kept.
  const renderfarm::v1::Scene& Description(const std::string& digest, std::stop_token stop,
                                           Progress progress);
  // The renderable scene, built once per scene digest; the last one is kept.
  const Scene& Built(const std::string& digest, std::stop_token stop, Progress progress);
  // The photon snapshot, fetched into the on-disk cache, pinned there and mapped into
  // memory once per digest; the last one is kept. `what` names it in errors ("the photon
  // snapshot of round 2").
  const PhotonSnapshot& Photons(const std::string& digest, const std::string& what,
                                std::stop_token stop, Progress progress);

  TaskResult EmitPhotons(const renderfarm::v1::LeaseTaskResponse& leased, std::stop_token stop,
                         Progress progress);
  TaskResult PrecomputeIrradiance(const renderfarm::v1::LeaseTaskResponse& leased,
                                  std::stop_token stop, Progress progress);
  TaskResult RenderTile(const renderfarm::v1::LeaseTaskResponse& leased, std::stop_token stop,
                        Progress progress);
  TaskResult Composite(const renderfarm::v1::LeaseTaskResponse& leased, std::stop_token stop,
                       Progress progress);

  BlobClient& blobs_;
  std::optional<TextureSystemOptions> texture_options_;
  std::unique_ptr<TextureSystem> textures_;
  std::string description_digest_;
  std::unique_ptr<renderfarm::v1::Scene> description_;
  std::string built_digest_;
  std::unique_ptr<Scene> built_;
  std::string photons_digest_;
  std::optional<BlobCache::Pinned> photons_file_;  // declared first: unpinned after unmapping
  std::unique_ptr<PhotonSnapshot> photons_;
};

}  // namespace farm
