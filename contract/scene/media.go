package scene

import (
	"math"
	"slices"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// media returns s's media: the medium filling the scene, if set, then every shape's
// interior medium in shape order.
func media(s *pb.Scene) []*pb.Medium {
	var out []*pb.Medium
	if m := s.GetMedium(); m != nil {
		out = append(out, m)
	}
	for _, sh := range s.GetShapes() {
		if m := sh.GetInteriorMedium(); m != nil {
			out = append(out, m)
		}
	}
	return out
}

// scatters reports whether light can scatter in m: sigma_s positive in some channel, or an
// albedo positive in some channel with a positive density. A medium that only absorbs
// attenuates rays but stores no volume photon.
func scatters(m *pb.Medium) bool {
	if a := m.GetAlbedo(); a != nil {
		return a.GetDensity() > 0 && positive(a.GetAlbedo())
	}
	return positive(m.GetSigma().GetSigmaS())
}

// PathTraced reports whether m's multiple scattering is path traced rather than read from
// the volume photon map: its Henyey-Greenstein |g| is at least the contract's
// path_traced_media_min_abs_g (rules.Scene), a lobe too narrow for k photons to weigh.
func PathTraced(m *pb.Medium) bool {
	return math.Abs(m.GetG()) >= rules.Scene.GetPathTracedMediaMinAbsG()
}

// MediaScatter reports whether some medium of s scatters light (scatters).
func MediaScatter(s *pb.Scene) bool { return slices.ContainsFunc(media(s), scatters) }

// MediaPathTraced reports whether some medium of s that scatters light is path traced.
func MediaPathTraced(s *pb.Scene) bool {
	return slices.ContainsFunc(media(s), func(m *pb.Medium) bool { return scatters(m) && PathTraced(m) })
}

// VolumeMapNeeded reports whether some medium of s scatters light and is not path traced,
// which decides whether s gets a volume map.
func VolumeMapNeeded(s *pb.Scene) bool {
	return slices.ContainsFunc(media(s), func(m *pb.Medium) bool { return scatters(m) && !PathTraced(m) })
}
