#include "scene/scene_rules.h"

#include <cmath>
#include <string>
#include <unordered_map>
#include <unordered_set>

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

void CheckMaterials(const pb::Scene& s) {
  std::unordered_set<std::string> names;
  for (int i = 0; i < s.materials_size(); ++i) {
    const pb::Material& m = s.materials(i);
    const std::string p = Index("materials", i);
    if (!names.insert(m.name()).second) Refuse(p + ".name", "duplicate material name " + GoQuote(m.name()));
    if (!m.has_glossy()) continue;
    const pb::Color &d = m.glossy().diffuse(), &sp = m.glossy().specular();
    const struct {
      const char* name;
      double d, s;
    } channels[] = {{"r", d.r(), sp.r()}, {"g", d.g(), sp.g()}, {"b", d.b(), sp.b()}};
    for (const auto& c : channels)
      if (c.d + c.s > 1)
        Refuse(p + ".glossy.specular." + c.name, "diffuse + specular must be <= 1 (energy conservation), got " +
                                                    GoNumber(c.d) + " + " + GoNumber(c.s));
  }
}

bool Positive(const pb::Color& c) { return c.r() > 0 || c.g() > 0 || c.b() > 0; }

// Checks the lights without geometry; returns whether one of them emits.
bool CheckLights(const pb::Scene& s) {
  bool emits = false;
  for (int i = 0; i < s.lights_size(); ++i) {
    const pb::Light& l = s.lights(i);
    if (l.has_sun() && Vec(l.sun().direction()).IsZero()) Refuse(Index("lights", i) + ".sun.direction", "must be non-zero");
    emits |= l.has_point() ? Positive(l.point().intensity()) : Positive(l.sun().irradiance());
  }
  return emits;
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

// Checks the shapes and returns whether one of them emits (in double precision, as in Go:
// a radiance too small for float still counts).
bool CheckShapes(const pb::Scene& s) {
  std::unordered_map<std::string, bool> emits;  // material name -> emits
  for (const pb::Material& m : s.materials())
    emits.emplace(m.name(), m.has_emissive() && Positive(m.emissive().radiance()));
  bool any_emits = false;
  for (int i = 0; i < s.shapes_size(); ++i) {
    const pb::Shape& shape = s.shapes(i);
    const std::string p = Index("shapes", i);
    const auto it = emits.find(shape.material());
    if (it == emits.end()) Refuse(p + ".material", "no material named " + GoQuote(shape.material()));
    any_emits |= it->second;
    switch (shape.geometry_case()) {
      case pb::Shape::kQuad: CheckQuad(p + ".quad", shape.quad()); break;
      case pb::Shape::kTriangles: CheckTriangles(p + ".triangles", shape.triangles()); break;
      case pb::Shape::kMesh: CheckTransform(p + ".mesh.transform", shape.mesh().transform()); break;
      case pb::Shape::kSphere:
      case pb::Shape::GEOMETRY_NOT_SET: break;
    }
  }
  return any_emits;
}

// Both photon counts, whether or not the scene gets that map: a rule about the settings
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
  };
  for (const auto& m : maps)
    if (CeilDiv(m.paths, per) > limit)
      Refuse("photons.photons_per_shard",
             "makes " + std::to_string(CeilDiv(m.paths, per)) + " shards of the " + m.map + " map's " +
                 std::to_string(m.paths) + " photon paths, more than the " + std::to_string(limit) +
                 " a map may have");
}

}  // namespace

void CheckScene(const pb::Scene& scene) {
  if (const std::optional<contract::FieldError> err = contract::CheckRules(scene)) throw SceneError(err->ToString());
  CheckCamera(scene.camera());
  CheckFilm(scene.film());
  CheckMaterials(scene);
  const bool lights_emit = CheckLights(scene);
  const bool shapes_emit = CheckShapes(scene);
  if (!lights_emit && !shapes_emit)
    Refuse("lights",
           "the scene needs a light: a point or sun light with a positive power, or a shape whose material is "
           "emissive with a positive radiance");
  CheckShards(scene.photons());
  const pb::ReferenceImage& ref = scene.progressive().reference();
  if (ref.digest().empty() && !ref.path().empty())
    Refuse("progressive.reference.digest",
           "missing: the client uploads the file at path " + GoQuote(ref.path()) + " and sets its digest");
}

}  // namespace farm
