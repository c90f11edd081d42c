#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

#include "contract/failure.h"

namespace renderfarm::v1 {
class Scene;
}

namespace farm {

// Thrown when a scene description cannot be turned into a renderable scene (a value out of
// range, a material name that does not exist, a mesh that does not parse, ...): bad input.
// The message starts with the field's path and ": " ("shapes[3].mesh: ..."), as the
// coordinator's refusals do.
class SceneError : public BadInputError {
 public:
  using BadInputError::BadInputError;
};

// Returns the bytes of a blob (a mesh file) by its content digest; the daemon fetches and
// caches them from the blob store. Throws if the blob cannot be had.
using BlobLoader = std::function<std::string(const std::string& digest)>;

// Returns the path of a blob's file (a texture) by its content digest, fetched into the
// daemon's blob cache if need be.
using BlobFileLoader = std::function<std::filesystem::path(const std::string& digest)>;

class TextureSystem;
struct SceneData;

// What building a scene takes beside its description and its blobs.
struct SceneOptions {
  // The worker's texture system (it outlives the scene) and where it gets a texture blob's
  // file; without them a scene whose materials name textures cannot be built.
  TextureSystem* textures = nullptr;
  BlobFileLoader load_file;
};

// A renderable scene: camera, film, materials, emitters and an Embree BVH over the
// geometry. Built once per job on a worker, then shared read-only by all render threads.
class Scene {
 public:
  // Checks the description as the coordinator does (scene/scene_rules.h), then builds it.
  // Throws SceneError; a mesh that does not parse is named by its shape's field, its path
  // in the scene file and the line that breaks it.
  static Scene Build(const renderfarm::v1::Scene& description, const BlobLoader& load_blob,
                     const SceneOptions& options = {});

  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;
  ~Scene();

  int width() const;
  int height() const;
  int tile_size() const;

  const SceneData& data() const { return *data_; }

 private:
  explicit Scene(std::unique_ptr<SceneData> data);
  std::unique_ptr<SceneData> data_;
};

}  // namespace farm
