package rules_test

import (
	"math"
	"strings"
	"testing"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

func rgb(r, g, b float64) *pb.Color { return &pb.Color{R: r, G: g, B: b} }

func digestOf(c byte) string { return "sha256:" + strings.Repeat(string(c), 64) }

// TestCheckEachKindAndBound checks one message per case against the rule its field
// declares in scene.proto (or, for the map and the optional fields, none): the error, in
// full, or none.
func TestCheckEachKindAndBound(t *testing.T) {
	nan, inf := math.NaN(), math.Inf(1)
	long := strings.Repeat("x", 257)
	tests := []struct {
		name string
		msg  proto.Message
		want string // "" when Check must accept
	}{
		// Doubles: finite and within max_magnitude whatever the rule, then the bounds.
		{"NaN", &pb.Camera{Position: scenetest.V(nan, 0, 0)}, "position.x: must be a finite number, got NaN"},
		{"+Inf", &pb.Sphere{Center: scenetest.V(0, 0, 0), Radius: inf}, "radius: must be a finite number, got +Inf"},
		{"-Inf", &pb.Sphere{Center: scenetest.V(0, 0, -inf), Radius: 1}, "center.z: must be a finite number, got -Inf"},
		{"magnitude past max_magnitude", &pb.Sphere{Center: scenetest.V(0, -2e12, 0), Radius: 1}, "center.y: must be within ±1e+12, got -2e+12"},
		{"magnitude at max_magnitude", &pb.Sphere{Center: scenetest.V(1e12, -1e12, 0), Radius: 1e12}, ""},
		{"gt hit exactly", &pb.Sphere{Center: scenetest.V(0, 0, 0), Radius: 0}, "radius: must be > 0, got 0"},
		{"gt passed", &pb.Sphere{Center: scenetest.V(0, 0, 0), Radius: 1e-300}, ""},
		{"gt and lt: lt hit exactly", &pb.Camera{Position: scenetest.V(0, 0, 0), LookAt: scenetest.V(0, 0, 1), Up: scenetest.V(0, 1, 0), VerticalFovDegrees: 180},
			"vertical_fov_degrees: must be in (0, 180), got 180"},
		{"gte and lte: below", &pb.Glossy{Diffuse: rgb(0, 0, 0), Specular: rgb(0, 0, 0), Exponent: 0.5}, "exponent: must be in [1, 100000], got 0.5"},
		{"gte and lte: both hit", &pb.Dielectric{Ior: 10}, ""},
		{"gte and lte: above", &pb.Dielectric{Ior: 10.5}, "ior: must be in [1, 10], got 10.5"},
		{"gte only", &pb.Progressive{TargetError: -0.25}, "target_error: must be >= 0, got -0.25"},
		{"default: 0 passes bounds that exclude it", &pb.Progressive{Alpha: 0}, ""},
		{"default: named in the error", &pb.Progressive{Alpha: -0.5}, "alpha: must be in (0, 1] (0 selects 0.7), got -0.5"},
		// Integers: bounds only, shown as integers.
		{"uint32 below gte", &pb.Film{Width: 0, Height: 1}, "width: must be in [1, 16384], got 0"},
		{"uint32 default and bounds", &pb.Film{Width: 1, Height: 1, TileSize: 7}, "tile_size: must be in [8, 256] (0 selects 32), got 7"},
		{"uint32 default: 0 passes", &pb.Film{Width: 16384, Height: 16384, TileSize: 0}, ""},
		{"uint64 lte", &pb.PhotonMapping{GlobalPhotons: 200000001}, "global_photons: must be <= 200000000 (0 selects 200000), got 200000001"},
		{"uint64 far past lte", &pb.PhotonMapping{CausticPhotons: math.MaxUint64}, "caustic_photons: must be <= 200000000 (0 selects 200000), got 18446744073709551615"},
		// Colour and vector components inherit the bounds of the field that holds them.
		{"component above inherited lte", &pb.Lambert{Reflectance: rgb(0.5, 1.5, 0)}, "reflectance.g: must be in [0, 1], got 1.5"},
		{"component below inherited gte", &pb.Emissive{Radiance: rgb(1, 1, -1)}, "radiance.b: must be >= 0, got -1"},
		{"component at inherited gt", &pb.Conductor{Eta: rgb(1, 0, 1), K: rgb(0, 0, 0)}, "eta.g: must be in (0, 100], got 0"},
		{"unbounded vector components", &pb.PointLight{Position: scenetest.V(-5, 0, 1e9), Intensity: rgb(0, 0, 0)}, ""},
		// Messages.
		{"required message missing", &pb.Lambert{}, "reflectance: missing"},
		{"optional message unset", &pb.Dielectric{Ior: 1.5}, ""},
		{"optional message set and checked", &pb.Dielectric{Ior: 1.5, Transmittance: rgb(0, 2, 0)}, "transmittance.g: must be in [0, 1], got 2"},
		// Strings.
		{"required string empty", &pb.Material{Kind: &pb.Material_Lambert{Lambert: &pb.Lambert{Reflectance: rgb(0, 0, 0)}}}, "name: missing"},
		{"max_bytes exceeded", &pb.Light{Name: long, Kind: &pb.Light_Sun{}}, "name: must be at most 256 bytes, got 257"},
		{"max_bytes hit", &pb.Shape{Name: long[:256], Material: "m", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: scenetest.V(0, 0, 0), Radius: 1}}}, ""},
		{"digest empty and not required", &pb.ReferenceImage{}, ""},
		{"digest well formed", &pb.ReferenceImage{Digest: digestOf('a')}, ""},
		{"digest upper case", &pb.ReferenceImage{Digest: digestOf('A')}, `digest: must be "sha256:" followed by 64 lowercase hex digits, got "sha256:` + strings.Repeat("A", 64) + `"`},
		{"digest echoed truncated", &pb.MeshFile{Digest: strings.Repeat("z", 100)}, `digest: must be "sha256:" followed by 64 lowercase hex digits, got "` + strings.Repeat("z", 80) + `…"`},
		{"required digest missing", &pb.MeshFile{Path: "a.obj"}, "digest: missing"},
		// Enums: a declared value.
		{"enum undeclared", &pb.Antialiasing{Mode: 7}, "mode: unknown AntialiasingMode value 7"},
		{"enum declared", &pb.RadianceEstimate{Filter: pb.Filter_FILTER_GAUSSIAN}, ""},
		// Lists: max_items, then min_items, then each element at path[i].
		{"min_items", &pb.TriangleMesh{Positions: []*pb.Vec3{scenetest.V(0, 0, 0), scenetest.V(1, 0, 0)}}, "positions: must have at least 3 entries, got 2"},
		{"list element", &pb.TriangleMesh{Positions: []*pb.Vec3{scenetest.V(0, 0, 0), scenetest.V(1, nan, 0), scenetest.V(0, 1, 0)}}, "positions[1].y: must be a finite number, got NaN"},
		{"max_items", &pb.TriangleMesh{Positions: []*pb.Vec3{scenetest.V(0, 0, 0), scenetest.V(1, 0, 0), scenetest.V(0, 1, 0)}, Indices: make([]uint32, 3000001)},
			"indices: must have at most 3000000 entries, got 3000001"},
		// Oneofs: only the set member is checked; a required oneof with none set is an error
		// at the message's own path.
		{"one_required unset", &pb.Scene{Camera: &pb.Camera{Position: scenetest.V(0, 0, 0), LookAt: scenetest.V(0, 0, 0), Up: scenetest.V(0, 0, 0), VerticalFovDegrees: 1},
			Film: &pb.Film{Width: 1, Height: 1}, Lights: []*pb.Light{{Name: "l"}}}, "lights[0]: exactly one of point, sun, spot must be set"},
		{"set member checked", &pb.Light{Kind: &pb.Light_Point{Point: &pb.PointLight{Position: scenetest.V(0, 0, 0)}}}, "point.intensity: missing"},
		// Maps and proto3 optional fields (rules.proto: every double finite).
		{"map value", &pb.RoundMetrics{LayerReferenceRmse: map[string]float64{"direct": 0.5, "caustic": nan}}, "layer_reference_rmse[caustic]: must be a finite number, got NaN"},
		// Maps with keys: no other key; the entries in key order, so that the first error is
		// the worker's too.
		{"map key not declared", &pb.RoundMetrics{LayerReferenceRmse: map[string]float64{"direct": 0.5, "albedo": 0.1}},
			"layer_reference_rmse[albedo]: is not a key it may have (direct, indirect, caustic, volume)"},
		{"map entries in key order", &pb.RoundMetrics{LayerReferenceRmse: map[string]float64{"volume": nan, "bias": 0.1, "caustic": inf}},
			"layer_reference_rmse[bias]: is not a key it may have (direct, indirect, caustic, volume)"},
		{"map keys declared", &pb.RoundMetrics{LayerReferenceRmse: map[string]float64{"direct": 0.5, "indirect": 0.1, "caustic": 0, "volume": 2}}, ""},
		{"optional double unset", &pb.RoundMetrics{}, ""},
		{"optional double set", &pb.RoundMetrics{ErrorEstimate: proto.Float64(inf)}, "error_estimate: must be a finite number, got +Inf"},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			err := rules.Check(tt.msg)
			switch {
			case tt.want == "" && err != nil:
				t.Errorf("Check = %v, want nil", err)
			case tt.want != "" && err == nil:
				t.Errorf("Check = nil, want %q", tt.want)
			case tt.want != "" && err.Error() != tt.want:
				t.Errorf("Check = %q, want %q", err, tt.want)
			}
		})
	}
}

// TestCheckOrder checks that of two faults the walk meets first the one the worker's walk
// meets first: fields in declaration order, depth first, a list's length before its
// elements, a message's fields before its required oneofs.
func TestCheckOrder(t *testing.T) {
	tests := []struct {
		name   string
		mutate func(*pb.Scene)
		field  string
	}{
		{"declaration order, not field numbers or names", func(s *pb.Scene) {
			s.Film.Width = 0
			s.Camera.VerticalFovDegrees = 0
		}, "camera.vertical_fov_degrees"},
		{"depth first", func(s *pb.Scene) {
			s.Materials[0].GetLambert().Reflectance.B = 2
			s.Shapes[0].GetSphere().Radius = 0
		}, "materials[0].lambert.reflectance.b"},
		{"components in order", func(s *pb.Scene) {
			s.Materials[0].GetLambert().Reflectance.B = 2
			s.Materials[0].GetLambert().Reflectance.G = -1
		}, "materials[0].lambert.reflectance.g"},
		{"elements in order", func(s *pb.Scene) {
			s.Shapes[2].Name = strings.Repeat("n", 300)
			s.Shapes[1].GetQuad().Origin = nil
		}, "shapes[1].quad.origin"},
		{"list length before elements", func(s *pb.Scene) {
			s.Shapes[0].Material = ""
			for len(s.Shapes) <= 100000 {
				s.Shapes = append(s.Shapes, s.Shapes[len(s.Shapes)-1])
			}
		}, "shapes"},
		{"fields before the required oneof", func(s *pb.Scene) {
			s.Materials[1].Kind = nil
			s.Materials[1].Name = ""
		}, "materials[1].name"},
		{"a later field is reached once earlier ones pass", func(s *pb.Scene) {
			s.Progressive = &pb.Progressive{Reference: &pb.ReferenceImage{Digest: "x"}}
		}, "progressive.reference.digest"},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			s := scenetest.Valid(8, 8)
			if err := rules.Check(s); err != nil {
				t.Fatalf("the base scene: %v", err)
			}
			tt.mutate(s)
			err := rules.Check(s)
			if err == nil || err.Field != tt.field {
				t.Errorf("Check = %v, want an error at %s", err, tt.field)
			}
		})
	}
}

func TestDescribe(t *testing.T) {
	f := proto.Float64
	tests := []struct {
		rule *pb.FieldRule
		want string
	}{
		{&pb.FieldRule{Gte: f(1), Lte: f(16384)}, "must be in [1, 16384]"},
		{&pb.FieldRule{Gt: f(0), Lt: f(180)}, "must be in (0, 180)"},
		{&pb.FieldRule{Gt: f(0), Lte: f(1), DefaultValue: f(0.7)}, "must be in (0, 1] (0 selects 0.7)"},
		{&pb.FieldRule{Gte: f(0)}, "must be >= 0"},
		{&pb.FieldRule{Gt: f(-1.5)}, "must be > -1.5"},
		{&pb.FieldRule{Lte: f(1e6), DefaultValue: f(1)}, "must be <= 1000000 (0 selects 1)"},
		{&pb.FieldRule{Lt: f(5)}, "must be < 5"},
		{&pb.FieldRule{DefaultValue: f(3), MaxItems: proto.Uint64(2)}, ""},
		{&pb.FieldRule{}, ""},
		{nil, ""},
	}
	for _, tt := range tests {
		if got := rules.Describe(tt.rule); got != tt.want {
			t.Errorf("Describe(%v) = %q, want %q", tt.rule, got, tt.want)
		}
	}
}

func TestTruncateAndNumber(t *testing.T) {
	for _, tt := range []struct {
		s    string
		n    int
		want string
	}{{"short", 10, "short"}, {"exactly", 7, "exactly"}, {"abcdef", 3, "abc…"}, {"héllo", 2, "h…"}, {"héllo", 3, "hé…"}} {
		if got := rules.Truncate(tt.s, tt.n); got != tt.want {
			t.Errorf("Truncate(%q, %d) = %q, want %q", tt.s, tt.n, got, tt.want)
		}
	}
	for _, tt := range []struct {
		v    float64
		want string
	}{{16384, "16384"}, {5e7, "50000000"}, {-604800, "-604800"}, {0.1, "0.1"}, {1e12, "1e+12"}, {-0.5, "-0.5"}, {math.Inf(-1), "-Inf"}, {math.NaN(), "NaN"}} {
		if got := rules.Number(tt.v); got != tt.want {
			t.Errorf("Number(%v) = %q, want %q", tt.v, got, tt.want)
		}
	}
}
