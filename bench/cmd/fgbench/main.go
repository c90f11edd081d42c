// Command fgbench is the benchmark of issue 4's acceptance 1: through a real local farm
// (`farm coordinator` and farm-worker processes), it renders a converged reference of a
// scene with final gathering (many progressive rounds within a few minutes), then, at each
// wall-clock budget, the same scene with final gathering and with the global photon map
// seen directly (PHOTON_MAP mode), both progressive within the budget and both told the
// reference so that the farm itself reports their RMSE against it. It prints, per budget,
// the RMSE of the indirect layer (the light final gathering computes) and of the beauty
// that each method had within the budget, and the ratios; it exits 1 unless final
// gathering's indirect light is the closer at every budget.
//
//	go run ./bench/cmd/fgbench -bin build/bin [-scene scenes/cornell-box.json]
//	    [-reference ref.exr | -save-reference ref.exr] [-gather-rays N]
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
	gatherRays := flag.Uint("gather-rays", 0, "final gathering's gather rays per camera sample (0: the scene's)")
	reference := flag.String("reference", "", "reuse this reference EXR instead of rendering one")
	saveReference := flag.String("save-reference", "", "write the rendered reference EXR here")
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
	opts := options{bin: *bin, scene: *scenePath, size: uint32(*size), workers: *workers, refBudget: *refBudget,
		budgets: budgets, photons: *photons, gatherRays: uint32(*gatherRays), reference: *reference, saveReference: *saveReference}
	if err := run(ctx, opts); err != nil {
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

// options are the command's flags.
type options struct {
	bin, scene               string
	size                     uint32
	workers                  int
	refBudget                time.Duration
	budgets                  []time.Duration
	photons                  uint64
	gatherRays               uint32
	reference, saveReference string
}

func run(ctx context.Context, o options) error {
	dir, err := os.MkdirTemp("", "fgbench-")
	if err != nil {
		return err
	}
	defer os.RemoveAll(dir)
	f, err := startFarm(ctx, o.bin, o.workers, dir)
	if err != nil {
		return err
	}
	defer f.stop()
	base, err := f.c.LoadSceneFile(ctx, o.scene)
	if err != nil {
		return err
	}
	base.Film.Width, base.Film.Height, base.Film.TileSize = o.size, o.size, 32
	base.Sampling.SamplesPerPixel = 1
	if base.Photons == nil {
		base.Photons = &pb.PhotonMapping{}
	}
	base.Photons.GlobalPhotons, base.Photons.PhotonsPerShard = o.photons, o.photons/2

	variant := func(mode pb.IndirectMode, budget time.Duration, reference string) *pb.Scene {
		sc := proto.Clone(base).(*pb.Scene)
		sc.Indirect = &pb.Indirect{Mode: mode, GatherRays: o.gatherRays}
		sc.Progressive = &pb.Progressive{MaxRounds: 1000, TimeBudgetSeconds: budget.Seconds()}
		if reference != "" {
			sc.Progressive.Reference = &pb.ReferenceImage{Digest: reference}
		}
		return sc
	}

	fmt.Printf("scene %s at %dx%d, 1 sample per pixel and %d global photon paths per round, %d workers of 1 thread\n",
		o.scene, o.size, o.size, o.photons, o.workers)
	refDigest, err := reference(ctx, f, o, variant(pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER, o.refBudget, ""))
	if err != nil {
		return fmt.Errorf("reference: %w", err)
	}

	// Final gathering computes the indirect light, so the verdict is on the indirect layer;
	// the beauty's RMSE is printed too, though both methods share its direct light and its
	// emitter edges.
	fmt.Printf("%-8s  %-8s  %-30s  %-30s  %s\n", "budget", "measure", "final gathering (rounds, s)", "photon map seen directly", "PM/FG")
	failed := false
	for _, b := range o.budgets {
		var at [2]*pb.RoundReport
		for i, mode := range []pb.IndirectMode{pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER, pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP} {
			job, err := f.render(ctx, variant(mode, b, refDigest))
			if err != nil {
				return fmt.Errorf("%s at %s: %w", mode, b, err)
			}
			at[i] = withinBudget(job.GetRounds(), b)
		}
		indirect := func(r *pb.RoundReport) float64 { return r.GetLayerReferenceRmse()["indirect"] }
		beauty := func(r *pb.RoundReport) float64 { return r.GetReferenceRmse() }
		for _, m := range []struct {
			name string
			rmse func(*pb.RoundReport) float64
		}{{"indirect", indirect}, {"beauty", beauty}} {
			fg, pm := m.rmse(at[0]), m.rmse(at[1])
			fmt.Printf("%-8s  %-8s  %-30s  %-30s  %.2fx\n", b, m.name,
				fmt.Sprintf("%.5f (%d, %.1f s)", fg, at[0].GetRound(), at[0].GetElapsedSeconds()),
				fmt.Sprintf("%.5f (%d, %.1f s)", pm, at[1].GetRound(), at[1].GetElapsedSeconds()), pm/fg)
		}
		if fg, pm := indirect(at[0]), indirect(at[1]); fg > 0 && fg < pm {
			fmt.Printf("PASS: at %s final gathering's indirect light is closer to the reference (%.2fx)\n", b, pm/fg)
		} else {
			fmt.Printf("FAIL: at %s final gathering's indirect light is not closer to the reference\n", b)
			failed = true
		}
	}
	fmt.Println("\nEach RMSE is the farm's, of the last round finished within the budget (the first")
	fmt.Println("round if none was): of the indirect layer and of the beauty, against the reference's.")
	fmt.Println("A ratio above 1 means final gathering is closer.")
	if failed {
		return errors.New("final gathering did not beat the photon map at every budget")
	}
	return nil
}

// reference is the digest of the converged image the runs are measured against: the file
// of -reference uploaded, or sc rendered for -reference-budget (and saved to
// -save-reference).
func reference(ctx context.Context, f *farm, o options, sc *pb.Scene) (string, error) {
	if o.reference != "" {
		fmt.Printf("reference: %s\n\n", o.reference)
		return f.c.UploadFile(ctx, o.reference)
	}
	fmt.Printf("reference: final gathering, progressive rounds for %s ...\n", o.refBudget)
	// The reference draws other photons and pixel samples (another seed), so that the runs
	// measured against it do not share its noise.
	sc.Sampling.Seed += 1_000_003
	ref, err := f.render(ctx, sc)
	if err != nil {
		return "", err
	}
	digest := ""
	for _, a := range ref.GetOutputs() {
		if a.GetName() == "image.exr" {
			digest = a.GetDigest()
		}
	}
	last := ref.GetRounds()[len(ref.GetRounds())-1]
	fmt.Printf("reference: %d rounds, %.0f s, %d samples per pixel, %s photon paths, error estimate %s\n\n",
		len(ref.GetRounds()), last.GetElapsedSeconds(), last.GetSamplesPerPixel(), client.FormatCount(last.GetPhotons()), client.FormatMetric(last.ErrorEstimate))
	if o.saveReference != "" {
		out, err := os.Create(o.saveReference)
		if err != nil {
			return "", err
		}
		defer out.Close()
		if _, err := f.c.Download(ctx, digest, out); err != nil {
			return "", err
		}
	}
	return digest, nil
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
