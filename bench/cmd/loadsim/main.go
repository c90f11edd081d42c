// Command loadsim is the coordinator's load simulation (issue 17, acceptance 4): real
// `farm coordinator` processes (1 or more replicas) on a real redis-server, and N
// simulated workers as goroutines speaking the real gRPC worker protocol (register,
// lease, heartbeat, upload a tiny tile, complete) against render-only jobs of 65,536
// tiles. For each N it prints leases per second, LeaseTask and CompleteTask latency
// percentiles, and each coordinator's CPU seconds and peak resident memory (/proc), with
// MISSED when N = 1000 falls short of 5,000 leases/s with LeaseTask p99 under 20 ms.
//
//	loadsim -bin build/bin [-workers 10,100,1000] [-replicas 1] [-duration 20s] [-profile DIR]
package main

import (
	"context"
	"flag"
	"fmt"
	"os"
	"os/exec"
	"strconv"
	"strings"
	"sync"
	"time"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

const (
	targetLeases = 5000
	targetP99    = 20 * time.Millisecond
	targetN      = 1000
)

func main() {
	bin := flag.String("bin", "build/bin", "folder holding the farm binary")
	workers := flag.String("workers", "10,100,1000", "simulated worker counts, comma-separated")
	replicas := flag.Int("replicas", 1, "coordinator replicas on the one Redis; workers are spread over them")
	profile := flag.String("profile", "", "write each coordinator's CPU profile to this folder (coordinator-I.pprof, the last worker count's)")
	upload := flag.Bool("upload", true, "upload a tile of its own for every task (false: one shared tile, stored once, so blob writes are left out)")
	duration := flag.Duration("duration", 20*time.Second, "how long each worker count runs")
	flag.Parse()
	for _, s := range strings.Split(*workers, ",") {
		n, err := strconv.Atoi(strings.TrimSpace(s))
		if err != nil || n < 1 {
			fail(fmt.Errorf("-workers: %q is not a positive count", s))
		}
		if err := run(*bin, n, *replicas, *duration, *profile, *upload); err != nil {
			fail(err)
		}
	}
}

func fail(err error) {
	fmt.Fprintln(os.Stderr, "loadsim:", err)
	os.Exit(1)
}

// scene is render-only (one sphere under a point light: no surface lights another, so
// no photon map), 2048x2048 in 8-pixel tiles: 65,536 render tiles, the most a round takes.
func scene() *pb.Scene {
	v := func(x, y, z float64) *pb.Vec3 { return &pb.Vec3{X: x, Y: y, Z: z} }
	return &pb.Scene{
		Name:   "loadsim",
		Camera: &pb.Camera{Position: v(0, 0, 5), LookAt: v(0, 0, 0), Up: v(0, 1, 0), VerticalFovDegrees: 40},
		Film:   &pb.Film{Width: 2048, Height: 2048, TileSize: 8},
		Materials: []*pb.Material{{Name: "white", Kind: &pb.Material_Lambert{Lambert: &pb.Lambert{
			Reflectance: &pb.Color{R: 0.5, G: 0.5, B: 0.5}}}}},
		Shapes: []*pb.Shape{{Name: "ball", Material: "white", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: v(0, 0, 0), Radius: 1}}}},
		Lights: []*pb.Light{{Name: "lamp", Kind: &pb.Light_Point{Point: &pb.PointLight{
			Position: v(3, 3, 3), Intensity: &pb.Color{R: 10, G: 10, B: 10}}}}},
	}
}

func run(bin string, n, replicas int, duration time.Duration, profileDir string, upload bool) error {
	dir, err := os.MkdirTemp("", "loadsim-")
	if err != nil {
		return err
	}
	defer os.RemoveAll(dir)
	ctx, cancel := context.WithCancel(context.Background())
	defer cancel()
	f, err := startFarm(ctx, bin, dir, replicas, profileDir)
	if err != nil {
		return err
	}
	defer f.stop()
	c, err := client.Dial(f.addrs[0])
	if err != nil {
		return err
	}
	defer c.Close()
	// Enough tiles for the run at twice the target rate, in 65,536-tile jobs.
	jobs := int(duration.Seconds()*2*targetLeases)/65536 + 1
	for range jobs {
		if _, err := c.Submit(ctx, scene()); err != nil {
			return fmt.Errorf("submit: %w", err)
		}
	}
	procs := append(append([]*exec.Cmd{}, f.coords...), f.redis)
	before := make([]usage, len(procs))
	for i, cmd := range procs {
		if before[i], err = procUsage(cmd.Process.Pid); err != nil {
			return err
		}
	}
	st := &stats{}
	runCtx, stop := context.WithTimeout(ctx, duration)
	defer stop()
	var wg sync.WaitGroup
	start := time.Now()
	for i := range n {
		wg.Add(1)
		go func() {
			defer wg.Done()
			simWorker(runCtx, f.addrs[i%len(f.addrs)], i, upload, st)
		}()
	}
	wg.Wait()
	elapsed := time.Since(start)
	rate := float64(len(st.lease)) / elapsed.Seconds()
	p99 := percentile(st.lease, 99)
	fmt.Printf("N=%d replicas=%d upload=%v: %d leases in %.1fs = %.0f leases/s (%d empty long polls)\n",
		n, replicas, upload, len(st.lease), elapsed.Seconds(), rate, st.empty)
	fmt.Printf("  LeaseTask    p50 %v  p90 %v  p99 %v\n", percentile(st.lease, 50).Round(10*time.Microsecond),
		percentile(st.lease, 90).Round(10*time.Microsecond), p99.Round(10*time.Microsecond))
	fmt.Printf("  CompleteTask p50 %v  p90 %v  p99 %v  (%d)\n", percentile(st.complete, 50).Round(10*time.Microsecond),
		percentile(st.complete, 90).Round(10*time.Microsecond), percentile(st.complete, 99).Round(10*time.Microsecond), len(st.complete))
	for i, cmd := range procs {
		u, err := procUsage(cmd.Process.Pid)
		if err != nil {
			return err
		}
		name := fmt.Sprintf("coordinator %d", i)
		if cmd == f.redis {
			name = "redis-server"
		}
		fmt.Printf("  %s: %.1f CPU s in the run, peak RSS %d MiB\n", name, (u.cpu - before[i].cpu).Seconds(), u.peakKB/1024)
	}
	twice := 0
	for _, k := range st.done {
		if k > 1 {
			twice++
		}
	}
	fmt.Printf("  tasks completed more than once: %d\n", twice)
	for e, k := range st.errors {
		fmt.Printf("  error x%d: %s\n", k, e)
	}
	if n == targetN {
		verdict := "met"
		if rate < targetLeases || p99 >= targetP99 {
			verdict = "MISSED"
		}
		fmt.Printf("  target %d leases/s with LeaseTask p99 < %v at N=%d: %s (%.0f leases/s, p99 %v)\n",
			targetLeases, targetP99, targetN, verdict, rate, p99.Round(10*time.Microsecond))
	}
	return nil
}
