package main

import (
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// base is the valid scene every generated case starts from: a piece of each part of the
// contract, so that a case changes one thing. Its layout is what the accessors below
// name; a case that needs a mesh file adds one (withMesh).
func base() *pb.Scene {
	return &pb.Scene{
		Name:     "vector-base",
		Camera:   &pb.Camera{Position: v(0, 1, 5), LookAt: v(0, 1, 0), Up: v(0, 1, 0), VerticalFovDegrees: 40, ApertureRadius: 0.01, FocusDistance: 5},
		Film:     &pb.Film{Width: 32, Height: 24, TileSize: 16},
		Sampling: &pb.Sampling{SamplesPerPixel: 2, Seed: 7, LightSamples: 4},
		Materials: []*pb.Material{
			{Name: "white", Kind: &pb.Material_Lambert{Lambert: &pb.Lambert{Reflectance: rgb(0.8, 0.8, 0.8)}}},
			{Name: "lamp", Kind: &pb.Material_Emissive{Emissive: &pb.Emissive{Radiance: rgb(10, 10, 10)}}},
			{Name: "shiny", Kind: &pb.Material_Glossy{Glossy: &pb.Glossy{Diffuse: rgb(0.4, 0.4, 0.4), Specular: rgb(0.5, 0.5, 0.5), Exponent: 50}}},
			{Name: "mirror", Kind: &pb.Material_Mirror{Mirror: &pb.Mirror{Reflectance: rgb(0.9, 0.9, 0.9)}}},
			{Name: "glass", Kind: &pb.Material_Dielectric{Dielectric: &pb.Dielectric{Ior: 1.5, Transmittance: rgb(1, 1, 1)}}},
			{Name: "gold", Kind: &pb.Material_Conductor{Conductor: &pb.Conductor{Eta: rgb(0.143, 0.374, 1.442), K: rgb(3.983, 2.385, 1.603)}}},
			{Name: "varnish", Kind: &pb.Material_Principled{Principled: &pb.Principled{
				BaseColor: rgb(0.6, 0.4, 0.2), BaseColorTexture: &pb.TextureRef{Texture: "wood"},
				Metallic: 0.2, Roughness: 0.4, MetallicRoughnessTexture: &pb.TextureRef{Texture: "wood"},
				NormalTexture: &pb.TextureRef{Texture: "wood"}, NormalScale: 0.8,
				Emission: rgb(0.1, 0.1, 0), EmissionTexture: &pb.TextureRef{Texture: "wood"},
				AlphaMode: pb.AlphaMode_ALPHA_MODE_MASK, Transparency: 0.1, AlphaCutoff: 0.4}}},
		},
		Shapes: []*pb.Shape{
			{Name: "ball", Material: "white", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: v(0, 1, 0), Radius: 1}}},
			{Name: "floor", Material: "white", Geometry: &pb.Shape_Quad{Quad: &pb.Quad{Origin: v(-5, 0, 5), EdgeU: v(10, 0, 0), EdgeV: v(0, 0, -10)}}},
			{Name: "lamp", Material: "lamp", Geometry: &pb.Shape_Quad{Quad: &pb.Quad{Origin: v(-0.5, 3, 0.5), EdgeU: v(0, 0, -1), EdgeV: v(1, 0, 0)}}},
			{Name: "prism", Material: "shiny", Geometry: &pb.Shape_Triangles{Triangles: &pb.TriangleMesh{
				Positions: []*pb.Vec3{v(2, 0, 0), v(3, 0, 0), v(2, 1, 0)}, Indices: []uint32{0, 1, 2}}}},
			{Name: "mirror-ball", Material: "mirror", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: v(-2, 0.5, 0), Radius: 0.5}}},
			{Name: "glass-ball", Material: "glass", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: v(-1, 0.5, 2), Radius: 0.5}}},
			{Name: "gold-ball", Material: "gold", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: v(1, 0.5, 2), Radius: 0.5}}},
		},
		Lights: []*pb.Light{
			{Name: "bulb", Kind: &pb.Light_Point{Point: &pb.PointLight{Position: v(0, 3, 2), Intensity: rgb(5, 5, 5)}}},
			{Name: "sun", Kind: &pb.Light_Sun{Sun: &pb.SunLight{Direction: v(0, -1, -0.2), Irradiance: rgb(1, 1, 1), AngularDiameterDegrees: 0.53}}},
			{Name: "torch", Kind: &pb.Light_Spot{Spot: &pb.SpotLight{Position: v(2, 3, 2), Direction: v(0, -1, 0), Intensity: rgb(3, 3, 3),
				InnerConeDegrees: 20, OuterConeDegrees: 30}}},
		},
		Photons: &pb.PhotonMapping{
			GlobalPhotons: 20000, CausticPhotons: 10000, PhotonsPerShard: 5000,
			GlobalEstimate:  &pb.RadianceEstimate{Neighbours: 100, MaxRadius: 0.5, Filter: pb.Filter_FILTER_BOX, ConeK: 1.5},
			CausticEstimate: &pb.RadianceEstimate{Neighbours: 50, MaxRadius: 0.1, Filter: pb.Filter_FILTER_CONE, ConeK: 1.1},
		},
		Antialiasing: &pb.Antialiasing{Mode: pb.AntialiasingMode_ANTIALIASING_MODE_EDGES, EdgeSamples: 8, EdgeThreshold: 0.2},
		Indirect:     &pb.Indirect{Mode: pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER, GatherRays: 16, SecondaryGatherRays: 4},
		Progressive:  &pb.Progressive{MaxRounds: 2, TargetError: 0.01, TimeBudgetSeconds: 60, Alpha: 0.7},
		Meshes: []*pb.Mesh{{Name: "crate", Parts: []*pb.MeshPart{
			{Path: "cube.obj", Digest: rules.DigestOf([]byte(cubeOBJ)), Material: "white"},
			{Path: "cube.obj", Digest: rules.DigestOf([]byte(cubeOBJ)), Material: "shiny"},
		}}},
		Textures: []*pb.Texture{
			{Name: "wood", Path: "sky.hdr", Digest: rules.DigestOf([]byte(skyHDR)), Encoding: pb.ColorEncoding_COLOR_ENCODING_LINEAR, Wrap: pb.TextureWrap_TEXTURE_WRAP_CLAMP},
			{Name: "sky", Path: "sky.hdr", Digest: rules.DigestOf([]byte(skyHDR))},
		},
		Environment: &pb.Environment{Radiance: rgb(0.5, 0.5, 0.5), Map: &pb.TextureRef{Texture: "sky"}, RotationDegrees: 30},
		Output:      &pb.Output{ExposureStops: 0.5, ToneMap: pb.ToneMap_TONE_MAP_FILMIC},
	}
}

func v(x, y, z float64) *pb.Vec3    { return &pb.Vec3{X: x, Y: y, Z: z} }
func rgb(r, g, b float64) *pb.Color { return &pb.Color{R: r, G: g, B: b} }

// Accessors of base's parts.
func lambert(s *pb.Scene) *pb.Lambert       { return s.Materials[0].GetLambert() }
func emissive(s *pb.Scene) *pb.Emissive     { return s.Materials[1].GetEmissive() }
func glossy(s *pb.Scene) *pb.Glossy         { return s.Materials[2].GetGlossy() }
func mirror(s *pb.Scene) *pb.Mirror         { return s.Materials[3].GetMirror() }
func dielectric(s *pb.Scene) *pb.Dielectric { return s.Materials[4].GetDielectric() }
func conductor(s *pb.Scene) *pb.Conductor   { return s.Materials[5].GetConductor() }
func sphere(s *pb.Scene) *pb.Sphere         { return s.Shapes[0].GetSphere() }
func quad(s *pb.Scene) *pb.Quad             { return s.Shapes[1].GetQuad() }
func triangles(s *pb.Scene) *pb.TriangleMesh {
	return s.Shapes[3].GetTriangles()
}
func point(s *pb.Scene) *pb.PointLight { return s.Lights[0].GetPoint() }
func sun(s *pb.Scene) *pb.SunLight     { return s.Lights[1].GetSun() }
func spot(s *pb.Scene) *pb.SpotLight   { return s.Lights[2].GetSpot() }
func principled(s *pb.Scene) *pb.Principled {
	return s.Materials[6].GetPrincipled()
}
func crate(s *pb.Scene) *pb.Mesh   { return s.Meshes[0] }
func wood(s *pb.Scene) *pb.Texture { return s.Textures[0] }
func estimate(s *pb.Scene) *pb.RadianceEstimate {
	return s.Photons.GlobalEstimate
}

// withoutOtherLights leaves base with its point light and its lamp alone: no sun, no spot
// light and no environment.
func withoutOtherLights(s *pb.Scene) {
	s.Lights = s.Lights[:1]
	s.Environment = nil
}

// withoutSpecular removes base's specular shapes (the mirror, glass and gold balls), so
// that it gets no caustic map.
func withoutSpecular(s *pb.Scene) { s.Shapes = s.Shapes[:4] }

// cubeOBJ is a unit cube, the mesh file of the cases that need one; the generator writes
// it to tests/vectors/meshes/accept-cube.obj (an accepted mesh vector of its own).
const cubeOBJ = `# vector: accept
# A unit cube with corners (0, 0, 0) and (1, 1, 1): 8 vertices, 12 triangles, counter-clockwise
# seen from outside. Written by tests/vectors/scenes/gen for the scene vectors that name a mesh.
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3
f 1 3 2
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 4 8 7
f 4 7 3
f 1 5 8
f 1 8 4
f 2 3 7
f 2 7 6
`

// skyHDR is a 2x1 Radiance HDR image (flat scanlines: run-length encoding starts at 8
// pixels), the texture of base's textures: a blue and a white pixel.
const skyHDR = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n" +
	"\x40\x60\x80\x81" + "\x80\x80\x80\x81"

// An asset file the generator writes and the vectors name: where it is written, from the
// repository's root, and where the vectors find it, from their folder.
type asset struct {
	file, fromVectors, data string
}

var assetFiles = []asset{
	{"tests/vectors/meshes/accept-cube.obj", "../meshes/accept-cube.obj", cubeOBJ},
	{"tests/vectors/scenes/sky.hdr", "sky.hdr", skyHDR},
	{"tests/vectors/scenes/ramp.farmgrid", "ramp.farmgrid", rampGrid},
}

// withInstance appends a shape (shapes[7] of base) placing the crate, and returns its
// instance.
func withInstance(s *pb.Scene) *pb.MeshInstance {
	inst := &pb.MeshInstance{Mesh: "crate", Transform: &pb.Transform{Matrix: []float64{0, 0, 1, 2, 0, 1, 0, 0, -1, 0, 0, 1}}}
	s.Shapes = append(s.Shapes, &pb.Shape{Name: "crate-1", Geometry: &pb.Shape_Instance{Instance: inst}})
	return inst
}

// withMesh appends a shape (shapes[7] of base) made of the cube, uploaded, and returns its
// mesh file.
func withMesh(s *pb.Scene) *pb.MeshFile {
	m := &pb.MeshFile{Path: "cube.obj", Digest: rules.DigestOf([]byte(cubeOBJ)), Transform: &pb.Transform{
		Translation: v(0, 0, -2), Scale: v(0.5, 0.5, 0.5), RotationAxis: v(0, 1, 0), RotationDegrees: 30}}
	s.Shapes = append(s.Shapes, &pb.Shape{Name: "cube", Material: "white", Geometry: &pb.Shape_Mesh{Mesh: m}})
	return m
}
