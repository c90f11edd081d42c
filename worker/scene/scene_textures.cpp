#include "scene/scene_textures.h"

#include <stdexcept>

#include "contract/go_text.h"
#include "renderfarm/v1/scene.pb.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

TextureEncoding EncodingOf(pb::ColorEncoding encoding) {
  switch (encoding) {
    case pb::COLOR_ENCODING_SRGB: return TextureEncoding::kSrgb;
    case pb::COLOR_ENCODING_LINEAR: return TextureEncoding::kLinear;
    default: return TextureEncoding::kByUse;  // unspecified (the rules refuse undeclared values)
  }
}

TextureWrap WrapOf(pb::TextureWrap wrap) {
  switch (wrap) {
    case pb::TEXTURE_WRAP_CLAMP: return TextureWrap::kClamp;
    case pb::TEXTURE_WRAP_MIRROR: return TextureWrap::kMirror;
    default: return TextureWrap::kRepeat;  // unspecified selects REPEAT
  }
}

}  // namespace

TextureBinder::TextureBinder(const pb::Scene& description, const SceneOptions& options, SceneData& data)
    : description_(description), options_(options), data_(data) {}

void TextureBinder::Bind(const pb::Principled& p, const std::string& field, PrincipledMaterial& m) {
  if (p.has_base_color_texture())
    m.base_color_texture = Use(p.base_color_texture(), TextureUse::kColor, field + ".base_color_texture");
  if (p.has_metallic_roughness_texture())
    m.metallic_roughness_texture =
        Use(p.metallic_roughness_texture(), TextureUse::kData, field + ".metallic_roughness_texture");
  if (p.has_normal_texture()) m.normal_texture = Use(p.normal_texture(), TextureUse::kData, field + ".normal_texture");
  if (p.has_emission_texture())
    m.emission_texture = Use(p.emission_texture(), TextureUse::kColor, field + ".emission_texture");
}

TextureIndex TextureBinder::Use(const pb::TextureRef& ref, TextureUse use, const std::string& field) {
  const auto key = std::make_pair(ref.texture(), use);
  if (const auto it = bound_.find(key); it != bound_.end()) return it->second;
  const pb::Texture* texture = nullptr;
  for (const pb::Texture& t : description_.textures())
    if (t.name() == ref.texture()) texture = &t;
  if (!texture) throw SceneError(field + ".texture: no texture named " + contract::GoQuote(ref.texture()));
  if (!options_.textures || !options_.load_file)
    throw std::runtime_error(field + ": this worker was started without a texture system");
  const std::string name = contract::GoQuote(texture->path().empty() ? texture->name() : texture->path());
  PreparedTexture prepared;
  try {
    prepared = options_.textures->Prepare(texture->digest(), use, EncodingOf(texture->encoding()),
                                          [&] { return options_.load_file(texture->digest()); });
  } catch (const BadInputError& e) {
    throw SceneError(field + ": texture " + name + ": " + e.what());
  } catch (const std::exception& e) {
    // Of the kind the error is (the blob store being away is not the scene's fault).
    throw TaskError(FailureKindOf(e), field + ": texture " + name + ": " + e.what());
  }
  data_.textures.push_back(SceneTexture{prepared, WrapOf(texture->wrap())});
  data_.texture_system = options_.textures;
  const auto index = static_cast<TextureIndex>(data_.textures.size() - 1);
  bound_.emplace(key, index);
  return index;
}

}  // namespace farm
