package service_test

import (
	"testing"
	"time"

	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// workerInfo returns ListWorkers' entry for id.
func (f *farm) workerInfo(id string) *pb.WorkerInfo {
	f.t.Helper()
	resp, err := f.jobs.ListWorkers(f.ctx, &pb.ListWorkersRequest{})
	if err != nil {
		f.t.Fatalf("ListWorkers: %v", err)
	}
	for _, w := range resp.Workers {
		if w.Id == id {
			return w
		}
	}
	f.t.Fatalf("ListWorkers: no worker %s in %v", id, resp.Workers)
	return nil
}

func wantWorker(t *testing.T, what string, w *pb.WorkerInfo, state pb.WorkerState, current string, done, failed uint64) {
	t.Helper()
	if w.State != state || w.CurrentTaskId != current || w.TasksDone != done || w.TasksFailed != failed {
		t.Errorf("%s: worker %s is %v on %q, %d done, %d failed; want %v on %q, %d done, %d failed",
			what, w.Id, w.State, w.CurrentTaskId, w.TasksDone, w.TasksFailed, state, current, done, failed)
	}
}

func TestListWorkersFollowsLeases(t *testing.T) {
	f := newFarm(t)
	f.submit(scenetest.Unlit(64, 64)) // several tiles
	registered := f.clock.Now()
	w := f.register()
	f.clock.Advance(time.Second)
	other := f.register()

	resp, err := f.jobs.ListWorkers(f.ctx, &pb.ListWorkersRequest{})
	if err != nil || len(resp.Workers) != 2 || resp.Workers[0].Id != w || resp.Workers[1].Id != other {
		t.Fatalf("ListWorkers = %v, %v; want %s then %s (oldest first)", resp, err, w, other)
	}
	info := resp.Workers[0]
	if info.Hostname != "test" || info.Cores != 2 || info.Version != "test" ||
		!info.RegisterTime.AsTime().Equal(registered) || !info.LastHeartbeat.AsTime().Equal(registered) {
		t.Errorf("worker = %v, want hostname, cores, version and times of its registration", info)
	}
	wantWorker(t, "registered", info, pb.WorkerState_WORKER_STATE_IDLE, "", 0, 0)

	// Lease and complete: BUSY on the task, then IDLE with one done.
	l := f.lease(w)
	wantWorker(t, "leased", f.workerInfo(w), pb.WorkerState_WORKER_STATE_BUSY, l.Lease.TaskId, 0, 0)
	if got := f.workerInfo(w).LastHeartbeat.AsTime(); !got.Equal(f.clock.Now()) {
		t.Errorf("last heartbeat %v after a lease at %v", got, f.clock.Now())
	}
	tile := f.upload([]byte("tile"))
	tile.Name = "tile.exr"
	if _, err := f.workers.CompleteTask(f.ctx, &pb.CompleteTaskRequest{WorkerId: w, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Outputs: []*pb.Artifact{tile}}); err != nil {
		t.Fatal(err)
	}
	wantWorker(t, "completed", f.workerInfo(w), pb.WorkerState_WORKER_STATE_IDLE, "", 1, 0)

	// Fail: one failed.
	l = f.lease(w)
	if _, err := f.workers.FailTask(f.ctx, &pb.FailTaskRequest{WorkerId: w, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Error: "boom"}); err != nil {
		t.Fatal(err)
	}
	wantWorker(t, "failed", f.workerInfo(w), pb.WorkerState_WORKER_STATE_IDLE, "", 1, 1)

	// Release: nothing counted.
	l = f.lease(w)
	if _, err := f.workers.ReleaseTask(f.ctx, &pb.ReleaseTaskRequest{WorkerId: w, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch}); err != nil {
		t.Fatal(err)
	}
	wantWorker(t, "released", f.workerInfo(w), pb.WorkerState_WORKER_STATE_IDLE, "", 1, 1)

	// A lease that expires: LOST (no heartbeat for longer than a lease) and one more
	// failed; the other worker keeps heartbeating and stays IDLE.
	l = f.lease(w)
	f.clock.Advance(leaseDuration / 2)
	if _, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: other}); err != nil {
		t.Fatal(err)
	}
	f.clock.Advance(leaseDuration/2 + time.Second)
	if _, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: other}); err != nil {
		t.Fatal(err)
	}
	wantWorker(t, "silent past a lease", f.workerInfo(w), pb.WorkerState_WORKER_STATE_LOST, l.Lease.TaskId, 1, 1)
	if err := f.svc.ExpireLeases(f.ctx); err != nil {
		t.Fatal(err)
	}
	wantWorker(t, "lease expired", f.workerInfo(w), pb.WorkerState_WORKER_STATE_LOST, "", 1, 2)
	wantWorker(t, "heartbeating", f.workerInfo(other), pb.WorkerState_WORKER_STATE_IDLE, "", 0, 0)

	// Heard from again: IDLE.
	if _, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: w}); err != nil {
		t.Fatal(err)
	}
	wantWorker(t, "back", f.workerInfo(w), pb.WorkerState_WORKER_STATE_IDLE, "", 1, 2)
}

func TestListWorkersClearsRevokedLease(t *testing.T) {
	f := newFarm(t)
	job, w, l := f.leased(scenetest.Unlit(8, 8))
	f.cancel(job.Id)
	// The worker learns of the cancellation at its heartbeat: the lease is revoked.
	hb, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: w, Leases: []*pb.HeldLease{{TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch}}})
	if err != nil || len(hb.Revoked) != 1 {
		t.Fatalf("heartbeat = %v, %v; want the lease revoked", hb, err)
	}
	wantWorker(t, "revoked", f.workerInfo(w), pb.WorkerState_WORKER_STATE_IDLE, "", 0, 0)

	// Unregistered workers are gone.
	if _, err := f.workers.UnregisterWorker(f.ctx, &pb.UnregisterWorkerRequest{WorkerId: w}); err != nil {
		t.Fatal(err)
	}
	resp, err := f.jobs.ListWorkers(f.ctx, &pb.ListWorkersRequest{})
	if err != nil || len(resp.Workers) != 0 {
		t.Errorf("ListWorkers after unregister = %v, %v; want none", resp, err)
	}
}

// A worker whose tile finishes just after its job was cancelled reports it, is refused
// (the lease is gone), and stops reporting the task: it must show IDLE, not stay BUSY on
// the cancelled job's task until its next lease.
func TestRefusedReportAfterCancelLeavesTheWorkerIdle(t *testing.T) {
	f := newFarm(t)
	job, w, l := f.leased(scenetest.Unlit(64, 64))
	f.cancel(job.Id)
	tile := f.upload([]byte("tile"))
	tile.Name = "tile.exr"
	if _, err := f.workers.CompleteTask(f.ctx, &pb.CompleteTaskRequest{WorkerId: w, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Outputs: []*pb.Artifact{tile}}); err == nil {
		t.Fatal("a report under a cancelled job's lease was accepted")
	}
	wantWorker(t, "after the refused report", f.workerInfo(w), pb.WorkerState_WORKER_STATE_IDLE, "", 0, 0)
}
