package hostile

import (
	"context"
	"math"
	"strings"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/metadata"
	"google.golang.org/protobuf/types/known/durationpb"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/coordinatortest"
	pb "photonfarm/proto/renderfarm/v1"
)

const unknownDigest = "sha256:0000000000000000000000000000000000000000000000000000000000000000"

// jobCases are bad JobService requests.
func jobCases(f *farm) []hostileCase {
	// watch fails with the watch's error or else that of its first message.
	watch := func(req *pb.WatchJobRequest) func(context.Context) error {
		return func(ctx context.Context) error {
			stream, err := f.jobs.WatchJob(ctx, req)
			if err != nil {
				return err
			}
			_, err = stream.Recv()
			return err
		}
	}
	return []hostileCase{
		{"get job: no id", coordinatortest.Call(f.jobs.GetJob, &pb.GetJobRequest{}), codes.InvalidArgument, "job_id"},
		{"get job: unknown", coordinatortest.Call(f.jobs.GetJob, &pb.GetJobRequest{JobId: "j-0000000000000000"}), codes.NotFound, "j-0000000000000000"},
		{"get job: huge id", coordinatortest.Call(f.jobs.GetJob, &pb.GetJobRequest{JobId: strings.Repeat("j", 1<<20)}), codes.InvalidArgument, "job_id"},
		{"get job: control characters", coordinatortest.Call(f.jobs.GetJob, &pb.GetJobRequest{JobId: "j-\x00\x1b[2J"}), codes.InvalidArgument, "job_id"},
		{"get job: spaces", coordinatortest.Call(f.jobs.GetJob, &pb.GetJobRequest{JobId: "j 1"}), codes.InvalidArgument, "job_id"},
		{"list jobs: negative page", coordinatortest.Call(f.jobs.ListJobs, &pb.ListJobsRequest{PageSize: -1}), codes.InvalidArgument, "page_size"},
		{"list jobs: forged token", coordinatortest.Call(f.jobs.ListJobs, &pb.ListJobsRequest{PageToken: "not-a-token"}), codes.InvalidArgument, "page_token"},
		{"list tasks: no job", coordinatortest.Call(f.jobs.ListTasks, &pb.ListTasksRequest{}), codes.InvalidArgument, "job_id"},
		{"list tasks: unknown job", coordinatortest.Call(f.jobs.ListTasks, &pb.ListTasksRequest{JobId: "j-nope"}), codes.NotFound, "j-nope"},
		{"list tasks: forged token", coordinatortest.Call(f.jobs.ListTasks, &pb.ListTasksRequest{JobId: f.job.GetId(), PageToken: "%%%"}), codes.InvalidArgument, "page_token"},
		{"list tasks: negative page", coordinatortest.Call(f.jobs.ListTasks, &pb.ListTasksRequest{JobId: f.job.GetId(), PageSize: -7}), codes.InvalidArgument, "page_size"},
		{"cancel: no id", coordinatortest.Call(f.jobs.CancelJob, &pb.CancelJobRequest{}), codes.InvalidArgument, "job_id"},
		{"cancel: unknown", coordinatortest.Call(f.jobs.CancelJob, &pb.CancelJobRequest{JobId: "j-ffffffffffffffff"}), codes.NotFound, "j-ffffffffffffffff"},
		{"plan: no scene", coordinatortest.Call(f.jobs.PlanScene, &pb.PlanSceneRequest{}), codes.InvalidArgument, "scene"},
		{"watch: unknown", watch(&pb.WatchJobRequest{JobId: "j-nope"}), codes.NotFound, "j-nope"},
		{"watch: no id", watch(&pb.WatchJobRequest{}), codes.InvalidArgument, "job_id"},
		{"submit: request id too long", coordinatortest.Call(f.jobs.SubmitJob, &pb.SubmitJobRequest{Scene: f.scene, RequestId: strings.Repeat("r", 129)}), codes.InvalidArgument, "request_id"},
		{"submit: request id not printable", coordinatortest.Call(f.jobs.SubmitJob, &pb.SubmitJobRequest{Scene: f.scene, RequestId: "id\n2"}), codes.InvalidArgument, "request_id"},
		{"submit: priority too high", coordinatortest.Call(f.jobs.SubmitJob, &pb.SubmitJobRequest{Scene: f.scene, Priority: 1001}), codes.InvalidArgument, "priority"},
		{"submit: priority too low", coordinatortest.Call(f.jobs.SubmitJob, &pb.SubmitJobRequest{Scene: f.scene, Priority: math.MinInt32}), codes.InvalidArgument, "priority"},
		{"set priority: no id", coordinatortest.Call(f.jobs.SetJobPriority, &pb.SetJobPriorityRequest{Priority: 1}), codes.InvalidArgument, "job_id"},
		{"set priority: unknown job", coordinatortest.Call(f.jobs.SetJobPriority, &pb.SetJobPriorityRequest{JobId: "j-0000000000000000", Priority: 1}), codes.NotFound, "j-0000000000000000"},
		{"set priority: out of range", coordinatortest.Call(f.jobs.SetJobPriority, &pb.SetJobPriorityRequest{JobId: f.job.GetId(), Priority: math.MaxInt32}), codes.InvalidArgument, "priority"},
		{"set priority: ended job", coordinatortest.Call(f.jobs.SetJobPriority, &pb.SetJobPriorityRequest{JobId: f.ended.GetId(), Priority: 1}), codes.FailedPrecondition, "ended"},
		{"set priority: huge id", coordinatortest.Call(f.jobs.SetJobPriority, &pb.SetJobPriorityRequest{JobId: strings.Repeat("j", 1<<20), Priority: 1}), codes.InvalidArgument, "job_id"},
		{"unblock: no id", coordinatortest.Call(f.jobs.UnblockWorker, &pb.UnblockWorkerRequest{}), codes.InvalidArgument, "job_id"},
		{"unblock: unknown job", coordinatortest.Call(f.jobs.UnblockWorker, &pb.UnblockWorkerRequest{JobId: "j-ffffffffffffffff", WorkerId: f.workerID}), codes.NotFound, "j-ffffffffffffffff"},
		{"unblock: control characters in worker id", coordinatortest.Call(f.jobs.UnblockWorker, &pb.UnblockWorkerRequest{JobId: f.job.GetId(), WorkerId: "w-\x00\x1b[2J"}), codes.InvalidArgument, "worker_id"},
		{"unblock: huge worker id", coordinatortest.Call(f.jobs.UnblockWorker, &pb.UnblockWorkerRequest{JobId: f.job.GetId(), WorkerId: strings.Repeat("w", 1<<20)}), codes.InvalidArgument, "worker_id"},
		{"requeue: no id", coordinatortest.Call(f.jobs.RequeueJob, &pb.RequeueJobRequest{}), codes.InvalidArgument, "job_id"},
		{"requeue: unknown", coordinatortest.Call(f.jobs.RequeueJob, &pb.RequeueJobRequest{JobId: "j-ffffffffffffffff"}), codes.NotFound, "j-ffffffffffffffff"},
		{"requeue: running job", coordinatortest.Call(f.jobs.RequeueJob, &pb.RequeueJobRequest{JobId: f.job.GetId()}), codes.FailedPrecondition, "has not ended"},
		{"requeue: huge id", coordinatortest.Call(f.jobs.RequeueJob, &pb.RequeueJobRequest{JobId: strings.Repeat("j", 1<<20)}), codes.InvalidArgument, "job_id"},
		{"retry: no id", coordinatortest.Call(f.jobs.RetryTask, &pb.RetryTaskRequest{}), codes.InvalidArgument, "task_id"},
		{"retry: a job id", coordinatortest.Call(f.jobs.RetryTask, &pb.RetryTaskRequest{TaskId: f.job.GetId()}), codes.InvalidArgument, "task_id"},
		{"retry: unknown task", coordinatortest.Call(f.jobs.RetryTask, &pb.RetryTaskRequest{TaskId: "j-ffffffffffffffff.0"}), codes.NotFound, "j-ffffffffffffffff"},
		{"retry: leased task", coordinatortest.Call(f.jobs.RetryTask, &pb.RetryTaskRequest{TaskId: f.lease.GetTaskId()}), codes.FailedPrecondition, "not failed"},
		{"retry: control characters", coordinatortest.Call(f.jobs.RetryTask, &pb.RetryTaskRequest{TaskId: "j-\x00\x1b[2J.0"}), codes.InvalidArgument, "task_id"},
		{"delete: no id", coordinatortest.Call(f.jobs.DeleteJob, &pb.DeleteJobRequest{}), codes.InvalidArgument, "job_id"},
		{"delete: unknown", coordinatortest.Call(f.jobs.DeleteJob, &pb.DeleteJobRequest{JobId: "j-ffffffffffffffff"}), codes.NotFound, "j-ffffffffffffffff"},
		{"delete: huge id", coordinatortest.Call(f.jobs.DeleteJob, &pb.DeleteJobRequest{JobId: strings.Repeat("j", 1<<20)}), codes.InvalidArgument, "job_id"},
	}
}

// workerCases are bad or forged WorkerService requests: unknown workers, reports under
// leases the caller does not hold, and absurd fields.
func workerCases(f *farm) []hostileCase {
	complete := func(mut func(r *pb.CompleteTaskRequest)) func(context.Context) error {
		r := &pb.CompleteTaskRequest{WorkerId: f.workerID, TaskId: f.lease.GetTaskId(), Epoch: f.lease.GetEpoch()}
		mut(r)
		return coordinatortest.Call(f.workers.CompleteTask, r)
	}
	fail := func(mut func(r *pb.FailTaskRequest)) func(context.Context) error {
		r := &pb.FailTaskRequest{WorkerId: f.workerID, TaskId: f.lease.GetTaskId(), Epoch: f.lease.GetEpoch(), Error: "boom"}
		mut(r)
		return coordinatortest.Call(f.workers.FailTask, r)
	}
	release := func(mut func(r *pb.ReleaseTaskRequest)) func(context.Context) error {
		r := &pb.ReleaseTaskRequest{WorkerId: f.workerID, TaskId: f.lease.GetTaskId(), Epoch: f.lease.GetEpoch()}
		mut(r)
		return coordinatortest.Call(f.workers.ReleaseTask, r)
	}
	return []hostileCase{
		{"register: hostname too long", coordinatortest.Call(f.workers.RegisterWorker, &pb.RegisterWorkerRequest{Hostname: strings.Repeat("h", 256)}), codes.InvalidArgument, "hostname"},
		{"heartbeat: no worker", coordinatortest.Call(f.workers.Heartbeat, &pb.HeartbeatRequest{}), codes.InvalidArgument, "worker_id"},
		{"heartbeat: unknown worker", coordinatortest.Call(f.workers.Heartbeat, &pb.HeartbeatRequest{WorkerId: "w-forged"}), codes.PermissionDenied, "worker_id"},
		{"heartbeat: lease without task", coordinatortest.Call(f.workers.Heartbeat, &pb.HeartbeatRequest{WorkerId: f.workerID, Leases: []*pb.HeldLease{{Epoch: 1}}}), codes.InvalidArgument, "leases[0].task_id"},
		{"heartbeat: lease without epoch", coordinatortest.Call(f.workers.Heartbeat, &pb.HeartbeatRequest{WorkerId: f.workerID, Leases: []*pb.HeldLease{{TaskId: f.lease.GetTaskId()}}}), codes.InvalidArgument, "leases[0].epoch"},
		{"lease: no worker", coordinatortest.Call(f.workers.LeaseTask, &pb.LeaseTaskRequest{}), codes.InvalidArgument, "worker_id"},
		{"lease: unknown worker", coordinatortest.Call(f.workers.LeaseTask, &pb.LeaseTaskRequest{WorkerId: "w-forged"}), codes.PermissionDenied, "worker_id"},
		{"lease: negative wait", coordinatortest.Call(f.workers.LeaseTask, &pb.LeaseTaskRequest{WorkerId: f.thief.GetWorkerId(), WaitTimeout: durationpb.New(-time.Second)}), codes.InvalidArgument, "wait_timeout"},
		{"lease: invalid wait", coordinatortest.Call(f.workers.LeaseTask, &pb.LeaseTaskRequest{WorkerId: f.thief.GetWorkerId(), WaitTimeout: &durationpb.Duration{Seconds: 1, Nanos: -5}}), codes.InvalidArgument, "wait_timeout"},
		{"complete: no task", complete(func(r *pb.CompleteTaskRequest) { r.TaskId = "" }), codes.InvalidArgument, "task_id"},
		{"complete: no epoch", complete(func(r *pb.CompleteTaskRequest) { r.Epoch = 0 }), codes.InvalidArgument, "epoch"},
		{"complete: no worker", complete(func(r *pb.CompleteTaskRequest) { r.WorkerId = "" }), codes.InvalidArgument, "worker_id"},
		{"complete: unknown task", complete(func(r *pb.CompleteTaskRequest) { r.TaskId = "j-nope.0" }), codes.NotFound, "task_id"},
		{"complete: stale epoch", complete(func(r *pb.CompleteTaskRequest) { r.Epoch++ }), codes.FailedPrecondition, "epoch"},
		{"complete: another worker's lease", complete(func(r *pb.CompleteTaskRequest) { r.WorkerId = f.thief.GetWorkerId() }), codes.FailedPrecondition, "another worker"},
		{"complete: a task never leased", complete(func(r *pb.CompleteTaskRequest) {
			r.TaskId = f.job.GetId() + ".1"
		}), codes.FailedPrecondition, ".1"},
		{"complete: output not uploaded", complete(func(r *pb.CompleteTaskRequest) {
			r.Outputs = []*pb.Artifact{{Name: "tile.exr", Digest: unknownDigest}}
		}), codes.InvalidArgument, "outputs[0].digest"},
		{"complete: output digest malformed", complete(func(r *pb.CompleteTaskRequest) {
			r.Outputs = []*pb.Artifact{{Name: "tile.exr", Digest: "sha256:xyz"}}
		}), codes.InvalidArgument, "outputs[0].digest"},
		{"complete: metrics NaN", complete(func(r *pb.CompleteTaskRequest) {
			r.Metrics = &pb.RoundMetrics{ErrorEstimate: ptr(math.NaN())}
		}), codes.InvalidArgument, "metrics.error_estimate"},
		{"complete: metrics negative", complete(func(r *pb.CompleteTaskRequest) {
			r.Metrics = &pb.RoundMetrics{ReferenceRmse: ptr(-1)}
		}), codes.InvalidArgument, "metrics.reference_rmse"},
		{"complete: metrics of an unknown layer", complete(func(r *pb.CompleteTaskRequest) {
			r.Metrics = &pb.RoundMetrics{LayerReferenceRmse: map[string]float64{"../../etc": 1}}
		}), codes.InvalidArgument, "layer_reference_rmse"},
		{"fail: no message", fail(func(r *pb.FailTaskRequest) { r.Error = "" }), codes.InvalidArgument, "error"},
		{"fail: no worker", fail(func(r *pb.FailTaskRequest) { r.WorkerId = "" }), codes.InvalidArgument, "worker_id"},
		{"fail: stale epoch", fail(func(r *pb.FailTaskRequest) { r.Epoch = 99 }), codes.FailedPrecondition, "epoch"},
		{"fail: another worker's lease", fail(func(r *pb.FailTaskRequest) { r.WorkerId = f.thief.GetWorkerId() }), codes.FailedPrecondition, "another worker"},
		{"fail: unknown task", fail(func(r *pb.FailTaskRequest) { r.TaskId = "j-nope.3" }), codes.NotFound, "task_id"},
		{"release: no epoch", release(func(r *pb.ReleaseTaskRequest) { r.Epoch = 0 }), codes.InvalidArgument, "epoch"},
		{"release: stale epoch", release(func(r *pb.ReleaseTaskRequest) { r.Epoch += 5 }), codes.FailedPrecondition, "epoch"},
		{"release: another worker's lease", release(func(r *pb.ReleaseTaskRequest) { r.WorkerId = f.thief.GetWorkerId() }), codes.FailedPrecondition, "another worker"},
		{"unregister: no id", coordinatortest.Call(f.workers.UnregisterWorker, &pb.UnregisterWorkerRequest{}), codes.InvalidArgument, "worker_id"},
		{"unregister: unknown", coordinatortest.Call(f.workers.UnregisterWorker, &pb.UnregisterWorkerRequest{WorkerId: "w-forged"}), codes.PermissionDenied, "worker_id"},
	}
}

// impersonationCases are calls naming the honest worker (who holds a lease) by a caller
// with a worker token but not that registration's secret: none, the thief's own, or one
// made up. Each must be refused before it touches the lease or the registration.
func impersonationCases(f *farm) []hostileCase {
	id, l := f.workerID, f.lease
	calls := []struct {
		name string
		call func(w pb.WorkerServiceClient) func(context.Context) error
	}{
		{"heartbeat", func(w pb.WorkerServiceClient) func(context.Context) error {
			return coordinatortest.Call(w.Heartbeat, &pb.HeartbeatRequest{WorkerId: id, Leases: []*pb.HeldLease{{TaskId: l.GetTaskId(), Epoch: l.GetEpoch()}}})
		}},
		{"lease", func(w pb.WorkerServiceClient) func(context.Context) error {
			return coordinatortest.Call(w.LeaseTask, &pb.LeaseTaskRequest{WorkerId: id})
		}},
		{"complete", func(w pb.WorkerServiceClient) func(context.Context) error {
			return coordinatortest.Call(w.CompleteTask, &pb.CompleteTaskRequest{WorkerId: id, TaskId: l.GetTaskId(), Epoch: l.GetEpoch()})
		}},
		{"fail", func(w pb.WorkerServiceClient) func(context.Context) error {
			return coordinatortest.Call(w.FailTask, &pb.FailTaskRequest{WorkerId: id, TaskId: l.GetTaskId(), Epoch: l.GetEpoch(), Error: "sabotage", Kind: pb.FailureKind_FAILURE_KIND_BAD_INPUT})
		}},
		{"release", func(w pb.WorkerServiceClient) func(context.Context) error {
			return coordinatortest.Call(w.ReleaseTask, &pb.ReleaseTaskRequest{WorkerId: id, TaskId: l.GetTaskId(), Epoch: l.GetEpoch()})
		}},
		{"unregister", func(w pb.WorkerServiceClient) func(context.Context) error {
			return coordinatortest.Call(w.UnregisterWorker, &pb.UnregisterWorkerRequest{WorkerId: id})
		}},
	}
	withSecret := func(secret string, call func(context.Context) error) func(context.Context) error {
		return func(ctx context.Context) error {
			return call(metadata.AppendToOutgoingContext(ctx, rules.WorkerSecretMetadata, secret))
		}
	}
	var out []hostileCase
	for _, c := range calls {
		out = append(out,
			hostileCase{c.name + ": another worker, no secret", c.call(f.bare), codes.PermissionDenied, "must carry the metadata"},
			hostileCase{c.name + ": another worker, the caller's own secret", withSecret(f.thief.GetWorkerSecret(), c.call(f.bare)), codes.PermissionDenied, "is not worker " + id},
			hostileCase{c.name + ": another worker, a made-up secret", withSecret(strings.Repeat("0", 64), c.call(f.bare)), codes.PermissionDenied, "is not worker " + id},
		)
	}
	return out
}

func ptr(v float64) *float64 { return &v }

// blobCases are bad uploads and downloads.
func blobCases(f *farm) []hostileCase {
	upload := func(parts ...*pb.UploadBlobRequest) func(context.Context) error {
		return func(ctx context.Context) error {
			stream, err := f.blobs.UploadBlob(ctx)
			if err != nil {
				return err
			}
			for _, p := range parts {
				if err := stream.Send(p); err != nil {
					break // the server has answered; CloseAndRecv tells what
				}
			}
			_, err = stream.CloseAndRecv()
			return err
		}
	}
	header := func(digest string, size int64) *pb.UploadBlobRequest {
		return &pb.UploadBlobRequest{Part: &pb.UploadBlobRequest_Header{Header: &pb.BlobHeader{Digest: digest, SizeBytes: size}}}
	}
	chunk := func(b []byte) *pb.UploadBlobRequest {
		return &pb.UploadBlobRequest{Part: &pb.UploadBlobRequest_Chunk{Chunk: b}}
	}
	hello := []byte("hello")
	helloDigest := "sha256:2cf24dba5fb0a30e26e83b2ac5b9e29e1b161e5c1fa7425e73043362938b9824"
	downloadRange := func(req *pb.DownloadBlobRequest) func(context.Context) error {
		return func(ctx context.Context) error {
			stream, err := f.blobs.DownloadBlob(ctx, req)
			if err != nil {
				return err
			}
			_, err = stream.Recv()
			return err
		}
	}
	download := func(digest string) func(context.Context) error {
		return downloadRange(&pb.DownloadBlobRequest{Digest: digest})
	}
	// helloPastItsEnd stores hello, then asks for it from past its end.
	helloPastItsEnd := func(ctx context.Context) error {
		if err := upload(header(helloDigest, 5), chunk(hello))(ctx); err != nil {
			return err
		}
		return downloadRange(&pb.DownloadBlobRequest{Digest: helloDigest, Offset: 6})(ctx)
	}
	return []hostileCase{
		{"upload: no header", upload(chunk(hello)), codes.InvalidArgument, "header"},
		{"upload: nothing at all", upload(), codes.InvalidArgument, "header"},
		{"upload: malformed digest", upload(header("sha256:nothex", 5), chunk(hello)), codes.InvalidArgument, "digest"},
		{"upload: other algorithm", upload(header("md5:5d41402abc4b2a76b9719d911017c592", 5), chunk(hello)), codes.InvalidArgument, "digest"},
		{"upload: digest does not match", upload(header(unknownDigest, 5), chunk(hello)), codes.InvalidArgument, "digest"},
		{"upload: fewer bytes than declared", upload(header(helloDigest, 6), chunk(hello)), codes.InvalidArgument, "size"},
		{"upload: more bytes than declared", upload(header(helloDigest, 4), chunk(hello)), codes.InvalidArgument, "size"},
		{"upload: negative size", upload(header(helloDigest, -5), chunk(hello)), codes.InvalidArgument, "size"},
		{"upload: absurd size", upload(header(helloDigest, 1<<50)), codes.ResourceExhausted, "limit"},
		{"upload: two headers", upload(header(helloDigest, 5), header(helloDigest, 5), chunk(hello)), codes.InvalidArgument, "header"},
		{"upload: chunk over the limit", upload(header(helloDigest, 5), chunk(make([]byte, 5<<20))), codes.InvalidArgument, "chunk"},
		{"download: unknown", download(unknownDigest), codes.NotFound, "sha256:0000"},
		{"download: malformed", download("../../etc/passwd"), codes.InvalidArgument, "digest"},
		{"download: empty", download(""), codes.InvalidArgument, "digest"},
		{"download: negative offset", downloadRange(&pb.DownloadBlobRequest{Digest: unknownDigest, Offset: -1}), codes.InvalidArgument, "offset"},
		{"download: negative length", downloadRange(&pb.DownloadBlobRequest{Digest: unknownDigest, Length: -1 << 62}), codes.InvalidArgument, "length"},
		{"download: offset past the end", helloPastItsEnd, codes.OutOfRange, "offset"},
		{"info: unknown", coordinatortest.Call(f.blobs.GetBlobInfo, &pb.GetBlobInfoRequest{Digest: unknownDigest}), codes.NotFound, "sha256:0000"},
		{"info: traversal", coordinatortest.Call(f.blobs.GetBlobInfo, &pb.GetBlobInfoRequest{Digest: "sha256:../../../../etc/shadow"}), codes.InvalidArgument, "digest"},
	}
}
