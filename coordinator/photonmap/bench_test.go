package photonmap

import (
	"math/rand/v2"
	"testing"
)

// BenchmarkBuild1M is the builder's throughput on a million uniform photons in 4 shards;
// `make bench` prints 1M and 10M figures through bench/cmd/mksnapshot.
func BenchmarkBuild1M(b *testing.B) {
	photons := uniformPhotons(rand.New(rand.NewPCG(1, 1)), 1_000_000)
	shards := splitShards(Global, photons, 250_000, 500_000, 750_000)
	b.SetBytes(int64(len(photons)) * recordSize)
	b.ResetTimer()
	for i := 0; i < b.N; i++ {
		if _, err := Build(shards); err != nil {
			b.Fatal(err)
		}
	}
}
