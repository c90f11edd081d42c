#include "scene/obj_mesh.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <optional>
#include <sstream>
#include <vector>

#include "contract/go_text.h"
#include "contract/rules.h"

namespace farm {
namespace {

// tinyobj's messages end in newlines and name lines; keep them on one line of ours.
std::string OneLine(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

// Calls visit(line number from 1, line) for each line, split as tinyobjloader splits them
// (at "\n", "\r\n" or a lone "\r"); returns the number of lines.
std::size_t ForEachLine(std::string_view text,
                        const std::function<void(std::size_t, std::string_view)>& visit) {
  std::size_t number = 0;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = std::min(text.find_first_of("\r\n", at), text.size());
    visit(++number, text.substr(at, end - at));
    at = end + (text.substr(end, 2) == "\r\n" ? 2 : 1);
  }
  return number;
}

// The words of a line, up to a "#" that starts a comment, into `out` (reused across lines:
// a big mesh has tens of millions of them).
void Tokens(std::string_view line, std::vector<std::string_view>& out) {
  line = line.substr(0, line.find('#'));
  out.clear();
  for (std::size_t at = 0; at < line.size();) {
    at = line.find_first_not_of(" \t", at);
    if (at == std::string_view::npos) break;
    const std::size_t end = std::min(line.find_first_of(" \t", at), line.size());
    out.push_back(line.substr(at, end - at));
    at = end;
  }
}

// Whether the line's first word is "v" (as Tokens splits it).
bool IsVertexLine(std::string_view line) {
  line = line.substr(0, line.find('#'));
  const std::size_t at = line.find_first_not_of(" \t");
  return at != std::string_view::npos && line[at] == 'v' &&
         (at + 1 == line.size() || line[at + 1] == ' ' || line[at + 1] == '\t');
}

std::string_view WithoutPlus(std::string_view s) {
  return s.size() > 1 && s[0] == '+' && s[1] != '-' ? s.substr(1) : s;
}

// A decimal number as tinyobjloader reads one (no hexadecimal: it would read 0x1p3 as 0);
// past double's range it is infinite, below it 0.
std::optional<double> Number(std::string_view token) {
  token = WithoutPlus(token);
  double v = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (end != token.data() + token.size()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) return std::strtod(std::string(token).c_str(), nullptr);
  if (ec != std::errc()) return std::nullopt;
  return v;
}

std::optional<long long> Integer(std::string_view token) {
  token = WithoutPlus(token);
  long long v = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || end != token.data() + token.size()) return std::nullopt;
  return v;
}

// A word of the file in a message: quoted, escaped and cut short, since it may be anything.
std::string Quoted(std::string_view token) { return contract::GoQuote(contract::Truncate(token, 40)); }

// Checks every line against the rules in the header; throws ObjError for the first that
// breaks one.
class ObjChecker {
 public:
  explicit ObjChecker(std::string_view text) : text_(text) {}

  void Check() {
    const auto& limits = contract::SceneLimits();
    if (text_.size() > limits.max_asset_bytes())
      throw ObjError(0, "the file is " + std::to_string(text_.size()) + " bytes, more than the " +
                            std::to_string(limits.max_asset_bytes()) + " an asset may have");
    // Positive indices may name vertices defined further down: count them all first.
    ForEachLine(text_, [&](std::size_t, std::string_view line) { total_vertices_ += IsVertexLine(line); });
    const std::size_t lines = ForEachLine(text_, [&](std::size_t n, std::string_view line) { Line(n, line); });
    if (faces_ == 0) throw ObjError(lines, "the file has no faces (f lines)");
  }

 private:
  void Line(std::size_t n, std::string_view line) {
    Tokens(line, tokens_);
    if (tokens_.empty()) return;
    if (tokens_[0] == "v") Vertex(n, tokens_);
    if (tokens_[0] == "f") Face(n, tokens_);
  }

  void Vertex(std::size_t n, const std::vector<std::string_view>& tokens) {
    if (tokens.size() < 4)
      throw ObjError(n, "a vertex needs 3 coordinates, got " + std::to_string(tokens.size() - 1));
    for (std::size_t i = 1; i < tokens.size(); ++i) {
      const std::optional<double> v = Number(tokens[i]);
      if (!v) throw ObjError(n, "vertex coordinate " + Quoted(tokens[i]) + " is not a number");
      if (!std::isfinite(*v)) throw ObjError(n, "vertex coordinate " + Quoted(tokens[i]) + " is not finite");
    }
    if (++vertices_ > contract::SceneLimits().max_mesh_vertices())
      throw ObjError(n, "more than " + std::to_string(contract::SceneLimits().max_mesh_vertices()) +
                            " vertices");
  }

  void Face(std::size_t n, const std::vector<std::string_view>& tokens) {
    const std::size_t corners = tokens.size() - 1;
    if (corners < 3) throw ObjError(n, "a face needs 3 vertices, got " + std::to_string(corners));
    for (std::size_t i = 1; i < tokens.size(); ++i) Reference(n, tokens[i]);
    ++faces_;
    triangles_ += corners - 2;
    if (triangles_ > contract::SceneLimits().max_mesh_triangles())
      throw ObjError(n, "more than " + std::to_string(contract::SceneLimits().max_mesh_triangles()) +
                            " triangles");
  }

  // One corner of a face: v, v/vt, v//vn or v/vt/vn.
  void Reference(std::size_t n, std::string_view ref) {
    std::vector<std::string_view> parts;
    for (std::size_t at = 0;;) {
      const std::size_t slash = ref.find('/', at);
      parts.push_back(ref.substr(at, slash == std::string_view::npos ? std::string_view::npos : slash - at));
      if (slash == std::string_view::npos) break;
      at = slash + 1;
    }
    if (parts.size() > 3) throw ObjError(n, "face vertex " + Quoted(ref) + " has more than 3 parts");
    for (std::size_t k = 0; k < parts.size(); ++k) {
      if (parts[k].empty() && k > 0) continue;  // v//vn, v/vt/
      const std::optional<long long> index = Integer(parts[k]);
      if (!index) throw ObjError(n, "face vertex " + Quoted(ref) + " is not made of integers");
      if (*index == 0) throw ObjError(n, "face vertex " + Quoted(ref) + ": OBJ indices start at 1, not 0");
      if (k == 0) Position(n, *index);
    }
  }

  void Position(std::size_t n, long long index) {
    if (index > 0 && static_cast<unsigned long long>(index) > total_vertices_)
      throw ObjError(n, "face refers to vertex " + std::to_string(index) + ", but the file has " +
                            std::to_string(total_vertices_) + " vertices");
    if (index < 0 && index < -static_cast<long long>(vertices_))
      throw ObjError(n, "face refers to vertex " + std::to_string(index) + " (relative), but only " +
                            std::to_string(vertices_) + " vertices come before it");
  }

  std::string_view text_;
  std::vector<std::string_view> tokens_;  // of the current line
  std::uint64_t total_vertices_ = 0;
  std::uint64_t vertices_ = 0;  // so far
  std::uint64_t faces_ = 0;
  std::uint64_t triangles_ = 0;
};

}  // namespace

ObjError::ObjError(std::size_t line, const std::string& reason)
    : BadInputError(line ? "line " + std::to_string(line) + ": " + reason : reason),
      line_(line),
      reason_(reason) {}

TriangleMesh ParseObjMesh(std::string_view bytes) {
  ObjChecker(bytes).Check();

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  std::istringstream in{std::string(bytes)};
  // No material reader: `mtllib` lines are ignored (the scene assigns the material).
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in,
                                   /*readMatFn=*/nullptr, /*triangulate=*/true);
  if (!ok) throw ObjError(0, "tinyobjloader: " + OneLine(err));

  TriangleMesh mesh;
  const std::size_t vertex_count = attrib.vertices.size() / 3;
  mesh.positions.reserve(vertex_count);
  for (std::size_t i = 0; i < vertex_count; ++i) {
    const Vec3 p(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
    // Finite as text, but past float's range.
    if (!IsFinite(p)) throw ObjError(0, "vertex " + std::to_string(i + 1) + " is out of float range");
    mesh.positions.push_back(p);
  }
  for (const tinyobj::shape_t& shape : shapes) {
    std::size_t offset = 0;
    for (const unsigned char n : shape.mesh.num_face_vertices) {
      if (n == 3) {  // after triangulation only degenerate leftovers differ; skip those
        for (std::size_t k = 0; k < 3; ++k)
          mesh.indices.push_back(static_cast<uint32_t>(shape.mesh.indices[offset + k].vertex_index));
      }
      offset += n;
    }
  }
  if (mesh.indices.empty())
    throw ObjError(0, "no triangle is left after triangulation" +
                          (warn.empty() ? std::string() : " (" + OneLine(warn) + ")"));
  return mesh;
}

}  // namespace farm
