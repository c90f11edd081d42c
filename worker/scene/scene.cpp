#include "scene/scene.h"

#include <cmath>
#include <unordered_map>

#include "math/transform.h"
#include "renderfarm/v1/scene.pb.h"
#include "scene/obj_mesh.h"
#include "scene/scene_data.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

Vec3d FromProto(const pb::Vec3& v) { return {v.x(), v.y(), v.z()}; }

Vec3 CheckedPoint(const pb::Vec3& v, const std::string& field) {
  const Vec3d p = FromProto(v);
  if (!IsFinite(p)) throw SceneError(field + ": not finite");
  return Vec3(p);
}

std::string ShapeLabel(int index, const pb::Shape& shape) {
  std::string label = "shapes[" + std::to_string(index) + "]";
  if (!shape.name().empty()) label += " (\"" + shape.name() + "\")";
  return label;
}

std::shared_ptr<const TriangleMesh> InlineMesh(const pb::TriangleMesh& t, const std::string& field) {
  auto mesh = std::make_shared<TriangleMesh>();
  for (int i = 0; i < t.positions_size(); ++i)
    mesh->positions.push_back(
        CheckedPoint(t.positions(i), field + ".positions[" + std::to_string(i) + "]"));
  if (t.indices_size() == 0) throw SceneError(field + ".indices: no triangles");
  if (t.indices_size() % 3 != 0)
    throw SceneError(field + ".indices: " + std::to_string(t.indices_size()) +
                     " indices is not a multiple of 3");
  for (int i = 0; i < t.indices_size(); ++i) {
    if (t.indices(i) >= mesh->positions.size())
      throw SceneError(field + ".indices[" + std::to_string(i) + "]: " +
                       std::to_string(t.indices(i)) + " is out of range (" +
                       std::to_string(mesh->positions.size()) + " positions)");
    mesh->indices.push_back(t.indices(i));
  }
  return mesh;
}

Affine3d TransformFromProto(const pb::Transform& t, const std::string& field) {
  const Vec3d scale = t.has_scale() ? FromProto(t.scale()) : Vec3d(1, 1, 1);
  const Vec3d axis = FromProto(t.rotation_axis());
  const Vec3d translation = FromProto(t.translation());
  if (!IsFinite(scale) || !IsFinite(axis) || !IsFinite(translation) ||
      !std::isfinite(t.rotation_degrees()))
    throw SceneError(field + ": not finite");
  if (scale.x == 0 || scale.y == 0 || scale.z == 0)
    throw SceneError(field + ".scale: a zero component flattens the mesh");
  if (t.rotation_degrees() != 0 && !(LengthSquared(axis) > 0))
    throw SceneError(field + ".rotation_axis: zero, but rotation_degrees is not");
  return Affine3d::ScaleRotateTranslate(scale, axis, t.rotation_degrees(), translation);
}

std::shared_ptr<const TriangleMesh> FileMesh(const pb::MeshFile& file, const std::string& field,
                                             const BlobLoader& load_blob) {
  std::string bytes;
  try {
    bytes = load_blob(file.digest());
  } catch (const std::exception& e) {
    throw SceneError(field + ".digest: cannot load blob \"" + file.digest() + "\": " + e.what());
  }
  const Affine3d transform = TransformFromProto(file.transform(), field + ".transform");
  TriangleMesh mesh = ParseObjMesh(bytes, field);
  for (Vec3& p : mesh.positions) {
    p = Vec3(transform.Apply(Vec3d(p)));
    if (!IsFinite(p)) throw SceneError(field + ".transform: moves a vertex out of float range");
  }
  // A mirroring transform (negative determinant) would turn every face inside out.
  if (transform.Determinant() < 0)
    for (std::size_t i = 0; i < mesh.indices.size(); i += 3) std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
  return std::make_shared<const TriangleMesh>(std::move(mesh));
}

ShapeGeometry GeometryFromProto(const pb::Shape& shape, const std::string& field,
                                const BlobLoader& load_blob) {
  switch (shape.geometry_case()) {
    case pb::Shape::kSphere: {
      const Vec3 center = CheckedPoint(shape.sphere().center(), field + ".sphere.center");
      const double radius = shape.sphere().radius();
      if (!(radius > 0) || !std::isfinite(radius))
        throw SceneError(field + ".sphere.radius: must be positive, got " + std::to_string(radius));
      return SphereShape{center, static_cast<float>(radius)};
    }
    case pb::Shape::kQuad: {
      const Vec3 o = CheckedPoint(shape.quad().origin(), field + ".quad.origin");
      const Vec3 u = CheckedPoint(shape.quad().edge_u(), field + ".quad.edge_u");
      const Vec3 v = CheckedPoint(shape.quad().edge_v(), field + ".quad.edge_v");
      if (!(LengthSquared(Cross(u, v)) > 0))
        throw SceneError(field + ".quad: edge_u and edge_v are zero or parallel");
      return QuadShape::Make(o, u, v);
    }
    case pb::Shape::kTriangles:
      return InlineMesh(shape.triangles(), field + ".triangles");
    case pb::Shape::kMesh:
      return FileMesh(shape.mesh(), field + ".mesh", load_blob);
    case pb::Shape::GEOMETRY_NOT_SET:
      break;
  }
  throw SceneError(field + ": no geometry set (sphere, quad, triangles or mesh)");
}

// An area light for an emissive shape, or nothing if it emits no light at all.
std::optional<Light> LightFor(const ShapeGeometry& geometry, const Material& material) {
  const auto* emissive = std::get_if<EmissiveMaterial>(&material);
  if (!emissive || emissive->radiance.IsBlack()) return std::nullopt;
  struct Visitor {
    Rgb radiance;
    Light operator()(const SphereShape& s) const { return SphereLight{s, radiance}; }
    Light operator()(const QuadShape& q) const { return QuadLight{q, radiance}; }
    Light operator()(const std::shared_ptr<const TriangleMesh>& m) const {
      return TriangleMeshLight::Make(m, radiance);
    }
  };
  return std::visit(Visitor{emissive->radiance}, geometry);
}

// Largest absolute coordinate of any geometry: sets the absolute floor of ray offsets.
float SceneExtent(const std::vector<ShapeRecord>& shapes) {
  float extent = 0;
  for (const ShapeRecord& s : shapes) {
    struct Visitor {
      float& e;
      void operator()(const SphereShape& s) const {
        e = std::max(e, MaxComponent(Abs(s.center)) + s.radius);
      }
      void operator()(const QuadShape& q) const {
        for (const Vec3& p : {q.origin, q.origin + q.edge_u, q.origin + q.edge_v,
                              q.origin + q.edge_u + q.edge_v})
          e = std::max(e, MaxComponent(Abs(p)));
      }
      void operator()(const std::shared_ptr<const TriangleMesh>& m) const {
        for (const Vec3& p : m->positions) e = std::max(e, MaxComponent(Abs(p)));
      }
    };
    std::visit(Visitor{extent}, s.geometry);
  }
  return extent;
}

}  // namespace

Scene Scene::Build(const pb::Scene& description, const BlobLoader& load_blob) {
  auto data = std::make_unique<SceneData>();
  SceneData& d = *data;

  const pb::Film& film = description.film();
  if (film.width() == 0) throw SceneError("film.width: must be positive");
  if (film.height() == 0) throw SceneError("film.height: must be positive");
  if (film.width() > 1u << 16) throw SceneError("film.width: larger than 65536");
  if (film.height() > 1u << 16) throw SceneError("film.height: larger than 65536");
  d.width = static_cast<int>(film.width());
  d.height = static_cast<int>(film.height());
  d.tile_size = film.tile_size() == 0 ? kDefaultTileSize : static_cast<int>(film.tile_size());
  d.samples_per_pixel = description.sampling().samples_per_pixel() == 0
                            ? kDefaultSamplesPerPixel
                            : description.sampling().samples_per_pixel();
  d.seed = description.sampling().seed();
  d.antialiasing = AntialiasingSettings::FromProto(description.antialiasing());
  d.indirect = IndirectSettings::FromProto(description);
  d.camera = Camera::FromProto(description.camera(), d.width, d.height);

  std::unordered_map<std::string, int> material_index;
  for (int i = 0; i < description.materials_size(); ++i) {
    const pb::Material& m = description.materials(i);
    const std::string field = "materials[" + std::to_string(i) + "]";
    if (!material_index.emplace(m.name(), i).second)
      throw SceneError(field + ".name: \"" + m.name() + "\" is defined twice");
    d.materials.push_back(MaterialFromProto(m, field));
    d.material_names.push_back(m.name());
  }

  std::vector<ShapeGeometry> geometries;
  for (int i = 0; i < description.shapes_size(); ++i) {
    const pb::Shape& shape = description.shapes(i);
    const std::string field = "shapes[" + std::to_string(i) + "]";
    ShapeRecord record;
    record.label = ShapeLabel(i, shape);
    const auto it = material_index.find(shape.material());
    if (it == material_index.end())
      throw SceneError(field + ".material: no material named \"" + shape.material() + "\"");
    record.material = it->second;
    try {
      record.geometry = GeometryFromProto(shape, field, load_blob);
    } catch (const SceneError& e) {
      // Name the shape too, when it has a name: "shapes[3].mesh: ... (shape "bunny")".
      if (shape.name().empty()) throw;
      throw SceneError(std::string(e.what()) + " (shape \"" + shape.name() + "\")");
    }
    if (std::optional<Light> light = LightFor(record.geometry, d.materials[record.material])) {
      record.light = static_cast<int>(d.lights.size());
      d.lights.push_back(std::move(*light));
    }
    geometries.push_back(record.geometry);
    d.shapes.push_back(std::move(record));
  }

  for (const ShapeRecord& shape : d.shapes) {
    d.bounds.Extend(BoundsOf(shape.geometry));
    if (IsSpecular(d.materials[shape.material]))
      d.specular_targets.push_back(BoundingSphereOf(shape.geometry));
  }
  for (int i = 0; i < description.lights_size(); ++i)
    d.lights.push_back(LightFromProto(description.lights(i), BoundingSphere::Of(d.bounds),
                                      "lights[" + std::to_string(i) + "]"));
  d.photons = PhotonSettings::FromProto(description.photons(), d.bounds.Diagonal());

  std::vector<float> power;
  for (const Light& light : d.lights) power.push_back(Power(light).Luminance());
  d.light_power = DiscreteDistribution(power);

  // ~17 ulps of the largest coordinate: above the rounding of the primitives' own
  // coordinates, which is what rays leaving points near the origin of a large scene meet.
  d.ray_epsilon = 2e-6f * SceneExtent(d.shapes);
  d.accelerator = Accelerator::Build(geometries);
  return Scene(std::move(data));
}

Scene::Scene(std::unique_ptr<SceneData> data) : data_(std::move(data)) {}
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;
Scene::~Scene() = default;

int Scene::width() const { return data_->width; }
int Scene::height() const { return data_->height; }
int Scene::tile_size() const { return data_->tile_size; }

}  // namespace farm
