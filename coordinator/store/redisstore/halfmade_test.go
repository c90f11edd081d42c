package redisstore

import (
	"context"
	"testing"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/coordinator/clock"
	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/coordinator/store/storetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// halfMake does what a CreateJob of nj does up to its staging of the first `staged`
// tasks, and stops there, as a coordinator that dies midway would; it returns the job id.
func halfMake(t *testing.T, s *Store, nj store.NewJob, staged int) string {
	t.Helper()
	ctx := context.Background()
	id := store.NewJobID()
	static, err := proto.Marshal(&pb.Job{Id: id, DisplayName: nj.DisplayName, SceneDigest: nj.SceneDigest})
	if err != nil {
		t.Fatal(err)
	}
	v, err := s.run(ctx, beginScript, id, nj.RequestID, static, nj.Priority, len(nj.Tasks), nj.SceneDigest)
	l, _ := v.([]any)
	if err != nil || len(l) != 2 || l[0] != "BUILD" {
		t.Fatalf("begin = %v, %v", v, err)
	}
	id, _ = l[1].(string)
	if _, err := s.stage(ctx, id, id, nil, 0, nj.Tasks[:staged]); err != nil {
		t.Fatal(err)
	}
	return id
}

// TestHalfMadeJobsAreFinishedByARetryOrPurged: a job whose creation stopped midway is
// seen by no listing, read or lease; a retry of the submission (same request id, same
// scene: planning is deterministic) finishes it, a different scene under that request id
// is refused, and one nobody comes back for is deleted, every record of it, by the purge
// once it has not grown for the abandonment time.
func TestHalfMadeJobsAreFinishedByARetryOrPurged(t *testing.T) {
	srv := redistest.Start(t)
	rdb := srv.Client()
	clk := clock.NewFake(time.Date(2030, 1, 2, 3, 4, 5, 0, time.UTC))
	ctx := context.Background()
	s, err := New(ctx, rdb, "half:", store.Options{Clock: clk})
	if err != nil {
		t.Fatal(err)
	}
	nj := storetest.TileJob("half", 1000) // 8 chunks of StageChunk
	nj.RequestID = "submit-1"
	id := halfMake(t, s, nj, 300)

	if jobs, _, err := s.ListJobs(ctx, 10, ""); err != nil || len(jobs) != 0 {
		t.Errorf("ListJobs = %v, %v; want no job", jobs, err)
	}
	if _, err := s.GetJob(ctx, id); errs.KindOf(err) != errs.NotFound {
		t.Errorf("GetJob of a half-made job: %v, want NotFound", err)
	}
	if _, _, err := s.ListTasks(ctx, id, 10, ""); errs.KindOf(err) != errs.NotFound {
		t.Errorf("ListTasks of a half-made job: %v, want NotFound", err)
	}
	if l, err := s.LeaseTask(ctx, "w1", store.WorkerPhases); l != nil || err != nil {
		t.Errorf("LeaseTask = %v, %v; want nothing", l, err)
	}
	other := storetest.TileJob("other scene", 1000)
	other.RequestID = nj.RequestID
	if _, err := s.CreateJob(ctx, other); errs.KindOf(err) != errs.FailedPrecondition {
		t.Errorf("CreateJob of another scene under the same request id: %v, want FailedPrecondition", err)
	}

	clk.Advance(time.Minute)
	j, err := s.CreateJob(ctx, nj)
	if err != nil || j.Id != id || j.Phases[0].TasksTotal != 1000 {
		t.Fatalf("the retried CreateJob = %v, %v; want job %s finished", j, err, id)
	}
	if jobs, _, _ := s.ListJobs(ctx, 10, ""); len(jobs) != 1 {
		t.Errorf("%d jobs listed, want 1", len(jobs))
	}
	if l, err := s.LeaseTask(ctx, "w1", store.WorkerPhases); err != nil || l.Lease.TaskId != store.TaskID(id, 0) {
		t.Errorf("LeaseTask = %v, %v; want the finished job's first tile", l, err)
	}

	abandoned := halfMake(t, s, storetest.TileJob("abandoned", 1000), 500)
	// Not yet: it grew a moment ago.
	if p, err := s.PurgeJobs(ctx, time.Time{}, clk.Now().Add(-time.Minute), 1000); err != nil || len(p.Deleted) != 0 {
		t.Fatalf("PurgeJobs before the abandonment time = %+v, %v", p, err)
	}
	clk.Advance(time.Hour)
	var deleted []string
	for {
		p, err := s.PurgeJobs(ctx, time.Time{}, clk.Now().Add(-time.Minute), 200)
		if err != nil {
			t.Fatal(err)
		}
		deleted = append(deleted, p.Deleted...)
		if !p.More {
			break
		}
	}
	if len(deleted) != 1 || deleted[0] != abandoned {
		t.Errorf("purged %v, want %s", deleted, abandoned)
	}
	if keys, _ := rdb.Keys(ctx, "half:*"+abandoned+"*").Result(); len(keys) != 0 {
		t.Errorf("keys of the purged job remain: %v", keys)
	}
	if _, err := s.GetJob(ctx, id); err != nil {
		t.Errorf("the finished job after the purge: %v", err)
	}
}
