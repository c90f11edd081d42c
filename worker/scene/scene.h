#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

#include "contract/failure.h"
#include "scene/cutout.h"

namespace renderfarm::v1 {
class Material;
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
  // The cut-out test of a material (Scene.materials[index]), or an empty one for a material
  // that cuts nothing. Unset: each material's own (CutoutOf, surface_shading.h: an
  // alpha-masked principled material's).
  std::function<CutoutTest(const renderfarm::v1::Material& material, int index)> cutout_of;
  // The worker's texture system (it outlives the scene) and where it gets a texture blob's
  // file; without them a scene whose materials name textures cannot be built.
  TextureSystem* textures = nullptr;
  BlobFileLoader load_file;
};

// A renderable scene: camera, film, materials, emitters and an Embree BVH over the
// geometry. Built once per job on a worker, then shared read-only by all render threads.
class Scene {
 public:
  // Checks the description as the coordinator does (scene/scene_rules.h), then builds it:
  // each mesh file and mesh part is read once per blob, each mesh of Scene.meshes is built
  // once (placed or not) and placed by the instances that name it. Throws SceneError; a
  // mesh that does not parse is named by its shape's or part's field, its path in the
  // scene file and the line (OBJ) or byte (farm mesh file) that breaks it.
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
