#include "scene/scene.h"

#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "contract/go_text.h"
#include "contract/rules.h"
#include "math/transform.h"
#include "renderfarm/v1/scene.pb.h"
#include "scene/obj_mesh.h"
#include "scene/proto_values.h"
#include "scene/scene_data.h"
#include "scene/scene_rules.h"
#include "scene/scene_textures.h"
#include "scene/surface_shading.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

Vec3 PointOf(const pb::Vec3& v) { return Vec3(Vec3dOf(v)); }

std::string ShapeLabel(int index, const pb::Shape& shape) {
  std::string label = "shapes[" + std::to_string(index) + "]";
  if (!shape.name().empty()) label += " (\"" + shape.name() + "\")";
  return label;
}

std::shared_ptr<const TriangleMesh> InlineMesh(const pb::TriangleMesh& t) {
  auto mesh = std::make_shared<TriangleMesh>();
  for (const pb::Vec3& p : t.positions()) mesh->positions.push_back(PointOf(p));
  mesh->indices.assign(t.indices().begin(), t.indices().end());
  return mesh;
}

Affine3d TransformFromProto(const pb::Transform& t) {
  const Vec3d scale = t.has_scale() ? Vec3dOf(t.scale()) : Vec3d(1, 1, 1);
  return Affine3d::ScaleRotateTranslate(scale, Vec3dOf(t.rotation_axis()), t.rotation_degrees(),
                                        Vec3dOf(t.translation()));
}

// How a message names a mesh file: its path in the scene file, else its digest.
std::string FileName(const pb::MeshFile& file) {
  return contract::GoQuote(file.path().empty() ? file.digest() : file.path());
}

std::shared_ptr<const TriangleMesh> FileMesh(const pb::MeshFile& file, const std::string& field,
                                             const BlobLoader& load_blob) {
  std::string bytes;
  try {
    bytes = load_blob(file.digest());
  } catch (const std::exception& e) {
    // Of the kind the loader's error is (the blob store being away is not the scene's fault).
    throw TaskError(FailureKindOf(e), field + ".digest: cannot load mesh " + FileName(file) + ": " + e.what());
  }
  const Affine3d transform = TransformFromProto(file.transform());
  TriangleMesh mesh;
  try {
    mesh = ParseObjMesh(bytes);
  } catch (const ObjError& e) {
    throw SceneError(field + ": OBJ file " + FileName(file) + " " + e.what());
  }
  for (Vec3& p : mesh.positions) {
    p = Vec3(transform.Apply(Vec3d(p)));
    if (!IsFinite(p)) throw SceneError(field + ".transform: moves a vertex of " + FileName(file) + " out of float range");
  }
  // A mirroring transform (negative determinant) would turn every face inside out.
  if (transform.Determinant() < 0)
    for (std::size_t i = 0; i < mesh.indices.size(); i += 3) std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
  return std::make_shared<const TriangleMesh>(std::move(mesh));
}

ShapeGeometry GeometryFromProto(const pb::Shape& shape, const std::string& field,
                                const BlobLoader& load_blob) {
  switch (shape.geometry_case()) {
    case pb::Shape::kSphere:
      return SphereShape{PointOf(shape.sphere().center()), static_cast<float>(shape.sphere().radius())};
    case pb::Shape::kQuad:
      return QuadShape::Make(PointOf(shape.quad().origin()), PointOf(shape.quad().edge_u()),
                             PointOf(shape.quad().edge_v()));
    case pb::Shape::kTriangles:
      return InlineMesh(shape.triangles());
    case pb::Shape::kMesh:
      return FileMesh(shape.mesh(), field + ".mesh", load_blob);
    case pb::Shape::kInstance:  // placeholder until the geom helper's instancing lands
      throw UnsupportedError(field + ".instance: mesh instances are not rendered by this worker yet");
    case pb::Shape::GEOMETRY_NOT_SET:
      break;
  }
  throw std::logic_error("GeometryFromProto: a shape without geometry (CheckRules refuses it)");
}

// An area light for an emissive shape, or nothing if it emits no light at all.
std::optional<Light> LightFor(const ShapeGeometry& geometry, const Rgb& radiance) {
  if (radiance.IsBlack()) return std::nullopt;
  struct Visitor {
    Rgb radiance;
    Light operator()(const SphereShape& s) const { return SphereLight{s, radiance}; }
    Light operator()(const QuadShape& q) const { return QuadLight{q, radiance}; }
    Light operator()(const std::shared_ptr<const TriangleMesh>& m) const {
      return TriangleMeshLight::Make(m, radiance);
    }
  };
  return std::visit(Visitor{radiance}, geometry);
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

Scene Scene::Build(const pb::Scene& description, const BlobLoader& load_blob, const SceneOptions& options) {
  CheckScene(description);
  auto data = std::make_unique<SceneData>();
  SceneData& d = *data;

  using contract::OrDefault;
  const pb::Film& film = description.film();
  d.width = static_cast<int>(film.width());
  d.height = static_cast<int>(film.height());
  d.tile_size = static_cast<int>(OrDefault<pb::Film>(film.tile_size(), "tile_size"));
  d.samples_per_pixel = OrDefault<pb::Sampling>(description.sampling().samples_per_pixel(), "samples_per_pixel");
  d.seed = description.sampling().seed();
  d.antialiasing = AntialiasingSettings::FromProto(description.antialiasing());
  d.indirect = IndirectSettings::FromProto(description);
  d.camera = Camera::FromProto(description.camera(), d.width, d.height);

  std::unordered_map<std::string, int> material_index;
  TextureBinder textures(description, options, d);
  for (int i = 0; i < description.materials_size(); ++i) {
    const pb::Material& m = description.materials(i);
    material_index.emplace(m.name(), i);
    d.materials.push_back(MaterialFromProto(m));
    if (m.has_principled())
      textures.Bind(m.principled(), "materials[" + std::to_string(i) + "].principled",
                    std::get<PrincipledMaterial>(d.materials.back()));
    d.capabilities.push_back(CapabilitiesOf(d.materials.back()));
    d.material_names.push_back(m.name());
  }

  std::vector<ShapeGeometry> geometries;
  for (int i = 0; i < description.shapes_size(); ++i) {
    const pb::Shape& shape = description.shapes(i);
    const std::string field = "shapes[" + std::to_string(i) + "]";
    ShapeRecord record;
    record.label = ShapeLabel(i, shape);
    record.material = material_index.at(shape.material());
    try {
      record.geometry = GeometryFromProto(shape, field, load_blob);
    } catch (const SceneError& e) {
      // Name the shape too, when it has a name: "shapes[3].mesh: ... (shape "bunny")".
      if (shape.name().empty()) throw;
      throw SceneError(std::string(e.what()) + " (shape \"" + shape.name() + "\")");
    }
    if (std::optional<Light> light = LightFor(record.geometry, AreaLightRadiance(d, d.materials[record.material]))) {
      record.light = static_cast<int>(d.lights.size());
      d.lights.push_back(std::move(*light));
    }
    geometries.push_back(record.geometry);
    d.shapes.push_back(std::move(record));
  }

  for (const ShapeRecord& shape : d.shapes) {
    d.bounds.Extend(BoundsOf(shape.geometry));
    if (d.capabilities[shape.material].specular)
      d.specular_targets.push_back(BoundingSphereOf(shape.geometry));
  }
  for (int i = 0; i < description.lights_size(); ++i)
    d.lights.push_back(LightFromProto(description.lights(i), BoundingSphere::Of(d.bounds)));
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
