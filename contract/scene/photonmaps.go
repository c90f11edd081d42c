package scene

import (
	"strings"

	pb "photonfarm/proto/renderfarm/v1"
)

// PhotonMap is a photon map a scene gets: its kind and the photon paths emitted for it in
// each round.
type PhotonMap struct {
	Kind    pb.PhotonMapKind
	Photons uint64
}

// Name is the map's kind for people: "global", "caustic", "volume".
func (m PhotonMap) Name() string {
	return strings.ToLower(strings.TrimPrefix(m.Kind.String(), "PHOTON_MAP_KIND_"))
}

// PhotonMaps returns the photon maps s gets, in plan order: a global map if its diffuse
// surfaces can light one another (InterreflectionOf), a caustic map if a shape is specular
// (SurfacesOf), a volume map if a medium that is not path traced scatters light
// (VolumeMapNeeded), each only if it is
// given photons. Every valid scene has a light (checkSomeLight), so none is asked for here.
func PhotonMaps(s *pb.Scene) []PhotonMap {
	var maps []PhotonMap
	if n := GlobalPhotons(s); n > 0 && InterreflectionOf(s).Possible {
		maps = append(maps, PhotonMap{Kind: pb.PhotonMapKind_PHOTON_MAP_KIND_GLOBAL, Photons: n})
	}
	if n := CausticPhotons(s); n > 0 && SurfacesOf(s).Specular {
		maps = append(maps, PhotonMap{Kind: pb.PhotonMapKind_PHOTON_MAP_KIND_CAUSTIC, Photons: n})
	}
	if n := VolumePhotons(s); n > 0 && VolumeMapNeeded(s) {
		maps = append(maps, PhotonMap{Kind: pb.PhotonMapKind_PHOTON_MAP_KIND_VOLUME, Photons: n})
	}
	return maps
}
