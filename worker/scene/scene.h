#pragma once

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

namespace renderfarm::v1 {
class Scene;
}

namespace farm {

// Thrown when a scene description cannot be turned into a renderable scene (a mesh that
// does not parse, a material name that does not exist, ...). The message names the field.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Returns the bytes of a blob (a mesh file) by its content digest; the daemon fetches and
// caches them from the blob store. Throws if the blob cannot be had.
using BlobLoader = std::function<std::string(const std::string& digest)>;

struct SceneData;

// A renderable scene: camera, film, materials, emitters and an Embree BVH over the
// geometry. Built once per job on a worker, then shared read-only by all render threads.
class Scene {
 public:
  static Scene Build(const renderfarm::v1::Scene& description, const BlobLoader& load_blob);

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
