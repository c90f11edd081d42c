// Package scenetest builds small valid scenes for tests.
package scenetest

import pb "photonfarm/proto/renderfarm/v1"

// V returns a Vec3.
func V(x, y, z float64) *pb.Vec3 { return &pb.Vec3{X: x, Y: y, Z: z} }

// Valid returns a valid scene: a white sphere on a grey floor lit by a quad light, rendered
// at width x height with the default tile size and sampling.
func Valid(width, height uint32) *pb.Scene {
	return &pb.Scene{
		Name: "sphere-and-light",
		Camera: &pb.Camera{
			Position:           V(0, 1, 5),
			LookAt:             V(0, 1, 0),
			Up:                 V(0, 1, 0),
			VerticalFovDegrees: 40,
		},
		Film:     &pb.Film{Width: width, Height: height},
		Sampling: &pb.Sampling{Seed: 7},
		Materials: []*pb.Material{
			{Name: "white", Kind: &pb.Material_Lambert{Lambert: &pb.Lambert{Reflectance: &pb.Color{R: 0.8, G: 0.8, B: 0.8}}}},
			{Name: "light", Kind: &pb.Material_Emissive{Emissive: &pb.Emissive{Radiance: &pb.Color{R: 10, G: 10, B: 10}}}},
		},
		Shapes: []*pb.Shape{
			{Name: "ball", Material: "white", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: V(0, 1, 0), Radius: 1}}},
			{Name: "floor", Material: "white", Geometry: &pb.Shape_Quad{Quad: &pb.Quad{Origin: V(-5, 0, 5), EdgeU: V(10, 0, 0), EdgeV: V(0, 0, -10)}}},
			{Name: "lamp", Material: "light", Geometry: &pb.Shape_Quad{Quad: &pb.Quad{Origin: V(-0.5, 3, 0.5), EdgeU: V(0, 0, -1), EdgeV: V(1, 0, 0)}}},
		},
	}
}

// Unlit returns Valid with the ball and the floor made of a black emissive material, so
// that no surface reflects and the job needs no photon maps: its plan is render tiles and
// a composite only.
func Unlit(width, height uint32) *pb.Scene {
	s := Valid(width, height)
	s.Materials = append(s.Materials, &pb.Material{Name: "black", Kind: &pb.Material_Emissive{Emissive: &pb.Emissive{Radiance: &pb.Color{}}}})
	s.Shapes[0].Material, s.Shapes[1].Material = "black", "black"
	return s
}
