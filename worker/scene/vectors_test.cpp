// The shared conformance vectors (tests/vectors/), which the coordinator's Go tests run too:
// a case one side accepts and the other refuses fails both suites.
//
//   tests/vectors/scenes/*.json  a renderfarm.v1.SceneVector each (protobuf JSON): its
//       scene, grown as `grow` says, with `assets` served by digest (each file's SHA-256
//       checked), must build when refused_field is empty and otherwise be refused with a
//       SceneError whose field (the text before the first ": ") is refused_field. Building
//       loads the mesh files and parts, the environment map and the textures materials
//       name (prepared by one texture system for all the vectors); a texture nothing
//       names is not read, so its digest is looked up among the assets here, after
//       building, as the README's step 4 says. Set FARM_SCENE_VECTORS to a folder to run
//       other vectors (while writing new ones).
//   tests/vectors/meshes/*.obj   OBJ files whose first line is "# vector: accept" or
//       "# vector: refuse line N: REASON": ParseObjMesh must accept the first kind and
//       refuse the second with an ObjError for line N.
//   tests/vectors/meshes/*.farmmesh   farm mesh files, each beside a NAME.farmmesh.vector
//       whose line is "# vector: accept" or "# vector: refuse byte N: REASON": ReadFarmMesh
//       must accept the first kind and refuse the second with a FarmMeshError at byte N
//       whose reason contains REASON (the reader words its refusals as Go does).
//   tests/vectors/grids/*.farmgrid   farm grid files, each beside its sidecar likewise:
//       ReadFarmGrid must accept or refuse them with a FarmGridError at byte N.
//
// Neither test skips: a folder without vectors fails it.

#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <unistd.h>

#include "daemon/sha256.h"
#include "renderfarm/v1/vectors.pb.h"
#include "scene/farm_grid.h"
#include "scene/farm_mesh.h"
#include "scene/obj_mesh.h"
#include "scene/scene.h"
#include "texture/texture_system.h"
#include "util/read_file.h"

namespace farm {
namespace {

namespace fs = std::filesystem;
namespace gp = google::protobuf;
namespace pb = renderfarm::v1;

// The files of `dir` whose names end in `extension`, sorted.
std::vector<fs::path> Vectors(const fs::path& dir, const std::string& extension) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.is_regular_file() && entry.path().extension() == extension) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

// Appends a copy of the last element of repeated field `fd` of `m`.
void AppendCopyOfLast(gp::Message& m, const gp::FieldDescriptor& fd) {
  const gp::Reflection& r = *m.GetReflection();
  const int last = r.FieldSize(m, &fd) - 1;
  switch (fd.cpp_type()) {
    case gp::FieldDescriptor::CPPTYPE_MESSAGE: {
      const gp::Message& copy = r.GetRepeatedMessage(m, &fd, last);
      r.AddMessage(&m, &fd)->CopyFrom(copy);
      return;
    }
    case gp::FieldDescriptor::CPPTYPE_INT32: return r.AddInt32(&m, &fd, r.GetRepeatedInt32(m, &fd, last));
    case gp::FieldDescriptor::CPPTYPE_INT64: return r.AddInt64(&m, &fd, r.GetRepeatedInt64(m, &fd, last));
    case gp::FieldDescriptor::CPPTYPE_UINT32: return r.AddUInt32(&m, &fd, r.GetRepeatedUInt32(m, &fd, last));
    case gp::FieldDescriptor::CPPTYPE_UINT64: return r.AddUInt64(&m, &fd, r.GetRepeatedUInt64(m, &fd, last));
    case gp::FieldDescriptor::CPPTYPE_DOUBLE: return r.AddDouble(&m, &fd, r.GetRepeatedDouble(m, &fd, last));
    case gp::FieldDescriptor::CPPTYPE_FLOAT: return r.AddFloat(&m, &fd, r.GetRepeatedFloat(m, &fd, last));
    case gp::FieldDescriptor::CPPTYPE_BOOL: return r.AddBool(&m, &fd, r.GetRepeatedBool(m, &fd, last));
    case gp::FieldDescriptor::CPPTYPE_ENUM: return r.AddEnumValue(&m, &fd, r.GetRepeatedEnumValue(m, &fd, last));
    case gp::FieldDescriptor::CPPTYPE_STRING: return r.AddString(&m, &fd, r.GetRepeatedString(m, &fd, last));
  }
}

// GrowField: appends copies of the last element of the list at path ("shapes",
// "shapes[0].triangles.indices") until it has count elements.
void Grow(pb::Scene& scene, const pb::GrowField& grow) {
  gp::Message* m = &scene;
  std::stringstream path(grow.path());
  std::string segment;
  std::vector<std::string> segments;
  while (std::getline(path, segment, '.')) segments.push_back(segment);
  for (std::size_t i = 0; i < segments.size(); ++i) {
    std::string name = segments[i];
    int index = -1;
    if (const std::size_t bracket = name.find('['); bracket != std::string::npos) {
      index = std::stoi(name.substr(bracket + 1));
      name.resize(bracket);
    }
    const gp::FieldDescriptor* fd = m->GetDescriptor()->FindFieldByName(name);
    if (fd == nullptr) throw std::runtime_error("grow path " + grow.path() + ": no field " + name);
    const gp::Reflection& r = *m->GetReflection();
    if (i + 1 == segments.size()) {
      if (!fd->is_repeated() || index >= 0 || r.FieldSize(*m, fd) == 0)
        throw std::runtime_error("grow path " + grow.path() + " is not a list with an element to copy");
      while (static_cast<std::uint64_t>(r.FieldSize(*m, fd)) < grow.count()) AppendCopyOfLast(*m, *fd);
      return;
    }
    if (fd->cpp_type() != gp::FieldDescriptor::CPPTYPE_MESSAGE)
      throw std::runtime_error("grow path " + grow.path() + ": " + name + " is not a message");
    m = index >= 0 ? r.MutableRepeatedMessage(m, fd, index) : r.MutableMessage(m, fd);
  }
}

// Serves the vector's assets, each checked against its digest first.
BlobLoader AssetLoader(const pb::SceneVector& v, const fs::path& dir) {
  std::map<std::string, std::string> blobs;
  for (const auto& [digest, file] : v.assets()) {
    std::string bytes = ReadFile(dir / file);
    if (Sha256Digest(bytes) != digest)
      throw std::runtime_error("asset " + file + " has digest " + Sha256Digest(bytes) + ", not " + digest);
    blobs.emplace(digest, std::move(bytes));
  }
  return [blobs = std::move(blobs)](const std::string& digest) {
    const auto it = blobs.find(digest);
    if (it == blobs.end()) throw std::runtime_error("the vector has no asset " + digest);
    return it->second;
  };
}

// The vector's assets as files, for the texture system (AssetLoader checks their digests).
BlobFileLoader AssetFileLoader(const pb::SceneVector& v, const fs::path& dir) {
  std::map<std::string, fs::path> files;
  for (const auto& [digest, file] : v.assets()) files.emplace(digest, dir / file);
  return [files = std::move(files)](const std::string& digest) {
    const auto it = files.find(digest);
    if (it == files.end()) throw std::runtime_error("the vector has no asset " + digest);
    return it->second;
  };
}

// "" if the worker treats the vector as it says, else what it did instead. `textures`
// prepares the textures materials name.
std::string Disagreement(const fs::path& file, TextureSystem& textures) {
  pb::SceneVector v;
  const auto status = gp::util::JsonStringToMessage(ReadFile(file), &v);
  if (!status.ok()) return "does not parse as a SceneVector: " + status.ToString();
  for (const pb::GrowField& g : v.grow()) Grow(*v.mutable_scene(), g);
  const BlobLoader load = AssetLoader(v, file.parent_path());
  SceneOptions options;
  options.textures = &textures;
  options.load_file = AssetFileLoader(v, file.parent_path());
  try {
    Scene::Build(v.scene(), load, options);
  } catch (const TaskError& e) {
    // A refusal of the scene (SceneError) or of one of its assets (a blob the store does
    // not have): either names the field.
    const std::string what = e.what();
    const std::string field = what.substr(0, what.find(": "));
    if (v.refused_field().empty()) return "refused, but every side must accept it: " + what;
    if (field != v.refused_field()) return "refused naming " + field + ", not " + v.refused_field() + ": " + what;
    return "";
  } catch (const std::exception& e) {
    return std::string("failed with an error that names no field: ") + e.what();
  }
  for (int i = 0; i < v.scene().textures_size(); ++i) {
    if (v.assets().contains(v.scene().textures(i).digest())) continue;
    const std::string field = "textures[" + std::to_string(i) + "].digest";
    if (field == v.refused_field()) return "";
    return "refused naming " + field + " (no such asset), not " + v.refused_field();
  }
  if (!v.refused_field().empty()) return "accepted, but every side must refuse it naming " + v.refused_field();
  return "";
}

TEST(SceneVectors, TheWorkerAcceptsAndRefusesWhatTheContractSays) {
  const char* override_dir = std::getenv("FARM_SCENE_VECTORS");
  const fs::path dir = override_dir && *override_dir ? fs::path(override_dir) : fs::path(SCENE_VECTORS);
  const std::vector<fs::path> vectors = Vectors(dir, ".json");
  ASSERT_FALSE(vectors.empty()) << "no scene vectors (*.json) in " << dir;
  const fs::path prepared = fs::temp_directory_path() / ("farm_scene_vectors_" + std::to_string(::getpid()));
  TextureSystem textures(TextureSystemOptions{64, prepared});
  for (const fs::path& file : vectors) EXPECT_EQ(Disagreement(file, textures), "") << file;
  fs::remove_all(prepared);
}

// What the first line of a mesh vector says: accept, or refuse at a line.
struct MeshExpectation {
  bool accept = false;
  std::size_t line = 0;
};

MeshExpectation ExpectationOf(const fs::path& file, const std::string& text) {
  std::string header = text.substr(0, text.find('\n'));
  if (!header.empty() && header.back() == '\r') header.pop_back();  // a CRLF file
  if (header == "# vector: accept") return {true, 0};
  constexpr std::string_view kRefuse = "# vector: refuse line ";
  if (header.rfind(kRefuse, 0) != 0 || header.find(": ", kRefuse.size()) == std::string::npos)
    throw std::runtime_error(file.string() + " does not start with \"# vector: accept\" or \"# vector: refuse line N: REASON\"");
  return {false, static_cast<std::size_t>(std::stoul(header.substr(kRefuse.size())))};
}

TEST(MeshVectors, TheObjLoaderAcceptsAndRefusesWhatEachFileSays) {
  const std::vector<fs::path> vectors = Vectors(MESH_VECTORS, ".obj");
  ASSERT_FALSE(vectors.empty()) << "no mesh vectors (*.obj) in " << MESH_VECTORS;
  int accepted = 0, refused = 0;
  for (const fs::path& file : vectors) {
    SCOPED_TRACE(file.string());
    const std::string text = ReadFile(file);
    const MeshExpectation want = ExpectationOf(file, text);
    try {
      const TriangleMesh mesh = ParseObjMesh(text);
      EXPECT_TRUE(want.accept) << "accepted (" << mesh.triangle_count() << " triangles), must be refused at line "
                               << want.line;
      accepted += want.accept;
    } catch (const ObjError& e) {
      EXPECT_FALSE(want.accept) << "refused, must be accepted: " << e.what();
      EXPECT_EQ(e.line(), want.line) << e.what();
      refused += !want.accept;
    }
  }
  EXPECT_GT(accepted, 0) << "no mesh vector is accepted";
  EXPECT_GT(refused, 0) << "no mesh vector is refused";
}

// Runs `read` on each file of `dir` ending in `extension` and holds it to the verdict of
// the file's sidecar (FILE.vector): accepted, or refused with an Error at byte N whose
// reason contains REASON.
template <typename Error, typename Read>
void CheckSidecarVectors(const fs::path& dir, const std::string& extension, Read read) {
  const std::vector<fs::path> vectors = Vectors(dir, extension);
  ASSERT_FALSE(vectors.empty()) << "no vectors (*" << extension << ") in " << dir;
  int accepted = 0, refused = 0;
  for (const fs::path& file : vectors) {
    SCOPED_TRACE(file.string());
    std::string verdict = ReadFile(fs::path(file.string() + ".vector"));
    ASSERT_TRUE(!verdict.empty() && verdict.back() == '\n');
    verdict.pop_back();
    constexpr std::string_view kRefuse = "# vector: refuse byte ";
    const bool accept = verdict == "# vector: accept";
    ASSERT_TRUE(accept || verdict.starts_with(kRefuse)) << verdict;
    try {
      const std::string what = read(ReadFile(file));
      EXPECT_TRUE(accept) << "accepted (" << what << "), must be refused: " << verdict;
      accepted += accept;
    } catch (const Error& e) {
      ASSERT_FALSE(accept) << "refused, must be accepted: " << e.what();
      const std::size_t colon = verdict.find(": ", kRefuse.size());
      EXPECT_EQ(e.offset(), std::stoull(verdict.substr(kRefuse.size()))) << e.what();
      EXPECT_NE(e.reason().find(verdict.substr(colon + 2)), std::string::npos) << e.what() << " vs " << verdict;
      refused += 1;
    }
  }
  EXPECT_GT(accepted, 0) << "no " << extension << " vector is accepted";
  EXPECT_GT(refused, 0) << "no " << extension << " vector is refused";
}

TEST(MeshVectors, TheFarmMeshReaderAcceptsAndRefusesWhatEachSidecarSays) {
  CheckSidecarVectors<FarmMeshError>(MESH_VECTORS, ".farmmesh", [](const std::string& bytes) {
    return std::to_string(ReadFarmMesh(bytes).triangle_count()) + " triangles";
  });
}

TEST(GridVectors, TheFarmGridReaderAcceptsAndRefusesWhatEachSidecarSays) {
  CheckSidecarVectors<FarmGridError>(GRID_VECTORS, ".farmgrid", [](const std::string& bytes) {
    const DenseGrid grid = ReadFarmGrid(bytes);
    return std::to_string(grid.nx()) + " x " + std::to_string(grid.ny()) + " x " + std::to_string(grid.nz()) + " cells";
  });
}

}  // namespace
}  // namespace farm
