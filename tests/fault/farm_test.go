package fault

import (
	"flag"
	"math/rand/v2"
	"testing"
	"time"

	"photonfarm/coordinator/store/redisstore/redistest"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// faultSeed seeds every random choice of the trials (when to kill, whom). 0 picks one from
// the clock; either way it is printed, so that a failing run can be replayed with
// -fault-seed.
var faultSeed = flag.Uint64("fault-seed", 0, "seed of the fault trials' random choices (0: from the clock; printed)")

// seed returns the run's seed, printing it.
func seed(t *testing.T) uint64 {
	s := *faultSeed
	if s == 0 {
		s = uint64(time.Now().UnixNano())
	}
	t.Logf("fault seed %d (replay with -fault-seed %d)", s, s)
	return s
}

// trialRNG is trial i's random source: it depends only on the seed and i, so a replay with
// the same seed makes the same choices in every trial however many trials run.
func trialRNG(seed uint64, i int) *rand.Rand { return rand.New(rand.NewPCG(seed, uint64(i))) }

// startRedisFarm starts a redis-server (append-only, so that it holds up to a crash) and a
// coordinator on it, with extra coordinator flags.
func startRedisFarm(t *testing.T, extra ...string) *farmtest.Farm {
	t.Helper()
	rs := redistest.Start(t, redistest.AppendOnly())
	return farmtest.StartFarm(t, append([]string{"--redis", "redis://" + rs.Addr(), "--redis-prefix", "fault:"}, extra...))
}

// phasedScene is the trials' scene: scenes/test-small.json at 64x48 in 12 tiles of 16, 4
// samples a pixel, with a global map of 80,000 photon paths in 4 shards, so that the job
// goes through emit, build, precompute, merge, render and composite, each long enough on
// two one-thread workers (a few hundred milliseconds) for a kill to land in it.
func phasedScene(t *testing.T, f *farmtest.Farm) *pb.Scene {
	sc := f.TestScene(t, 64, 48, 16, 4)
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 80000, PhotonsPerShard: 20000}
	// Gaussian-filtered: a tile a killed worker held is redone with the samples of its margin.
	sc.Film.Filter = &pb.PixelFilter{Kind: &pb.PixelFilter_Gaussian{Gaussian: &pb.GaussianFilter{}}}
	return sc
}

// tinyScene is scenes/test-small.json reduced to its floor and its lamp, 16x16 pixels in
// one tile, one sample a pixel: every diffuse surface lies in one plane, so the job gets no
// photon map and runs one render task and one composite. seed varies the job.
func tinyScene(t *testing.T, f *farmtest.Farm, seed uint64) *pb.Scene {
	sc := f.LoadScene(t, "test-small.json")
	var kept []*pb.Shape
	for _, s := range sc.GetShapes() {
		if s.GetName() == "floor" || s.GetName() == "lamp" {
			kept = append(kept, s)
		}
	}
	sc.Shapes = kept
	sc.Film = &pb.Film{Width: 16, Height: 16, TileSize: 16}
	sc.Sampling.SamplesPerPixel = 1
	sc.Sampling.Seed = seed
	return sc
}
