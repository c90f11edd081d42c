#pragma once

// Whether a scene description keeps the contract (scene.proto), checked by the worker as
// the coordinator checks it on submit (contract/scene.Validate), naming the same field,
// in the same order: first every field's rule (contract::CheckRules), then the rules no
// (rule) option can state, each one a note in scene.proto:
//
//   camera.look_at               differs from camera.position
//   camera.up                    non-zero and not parallel to look_at - position
//   film.tile_size               at most SceneLimits().max_tiles_per_round tiles in the film
//                                (ceil(width / tile) * ceil(height / tile))
//   film.height                  width * height at most SceneLimits().max_film_pixels
//   materials[i].name, meshes[i].name, textures[i].name   unique among their kind
//   shapes[i].material           names a material; empty for an instance
//   shapes[i].instance.mesh      names a mesh
//   meshes[i].parts[j].material  names a material
//   materials[i].principled.*_texture.texture, environment.map.texture   names a texture
//   lights                       at least one light: a point, spot or sun light with a
//                                positive component, a shape (or an instanced mesh part)
//                                whose material emits (emissive radiance or principled
//                                emission positive), or an environment that is not black
//   materials[i].glossy.specular.r/g/b   diffuse + specular <= 1
//   shapes[i].quad.edge_u        non-zero; edge_v non-zero and not parallel to edge_u
//   shapes[i].triangles.indices  a non-zero multiple of 3; indices[j] < the positions
//   shapes[i].mesh.transform, shapes[i].instance.transform   a matrix of 12 values with
//                                nothing else set and a non-zero determinant; or scale
//                                components non-zero, rotation_axis non-zero when
//                                rotation_degrees is not 0
//   lights[i].sun.direction, lights[i].spot.direction   non-zero
//   lights[i].spot.inner_cone_degrees   at most outer_cone_degrees
//   photons.photons_per_shard    at most SceneLimits().max_shards_per_map shards for each
//                                photon count, whether or not the scene gets that map
//   progressive.reference.digest set when reference.path is
//
// "Parallel" is |u x v| <= 1e-9 |u| |v|, in double precision, as in Go.

#include <string>
#include <vector>

#include "renderfarm/v1/scene.pb.h"

namespace farm {

// Throws SceneError ("shapes[3].quad.edge_v: must not be parallel to edge_u ...") for the
// first rule `scene` breaks.
void CheckScene(const renderfarm::v1::Scene& scene);

// Whether a material emits light: emissive with a positive radiance, or principled with a
// positive emission (in double precision).
bool MaterialEmits(const renderfarm::v1::Material& material);

// Whether the environment is not black: a positive radiance, or a map with the radiance
// unset (which multiplies the map by 1).
bool EnvironmentLights(const renderfarm::v1::Scene& scene);

// A place where a scene reads a texture: "materials[2].principled.base_color_texture",
// "environment.map".
struct TextureRefAt {
  std::string field;
  const renderfarm::v1::TextureRef* ref = nullptr;
};
// The texture references that are set, in field order: each principled material's base
// colour, metallic-roughness, normal and emission textures, then the environment's map.
std::vector<TextureRefAt> TextureRefs(const renderfarm::v1::Scene& scene);

// The determinant of the linear part of a transform's 12-value matrix (row-major),
// expanded along the first row, as contract/scene.MatrixDeterminant computes it.
double MatrixDeterminant(const renderfarm::v1::Transform& transform);

}  // namespace farm
