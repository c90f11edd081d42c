package scene

import (
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// FieldError says which field of a scene is wrong and why; Field is a path of .proto field
// names, "shapes[2].sphere.radius".
type FieldError = rules.FieldError

// Validate checks s against the contract and returns the first violation as a
// *FieldError, or nil: first the rules scene.proto declares on each field (rules.Check),
// then, on a scene that passes them, the rules no bound expresses, in the order of
// structural below. The worker checks the same rules in the same order
// (worker/contract), and the shared vectors in tests/vectors/scenes hold both to it.
func Validate(s *pb.Scene) error {
	if s == nil {
		return rules.Errorf("scene", "missing")
	}
	if err := rules.Check(s); err != nil {
		return explainUpload(s, err)
	}
	for _, rule := range structural {
		if err := rule(s); err != nil {
			return err
		}
	}
	return nil
}

// structural lists the hand-written rules (the notes of scene.proto), each naming the
// field in parentheses; they may assume that rules.Check has passed.
var structural = []func(*pb.Scene) *FieldError{
	checkView,           // camera.look_at differs from position (camera.look_at); up non-zero, not parallel to the view (camera.up)
	checkTiles,          // tiles per round at most max_tiles_per_round (film.tile_size)
	checkPixels,         // pixels at most max_film_pixels (film.height)
	checkNames,          // unique (materials[i].name, meshes[i].name, textures[i].name)
	checkShapeMaterials, // names a material, or none for an instance (shapes[i].material); names a mesh (shapes[i].instance.mesh)
	checkPartMaterials,  // names a material (meshes[i].parts[j].material)
	checkTextureRefs,    // names a texture (materials[i].principled.*_texture.texture, environment.map.texture)
	checkSomeLight,      // at least one light (lights)
	checkGlossyEnergy,   // diffuse + specular <= 1 (materials[i].glossy.specular.r/g/b)
	checkShapes,         // quad edges, triangle indices, mesh and instance transforms (shapes[i]...)
	checkLightShapes,    // directions non-zero (lights[i].sun.direction, lights[i].spot.direction); inner cone <= outer (lights[i].spot.inner_cone_degrees)
	checkShards,         // shards per map at most max_shards_per_map (photons.photons_per_shard)
	checkReference,      // digest set when path is (progressive.reference.digest)
}
