package coordinator_test

import (
	"context"
	"crypto/tls"
	"strings"
	"testing"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"
	"google.golang.org/protobuf/types/known/durationpb"

	"photonfarm/client"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator"
	"photonfarm/coordinator/tlstest"
	pb "photonfarm/proto/renderfarm/v1"
)

const (
	clientToken = "client-token-0123456789"
	workerToken = "worker-token-0123456789"
)

// as returns a context whose calls carry token ("" for none).
func as(token string) (context.Context, context.CancelFunc) {
	ctx, cancel := context.WithTimeout(context.Background(), 10*time.Second)
	return client.ContextWithToken(ctx, token), cancel
}

func wantCode(t *testing.T, what string, err error, code codes.Code, msgParts ...string) {
	t.Helper()
	if status.Code(err) != code {
		t.Errorf("%s: %v, want %v", what, err, code)
		return
	}
	for _, p := range msgParts {
		if !strings.Contains(status.Convert(err).Message(), p) {
			t.Errorf("%s: message %q does not contain %q", what, status.Convert(err).Message(), p)
		}
	}
}

// TestTokensGateEachServiceByRole talks real gRPC to a coordinator configured with one
// client and one worker token.
func TestTokensGateEachServiceByRole(t *testing.T) {
	conn := serve(t, coordinator.Config{ClientTokens: []string{clientToken}, WorkerTokens: []string{workerToken}}).Dial(t, client.WorkerSecrets())
	jobs, workers, blobs := pb.NewJobServiceClient(conn), pb.NewWorkerServiceClient(conn), pb.NewBlobServiceClient(conn)
	submit := &pb.SubmitJobRequest{Scene: scenetest.Unlit(8, 8)}

	ctx, cancel := as("")
	defer cancel()
	_, err := jobs.SubmitJob(ctx, submit)
	wantCode(t, "SubmitJob without a token", err, codes.Unauthenticated, "no token", "SubmitJob")
	_, err = workers.RegisterWorker(ctx, &pb.RegisterWorkerRequest{Hostname: "h"})
	wantCode(t, "RegisterWorker without a token", err, codes.Unauthenticated, "no token")
	watch, err := jobs.WatchJob(ctx, &pb.WatchJobRequest{JobId: "x"})
	if err == nil {
		_, err = watch.Recv()
	}
	wantCode(t, "WatchJob (a stream) without a token", err, codes.Unauthenticated, "no token")

	ctx, cancel = as("not-a-token")
	defer cancel()
	_, err = jobs.ListJobs(ctx, &pb.ListJobsRequest{})
	wantCode(t, "ListJobs with an unknown token", err, codes.Unauthenticated, "unknown token")

	// The client token submits, lists and cancels, and may not touch tasks.
	cctx, cancel := as(clientToken)
	defer cancel()
	job, err := jobs.SubmitJob(cctx, submit)
	if err != nil {
		t.Fatalf("SubmitJob with the client token: %v", err)
	}
	if _, err := jobs.ListJobs(cctx, &pb.ListJobsRequest{}); err != nil {
		t.Errorf("ListJobs with the client token: %v", err)
	}
	_, err = workers.LeaseTask(cctx, &pb.LeaseTaskRequest{WorkerId: "w"})
	wantCode(t, "LeaseTask with the client token", err, codes.PermissionDenied, "client token", "LeaseTask")
	_, err = workers.RegisterWorker(cctx, &pb.RegisterWorkerRequest{Hostname: "h"})
	wantCode(t, "RegisterWorker with the client token", err, codes.PermissionDenied, "client token")

	// The worker token leases, and may neither submit nor cancel.
	wctx, cancel := as(workerToken)
	defer cancel()
	_, err = jobs.SubmitJob(wctx, submit)
	wantCode(t, "SubmitJob with the worker token", err, codes.PermissionDenied, "worker token", "SubmitJob")
	_, err = jobs.CancelJob(wctx, &pb.CancelJobRequest{JobId: job.GetJob().GetId()})
	wantCode(t, "CancelJob with the worker token", err, codes.PermissionDenied, "worker token", "CancelJob")
	reg, err := workers.RegisterWorker(wctx, &pb.RegisterWorkerRequest{Hostname: "h"})
	if err != nil {
		t.Fatalf("RegisterWorker with the worker token: %v", err)
	}
	leased, err := workers.LeaseTask(wctx, &pb.LeaseTaskRequest{WorkerId: reg.GetWorkerId(), WaitTimeout: durationpb.New(time.Second)})
	if err != nil || leased.GetLease() == nil {
		t.Errorf("LeaseTask with the worker token = %v, %v; want a lease", leased, err)
	}

	// Blobs are both roles': an absent blob is NOT_FOUND, not an auth error.
	for _, ctx := range []context.Context{cctx, wctx} {
		_, err = blobs.GetBlobInfo(ctx, &pb.GetBlobInfoRequest{Digest: "sha256:" + strings.Repeat("0", 64)})
		wantCode(t, "GetBlobInfo", err, codes.NotFound)
	}

	if _, err := jobs.CancelJob(cctx, &pb.CancelJobRequest{JobId: job.GetJob().GetId()}); err != nil {
		t.Errorf("CancelJob with the client token: %v", err)
	}
}

// TestClientSDKSendsTheToken goes through client.Dial's options, as the CLI does.
func TestClientSDKSendsTheToken(t *testing.T) {
	addr := serve(t, coordinator.Config{ClientTokens: []string{clientToken}, WorkerTokens: []string{workerToken}}).Addr
	for _, tc := range []struct {
		token string
		code  codes.Code
	}{{clientToken, codes.OK}, {"", codes.Unauthenticated}, {workerToken, codes.PermissionDenied}} {
		c, err := client.Dial(addr, client.WithToken(tc.token))
		if err != nil {
			t.Fatal(err)
		}
		ctx, cancel := context.WithTimeout(context.Background(), 10*time.Second)
		_, err = c.ListJobs(ctx)
		cancel()
		c.Close()
		wantCode(t, "ListJobs with token "+tc.token, err, tc.code)
	}
}

func TestTLSNeedsTheCA(t *testing.T) {
	tc := tlstest.SelfSigned(t, t.TempDir())
	cert, caFile := tc.TLS, tc.CertFile
	addr := serve(t, coordinator.Config{
		ClientTokens: []string{clientToken}, WorkerTokens: []string{workerToken},
		TLS: &tls.Config{Certificates: []tls.Certificate{cert}},
	}).Addr
	list := func(opts ...client.Option) error {
		c, err := client.Dial(addr, opts...)
		if err != nil {
			t.Fatal(err)
		}
		defer c.Close()
		ctx, cancel := context.WithTimeout(context.Background(), 10*time.Second)
		defer cancel()
		_, err = c.ListJobs(ctx)
		return err
	}
	if err := list(client.WithTLS(caFile), client.WithToken(clientToken)); err != nil {
		t.Errorf("with the CA and the token: %v", err)
	}
	// The system roots do not know the test's CA.
	if err := list(client.WithTLS(""), client.WithToken(clientToken)); status.Code(err) != codes.Unavailable || !strings.Contains(err.Error(), "certificate") {
		t.Errorf("without the CA: %v, want UNAVAILABLE about the certificate", err)
	}
	if err := list(client.WithToken(clientToken)); status.Code(err) != codes.Unavailable {
		t.Errorf("in plaintext against TLS: %v, want UNAVAILABLE", err)
	}
	if err := list(client.WithTLS(caFile)); status.Code(err) != codes.Unauthenticated {
		t.Errorf("over TLS without a token: %v, want UNAUTHENTICATED", err)
	}
}

func TestNewRefusesTLSWithoutCertificate(t *testing.T) {
	if _, err := coordinator.New(coordinator.Config{DataDir: t.TempDir(), TLS: &tls.Config{}}); err == nil {
		t.Error("New accepted a TLS config without a certificate")
	}
	if _, err := coordinator.New(coordinator.Config{DataDir: t.TempDir(), ClientTokens: []string{"a b"}}); err == nil {
		t.Error("New accepted a token with a space")
	}
}
