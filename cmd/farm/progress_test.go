package main

import (
	"strings"
	"testing"
	"time"

	"google.golang.org/protobuf/types/known/timestamppb"

	pb "photonfarm/proto/renderfarm/v1"
)

// t0 is when the test jobs were created and when the test clocks start.
var t0 = time.Date(2030, 1, 1, 0, 0, 0, 0, time.UTC)

// fakeClock is a settable time.
type fakeClock struct{ t time.Time }

func (c *fakeClock) now() time.Time { return c.t }

// testProgress is a progress display (a bar on a terminal, else lines) writing to out, at
// the time clk says: t0 until the test sets it.
func testProgress(terminal bool) (p *progress, clk *fakeClock, out *strings.Builder) {
	clk, out = &fakeClock{t0}, &strings.Builder{}
	return newProgress(out, terminal, clk.now, 1), clk, out
}

// testJob is job j1, created at t0, in state, with phases' progress.
func testJob(state pb.JobState, phases ...*pb.PhaseProgress) *pb.Job {
	return &pb.Job{Id: "j1", State: state, CreateTime: timestamppb.New(t0), Phases: phases}
}

// phase is the progress of a phase of total tasks, succeeded of them done.
func phase(p pb.Phase, total, succeeded uint32) *pb.PhaseProgress {
	return &pb.PhaseProgress{Phase: p, TasksTotal: total, TasksSucceeded: succeeded}
}

// tileJob is a job without photon mapping: 48 tiles and a composite.
func tileJob(state pb.JobState, render, composite uint32) *pb.Job {
	return testJob(state, phase(pb.Phase_PHASE_RENDER, 48, render), phase(pb.Phase_PHASE_COMPOSITE, 1, composite))
}

// photonJob is a job with all four phases: 4 emit shards, a build, 48 tiles, a composite.
func photonJob(state pb.JobState, emit, build, render, composite uint32) *pb.Job {
	return testJob(state, phase(pb.Phase_PHASE_EMIT, 4, emit), phase(pb.Phase_PHASE_BUILD, 1, build),
		phase(pb.Phase_PHASE_RENDER, 48, render), phase(pb.Phase_PHASE_COMPOSITE, 1, composite))
}

func TestProgressPlainLines(t *testing.T) {
	p, clk, out := testProgress(false)
	running := pb.JobState_JOB_STATE_RUNNING
	p.update(tileJob(running, 0, 0), time.Time{})
	clk.t = t0.Add(1 * time.Second)
	p.update(tileJob(running, 6, 0), time.Time{}) // within plainEvery of the last line: not printed
	clk.t = t0.Add(4 * time.Second)
	p.update(tileJob(running, 24, 0), time.Time{})
	clk.t = t0.Add(8 * time.Second)
	p.update(tileJob(running, 48, 0), time.Time{}) // a new phase is printed at once
	end := tileJob(pb.JobState_JOB_STATE_SUCCEEDED, 48, 1)
	end.EndTime = timestamppb.New(t0.Add(8500 * time.Millisecond))
	p.draw(true)
	p.observe(end, clk.t)
	p.draw(true)

	want := []string{
		// Weighted by task counts: 24 of 49 tasks is 48%, and 4 s for 48% leaves 4 s.
		"job j1: 0%, Render tiles 0/48 tiles, elapsed 0s",
		"job j1: 48%, Render tiles 24/48 tiles, elapsed 4s, ETA 4s",
		"job j1: 97%, Composite 0/1 tasks, elapsed 8s, ETA 0s",
		"job j1: succeeded (render 48/48, composite 1/1), took 8.5s",
	}
	got := strings.Split(strings.TrimRight(out.String(), "\n"), "\n")
	if strings.Join(got, "\n") != strings.Join(want, "\n") {
		t.Errorf("got\n%s\nwant\n%s", strings.Join(got, "\n"), strings.Join(want, "\n"))
	}
}

func TestProgressBarRedrawsInPlace(t *testing.T) {
	p, clk, out := testProgress(true)
	p.update(tileJob(pb.JobState_JOB_STATE_RUNNING, 0, 0), time.Time{})
	clk.t = t0.Add(3 * time.Second)
	p.update(tileJob(pb.JobState_JOB_STATE_RUNNING, 12, 0), time.Time{})
	s := out.String()
	frames := strings.Split(s, "\r")[1:]
	if len(frames) != 2 || strings.Contains(s, "\n") {
		t.Fatalf("output %q: want two frames, each starting with \\r, no newline", s)
	}
	last := frames[1]
	for _, want := range []string{"Render tiles", "[#####-------------------]", "12/48", "tiles", "24%", "elapsed 0:03", "ETA 0:09"} {
		if !strings.Contains(last, want) {
			t.Errorf("frame %q lacks %q", last, want)
		}
	}

	end := tileJob(pb.JobState_JOB_STATE_SUCCEEDED, 48, 1)
	end.EndTime = timestamppb.New(t0.Add(5 * time.Second))
	clk.t = t0.Add(6 * time.Second)
	p.update(end, time.Time{})
	frames = strings.Split(out.String(), "\r")
	last = frames[len(frames)-1]
	for _, want := range []string{"succeeded", "48/48", "tiles", "100%", "elapsed 0:05"} {
		if !strings.Contains(last, want) {
			t.Errorf("final frame %q lacks %q", last, want)
		}
	}
	if strings.Contains(last, "ETA") {
		t.Errorf("final frame %q shows an ETA", last)
	}
}

func TestProgressPlainLinesShowEveryPhase(t *testing.T) {
	p, clk, out := testProgress(false)
	running := pb.JobState_JOB_STATE_RUNNING
	for _, st := range []struct {
		at                             time.Duration
		emit, build, render, composite uint32
	}{
		{0, 0, 0, 0, 0}, {time.Second, 2, 0, 0, 0}, {2 * time.Second, 4, 0, 0, 0},
		{3 * time.Second, 4, 1, 0, 0}, {5 * time.Second, 4, 1, 48, 0},
	} {
		clk.t = t0.Add(st.at)
		p.update(photonJob(running, st.emit, st.build, st.render, st.composite), time.Time{})
	}
	end := photonJob(pb.JobState_JOB_STATE_SUCCEEDED, 4, 1, 48, 1)
	end.EndTime = timestamppb.New(t0.Add(6 * time.Second))
	p.observe(end, clk.t)
	p.draw(true)

	want := []string{
		// 54 tasks: 4 are 7%, 5 are 9%, 53 are 98%; the ETA smoothed over etaSmoothing.
		"job j1: 0%, Emit photons 0/4 shards, elapsed 0s",
		"job j1: 7%, Build photon map 0/1 tasks, elapsed 2s, ETA 25s",
		"job j1: 9%, Render tiles 0/48 tiles, elapsed 3s, ETA 25s",
		"job j1: 98%, Composite 0/1 tasks, elapsed 5s, ETA 14s",
		"job j1: succeeded (emit 4/4, build 1/1, render 48/48, composite 1/1), took 6s",
	}
	if got := strings.TrimRight(out.String(), "\n"); got != strings.Join(want, "\n") {
		t.Errorf("got\n%s\nwant\n%s", got, strings.Join(want, "\n"))
	}
}

func TestProgressBarNamesThePhaseAndItsPlace(t *testing.T) {
	tests := []struct {
		job  *pb.Job
		want []string
	}{
		{photonJob(pb.JobState_JOB_STATE_RUNNING, 1, 0, 0, 0), []string{"Emit photons 1/4", "1/4", "shards", " 1%"}},
		{photonJob(pb.JobState_JOB_STATE_RUNNING, 4, 0, 0, 0), []string{"Build photon map 2/4", "0/1", "tasks"}},
		{photonJob(pb.JobState_JOB_STATE_RUNNING, 4, 1, 12, 0), []string{"Render tiles 3/4", "12/48", "tiles", "31%"}},
		{photonJob(pb.JobState_JOB_STATE_SUCCEEDED, 4, 1, 48, 1), []string{"succeeded", "48/48", "tiles", "100%"}},
	}
	for _, tt := range tests {
		p, _, out := testProgress(true)
		p.update(tt.job, time.Time{})
		for _, w := range tt.want {
			if !strings.Contains(out.String(), w) {
				t.Errorf("frame %q lacks %q", out.String(), w)
			}
		}
	}
}

func TestTaskWorkDescribesTilesAndShards(t *testing.T) {
	for _, tt := range []struct {
		task *pb.Task
		want string
	}{
		{&pb.Task{Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{Rect: &pb.PixelRect{X: 32, Width: 16, Height: 8}}}}, "16x8+32+0"},
		{&pb.Task{Spec: &pb.Task_EmitPhotons{EmitPhotons: &pb.EmitPhotonsSpec{Map: pb.PhotonMapKind_PHOTON_MAP_KIND_CAUSTIC,
			FirstPhoton: 10000, PhotonCount: 10000, TotalPhotons: 40000}}}, "caustic 10000+10000/40000"},
		{&pb.Task{Spec: &pb.Task_EmitPhotons{EmitPhotons: &pb.EmitPhotonsSpec{Map: pb.PhotonMapKind_PHOTON_MAP_KIND_VOLUME,
			FirstPhoton: 200000, PhotonCount: 50000, TotalPhotons: 200000}}}, "volume 200000+50000/200000"},
		{&pb.Task{Spec: &pb.Task_BuildPhotonMap{BuildPhotonMap: &pb.BuildPhotonMapSpec{}}}, ""},
	} {
		if got := taskWork(tt.task); got != tt.want {
			t.Errorf("taskWork(%v) = %q, want %q", tt.task, got, tt.want)
		}
	}
}
