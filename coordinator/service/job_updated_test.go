package service_test

import (
	"testing"

	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestJobOnlyChangesAreWatched: a change of the job alone (its priority, its blocklist)
// reaches watchers as JOB_EVENT_KIND_JOB_UPDATED with the job after the change, so that
// open dashboard pages show it at once rather than at the next task update.
func TestJobOnlyChangesAreWatched(t *testing.T) {
	f := newFarm(t)
	job, _, _ := f.leased(scenetest.Unlit(64, 64))
	stream, err := f.jobs.WatchJob(f.ctx, &pb.WatchJobRequest{JobId: job.Id})
	if err != nil {
		t.Fatal(err)
	}
	if _, err := stream.Recv(); err != nil {
		t.Fatal(err)
	}
	for _, tc := range []struct {
		name   string
		change func() error
		want   func(*pb.Job) bool
	}{
		{"priority", func() error {
			_, err := f.jobs.SetJobPriority(f.ctx, &pb.SetJobPriorityRequest{JobId: job.Id, Priority: 7})
			return err
		}, func(j *pb.Job) bool { return j.Priority == 7 }},
		{"unblock", func() error {
			_, err := f.jobs.UnblockWorker(f.ctx, &pb.UnblockWorkerRequest{JobId: job.Id})
			return err
		}, func(j *pb.Job) bool { return len(j.BlockedWorkers) == 0 }},
	} {
		if err := tc.change(); err != nil {
			t.Fatalf("%s: %v", tc.name, err)
		}
		ev, err := stream.Recv()
		if err != nil || ev.Kind != pb.JobEventKind_JOB_EVENT_KIND_JOB_UPDATED || ev.Job.GetId() != job.Id || !tc.want(ev.Job) {
			t.Errorf("%s: event %v, %v; want JOB_UPDATED with the changed job", tc.name, ev, err)
		}
	}
}
