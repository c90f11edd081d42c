package scene

import (
	"slices"

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
// albedo positive in some channel with a positive density (a grid's density scale is
// positive; its file's densities are not looked at). A medium that only absorbs
// attenuates rays but stores no volume photon.
func scatters(m *pb.Medium) bool {
	if a := m.GetAlbedo(); a != nil {
		return a.GetDensity() > 0 && positive(a.GetAlbedo())
	}
	if g := m.GetGrid(); g != nil {
		return positive(g.GetAlbedo())
	}
	return positive(m.GetSigma().GetSigmaS())
}

// MediaScatter reports whether some medium of s scatters light (scatters), which decides
// whether s gets a volume map.
func MediaScatter(s *pb.Scene) bool { return slices.ContainsFunc(media(s), scatters) }
