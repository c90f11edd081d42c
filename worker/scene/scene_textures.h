#pragma once

// Binds the textures principled materials name to SceneData::textures while a scene is
// built: each (texture, use) pair is prepared by the worker's texture system once (a base
// colour and a normal map reading the same image are decoded differently), and only the
// textures some material names are fetched.

#include <map>
#include <string>
#include <utility>

#include "scene/materials.h"
#include "scene/scene.h"
#include "scene/scene_data.h"

namespace renderfarm::v1 {
class Principled;
class Scene;
class TextureRef;
}  // namespace renderfarm::v1

namespace farm {

class TextureBinder {
 public:
  TextureBinder(const renderfarm::v1::Scene& description, const SceneOptions& options, SceneData& data);

  // Sets m's texture indices from p's references; `field` names p in messages
  // ("materials[2].principled"). Throws SceneError for a texture that is not an image the
  // rules allow, naming the field and the texture.
  void Bind(const renderfarm::v1::Principled& p, const std::string& field, PrincipledMaterial& m);

 private:
  TextureIndex Use(const renderfarm::v1::TextureRef& ref, TextureUse use, const std::string& field);

  const renderfarm::v1::Scene& description_;
  const SceneOptions& options_;
  SceneData& data_;
  std::map<std::pair<std::string, TextureUse>, TextureIndex> bound_;
};

}  // namespace farm
