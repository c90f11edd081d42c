package rules_test

import (
	"math"
	"slices"
	"testing"

	"google.golang.org/protobuf/encoding/prototext"
	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/reflect/protoreflect"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestApplyDefaults checks that every 0 whose rule declares a default takes it, that the
// messages holding such fields are created and no other, and that set values, lists and
// oneofs are left as they are.
func TestApplyDefaults(t *testing.T) {
	estimate := &pb.RadianceEstimate{ConeK: 1.1}
	tests := []struct {
		name string
		in   proto.Message
		want proto.Message
	}{
		{"an empty scene gets exactly the messages that hold defaults", &pb.Scene{}, &pb.Scene{
			Film:         &pb.Film{TileSize: 32},
			Sampling:     &pb.Sampling{SamplesPerPixel: 1, LightSamples: 16, Specular: pb.SpecularSampling_SPECULAR_SAMPLING_SPLIT, Adaptive: pb.AdaptiveSampling_ADAPTIVE_SAMPLING_OFF, Spectral: pb.SpectralSampling_SPECTRAL_SAMPLING_AUTO},
			Photons:      &pb.PhotonMapping{GlobalPhotons: 200000, CausticPhotons: 200000, PhotonsPerShard: 100000, GlobalEstimate: estimate, CausticEstimate: estimate, VolumePhotons: 200000, VolumeEstimate: estimate},
			Antialiasing: &pb.Antialiasing{Mode: pb.AntialiasingMode_ANTIALIASING_MODE_EDGES, EdgeSamples: 32, EdgeThreshold: 0.1},
			Indirect:     &pb.Indirect{Mode: pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER, GatherRays: 64, SecondaryGatherRays: 8},
			Progressive:  &pb.Progressive{MaxRounds: 1, Alpha: 0.7},
		}},
		{"-0 is 0, as Check reads it", &pb.Progressive{Alpha: math.Copysign(0, -1)}, &pb.Progressive{MaxRounds: 1, Alpha: 0.7}},
		{"set values stay", &pb.Progressive{MaxRounds: 5, Alpha: 0.25, TargetError: 0}, &pb.Progressive{MaxRounds: 5, Alpha: 0.25}},
		{"fields without a default stay 0, messages without one stay unset", &pb.Progressive{}, &pb.Progressive{MaxRounds: 1, Alpha: 0.7}},
		{"a set enum stays", &pb.Indirect{Mode: pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP}, &pb.Indirect{Mode: pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP, GatherRays: 64, SecondaryGatherRays: 8}},
		{"nothing to default", &pb.Camera{}, &pb.Camera{}},
		{"list elements and oneof members are left as given", &pb.Shape{Geometry: &pb.Shape_Mesh{Mesh: &pb.MeshFile{}}}, &pb.Shape{Geometry: &pb.Shape_Mesh{Mesh: &pb.MeshFile{}}}},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			got := tt.in // not a clone: proto.Clone drops a -0
			rules.ApplyDefaults(got)
			if !proto.Equal(got, tt.want) {
				t.Errorf("ApplyDefaults = {%v}, want {%v}", prototext.Format(got), prototext.Format(tt.want))
			}
		})
	}
}

func TestDefaultMinMax(t *testing.T) {
	tests := []struct {
		name   string
		get    func(proto.Message, protoreflect.Name) float64
		msg    proto.Message
		fld    protoreflect.Name
		want   float64 // ignored when panics
		panics bool
	}{
		{"default", rules.Default, (*pb.Film)(nil), "tile_size", 32, false},
		{"default of a double", rules.Default, (*pb.Progressive)(nil), "alpha", 0.7, false},
		{"max", rules.Max, (*pb.Film)(nil), "width", 16384, false},
		{"min", rules.Min, (*pb.PhotonMapping)(nil), "photons_per_shard", 1000, false},
		{"no default declared", rules.Default, (*pb.Film)(nil), "width", 0, true},
		{"no lte declared", rules.Max, (*pb.Progressive)(nil), "target_error", 0, true},
		{"no gte declared (gt only)", rules.Min, (*pb.Sphere)(nil), "radius", 0, true},
		{"no rule", rules.Default, (*pb.Vec3)(nil), "x", 0, true},
		{"no such field", rules.Max, (*pb.Film)(nil), "depth", 0, true},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			defer func() {
				if r := recover(); (r != nil) != tt.panics {
					t.Errorf("panic %v, want a panic: %v", r, tt.panics)
				}
			}()
			if got := tt.get(tt.msg, tt.fld); got != tt.want {
				t.Errorf("got %v, want %v", got, tt.want)
			}
		})
	}
}

func TestKeys(t *testing.T) {
	if got, want := rules.Keys((*pb.RoundMetrics)(nil), "layer_reference_rmse"), []string{"direct", "indirect", "caustic", "volume"}; !slices.Equal(got, want) {
		t.Errorf("Keys(RoundMetrics.layer_reference_rmse) = %q, want %q", got, want)
	}
	for _, tt := range []struct {
		msg proto.Message
		fld protoreflect.Name
	}{{(*pb.Film)(nil), "width"}, {(*pb.Vec3)(nil), "x"}} {
		func() {
			defer func() {
				if recover() == nil {
					t.Errorf("Keys(%T, %s) did not panic: it declares no keys", tt.msg, tt.fld)
				}
			}()
			rules.Keys(tt.msg, tt.fld)
		}()
	}
}
