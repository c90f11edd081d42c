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
// 0 selects. Each reads its default from scene.proto.

func TileSize(s *pb.Scene) uint32 { return or(s.GetFilm().GetTileSize(), (*pb.Film)(nil), "tile_size") }

func SamplesPerPixel(s *pb.Scene) uint32 {
	return or(s.GetSampling().GetSamplesPerPixel(), (*pb.Sampling)(nil), "samples_per_pixel")
}

func LightSamples(s *pb.Scene) uint32 {
	return or(s.GetSampling().GetLightSamples(), (*pb.Sampling)(nil), "light_samples")
}

func GlobalPhotons(s *pb.Scene) uint64 {
	return or(s.GetPhotons().GetGlobalPhotons(), (*pb.PhotonMapping)(nil), "global_photons")
}

func CausticPhotons(s *pb.Scene) uint64 {
	return or(s.GetPhotons().GetCausticPhotons(), (*pb.PhotonMapping)(nil), "caustic_photons")
}

func PhotonsPerShard(s *pb.Scene) uint64 {
	return or(s.GetPhotons().GetPhotonsPerShard(), (*pb.PhotonMapping)(nil), "photons_per_shard")
}

func AntialiasingMode(s *pb.Scene) pb.AntialiasingMode {
	return or(s.GetAntialiasing().GetMode(), (*pb.Antialiasing)(nil), "mode")
}

// EdgeSamples is the camera rays per edge pixel.
func EdgeSamples(s *pb.Scene) uint32 {
	return or(s.GetAntialiasing().GetEdgeSamples(), (*pb.Antialiasing)(nil), "edge_samples")
}

func EdgeThreshold(s *pb.Scene) float64 {
	return or(s.GetAntialiasing().GetEdgeThreshold(), (*pb.Antialiasing)(nil), "edge_threshold")
}

func IndirectMode(s *pb.Scene) pb.IndirectMode {
	return or(s.GetIndirect().GetMode(), (*pb.Indirect)(nil), "mode")
}

// FinalGather reports whether the scene asks for final gathering (the default) rather than
// the global map's radiance seen directly.
func FinalGather(s *pb.Scene) bool {
	return IndirectMode(s) == pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER
}

func GatherRays(s *pb.Scene) uint32 {
	return or(s.GetIndirect().GetGatherRays(), (*pb.Indirect)(nil), "gather_rays")
}

func SecondaryGatherRays(s *pb.Scene) uint32 {
	return or(s.GetIndirect().GetSecondaryGatherRays(), (*pb.Indirect)(nil), "secondary_gather_rays")
}

// Rounds is the most progressive rounds the job runs.
func Rounds(s *pb.Scene) uint32 {
	return or(s.GetProgressive().GetMaxRounds(), (*pb.Progressive)(nil), "max_rounds")
}

// Alpha is progressive photon mapping's alpha.
func Alpha(s *pb.Scene) float64 {
	return or(s.GetProgressive().GetAlpha(), (*pb.Progressive)(nil), "alpha")
}

// ReferenceDigest returns the digest of the scene's reference image, or "".
func ReferenceDigest(s *pb.Scene) string { return s.GetProgressive().GetReference().GetDigest() }

// or returns v, or the value 0 selects for field of message type m when v is 0.
func or[T ~uint32 | ~uint64 | ~int32 | ~float64](v T, m proto.Message, field protoreflect.Name) T {
	if v != 0 {
		return v
	}
	return T(rules.Default(m, field))
}
