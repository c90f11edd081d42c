package service_test

import (
	"bytes"
	"context"
	"math"
	"strings"
	"testing"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/protobuf/proto"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator/coordinatortest"
	pb "photonfarm/proto/renderfarm/v1"
)

func TestRegisterTellsTimings(t *testing.T) {
	f := newFarm(t)
	resp, err := f.workers.RegisterWorker(f.ctx, &pb.RegisterWorkerRequest{Hostname: "h"})
	if err != nil || !strings.HasPrefix(resp.WorkerId, "w-") {
		t.Fatalf("RegisterWorker = %v, %v", resp, err)
	}
	if resp.LeaseDuration.AsDuration() != leaseDuration || resp.HeartbeatInterval.AsDuration() != leaseDuration/4 {
		t.Errorf("timings = %v / %v", resp.LeaseDuration.AsDuration(), resp.HeartbeatInterval.AsDuration())
	}
	if other := f.register(); other == resp.WorkerId {
		t.Error("two workers got the same id")
	}
}

func TestFailedTaskIsRetriedThenFailsTheJob(t *testing.T) {
	f := newFarm(t)
	job := f.submit(scenetest.Unlit(8, 8))
	w := f.register()
	for attempt := 1; attempt <= 3; attempt++ {
		l := f.lease(w)
		if l.Task.Attempts != uint32(attempt) {
			t.Fatalf("attempt %d: task %v", attempt, l.Task)
		}
		if _, err := f.workers.FailTask(f.ctx, &pb.FailTaskRequest{WorkerId: w, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Error: "embree exploded"}); err != nil {
			t.Fatalf("FailTask: %v", err)
		}
		f.clock.Advance(time.Minute) // past the backoff
	}
	got, _ := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: job.Id})
	if got.Job.State != pb.JobState_JOB_STATE_FAILED || !strings.Contains(got.Job.Error, "embree exploded") || got.Job.EndTime == nil {
		t.Errorf("job = %v, want FAILED with the task's error", got.Job)
	}
}

func TestStaleEpochIsRefused(t *testing.T) {
	f := newFarm(t)
	f.submit(scenetest.Unlit(8, 8))
	w1, w2 := f.register(), f.register()
	old := f.lease(w1)
	f.clock.Advance(leaseDuration + time.Second)
	if err := f.svc.ExpireLeases(f.ctx); err != nil {
		t.Fatal(err)
	}
	cur := f.lease(w2)
	if cur.Lease.TaskId != old.Lease.TaskId || cur.Lease.Epoch <= old.Lease.Epoch {
		t.Fatalf("re-lease %v after %v", cur.Lease, old.Lease)
	}
	tile := f.upload([]byte("tile"))
	tile.Name = "tile.exr"
	_, err := f.workers.CompleteTask(f.ctx, &pb.CompleteTaskRequest{WorkerId: w1, TaskId: old.Lease.TaskId, Epoch: old.Lease.Epoch, Outputs: []*pb.Artifact{tile}})
	wantCode(t, "complete under the expired epoch", err, codes.FailedPrecondition, "")
	_, err = f.workers.CompleteTask(f.ctx, &pb.CompleteTaskRequest{WorkerId: w1, TaskId: cur.Lease.TaskId, Epoch: cur.Lease.Epoch, Outputs: []*pb.Artifact{tile}})
	wantCode(t, "complete by the wrong worker", err, codes.FailedPrecondition, "")
	hb, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: w1, Leases: []*pb.HeldLease{{TaskId: old.Lease.TaskId, Epoch: old.Lease.Epoch}}})
	if err != nil || len(hb.Revoked) != 1 {
		t.Errorf("old holder's heartbeat = %v, %v; want its lease revoked", hb, err)
	}
	hb, err = f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: w2, Leases: []*pb.HeldLease{{TaskId: cur.Lease.TaskId, Epoch: cur.Lease.Epoch}}})
	if err != nil || len(hb.Leases) != 1 || !hb.Leases[0].ExpireTime.AsTime().Equal(f.clock.Now().Add(leaseDuration)) {
		t.Errorf("holder's heartbeat = %v, %v; want the lease extended", hb, err)
	}
	if _, err := f.workers.CompleteTask(f.ctx, &pb.CompleteTaskRequest{WorkerId: w2, TaskId: cur.Lease.TaskId, Epoch: cur.Lease.Epoch, Outputs: []*pb.Artifact{tile}}); err != nil {
		t.Errorf("complete by the holder: %v", err)
	}
}

func TestCompleteRefusesOutputsNotUploaded(t *testing.T) {
	f := newFarm(t)
	_, w, l := f.leased(scenetest.Unlit(8, 8))
	real := f.upload([]byte("tile"))
	tests := []struct {
		name  string
		out   *pb.Artifact
		field string
	}{
		{"no name", &pb.Artifact{Digest: real.Digest, SizeBytes: real.SizeBytes}, "outputs[0].name"},
		{"bad digest", &pb.Artifact{Name: "tile.exr", Digest: "sha256:xyz"}, "outputs[0].digest"},
		{"not uploaded", &pb.Artifact{Name: "tile.exr", Digest: "sha256:" + strings.Repeat("ab", 32), SizeBytes: 4}, "outputs[0].digest"},
		{"wrong size", &pb.Artifact{Name: "tile.exr", Digest: real.Digest, SizeBytes: 5}, "outputs[0].size_bytes"},
	}
	for _, tt := range tests {
		_, err := f.workers.CompleteTask(f.ctx, &pb.CompleteTaskRequest{WorkerId: w, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Outputs: []*pb.Artifact{tt.out}})
		wantCode(t, tt.name, err, codes.InvalidArgument, tt.field)
	}
}

func TestLeaseLongPollWakesWhenWorkIsQueued(t *testing.T) {
	f := newFarm(t)
	w := f.register()
	start := time.Now()
	resp, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: w, WaitTimeout: wait(100 * time.Millisecond)})
	if err != nil || resp.Lease != nil || time.Since(start) < 100*time.Millisecond {
		t.Fatalf("empty long poll = %v, %v after %v", resp, err, time.Since(start))
	}
	got := f.longPoll(w, 20*time.Second)
	time.Sleep(50 * time.Millisecond)
	start = time.Now()
	f.submit(scenetest.Unlit(8, 8))
	select {
	case resp := <-got:
		if resp.GetLease() == nil {
			t.Fatalf("long poll returned %v, want a lease", resp)
		}
	case <-time.After(5 * time.Second):
		t.Fatal("long poll not woken by a submit")
	}
	// A poll also wakes when a task goes back to the queue.
	got = f.longPoll(w, 20*time.Second)
	time.Sleep(50 * time.Millisecond)
	if _, err := f.workers.UnregisterWorker(f.ctx, &pb.UnregisterWorkerRequest{WorkerId: w}); err != nil {
		t.Fatal(err)
	}
	select {
	case resp := <-got:
		if resp.GetLease() == nil || resp.Lease.Epoch != 2 {
			t.Errorf("after unregister, long poll = %v; want the released task under epoch 2", resp)
		}
	case <-time.After(5 * time.Second):
		t.Fatal("long poll not woken by a release")
	}
}

func TestLeaseRespectsCallerCancellation(t *testing.T) {
	f := newFarm(t)
	w := f.register()
	ctx, cancel := context.WithTimeout(f.ctx, 100*time.Millisecond)
	defer cancel()
	start := time.Now()
	_, err := f.workers.LeaseTask(ctx, &pb.LeaseTaskRequest{WorkerId: w, WaitTimeout: wait(30 * time.Second)})
	wantCode(t, "cancelled long poll", err, codes.DeadlineExceeded, "")
	if time.Since(start) > 5*time.Second {
		t.Errorf("long poll outlived its caller by %v", time.Since(start))
	}
}

func TestReleaseRequeuesWithoutFailure(t *testing.T) {
	f := newFarm(t)
	job := f.submit(scenetest.Unlit(8, 8))
	w := f.register()
	for i := 0; i < 5; i++ {
		l := f.lease(w)
		if _, err := f.workers.ReleaseTask(f.ctx, &pb.ReleaseTaskRequest{WorkerId: w, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch}); err != nil {
			t.Fatal(err)
		}
	}
	got, _ := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: job.Id})
	if got.Job.State != pb.JobState_JOB_STATE_RUNNING {
		t.Errorf("job = %v after releases", got.Job.State)
	}
}

func TestWorkerRPCsValidateFields(t *testing.T) {
	f := newFarm(t)
	w := f.register()
	// completeWithLayers completes task j.0 with these per-layer reference errors.
	completeWithLayers := func(layers map[string]float64) func(context.Context) error {
		return coordinatortest.Call(f.workers.CompleteTask, &pb.CompleteTaskRequest{WorkerId: w, TaskId: "j.0", Epoch: 1,
			Metrics: &pb.RoundMetrics{LayerReferenceRmse: layers}})
	}
	completeWithSamples := func(sp *pb.SampleSpread) func(context.Context) error {
		return coordinatortest.Call(f.workers.CompleteTask, &pb.CompleteTaskRequest{WorkerId: w, TaskId: "j.0", Epoch: 1,
			Metrics: &pb.RoundMetrics{Samples: sp}})
	}
	completeWithEstimate := func(m *pb.RoundMetrics) func(context.Context) error {
		return coordinatortest.Call(f.workers.CompleteTask, &pb.CompleteTaskRequest{WorkerId: w, TaskId: "j.0", Epoch: 1, Metrics: m})
	}
	cases := []struct {
		name  string
		call  func(context.Context) error
		code  codes.Code
		field string
	}{
		{"heartbeat no id", coordinatortest.Call(f.workers.Heartbeat, &pb.HeartbeatRequest{}), codes.InvalidArgument, "worker_id"},
		{"heartbeat unknown", coordinatortest.Call(f.workers.Heartbeat, &pb.HeartbeatRequest{WorkerId: "w-nope"}), codes.PermissionDenied, "worker_id"},
		{"heartbeat lease without task", coordinatortest.Call(f.workers.Heartbeat, &pb.HeartbeatRequest{WorkerId: w, Leases: []*pb.HeldLease{{Epoch: 1}}}), codes.InvalidArgument, "leases[0].task_id"},
		{"lease no id", coordinatortest.Call(f.workers.LeaseTask, &pb.LeaseTaskRequest{}), codes.InvalidArgument, "worker_id"},
		{"lease unknown", coordinatortest.Call(f.workers.LeaseTask, &pb.LeaseTaskRequest{WorkerId: "w-nope"}), codes.PermissionDenied, "worker_id"},
		{"lease negative wait", coordinatortest.Call(f.workers.LeaseTask, &pb.LeaseTaskRequest{WorkerId: w, WaitTimeout: wait(-time.Second)}), codes.InvalidArgument, "wait_timeout"},
		{"complete no task", coordinatortest.Call(f.workers.CompleteTask, &pb.CompleteTaskRequest{WorkerId: w, Epoch: 1}), codes.InvalidArgument, "task_id"},
		{"complete no epoch", coordinatortest.Call(f.workers.CompleteTask, &pb.CompleteTaskRequest{WorkerId: w, TaskId: "j.0"}), codes.InvalidArgument, "epoch"},
		{"complete unknown task", coordinatortest.Call(f.workers.CompleteTask, &pb.CompleteTaskRequest{WorkerId: w, TaskId: "j.0", Epoch: 1}), codes.NotFound, "task_id"},
		{"complete NaN layer error", completeWithLayers(map[string]float64{"indirect": math.NaN()}),
			codes.InvalidArgument, "metrics.layer_reference_rmse[indirect]"},
		{"complete unknown layer", completeWithLayers(map[string]float64{"albedo": 0.1}),
			codes.InvalidArgument, "metrics.layer_reference_rmse[albedo]"},
		{"complete samples without a layer", completeWithSamples(&pb.SampleSpread{Min: 1, Mean: 1, Max: 1}),
			codes.InvalidArgument, "metrics.samples.layer"},
		{"complete samples out of order", completeWithSamples(&pb.SampleSpread{Layer: "samples.Y", Min: 3, Mean: 2, Max: 4}),
			codes.InvalidArgument, "metrics.samples"},
		{"complete samples share above 1", completeWithSamples(&pb.SampleSpread{Layer: "samples.Y", Min: 1, Mean: 2, Max: 4, TopErrorDecileShare: proto.Float64(1.5)}),
			codes.InvalidArgument, "metrics.samples.top_error_decile_share"},
		{"complete samples NaN mean", completeWithSamples(&pb.SampleSpread{Layer: "samples.Y", Min: 1, Mean: math.NaN(), Max: 4}),
			codes.InvalidArgument, "metrics.samples.mean"},
		{"complete interval without an estimate", completeWithEstimate(&pb.RoundMetrics{ErrorEstimateLow: proto.Float64(0.1), ErrorEstimateHigh: proto.Float64(0.2)}),
			codes.InvalidArgument, "metrics.error_estimate"},
		{"complete bias above the estimate", completeWithEstimate(&pb.RoundMetrics{ErrorEstimate: proto.Float64(0.1), ErrorEstimateBias: proto.Float64(0.2)}),
			codes.InvalidArgument, "metrics.error_estimate_bias"},
		{"complete interval above the estimate", completeWithEstimate(&pb.RoundMetrics{ErrorEstimate: proto.Float64(0.1), ErrorEstimateLow: proto.Float64(0.15), ErrorEstimateHigh: proto.Float64(0.2)}),
			codes.InvalidArgument, "metrics.error_estimate_low"},
		{"complete interval below the estimate", completeWithEstimate(&pb.RoundMetrics{ErrorEstimate: proto.Float64(0.1), ErrorEstimateLow: proto.Float64(0.05), ErrorEstimateHigh: proto.Float64(0.08)}),
			codes.InvalidArgument, "metrics.error_estimate_high"},
		{"complete NaN interval", completeWithEstimate(&pb.RoundMetrics{ErrorEstimate: proto.Float64(0.1), ErrorEstimateHigh: proto.Float64(math.NaN())}),
			codes.InvalidArgument, "metrics.error_estimate_high"},
		{"fail no worker", coordinatortest.Call(f.workers.FailTask, &pb.FailTaskRequest{TaskId: "j.0", Epoch: 1, Error: "x"}), codes.InvalidArgument, "worker_id"},
		{"fail no message", coordinatortest.Call(f.workers.FailTask, &pb.FailTaskRequest{WorkerId: w, TaskId: "j.0", Epoch: 1}), codes.InvalidArgument, "error"},
		{"release no epoch", coordinatortest.Call(f.workers.ReleaseTask, &pb.ReleaseTaskRequest{WorkerId: w, TaskId: "j.0"}), codes.InvalidArgument, "epoch"},
		{"unregister no id", coordinatortest.Call(f.workers.UnregisterWorker, &pb.UnregisterWorkerRequest{}), codes.InvalidArgument, "worker_id"},
	}
	for _, c := range cases {
		t.Run(c.name, func(t *testing.T) { wantCode(t, c.name, c.call(f.ctx), c.code, c.field) })
	}
}

// A task log ("task.log") is checked as outputs are, with the contract's size limit, in
// CompleteTask's outputs and FailTask's log; a failure's log is then the task's Task.log.
func TestTaskLogIsCheckedAndKeptOnTheTask(t *testing.T) {
	f := newFarm(t)
	_, w, l := f.leased(scenetest.Unlit(8, 8))
	log := f.upload([]byte("time=2026-12-02T18:00:00.000Z level=INFO msg=\"task started\"\n"))
	log.Name = "task.log"
	big := f.upload(bytes.Repeat([]byte("x"), int(rules.RPC.GetMaxTaskLogBytes())+1))
	big.Name = "task.log"
	_, err := f.workers.CompleteTask(f.ctx, &pb.CompleteTaskRequest{WorkerId: w, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Outputs: []*pb.Artifact{big}})
	wantCode(t, "complete with a log over max_task_log_bytes", err, codes.InvalidArgument, "outputs[0].size_bytes")
	tests := []struct {
		name  string
		log   *pb.Artifact
		field string
	}{
		{"log of another name", &pb.Artifact{Name: "tile.exr", Digest: log.Digest, SizeBytes: log.SizeBytes}, "log.name"},
		{"log not uploaded", &pb.Artifact{Name: "task.log", Digest: "sha256:" + strings.Repeat("ab", 32), SizeBytes: 4}, "log.digest"},
		{"log of the wrong size", &pb.Artifact{Name: "task.log", Digest: log.Digest, SizeBytes: log.SizeBytes + 1}, "log.size_bytes"},
		{"log over max_task_log_bytes", big, "log.size_bytes"},
	}
	for _, tt := range tests {
		_, err := f.workers.FailTask(f.ctx, &pb.FailTaskRequest{WorkerId: w, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Error: "boom", Log: tt.log})
		wantCode(t, tt.name, err, codes.InvalidArgument, tt.field)
	}
	if _, err := f.workers.FailTask(f.ctx, &pb.FailTaskRequest{WorkerId: w, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Error: "boom", Log: log}); err != nil {
		t.Fatalf("fail with a good log: %v", err)
	}
	tasks, err := f.jobs.ListTasks(f.ctx, &pb.ListTasksRequest{JobId: l.Task.JobId})
	if err != nil {
		t.Fatal(err)
	}
	if got := tasks.Tasks[l.Task.Index].GetLog(); !proto.Equal(got, log) {
		t.Errorf("failed task's log = %v, want %v", got, log)
	}
}
