// Command mksnapshot generates synthetic photons, builds a snapshot with the product's Go
// builder (coordinator/photonmap.Build) and writes it, printing the build time: the
// coordinator's kd-tree build benchmark, and the input of the C++ nearest-k benchmark
// (which must measure the tree the farm really ships, so it reads this file).
//
//	go run ./bench/cmd/mksnapshot -n 1000000 -dist uniform -o /tmp/uniform-1m.snap
package main

import (
	"flag"
	"fmt"
	"math"
	"math/rand/v2"
	"os"
	"runtime"
	"time"

	"photonfarm/coordinator/photonmap"
)

func main() {
	n := flag.Int("n", 1000000, "photons")
	dist := flag.String("dist", "uniform", "uniform (in a unit box) or surfaces (a box's walls and a sphere, like a Cornell box)")
	out := flag.String("o", "", "output snapshot file (none: build only)")
	shardSize := flag.Int("shard", 250000, "photons per emission shard")
	seed := flag.Uint64("seed", 1, "random seed")
	flag.Parse()

	r := rand.New(rand.NewPCG(*seed, 0))
	var shards []photonmap.Shard
	for first := 0; first < *n; first += *shardSize {
		count := min(*shardSize, *n-first)
		ps := make([]photonmap.ShardPhoton, count)
		for i := range ps {
			ps[i] = photon(r, *dist)
		}
		shards = append(shards, photonmap.Shard{Data: photonmap.EncodeShard(photonmap.Global, uint64(first), uint64(count), ps)})
	}
	runtime.GC()
	var before runtime.MemStats
	runtime.ReadMemStats(&before)
	start := time.Now()
	snap, err := photonmap.Build(shards)
	elapsed := time.Since(start)
	if err != nil {
		fmt.Fprintln(os.Stderr, "mksnapshot:", err)
		os.Exit(1)
	}
	var after runtime.MemStats
	runtime.ReadMemStats(&after)
	fmt.Printf("go kd-tree build  %-8s %9d photons  %8.0f ms  %6.2f M photons/s  %5.1f B/photon  %.1f MB allocated  GOMAXPROCS=%d\n",
		*dist, *n, float64(elapsed.Microseconds())/1e3, float64(*n)/elapsed.Seconds()/1e6,
		float64(len(snap))/float64(max(*n, 1)), float64(after.TotalAlloc-before.TotalAlloc)/1e6, runtime.GOMAXPROCS(0))
	if *out != "" {
		if err := os.WriteFile(*out, snap, 0o644); err != nil {
			fmt.Fprintln(os.Stderr, "mksnapshot:", err)
			os.Exit(1)
		}
	}
}

func photon(r *rand.Rand, dist string) photonmap.ShardPhoton {
	var p photonmap.ShardPhoton
	p.Power = [3]float32{r.Float32() * 1e-6, r.Float32() * 1e-6, r.Float32() * 1e-6}
	p.Wi = uint16(r.Uint32())
	p.Normal = uint16(r.Uint32()) &^ 3
	u, v := r.Float32(), r.Float32()
	switch dist {
	case "surfaces":
		// 5 walls of a unit box (open at the front) and a sphere resting on the floor: the
		// photons of a real scene lie on 2-D surfaces, which skews the tree differently.
		switch face := r.IntN(6); face {
		case 0:
			p.Position = [3]float32{u, 0, v}
		case 1:
			p.Position = [3]float32{u, 1, v}
		case 2:
			p.Position = [3]float32{0, u, v}
		case 3:
			p.Position = [3]float32{1, u, v}
		case 4:
			p.Position = [3]float32{u, v, 1}
		default:
			z := 2*u - 1
			phi := 2 * math.Pi * float64(v)
			s := float32(math.Sqrt(float64(1 - z*z)))
			p.Position = [3]float32{0.5 + 0.2*s*float32(math.Cos(phi)), 0.2 + 0.2*z, 0.5 + 0.2*s*float32(math.Sin(phi))}
		}
	default:
		p.Position = [3]float32{u, v, r.Float32()}
	}
	return p
}
