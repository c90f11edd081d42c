#include "daemon/task_executor.h"

#include <algorithm>
#include <filesystem>

#include "image/composite.h"
#include "image/tile_exr.h"
#include "photon/photon_tracer.h"
#include "photonmap/photon_snapshot.h"
#include "render/tile_renderer.h"
#include "renderfarm/v1/scene.pb.h"
#include "scene/scene.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

// Film.tile_size 0 selects this default (see scene.proto).
constexpr int kDefaultTileSize = 32;
// Far beyond any real film; keeps a hostile scene from making us allocate absurd buffers.
constexpr std::uint32_t kMaxFilmSide = 1 << 16;

struct Film {
  ImageSize size;
  int tile_size = 0;
};

Film FilmOf(const pb::Scene& scene) {
  const pb::Film& f = scene.film();
  if (f.width() == 0 || f.height() == 0 || f.width() > kMaxFilmSide || f.height() > kMaxFilmSide) {
    throw std::runtime_error("scene film size " + std::to_string(f.width()) + "x" +
                             std::to_string(f.height()) + " is out of range");
  }
  if (f.tile_size() > kMaxFilmSide) throw std::runtime_error("scene film tile_size is out of range");
  return {{static_cast<int>(f.width()), static_cast<int>(f.height())},
          f.tile_size() == 0 ? kDefaultTileSize : static_cast<int>(f.tile_size())};
}

// A rectangle from the wire, checked to be a non-empty part of the film.
PixelRect RectIn(const pb::PixelRect& r, ImageSize film, const char* field) {
  const auto inside = [](std::uint64_t start, std::uint64_t extent, int limit) {
    return extent > 0 && start + extent <= static_cast<std::uint64_t>(limit);
  };
  if (!inside(r.x(), r.width(), film.width) || !inside(r.y(), r.height(), film.height)) {
    throw std::runtime_error(std::string(field) + " (x " + std::to_string(r.x()) + ", y " +
                             std::to_string(r.y()) + ", " + std::to_string(r.width()) + "x" +
                             std::to_string(r.height()) + ") is empty or outside the " +
                             std::to_string(film.width) + "x" + std::to_string(film.height) +
                             " film");
  }
  return {static_cast<int>(r.x()), static_cast<int>(r.y()), static_cast<int>(r.width()),
          static_cast<int>(r.height())};
}

pb::Artifact MakeArtifact(const char* name, const std::string& digest, std::size_t size) {
  pb::Artifact a;
  a.set_name(name);
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

// The tracer's request for an emission spec from the wire, checked.
PhotonShardRequest ShardRequestOf(const pb::EmitPhotonsSpec& spec) {
  PhotonShardRequest r;
  switch (spec.map()) {
    case pb::PHOTON_MAP_KIND_GLOBAL:
      r.map = PhotonMapKind::kGlobal;
      break;
    case pb::PHOTON_MAP_KIND_CAUSTIC:
      r.map = PhotonMapKind::kCaustic;
      break;
    default:
      throw std::runtime_error("emit_photons.map " + std::to_string(spec.map()) + " is not a photon map");
  }
  if (spec.photon_count() == 0 || spec.total_photons() == 0 ||
      spec.first_photon() > spec.total_photons() ||
      spec.photon_count() > spec.total_photons() - spec.first_photon()) {
    throw std::runtime_error("emit_photons: photons " + std::to_string(spec.first_photon()) + "+" +
                             std::to_string(spec.photon_count()) + " are not a non-empty part of " +
                             std::to_string(spec.total_photons()));
  }
  r.first_photon = spec.first_photon();
  r.photon_count = spec.photon_count();
  r.total_photons = spec.total_photons();
  return r;
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
      return "composite (" + std::to_string(task.composite().tiles_size()) + " tiles)";
    default:
      return "unknown kind";
  }
}

TaskExecutor::TaskExecutor(BlobClient& blobs) : blobs_(blobs) {}
TaskExecutor::~TaskExecutor() = default;

std::vector<pb::Artifact> TaskExecutor::Execute(const pb::LeaseTaskResponse& leased,
                                                std::stop_token stop) {
  switch (leased.task().spec_case()) {
    case pb::Task::kRenderTile:
      return RenderTile(leased, stop);
    case pb::Task::kComposite:
      return Composite(leased, stop);
    case pb::Task::kEmitPhotons:
      return EmitPhotons(leased, stop);
    default:
      throw std::runtime_error("task " + leased.task().id() +
                               " has a kind this worker does not know (is it out of date?)");
  }
}

const pb::Scene& TaskExecutor::Description(const std::string& digest, std::stop_token stop) {
  if (!description_ || description_digest_ != digest) {
    const std::string bytes = blobs_.Fetch(digest, stop);
    auto scene = std::make_unique<pb::Scene>();
    if (!scene->ParseFromString(bytes)) {
      throw std::runtime_error("scene blob " + digest + " is not a binary renderfarm.v1.Scene");
    }
    description_ = std::move(scene);
    description_digest_ = digest;
  }
  return *description_;
}

const Scene& TaskExecutor::Built(const std::string& digest, std::stop_token stop) {
  if (!built_ || built_digest_ != digest) {
    built_.reset();  // Frees the previous scene before building the next.
    const pb::Scene& description = Description(digest, stop);
    const BlobLoader load = [this, stop](const std::string& mesh_digest) {
      return blobs_.Fetch(mesh_digest, stop);
    };
    built_ = std::make_unique<Scene>(Scene::Build(description, load));
    built_digest_ = digest;
  }
  return *built_;
}

const PhotonSnapshot& TaskExecutor::Photons(const std::string& digest, std::stop_token stop) {
  if (!photons_ || photons_digest_ != digest) {
    photons_.reset();  // Unmaps the previous job's snapshot first.
    const std::filesystem::path file = blobs_.FetchFile(digest, stop);
    ThrowIfStopped(stop);
    try {
      photons_ = std::make_unique<PhotonSnapshot>(PhotonSnapshot::Open(file));
    } catch (const std::exception& e) {
      throw std::runtime_error("photon snapshot " + digest + ": " + e.what());
    }
    photons_digest_ = digest;
  }
  return *photons_;
}

std::vector<pb::Artifact> TaskExecutor::EmitPhotons(const pb::LeaseTaskResponse& leased,
                                                    std::stop_token stop) {
  const PhotonShardRequest request = ShardRequestOf(leased.task().emit_photons());
  const Scene& scene = Built(leased.scene_digest(), stop);
  ThrowIfStopped(stop);
  const std::string shard = TracePhotonShard(scene, request, stop);
  ThrowIfStopped(stop);  // A stopped trace returns an unfinished shard.
  const std::string digest = blobs_.Upload(shard, stop);
  return {MakeArtifact("photons.shard", digest, shard.size())};
}

std::vector<pb::Artifact> TaskExecutor::RenderTile(const pb::LeaseTaskResponse& leased,
                                                   std::stop_token stop) {
  const Film film = FilmOf(Description(leased.scene_digest(), stop));
  const PixelRect rect = RectIn(leased.task().render_tile().rect(), film.size, "render_tile.rect");
  const Scene& scene = Built(leased.scene_digest(), stop);
  const pb::RenderTileSpec& spec = leased.task().render_tile();
  const PhotonSnapshot* photons = nullptr;
  if (spec.has_photon_snapshot()) photons = &Photons(spec.photon_snapshot().digest(), stop);
  ThrowIfStopped(stop);
  const Image tile = farm::RenderTile(scene, photons, rect, stop);
  ThrowIfStopped(stop);  // A stopped render returns an unfinished image.
  if (tile.rect() != rect) throw std::runtime_error("renderer returned a tile of the wrong size");
  const std::string exr = EncodeTileExr(tile, film.size);
  const std::string digest = blobs_.Upload(exr, stop);
  return {MakeArtifact("tile.exr", digest, exr.size())};
}

std::vector<pb::Artifact> TaskExecutor::Composite(const pb::LeaseTaskResponse& leased,
                                                  std::stop_token stop) {
  const Film film = FilmOf(Description(leased.scene_digest(), stop));
  const auto& inputs = leased.task().composite().tiles();
  // Row by row, so OpenEXR can write each tile at once instead of holding it back.
  std::vector<const pb::TileInput*> order;
  for (const auto& t : inputs) order.push_back(&t);
  std::stable_sort(order.begin(), order.end(), [](const pb::TileInput* a, const pb::TileInput* b) {
    return std::pair(a->rect().y(), a->rect().x()) < std::pair(b->rect().y(), b->rect().x());
  });
  Compositor compositor(film.size, film.tile_size);
  for (const pb::TileInput* t : order) {
    const PixelRect rect = RectIn(t->rect(), film.size, "composite.tiles.rect");
    std::string bytes;
    try {
      bytes = blobs_.Download(t->tile().digest(), stop);
    } catch (const BlobError& e) {
      ThrowIfStopped(stop);
      throw std::runtime_error("tile at x " + std::to_string(rect.x) + ", y " +
                               std::to_string(rect.y) + ": " + e.what());
    }
    ThrowIfStopped(stop);
    compositor.Add(rect, bytes);
  }
  const CompositeOutput out = compositor.Finish();
  ThrowIfStopped(stop);
  const std::string exr_digest = blobs_.Upload(out.exr, stop);
  const std::string png_digest = blobs_.Upload(out.preview_png, stop);
  return {MakeArtifact("image.exr", exr_digest, out.exr.size()),
          MakeArtifact("preview.png", png_digest, out.preview_png.size())};
}

}  // namespace farm
