package scene

import (
	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/reflect/protoreflect"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// Defaults returns a copy of s with every field that is 0 and declares a default
// (rules.ApplyDefaults) set to it, so that the stored scene says exactly what workers
// render. A reference image without a digest is dropped: there is nothing to compare
// with. s is not modified.
func Defaults(s *pb.Scene) *pb.Scene {
	out := proto.Clone(s).(*pb.Scene)
	rules.ApplyDefaults(out)
	if out.GetProgressive().GetReference().GetDigest() == "" {
		out.Progressive.Reference = nil
	}
	return out
}

// The effective values of the fields the coordinator reads: the field, or the value its
// 0 selects (scene.proto's default_value, read once).
var (
	TileSize        = effective((*pb.Scene).GetFilm, (*pb.Film).GetTileSize, "tile_size")
	SamplesPerPixel = effective((*pb.Scene).GetSampling, (*pb.Sampling).GetSamplesPerPixel, "samples_per_pixel")
	LightSamples    = effective((*pb.Scene).GetSampling, (*pb.Sampling).GetLightSamples, "light_samples")
	GlobalPhotons   = effective((*pb.Scene).GetPhotons, (*pb.PhotonMapping).GetGlobalPhotons, "global_photons")
	CausticPhotons  = effective((*pb.Scene).GetPhotons, (*pb.PhotonMapping).GetCausticPhotons, "caustic_photons")
	VolumePhotons   = effective((*pb.Scene).GetPhotons, (*pb.PhotonMapping).GetVolumePhotons, "volume_photons")
	PhotonsPerShard = effective((*pb.Scene).GetPhotons, (*pb.PhotonMapping).GetPhotonsPerShard, "photons_per_shard")
	// AntialiasingMode, EdgeSamples (camera rays per edge pixel) and EdgeThreshold.
	AntialiasingMode = effective((*pb.Scene).GetAntialiasing, (*pb.Antialiasing).GetMode, "mode")
	EdgeSamples      = effective((*pb.Scene).GetAntialiasing, (*pb.Antialiasing).GetEdgeSamples, "edge_samples")
	EdgeThreshold    = effective((*pb.Scene).GetAntialiasing, (*pb.Antialiasing).GetEdgeThreshold, "edge_threshold")
	// IndirectMode, and the gather rays at a first diffuse hit and after a glossy bounce.
	IndirectMode        = effective((*pb.Scene).GetIndirect, (*pb.Indirect).GetMode, "mode")
	GatherRays          = effective((*pb.Scene).GetIndirect, (*pb.Indirect).GetGatherRays, "gather_rays")
	SecondaryGatherRays = effective((*pb.Scene).GetIndirect, (*pb.Indirect).GetSecondaryGatherRays, "secondary_gather_rays")
	// Rounds is the most progressive rounds a job runs; Alpha is progressive photon
	// mapping's alpha.
	Rounds = effective((*pb.Scene).GetProgressive, (*pb.Progressive).GetMaxRounds, "max_rounds")
	Alpha  = effective((*pb.Scene).GetProgressive, (*pb.Progressive).GetAlpha, "alpha")
)

// effective returns the getter of the effective value of field name of the message part
// of a scene: the field if it is not 0, else its default.
func effective[M proto.Message, T ~uint32 | ~uint64 | ~int32 | ~float64](part func(*pb.Scene) M, field func(M) T, name protoreflect.Name) func(*pb.Scene) T {
	var zero M // a nil message of the part's type, which has its descriptor
	def := T(rules.Default(zero, name))
	return func(s *pb.Scene) T {
		if v := field(part(s)); v != 0 {
			return v
		}
		return def
	}
}

// FinalGather reports whether the scene asks for final gathering (the default) rather than
// the global map's radiance seen directly.
func FinalGather(s *pb.Scene) bool {
	return IndirectMode(s) == pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER
}

// ReferenceDigest returns the digest of the scene's reference image, or "".
func ReferenceDigest(s *pb.Scene) string { return s.GetProgressive().GetReference().GetDigest() }
