package main

import (
	"strings"
	"testing"
	"time"

	"google.golang.org/protobuf/types/known/timestamppb"

	pb "photonfarm/proto/renderfarm/v1"
)

// photonJob is a job with all four phases: 4 emit shards, a build, 48 tiles, a composite.
func photonJob(state pb.JobState, created time.Time, emit, build, render, composite uint32) *pb.Job {
	return &pb.Job{
		Id: "j2", State: state, CreateTime: timestamppb.New(created),
		Phases: []*pb.PhaseProgress{
			{Phase: pb.Phase_PHASE_EMIT, TasksTotal: 4, TasksSucceeded: emit},
			{Phase: pb.Phase_PHASE_BUILD, TasksTotal: 1, TasksSucceeded: build},
			{Phase: pb.Phase_PHASE_RENDER, TasksTotal: 48, TasksSucceeded: render},
			{Phase: pb.Phase_PHASE_COMPOSITE, TasksTotal: 1, TasksSucceeded: composite},
		},
	}
}

func TestProgressPlainLinesShowEveryPhase(t *testing.T) {
	t0 := time.Date(2030, 1, 1, 0, 0, 0, 0, time.UTC)
	clk := &fakeClock{t0}
	var out strings.Builder
	p := newProgress(&out, false, clk.now)
	running := pb.JobState_JOB_STATE_RUNNING
	for _, st := range []struct {
		at                             time.Duration
		emit, build, render, composite uint32
	}{
		{0, 0, 0, 0, 0}, {time.Second, 2, 0, 0, 0}, {2 * time.Second, 4, 0, 0, 0},
		{3 * time.Second, 4, 1, 0, 0}, {5 * time.Second, 4, 1, 48, 0},
	} {
		clk.t = t0.Add(st.at)
		p.update(photonJob(running, t0, st.emit, st.build, st.render, st.composite))
	}
	end := photonJob(pb.JobState_JOB_STATE_SUCCEEDED, t0, 4, 1, 48, 1)
	end.EndTime = timestamppb.New(t0.Add(6 * time.Second))
	p.observe(end)
	p.draw(true)

	want := []string{
		"job j2: Emit photons 0/4 shards (0%), elapsed 0s",
		"job j2: Build photon map 0/1 tasks (0%), elapsed 2s",
		"job j2: Render tiles 0/48 tiles (0%), elapsed 3s",
		"job j2: Composite 0/1 tasks (0%), elapsed 5s",
		"job j2: succeeded (emit 4/4, build 1/1, render 48/48, composite 1/1), took 6s",
	}
	if got := strings.TrimRight(out.String(), "\n"); got != strings.Join(want, "\n") {
		t.Errorf("got\n%s\nwant\n%s", got, strings.Join(want, "\n"))
	}
}

func TestProgressBarNamesThePhaseAndItsPlace(t *testing.T) {
	t0 := time.Date(2030, 1, 1, 0, 0, 0, 0, time.UTC)
	clk := &fakeClock{t0}
	tests := []struct {
		job  *pb.Job
		want []string
	}{
		{photonJob(pb.JobState_JOB_STATE_RUNNING, t0, 1, 0, 0, 0), []string{"Emit photons 1/4", "1/4", "shards", "25%"}},
		{photonJob(pb.JobState_JOB_STATE_RUNNING, t0, 4, 0, 0, 0), []string{"Build photon map 2/4", "0/1", "tasks"}},
		{photonJob(pb.JobState_JOB_STATE_RUNNING, t0, 4, 1, 12, 0), []string{"Render tiles 3/4", "12/48", "tiles", "25%"}},
		{photonJob(pb.JobState_JOB_STATE_SUCCEEDED, t0, 4, 1, 48, 1), []string{"succeeded", "48/48", "tiles", "100%"}},
	}
	for _, tt := range tests {
		var out strings.Builder
		p := newProgress(&out, true, clk.now)
		p.update(tt.job)
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
		{&pb.Task{Spec: &pb.Task_BuildPhotonMap{BuildPhotonMap: &pb.BuildPhotonMapSpec{}}}, ""},
	} {
		if got := taskWork(tt.task); got != tt.want {
			t.Errorf("taskWork(%v) = %q, want %q", tt.task, got, tt.want)
		}
	}
}
