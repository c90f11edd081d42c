#include "daemon/task_executor.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "contract/failure.h"
#include "contract/rules.h"
#include "contract/tasks.h"
#include "daemon/version.h"
#include "image/composite.h"
#include "image/reference_exr.h"
#include "image/round_accumulator.h"
#include "image/image_error.h"
#include "image/sample_map.h"
#include "image/srgb_preview.h"
#include "image/tile_exr.h"
#include "photon/irradiance_precompute.h"
#include "photon/photon_tracer.h"
#include "photonmap/photon_snapshot.h"
#include "render/tile_renderer.h"
#include "renderfarm/v1/scene.pb.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "scene/scene_rules.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

struct Film {
  ImageSize size;
  int tile_size = 0;
};

// The film of a scene that has passed CheckScene.
Film FilmOf(const pb::Scene& scene) {
  const pb::Film& f = scene.film();
  return {{static_cast<int>(f.width()), static_cast<int>(f.height())},
          static_cast<int>(contract::OrDefault<pb::Film>(f.tile_size(), "tile_size"))};
}

// A rectangle from the wire, checked to be a non-empty part of the film.
PixelRect RectIn(const pb::PixelRect& r, ImageSize film, const char* field) {
  const auto inside = [](std::uint64_t start, std::uint64_t extent, int limit) {
    return extent > 0 && start + extent <= static_cast<std::uint64_t>(limit);
  };
  if (!inside(r.x(), r.width(), film.width) || !inside(r.y(), r.height(), film.height)) {
    throw BadInputError(std::string(field) + " (x " + std::to_string(r.x()) + ", y " +
                             std::to_string(r.y()) + ", " + std::to_string(r.width()) + "x" +
                             std::to_string(r.height()) + ") is empty or outside the " +
                             std::to_string(film.width) + "x" + std::to_string(film.height) +
                             " film");
  }
  return {static_cast<int>(r.x()), static_cast<int>(r.y()), static_cast<int>(r.width()),
          static_cast<int>(r.height())};
}

pb::Artifact MakeArtifact(pb::ArtifactKind kind, const std::string& digest, std::size_t size) {
  pb::Artifact a;
  a.set_name(contract::ArtifactName(kind));
  a.set_digest(digest);
  a.set_size_bytes(static_cast<std::int64_t>(size));
  return a;
}

void ThrowIfStopped(std::stop_token stop) {
  if (stop.stop_requested()) throw TaskCancelled();
}

const char* MapName(pb::PhotonMapKind kind) {
  switch (kind) {
    case pb::PHOTON_MAP_KIND_GLOBAL:
      return "global";
    case pb::PHOTON_MAP_KIND_CAUSTIC:
      return "caustic";
    default:
      return "unknown";
  }
}

// The tracer's request for an emission spec from the wire. Round r of N paths per round
// owns the absolute path indices [(r-1)·N, r·N); the tracer counts the shard's range from
// the round's start (and checks it lies inside the round's N paths).
PhotonShardRequest ShardRequestOf(const pb::Task& task) {
  const pb::EmitPhotonsSpec& spec = task.emit_photons();
  PhotonShardRequest r;
  switch (spec.map()) {
    case pb::PHOTON_MAP_KIND_GLOBAL:
      r.map = PhotonMapKind::kGlobal;
      break;
    case pb::PHOTON_MAP_KIND_CAUSTIC:
      r.map = PhotonMapKind::kCaustic;
      break;
    case pb::PHOTON_MAP_KIND_VOLUME:
      r.map = PhotonMapKind::kVolume;
      break;
    default:
      throw BadInputError("emit_photons.map " + std::to_string(spec.map()) + " is not a photon map");
  }
  r.total_photons = spec.total_photons();
  const std::uint64_t round = std::max<std::uint32_t>(task.round(), 1);
  if (r.total_photons == 0 || (round - 1) > UINT64_MAX / r.total_photons)
    throw BadInputError("emit_photons: round " + std::to_string(round) + " of " +
                             std::to_string(r.total_photons) + " paths is out of range");
  r.round_offset = (round - 1) * r.total_photons;
  if (spec.first_photon() < r.round_offset)
    throw BadInputError("emit_photons.first_photon " + std::to_string(spec.first_photon()) +
                             " lies before round " + std::to_string(round));
  r.first_photon = spec.first_photon() - r.round_offset;
  r.photon_count = spec.photon_count();
  return r;
}

// A radius_scale from the wire (tiles, precompute): 0 (unset) means 1; else finite in (0, 1].
double RadiusScaleOf(double v) {
  if (v == 0) return 1.0;
  if (!std::isfinite(v) || v < 0 || v > 1) {
    throw BadInputError("radius_scale " + std::to_string(v) + " is not in (0, 1]");
  }
  return v;
}

TaskResult Outputs(std::vector<pb::Artifact> artifacts) {
  TaskResult result;
  result.outputs = std::move(artifacts);
  return result;
}

// The previews' exposure and tone map (Scene.output; unset, the contract's FILMIC).
PreviewSettings PreviewOf(const pb::Scene& scene) {
  const pb::Output& o = scene.output();
  return {o.exposure_stops(), o.tone_map() == pb::TONE_MAP_CLAMP ? ToneMap::kClamp : ToneMap::kFilmic};
}

// What round `round`'s composite makes besides pixels: the previews' tone mapping and the
// final EXR's metadata (samples per ordinary pixel over all rounds, as the job's round
// reports count them).
OutputSettings OutputOf(const pb::Scene& scene, const Film& film, std::uint32_t round, const pb::CompositeSpec& spec) {
  OutputSettings out{PreviewOf(scene), {}};
  const Camera camera = Camera::FromProto(scene.camera(), film.size.width, film.size.height);
  out.metadata.world_to_camera = camera.WorldToCamera();
  out.metadata.world_to_ndc = camera.WorldToNdc();
  if (spec.elapsed_seconds() > 0) out.metadata.render_seconds = spec.elapsed_seconds();
  const std::uint32_t spp = contract::OrDefault<pb::Sampling>(scene.sampling().samples_per_pixel(), "samples_per_pixel");
  out.metadata.samples_per_pixel = static_cast<int>(round * spp);  // at most 1000 x 65536
  out.metadata.rounds = static_cast<int>(round);
  out.metadata.software = std::string("photonfarm ") + kWorkerVersion;
  return out;
}

// The most samples a pixel of the scene may draw in a round under adaptive sampling.
std::uint32_t MaxSamplesOf(const pb::Scene& scene) {
  return AdaptiveMaxSamples(contract::OrDefault<pb::Sampling>(scene.sampling().samples_per_pixel(), "samples_per_pixel"),
                            contract::OrDefault<pb::Antialiasing>(scene.antialiasing().edge_samples(), "edge_samples"));
}

// The task's round, from 1.
std::uint32_t RoundOf(const pb::Task& task) { return std::max<std::uint32_t>(task.round(), 1); }

// Runs `fetch` (a blob transfer), putting what the blob holds before the message of any
// error it throws, whose kind it keeps: "the scene: blob sha256:... is not in the
// coordinator's blob store" (lost input), "the photon snapshot of round 2: cannot cache
// blob ...: No space left on device" (resource exhaustion).
template <typename Fetch>
auto Fetching(const std::string& what, std::stop_token stop, Fetch fetch) -> decltype(fetch()) {
  try {
    return fetch();
  } catch (const TaskCancelled&) {
    throw;
  } catch (const std::exception& e) {
    ThrowIfStopped(stop);
    throw TaskError(FailureKindOf(e), what + ": " + e.what());
  }
}

std::string SnapshotOfRound(const pb::Task& task) {
  return "the photon snapshot of round " + std::to_string(RoundOf(task));
}

}  // namespace

std::string DescribeTask(const pb::Task& task) {
  switch (task.spec_case()) {
    case pb::Task::kEmitPhotons: {
      const auto& e = task.emit_photons();
      return std::string("emit_photons (") + MapName(e.map()) + " " + std::to_string(e.first_photon()) +
             "+" + std::to_string(e.photon_count()) + " of " + std::to_string(e.total_photons()) + ")";
    }
    case pb::Task::kBuildPhotonMap:
      return "build_photon_map (" + std::to_string(task.build_photon_map().shards_size()) + " shards)";
    case pb::Task::kRenderTile: {
      const auto& r = task.render_tile().rect();
      return "render_tile (x " + std::to_string(r.x()) + ", y " + std::to_string(r.y()) + ", " +
             std::to_string(r.width()) + "x" + std::to_string(r.height()) + ")";
    }
    case pb::Task::kComposite:
      return "composite (round " + std::to_string(task.round()) + ", " +
             std::to_string(task.composite().tiles_size()) + " tiles)";
    case pb::Task::kPrecomputeIrradiance: {
      const auto& p = task.precompute_irradiance();
      return "precompute_irradiance (round " + std::to_string(task.round()) + ", part " +
             std::to_string(p.part() + 1) + " of " + std::to_string(p.parts()) + ")";
    }
    case pb::Task::kMergeIrradiance:
      return "merge_irradiance (" + std::to_string(task.merge_irradiance().irradiance_shards_size()) +
             " shards)";
    default:
      return "unknown kind";
  }
}

TaskExecutor::TaskExecutor(BlobClient& blobs) : blobs_(blobs) {}
TaskExecutor::TaskExecutor(BlobClient& blobs, TextureSystemOptions textures)
    : blobs_(blobs), texture_options_(std::move(textures)) {}
TaskExecutor::~TaskExecutor() = default;

TaskResult TaskExecutor::Execute(const pb::LeaseTaskResponse& leased, std::stop_token stop,
                                 Progress progress) {
  switch (leased.task().spec_case()) {
    case pb::Task::kPrecomputeIrradiance:
      return PrecomputeIrradiance(leased, stop, progress);
    case pb::Task::kRenderTile:
      return RenderTile(leased, stop, progress);
    case pb::Task::kComposite:
      return Composite(leased, stop, progress);
    case pb::Task::kEmitPhotons:
      return EmitPhotons(leased, stop, progress);
    default: {
      const pb::Phase phase = contract::PhaseOf(leased.task());
      const contract::PhaseEntry* entry = contract::FindPhase(phase);
      const bool ours = entry && entry->executor == pb::EXECUTOR_WORKER;
      throw UnsupportedError("task " + leased.task().id() + " is a " + contract::PhaseLabel(phase) + " task, which " +
                             (ours ? "this worker cannot run (is it out of date?)" : "workers do not run"));
    }
  }
}

const pb::Scene& TaskExecutor::Description(const std::string& digest, std::stop_token stop,
                                           Progress progress) {
  if (!description_ || description_digest_ != digest) {
    const std::string bytes = Fetching("the scene", stop, [&] { return blobs_.Fetch(digest, stop, progress); });
    auto scene = std::make_unique<pb::Scene>();
    if (!scene->ParseFromString(bytes)) {
      throw BadInputError("scene blob " + digest + " is not a binary renderfarm.v1.Scene");
    }
    CheckScene(*scene);  // every task, even one that needs only the film
    description_ = std::move(scene);
    description_digest_ = digest;
  }
  return *description_;
}

const Scene& TaskExecutor::Built(const std::string& digest, std::stop_token stop,
                                 Progress progress) {
  if (!built_ || built_digest_ != digest) {
    built_.reset();  // Frees the previous scene before building the next.
    const pb::Scene& description = Description(digest, stop, progress);
    const BlobLoader load = [this, stop, progress](const std::string& mesh_digest) {
      return blobs_.Fetch(mesh_digest, stop, progress);
    };
    SceneOptions options;
    // Texture blobs stay pinned in the cache (no worker sharing it evicts them) until the
    // scene is built: the texture system prepares its own copies from them.
    std::vector<BlobCache::Pinned> texture_blobs;
    if (description.textures_size() > 0 && texture_options_) {
      if (!textures_) textures_ = std::make_unique<TextureSystem>(*texture_options_);
      options.textures = textures_.get();
      options.load_file = [this, stop, progress, &texture_blobs](const std::string& texture_digest) {
        texture_blobs.push_back(blobs_.FetchFile(texture_digest, stop, progress));
        return texture_blobs.back().path();
      };
    }
    built_ = std::make_unique<Scene>(Scene::Build(description, load, options));
    built_digest_ = digest;
  }
  return *built_;
}

const PhotonSnapshot& TaskExecutor::Photons(const std::string& digest, const std::string& what,
                                            std::stop_token stop, Progress progress) {
  if (!photons_ || photons_digest_ != digest) {
    photons_.reset();  // Unmaps the previous job's snapshot first, then unpins it.
    photons_file_.reset();
    photons_file_ = Fetching(what, stop, [&] { return blobs_.FetchFile(digest, stop, progress); });
    ThrowIfStopped(stop);
    try {
      photons_ = std::make_unique<PhotonSnapshot>(PhotonSnapshot::Open(photons_file_->path()));
    } catch (const std::exception& e) {
      throw TaskError(FailureKindOf(e), what + " (blob " + digest + "): " + e.what());
    }
    photons_digest_ = digest;
  }
  return *photons_;
}

TaskResult TaskExecutor::EmitPhotons(const pb::LeaseTaskResponse& leased, std::stop_token stop,
                                     Progress progress) {
  const PhotonShardRequest request = ShardRequestOf(leased.task());
  const Scene& scene = Built(leased.scene_digest(), stop, progress);
  ThrowIfStopped(stop);
  const std::string shard = TracePhotonShard(scene, request, stop, progress);
  ThrowIfStopped(stop);  // A stopped trace returns an unfinished shard.
  const std::string digest = blobs_.Upload(shard, stop, progress);
  return Outputs({MakeArtifact(pb::ARTIFACT_KIND_PHOTON_SHARD, digest, shard.size())});
}

TaskResult TaskExecutor::PrecomputeIrradiance(const pb::LeaseTaskResponse& leased,
                                              std::stop_token stop, Progress progress) {
  const pb::PrecomputeIrradianceSpec& spec = leased.task().precompute_irradiance();
  if (!spec.has_photon_snapshot()) {
    throw BadInputError("precompute_irradiance has no photon_snapshot");
  }
  const Scene& scene = Built(leased.scene_digest(), stop, progress);
  const PhotonSnapshot& photons =
      Photons(spec.photon_snapshot().digest(), SnapshotOfRound(leased.task()), stop, progress);
  ThrowIfStopped(stop);
  if (spec.parts() == 0 || spec.part() >= spec.parts()) {
    throw BadInputError("precompute_irradiance: part " + std::to_string(spec.part()) + " of " +
                        std::to_string(spec.parts()) + " (want part < parts)");
  }
  const std::string shard = ComputeIrradianceShard(scene, photons, spec.part(), spec.parts(),
                                                   RadiusScaleOf(spec.radius_scale()), stop, progress);
  ThrowIfStopped(stop);
  const std::string digest = blobs_.Upload(shard, stop, progress);
  return Outputs({MakeArtifact(pb::ARTIFACT_KIND_IRRADIANCE_SHARD, digest, shard.size())});
}

TaskResult TaskExecutor::RenderTile(const pb::LeaseTaskResponse& leased, std::stop_token stop,
                                    Progress progress) {
  const pb::Scene& description = Description(leased.scene_digest(), stop, progress);
  const Film film = FilmOf(description);
  const PreviewSettings preview = PreviewOf(description);
  const PixelRect rect = RectIn(leased.task().render_tile().rect(), film.size, "render_tile.rect");
  const Scene& scene = Built(leased.scene_digest(), stop, progress);
  const pb::RenderTileSpec& spec = leased.task().render_tile();
  const PhotonSnapshot* photons = nullptr;
  if (spec.has_photon_snapshot()) {
    photons = &Photons(spec.photon_snapshot().digest(), SnapshotOfRound(leased.task()), stop, progress);
  }
  std::optional<SampleMap> allocated;
  if (spec.has_sample_map()) {
    const std::string what = "the sample map of round " + std::to_string(RoundOf(leased.task()));
    const std::string bytes =
        Fetching(what, stop, [&] { return blobs_.Fetch(spec.sample_map().digest(), stop, progress); });
    try {
      allocated = DecodeSampleMap(bytes, film.size, MaxSamplesOf(description));
    } catch (const ImageError& e) {
      throw BadInputError(what + ": " + e.what());
    }
  }
  ThrowIfStopped(stop);
  RoundSettings round{RadiusScaleOf(spec.radius_scale()), spec.first_sample()};
  // A job of one round has no error estimate to give the bias layer to.
  round.bias_layer = description.progressive().max_rounds() > 1;
  if (allocated) {
    round.samples = allocated->counts;
    round.max_samples = MaxSamplesOf(description);
  }
  SampleCounts counts;
  const Image tile = farm::RenderTile(scene, photons, rect, round, stop, progress, &counts);
  ThrowIfStopped(stop);  // A stopped render returns an unfinished image.
  if (tile.rect() != rect) throw std::runtime_error("renderer returned a tile of the wrong size");
  const std::string exr = EncodeTileExr(tile, film.size);
  const std::string digest = blobs_.Upload(exr, stop, progress);
  // The tile's sRGB preview, for the dashboard to show before the image is composited;
  // the composite reads only the tile EXR.
  const std::string png = EncodeTilePreviewPng(tile, preview);
  const std::string png_digest = blobs_.Upload(png, stop, progress);
  TaskResult result = Outputs({MakeArtifact(pb::ARTIFACT_KIND_TILE_EXR, digest, exr.size()),
                               MakeArtifact(pb::ARTIFACT_KIND_TILE_PNG, png_digest, png.size())});
  result.samples.emplace();
  result.samples->set_samples(counts.samples);
  result.samples->set_nonfinite(counts.nonfinite);
  result.samples->set_zero(counts.zero);
  return result;
}

TaskResult TaskExecutor::Composite(const pb::LeaseTaskResponse& leased, std::stop_token stop,
                                   Progress progress) {
  // A composite needs neither the built scene nor the photon snapshot: they are freed
  // first, so that the largest composite and the largest scene never add up in one worker
  // (docs/limits.md, "Worker memory"). A next round's tiles build the scene again.
  photons_.reset();
  photons_file_.reset();
  built_.reset();
  const pb::Scene& description = Description(leased.scene_digest(), stop, progress);
  const Film film = FilmOf(description);
  const pb::CompositeSpec& spec = leased.task().composite();
  std::vector<EncodedTile> tiles;
  tiles.reserve(static_cast<std::size_t>(spec.tiles_size()));
  const std::uint32_t round = RoundOf(leased.task());
  const auto download = [&](const std::string& what, const pb::Artifact& a) {
    return Fetching(what, stop, [&] { return blobs_.Download(a.digest(), stop, progress); });
  };
  for (const pb::TileInput& t : spec.tiles()) {
    const PixelRect rect = RectIn(t.rect(), film.size, "composite.tiles.rect");
    tiles.push_back({rect, download("tile x " + std::to_string(rect.x) + " y " + std::to_string(rect.y) +
                                        " of round " + std::to_string(round),
                                    t.tile())});
    ThrowIfStopped(stop);
  }
  RoundInputs in;
  in.size = film.size;
  in.tile_size = film.tile_size;
  in.round = static_cast<int>(round);
  in.tiles = tiles;
  in.output = OutputOf(description, film, round, spec);
  if (spec.has_previous_accumulation()) {
    in.previous_accumulation =
        download("the accumulation of round " + std::to_string(round - 1), spec.previous_accumulation());
  }
  if (spec.has_reference()) in.reference_exr = download("the reference image", spec.reference());
  in.measured_layers = contract::Keys<pb::RoundMetrics>("layer_reference_rmse");
  in.samples_per_pixel = contract::OrDefault<pb::Sampling>(description.sampling().samples_per_pixel(), "samples_per_pixel");
  if (description.sampling().adaptive() == pb::ADAPTIVE_SAMPLING_ON) in.adaptive_max_samples = MaxSamplesOf(description);
  if (spec.has_sample_map()) in.sample_map = download("the sample map of round " + std::to_string(round), spec.sample_map());
  ThrowIfStopped(stop);
  RoundOutputs out;
  try {
    out = AccumulateRound(in, progress);
  } catch (const ReferenceImageError& e) {
    throw BadInputError(std::string("progressive.reference.digest: ") + e.what());
  }
  ThrowIfStopped(stop);
  TaskResult result;
  for (const auto& [kind, bytes] : {std::pair{pb::ARTIFACT_KIND_IMAGE_EXR, &out.image_exr},
                                    std::pair{pb::ARTIFACT_KIND_PREVIEW_PNG, &out.preview_png},
                                    std::pair{pb::ARTIFACT_KIND_ACCUMULATION_EXR, &out.accumulation_exr}}) {
    result.outputs.push_back(MakeArtifact(kind, blobs_.Upload(*bytes, stop, progress), bytes->size()));
  }
  if (out.sample_map) {
    result.outputs.push_back(MakeArtifact(pb::ARTIFACT_KIND_SAMPLE_MAP, blobs_.Upload(*out.sample_map, stop, progress),
                                          out.sample_map->size()));
  }
  pb::RoundMetrics metrics;
  if (out.error_estimate) {
    metrics.set_error_estimate(out.error_estimate->rmse);
    metrics.set_error_estimate_bias(out.error_estimate->bias);
    metrics.set_error_estimate_low(out.error_estimate->low);
    metrics.set_error_estimate_high(out.error_estimate->high);
  }
  if (out.reference_rmse) metrics.set_reference_rmse(*out.reference_rmse);
  for (const auto& [layer, rmse] : out.layer_reference_rmse) (*metrics.mutable_layer_reference_rmse())[layer] = rmse;
  if (out.samples) {
    pb::SampleSpread& spread = *metrics.mutable_samples();
    spread.set_layer(out.samples->layer);
    spread.set_min(out.samples->min);
    spread.set_mean(out.samples->mean);
    spread.set_max(out.samples->max);
    if (out.samples->top_error_decile_share) spread.set_top_error_decile_share(*out.samples->top_error_decile_share);
  }
  result.metrics = metrics;
  return result;
}

}  // namespace farm
