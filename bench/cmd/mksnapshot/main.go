// Command mksnapshot generates synthetic photons, builds a snapshot with the product's Go
// builder the way the coordinator does (coordinator/photonmap.BuildTo: shards read from
// files record by record, the snapshot written to a file) and prints the build's time and
// the process's peak resident memory (VmHWM): the coordinator's kd-tree build benchmark,
// and the input of the C++ nearest-k benchmark (which must measure the tree the farm
// really ships, so it reads this file).
//
//	go run ./bench/cmd/mksnapshot -n 1000000 -dist uniform -o /tmp/uniform-1m.snap
package main

import (
	"bufio"
	"flag"
	"fmt"
	"io"
	"math"
	"math/rand/v2"
	"os"
	"path/filepath"
	"runtime"
	"runtime/debug"
	"strconv"
	"strings"
	"time"

	"photonfarm/coordinator/photonmap"
)

func main() {
	n := flag.Int("n", 1000000, "photons")
	dist := flag.String("dist", "uniform", "uniform (in a unit box) or surfaces (a box's walls and a sphere, like a Cornell box)")
	out := flag.String("o", "", "output snapshot file (none: a temporary file, removed)")
	shardSize := flag.Int("shard", 250000, "photons per emission shard")
	seed := flag.Uint64("seed", 1, "random seed")
	flag.Parse()
	if err := run(*n, *dist, *out, *shardSize, *seed); err != nil {
		fmt.Fprintln(os.Stderr, "mksnapshot:", err)
		os.Exit(1)
	}
}

func run(n int, dist, out string, shardSize int, seed uint64) error {
	dir, err := os.MkdirTemp("", "mksnapshot-")
	if err != nil {
		return err
	}
	defer os.RemoveAll(dir)
	shards, err := writeShards(dir, n, dist, shardSize, seed)
	if err != nil {
		return err
	}
	if out == "" {
		out = filepath.Join(dir, "snapshot")
	}
	f, err := os.Create(out)
	if err != nil {
		return err
	}
	defer f.Close()
	// The shards' generation is not the build's: its garbage goes back to the system and
	// the high-water mark starts again from what the process holds now.
	debug.FreeOSMemory()
	before := resetPeakRSS()
	start := time.Now()
	size, err := photonmap.BuildTo(f, shards, math.MaxInt)
	elapsed := time.Since(start)
	if err != nil {
		return err
	}
	peak := peakRSS()
	fmt.Printf("go kd-tree build  %-8s %9d photons  %8.0f ms  %6.2f M photons/s  %5.1f B/photon  peak RSS %.0f MB, %.1f B/photon over the %.0f MB before  GOMAXPROCS=%d\n",
		dist, n, float64(elapsed.Microseconds())/1e3, float64(n)/elapsed.Seconds()/1e6,
		float64(size)/float64(max(n, 1)), float64(peak)/1e6, float64(peak-min(before, peak))/float64(max(n, 1)), float64(before)/1e6, runtime.GOMAXPROCS(0))
	return f.Close()
}

// writeShards writes n photons as emission shards of shardSize into dir, one file each,
// and returns them as the builder's sources: the builder reads them as it reads blobs,
// never holding one.
func writeShards(dir string, n int, dist string, shardSize int, seed uint64) ([]photonmap.Source, error) {
	r := rand.New(rand.NewPCG(seed, 0))
	var shards []photonmap.Source
	for first := 0; first < n; first += shardSize {
		count := min(shardSize, n-first)
		ps := make([]photonmap.ShardPhoton, count)
		for i := range ps {
			ps[i] = photon(r, dist)
		}
		path := filepath.Join(dir, fmt.Sprintf("shard-%09d", first))
		if err := os.WriteFile(path, photonmap.EncodeShard(photonmap.Global, uint64(first), uint64(count), ps), 0o644); err != nil {
			return nil, err
		}
		shards = append(shards, func() (io.ReadCloser, error) {
			f, err := os.Open(path)
			if err != nil {
				return nil, err
			}
			return struct {
				io.Reader
				io.Closer
			}{bufio.NewReaderSize(f, 1<<16), f}, nil
		})
	}
	return shards, nil
}

// resetPeakRSS starts the process's high-water mark again from its resident set now (Linux
// 4.0 and later) and returns that.
func resetPeakRSS() uint64 {
	os.WriteFile("/proc/self/clear_refs", []byte("5"), 0) // unsupported: the peak stays the process's
	return statusBytes("VmRSS:")
}

// peakRSS is the process's peak resident set (VmHWM) in bytes, 0 if unknown.
func peakRSS() uint64 { return statusBytes("VmHWM:") }

// statusBytes is a size field of /proc/self/status in bytes, 0 if unknown.
func statusBytes(field string) uint64 {
	status, err := os.ReadFile("/proc/self/status")
	if err != nil {
		return 0
	}
	for _, line := range strings.Split(string(status), "\n") {
		if rest, ok := strings.CutPrefix(line, field); ok {
			kb, _ := strconv.ParseUint(strings.TrimSuffix(strings.TrimSpace(rest), " kB"), 10, 64)
			return kb << 10
		}
	}
	return 0
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
