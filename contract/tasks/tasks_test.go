package tasks_test

import (
	"slices"
	"testing"

	"photonfarm/contract/tasks"
	"photonfarm/contract/tasks/taskstest"
	pb "photonfarm/proto/renderfarm/v1"
)

// phaseDenoise is a phase a later version of the contract might declare between render
// and composite, taking the next free number.
const phaseDenoise pb.Phase = 7

func denoiseTable(t *testing.T) tasks.Table {
	t.Helper()
	render, _ := tasks.Phases.Of(pb.Phase_PHASE_RENDER)
	ed, err := taskstest.PhaseEnumWith("PHASE_DENOISE", int32(phaseDenoise), pb.Phase_PHASE_RENDER, &pb.PhaseInfo{
		Label: "Denoise tiles", Executor: render.Executor, Inputs: render.Outputs, Outputs: render.Outputs,
	})
	if err != nil {
		t.Fatal(err)
	}
	return tasks.TableOf(ed)
}

func TestPhaseDeclaredBetweenRenderAndCompositeRanksBetweenThemWithoutRenumbering(t *testing.T) {
	table := denoiseTable(t)
	var order []pb.Phase
	for _, ph := range table {
		order = append(order, ph.Phase)
	}
	want := []pb.Phase{pb.Phase_PHASE_EMIT, pb.Phase_PHASE_BUILD, pb.Phase_PHASE_PRECOMPUTE, pb.Phase_PHASE_MERGE,
		pb.Phase_PHASE_RENDER, phaseDenoise, pb.Phase_PHASE_COMPOSITE}
	if len(order) != len(want) {
		t.Fatalf("phases %v, want %v", order, want)
	}
	for i := range want {
		if order[i] != want[i] {
			t.Fatalf("phases %v, want %v", order, want)
		}
	}
	render, denoise, composite := table.Rank(pb.Phase_PHASE_RENDER), table.Rank(phaseDenoise), table.Rank(pb.Phase_PHASE_COMPOSITE)
	if !(render < denoise && denoise < composite) {
		t.Errorf("ranks render %d, denoise %d, composite %d: want denoise between", render, denoise, composite)
	}
	// Every phase the contract declares today keeps its wire number and its facts.
	for _, ph := range tasks.Phases {
		got, ok := table.Of(ph.Phase)
		if !ok || got.Label != ph.Label || got.Executor != ph.Executor {
			t.Errorf("phase %d (%s) = %+v in the new table, want %+v", ph.Phase, ph.Label, got, ph)
		}
	}
	if got, _ := table.Of(phaseDenoise); got.Label != "Denoise tiles" || got.Executor != pb.Executor_EXECUTOR_WORKER {
		t.Errorf("denoise = %+v", got)
	}
	if got := table.RunBy(pb.Executor_EXECUTOR_WORKER); len(got) != 5 || got[3] != phaseDenoise {
		t.Errorf("worker phases %v, want denoise between render and composite", got)
	}
}

func TestPhasesRunInDeclarationOrderWithExecutors(t *testing.T) {
	workers := tasks.Phases.RunBy(pb.Executor_EXECUTOR_WORKER)
	builder := tasks.Phases.RunBy(pb.Executor_EXECUTOR_COORDINATOR)
	wantW := []pb.Phase{pb.Phase_PHASE_EMIT, pb.Phase_PHASE_PRECOMPUTE, pb.Phase_PHASE_RENDER, pb.Phase_PHASE_COMPOSITE}
	wantB := []pb.Phase{pb.Phase_PHASE_BUILD, pb.Phase_PHASE_MERGE}
	if !equal(workers, wantW) || !equal(builder, wantB) {
		t.Errorf("workers lease %v, the builder %v; want %v and %v", workers, builder, wantW, wantB)
	}
	for i, ph := range tasks.Phases {
		if ph.Rank != i+1 {
			t.Errorf("%s has rank %d at position %d", ph.Label, ph.Rank, i)
		}
	}
	if tasks.Rank(pb.Phase(99)) != 0 || tasks.Label(pb.Phase(99)) != "99" {
		t.Errorf("an unknown phase has rank %d and label %q", tasks.Rank(pb.Phase(99)), tasks.Label(pb.Phase(99)))
	}
}

func equal(a, b []pb.Phase) bool {
	if len(a) != len(b) {
		return false
	}
	for i := range a {
		if a[i] != b[i] {
			return false
		}
	}
	return true
}

func TestEveryTaskSpecNamesItsPhase(t *testing.T) {
	cases := []struct {
		task *pb.Task
		want pb.Phase
	}{
		{&pb.Task{Spec: &pb.Task_EmitPhotons{EmitPhotons: &pb.EmitPhotonsSpec{}}}, pb.Phase_PHASE_EMIT},
		{&pb.Task{Spec: &pb.Task_BuildPhotonMap{BuildPhotonMap: &pb.BuildPhotonMapSpec{}}}, pb.Phase_PHASE_BUILD},
		{&pb.Task{Spec: &pb.Task_PrecomputeIrradiance{PrecomputeIrradiance: &pb.PrecomputeIrradianceSpec{}}}, pb.Phase_PHASE_PRECOMPUTE},
		{&pb.Task{Spec: &pb.Task_MergeIrradiance{MergeIrradiance: &pb.MergeIrradianceSpec{}}}, pb.Phase_PHASE_MERGE},
		{&pb.Task{Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{}}}, pb.Phase_PHASE_RENDER},
		{&pb.Task{Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{}}}, pb.Phase_PHASE_COMPOSITE},
		{&pb.Task{}, pb.Phase_PHASE_UNSPECIFIED},
	}
	for _, c := range cases {
		if got := tasks.PhaseOf(c.task); got != c.want {
			t.Errorf("PhaseOf(%v) = %v, want %v", c.task, got, c.want)
		}
	}
	// Every member of Task.spec declares one.
	od := (&pb.Task{}).ProtoReflect().Descriptor().Oneofs().ByName("spec")
	for i := 0; i < od.Fields().Len(); i++ {
		if fd := od.Fields().Get(i); tasks.SpecPhase(fd) == pb.Phase_PHASE_UNSPECIFIED {
			t.Errorf("Task.%s declares no task_phase", fd.Name())
		}
	}
}

func TestArtifactNamesAndFailureKindsComeFromTheContract(t *testing.T) {
	if got := tasks.ArtifactName(pb.ArtifactKind_ARTIFACT_KIND_TILE_PNG); got != "tile.png" {
		t.Errorf("tile png is %q", got)
	}
	list := []*pb.Artifact{{Name: "image.exr", Digest: "a"}, {Name: "preview.png", Digest: "b"}}
	if a := tasks.Find(list, pb.ArtifactKind_ARTIFACT_KIND_PREVIEW_PNG); a == nil || a.Digest != "b" {
		t.Errorf("Find(preview) = %v", a)
	}
	if a := tasks.Find(list, pb.ArtifactKind_ARTIFACT_KIND_TILE_EXR); a != nil {
		t.Errorf("Find(tile.exr) = %v, want nil", a)
	}
	type treated struct{ permanent, blames bool }
	for k, want := range map[pb.FailureKind]treated{
		pb.FailureKind_FAILURE_KIND_UNSPECIFIED:        {false, true},
		pb.FailureKind_FAILURE_KIND_TRANSIENT:          {false, true},
		pb.FailureKind_FAILURE_KIND_BAD_INPUT:          {true, false},
		pb.FailureKind_FAILURE_KIND_UNSUPPORTED:        {true, false},
		pb.FailureKind_FAILURE_KIND_RESOURCE_EXHAUSTED: {false, false}, // a full disk is not a broken worker
		pb.FailureKind_FAILURE_KIND_LOST_INPUT:         {true, false},
		pb.FailureKind(42):                             {false, true}, // a kind from a newer worker
	} {
		if f := tasks.FailureOf(k); f.Permanent != want.permanent || f.BlamesWorker != want.blames || f.Label == "" {
			t.Errorf("FailureOf(%v) = %+v, want permanent %v, blames worker %v, with a label", k, f, want.permanent, want.blames)
		}
	}
}

func TestInputsNameWhatEachBlobHolds(t *testing.T) {
	a := func(d string) *pb.Artifact { return &pb.Artifact{Digest: d} }
	tests := []struct {
		task *pb.Task
		want []string
	}{
		{&pb.Task{Round: 2, Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{
			Tiles:                []*pb.TileInput{{Rect: &pb.PixelRect{X: 32, Y: 64}, Tile: a("t")}},
			PreviousAccumulation: a("acc"), Reference: a("ref")}}},
			[]string{"tile x 32 y 64 of round 2 t", "the accumulation of round 1 acc", "the reference image ref"}},
		{&pb.Task{Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{}}}, nil},
		{&pb.Task{Round: 1, Spec: &pb.Task_BuildPhotonMap{BuildPhotonMap: &pb.BuildPhotonMapSpec{Shards: []*pb.EmittedShard{
			{Spec: &pb.EmitPhotonsSpec{Map: pb.PhotonMapKind_PHOTON_MAP_KIND_CAUSTIC, FirstPhoton: 300, PhotonCount: 100}, Shard: a("s")},
			{Spec: &pb.EmitPhotonsSpec{Map: pb.PhotonMapKind_PHOTON_MAP_KIND_VOLUME, FirstPhoton: 0, PhotonCount: 50}, Shard: a("v")}}}}},
			[]string{"the caustic photon shard of paths 300+100 of round 1 s", "the volume photon shard of paths 0+50 of round 1 v"}},
		{&pb.Task{Round: 3, Spec: &pb.Task_MergeIrradiance{MergeIrradiance: &pb.MergeIrradianceSpec{
			PhotonSnapshot: a("p"), IrradianceShards: []*pb.Artifact{a("i0"), a("i1")}}}},
			[]string{"the photon snapshot of round 3 p", "irradiance shard 0 of round 3 i0", "irradiance shard 1 of round 3 i1"}},
		{&pb.Task{Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{PhotonSnapshot: a("p")}}}, []string{"the photon snapshot of round 1 p"}},
		{&pb.Task{Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{}}}, nil},
	}
	for _, tt := range tests {
		var got []string
		for _, in := range tasks.Inputs(tt.task) {
			got = append(got, in.What+" "+in.Artifact.GetDigest())
		}
		if !slices.Equal(got, tt.want) {
			t.Errorf("Inputs(%v) = %q, want %q", tt.task, got, tt.want)
		}
	}
}
