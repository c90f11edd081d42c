package main

import (
	"slices"

	pb "photonfarm/proto/renderfarm/v1"
)

// refusedAssets are the refusals of what scenes name by digest and by name: meshes and
// their parts, the instances that place them, textures and the references to them, and
// affine matrices.
var refusedAssets = slices.Concat([]vectorCase{
	// Scene.
	refuse("refuse-100001-meshes", "meshes", "Scene.meshes:max_items", unchanged, grow("meshes", 100001)),
	refuse("refuse-4097-textures", "textures", "Scene.textures:max_items", unchanged, grow("textures", 4097)),

	// Meshes.
	refuse("refuse-mesh-without-name", "meshes[0].name", "Mesh.name:required", func(s *pb.Scene) { crate(s).Name = "" }),
	refuse("refuse-mesh-name-of-257-bytes", "meshes[0].name", "Mesh.name:max_bytes", func(s *pb.Scene) { crate(s).Name = long(257) }),
	refuse("refuse-duplicate-mesh-name", "meshes[1].name", "Mesh.name:note", func(s *pb.Scene) {
		s.Meshes = append(s.Meshes, &pb.Mesh{Name: "crate", Parts: crate(s).Parts[:1]})
	}),
	refuse("refuse-mesh-without-parts", "meshes[0].parts", "Mesh.parts:min_items", func(s *pb.Scene) { crate(s).Parts = nil }),
	refuse("refuse-mesh-of-4097-parts", "meshes[0].parts", "Mesh.parts:max_items", unchanged, grow("meshes[0].parts", 4097)),
	refuse("refuse-mesh-part-path-of-4097-bytes", "meshes[0].parts[1].path", "MeshPart.path:max_bytes", func(s *pb.Scene) { crate(s).Parts[1].Path = long(4097) }),
	refuse("refuse-mesh-part-without-digest", "meshes[0].parts[0].digest", "MeshPart.digest:required", func(s *pb.Scene) { crate(s).Parts[0].Digest = "" }),
	refuse("refuse-mesh-part-digest-malformed", "meshes[0].parts[0].digest", "MeshPart.digest:digest", func(s *pb.Scene) { crate(s).Parts[0].Digest = badDigest }),
	refuse("refuse-mesh-part-of-no-uploaded-file", "meshes[0].parts[1].digest", "MeshPart.digest:note", func(s *pb.Scene) { crate(s).Parts[1].Digest = absentDigest }),
	refuse("refuse-mesh-part-without-material", "meshes[0].parts[1].material", "MeshPart.material:required", func(s *pb.Scene) { crate(s).Parts[1].Material = "" }),
	refuse("refuse-mesh-part-of-unknown-material", "meshes[0].parts[1].material", "MeshPart.material:note", func(s *pb.Scene) { crate(s).Parts[1].Material = "chrome" }),

	// Instances.
	refuse("refuse-instance-without-mesh", "shapes[7].instance.mesh", "MeshInstance.mesh:required", func(s *pb.Scene) { withInstance(s).Mesh = "" }),
	refuse("refuse-instance-of-unknown-mesh", "shapes[7].instance.mesh", "MeshInstance.mesh:note", func(s *pb.Scene) { withInstance(s).Mesh = "barrel" }),
	refuse("refuse-instance-with-a-material", "shapes[7].material", "Shape.material:note", func(s *pb.Scene) {
		withInstance(s)
		s.Shapes[7].Material = "white"
	}),
	refuse("refuse-instance-scale-y-0", "shapes[7].instance.transform.scale.y", "Transform.scale:note", func(s *pb.Scene) {
		withInstance(s).Transform = &pb.Transform{Scale: v(1, 0, 1)}
	}),

	// Affine matrices.
	refuse("refuse-matrix-of-13-values", "shapes[7].instance.transform.matrix", "Transform.matrix:max_items", func(s *pb.Scene) {
		inst := withInstance(s)
		inst.Transform.Matrix = append(inst.Transform.Matrix, 1)
	}),
	refuse("refuse-matrix-of-11-values", "shapes[7].instance.transform.matrix", "Transform.matrix:note", func(s *pb.Scene) {
		inst := withInstance(s)
		inst.Transform.Matrix = inst.Transform.Matrix[:11]
	}),
	refuse("refuse-matrix-with-a-translation", "shapes[7].instance.transform.matrix", "Transform.matrix:note", func(s *pb.Scene) {
		withInstance(s).Transform.Translation = v(1, 0, 0)
	}),
	refuse("refuse-matrix-with-a-rotation", "shapes[7].mesh.transform.matrix", "Transform.matrix:note", func(s *pb.Scene) {
		// The mesh's scale, rotation and translation stay: rotation_degrees is the field named.
		m := withMesh(s)
		m.Transform.Translation, m.Transform.Scale, m.Transform.RotationAxis = nil, nil, nil
		m.Transform.Matrix = []float64{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}
	}),
	refuse("refuse-singular-matrix", "shapes[7].instance.transform.matrix", "Transform.matrix:note", func(s *pb.Scene) {
		// Its third column is the sum of the first two.
		withInstance(s).Transform.Matrix = []float64{1, 2, 3, 0, 4, 5, 9, 0, 7, 8, 15, 0}
	}),

	// Textures.
	refuse("refuse-texture-without-name", "textures[0].name", "Texture.name:required", func(s *pb.Scene) { wood(s).Name = "" }),
	refuse("refuse-texture-name-of-257-bytes", "textures[0].name", "Texture.name:max_bytes", func(s *pb.Scene) { wood(s).Name = long(257) }),
	refuse("refuse-duplicate-texture-name", "textures[1].name", "Texture.name:note", func(s *pb.Scene) { s.Textures[1].Name = "wood" }),
	refuse("refuse-texture-path-of-4097-bytes", "textures[1].path", "Texture.path:max_bytes", func(s *pb.Scene) { s.Textures[1].Path = long(4097) }),
	refuse("refuse-texture-without-digest", "textures[0].digest", "Texture.digest:required", func(s *pb.Scene) { wood(s).Digest = "" }),
	refuse("refuse-texture-digest-malformed", "textures[0].digest", "Texture.digest:digest", func(s *pb.Scene) { wood(s).Digest = badDigest }),
	refuse("refuse-texture-of-no-uploaded-file", "textures[1].digest", "Texture.digest:note", func(s *pb.Scene) { s.Textures[1].Digest = absentDigest }),
	refuse("refuse-unknown-texture-encoding", "textures[0].encoding", "Texture.encoding:enum", func(s *pb.Scene) { wood(s).Encoding = 9 }),
	refuse("refuse-unknown-texture-wrap", "textures[0].wrap", "Texture.wrap:enum", func(s *pb.Scene) { wood(s).Wrap = 9 }),
	refuse("refuse-texture-reference-without-texture", "materials[6].principled.normal_texture.texture", "TextureRef.texture:required", func(s *pb.Scene) {
		principled(s).NormalTexture.Texture = ""
	}),
	refuse("refuse-base-color-texture-of-unknown-texture", "materials[6].principled.base_color_texture.texture", "TextureRef.texture:note", func(s *pb.Scene) {
		principled(s).BaseColorTexture.Texture = "oak"
	}),
	refuse("refuse-emission-texture-of-unknown-texture", "materials[6].principled.emission_texture.texture", "TextureRef.texture:note", func(s *pb.Scene) {
		principled(s).EmissionTexture.Texture = "oak"
	}),
	refuse("refuse-environment-map-of-unknown-texture", "environment.map.texture", "TextureRef.texture:note", func(s *pb.Scene) {
		s.Environment.Map.Texture = "dusk"
	}),
},
	nonFinite("refuse-matrix-value", "shapes[7].instance.transform.matrix[3]", "Transform.matrix", func(s *pb.Scene, x float64) {
		withInstance(s).Transform.Matrix[3] = x
	}),
)
