// Command fgbench is the benchmark of issue 4's acceptance 1: through a real local farm
// (`farm coordinator` and farm-worker processes), it renders a converged reference of a
// scene with final gathering (many progressive rounds within a few minutes), then, at each
// wall-clock budget, the same scene with final gathering and with the global photon map
// seen directly (PHOTON_MAP mode), both progressive within the budget and both told the
// reference so that the farm itself reports their RMSE against it. It prints, per budget,
// the RMSE of the image each method had within the budget and the ratio.
//
//	go run ./bench/cmd/fgbench -bin build/bin [-scene scenes/cornell-box.json]
package main

import (
	"bufio"
	"context"
	"errors"
	"flag"
	"fmt"
	"os"
	"os/exec"
	"os/signal"
	"path/filepath"
	"strconv"
	"strings"
	"syscall"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

func main() {
	bin := flag.String("bin", "build/bin", "folder with farm and farm-worker")
	scenePath := flag.String("scene", "scenes/cornell-box.json", "scene file")
	size := flag.Uint("size", 128, "film width and height in pixels")
	workers := flag.Int("workers", 2, "farm-worker processes (one thread each)")
	refBudget := flag.Duration("reference-budget", 150*time.Second, "time budget of the reference render")
	budgetList := flag.String("budgets", "10s,60s", "comma-separated wall-clock budgets to compare at")
	photons := flag.Uint64("photons", 100000, "global photon paths per round")
	flag.Parse()
	var budgets []time.Duration
	for _, s := range strings.Split(*budgetList, ",") {
		d, err := time.ParseDuration(strings.TrimSpace(s))
		if err != nil {
			fail(fmt.Errorf("-budgets: %w", err))
		}
		budgets = append(budgets, d)
	}
	ctx, stop := signal.NotifyContext(context.Background(), os.Interrupt, syscall.SIGTERM)
	defer stop()
	if err := run(ctx, *bin, *scenePath, uint32(*size), *workers, *refBudget, budgets, *photons); err != nil {
		fail(err)
	}
}

func fail(err error) {
	fmt.Fprintln(os.Stderr, "fgbench:", err)
	os.Exit(1)
}

// farm is a coordinator and its workers, as processes.
type farm struct {
	procs []*exec.Cmd
	c     *client.Client
}

func startFarm(ctx context.Context, bin string, workers int, dir string) (*farm, error) {
	f := &farm{}
	coord := exec.CommandContext(ctx, filepath.Join(bin, "farm"), "coordinator", "--listen", "127.0.0.1:0", "--data-dir", filepath.Join(dir, "data"))
	stderr, err := coord.StderrPipe()
	if err != nil {
		return nil, err
	}
	if err := coord.Start(); err != nil {
		return nil, err
	}
	f.procs = append(f.procs, coord)
	addrc := make(chan string, 1)
	go func() {
		sc := bufio.NewScanner(stderr)
		for sc.Scan() {
			if _, addr, ok := strings.Cut(sc.Text(), "coordinator listening on "); ok {
				addrc <- strings.TrimSpace(addr)
			}
		}
	}()
	var addr string
	select {
	case addr = <-addrc:
	case <-time.After(20 * time.Second):
		f.stop()
		return nil, errors.New("the coordinator did not start listening within 20s")
	}
	for i := range workers {
		w := exec.CommandContext(ctx, filepath.Join(bin, "farm-worker"), "--coordinator", addr, "--threads", "1",
			"--cache-dir", filepath.Join(dir, "cache"), "--name", fmt.Sprintf("bench-%d", i+1))
		if err := w.Start(); err != nil {
			f.stop()
			return nil, err
		}
		f.procs = append(f.procs, w)
	}
	if f.c, err = client.Dial(addr); err != nil {
		f.stop()
		return nil, err
	}
	return f, nil
}

// stop ends the workers, then the coordinator, with SIGTERM, and waits for them.
func (f *farm) stop() {
	if f.c != nil {
		f.c.Close()
	}
	for i := len(f.procs) - 1; i >= 0; i-- {
		p := f.procs[i]
		_ = p.Process.Signal(syscall.SIGTERM)
		done := make(chan struct{})
		go func() { _ = p.Wait(); close(done) }()
		select {
		case <-done:
		case <-time.After(10 * time.Second):
			_ = p.Process.Kill()
			<-done
		}
	}
}

// render submits sc, waits for the job to succeed and returns it.
func (f *farm) render(ctx context.Context, sc *pb.Scene) (*pb.Job, error) {
	job, err := f.c.Submit(ctx, sc)
	if err != nil {
		return nil, err
	}
	job, err = f.c.Watch(ctx, job.GetId(), nil)
	if err != nil {
		return nil, err
	}
	if job.GetState() != pb.JobState_JOB_STATE_SUCCEEDED {
		return nil, fmt.Errorf("job %s ended %s: %s", job.GetId(), job.GetState(), job.GetError())
	}
	return job, nil
}

func run(ctx context.Context, bin, scenePath string, size uint32, workers int, refBudget time.Duration, budgets []time.Duration, photons uint64) error {
	dir, err := os.MkdirTemp("", "fgbench-")
	if err != nil {
		return err
	}
	defer os.RemoveAll(dir)
	f, err := startFarm(ctx, bin, workers, dir)
	if err != nil {
		return err
	}
	defer f.stop()
	base, err := f.c.LoadSceneFile(ctx, scenePath)
	if err != nil {
		return err
	}
	base.Film.Width, base.Film.Height, base.Film.TileSize = size, size, 32
	base.Sampling.SamplesPerPixel = 1
	if base.Photons == nil {
		base.Photons = &pb.PhotonMapping{}
	}
	base.Photons.GlobalPhotons, base.Photons.PhotonsPerShard = photons, photons/2

	variant := func(mode pb.IndirectMode, budget time.Duration, reference string) *pb.Scene {
		sc := proto.Clone(base).(*pb.Scene)
		sc.Indirect = &pb.Indirect{Mode: mode}
		sc.Progressive = &pb.Progressive{MaxRounds: 1000, TimeBudgetSeconds: budget.Seconds()}
		if reference != "" {
			sc.Progressive.Reference = &pb.ReferenceImage{Digest: reference}
		}
		return sc
	}

	fmt.Printf("scene %s at %dx%d, 1 sample per pixel and %d global photon paths per round, %d workers of 1 thread\n",
		scenePath, size, size, photons, workers)
	fmt.Printf("reference: final gathering, progressive rounds for %s ...\n", refBudget)
	// The reference draws other photons and pixel samples (another seed), so that the runs
	// measured against it do not share its noise.
	refScene := variant(pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER, refBudget, "")
	refScene.Sampling.Seed += 1_000_003
	ref, err := f.render(ctx, refScene)
	if err != nil {
		return fmt.Errorf("reference: %w", err)
	}
	refDigest := ""
	for _, a := range ref.GetOutputs() {
		if a.GetName() == "image.exr" {
			refDigest = a.GetDigest()
		}
	}
	last := ref.GetRounds()[len(ref.GetRounds())-1]
	fmt.Printf("reference: %d rounds, %.0f s, %d samples per pixel, %s photon paths, error estimate %s\n\n",
		len(ref.GetRounds()), last.GetElapsedSeconds(), last.GetSamplesPerPixel(), grouped(last.GetPhotons()), opt(last.ErrorEstimate))

	fmt.Printf("%-8s  %-32s  %-32s  %s\n", "budget", "final gathering: RMSE (rounds, s)", "photon map seen directly: RMSE", "ratio PM/FG")
	for _, b := range budgets {
		var rmse [2]float64
		var cells [2]string
		for i, mode := range []pb.IndirectMode{pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER, pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP} {
			job, err := f.render(ctx, variant(mode, b, refDigest))
			if err != nil {
				return fmt.Errorf("%s at %s: %w", mode, b, err)
			}
			r := withinBudget(job.GetRounds(), b)
			rmse[i] = r.GetReferenceRmse()
			cells[i] = fmt.Sprintf("%.5f (%d, %.1f s)", rmse[i], r.GetRound(), r.GetElapsedSeconds())
		}
		fmt.Printf("%-8s  %-32s  %-32s  %.2fx\n", b, cells[0], cells[1], rmse[1]/rmse[0])
	}
	fmt.Println("\nEach RMSE is the farm's reference_rmse of the last round finished within the budget")
	fmt.Println("(the first round if none was); the ratio above 1 means final gathering is closer.")
	return nil
}

// withinBudget is the last round that ended within b, or the first round.
func withinBudget(rounds []*pb.RoundReport, b time.Duration) *pb.RoundReport {
	best := rounds[0]
	for _, r := range rounds {
		if r.GetElapsedSeconds() <= b.Seconds() {
			best = r
		}
	}
	return best
}

func opt(v *float64) string {
	if v == nil {
		return "-"
	}
	return strconv.FormatFloat(*v, 'g', 4, 64)
}

func grouped(n uint64) string {
	s := strconv.FormatUint(n, 10)
	var b strings.Builder
	for i := range len(s) {
		if i > 0 && (len(s)-i)%3 == 0 {
			b.WriteByte(',')
		}
		b.WriteByte(s[i])
	}
	return b.String()
}
