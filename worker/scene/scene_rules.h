#pragma once

// Whether a scene description keeps the contract (scene.proto), checked by the worker as
// the coordinator checks it on submit, naming the same field: first every field's rule
// (contract::CheckRules), then the rules no (rule) option can state, each one a note in
// scene.proto:
//
//   camera.look_at               differs from camera.position
//   camera.up                    non-zero and not parallel to look_at - position
//   film.tile_size               at most SceneLimits().max_tiles_per_round tiles in the film
//                                (ceil(width / tile) * ceil(height / tile))
//   film.height                  width * height at most SceneLimits().max_film_pixels
//   materials[i].name            unique
//   materials[i].glossy.specular.r/g/b   diffuse + specular <= 1
//   lights[i].sun.direction      non-zero
//   shapes[i].material           names a material
//   shapes[i].quad.edge_u        non-zero; edge_v non-zero and not parallel to edge_u
//   shapes[i].triangles.indices  a non-zero multiple of 3; indices[j] < the positions
//   shapes[i].mesh.transform.scale.x/y/z   non-zero; rotation_axis non-zero when
//                                rotation_degrees is not 0
//   lights                       at least one light: a point or sun light with a positive
//                                component, or a shape with a positive emissive material
//   photons.photons_per_shard    at most SceneLimits().max_shards_per_map shards for each
//                                photon map the scene uses (global: a shape reflects
//                                diffusely; caustic: a shape is specular)
//   progressive.reference.digest set when reference.path is
//
// "Parallel" is |u x v| <= 1e-9 |u| |v|, in double precision, as in Go.

#include "renderfarm/v1/scene.pb.h"

namespace farm {

// Throws SceneError ("shapes[3].quad.edge_v: must not be parallel to edge_u ...") for the
// first rule `scene` breaks.
void CheckScene(const renderfarm::v1::Scene& scene);

}  // namespace farm
