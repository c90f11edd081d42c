package scene_test

import (
	"math"
	"testing"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

const goodDigest = "sha256:0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef"

func meshShape(m *pb.MeshFile) *pb.Shape {
	return &pb.Shape{Material: "white", Geometry: &pb.Shape_Mesh{Mesh: m}}
}

func TestValidateAcceptsValidScenes(t *testing.T) {
	tests := []variant{
		{"as built", func(*pb.Scene) {}},
		{"explicit tile size and spp", func(s *pb.Scene) {
			s.Film.TileSize = 8
			s.Sampling.SamplesPerPixel = uint32(rules.Max(&pb.Sampling{}, "samples_per_pixel"))
		}},
		{"no sampling message", func(s *pb.Scene) { s.Sampling = nil }},
		{"max film", func(s *pb.Scene) { s.Film.Width, s.Film.Height = uint32(rules.Max(&pb.Film{}, "width")), 1 }},
		{"triangles", func(s *pb.Scene) {
			s.Shapes = append(s.Shapes, &pb.Shape{Material: "white", Geometry: &pb.Shape_Triangles{Triangles: &pb.TriangleMesh{
				Positions: []*pb.Vec3{scenetest.V(0, 0, 0), scenetest.V(1, 0, 0), scenetest.V(0, 1, 0)}, Indices: []uint32{0, 1, 2}}}})
		}},
		{"mesh with digest and transform", func(s *pb.Scene) {
			s.Shapes = append(s.Shapes, meshShape(&pb.MeshFile{Path: "bunny.obj", Digest: goodDigest,
				Transform: &pb.Transform{Scale: scenetest.V(2, 2, -2), RotationAxis: scenetest.V(0, 1, 0), RotationDegrees: 90}}))
		}},
	}
	expectValid(t, tests)
}

func TestValidateRefusesNamingTheField(t *testing.T) {
	nan, inf := math.NaN(), math.Inf(1)
	tests := []refusal{
		{"no camera", func(s *pb.Scene) { s.Camera = nil }, "camera", "missing"},
		{"too many rounds", func(s *pb.Scene) { s.Progressive = &pb.Progressive{MaxRounds: 1001} }, "progressive.max_rounds", "<= 1000"},
		{"negative target", func(s *pb.Scene) { s.Progressive = &pb.Progressive{TargetError: -0.1} }, "progressive.target_error", ">= 0"},
		{"NaN target", func(s *pb.Scene) { s.Progressive = &pb.Progressive{TargetError: nan} }, "progressive.target_error", "finite"},
		{"budget over a week", func(s *pb.Scene) { s.Progressive = &pb.Progressive{TimeBudgetSeconds: 7*24*3600 + 1} }, "progressive.time_budget_seconds", "604800"},
		{"alpha above 1", func(s *pb.Scene) { s.Progressive = &pb.Progressive{Alpha: 1.5} }, "progressive.alpha", "(0, 1]"},
		{"negative alpha", func(s *pb.Scene) { s.Progressive = &pb.Progressive{Alpha: -0.5} }, "progressive.alpha", "(0, 1]"},
		{"reference path without digest", func(s *pb.Scene) {
			s.Progressive = &pb.Progressive{Reference: &pb.ReferenceImage{Path: "ref.exr"}}
		}, "progressive.reference.digest", "missing"},
		{"bad reference digest", func(s *pb.Scene) {
			s.Progressive = &pb.Progressive{Reference: &pb.ReferenceImage{Digest: "sha256:XYZ"}}
		}, "progressive.reference.digest", "64 lowercase hex"},
		{"too many gather rays", func(s *pb.Scene) { s.Indirect = &pb.Indirect{GatherRays: 4097} }, "indirect.gather_rays", "<= 4096"},
		{"too many secondary rays", func(s *pb.Scene) { s.Indirect = &pb.Indirect{SecondaryGatherRays: 5000} }, "indirect.secondary_gather_rays", "<= 4096"},
		{"unknown indirect mode", func(s *pb.Scene) { s.Indirect = &pb.Indirect{Mode: 9} }, "indirect.mode", "unknown"},
		{"too many edge samples", func(s *pb.Scene) { s.Antialiasing = &pb.Antialiasing{EdgeSamples: 1025} }, "antialiasing.edge_samples", "<= 1024"},
		{"negative edge threshold", func(s *pb.Scene) { s.Antialiasing = &pb.Antialiasing{EdgeThreshold: -1} }, "antialiasing.edge_threshold", ">= 0"},
		{"infinite edge threshold", func(s *pb.Scene) { s.Antialiasing = &pb.Antialiasing{EdgeThreshold: inf} }, "antialiasing.edge_threshold", "finite"},
		{"unknown antialiasing mode", func(s *pb.Scene) { s.Antialiasing = &pb.Antialiasing{Mode: 7} }, "antialiasing.mode", "unknown"},
		{"too many light samples", func(s *pb.Scene) { s.Sampling.LightSamples = 1025 }, "sampling.light_samples", "<= 1024"},

		{"no look_at", func(s *pb.Scene) { s.Camera.LookAt = nil }, "camera.look_at", "missing"},
		{"NaN position", func(s *pb.Scene) { s.Camera.Position.Y = nan }, "camera.position.y", "finite"},
		{"Inf up", func(s *pb.Scene) { s.Camera.Up.Z = inf }, "camera.up.z", "finite"},
		{"look_at == position", func(s *pb.Scene) { s.Camera.LookAt = scenetest.V(0, 1, 5) }, "camera.look_at", "must differ"},
		{"up parallel to view", func(s *pb.Scene) { s.Camera.Up = scenetest.V(0, 0, -3) }, "camera.up", "parallel"},
		{"zero up", func(s *pb.Scene) { s.Camera.Up = scenetest.V(0, 0, 0) }, "camera.up", "non-zero"},
		{"fov 0", func(s *pb.Scene) { s.Camera.VerticalFovDegrees = 0 }, "camera.vertical_fov_degrees", "(0, 180), got 0"},
		{"fov 180", func(s *pb.Scene) { s.Camera.VerticalFovDegrees = 180 }, "camera.vertical_fov_degrees", "got 180"},
		{"fov NaN", func(s *pb.Scene) { s.Camera.VerticalFovDegrees = nan }, "camera.vertical_fov_degrees", "finite"},
		{"no film", func(s *pb.Scene) { s.Film = nil }, "film", "missing"},
		{"width 0", func(s *pb.Scene) { s.Film.Width = 0 }, "film.width", "[1, 16384], got 0"},
		{"height too big", func(s *pb.Scene) { s.Film.Height = 16385 }, "film.height", "got 16385"},
		{"tile too small", func(s *pb.Scene) { s.Film.TileSize = 4 }, "film.tile_size", "got 4"},
		{"tile too big", func(s *pb.Scene) { s.Film.TileSize = 257 }, "film.tile_size", "got 257"},
		{"spp too many", func(s *pb.Scene) { s.Sampling.SamplesPerPixel = 65537 }, "sampling.samples_per_pixel", "<= 65536"},
		{"material no name", func(s *pb.Scene) { s.Materials[0].Name = "" }, "materials[0].name", "missing"},
		{"material duplicate", func(s *pb.Scene) { s.Materials[1].Name = "white" }, "materials[1].name", "duplicate material name \"white\" (also materials[0])"},
		{"material no kind", func(s *pb.Scene) { s.Materials[0].Kind = nil }, "materials[0]", "exactly one of lambert, emissive, glossy, mirror, dielectric, conductor, principled must be set"},
		{"reflectance > 1", func(s *pb.Scene) { s.Materials[0].GetLambert().Reflectance.G = 1.5 }, "materials[0].lambert.reflectance.g", "[0, 1], got 1.5"},
		{"reflectance < 0", func(s *pb.Scene) { s.Materials[0].GetLambert().Reflectance.R = -0.1 }, "materials[0].lambert.reflectance.r", "[0, 1], got -0.1"},
		{"reflectance missing", func(s *pb.Scene) { s.Materials[0].GetLambert().Reflectance = nil }, "materials[0].lambert.reflectance", "missing"},
		{"radiance negative", func(s *pb.Scene) { s.Materials[1].GetEmissive().Radiance.B = -1 }, "materials[1].emissive.radiance.b", ">= 0"},
		{"radiance Inf", func(s *pb.Scene) { s.Materials[1].GetEmissive().Radiance.R = inf }, "materials[1].emissive.radiance.r", "finite"},
		{"unknown material", func(s *pb.Scene) { s.Shapes[1].Material = "chrome" }, "shapes[1].material", `"chrome"`},
		{"empty material", func(s *pb.Scene) { s.Shapes[1].Material = "" }, "shapes[1].material", "missing"},
		{"no geometry", func(s *pb.Scene) { s.Shapes[0].Geometry = nil }, "shapes[0]", "exactly one of sphere, quad, triangles, mesh, instance must be set"},
		{"negative radius", func(s *pb.Scene) { s.Shapes[0].GetSphere().Radius = -1 }, "shapes[0].sphere.radius", "must be > 0, got -1"},
		{"NaN center", func(s *pb.Scene) { s.Shapes[0].GetSphere().Center.X = nan }, "shapes[0].sphere.center.x", "finite"},
		{"zero quad edge", func(s *pb.Scene) { s.Shapes[1].GetQuad().EdgeU = scenetest.V(0, 0, 0) }, "shapes[1].quad.edge_u", "non-zero"},
		{"parallel quad edges", func(s *pb.Scene) { s.Shapes[1].GetQuad().EdgeV = scenetest.V(-2, 0, 0) }, "shapes[1].quad.edge_v", "parallel"},
		{"indices not multiple of 3", func(s *pb.Scene) {
			s.Shapes[0].Geometry = &pb.Shape_Triangles{Triangles: &pb.TriangleMesh{
				Positions: []*pb.Vec3{scenetest.V(0, 0, 0), scenetest.V(1, 0, 0), scenetest.V(0, 1, 0)}, Indices: []uint32{0, 1}}}
		}, "shapes[0].triangles.indices", "multiple of 3"},
		{"index out of range", func(s *pb.Scene) {
			s.Shapes[0].Geometry = &pb.Shape_Triangles{Triangles: &pb.TriangleMesh{
				Positions: []*pb.Vec3{scenetest.V(0, 0, 0), scenetest.V(1, 0, 0), scenetest.V(0, 1, 0)}, Indices: []uint32{0, 1, 3}}}
		}, "shapes[0].triangles.indices[2]", "must be < 3"},
		{"too many positions", func(s *pb.Scene) {
			s.Shapes[0].Geometry = &pb.Shape_Triangles{Triangles: &pb.TriangleMesh{
				Positions: make([]*pb.Vec3, 1000001), Indices: []uint32{0, 1, 2}}}
		}, "shapes[0].triangles.positions", "must have at most 1000000 entries, got 1000001"},
		{"mesh path without digest", func(s *pb.Scene) { s.Shapes = append(s.Shapes, meshShape(&pb.MeshFile{Path: "bunny.obj"})) },
			"shapes[3].mesh.digest", "missing; clients upload the file named by path and set its digest"},
		{"an earlier fault before a mesh not uploaded", func(s *pb.Scene) {
			s.Shapes[2].GetQuad().Origin = nil
			s.Shapes = append(s.Shapes, meshShape(&pb.MeshFile{Path: "bunny.obj"}))
		}, "shapes[2].quad.origin", "missing"},
		{"mesh bad digest", func(s *pb.Scene) { s.Shapes = append(s.Shapes, meshShape(&pb.MeshFile{Digest: "sha256:ABC"})) },
			"shapes[3].mesh.digest", "64 lowercase hex"},
		{"mesh zero scale", func(s *pb.Scene) {
			s.Shapes = append(s.Shapes, meshShape(&pb.MeshFile{Digest: goodDigest, Transform: &pb.Transform{Scale: scenetest.V(1, 0, 1)}}))
		}, "shapes[3].mesh.transform.scale.y", "non-zero"},
		{"no light", func(s *pb.Scene) { s.Shapes = s.Shapes[:2] }, "lights", "emissive"},
		{"black light", func(s *pb.Scene) { s.Materials[1].GetEmissive().Radiance = &pb.Color{} }, "lights", "emissive"},
	}
	expectRefused(t, tests)
}

func TestDefaults(t *testing.T) {
	s := scenetest.Valid(10, 10)
	s.Sampling = nil
	d := scene.Defaults(s)
	if d.Film.TileSize != 32 || d.Sampling.SamplesPerPixel != 1 || d.Sampling.LightSamples != 16 {
		t.Errorf("Defaults: tile %d spp %d light samples %d, want 32, 1 and 16", d.Film.TileSize, d.Sampling.SamplesPerPixel, d.Sampling.LightSamples)
	}
	if d.GetIndirect().GetMode() != pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER || d.GetIndirect().GetGatherRays() != 64 ||
		d.GetIndirect().GetSecondaryGatherRays() != 8 {
		t.Errorf("Defaults: indirect %v, want final gathering with 64 and 8 rays", d.GetIndirect())
	}
	if a := d.GetAntialiasing(); a.GetMode() != pb.AntialiasingMode_ANTIALIASING_MODE_EDGES || a.GetEdgeSamples() != 32 || a.GetEdgeThreshold() != 0.1 {
		t.Errorf("Defaults: antialiasing %v, want EDGES, 12 samples, threshold 0.1", a)
	}
	if p := d.GetProgressive(); p.GetMaxRounds() != 1 || p.GetAlpha() != 0.7 || p.GetReference() != nil {
		t.Errorf("Defaults: progressive %v, want 1 round, alpha 0.7, no reference", p)
	}
	if ph := d.GetPhotons(); ph.GetGlobalPhotons() != 200000 || ph.GetCausticPhotons() != 200000 || ph.GetPhotonsPerShard() != 100000 {
		t.Errorf("Defaults: photons %v, want 200000, 200000 and 100000 per shard", ph)
	}
	if s.Sampling != nil || s.Film.TileSize != 0 || s.Photons != nil {
		t.Error("Defaults modified its argument")
	}
	s.Film.TileSize = 64
	if got := scene.Defaults(s).Film.TileSize; got != 64 {
		t.Errorf("Defaults overrode an explicit tile size: %d", got)
	}
	s.Photons = &pb.PhotonMapping{GlobalPhotons: 5000, PhotonsPerShard: 1000}
	if ph := scene.Defaults(s).Photons; ph.GlobalPhotons != 5000 || ph.CausticPhotons != 200000 || ph.PhotonsPerShard != 1000 {
		t.Errorf("Defaults with explicit photon counts: %v", ph)
	}
}

// TestEffectiveValuesAreTheDefaults checks each getter of an effective value against the
// field Defaults fills in, on a scene that sets none of them and on one that sets all.
func TestEffectiveValuesAreTheDefaults(t *testing.T) {
	unset := scenetest.Valid(10, 10)
	set := scenetest.Valid(10, 10)
	set.Film.TileSize = 8
	set.Sampling = &pb.Sampling{SamplesPerPixel: 3, LightSamples: 5}
	set.Photons = &pb.PhotonMapping{GlobalPhotons: 7, CausticPhotons: 9, PhotonsPerShard: 1000}
	set.Antialiasing = &pb.Antialiasing{Mode: pb.AntialiasingMode_ANTIALIASING_MODE_FULL, EdgeSamples: 2, EdgeThreshold: 0.5}
	set.Indirect = &pb.Indirect{Mode: pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP, GatherRays: 4, SecondaryGatherRays: 6}
	set.Progressive = &pb.Progressive{MaxRounds: 11, Alpha: 0.25}
	for name, s := range map[string]*pb.Scene{"unset": unset, "set": set} {
		d := scene.Defaults(s)
		got := []any{scene.TileSize(s), scene.SamplesPerPixel(s), scene.LightSamples(s), scene.GlobalPhotons(s), scene.CausticPhotons(s),
			scene.PhotonsPerShard(s), scene.AntialiasingMode(s), scene.EdgeSamples(s), scene.EdgeThreshold(s), scene.IndirectMode(s),
			scene.GatherRays(s), scene.SecondaryGatherRays(s), scene.Rounds(s), scene.Alpha(s)}
		want := []any{d.Film.TileSize, d.Sampling.SamplesPerPixel, d.Sampling.LightSamples, d.Photons.GlobalPhotons, d.Photons.CausticPhotons,
			d.Photons.PhotonsPerShard, d.Antialiasing.Mode, d.Antialiasing.EdgeSamples, d.Antialiasing.EdgeThreshold, d.Indirect.Mode,
			d.Indirect.GatherRays, d.Indirect.SecondaryGatherRays, d.Progressive.MaxRounds, d.Progressive.Alpha}
		for i := range got {
			if got[i] != want[i] {
				t.Errorf("%s: getter %d = %v, Defaults says %v", name, i, got[i], want[i])
			}
		}
		if scene.FinalGather(s) != (d.Indirect.Mode == pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER) {
			t.Errorf("%s: FinalGather = %v with mode %v", name, scene.FinalGather(s), d.Indirect.Mode)
		}
	}
}

func TestDefaultsDropsAReferenceWithoutDigest(t *testing.T) {
	s := scenetest.Valid(10, 10)
	s.Progressive = &pb.Progressive{Reference: &pb.ReferenceImage{}}
	if r := scene.Defaults(s).GetProgressive().GetReference(); r != nil {
		t.Errorf("reference without digest kept: %v", r)
	}
	s.Progressive.Reference = &pb.ReferenceImage{Path: "ref.exr", Digest: goodDigest}
	if r := scene.Defaults(s).GetProgressive().GetReference(); r.GetDigest() != goodDigest || r.GetPath() != "ref.exr" {
		t.Errorf("reference = %v, want it kept as given", r)
	}
}
