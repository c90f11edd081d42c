package scene

import (
	"fmt"

	pb "photonfarm/proto/renderfarm/v1"
)

// AdaptiveFrom is the first round whose camera samples are allocated by error: two rounds
// give each pixel the first spread between its round values.
const AdaptiveFrom = 3

// Adaptive says whether a job of s moves camera samples by error in its later rounds
// (sampling.adaptive ON, at least AdaptiveFrom rounds and the one-pixel box filter), and
// why. The workers' composite makes the same decision (worker/scene: AdaptiveSamplingOn),
// writing a sample map only when this is true.
func Adaptive(s *pb.Scene) (bool, string) {
	if s.GetSampling().GetAdaptive() != pb.AdaptiveSampling_ADAPTIVE_SAMPLING_ON {
		return false, "sampling.adaptive is OFF (the default): every round samples every pixel alike"
	}
	if Rounds(s) < AdaptiveFrom {
		return false, fmt.Sprintf("sampling.adaptive is ON but progressive.max_rounds is %d: allocation by error starts in round %d", Rounds(s), AdaptiveFrom)
	}
	if !PixelBox(s) {
		return false, "sampling.adaptive is ON but the pixel filter is wider than the one-pixel box: a pixel's value mixes its neighbours' samples"
	}
	return true, fmt.Sprintf("from round %d each pixel's camera samples follow its estimated error (more where the spread between rounds is large), as many samples a round as round 2 drew", AdaptiveFrom)
}

// PixelBox reports whether s's pixel filter is the box of radius 1/2 (or unset): each pixel
// the plain mean of its own samples.
func PixelBox(s *pb.Scene) bool {
	f := s.GetFilm().GetFilter()
	switch f.GetKind().(type) {
	case nil:
		return true
	case *pb.PixelFilter_Box:
		r := f.GetBox().GetRadius()
		return r == 0 || r == 0.5
	default:
		return false
	}
}
