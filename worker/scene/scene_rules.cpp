#include "scene/scene_rules.h"

#include <cmath>
#include <string>
#include <unordered_map>
#include <stdexcept>

#include "contract/go_text.h"
#include "contract/rules.h"
#include "scene/materials.h"
#include "scene/scene.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;
using contract::GoNumber;
using contract::GoQuote;

// The vector arithmetic of contract/scene (Go), in the same order, so that "parallel"
// is decided alike.
struct Vec {
  double x = 0, y = 0, z = 0;

  explicit Vec(const pb::Vec3& v) : x(v.x()), y(v.y()), z(v.z()) {}
  Vec(double x, double y, double z) : x(x), y(y), z(z) {}
  Vec operator-(const Vec& b) const { return {x - b.x, y - b.y, z - b.z}; }
  Vec Cross(const Vec& b) const { return {y * b.z - z * b.y, z * b.x - x * b.z, x * b.y - y * b.x}; }
  double Length() const { return std::sqrt(x * x + y * y + z * z); }
  bool IsZero() const { return x == 0 && y == 0 && z == 0; }
  std::string ToString() const {  // appended, not "(" + ...: GCC 12 warns falsely (-Wrestrict)
    std::string s = "(";
    s.append(GoNumber(x)).append(", ").append(GoNumber(y)).append(", ").append(GoNumber(z)).append(")");
    return s;
  }
};

bool Parallel(const Vec& a, const Vec& b) { return a.Cross(b).Length() <= 1e-9 * a.Length() * b.Length(); }

[[noreturn]] void Refuse(const std::string& field, const std::string& message) {
  throw SceneError(field + ": " + message);
}

std::string Index(const std::string& list, int i) { return list + "[" + std::to_string(i) + "]"; }

std::uint64_t CeilDiv(std::uint64_t a, std::uint64_t b) { return (a + b - 1) / b; }

void CheckCamera(const pb::Camera& c) {
  const Vec position(c.position()), up(c.up());
  const Vec view = Vec(c.look_at()) - position;
  if (view.IsZero()) Refuse("camera.look_at", "must differ from camera.position, both are " + position.ToString());
  if (up.IsZero()) Refuse("camera.up", "must be non-zero");
  if (Parallel(view, up))
    Refuse("camera.up", "must not be parallel to the view direction look_at - position = " + view.ToString() +
                            ", got " + up.ToString());
}

void CheckFilm(const pb::Film& f) {
  const std::uint64_t tile = contract::OrDefault<pb::Film>(f.tile_size(), "tile_size");
  const std::uint64_t across = CeilDiv(f.width(), tile), down = CeilDiv(f.height(), tile);
  const std::uint64_t limit = contract::SceneLimits().max_tiles_per_round();
  if (across * down > limit)
    Refuse("film.tile_size", "makes " + std::to_string(across * down) + " tiles (" + std::to_string(across) +
                                 " x " + std::to_string(down) + " of " + std::to_string(tile) + " pixels) in the " +
                                 std::to_string(f.width()) + "x" + std::to_string(f.height()) +
                                 " film, more than the " + std::to_string(limit) + " a round may have");
  const std::uint64_t pixels = std::uint64_t{f.width()} * f.height();
  if (pixels > contract::SceneLimits().max_film_pixels())
    Refuse("film.height", "a " + std::to_string(f.width()) + "x" + std::to_string(f.height()) + " film has " +
                              std::to_string(pixels) + " pixels, more than the " +
                              std::to_string(contract::SceneLimits().max_film_pixels()) + " a film may have");
}

// How a message quotes a name: at most 80 bytes of it, as in Go.
std::string QuotedName(const std::string& name) { return GoQuote(contract::Truncate(name, 80)); }

// Unique names of one kind: "materials[4].name: duplicate material name "white" (also
// materials[0])".
template <typename Named>
void CheckUnique(const google::protobuf::RepeatedPtrField<Named>& list, const std::string& field,
                 const std::string& what) {
  std::unordered_map<std::string, int> first;
  for (int i = 0; i < list.size(); ++i) {
    const auto [it, fresh] = first.emplace(list[i].name(), i);
    if (!fresh)
      Refuse(Index(field, i) + ".name",
             "duplicate " + what + " name " + QuotedName(list[i].name()) + " (also " + Index(field, it->second) + ")");
  }
}

void CheckNames(const pb::Scene& s) {
  CheckUnique(s.materials(), "materials", "material");
  CheckUnique(s.meshes(), "meshes", "mesh");
  CheckUnique(s.textures(), "textures", "texture");
}

template <typename Named>
std::unordered_map<std::string, const Named*> ByName(const google::protobuf::RepeatedPtrField<Named>& list) {
  std::unordered_map<std::string, const Named*> by_name;
  for (const Named& x : list) by_name.emplace(x.name(), &x);
  return by_name;
}

void CheckShapeMaterials(const pb::Scene& s) {
  const auto materials = ByName(s.materials());
  const auto meshes = ByName(s.meshes());
  for (int i = 0; i < s.shapes_size(); ++i) {
    const pb::Shape& shape = s.shapes(i);
    const std::string p = Index("shapes", i);
    const bool instance = shape.has_instance();
    if (instance && !shape.material().empty())
      Refuse(p + ".material", "must be empty for an instance, whose mesh's parts name their materials; got " +
                                  QuotedName(shape.material()));
    if (!instance && shape.material().empty()) Refuse(p + ".material", "missing; a shape names one of the scene's materials");
    if (!instance && !materials.contains(shape.material()))
      Refuse(p + ".material", "no material named " + QuotedName(shape.material()));
    if (instance && !meshes.contains(shape.instance().mesh()))
      Refuse(p + ".instance.mesh", "no mesh named " + QuotedName(shape.instance().mesh()));
  }
}

void CheckPartMaterials(const pb::Scene& s) {
  const auto materials = ByName(s.materials());
  for (int i = 0; i < s.meshes_size(); ++i)
    for (int j = 0; j < s.meshes(i).parts_size(); ++j)
      if (const pb::MeshPart& part = s.meshes(i).parts(j); !materials.contains(part.material()))
        Refuse(Index(Index("meshes", i) + ".parts", j) + ".material", "no material named " + QuotedName(part.material()));
}

void CheckTextureRefs(const pb::Scene& s) {
  const auto textures = ByName(s.textures());
  for (const TextureRefAt& ref : TextureRefs(s))
    if (!textures.contains(ref.ref->texture()))
      Refuse(ref.field + ".texture", "no texture named " + QuotedName(ref.ref->texture()));
}

bool Positive(const pb::Color& c) { return c.r() > 0 || c.g() > 0 || c.b() > 0; }

const pb::Color& LightPower(const pb::Light& l) {
  switch (l.kind_case()) {
    case pb::Light::kPoint: return l.point().intensity();
    case pb::Light::kSpot: return l.spot().intensity();
    case pb::Light::kSun: return l.sun().irradiance();
    case pb::Light::KIND_NOT_SET: break;
  }
  throw std::logic_error("LightPower: a light without a kind (CheckRules refuses it)");
}

// In double precision, as in Go: a radiance too small for float still counts.
void CheckSomeLight(const pb::Scene& s) {
  for (const pb::Light& l : s.lights())
    if (Positive(LightPower(l))) return;
  const auto materials = ByName(s.materials());
  const auto meshes = ByName(s.meshes());
  for (const pb::Shape& shape : s.shapes()) {
    if (!shape.has_instance()) {
      if (MaterialEmits(*materials.at(shape.material()))) return;
      continue;
    }
    for (const pb::MeshPart& part : meshes.at(shape.instance().mesh())->parts())
      if (MaterialEmits(*materials.at(part.material()))) return;
  }
  if (EnvironmentLights(s)) return;
  Refuse("lights",
         "the scene needs a light: a point, spot or sun light with a positive component, a shape whose material "
         "emits (emissive with a positive radiance, or principled with a positive emission), or an environment that "
         "is not black");
}

void CheckGlossyEnergy(const pb::Scene& s) {
  for (int i = 0; i < s.materials_size(); ++i) {
    const pb::Material& m = s.materials(i);
    if (!m.has_glossy()) continue;
    const pb::Color &d = m.glossy().diffuse(), &sp = m.glossy().specular();
    const struct {
      const char* name;
      double d, s;
    } channels[] = {{"r", d.r(), sp.r()}, {"g", d.g(), sp.g()}, {"b", d.b(), sp.b()}};
    for (const auto& c : channels)
      if (c.d + c.s > 1)
        Refuse(Index("materials", i) + ".glossy.specular." + c.name,
               "diffuse + specular must be <= 1 (energy conservation), got " + GoNumber(c.d) + " + " + GoNumber(c.s));
  }
}

void CheckQuad(const std::string& p, const pb::Quad& q) {
  const Vec u(q.edge_u()), v(q.edge_v());
  if (u.IsZero()) Refuse(p + ".edge_u", "must be non-zero");
  if (v.IsZero()) Refuse(p + ".edge_v", "must be non-zero");
  if (Parallel(u, v)) Refuse(p + ".edge_v", "must not be parallel to edge_u " + u.ToString() + ", got " + v.ToString());
}

void CheckTriangles(const std::string& p, const pb::TriangleMesh& t) {
  const int n = t.indices_size();
  if (n == 0 || n % 3 != 0) Refuse(p + ".indices", "count must be a non-zero multiple of 3, got " + std::to_string(n));
  for (int i = 0; i < n; ++i)
    if (t.indices(i) >= static_cast<std::uint32_t>(t.positions_size()))
      Refuse(Index(p + ".indices", i), "must be < " + std::to_string(t.positions_size()) +
                                           " (the number of positions), got " + std::to_string(t.indices(i)));
}

void CheckTransform(const std::string& p, const pb::Transform& t) {
  if (t.matrix_size() > 0) {
    if (t.matrix_size() != 12)
      Refuse(p + ".matrix", "must have 12 values (3 rows of 4: an affine matrix without its last row), got " +
                                std::to_string(t.matrix_size()));
    const struct {
      const char* name;
      bool set;
    } trs[] = {{"translation", t.has_translation()},
               {"scale", t.has_scale()},
               {"rotation_axis", t.has_rotation_axis()},
               {"rotation_degrees", t.rotation_degrees() != 0}};
    for (const auto& f : trs)
      if (f.set) Refuse(p + ".matrix", std::string("must be the only part of the transform set, but ") + f.name + " is set too");
    if (MatrixDeterminant(t) == 0) Refuse(p + ".matrix", "must be invertible, but the determinant of its 3x3 part is 0");
    return;
  }
  if (t.has_scale()) {
    const struct {
      const char* name;
      double v;
    } components[] = {{"x", t.scale().x()}, {"y", t.scale().y()}, {"z", t.scale().z()}};
    for (const auto& c : components)
      if (c.v == 0) Refuse(p + ".scale." + c.name, "must be non-zero");
  }
  if (t.rotation_degrees() != 0 && Vec(t.rotation_axis()).IsZero())
    Refuse(p + ".rotation_axis", "must be non-zero when rotation_degrees is " + GoNumber(t.rotation_degrees()));
}

void CheckShapes(const pb::Scene& s) {
  for (int i = 0; i < s.shapes_size(); ++i) {
    const pb::Shape& shape = s.shapes(i);
    const std::string p = Index("shapes", i);
    switch (shape.geometry_case()) {
      case pb::Shape::kQuad: CheckQuad(p + ".quad", shape.quad()); break;
      case pb::Shape::kTriangles: CheckTriangles(p + ".triangles", shape.triangles()); break;
      case pb::Shape::kMesh: CheckTransform(p + ".mesh.transform", shape.mesh().transform()); break;
      case pb::Shape::kInstance: CheckTransform(p + ".instance.transform", shape.instance().transform()); break;
      case pb::Shape::kSphere:  // CheckRules has bounded its radius; a centre may be anywhere
      case pb::Shape::GEOMETRY_NOT_SET: break;
    }
    if (shape.interior_medium().has_grid())
      CheckTransform(p + ".interior_medium.grid.transform", shape.interior_medium().grid().transform());
  }
  if (s.medium().has_grid()) CheckTransform("medium.grid.transform", s.medium().grid().transform());
}

void CheckLightShapes(const pb::Scene& s) {
  for (int i = 0; i < s.lights_size(); ++i) {
    const pb::Light& l = s.lights(i);
    const std::string p = Index("lights", i);
    if (l.has_sun() && Vec(l.sun().direction()).IsZero()) Refuse(p + ".sun.direction", "must be non-zero");
    if (!l.has_spot()) continue;
    const pb::SpotLight& spot = l.spot();
    if (Vec(spot.direction()).IsZero()) Refuse(p + ".spot.direction", "must be non-zero");
    if (spot.inner_cone_degrees() > spot.outer_cone_degrees())
      Refuse(p + ".spot.inner_cone_degrees", "must be at most outer_cone_degrees " + GoNumber(spot.outer_cone_degrees()) +
                                                 ", got " + GoNumber(spot.inner_cone_degrees()));
  }
}

// Every map's photon count, whether or not the scene gets that map: a rule about the settings
// alone, which the coordinator checks the same way without planning.
void CheckShards(const pb::PhotonMapping& photons) {
  using contract::OrDefault;
  const std::uint64_t per = OrDefault<pb::PhotonMapping>(photons.photons_per_shard(), "photons_per_shard");
  const std::uint64_t limit = contract::SceneLimits().max_shards_per_map();
  const struct {
    const char* map;
    std::uint64_t paths;
  } maps[] = {
      {"global", OrDefault<pb::PhotonMapping>(photons.global_photons(), "global_photons")},
      {"caustic", OrDefault<pb::PhotonMapping>(photons.caustic_photons(), "caustic_photons")},
      {"volume", OrDefault<pb::PhotonMapping>(photons.volume_photons(), "volume_photons")},
  };
  for (const auto& m : maps)
    if (CeilDiv(m.paths, per) > limit)
      Refuse("photons.photons_per_shard",
             "makes " + std::to_string(CeilDiv(m.paths, per)) + " shards of the " + m.map + " map's " +
                 std::to_string(m.paths) + " photon paths, more than the " + std::to_string(limit) +
                 " a map may have");
}

}  // namespace

bool MaterialEmits(const pb::Material& m) {
  return (m.has_emissive() && Positive(m.emissive().radiance())) ||
         (m.has_principled() && Positive(m.principled().emission()));
}

bool EnvironmentLights(const pb::Scene& s) {
  if (!s.has_environment()) return false;
  const pb::Environment& env = s.environment();
  return env.has_radiance() ? Positive(env.radiance()) : env.has_map();
}

std::vector<TextureRefAt> TextureRefs(const pb::Scene& s) {
  std::vector<TextureRefAt> refs;
  for (int i = 0; i < s.materials_size(); ++i) {
    if (!s.materials(i).has_principled()) continue;
    const pb::Principled& p = s.materials(i).principled();
    const std::string at = Index("materials", i) + ".principled.";
    if (p.has_base_color_texture()) refs.push_back({at + "base_color_texture", &p.base_color_texture()});
    if (p.has_metallic_roughness_texture()) refs.push_back({at + "metallic_roughness_texture", &p.metallic_roughness_texture()});
    if (p.has_normal_texture()) refs.push_back({at + "normal_texture", &p.normal_texture()});
    if (p.has_emission_texture()) refs.push_back({at + "emission_texture", &p.emission_texture()});
  }
  if (s.environment().has_map()) refs.push_back({"environment.map", &s.environment().map()});
  return refs;
}

double MatrixDeterminant(const pb::Transform& t) {
  const auto m = [&t](int i) { return t.matrix(i); };
  return m(0) * (m(5) * m(10) - m(6) * m(9)) - m(1) * (m(4) * m(10) - m(6) * m(8)) + m(2) * (m(4) * m(9) - m(5) * m(8));
}

void CheckScene(const pb::Scene& scene) {
  if (const std::optional<contract::FieldError> err = contract::CheckRules(scene)) throw SceneError(err->ToString());
  CheckCamera(scene.camera());
  CheckFilm(scene.film());
  CheckNames(scene);
  CheckShapeMaterials(scene);
  CheckPartMaterials(scene);
  CheckTextureRefs(scene);
  CheckSomeLight(scene);
  CheckGlossyEnergy(scene);
  CheckShapes(scene);
  CheckLightShapes(scene);
  CheckShards(scene.photons());
  const pb::ReferenceImage& ref = scene.progressive().reference();
  if (ref.digest().empty() && !ref.path().empty())
    Refuse("progressive.reference.digest",
           "missing: the client uploads the file at path " + GoQuote(ref.path()) + " and sets its digest");
}

}  // namespace farm
