package photonmap

import (
	"math/rand/v2"
)

// Photon sets used by the tests, the test vectors and (through the same shapes) the
// benchmarks. Directions are random codes: the builder copies them, it never decodes them.

func randomCodes(r *rand.Rand) (uint16, uint16) {
	return uint16(r.Uint32()), uint16(r.Uint32()) &^ normalAxisMask
}

func randomPower(r *rand.Rand) [3]float32 {
	return [3]float32{r.Float32() * 1e-3, r.Float32() * 1e-3, r.Float32() * 1e-3}
}

// uniformPhotons are n photons uniformly in [-1,1]^3.
func uniformPhotons(r *rand.Rand, n int) []ShardPhoton {
	ps := make([]ShardPhoton, n)
	for i := range ps {
		ps[i].Position = [3]float32{r.Float32()*2 - 1, r.Float32()*2 - 1, r.Float32()*2 - 1}
		ps[i].Power = randomPower(r)
		ps[i].Wi, ps[i].Normal = randomCodes(r)
	}
	return ps
}

// oct7PlusZ is the oct7 code of +z (u = v = h = 63), the normal field of every volume
// photon: a photon stored in a medium lies on no surface.
const oct7PlusZ = 63<<2 | 63<<9

// volumePhotons are n photons uniformly in [-1,1]^3 with the volume map's normal.
func volumePhotons(r *rand.Rand, n int) []ShardPhoton {
	ps := uniformPhotons(r, n)
	for i := range ps {
		ps[i].Normal = oct7PlusZ
	}
	return ps
}

// planePhotons all lie on z = 0.5: one axis has zero extent.
func planePhotons(r *rand.Rand, n int) []ShardPhoton {
	ps := uniformPhotons(r, n)
	for i := range ps {
		ps[i].Position[2] = 0.5
	}
	return ps
}

// duplicatePhotons repeat a handful of positions (with different payloads), so ties on
// every axis must be broken by input order.
func duplicatePhotons(r *rand.Rand, n int) []ShardPhoton {
	ps := uniformPhotons(r, n)
	spots := uniformPhotons(r, 5)
	for i := range ps {
		ps[i].Position = spots[r.IntN(len(spots))].Position
	}
	return ps
}

// splitShards cuts photons into shards of one map at the given record boundaries, giving
// each shard paths proportional to its records (any tiling of the path range is valid).
func splitShards(kind Kind, photons []ShardPhoton, cuts ...int) []Shard {
	var shards []Shard
	bounds := append(append([]int{0}, cuts...), len(photons))
	for i := 0; i+1 < len(bounds); i++ {
		a, b := bounds[i], bounds[i+1]
		shards = append(shards, Shard{Data: EncodeShard(kind, uint64(a)*3, uint64(b-a)*3, photons[a:b])})
	}
	return shards
}
