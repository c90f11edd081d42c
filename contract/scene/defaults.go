package scene

import (
	"google.golang.org/protobuf/proto"

	pb "photonfarm/proto/renderfarm/v1"
)

// TileSize returns the scene's effective tile size (DefaultTileSize when unset).
func TileSize(s *pb.Scene) uint32 {
	if t := s.GetFilm().GetTileSize(); t != 0 {
		return t
	}
	return DefaultTileSize
}

// SamplesPerPixel returns the scene's effective samples per pixel.
func SamplesPerPixel(s *pb.Scene) uint32 {
	if n := s.GetSampling().GetSamplesPerPixel(); n != 0 {
		return n
	}
	return DefaultSamplesPerPixel
}

// Defaults returns a copy of s with every "0 selects the default" field filled in, so that
// the stored scene says exactly what workers render. s is not modified.
func Defaults(s *pb.Scene) *pb.Scene {
	out := proto.Clone(s).(*pb.Scene)
	if out.Film == nil {
		out.Film = &pb.Film{}
	}
	out.Film.TileSize = TileSize(s)
	if out.Sampling == nil {
		out.Sampling = &pb.Sampling{}
	}
	out.Sampling.SamplesPerPixel = SamplesPerPixel(s)
	if out.Photons == nil {
		out.Photons = &pb.PhotonMapping{}
	}
	out.Photons.GlobalPhotons = GlobalPhotons(s)
	out.Photons.CausticPhotons = CausticPhotons(s)
	out.Photons.PhotonsPerShard = PhotonsPerShard(s)
	defaultRendering(out)
	return out
}

// GlobalPhotons returns the scene's effective number of global-map photon paths.
func GlobalPhotons(s *pb.Scene) uint64 {
	if n := s.GetPhotons().GetGlobalPhotons(); n != 0 {
		return n
	}
	return DefaultGlobalPhotons
}

// CausticPhotons returns the scene's effective number of caustic-map photon paths.
func CausticPhotons(s *pb.Scene) uint64 {
	if n := s.GetPhotons().GetCausticPhotons(); n != 0 {
		return n
	}
	return DefaultCausticPhotons
}

// PhotonsPerShard returns the scene's effective photon paths per emission task.
func PhotonsPerShard(s *pb.Scene) uint64 {
	if n := s.GetPhotons().GetPhotonsPerShard(); n != 0 {
		return n
	}
	return DefaultPhotonsPerShard
}

// MeshRef is a mesh file a scene refers to by digest.
type MeshRef struct {
	// Field is the digest's path, "shapes[3].mesh.digest".
	Field  string
	Digest string
}

// MeshRefs lists the mesh files s refers to, in shape order.
func MeshRefs(s *pb.Scene) []MeshRef {
	var refs []MeshRef
	for i, sh := range s.GetShapes() {
		if m := sh.GetMesh(); m != nil {
			refs = append(refs, MeshRef{Field: idx("shapes", i) + ".mesh.digest", Digest: m.GetDigest()})
		}
	}
	return refs
}
