package store_test

import (
	"testing"
	"time"

	"photonfarm/contract/tasks"
	"photonfarm/contract/tasks/taskstest"
	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

func TestBackoffDoublesUpToTheCap(t *testing.T) {
	o := store.Options{}.WithDefaults()
	for _, tc := range []struct {
		failures int
		want     time.Duration
	}{
		{1, time.Second},
		{2, 2 * time.Second},
		{3, 4 * time.Second},
		{6, 32 * time.Second},
		{7, time.Minute},
		{1000, time.Minute},
	} {
		if got := o.Backoff(tc.failures); got != tc.want {
			t.Errorf("Backoff(%d) = %v, want %v", tc.failures, got, tc.want)
		}
	}
}

func TestCheckPriority(t *testing.T) {
	for p, ok := range map[int32]bool{-1001: false, -1000: true, 0: true, 1000: true, 1001: false} {
		if err := store.CheckPriority(p); (err == nil) != ok {
			t.Errorf("CheckPriority(%d) = %v", p, err)
		}
	}
}

func TestStagesFollowPhaseRankNotPhaseNumber(t *testing.T) {
	render, _ := tasks.Phases.Of(pb.Phase_PHASE_RENDER)
	const denoise pb.Phase = 7 // declared between render and composite, numbered after both
	ed, err := taskstest.PhaseEnumWith("PHASE_DENOISE", int32(denoise), pb.Phase_PHASE_RENDER, &pb.PhaseInfo{
		Label: "Denoise tiles", Executor: render.Executor, Inputs: render.Outputs, Outputs: render.Outputs})
	if err != nil {
		t.Fatal(err)
	}
	table := tasks.TableOf(ed)
	order := []struct {
		round uint32
		phase pb.Phase
	}{
		{1, pb.Phase_PHASE_EMIT}, {1, pb.Phase_PHASE_BUILD}, {1, pb.Phase_PHASE_RENDER}, {1, denoise},
		{1, pb.Phase_PHASE_COMPOSITE}, {2, pb.Phase_PHASE_EMIT}, {2, denoise}, {2, pb.Phase_PHASE_COMPOSITE},
	}
	for i := 1; i < len(order); i++ {
		a, b := order[i-1], order[i]
		if sa, sb := store.StageIn(table, a.round, a.phase), store.StageIn(table, b.round, b.phase); sa >= sb {
			t.Errorf("stage of round %d %v = %d, not before round %d %v = %d", a.round, a.phase, sa, b.round, b.phase, sb)
		}
	}
	// The contract's own table: a round's phases in declaration order, round 0 as 1.
	for i := 1; i < len(tasks.Phases); i++ {
		prev, cur := &pb.Task{Phase: tasks.Phases[i-1].Phase}, &pb.Task{Phase: tasks.Phases[i].Phase, Round: 1}
		if store.Stage(prev) >= store.Stage(cur) {
			t.Errorf("%v is not staged before %v", prev.Phase, cur.Phase)
		}
	}
}

func TestCheckPlanRefusesATaskWhosePhaseIsNotItsSpecs(t *testing.T) {
	good := []*pb.Task{
		{Index: 0, Phase: pb.Phase_PHASE_RENDER, Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{}}},
		{Index: 1, Phase: pb.Phase_PHASE_COMPOSITE, Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{}}},
	}
	if err := store.CheckPlan(good); err != nil {
		t.Fatalf("CheckPlan(render, composite) = %v", err)
	}
	for name, bad := range map[string][]*pb.Task{
		"composite spec in the render phase": {{Index: 0, Phase: pb.Phase_PHASE_RENDER, Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{}}}},
		"no spec":                            {{Index: 0, Phase: pb.Phase_PHASE_RENDER}},
		"composite before render":            {{Index: 0, Phase: pb.Phase_PHASE_COMPOSITE, Spec: good[1].Spec}, {Index: 1, Phase: pb.Phase_PHASE_RENDER, Spec: good[0].Spec}},
		"index skipped":                      {{Index: 1, Phase: pb.Phase_PHASE_RENDER, Spec: good[0].Spec}},
	} {
		if err := store.CheckPlan(bad); errs.KindOf(err) != errs.Internal {
			t.Errorf("%s: CheckPlan = %v, want an Internal error", name, err)
		}
	}
}

func TestJobOfTask(t *testing.T) {
	for _, tc := range []struct {
		task, job string
		ok        bool
	}{
		{"j-0123456789abcdef.0", "j-0123456789abcdef", true},
		{"j-0123456789abcdef.95538", "j-0123456789abcdef", true},
		{store.TaskID("j-a.b", 7), "j-a.b", true},
		{"j-0123456789abcdef", "", false},
		{"j-0123456789abcdef.", "", false},
		{"j-0123456789abcdef.x", "", false},
		{"j-0123456789abcdef.-1", "", false},
		{".3", "", false},
		{"", "", false},
	} {
		if job, ok := store.JobOfTask(tc.task); job != tc.job || ok != tc.ok {
			t.Errorf("JobOfTask(%q) = %q, %v; want %q, %v", tc.task, job, ok, tc.job, tc.ok)
		}
	}
}
