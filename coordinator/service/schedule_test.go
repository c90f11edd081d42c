package service_test

import (
	"context"
	"testing"
	"time"

	"google.golang.org/grpc/codes"

	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator/coordinatortest"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

func TestSchedulingRPCsValidate(t *testing.T) {
	f := newFarm(t)
	job := f.submit(scenetest.Unlit(8, 8))
	ended := f.submit(scenetest.Unlit(8, 8))
	f.cancel(ended.Id)
	for _, tc := range []struct {
		name  string
		call  func(context.Context) error
		code  codes.Code
		field string
	}{
		{"submit: priority too high", coordinatortest.Call(f.jobs.SubmitJob, &pb.SubmitJobRequest{Scene: scenetest.Unlit(8, 8), Priority: store.MaxPriority + 1}), codes.InvalidArgument, "priority"},
		{"set priority: no job", coordinatortest.Call(f.jobs.SetJobPriority, &pb.SetJobPriorityRequest{Priority: 1}), codes.InvalidArgument, "job_id"},
		{"set priority: too low", coordinatortest.Call(f.jobs.SetJobPriority, &pb.SetJobPriorityRequest{JobId: job.Id, Priority: store.MinPriority - 1}), codes.InvalidArgument, "priority"},
		{"set priority: unknown job", coordinatortest.Call(f.jobs.SetJobPriority, &pb.SetJobPriorityRequest{JobId: "j-nope", Priority: 1}), codes.NotFound, "job_id"},
		{"set priority: ended job", coordinatortest.Call(f.jobs.SetJobPriority, &pb.SetJobPriorityRequest{JobId: ended.Id, Priority: 1}), codes.FailedPrecondition, ""},
		{"unblock: no job", coordinatortest.Call(f.jobs.UnblockWorker, &pb.UnblockWorkerRequest{WorkerId: "w-1"}), codes.InvalidArgument, "job_id"},
		{"unblock: worker id with spaces", coordinatortest.Call(f.jobs.UnblockWorker, &pb.UnblockWorkerRequest{JobId: job.Id, WorkerId: "w 1"}), codes.InvalidArgument, "worker_id"},
		{"unblock: unknown job", coordinatortest.Call(f.jobs.UnblockWorker, &pb.UnblockWorkerRequest{JobId: "j-nope"}), codes.NotFound, "job_id"},
	} {
		t.Run(tc.name, func(t *testing.T) { wantCode(t, tc.name, tc.call(f.ctx), tc.code, tc.field) })
	}
	set, err := f.jobs.SetJobPriority(f.ctx, &pb.SetJobPriorityRequest{JobId: job.Id, Priority: -7})
	if err != nil || set.Job.Priority != -7 {
		t.Errorf("SetJobPriority = %v, %v", set, err)
	}
	if _, err := f.jobs.UnblockWorker(f.ctx, &pb.UnblockWorkerRequest{JobId: ended.Id}); err != nil {
		t.Errorf("UnblockWorker of an ended job: %v", err)
	}
}

// TestLongPollWakesWhenBackoffEnds: a worker waiting for a task gets the one another
// worker failed once its backoff is over, without anything else being queued.
func TestLongPollWakesWhenBackoffEnds(t *testing.T) {
	f := newFarm(t)
	f.submit(scenetest.Unlit(8, 8)) // one tile
	w1, w2 := f.register(), f.register()
	l := f.lease(w1)
	got := f.longPoll(w2, 10*time.Second)
	if _, err := f.workers.FailTask(f.ctx, &pb.FailTaskRequest{WorkerId: w1, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Error: "flaky"}); err != nil {
		t.Fatal(err)
	}
	f.clock.Advance(store.DefaultRetryBackoff)
	select {
	case resp := <-got:
		if resp.GetLease().GetTaskId() != l.Lease.TaskId {
			t.Errorf("long poll = %v, want the failed task", resp)
		}
	case <-time.After(5 * time.Second):
		t.Fatal("the long poll did not wake when the backoff ended")
	}
}

func TestHeartbeatWithoutProgressRevokesAsStuck(t *testing.T) {
	f := newFarm(t)
	_, w, l := f.leased(scenetest.Unlit(8, 8))
	held := []*pb.HeldLease{{TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Progress: 0}}
	for elapsed := time.Duration(0); elapsed < store.DefaultStuckTimeout; {
		f.clock.Advance(leaseDuration / 2)
		elapsed += leaseDuration / 2
		hb, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: w, Leases: held})
		if err != nil {
			t.Fatal(err)
		}
		want := 0
		if elapsed >= store.DefaultStuckTimeout {
			want = 1
		}
		if len(hb.Revoked) != want {
			t.Fatalf("after %v: heartbeat = %v, want %d revoked", elapsed, hb, want)
		}
	}
	task, err := f.jobs.ListTasks(f.ctx, &pb.ListTasksRequest{JobId: l.Task.JobId})
	if err != nil || task.Tasks[0].Error != "no progress for 10m0s (stuck)" || task.Tasks[0].State != pb.TaskState_TASK_STATE_QUEUED {
		t.Errorf("task after the stuck heartbeat = %v, %v", task.GetTasks()[0], err)
	}
}
