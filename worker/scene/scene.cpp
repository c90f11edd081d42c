#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <unordered_map>

#include "contract/failure.h"
#include "contract/go_text.h"
#include "contract/rules.h"
#include "math/transform.h"
#include "renderfarm/v1/scene.pb.h"
#include "scene/environment_image.h"
#include "scene/farm_grid.h"
#include "scene/farm_mesh.h"
#include "scene/mesh_file.h"
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
  if (t.matrix_size() == 12) {  // CheckScene allows 12 values or none
    double rows[12];
    std::copy(t.matrix().begin(), t.matrix().end(), rows);
    return Affine3d::FromRows(rows);
  }
  const Vec3d scale = t.has_scale() ? Vec3dOf(t.scale()) : Vec3d(1, 1, 1);
  return Affine3d::ScaleRotateTranslate(scale, Vec3dOf(t.rotation_axis()), t.rotation_degrees(),
                                        Vec3dOf(t.translation()));
}

// The files of one kind a scene names by digest (mesh files and mesh parts; media's grid
// files), each blob fetched and read once however many fields name it. `what` names the
// kind in messages ("mesh", "grid"); parse reads the bytes, throwing SceneError.
template <typename T>
class BlobFiles {
 public:
  // Reads the bytes of the file `name` (its path in the scene file, or its digest) that
  // `field` names.
  using Parse = std::function<T(const std::string& bytes, const std::string& field, const std::string& name)>;

  BlobFiles(const BlobLoader& load_blob, std::string what, Parse parse)
      : load_blob_(load_blob), what_(std::move(what)), parse_(std::move(parse)) {}

  // The file's contents as stored (object or grid space). `field` names the message that
  // holds the file ("shapes[3].mesh", "meshes[0].parts[1]", "medium.grid"), `path` its
  // path in the scene file.
  std::shared_ptr<const T> Read(const std::string& digest, const std::string& path, const std::string& field) {
    if (const auto it = read_.find(digest); it != read_.end()) return it->second;
    const std::string name = contract::GoQuote(path.empty() ? digest : path);
    std::string bytes;
    try {
      bytes = load_blob_(digest);
    } catch (const std::exception& e) {
      // Of the kind the loader's error is (the blob store being away is not the scene's fault).
      throw TaskError(FailureKindOf(e), field + ".digest: cannot load " + what_ + " " + name + ": " + e.what());
    }
    auto read = std::make_shared<const T>(parse_(bytes, field, name));
    read_.emplace(digest, read);
    return read;
  }

 private:
  const BlobLoader& load_blob_;
  std::string what_;
  Parse parse_;
  std::unordered_map<std::string, std::shared_ptr<const T>> read_;
};

using MeshFiles = BlobFiles<TriangleMesh>;
using GridFiles = BlobFiles<DenseGrid>;

MeshFiles MeshFilesOf(const BlobLoader& load_blob) {
  return MeshFiles(load_blob, "mesh", [](const std::string& bytes, const std::string& field, const std::string& name) {
    try {
      return ReadMeshFile(bytes);
    } catch (const ObjError& e) {
      throw SceneError(field + ": OBJ file " + name + " " + e.what());
    } catch (const FarmMeshError& e) {
      throw SceneError(field + ": farm mesh file " + name + " " + e.what());
    }
  });
}

GridFiles GridFilesOf(const BlobLoader& load_blob) {
  return GridFiles(load_blob, "grid", [](const std::string& bytes, const std::string& field, const std::string& name) {
    try {
      return ReadFarmGrid(bytes);
    } catch (const FarmGridError& e) {
      throw SceneError(field + ": farm grid file " + name + " " + e.what());
    }
  });
}

// A scene's or a shape's medium (`field`: "medium", "shapes[2].interior_medium").
Medium MediumFromProto(const pb::Medium& m, const std::string& field, GridFiles& grids) {
  const float g = float(m.g());
  switch (m.coefficients_case()) {
    case pb::Medium::kAlbedo:
      return {HomogeneousMedium::FromAlbedo(RgbOf(m.albedo().albedo()), float(m.albedo().density()), g)};
    case pb::Medium::kSigma:
      return {HomogeneousMedium::FromCoefficients(RgbOf(m.sigma().sigma_a()), RgbOf(m.sigma().sigma_s()), g)};
    case pb::Medium::kGrid: {
      const pb::MediumGrid& grid = m.grid();
      const Affine3d placement = grid.has_transform() ? TransformFromProto(grid.transform()) : Affine3d{};
      return {GridMedium{grids.Read(grid.digest(), grid.path(), field + ".grid"), placement.Inverse(),
                         float(contract::OrDefault<pb::MediumGrid>(grid.density_scale(), "density_scale")),
                         RgbOf(grid.albedo()), g}};
    }
    case pb::Medium::COEFFICIENTS_NOT_SET: break;
  }
  throw SceneError(field + ": no coefficients");  // CheckScene refuses it first
}

// A shape's mesh file placed in the world; the file's own mesh, shared, when the shape
// does not move it.
std::shared_ptr<const TriangleMesh> FileMesh(const pb::MeshFile& file, const std::string& field, MeshFiles& files) {
  std::shared_ptr<const TriangleMesh> mesh = files.Read(file.digest(), file.path(), field);
  if (!file.has_transform()) return mesh;
  std::optional<TriangleMesh> placed = PlaceMesh(*mesh, Placement(TransformFromProto(file.transform())));
  if (!placed)
    throw SceneError(field + ".transform: moves a vertex of " + contract::GoQuote(file.path().empty() ? file.digest() : file.path()) +
                     " out of float range");
  return std::make_shared<const TriangleMesh>(std::move(*placed));
}

// Scene.meshes[index], its parts read and bounded.
std::shared_ptr<const SceneMesh> MeshFromProto(const pb::Mesh& mesh, int index, MeshFiles& files,
                                               const std::unordered_map<std::string, int>& material_index) {
  auto built = std::make_shared<SceneMesh>();
  built->name = mesh.name();
  for (int j = 0; j < mesh.parts_size(); ++j) {
    const pb::MeshPart& part = mesh.parts(j);
    const std::string field = "meshes[" + std::to_string(index) + "].parts[" + std::to_string(j) + "]";
    SceneMesh::Part& p = built->parts.emplace_back();
    p.triangles = files.Read(part.digest(), part.path(), field);
    p.material = material_index.at(part.material());
    p.bounds = BoundsOf(*p.triangles);
    built->bounds.Extend(p.bounds);
  }
  return built;
}

// What shapes' geometry is built from besides the shape itself.
struct GeometrySources {
  MeshFiles& files;
  const std::vector<std::shared_ptr<const SceneMesh>>& meshes;
  const std::unordered_map<std::string, int>& mesh_index;
};

ShapeGeometry GeometryFromProto(const pb::Shape& shape, const std::string& field, const GeometrySources& sources) {
  switch (shape.geometry_case()) {
    case pb::Shape::kSphere:
      return SphereShape{PointOf(shape.sphere().center()), static_cast<float>(shape.sphere().radius())};
    case pb::Shape::kQuad:
      return QuadShape::Make(PointOf(shape.quad().origin()), PointOf(shape.quad().edge_u()),
                             PointOf(shape.quad().edge_v()));
    case pb::Shape::kTriangles:
      return InlineMesh(shape.triangles());
    case pb::Shape::kMesh:
      return FileMesh(shape.mesh(), field + ".mesh", sources.files);
    case pb::Shape::kInstance: {
      InstanceShape instance{sources.meshes[sources.mesh_index.at(shape.instance().mesh())],
                             Placement(TransformFromProto(shape.instance().transform()))};
      const Bounds3 placed = Place(instance.mesh->bounds, instance.placement);
      if (!IsFinite(placed.min) || !IsFinite(placed.max))
        throw SceneError(field + ".instance.transform: moves the mesh " + contract::GoQuote(instance.mesh->name) +
                         " out of float range");
      return instance;
    }
    case pb::Shape::GEOMETRY_NOT_SET:
      break;
  }
  throw std::logic_error("GeometryFromProto: a shape without geometry (CheckRules refuses it)");
}

// The area lights of shape `shape`: itself if its material emits; for an instance, each
// part of its mesh whose material emits, over the part's triangles placed. Each is sampled
// with its material's AreaLightRadiance (a textured emission by the texture's mean), and
// its surface recorded in area_light_surfaces.
void AddLights(int shape, const ShapeGeometry& geometry, int material, SceneData& d) {
  struct Visitor {
    const int shape;
    const Rgb radiance;  // of the shape's material (unused for instances)
    SceneData& d;
    void Add(Light light, uint32_t part = 0) const {
      d.lights.push_back(std::move(light));
      d.area_light_surfaces.push_back({shape, part});
    }
    void operator()(const SphereShape& s) const {
      if (!radiance.IsBlack()) Add(SphereLight{s, radiance});
    }
    void operator()(const QuadShape& q) const {
      if (!radiance.IsBlack()) Add(QuadLight{q, radiance});
    }
    void operator()(const std::shared_ptr<const TriangleMesh>& m) const {
      if (!radiance.IsBlack()) Add(TriangleMeshLight::Make(m, radiance));
    }
    void operator()(const InstanceShape& instance) const {
      for (std::size_t p = 0; p < instance.mesh->parts.size(); ++p) {
        const SceneMesh::Part& part = instance.mesh->parts[p];
        if (const Rgb r = AreaLightRadiance(d, d.materials[part.material]); !r.IsBlack())
          Add(TriangleMeshLight::Make(part.triangles, r, instance.placement), static_cast<uint32_t>(p));
      }
    }
  };
  std::visit(Visitor{shape, AreaLightRadiance(d, d.materials[material]), d}, geometry);
}

// Spheres around a shape's specular surfaces (caustic photons are aimed at them): the
// shape's if its material is specular; for an instance, each specular part's, placed.
void AddSpecularTargets(int shape, const ShapeGeometry& geometry, int material,
                        const std::vector<MaterialCapabilities>& can, std::vector<BoundingSphere>& targets,
                        std::vector<SceneData::TargetSurface>& surfaces) {
  if (const auto* instance = std::get_if<InstanceShape>(&geometry)) {
    for (std::size_t p = 0; p < instance->mesh->parts.size(); ++p) {
      const SceneMesh::Part& part = instance->mesh->parts[p];
      if (!can[part.material].specular) continue;
      targets.push_back(BoundingSphere::Of(Place(part.bounds, instance->placement)));
      surfaces.push_back({shape, static_cast<uint32_t>(p)});
    }
    return;
  }
  if (!can[material].specular) return;
  targets.push_back(BoundingSphereOf(geometry));
  surfaces.push_back({shape, 0});
}

// The caustic targets' table of each light with an origin, seen from the point its
// origin sampling gives the middle of [0, 1)^2 (a point light's position, a lamp's centre or
// a point on it): any point will do for an unbiased estimate (every target's solid angle is
// positive from anywhere outside it), and one near the light's photons keeps their weights
// even.
void AddCausticAim(SceneData& d) {
  d.caustic_aim.resize(d.lights.size());
  if (d.specular_targets.empty()) return;
  std::size_t entries = 0;
  for (std::size_t i = 0; i < d.lights.size(); ++i) {
    if (entries + d.specular_targets.size() > SceneData::kMaxCausticAimEntries) return;
    const std::optional<LightOrigin> o = SampleLightOrigin(d.lights[i], {0.5f, 0.5f});
    if (!o) continue;
    if (std::optional<AliasTable> table = d.specular_targets.TableFrom(o->p)) {
      d.caustic_aim[i] = std::move(*table);
      entries += d.specular_targets.size();
    }
  }
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
      void operator()(const InstanceShape& i) const {
        const Bounds3 b = Place(i.mesh->bounds, i.placement);
        e = std::max({e, MaxComponent(Abs(b.min)), MaxComponent(Abs(b.max))});
      }
    };
    std::visit(Visitor{extent}, s.geometry);
  }
  return extent;
}

// Which geometry the accelerator runs the materials' cut-out tests on, and how.
void AddCutoutFilter(const SceneData& d, AcceleratorInput& input) {
  const auto cuts = [&d](int material) { return static_cast<bool>(d.cutouts[material]); };
  if (std::none_of(d.cutouts.begin(), d.cutouts.end(), [](const CutoutTest& c) { return static_cast<bool>(c); }))
    return;
  for (const ShapeRecord& shape : d.shapes) input.filtered_shapes.push_back(cuts(shape.material));
  for (const auto& mesh : d.meshes) {
    std::vector<bool>& parts = input.filtered_parts.emplace_back();
    for (const SceneMesh::Part& part : mesh->parts) parts.push_back(cuts(part.material));
  }
  input.filter = [&d](const RawHit& raw, const Vec3& point) {
    const CutoutHit hit = d.CutoutHitOf(raw, point);
    return d.cutouts[hit.material](hit);
  };
}

// The environment the scene describes (Scene.environment), its map fetched by load_blob;
// null if the scene has none. A map's errors name its texture's field, as the coordinator's
// checks of the files a scene names do: textures[i].digest for a blob that cannot be
// loaded, textures[i] for a file that is not a usable image.
std::shared_ptr<const Environment> EnvironmentFromProto(const pb::Scene& scene, const BlobLoader& load_blob) {
  if (!scene.has_environment()) return nullptr;
  const pb::Environment& e = scene.environment();
  if (!e.has_map()) return std::make_shared<const Environment>(Environment::Constant(RgbOf(e.radiance())));
  const auto named = std::find_if(scene.textures().begin(), scene.textures().end(),
                                  [&e](const pb::Texture& t) { return t.name() == e.map().texture(); });
  if (named == scene.textures().end())
    throw std::logic_error("EnvironmentFromProto: a map of no texture (CheckScene refuses it)");
  const pb::Texture* texture = &*named;
  const std::string field = "textures[" + std::to_string(named - scene.textures().begin()) + "]";
  const std::string name = contract::GoQuote(texture->path().empty() ? texture->digest() : texture->path());
  std::string bytes;
  try {
    bytes = load_blob(texture->digest());
  } catch (const std::exception& e) {
    throw TaskError(FailureKindOf(e), field + ".digest: cannot load texture " + name + ": " + e.what());
  }
  const EnvironmentEncoding encoding = texture->encoding() == pb::COLOR_ENCODING_SRGB     ? EnvironmentEncoding::kSrgb
                                       : texture->encoding() == pb::COLOR_ENCODING_LINEAR ? EnvironmentEncoding::kLinear
                                                                                          : EnvironmentEncoding::kByFormat;
  EnvironmentImage image;
  try {
    image = DecodeEnvironmentImage(bytes, encoding, contract::SceneLimits().max_texture_pixels());
  } catch (const EnvironmentImageError& err) {
    throw SceneError(field + ": texture " + name + " " + err.what());
  }
  const Rgb scale = e.has_radiance() ? RgbOf(e.radiance()) : Rgb(1);
  return std::make_shared<const Environment>(Environment::Map(std::move(image), scale, e.rotation_degrees()));
}

// Sampling.specular with its default: whether camera paths split at glass.
bool SplitsSpecular(const pb::Sampling& sampling) {
  const pb::SpecularSampling mode = contract::OrDefault<pb::Sampling>(sampling.specular(), "specular");
  switch (mode) {
    case pb::SPECULAR_SAMPLING_SPLIT: return true;
    case pb::SPECULAR_SAMPLING_CHOOSE: return false;
    default:  // a mode the contract declares and this worker does not know
      throw UnsupportedError("sampling.specular: " + pb::SpecularSampling_Name(mode) +
                             " is not supported by this worker");
  }
}

// Sampling.spectral with its default: whether every path is traced at wavelengths.
bool SpectralAlways(const pb::Sampling& sampling) {
  const pb::SpectralSampling mode = contract::OrDefault<pb::Sampling>(sampling.spectral(), "spectral");
  switch (mode) {
    case pb::SPECTRAL_SAMPLING_AUTO: return false;
    case pb::SPECTRAL_SAMPLING_ALWAYS: return true;
    default:  // a mode the contract declares and this worker does not know
      throw UnsupportedError("sampling.spectral: " + pb::SpectralSampling_Name(mode) +
                             " is not supported by this worker");
  }
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
  d.filter = PixelFilter::FromProto(film.filter());
  d.indirect = IndirectSettings::FromProto(description);
  d.split_specular = SplitsSpecular(description.sampling());
  d.spectral_always = SpectralAlways(description.sampling());
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
    d.cutouts.push_back(options.cutout_of ? options.cutout_of(m, i) : CutoutOf(d, i));
  }

  MeshFiles files = MeshFilesOf(load_blob);
  GridFiles grids = GridFilesOf(load_blob);
  std::unordered_map<std::string, int> mesh_index;
  for (int i = 0; i < description.meshes_size(); ++i) {
    mesh_index.emplace(description.meshes(i).name(), i);
    d.meshes.push_back(MeshFromProto(description.meshes(i), i, files, material_index));
  }

  const GeometrySources sources{files, d.meshes, mesh_index};
  std::vector<ShapeGeometry> geometries;
  for (int i = 0; i < description.shapes_size(); ++i) {
    const pb::Shape& shape = description.shapes(i);
    const std::string field = "shapes[" + std::to_string(i) + "]";
    ShapeRecord record;
    record.label = ShapeLabel(i, shape);
    if (!shape.has_instance()) record.material = material_index.at(shape.material());
    if (shape.has_interior_medium()) {
      record.interior_medium = MediumFromProto(shape.interior_medium(), field + ".interior_medium", grids);
      d.has_media = true;
    }
    try {
      record.geometry = GeometryFromProto(shape, field, sources);
    } catch (const SceneError& e) {
      // Name the shape too, when it has a name: "shapes[3].mesh: ... (shape "bunny")".
      if (shape.name().empty()) throw;
      throw SceneError(std::string(e.what()) + " (shape \"" + shape.name() + "\")");
    }
    AddLights(static_cast<int>(d.shapes.size()), record.geometry, record.material, d);
    geometries.push_back(record.geometry);
    d.shapes.push_back(std::move(record));
  }

  std::vector<BoundingSphere> specular_targets;
  for (std::size_t i = 0; i < d.shapes.size(); ++i) {
    const ShapeRecord& shape = d.shapes[i];
    d.bounds.Extend(BoundsOf(shape.geometry));
    AddSpecularTargets(static_cast<int>(i), shape.geometry, shape.material, d.capabilities, specular_targets,
                       d.specular_target_surfaces);
  }
  d.specular_targets = TargetSpheres(std::move(specular_targets));
  const BoundingSphere scene_sphere = BoundingSphere::Of(d.bounds);
  for (int i = 0; i < description.lights_size(); ++i)
    d.lights.push_back(LightFromProto(description.lights(i), scene_sphere));
  if (description.has_medium()) {
    d.medium = MediumFromProto(description.medium(), "medium", grids);
    const DistantDisc disc = DistantDisc::Around(scene_sphere);
    d.medium_ball = {disc.center, disc.radius};
    d.has_media = true;
  }
  d.environment = EnvironmentFromProto(description, load_blob);
  d.environment_visible = d.environment && !description.environment().hidden_from_camera();
  if (d.environment && !d.environment->IsBlack()) {
    d.environment_light = static_cast<int>(d.lights.size());
    d.lights.push_back(EnvironmentLight{d.environment, DistantDisc::Around(scene_sphere)});
  }
  d.photons = PhotonSettings::FromProto(description.photons(), d.bounds.Diagonal());

  std::vector<float> power;
  for (const Light& light : d.lights) power.push_back(Power(light).Luminance());
  d.light_power = DiscreteDistribution(power);
  AddCausticAim(d);

  // ~17 ulps of the largest coordinate: above the rounding of the primitives' own
  // coordinates, which is what rays leaving points near the origin of a large scene meet.
  d.ray_epsilon = 2e-6f * SceneExtent(d.shapes);
  AcceleratorInput input{geometries, d.meshes, {}, {}, {}};
  AddCutoutFilter(d, input);
  d.accelerator = Accelerator::Build(input);
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
