package storetest

import (
	"fmt"
	"strings"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// roundTasks is one progressive round of `tiles` render tasks and a composite, indexed
// from 0.
func roundTasks(round uint32, tiles int) []*pb.Task {
	var ts []*pb.Task
	for i := 0; i < tiles; i++ {
		ts = append(ts, &pb.Task{Index: uint32(i), Round: round, Phase: pb.Phase_PHASE_RENDER,
			Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{Rect: &pb.PixelRect{X: uint32(8 * i), Width: 8, Height: 8}, FirstSample: round - 1}}})
	}
	return append(ts, &pb.Task{Index: uint32(tiles), Round: round, Phase: pb.Phase_PHASE_COMPOSITE,
		Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{}}})
}

// finishTiles completes every queued tile with w1 and returns the leased composite.
func (f *fixture) finishTiles(tiles int) *store.Leased {
	f.t.Helper()
	for i := 0; i < tiles; i++ {
		l := f.lease("w1")
		if l.Task.GetRenderTile() == nil {
			f.t.Fatalf("leased %v, want a tile", l.Task)
		}
		f.complete("w1", l, artifact("tile.exr", l.Lease.TaskId))
	}
	comp := f.lease("w1")
	if comp.Task.GetComposite() == nil {
		f.t.Fatalf("leased %v, want the composite", comp.Task)
	}
	return comp
}

func testCompleteRoundAppendsNextRound(f *fixture) {
	plan := &pb.Plan{Passes: []*pb.PlannedPass{{Name: "direct lighting", Enabled: true, Reason: "shadow rays"}}}
	j, err := f.s.CreateJob(f.ctx, store.NewJob{DisplayName: "p", SceneDigest: digest("p"), Width: 16, Height: 8, Plan: plan, Tasks: roundTasks(1, 2)})
	if err != nil {
		f.t.Fatalf("CreateJob: %v", err)
	}
	if !proto.Equal(j.Plan, plan) || !proto.Equal(f.job(j.Id).Plan, plan) {
		f.t.Errorf("plan = %v, want %v", f.job(j.Id).Plan, plan)
	}
	comp := f.finishTiles(2)
	report := &pb.RoundReport{Round: 1, ElapsedSeconds: 1.5, Photons: 100, SamplesPerPixel: 1}
	outs := []*pb.Artifact{artifact("image.exr", "i1"), artifact("accumulation.exr", "a1")}
	c, err := f.s.CompleteRound(f.ctx, ref("w1", comp), store.RoundEnd{Outputs: outs, Report: report, Next: roundTasks(2, 2)})
	if err != nil {
		f.t.Fatalf("CompleteRound: %v", err)
	}
	if !c.Queued || c.JobStateChanged || c.Job.State != pb.JobState_JOB_STATE_RUNNING {
		f.t.Errorf("change = %+v, want round 2 queued and the job still running", c)
	}
	ts := f.tasks(j.Id)
	if got := taskStates(ts); got != "SSSQQW" {
		f.t.Fatalf("states = %s, want SSSQQW", got)
	}
	for i, tk := range ts {
		if tk.Index != uint32(i) || tk.Id != store.TaskID(j.Id, uint32(i)) {
			f.t.Errorf("task %d has index %d, id %s", i, tk.Index, tk.Id)
		}
	}
	if ts[3].Round != 2 || ts[3].GetRenderTile().GetFirstSample() != 1 {
		f.t.Errorf("appended task = %v, want round 2's first tile", ts[3])
	}
	job := f.job(j.Id)
	if len(job.Rounds) != 1 || !proto.Equal(job.Rounds[0], report) {
		f.t.Errorf("rounds = %v, want [%v]", job.Rounds, report)
	}
	// Progress is the latest round's.
	if len(job.Phases) != 2 || job.Phases[0].TasksTotal != 2 || job.Phases[0].TasksSucceeded != 0 {
		f.t.Errorf("phases = %v, want round 2's (0 of 2 tiles)", job.Phases)
	}
	// A repeated report changes nothing, not even the rounds.
	if c, err := f.s.CompleteRound(f.ctx, ref("w1", comp), store.RoundEnd{Outputs: outs, Report: report, Next: roundTasks(2, 2)}); err != nil || c.Job != nil {
		f.t.Errorf("repeated CompleteRound = %+v, %v; want no change", c, err)
	}
	if n := len(f.tasks(j.Id)); n != 6 {
		f.t.Errorf("%d tasks after a repeated report, want 6", n)
	}

	// Round 2 ends the job with the final outputs only.
	comp2 := f.finishTiles(2)
	f.clock.Advance(time.Second)
	final := []*pb.Artifact{artifact("image.exr", "i2"), artifact("preview.png", "p2")}
	c, err = f.s.CompleteRound(f.ctx, ref("w1", comp2), store.RoundEnd{
		Outputs: append([]*pb.Artifact{artifact("accumulation.exr", "a2")}, final...),
		Report:  &pb.RoundReport{Round: 2, ElapsedSeconds: 3, ErrorEstimate: proto.Float64(0.1)}, Final: final,
	})
	if err != nil || !c.JobStateChanged || c.Job.State != pb.JobState_JOB_STATE_SUCCEEDED {
		f.t.Fatalf("last CompleteRound = %+v, %v; want the job SUCCEEDED", c, err)
	}
	job = f.job(j.Id)
	if len(job.Rounds) != 2 || job.Rounds[1].GetErrorEstimate() != 0.1 || len(job.Outputs) != 2 || job.Outputs[1].Digest != digest("p2") {
		f.t.Errorf("job = %v", job)
	}
	f.noLease("w1")
}

func testCompleteRoundRefusals(f *fixture) {
	j, err := f.s.CreateJob(f.ctx, store.NewJob{DisplayName: "p", SceneDigest: digest("p"), Width: 16, Height: 8, Tasks: roundTasks(1, 2)})
	if err != nil {
		f.t.Fatalf("CreateJob: %v", err)
	}
	tile := f.lease("w1")
	end := store.RoundEnd{Report: &pb.RoundReport{Round: 1}}
	_, err = f.s.CompleteRound(f.ctx, ref("w1", tile), end)
	wantKind(f.t, "CompleteRound of a tile", err, errs.Internal)
	f.complete("w1", tile, artifact("tile.exr", "t0"))
	f.complete("w1", f.lease("w1"), artifact("tile.exr", "t1"))
	comp := f.lease("w1")
	_, err = f.s.CompleteRound(f.ctx, ref("w2", comp), end)
	wantKind(f.t, "CompleteRound by another worker", err, errs.FailedPrecondition)
	f.clock.Advance(leaseDuration)
	_, err = f.s.CompleteRound(f.ctx, ref("w1", comp), end)
	wantKind(f.t, "CompleteRound after the lease expired", err, errs.FailedPrecondition)
	if job := f.job(j.Id); len(job.Rounds) != 0 || job.State != pb.JobState_JOB_STATE_RUNNING {
		f.t.Errorf("refused reports changed the job: %v", job)
	}
	if _, err := f.s.GetTask(f.ctx, store.TaskID(j.Id, 99)); errs.KindOf(err) != errs.NotFound {
		f.t.Errorf("GetTask of an unknown task: %v, want NotFound", err)
	}
	if tk, err := f.s.GetTask(f.ctx, store.TaskID(j.Id, 2)); err != nil || tk.GetComposite() == nil {
		f.t.Errorf("GetTask(composite) = %v, %v", tk, err)
	}
}

func testCancelledRoundIsNotExtended(f *fixture) {
	j, err := f.s.CreateJob(f.ctx, store.NewJob{DisplayName: "p", SceneDigest: digest("p"), Width: 8, Height: 8, Tasks: roundTasks(1, 1)})
	if err != nil {
		f.t.Fatalf("CreateJob: %v", err)
	}
	comp := f.finishTiles(1)
	if _, err := f.s.CancelJob(f.ctx, j.Id); err != nil {
		f.t.Fatal(err)
	}
	_, err = f.s.CompleteRound(f.ctx, ref("w1", comp), store.RoundEnd{Report: &pb.RoundReport{Round: 1}, Next: roundTasks(2, 1)})
	wantKind(f.t, "CompleteRound of a cancelled job", err, errs.FailedPrecondition)
	if n := len(f.tasks(j.Id)); n != 2 {
		f.t.Errorf("%d tasks, want 2: a cancelled job gets no new round", n)
	}
}

func testRepeatedReportsMustBeTheSame(f *fixture) {
	j, err := f.s.CreateJob(f.ctx, store.NewJob{DisplayName: "p", SceneDigest: digest("p"), Width: 16, Height: 8, Tasks: roundTasks(1, 1)})
	if err != nil {
		f.t.Fatalf("CreateJob: %v", err)
	}
	tile := f.lease("w1")
	f.complete("w1", tile, artifact("tile.exr", "t0"))
	if c := f.complete("w1", tile, artifact("tile.exr", "t0")); c.Job != nil {
		f.t.Errorf("the same report again changed %+v", c)
	}
	for _, outs := range [][]*pb.Artifact{{artifact("tile.exr", "other")}, nil, {artifact("tile.exr", "t0"), artifact("x", "y")}} {
		_, err := f.s.CompleteTask(f.ctx, ref("w1", tile), outs)
		wantKind(f.t, fmt.Sprintf("a repeat with outputs %v", outs), err, errs.FailedPrecondition)
		if err != nil && !strings.Contains(err.Error(), "other outputs") {
			f.t.Errorf("refusal %q does not name the outputs", err)
		}
	}
	if ts := f.tasks(j.Id); len(ts[0].Outputs) != 1 || ts[0].Outputs[0].Digest != digest("t0") {
		f.t.Errorf("outputs after refused repeats = %v, want the first", ts[0].Outputs)
	}

	comp := f.lease("w1")
	outs := []*pb.Artifact{artifact("image.exr", "i1"), artifact("accumulation.exr", "a1")}
	report := &pb.RoundReport{Round: 1, ElapsedSeconds: 1, ErrorEstimate: proto.Float64(0.5), ErrorEstimateBias: proto.Float64(0.1),
		ErrorEstimateLow: proto.Float64(0.4), ErrorEstimateHigh: proto.Float64(0.6), LayerReferenceRmse: map[string]float64{"direct": 0.1}}
	otherInterval := proto.Clone(report).(*pb.RoundReport)
	otherInterval.ErrorEstimateHigh = proto.Float64(0.7)
	end := store.RoundEnd{Outputs: outs, Report: report, Next: roundTasks(2, 1)}
	if _, err := f.s.CompleteRound(f.ctx, ref("w1", comp), end); err != nil {
		f.t.Fatalf("CompleteRound: %v", err)
	}
	// The coordinator's own part of the report (the elapsed time) may differ in a repeat.
	later := proto.Clone(report).(*pb.RoundReport)
	later.ElapsedSeconds = 7
	if c, err := f.s.CompleteRound(f.ctx, ref("w1", comp), store.RoundEnd{Outputs: outs, Report: later, Next: roundTasks(2, 1)}); err != nil || c.Job != nil {
		f.t.Errorf("the same outputs and metrics again = %+v, %v; want no change", c, err)
	}
	for _, c := range []struct {
		what string
		end  store.RoundEnd
	}{
		{"outputs", store.RoundEnd{Outputs: outs[:1], Report: report, Next: roundTasks(2, 1)}},
		{"metrics", store.RoundEnd{Outputs: outs, Report: &pb.RoundReport{Round: 1, ErrorEstimate: proto.Float64(0.25)}, Next: roundTasks(2, 1)}},
		{"metrics", store.RoundEnd{Outputs: outs, Report: otherInterval, Next: roundTasks(2, 1)}},
	} {
		what, end := c.what, c.end
		_, err := f.s.CompleteRound(f.ctx, ref("w1", comp), end)
		wantKind(f.t, "a repeat with other "+what, err, errs.FailedPrecondition)
		if err != nil && !strings.Contains(err.Error(), "other "+what) {
			f.t.Errorf("refusal %q does not name the %s", err, what)
		}
	}
	if job := f.job(j.Id); len(job.Rounds) != 1 || job.Rounds[0].GetErrorEstimate() != 0.5 || len(f.tasks(j.Id)) != 4 {
		f.t.Errorf("after refused repeats: rounds %v, %d tasks; want the first report and one round appended", job.Rounds, len(f.tasks(j.Id)))
	}
}
