package integration

import (
	"encoding/xml"
	"math"
	"os"
	"path/filepath"
	"regexp"
	"strconv"
	"strings"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// progressiveCaustics is scenes/test-caustics.json made quick for rounds: 32x32 in tiles
// of 16, one sample per pixel, 8 gather rays, and 10,000 global and caustic photon paths
// per round in one shard each.
func progressiveCaustics(t *testing.T, f *farmtest.Farm, maxRounds uint32, target float64) *pb.Scene {
	sc := f.LoadScene(t, causticsFile)
	sc.Film.Width, sc.Film.Height, sc.Film.TileSize = 32, 32, 16
	sc.Sampling.SamplesPerPixel = 1
	sc.Photons.GlobalPhotons, sc.Photons.CausticPhotons, sc.Photons.PhotonsPerShard = 10000, 10000, 10000
	sc.Indirect = &pb.Indirect{GatherRays: 8, SecondaryGatherRays: 2}
	sc.Progressive = &pb.Progressive{MaxRounds: maxRounds, TargetError: target}
	return sc
}

// The fields a round's row of `farm report`'s table splits into: round, seconds, photons,
// samples/px, estimated error, 95% interval, of it bias, reference RMSE (then a column
// for each measured layer).
const (
	reportColumns         = 8
	reportReferenceColumn = 7
)

// errorEstimate is round r's estimated error, which must be positive and come with its
// bias part (at most the estimate) and a 95% interval that holds it.
func errorEstimate(t *testing.T, r *pb.RoundReport) float64 {
	t.Helper()
	if r.ErrorEstimate == nil || math.IsNaN(r.GetErrorEstimate()) || r.GetErrorEstimate() <= 0 {
		t.Fatalf("round %d has no positive error estimate: %v", r.GetRound(), r)
	}
	e := r.GetErrorEstimate()
	if r.ErrorEstimateBias == nil || !(r.GetErrorEstimateBias() >= 0 && r.GetErrorEstimateBias() <= e) {
		t.Errorf("round %d: estimated error %.5g with bias part %v, want one within [0, the estimate]", r.GetRound(), e, r.ErrorEstimateBias)
	}
	if r.ErrorEstimateLow == nil || r.ErrorEstimateHigh == nil ||
		!(r.GetErrorEstimateLow() > 0 && r.GetErrorEstimateLow() <= e && e <= r.GetErrorEstimateHigh()) {
		t.Errorf("round %d: estimated error %.5g with 95%% interval %v-%v, want a positive one that holds it",
			r.GetRound(), e, r.ErrorEstimateLow, r.ErrorEstimateHigh)
	}
	return e
}

// TestProgressiveRoundsReportFallingErrorAndTargetStopsTheJob runs a 4-round job (error
// falling from round 2 to round 4, `farm report` printing the rounds and writing the
// plot), then the same scene with a target between the round-2 and round-4 errors and up
// to 8 rounds: rounds are deterministic, so it must stop by itself at round 3 or 4.
func TestProgressiveRoundsReportFallingErrorAndTargetStopsTheJob(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	f.StartWorker(t)
	f.StartWorker(t)
	job := f.Render(t, progressiveCaustics(t, f, 4, 0), 180*time.Second)

	rounds := job.GetRounds()
	if len(rounds) != 4 {
		t.Fatalf("job has %d rounds, want 4: %v", len(rounds), rounds)
	}
	for i, r := range rounds {
		want := uint32(i + 1)
		if r.GetRound() != want || r.GetSamplesPerPixel() != uint64(want) || r.GetPhotons() != 20000*uint64(want) {
			t.Errorf("round %d = %v, want round %d with %d samples and %d photons", i, r, want, want, 20000*want)
		}
		if i > 0 && r.GetElapsedSeconds() <= rounds[i-1].GetElapsedSeconds() {
			t.Errorf("round %d ended at %.3fs, not after round %d (%.3fs)", want, r.GetElapsedSeconds(), i, rounds[i-1].GetElapsedSeconds())
		}
	}
	if rounds[0].ErrorEstimate != nil {
		t.Errorf("round 1 has an error estimate (%v); it needs two rounds", rounds[0].GetErrorEstimate())
	}
	e2, e4 := errorEstimate(t, rounds[1]), errorEstimate(t, rounds[3])
	if e4 >= e2 {
		t.Errorf("error estimate rose from %.5g (round 2) to %.5g (round 4)", e2, e4)
	}
	tasks := f.Tasks(t, job.GetId())
	if n := len(farmtest.TasksOf(tasks, pb.Phase_PHASE_PRECOMPUTE)); n != 4 {
		t.Errorf("%d precompute tasks, want one per round", n)
	}
	for _, a := range job.GetOutputs() {
		if a.GetName() == "accumulation.exr" {
			t.Errorf("the job's outputs include the accumulation: %v", job.GetOutputs())
		}
	}
	if err := checkFinalEXR(f.Output(t, job, "image.exr"), 32, 32, 16, aovChannels...); err != nil {
		t.Error(err)
	}

	plot := filepath.Join(t.TempDir(), "plot.svg")
	code, stdout, stderr := farmtest.RunFarm(t, 30*time.Second, nil, "report", job.GetId(), "-o", plot, "--coordinator", f.Addr)
	if code != 0 {
		t.Fatalf("farm report: exit %d, stderr %s", code, stderr)
	}
	var rows int
	for _, line := range strings.Split(stdout, "\n") {
		fields := strings.Fields(line)
		if len(fields) == reportColumns {
			if n, err := strconv.Atoi(fields[0]); err == nil && n == rows+1 {
				rows++
			}
		}
	}
	if rows != 4 || !strings.Contains(stdout, "estimated error") || !strings.Contains(stdout, strconv.FormatFloat(e4, 'g', 4, 64)) {
		t.Errorf("farm report printed %d round rows, want 4 with the round-4 error %.4g:\n%s", rows, e4, stdout)
	}
	t.Logf("farm report:\n%s", stdout)
	svg, err := os.ReadFile(plot)
	if err != nil {
		t.Fatal(err)
	}
	if n := countPoints(t, svg); n != 3 {
		t.Errorf("plot has %d points, want 3 (rounds 2 to 4 have an error estimate)", n)
	}

	target := math.Sqrt(e2 * e4) // between the two
	stopped := f.Render(t, progressiveCaustics(t, f, 8, target), 180*time.Second)
	got := stopped.GetRounds()
	if len(got) < 3 || len(got) > 4 {
		t.Fatalf("target %.5g: job ran %d rounds, want it to stop at round 3 or 4", target, len(got))
	}
	last := errorEstimate(t, got[len(got)-1])
	if last > target {
		t.Errorf("job stopped at round %d with error %.5g above the target %.5g", len(got), last, target)
	}
	if prev := errorEstimate(t, got[len(got)-2]); len(got) > 2 && prev <= target {
		t.Errorf("job went on after round %d whose error %.5g already met the target %.5g", len(got)-1, prev, target)
	}
}

// countPoints parses svg as XML and counts its round markers.
func countPoints(t *testing.T, svg []byte) int {
	t.Helper()
	dec := xml.NewDecoder(strings.NewReader(string(svg)))
	n := 0
	for {
		tok, err := dec.Token()
		if err != nil {
			if err.Error() == "EOF" {
				return n
			}
			t.Fatalf("plot is not well-formed XML: %v", err)
		}
		if el, ok := tok.(xml.StartElement); ok {
			for _, a := range el.Attr {
				if a.Name.Local == "class" && a.Value == "point" {
					n++
				}
			}
		}
	}
}

// farm plan needs no coordinator: $FARM_COORDINATOR names one that is not there.
func TestPlanOfCornellScenesSaysWhichCausticMapRuns(t *testing.T) {
	noCoordinator := []string{"FARM_COORDINATOR=" + farmtest.ClosedAddress(t)}
	tests := []struct {
		scene, want string
	}{
		{"cornell-box.json", `(?m)^\s*skip\s+caustic photon map\s+no specular surface \(mirror, glass, metal\)$`},
		{"cornell-caustics.json", `(?m)^\s*run\s+caustic photon map\s+\S`},
	}
	for _, tt := range tests {
		code, stdout, stderr := farmtest.RunFarm(t, 30*time.Second, noCoordinator, "plan", filepath.Join(farmtest.RepoRoot(), "scenes", tt.scene))
		if code != 0 {
			t.Fatalf("farm plan %s: exit %d, stderr %s", tt.scene, code, stderr)
		}
		if !regexp.MustCompile(tt.want).MatchString(stdout) {
			t.Errorf("farm plan %s does not say %q:\n%s", tt.scene, tt.want, stdout)
		}
		for _, pass := range []string{"global photon map", "irradiance precompute", "final gathering", "direct lighting", "edge antialiasing", "progressive rounds", "tasks per phase"} {
			if !strings.Contains(stdout, pass) {
				t.Errorf("farm plan %s does not mention %q:\n%s", tt.scene, pass, stdout)
			}
		}
	}
}
