package farmtest

import (
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// Furnace is the inside of a closed Lambert sphere of albedo 0.8 around a point light:
// every path stores about 0.8 / (1 - 0.8) = 4 photons (one at each diffuse bounce after
// the first), so paths photon paths fill a snapshot of about 4 · paths photons. A small
// ball outside keeps the global map in the plan (a lone sphere's surface cannot light
// itself, the planner's heuristic says); a few gather rays and neighbours keep the
// irradiance precompute over every stored photon short.
func Furnace(paths uint64) *pb.Scene {
	sc := scenetest.Valid(16, 16)
	sc.Camera = &pb.Camera{Position: scenetest.V(0, 0, 0), LookAt: scenetest.V(0, 0, 1), Up: scenetest.V(0, 1, 0), VerticalFovDegrees: 90}
	sc.Film.TileSize = 16
	sc.Materials = []*pb.Material{{Name: "wall", Kind: &pb.Material_Lambert{Lambert: &pb.Lambert{Reflectance: &pb.Color{R: 0.8, G: 0.8, B: 0.8}}}}}
	sc.Shapes = []*pb.Shape{
		{Name: "furnace", Material: "wall", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: scenetest.V(0, 0, 0), Radius: 1}}},
		{Name: "outside", Material: "wall", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: scenetest.V(5, 0, 0), Radius: 0.1}}},
	}
	sc.Lights = []*pb.Light{{Name: "centre", Kind: &pb.Light_Point{Point: &pb.PointLight{Position: scenetest.V(0, 0, 0), Intensity: &pb.Color{R: 1, G: 1, B: 1}}}}}
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: paths, PhotonsPerShard: 100_000, GlobalEstimate: &pb.RadianceEstimate{Neighbours: 8}}
	sc.Indirect = &pb.Indirect{GatherRays: 4, SecondaryGatherRays: 1}
	return sc
}
