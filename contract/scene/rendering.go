package scene

import (
	"math"

	pb "photonfarm/proto/renderfarm/v1"
)

// validateRendering checks the settings of issue 4 (light samples, edge anti-aliasing,
// indirect light, progressive rounds); every field may be unset.
func validateRendering(s *pb.Scene) error {
	if n := s.GetSampling().GetLightSamples(); n > MaxLightSamples {
		return fe("sampling.light_samples", "must be <= %d (0 selects %d), got %d", MaxLightSamples, DefaultLightSamples, n)
	}
	if err := validateAntialiasing(s.GetAntialiasing()); err != nil {
		return err
	}
	if err := validateIndirect(s.GetIndirect()); err != nil {
		return err
	}
	return validateProgressive(s.GetProgressive())
}

func validateAntialiasing(a *pb.Antialiasing) error {
	if a == nil {
		return nil
	}
	if _, ok := pb.AntialiasingMode_name[int32(a.GetMode())]; !ok {
		return fe("antialiasing.mode", "unknown mode %d", int32(a.GetMode()))
	}
	if n := a.GetEdgeSamples(); n > MaxEdgeSamples {
		return fe("antialiasing.edge_samples", "must be <= %d (0 selects %d), got %d", MaxEdgeSamples, DefaultEdgeSamples, n)
	}
	return nonNegative("antialiasing.edge_threshold", a.GetEdgeThreshold(), math.MaxFloat64)
}

func validateIndirect(in *pb.Indirect) error {
	if in == nil {
		return nil
	}
	if _, ok := pb.IndirectMode_name[int32(in.GetMode())]; !ok {
		return fe("indirect.mode", "unknown mode %d", int32(in.GetMode()))
	}
	if n := in.GetGatherRays(); n > MaxGatherRays {
		return fe("indirect.gather_rays", "must be <= %d (0 selects %d), got %d", MaxGatherRays, DefaultGatherRays, n)
	}
	if n := in.GetSecondaryGatherRays(); n > MaxGatherRays {
		return fe("indirect.secondary_gather_rays", "must be <= %d (0 selects %d), got %d", MaxGatherRays, DefaultSecondaryGatherRays, n)
	}
	return nil
}

func validateProgressive(p *pb.Progressive) error {
	if p == nil {
		return nil
	}
	if n := p.GetMaxRounds(); n > MaxRounds {
		return fe("progressive.max_rounds", "must be <= %d (0 selects 1), got %d", MaxRounds, n)
	}
	if err := nonNegative("progressive.target_error", p.GetTargetError(), math.MaxFloat64); err != nil {
		return err
	}
	if err := nonNegative("progressive.time_budget_seconds", p.GetTimeBudgetSeconds(), MaxTimeBudgetSeconds); err != nil {
		return err
	}
	a := p.GetAlpha()
	if math.IsNaN(a) || math.IsInf(a, 0) || a < 0 || a > 1 {
		return fe("progressive.alpha", "must be in (0, 1] (0 selects %s), got %s", fmtNum(DefaultAlpha), fmtNum(a))
	}
	ref := p.GetReference()
	if ref.GetPath() != "" && len(ref.GetPath()) > MaxPathLength {
		return fe("progressive.reference.path", "must be at most %d bytes, got %d", MaxPathLength, len(ref.GetPath()))
	}
	if d := ref.GetDigest(); d != "" && !DigestPattern.MatchString(d) {
		return fe("progressive.reference.digest", "must be \"sha256:\" followed by 64 lowercase hex digits, got %q", d)
	}
	if ref != nil && ref.GetDigest() == "" && ref.GetPath() != "" {
		return fe("progressive.reference.digest", "missing: the client uploads the file at path %q and sets its digest", ref.GetPath())
	}
	return nil
}

// nonNegative refuses NaN, infinities, negatives and values above max.
func nonNegative(field string, v, max float64) error {
	if math.IsNaN(v) || math.IsInf(v, 0) {
		return fe(field, "must be a finite number, got %s", fmtNum(v))
	}
	if v < 0 || v > max {
		if max == math.MaxFloat64 {
			return fe(field, "must be >= 0, got %s", fmtNum(v))
		}
		return fe(field, "must be in [0, %s], got %s", fmtNum(max), fmtNum(v))
	}
	return nil
}

// Rounds returns the scene's effective maximum number of progressive rounds.
func Rounds(s *pb.Scene) uint32 {
	if n := s.GetProgressive().GetMaxRounds(); n != 0 {
		return n
	}
	return 1
}

// Alpha returns the scene's effective progressive photon mapping alpha.
func Alpha(s *pb.Scene) float64 {
	if a := s.GetProgressive().GetAlpha(); a != 0 {
		return a
	}
	return DefaultAlpha
}

// FinalGather reports whether the scene asks for final gathering (the default) rather than
// the global map's radiance seen directly.
func FinalGather(s *pb.Scene) bool {
	return s.GetIndirect().GetMode() != pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP
}

// AntialiasingMode returns the scene's effective edge anti-aliasing mode.
func AntialiasingMode(s *pb.Scene) pb.AntialiasingMode {
	if m := s.GetAntialiasing().GetMode(); m != pb.AntialiasingMode_ANTIALIASING_MODE_UNSPECIFIED {
		return m
	}
	return pb.AntialiasingMode_ANTIALIASING_MODE_EDGES
}

// EdgeSamples returns the scene's effective camera rays per edge pixel.
func EdgeSamples(s *pb.Scene) uint32 {
	if n := s.GetAntialiasing().GetEdgeSamples(); n != 0 {
		return n
	}
	return DefaultEdgeSamples
}

// ReferenceDigest returns the digest of the scene's reference image, or "".
func ReferenceDigest(s *pb.Scene) string { return s.GetProgressive().GetReference().GetDigest() }

// defaultRendering fills in the "0 selects" fields of issue 4 on out (a copy).
func defaultRendering(out *pb.Scene) {
	if out.Sampling.LightSamples == 0 {
		out.Sampling.LightSamples = DefaultLightSamples
	}
	if out.Antialiasing == nil {
		out.Antialiasing = &pb.Antialiasing{}
	}
	out.Antialiasing.Mode = AntialiasingMode(out)
	out.Antialiasing.EdgeSamples = EdgeSamples(out)
	if out.Antialiasing.EdgeThreshold == 0 {
		out.Antialiasing.EdgeThreshold = DefaultEdgeThreshold
	}
	if out.Indirect == nil {
		out.Indirect = &pb.Indirect{}
	}
	if out.Indirect.Mode == pb.IndirectMode_INDIRECT_MODE_UNSPECIFIED {
		out.Indirect.Mode = pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER
	}
	if out.Indirect.GatherRays == 0 {
		out.Indirect.GatherRays = DefaultGatherRays
	}
	if out.Indirect.SecondaryGatherRays == 0 {
		out.Indirect.SecondaryGatherRays = DefaultSecondaryGatherRays
	}
	if out.Progressive == nil {
		out.Progressive = &pb.Progressive{}
	}
	out.Progressive.MaxRounds = Rounds(out)
	out.Progressive.Alpha = Alpha(out)
	if r := out.Progressive.Reference; r != nil {
		if r.Digest == "" {
			out.Progressive.Reference = nil
		}
	}
}
