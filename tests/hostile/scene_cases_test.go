package hostile

import (
	"math"
	"strings"

	"google.golang.org/grpc/codes"
	"google.golang.org/protobuf/proto"

	"photonfarm/coordinator/coordinatortest"
	pb "photonfarm/proto/renderfarm/v1"
)

// sceneCases break a valid scene (scenes/test-small.json: shapes floor quad, two spheres,
// an OBJ mesh and a lamp quad; materials white, red, blue and lamp) one way each; every
// one must be refused with INVALID_ARGUMENT naming the field.
func sceneCases(f *farm) []hostileCase {
	nan, inf := math.NaN(), math.Inf(1)
	type mutation struct {
		name   string
		mutate func(s *pb.Scene)
		want   string
	}
	mutations := []mutation{
		{"no camera", func(s *pb.Scene) { s.Camera = nil }, "camera"},
		{"camera position NaN", func(s *pb.Scene) { s.Camera.Position.X = nan }, "camera.position"},
		{"camera position infinite", func(s *pb.Scene) { s.Camera.Position.Y = inf }, "camera.position"},
		{"camera position huge", func(s *pb.Scene) { s.Camera.Position.Z = 1e300 }, "camera.position"},
		{"camera looks at itself", func(s *pb.Scene) { s.Camera.LookAt = proto.Clone(s.Camera.Position).(*pb.Vec3) }, "camera.look_at"},
		{"camera up zero", func(s *pb.Scene) { s.Camera.Up = &pb.Vec3{} }, "camera.up"},
		{"camera fov 0", func(s *pb.Scene) { s.Camera.VerticalFovDegrees = 0 }, "camera.vertical_fov_degrees"},
		{"camera fov 180", func(s *pb.Scene) { s.Camera.VerticalFovDegrees = 180 }, "camera.vertical_fov_degrees"},
		{"camera fov NaN", func(s *pb.Scene) { s.Camera.VerticalFovDegrees = nan }, "camera.vertical_fov_degrees"},
		{"no film", func(s *pb.Scene) { s.Film = nil }, "film"},
		{"film width 0", func(s *pb.Scene) { s.Film.Width = 0 }, "film.width"},
		{"film height absurd", func(s *pb.Scene) { s.Film.Height = 1 << 31 }, "film.height"},
		{"film width past limit", func(s *pb.Scene) { s.Film.Width = 16385 }, "film.width"},
		{"tile size 3", func(s *pb.Scene) { s.Film.TileSize = 3 }, "film.tile_size"},
		{"tile size huge", func(s *pb.Scene) { s.Film.TileSize = 1 << 20 }, "film.tile_size"},
		{"samples per pixel absurd", func(s *pb.Scene) { s.Sampling.SamplesPerPixel = 1 << 30 }, "sampling.samples_per_pixel"},
		{"light samples absurd", func(s *pb.Scene) { s.Sampling.LightSamples = 1 << 20 }, "sampling.light_samples"},
		{"name too long", func(s *pb.Scene) { s.Name = strings.Repeat("n", 300) }, "name"},
		{"no materials", func(s *pb.Scene) { s.Materials = nil }, "material"},
		{"duplicate material", func(s *pb.Scene) { s.Materials[1].Name = "white" }, "materials[1].name"},
		{"material without kind", func(s *pb.Scene) { s.Materials[0].Kind = nil }, "materials[0]"},
		{"reflectance above 1", func(s *pb.Scene) { s.Materials[0].GetLambert().Reflectance.R = 1.5 }, "materials[0].lambert.reflectance"},
		{"reflectance negative", func(s *pb.Scene) { s.Materials[1].GetLambert().Reflectance.G = -0.1 }, "materials[1].lambert.reflectance"},
		{"reflectance NaN", func(s *pb.Scene) { s.Materials[2].GetLambert().Reflectance.B = nan }, "materials[2].lambert.reflectance"},
		{"radiance infinite", func(s *pb.Scene) { s.Materials[3].GetEmissive().Radiance.R = inf }, "materials[3].emissive.radiance"},
		{"radiance negative", func(s *pb.Scene) { s.Materials[3].GetEmissive().Radiance.G = -1 }, "materials[3].emissive.radiance"},
		{"ior below 1", func(s *pb.Scene) {
			s.Materials[0].Kind = &pb.Material_Dielectric{Dielectric: &pb.Dielectric{Ior: 0.5}}
		}, "materials[0].dielectric.ior"},
		{"ior absurd", func(s *pb.Scene) {
			s.Materials[0].Kind = &pb.Material_Dielectric{Dielectric: &pb.Dielectric{Ior: 1e9}}
		}, "materials[0].dielectric.ior"},
		{"glossy over unity", func(s *pb.Scene) {
			s.Materials[0].Kind = &pb.Material_Glossy{Glossy: &pb.Glossy{Diffuse: &pb.Color{R: 0.8, G: 0.8, B: 0.8},
				Specular: &pb.Color{R: 0.5, G: 0.5, B: 0.5}, Exponent: 10}}
		}, "materials[0].glossy"},
		{"glossy exponent 0", func(s *pb.Scene) {
			s.Materials[0].Kind = &pb.Material_Glossy{Glossy: &pb.Glossy{Diffuse: &pb.Color{R: 0.2}, Specular: &pb.Color{R: 0.2}}}
		}, "materials[0].glossy.exponent"},
		{"no shapes and no lights", func(s *pb.Scene) { s.Shapes = nil }, "lights"},
		{"shape with unknown material", func(s *pb.Scene) { s.Shapes[0].Material = "unobtainium" }, "shapes[0].material"},
		{"shape without geometry", func(s *pb.Scene) { s.Shapes[1].Geometry = nil }, "shapes[1]"},
		{"sphere radius negative", func(s *pb.Scene) { s.Shapes[1].GetSphere().Radius = -1 }, "shapes[1].sphere.radius"},
		{"sphere radius zero", func(s *pb.Scene) { s.Shapes[2].GetSphere().Radius = 0 }, "shapes[2].sphere.radius"},
		{"sphere radius NaN", func(s *pb.Scene) { s.Shapes[2].GetSphere().Radius = nan }, "shapes[2].sphere.radius"},
		{"sphere centre missing", func(s *pb.Scene) { s.Shapes[1].GetSphere().Center = nil }, "shapes[1].sphere.center"},
		{"quad edge zero", func(s *pb.Scene) { s.Shapes[0].GetQuad().EdgeU = &pb.Vec3{} }, "shapes[0].quad"},
		{"quad edges parallel", func(s *pb.Scene) {
			q := s.Shapes[0].GetQuad()
			q.EdgeV = &pb.Vec3{X: 2 * q.EdgeU.X, Y: 2 * q.EdgeU.Y, Z: 2 * q.EdgeU.Z}
		}, "shapes[0].quad"},
		{"quad origin infinite", func(s *pb.Scene) { s.Shapes[4].GetQuad().Origin.X = -inf }, "shapes[4].quad.origin"},
		{"mesh digest missing", func(s *pb.Scene) { s.Shapes[3].GetMesh().Digest = "" }, "shapes[3].mesh.digest"},
		{"mesh digest malformed", func(s *pb.Scene) { s.Shapes[3].GetMesh().Digest = "md5:abc" }, "shapes[3].mesh.digest"},
		{"mesh digest not uploaded", func(s *pb.Scene) {
			s.Shapes[3].GetMesh().Digest = "sha256:" + strings.Repeat("0", 64)
		}, "shapes[3].mesh.digest"},
		{"mesh scale zero", func(s *pb.Scene) { s.Shapes[3].GetMesh().Transform.Scale = &pb.Vec3{X: 1, Y: 0, Z: 1} }, "shapes[3].mesh.transform.scale"},
		{"triangles index out of range", func(s *pb.Scene) {
			s.Shapes[0].Geometry = &pb.Shape_Triangles{Triangles: &pb.TriangleMesh{
				Positions: []*pb.Vec3{{}, {X: 1}, {Y: 1}}, Indices: []uint32{0, 1, 7}}}
		}, "shapes[0].triangles.indices"},
		{"triangles indices not in threes", func(s *pb.Scene) {
			s.Shapes[0].Geometry = &pb.Shape_Triangles{Triangles: &pb.TriangleMesh{
				Positions: []*pb.Vec3{{}, {X: 1}, {Y: 1}}, Indices: []uint32{0, 1}}}
		}, "shapes[0].triangles.indices"},
		{"triangles too few positions", func(s *pb.Scene) {
			s.Shapes[0].Geometry = &pb.Shape_Triangles{Triangles: &pb.TriangleMesh{Positions: []*pb.Vec3{{}}, Indices: []uint32{0, 0, 0}}}
		}, "shapes[0].triangles.positions"},
		{"point light without position", func(s *pb.Scene) {
			s.Lights = []*pb.Light{{Kind: &pb.Light_Point{Point: &pb.PointLight{Intensity: &pb.Color{R: 1}}}}}
		}, "lights[0].point.position"},
		{"sun light direction zero", func(s *pb.Scene) {
			s.Lights = []*pb.Light{{Kind: &pb.Light_Sun{Sun: &pb.SunLight{Direction: &pb.Vec3{}, Irradiance: &pb.Color{R: 1}}}}}
		}, "lights[0].sun.direction"},
		{"light without kind", func(s *pb.Scene) { s.Lights = []*pb.Light{{Name: "nothing"}} }, "lights[0]"},
		{"photons past the limit", func(s *pb.Scene) { s.Photons = &pb.PhotonMapping{GlobalPhotons: 1 << 40} }, "photons.global_photons"},
		{"photons per shard past the limit", func(s *pb.Scene) { s.Photons = &pb.PhotonMapping{PhotonsPerShard: 1 << 40} }, "photons.photons_per_shard"},
		{"gather rays absurd", func(s *pb.Scene) { s.Indirect = &pb.Indirect{GatherRays: 1 << 20} }, "indirect.gather_rays"},
		{"unknown indirect mode", func(s *pb.Scene) { s.Indirect = &pb.Indirect{Mode: 99} }, "indirect.mode"},
		{"unknown antialiasing mode", func(s *pb.Scene) { s.Antialiasing = &pb.Antialiasing{Mode: 42} }, "antialiasing.mode"},
		{"edge threshold NaN", func(s *pb.Scene) { s.Antialiasing = &pb.Antialiasing{EdgeThreshold: nan} }, "antialiasing.edge_threshold"},
		{"rounds absurd", func(s *pb.Scene) { s.Progressive = &pb.Progressive{MaxRounds: 1 << 20} }, "progressive.max_rounds"},
		{"time budget negative", func(s *pb.Scene) { s.Progressive = &pb.Progressive{TimeBudgetSeconds: -5} }, "progressive.time_budget_seconds"},
		{"alpha above 1", func(s *pb.Scene) { s.Progressive = &pb.Progressive{Alpha: 1.5} }, "progressive.alpha"},
		{"reference not uploaded", func(s *pb.Scene) {
			s.Progressive = &pb.Progressive{Reference: &pb.ReferenceImage{Digest: "sha256:" + strings.Repeat("a", 64)}}
		}, "progressive.reference.digest"},
	}
	// broken is the farm's valid scene with mutate applied to a copy.
	broken := func(mutate func(s *pb.Scene)) *pb.Scene {
		s := proto.Clone(f.scene).(*pb.Scene)
		mutate(s)
		return s
	}
	var cases []hostileCase
	for _, m := range mutations {
		cases = append(cases, hostileCase{
			name: "scene: " + m.name,
			call: coordinatortest.Call(f.jobs.SubmitJob, &pb.SubmitJobRequest{Scene: broken(m.mutate)}),
			code: codes.InvalidArgument,
			want: m.want,
		})
	}
	return append(cases,
		hostileCase{"scene: missing", coordinatortest.Call(f.jobs.SubmitJob, &pb.SubmitJobRequest{}), codes.InvalidArgument, "scene"},
		hostileCase{"plan: broken scene", coordinatortest.Call(f.jobs.PlanScene,
			&pb.PlanSceneRequest{Scene: broken(func(s *pb.Scene) { s.Film.Width = 0 })}), codes.InvalidArgument, "film.width"},
	)
}
