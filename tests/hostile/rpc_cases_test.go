package hostile

import (
	"math"
	"strings"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/protobuf/types/known/durationpb"

	pb "photonfarm/proto/renderfarm/v1"
)

const unknownDigest = "sha256:0000000000000000000000000000000000000000000000000000000000000000"

// jobCases are bad JobService requests.
func jobCases() []hostileCase {
	return []hostileCase{
		{"get job: no id", func(f *farm) error { _, err := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{}); return err }, codes.InvalidArgument, "job_id"},
		{"get job: unknown", func(f *farm) error {
			_, err := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: "j-0000000000000000"})
			return err
		}, codes.NotFound, "j-0000000000000000"},
		{"get job: huge id", func(f *farm) error {
			_, err := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: strings.Repeat("j", 1<<20)})
			return err
		}, codes.InvalidArgument, "job_id"},
		{"get job: control characters", func(f *farm) error {
			_, err := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: "j-\x00\x1b[2J"})
			return err
		}, codes.InvalidArgument, "job_id"},
		{"get job: spaces", func(f *farm) error {
			_, err := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: "j 1"})
			return err
		}, codes.InvalidArgument, "job_id"},
		{"list jobs: negative page", func(f *farm) error {
			_, err := f.jobs.ListJobs(f.ctx, &pb.ListJobsRequest{PageSize: -1})
			return err
		}, codes.InvalidArgument, "page_size"},
		{"list jobs: forged token", func(f *farm) error {
			_, err := f.jobs.ListJobs(f.ctx, &pb.ListJobsRequest{PageToken: "not-a-token"})
			return err
		}, codes.InvalidArgument, "page_token"},
		{"list tasks: no job", func(f *farm) error { _, err := f.jobs.ListTasks(f.ctx, &pb.ListTasksRequest{}); return err }, codes.InvalidArgument, "job_id"},
		{"list tasks: unknown job", func(f *farm) error {
			_, err := f.jobs.ListTasks(f.ctx, &pb.ListTasksRequest{JobId: "j-nope"})
			return err
		}, codes.NotFound, "j-nope"},
		{"list tasks: forged token", func(f *farm) error {
			_, err := f.jobs.ListTasks(f.ctx, &pb.ListTasksRequest{JobId: f.job.GetId(), PageToken: "%%%"})
			return err
		}, codes.InvalidArgument, "page_token"},
		{"list tasks: negative page", func(f *farm) error {
			_, err := f.jobs.ListTasks(f.ctx, &pb.ListTasksRequest{JobId: f.job.GetId(), PageSize: -7})
			return err
		}, codes.InvalidArgument, "page_size"},
		{"cancel: no id", func(f *farm) error { _, err := f.jobs.CancelJob(f.ctx, &pb.CancelJobRequest{}); return err }, codes.InvalidArgument, "job_id"},
		{"cancel: unknown", func(f *farm) error {
			_, err := f.jobs.CancelJob(f.ctx, &pb.CancelJobRequest{JobId: "j-ffffffffffffffff"})
			return err
		}, codes.NotFound, "j-ffffffffffffffff"},
		{"plan: no scene", func(f *farm) error { _, err := f.jobs.PlanScene(f.ctx, &pb.PlanSceneRequest{}); return err }, codes.InvalidArgument, "scene"},
		{"watch: unknown", func(f *farm) error {
			stream, err := f.jobs.WatchJob(f.ctx, &pb.WatchJobRequest{JobId: "j-nope"})
			if err != nil {
				return err
			}
			_, err = stream.Recv()
			return err
		}, codes.NotFound, "j-nope"},
		{"watch: no id", func(f *farm) error {
			stream, err := f.jobs.WatchJob(f.ctx, &pb.WatchJobRequest{})
			if err != nil {
				return err
			}
			_, err = stream.Recv()
			return err
		}, codes.InvalidArgument, "job_id"},
		{"submit: request id too long", func(f *farm) error {
			_, err := f.jobs.SubmitJob(f.ctx, &pb.SubmitJobRequest{Scene: f.scene, RequestId: strings.Repeat("r", 129)})
			return err
		}, codes.InvalidArgument, "request_id"},
		{"submit: request id not printable", func(f *farm) error {
			_, err := f.jobs.SubmitJob(f.ctx, &pb.SubmitJobRequest{Scene: f.scene, RequestId: "id\n2"})
			return err
		}, codes.InvalidArgument, "request_id"},
		{"submit: priority too high", func(f *farm) error {
			_, err := f.jobs.SubmitJob(f.ctx, &pb.SubmitJobRequest{Scene: f.scene, Priority: 1001})
			return err
		}, codes.InvalidArgument, "priority"},
		{"submit: priority too low", func(f *farm) error {
			_, err := f.jobs.SubmitJob(f.ctx, &pb.SubmitJobRequest{Scene: f.scene, Priority: math.MinInt32})
			return err
		}, codes.InvalidArgument, "priority"},
		{"set priority: no id", func(f *farm) error {
			_, err := f.jobs.SetJobPriority(f.ctx, &pb.SetJobPriorityRequest{Priority: 1})
			return err
		}, codes.InvalidArgument, "job_id"},
		{"set priority: unknown job", func(f *farm) error {
			_, err := f.jobs.SetJobPriority(f.ctx, &pb.SetJobPriorityRequest{JobId: "j-0000000000000000", Priority: 1})
			return err
		}, codes.NotFound, "j-0000000000000000"},
		{"set priority: out of range", func(f *farm) error {
			_, err := f.jobs.SetJobPriority(f.ctx, &pb.SetJobPriorityRequest{JobId: f.job.GetId(), Priority: math.MaxInt32})
			return err
		}, codes.InvalidArgument, "priority"},
		{"set priority: ended job", func(f *farm) error {
			_, err := f.jobs.SetJobPriority(f.ctx, &pb.SetJobPriorityRequest{JobId: f.ended.GetId(), Priority: 1})
			return err
		}, codes.FailedPrecondition, "ended"},
		{"set priority: huge id", func(f *farm) error {
			_, err := f.jobs.SetJobPriority(f.ctx, &pb.SetJobPriorityRequest{JobId: strings.Repeat("j", 1<<20), Priority: 1})
			return err
		}, codes.InvalidArgument, "job_id"},
		{"unblock: no id", func(f *farm) error {
			_, err := f.jobs.UnblockWorker(f.ctx, &pb.UnblockWorkerRequest{})
			return err
		}, codes.InvalidArgument, "job_id"},
		{"unblock: unknown job", func(f *farm) error {
			_, err := f.jobs.UnblockWorker(f.ctx, &pb.UnblockWorkerRequest{JobId: "j-ffffffffffffffff", WorkerId: f.workerID})
			return err
		}, codes.NotFound, "j-ffffffffffffffff"},
		{"unblock: control characters in worker id", func(f *farm) error {
			_, err := f.jobs.UnblockWorker(f.ctx, &pb.UnblockWorkerRequest{JobId: f.job.GetId(), WorkerId: "w-\x00\x1b[2J"})
			return err
		}, codes.InvalidArgument, "worker_id"},
		{"unblock: huge worker id", func(f *farm) error {
			_, err := f.jobs.UnblockWorker(f.ctx, &pb.UnblockWorkerRequest{JobId: f.job.GetId(), WorkerId: strings.Repeat("w", 1<<20)})
			return err
		}, codes.InvalidArgument, "worker_id"},
	}
}

// workerCases are bad or forged WorkerService requests: unknown workers, reports under
// leases the caller does not hold, and absurd fields.
func workerCases() []hostileCase {
	complete := func(mut func(f *farm, r *pb.CompleteTaskRequest)) func(f *farm) error {
		return func(f *farm) error {
			r := &pb.CompleteTaskRequest{WorkerId: f.workerID, TaskId: f.lease.GetTaskId(), Epoch: f.lease.GetEpoch()}
			mut(f, r)
			_, err := f.workers.CompleteTask(f.ctx, r)
			return err
		}
	}
	fail := func(mut func(f *farm, r *pb.FailTaskRequest)) func(f *farm) error {
		return func(f *farm) error {
			r := &pb.FailTaskRequest{WorkerId: f.workerID, TaskId: f.lease.GetTaskId(), Epoch: f.lease.GetEpoch(), Error: "boom"}
			mut(f, r)
			_, err := f.workers.FailTask(f.ctx, r)
			return err
		}
	}
	release := func(mut func(f *farm, r *pb.ReleaseTaskRequest)) func(f *farm) error {
		return func(f *farm) error {
			r := &pb.ReleaseTaskRequest{WorkerId: f.workerID, TaskId: f.lease.GetTaskId(), Epoch: f.lease.GetEpoch()}
			mut(f, r)
			_, err := f.workers.ReleaseTask(f.ctx, r)
			return err
		}
	}
	return []hostileCase{
		{"register: hostname too long", func(f *farm) error {
			_, err := f.workers.RegisterWorker(f.ctx, &pb.RegisterWorkerRequest{Hostname: strings.Repeat("h", 256)})
			return err
		}, codes.InvalidArgument, "hostname"},
		{"heartbeat: no worker", func(f *farm) error { _, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{}); return err }, codes.InvalidArgument, "worker_id"},
		{"heartbeat: unknown worker", func(f *farm) error {
			_, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: "w-forged"})
			return err
		}, codes.NotFound, "worker_id"},
		{"heartbeat: lease without task", func(f *farm) error {
			_, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: f.workerID, Leases: []*pb.HeldLease{{Epoch: 1}}})
			return err
		}, codes.InvalidArgument, "leases[0].task_id"},
		{"heartbeat: lease without epoch", func(f *farm) error {
			_, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: f.workerID, Leases: []*pb.HeldLease{{TaskId: f.lease.GetTaskId()}}})
			return err
		}, codes.InvalidArgument, "leases[0].epoch"},
		{"lease: no worker", func(f *farm) error { _, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{}); return err }, codes.InvalidArgument, "worker_id"},
		{"lease: unknown worker", func(f *farm) error {
			_, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: "w-forged"})
			return err
		}, codes.NotFound, "worker_id"},
		{"lease: negative wait", func(f *farm) error {
			_, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: "w-forged", WaitTimeout: durationpb.New(-time.Second)})
			return err
		}, codes.InvalidArgument, "wait_timeout"},
		{"lease: invalid wait", func(f *farm) error {
			_, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: "w-forged", WaitTimeout: &durationpb.Duration{Seconds: 1, Nanos: -5}})
			return err
		}, codes.InvalidArgument, "wait_timeout"},
		{"complete: no task", complete(func(_ *farm, r *pb.CompleteTaskRequest) { r.TaskId = "" }), codes.InvalidArgument, "task_id"},
		{"complete: no epoch", complete(func(_ *farm, r *pb.CompleteTaskRequest) { r.Epoch = 0 }), codes.InvalidArgument, "epoch"},
		{"complete: no worker", complete(func(_ *farm, r *pb.CompleteTaskRequest) { r.WorkerId = "" }), codes.InvalidArgument, "worker_id"},
		{"complete: unknown task", complete(func(_ *farm, r *pb.CompleteTaskRequest) { r.TaskId = "j-nope.0" }), codes.NotFound, "task_id"},
		{"complete: stale epoch", complete(func(_ *farm, r *pb.CompleteTaskRequest) { r.Epoch++ }), codes.FailedPrecondition, "epoch"},
		{"complete: another worker's lease", complete(func(_ *farm, r *pb.CompleteTaskRequest) { r.WorkerId = "w-thief" }), codes.FailedPrecondition, "another worker"},
		{"complete: a task never leased", complete(func(f *farm, r *pb.CompleteTaskRequest) {
			r.TaskId = f.job.GetId() + ".1"
		}), codes.FailedPrecondition, ".1"},
		{"complete: output not uploaded", complete(func(_ *farm, r *pb.CompleteTaskRequest) {
			r.Outputs = []*pb.Artifact{{Name: "tile.exr", Digest: unknownDigest}}
		}), codes.InvalidArgument, "outputs[0].digest"},
		{"complete: output digest malformed", complete(func(_ *farm, r *pb.CompleteTaskRequest) {
			r.Outputs = []*pb.Artifact{{Name: "tile.exr", Digest: "sha256:xyz"}}
		}), codes.InvalidArgument, "outputs[0].digest"},
		{"complete: metrics NaN", complete(func(_ *farm, r *pb.CompleteTaskRequest) {
			r.Metrics = &pb.RoundMetrics{ErrorEstimate: ptr(math.NaN())}
		}), codes.InvalidArgument, "metrics.error_estimate"},
		{"complete: metrics negative", complete(func(_ *farm, r *pb.CompleteTaskRequest) {
			r.Metrics = &pb.RoundMetrics{ReferenceRmse: ptr(-1)}
		}), codes.InvalidArgument, "metrics.reference_rmse"},
		{"complete: metrics of an unknown layer", complete(func(_ *farm, r *pb.CompleteTaskRequest) {
			r.Metrics = &pb.RoundMetrics{LayerReferenceRmse: map[string]float64{"../../etc": 1}}
		}), codes.InvalidArgument, "layer_reference_rmse"},
		{"fail: no message", fail(func(_ *farm, r *pb.FailTaskRequest) { r.Error = "" }), codes.InvalidArgument, "error"},
		{"fail: no worker", fail(func(_ *farm, r *pb.FailTaskRequest) { r.WorkerId = "" }), codes.InvalidArgument, "worker_id"},
		{"fail: stale epoch", fail(func(_ *farm, r *pb.FailTaskRequest) { r.Epoch = 99 }), codes.FailedPrecondition, "epoch"},
		{"fail: another worker's lease", fail(func(_ *farm, r *pb.FailTaskRequest) { r.WorkerId = "w-thief" }), codes.FailedPrecondition, "another worker"},
		{"fail: unknown task", fail(func(_ *farm, r *pb.FailTaskRequest) { r.TaskId = "j-nope.3" }), codes.NotFound, "task_id"},
		{"release: no epoch", release(func(_ *farm, r *pb.ReleaseTaskRequest) { r.Epoch = 0 }), codes.InvalidArgument, "epoch"},
		{"release: stale epoch", release(func(_ *farm, r *pb.ReleaseTaskRequest) { r.Epoch += 5 }), codes.FailedPrecondition, "epoch"},
		{"release: another worker's lease", release(func(_ *farm, r *pb.ReleaseTaskRequest) { r.WorkerId = "w-thief" }), codes.FailedPrecondition, "another worker"},
		{"unregister: no id", func(f *farm) error {
			_, err := f.workers.UnregisterWorker(f.ctx, &pb.UnregisterWorkerRequest{})
			return err
		}, codes.InvalidArgument, "worker_id"},
		{"unregister: unknown", func(f *farm) error {
			_, err := f.workers.UnregisterWorker(f.ctx, &pb.UnregisterWorkerRequest{WorkerId: "w-forged"})
			return err
		}, codes.NotFound, "worker_id"},
	}
}

func ptr(v float64) *float64 { return &v }

// blobCases are bad uploads and downloads.
func blobCases() []hostileCase {
	upload := func(parts ...*pb.UploadBlobRequest) func(f *farm) error {
		return func(f *farm) error {
			stream, err := f.blobs.UploadBlob(f.ctx)
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
	download := func(digest string) func(f *farm) error {
		return func(f *farm) error {
			stream, err := f.blobs.DownloadBlob(f.ctx, &pb.DownloadBlobRequest{Digest: digest})
			if err != nil {
				return err
			}
			_, err = stream.Recv()
			return err
		}
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
		{"info: unknown", func(f *farm) error {
			_, err := f.blobs.GetBlobInfo(f.ctx, &pb.GetBlobInfoRequest{Digest: unknownDigest})
			return err
		}, codes.NotFound, "sha256:0000"},
		{"info: traversal", func(f *farm) error {
			_, err := f.blobs.GetBlobInfo(f.ctx, &pb.GetBlobInfoRequest{Digest: "sha256:../../../../etc/shadow"})
			return err
		}, codes.InvalidArgument, "digest"},
	}
}
