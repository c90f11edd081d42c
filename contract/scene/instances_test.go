package scene_test

import (
	"testing"

	"photonfarm/contract/scene"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// The rules of the assets issue 13 added: meshes placed by instances, textures, affine
// matrices, spot lights, principled emission and the environment as lights.

// part is a mesh part of material.
func part(material string) *pb.MeshPart {
	return &pb.MeshPart{Path: material + ".farmmesh", Digest: goodDigest, Material: material}
}

// withCrate adds a mesh "crate" of the given parts and a shape (shapes[3]) placing it.
func withCrate(parts ...*pb.MeshPart) func(*pb.Scene) {
	return func(s *pb.Scene) {
		s.Meshes = append(s.Meshes, &pb.Mesh{Name: "crate", Parts: parts})
		s.Shapes = append(s.Shapes, &pb.Shape{Name: "crate-1", Geometry: &pb.Shape_Instance{Instance: &pb.MeshInstance{Mesh: "crate",
			Transform: &pb.Transform{Translation: scenetest.V(1, 0, 0)}}}})
	}
}

func instance(s *pb.Scene) *pb.MeshInstance { return s.Shapes[3].GetInstance() }

func principled(name string, p *pb.Principled) *pb.Material {
	return &pb.Material{Name: name, Kind: &pb.Material_Principled{Principled: p}}
}

func texture(name string) *pb.Texture {
	return &pb.Texture{Name: name, Path: name + ".png", Digest: goodDigest}
}

func spot(dir *pb.Vec3, inner, outer float64) *pb.Light {
	return &pb.Light{Kind: &pb.Light_Spot{Spot: &pb.SpotLight{Position: scenetest.V(0, 3, 0), Direction: dir,
		Intensity: rgb(5, 5, 5), InnerConeDegrees: inner, OuterConeDegrees: outer}}}
}

// matrix is a 12-value Transform.matrix: a scale by k and a translation along x.
func matrix(k float64) *pb.Transform {
	return &pb.Transform{Matrix: []float64{k, 0, 0, 1, 0, k, 0, 0, 0, 0, k, 0}}
}

// then runs mutations in order.
func then(fs ...func(*pb.Scene)) func(*pb.Scene) {
	return func(s *pb.Scene) {
		for _, f := range fs {
			f(s)
		}
	}
}

func TestValidateAcceptsInstancesTexturesAndNewLights(t *testing.T) {
	expectValid(t, []variant{
		{"an instance of two parts", withCrate(part("white"), part("light"))},
		{"an instance placed by a matrix", then(withCrate(part("white")), func(s *pb.Scene) { instance(s).Transform = matrix(2) })},
		{"a mirroring matrix", then(withCrate(part("white")), func(s *pb.Scene) { instance(s).Transform = matrix(-1) })},
		{"a mesh file placed by a matrix", func(s *pb.Scene) {
			s.Shapes = append(s.Shapes, meshShape(&pb.MeshFile{Digest: goodDigest, Transform: matrix(0.5)}))
		}},
		{"principled textures", func(s *pb.Scene) {
			s.Textures = []*pb.Texture{texture("wood"), texture("rough"), texture("bumps"), texture("glow")}
			s.Materials = append(s.Materials, principled("varnish", &pb.Principled{
				BaseColorTexture: &pb.TextureRef{Texture: "wood"}, MetallicRoughnessTexture: &pb.TextureRef{Texture: "rough"},
				NormalTexture: &pb.TextureRef{Texture: "bumps"}, EmissionTexture: &pb.TextureRef{Texture: "glow"}}))
			s.Shapes[0].Material = "varnish"
		}},
		{"an environment map", func(s *pb.Scene) {
			s.Textures = []*pb.Texture{texture("sky")}
			s.Environment = &pb.Environment{Map: &pb.TextureRef{Texture: "sky"}}
		}},
		{"spot light only", then(withoutLamp, func(s *pb.Scene) { s.Lights = []*pb.Light{spot(scenetest.V(0, -1, 0), 20, 20)} })},
		{"principled emission only", then(withoutLamp, func(s *pb.Scene) {
			s.Materials = append(s.Materials, principled("glow", &pb.Principled{Emission: rgb(0, 0, 1)}))
			s.Shapes[1].Material = "glow"
		})},
		{"an instanced emissive part only", then(withoutLamp, withCrate(part("light")))},
		{"a constant environment only", then(withoutLamp, func(s *pb.Scene) { s.Environment = &pb.Environment{Radiance: rgb(0, 0.1, 0)} })},
		{"an environment map only", then(withoutLamp, func(s *pb.Scene) {
			s.Textures = []*pb.Texture{texture("sky")}
			s.Environment = &pb.Environment{Map: &pb.TextureRef{Texture: "sky"}}
		})},
	})
}

func TestValidateRefusesBrokenReferencesTransformsAndLights(t *testing.T) {
	expectRefused(t, []refusal{
		{"an instance with a material", then(withCrate(part("white")), func(s *pb.Scene) { s.Shapes[3].Material = "white" }),
			"shapes[3].material", "must be empty for an instance"},
		{"an instance of no mesh", then(withCrate(part("white")), func(s *pb.Scene) { instance(s).Mesh = "barrel" }),
			"shapes[3].instance.mesh", `no mesh named "barrel"`},
		{"a part of no material", withCrate(part("white"), part("chrome")), "meshes[0].parts[1].material", `no material named "chrome"`},
		{"a mesh without parts", withCrate(), "meshes[0].parts", "at least 1"},
		{"two meshes of one name", then(withCrate(part("white")), func(s *pb.Scene) { s.Meshes = append(s.Meshes, s.Meshes[0]) }),
			"meshes[1].name", `duplicate mesh name "crate" (also meshes[0])`},
		{"two textures of one name", func(s *pb.Scene) { s.Textures = []*pb.Texture{texture("sky"), texture("sky")} },
			"textures[1].name", `duplicate texture name "sky" (also textures[0])`},
		{"a material reads no texture", func(s *pb.Scene) {
			s.Materials = append(s.Materials, principled("varnish", &pb.Principled{NormalTexture: &pb.TextureRef{Texture: "bumps"}}))
		}, "materials[2].principled.normal_texture.texture", `no texture named "bumps"`},
		{"the environment reads no texture", func(s *pb.Scene) { s.Environment = &pb.Environment{Map: &pb.TextureRef{Texture: "sky"}} },
			"environment.map.texture", `no texture named "sky"`},
		{"a matrix of 11 values", then(withCrate(part("white")), func(s *pb.Scene) {
			instance(s).Transform = matrix(1)
			instance(s).Transform.Matrix = instance(s).Transform.Matrix[:11]
		}), "shapes[3].instance.transform.matrix", "must have 12 values"},
		{"a matrix of 13 values", then(withCrate(part("white")), func(s *pb.Scene) {
			instance(s).Transform = matrix(1)
			instance(s).Transform.Matrix = append(instance(s).Transform.Matrix, 1)
		}), "shapes[3].instance.transform.matrix", "at most 12"},
		{"a matrix and a translation", then(withCrate(part("white")), func(s *pb.Scene) { instance(s).Transform.Matrix = matrix(1).Matrix }),
			"shapes[3].instance.transform.matrix", "but translation is set too"},
		{"a matrix and a rotation", func(s *pb.Scene) {
			tr := matrix(1)
			tr.RotationDegrees = 10
			s.Shapes = append(s.Shapes, meshShape(&pb.MeshFile{Digest: goodDigest, Transform: tr}))
		}, "shapes[3].mesh.transform.matrix", "but rotation_degrees is set too"},
		{"a singular matrix", then(withCrate(part("white")), func(s *pb.Scene) {
			instance(s).Transform = &pb.Transform{Matrix: []float64{1, 2, 3, 0, 2, 4, 6, 0, 0, 0, 1, 0}}
		}), "shapes[3].instance.transform.matrix", "must be invertible"},
		{"an instance scaled by 0", then(withCrate(part("white")), func(s *pb.Scene) { instance(s).Transform.Scale = scenetest.V(1, 1, 0) }),
			"shapes[3].instance.transform.scale.z", "non-zero"},
		{"a spot light without direction", func(s *pb.Scene) { s.Lights = []*pb.Light{spot(scenetest.V(0, 0, 0), 10, 20)} },
			"lights[0].spot.direction", "non-zero"},
		{"a spot light's inner cone past its outer one", func(s *pb.Scene) { s.Lights = []*pb.Light{spot(scenetest.V(0, -1, 0), 30, 20)} },
			"lights[0].spot.inner_cone_degrees", "must be at most outer_cone_degrees 20, got 30"},
		{"a black principled emission and a black environment", then(withoutLamp, func(s *pb.Scene) {
			s.Materials = append(s.Materials, principled("glow", &pb.Principled{Emission: rgb(0, 0, 0)}))
			s.Shapes[1].Material = "glow"
			s.Environment = &pb.Environment{Radiance: rgb(0, 0, 0)}
		}), "lights", "needs a light"},
		{"an environment map multiplied by black", then(withoutLamp, func(s *pb.Scene) {
			s.Textures = []*pb.Texture{texture("sky")}
			s.Environment = &pb.Environment{Map: &pb.TextureRef{Texture: "sky"}, Radiance: rgb(0, 0, 0)}
		}), "lights", "needs a light"},
		{"a black spot light", then(withoutLamp, func(s *pb.Scene) {
			s.Lights = []*pb.Light{spot(scenetest.V(0, -1, 0), 10, 20)}
			s.Lights[0].GetSpot().Intensity = rgb(0, 0, 0)
		}), "lights", "needs a light"},
	})
}

func TestInstancedPartsCountLikeMeshFiles(t *testing.T) {
	flatFloor := func(s *pb.Scene) { s.Shapes = s.Shapes[1:] } // floor and lamp only: shapes[2] is the instance
	tests := []struct {
		name       string
		mutate     func(*pb.Scene)
		surfaces   scene.Surfaces
		interlight bool
	}{
		{"a flat floor", flatFloor, scene.Surfaces{Diffuse: true}, false},
		{"a diffuse instance over the floor", then(flatFloor, withCrate(part("white"))), scene.Surfaces{Diffuse: true}, true},
		{"an emissive instance over the floor", then(flatFloor, withCrate(part("light"))), scene.Surfaces{Diffuse: true}, false},
		{"an instance with a mirror part", then(flatFloor, addMaterial(mirror(rgb(1, 1, 1))), withCrate(part("light"), part("mirror"))),
			scene.Surfaces{Diffuse: true, Specular: true}, true},
		{"a sphere lit by an emissive instance, which may be inside it", func(s *pb.Scene) {
			s.Shapes = s.Shapes[:1]
			withCrate(part("light"))(s)
		}, scene.Surfaces{Diffuse: true}, true},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			s := validated(t, tt.mutate)
			if got := scene.SurfacesOf(s); got != tt.surfaces {
				t.Errorf("SurfacesOf = %+v, want %+v", got, tt.surfaces)
			}
			if got := scene.InterreflectionOf(s); got.Possible != tt.interlight {
				t.Errorf("InterreflectionOf = %+v, want Possible %v", got, tt.interlight)
			}
		})
	}
}
