package scene

import (
	"math"

	pb "photonfarm/proto/renderfarm/v1"
)

// validatePhotons checks the photon mapping settings; every field may be unset (0).
func validatePhotons(ph *pb.PhotonMapping) error {
	if ph == nil {
		return nil
	}
	for _, c := range []struct {
		field string
		n     uint64
	}{{"photons.global_photons", ph.GetGlobalPhotons()}, {"photons.caustic_photons", ph.GetCausticPhotons()}} {
		if c.n > MaxPhotonsPerMap {
			return fe(c.field, "must be <= %d, got %d", uint64(MaxPhotonsPerMap), c.n)
		}
	}
	if n := ph.GetPhotonsPerShard(); n != 0 && (n < MinPhotonsPerShard || n > MaxPhotonsPerShard) {
		return fe("photons.photons_per_shard", "must be 0 (default %d) or in [%d, %d], got %d",
			uint64(DefaultPhotonsPerShard), uint64(MinPhotonsPerShard), uint64(MaxPhotonsPerShard), n)
	}
	if err := validateEstimate("photons.global_estimate", ph.GetGlobalEstimate()); err != nil {
		return err
	}
	return validateEstimate("photons.caustic_estimate", ph.GetCausticEstimate())
}

func validateEstimate(p string, e *pb.RadianceEstimate) error {
	if e == nil {
		return nil
	}
	if n := e.GetNeighbours(); n > MaxNeighbours {
		return fe(p+".neighbours", "must be <= %d, got %d", MaxNeighbours, n)
	}
	r := e.GetMaxRadius()
	if err := checkFinite(p+".max_radius", r); err != nil {
		return err
	}
	if r < 0 {
		return fe(p+".max_radius", "must be >= 0 (0 selects the default), got %s", fmtNum(r))
	}
	if _, ok := pb.Filter_name[int32(e.GetFilter())]; !ok {
		return fe(p+".filter", "unknown filter %d", int32(e.GetFilter()))
	}
	k := e.GetConeK()
	if math.IsNaN(k) || math.IsInf(k, 0) {
		return fe(p+".cone_k", "must be a finite number, got %s", fmtNum(k))
	}
	if k != 0 && (k < 1 || k > MaxConeK) {
		return fe(p+".cone_k", "must be 0 (default 1.1) or in [1, %s], got %s", fmtNum(MaxConeK), fmtNum(k))
	}
	return nil
}
