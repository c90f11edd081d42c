package hostile

import (
	"context"
	"strings"
	"testing"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/metadata"
	"google.golang.org/grpc/status"

	"photonfarm/client"
	"photonfarm/coordinator"
	"photonfarm/coordinator/coordinatortest"
	pb "photonfarm/proto/renderfarm/v1"
)

const (
	clientToken = "client-token-for-the-hostile-suite"
	workerToken = "worker-token-for-the-hostile-suite"
)

// TestHostileTokensAreRefused sends a coordinator that requires tokens calls with none, a
// malformed header, an unknown token, and the other role's token, on every service; each
// must be refused with UNAUTHENTICATED or PERMISSION_DENIED naming the method, and the
// stored jobs must be as they were.
func TestHostileTokensAreRefused(t *testing.T) {
	ctx, stop := context.WithCancel(context.Background())
	defer stop()
	conn := coordinatortest.Serve(t, coordinator.Config{LeaseDuration: time.Minute,
		ClientTokens: []string{clientToken}, WorkerTokens: []string{workerToken}}).Dial(t, client.WorkerSecrets())
	jobs, workers, blobs := pb.NewJobServiceClient(conn), pb.NewWorkerServiceClient(conn), pb.NewBlobServiceClient(conn)
	as := func(authorization string) context.Context {
		if authorization == "" {
			return ctx
		}
		return metadata.AppendToOutgoingContext(ctx, "authorization", authorization)
	}
	asClient := as("Bearer " + clientToken)

	job, err := jobs.GetJob(asClient, &pb.GetJobRequest{JobId: "j-nope"})
	if status.Code(err) != codes.NotFound {
		t.Fatalf("GetJob with the client token = %v, %v; want NotFound (the token works)", job, err)
	}
	before, err := jobs.ListJobs(asClient, &pb.ListJobsRequest{})
	if err != nil {
		t.Fatal(err)
	}

	calls := []struct {
		method string
		call   func(ctx context.Context) error
	}{
		{"ListJobs", coordinatortest.Call(jobs.ListJobs, &pb.ListJobsRequest{})},
		{"CancelJob", coordinatortest.Call(jobs.CancelJob, &pb.CancelJobRequest{JobId: "j-1"})},
		{"SetJobPriority", coordinatortest.Call(jobs.SetJobPriority, &pb.SetJobPriorityRequest{JobId: "j-1", Priority: 5})},
		{"RegisterWorker", coordinatortest.Call(workers.RegisterWorker, &pb.RegisterWorkerRequest{Hostname: "intruder"})},
		{"LeaseTask", coordinatortest.Call(workers.LeaseTask, &pb.LeaseTaskRequest{WorkerId: "w-1"})},
		{"GetBlobInfo", coordinatortest.Call(blobs.GetBlobInfo, &pb.GetBlobInfoRequest{Digest: unknownDigest})},
	}
	clientOnly := map[string]bool{"ListJobs": true, "CancelJob": true, "SetJobPriority": true}
	workerOnly := map[string]bool{"RegisterWorker": true, "LeaseTask": true}
	n := 0
	for _, c := range calls {
		for _, cred := range []struct {
			name, authorization string
			code                codes.Code
			applies             bool
		}{
			{"no token", "", codes.Unauthenticated, true},
			{"empty bearer", "Bearer ", codes.Unauthenticated, true},
			{"basic auth", "Basic dXNlcjpwYXNz", codes.Unauthenticated, true},
			{"unknown token", "Bearer guessed-token", codes.Unauthenticated, true},
			{"worker token", "Bearer " + workerToken, codes.PermissionDenied, clientOnly[c.method]},
			{"client token", "Bearer " + clientToken, codes.PermissionDenied, workerOnly[c.method]},
		} {
			if !cred.applies {
				continue
			}
			n++
			t.Run(c.method+"/"+cred.name, func(t *testing.T) {
				st, _ := status.FromError(c.call(as(cred.authorization)))
				if st.Code() != cred.code || !strings.Contains(st.Message(), c.method) {
					t.Errorf("got %v %q, want %v naming %s", st.Code(), st.Message(), cred.code, c.method)
				}
			})
		}
	}
	after, err := jobs.ListJobs(asClient, &pb.ListJobsRequest{})
	if err != nil || len(after.GetJobs()) != len(before.GetJobs()) {
		t.Errorf("jobs after the refused calls: %v, %v; before: %d", after, err, len(before.GetJobs()))
	}
	t.Logf("%d calls with missing, malformed, unknown or wrong-role tokens refused", n)
}
