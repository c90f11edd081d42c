package service_test

import (
	"bytes"
	"context"
	"errors"
	"io"
	"net"
	"os"
	"path/filepath"
	"strings"
	"testing"
	"time"

	"google.golang.org/genproto/googleapis/rpc/errdetails"
	"google.golang.org/grpc"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/credentials/insecure"
	healthpb "google.golang.org/grpc/health/grpc_health_v1"
	"google.golang.org/grpc/status"
	"google.golang.org/protobuf/types/known/durationpb"

	"photonfarm/client"
	"photonfarm/contract/rules"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/clock"
	"photonfarm/coordinator/events"
	"photonfarm/coordinator/service"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/memstore"
	pb "photonfarm/proto/renderfarm/v1"
)

const leaseDuration = 10 * time.Second

// farm is a real gRPC server on a loopback port with real clients.
type farm struct {
	t       *testing.T
	ctx     context.Context
	clock   *clock.Fake
	svc     *service.Service
	blobDir string
	jobs    pb.JobServiceClient
	workers pb.WorkerServiceClient
	blobs   pb.BlobServiceClient
	health  healthpb.HealthClient
}

func newFarm(t *testing.T) *farm {
	t.Helper()
	return newFarmOn(t, func(opts store.Options) store.Store { return memstore.New(opts) })
}

// newFarmOn is newFarm on the store newStore makes.
func newFarmOn(t *testing.T, newStore func(store.Options) store.Store) *farm {
	t.Helper()
	clk := clock.NewFake(time.Date(2030, 1, 1, 0, 0, 0, 0, time.UTC))
	dir := t.TempDir()
	bs, err := blobstore.New(dir, 0)
	if err != nil {
		t.Fatal(err)
	}
	svc := service.New(service.Config{
		Store:         newStore(store.Options{Clock: clk, LeaseDuration: leaseDuration}),
		Blobs:         bs,
		Events:        events.NewBroker(0),
		Clock:         clk,
		LeaseDuration: leaseDuration,
	})
	srv := svc.NewGRPCServer()
	lis, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		t.Fatal(err)
	}
	go srv.Serve(lis)
	conn, err := grpc.NewClient(lis.Addr().String(),
		grpc.WithTransportCredentials(insecure.NewCredentials()), client.WorkerSecrets(),
		grpc.WithDefaultCallOptions(grpc.MaxCallRecvMsgSize(int(rules.RPC.GetMaxMessageBytes()))))
	if err != nil {
		t.Fatal(err)
	}
	ctx, cancel := context.WithTimeout(context.Background(), 30*time.Second)
	t.Cleanup(func() {
		cancel()
		conn.Close()
		svc.Shutdown()
		srv.Stop()
	})
	return &farm{t: t, ctx: ctx, clock: clk, svc: svc, blobDir: dir,
		jobs: pb.NewJobServiceClient(conn), workers: pb.NewWorkerServiceClient(conn), blobs: pb.NewBlobServiceClient(conn),
		health: healthpb.NewHealthClient(conn)}
}

func (f *farm) submit(s *pb.Scene) *pb.Job {
	f.t.Helper()
	resp, err := f.jobs.SubmitJob(f.ctx, &pb.SubmitJobRequest{Scene: s})
	if err != nil {
		f.t.Fatalf("SubmitJob: %v", err)
	}
	return resp.Job
}

func (f *farm) register() string {
	f.t.Helper()
	resp, err := f.workers.RegisterWorker(f.ctx, &pb.RegisterWorkerRequest{Hostname: "test", Cores: 2, Version: "test"})
	if err != nil {
		f.t.Fatalf("RegisterWorker: %v", err)
	}
	return resp.WorkerId
}

func (f *farm) lease(worker string) *pb.LeaseTaskResponse {
	f.t.Helper()
	resp, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: worker})
	if err != nil {
		f.t.Fatalf("LeaseTask: %v", err)
	}
	if resp.Lease == nil {
		f.t.Fatal("LeaseTask: nothing to do, want a task")
	}
	return resp
}

// leased submits s, registers a worker and leases it the job's first task.
func (f *farm) leased(s *pb.Scene) (job *pb.Job, worker string, l *pb.LeaseTaskResponse) {
	f.t.Helper()
	job = f.submit(s)
	worker = f.register()
	return job, worker, f.lease(worker)
}

// longPoll starts worker's LeaseTask waiting up to timeout and returns where its answer
// comes (nil, the error reported, if the call fails).
func (f *farm) longPoll(worker string, timeout time.Duration) <-chan *pb.LeaseTaskResponse {
	got := make(chan *pb.LeaseTaskResponse, 1)
	go func() {
		resp, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: worker, WaitTimeout: wait(timeout)})
		if err != nil {
			f.t.Error(err)
		}
		got <- resp
	}()
	return got
}

// cancel cancels the job.
func (f *farm) cancel(jobID string) {
	f.t.Helper()
	if _, err := f.jobs.CancelJob(f.ctx, &pb.CancelJobRequest{JobId: jobID}); err != nil {
		f.t.Fatalf("CancelJob: %v", err)
	}
}

func (f *farm) upload(data []byte) *pb.Artifact {
	f.t.Helper()
	d, err := f.uploadChunks(&pb.BlobHeader{SizeBytes: int64(len(data))}, chunks(data, 1<<20)...)
	if err != nil {
		f.t.Fatalf("UploadBlob: %v", err)
	}
	return &pb.Artifact{Digest: d.Digest, SizeBytes: d.SizeBytes}
}

func (f *farm) uploadChunks(h *pb.BlobHeader, cs ...[]byte) (*pb.UploadBlobResponse, error) {
	stream, err := f.blobs.UploadBlob(f.ctx)
	if err != nil {
		return nil, err
	}
	if err := stream.Send(&pb.UploadBlobRequest{Part: &pb.UploadBlobRequest_Header{Header: h}}); err != nil {
		return nil, err
	}
	for _, c := range cs {
		if err := stream.Send(&pb.UploadBlobRequest{Part: &pb.UploadBlobRequest_Chunk{Chunk: c}}); err != nil {
			break // the server refused; CloseAndRecv reports why
		}
	}
	return stream.CloseAndRecv()
}

func (f *farm) download(digest string) ([]byte, []int, error) {
	got, sizes, _, err := f.downloadRange(&pb.DownloadBlobRequest{Digest: digest})
	return got, sizes, err
}

// downloadRange downloads what req asks for: the bytes, each chunk's size, and the blob's
// size the first message announces.
func (f *farm) downloadRange(req *pb.DownloadBlobRequest) ([]byte, []int, int64, error) {
	stream, err := f.blobs.DownloadBlob(f.ctx, req)
	if err != nil {
		return nil, nil, 0, err
	}
	var buf bytes.Buffer
	var sizes []int
	var size int64
	for {
		msg, err := stream.Recv()
		if errors.Is(err, io.EOF) {
			return buf.Bytes(), sizes, size, nil
		}
		if err != nil {
			return nil, nil, 0, err
		}
		if sizes == nil {
			size = msg.GetSizeBytes()
		}
		buf.Write(msg.Chunk)
		sizes = append(sizes, len(msg.Chunk))
	}
}

func chunks(b []byte, n int) [][]byte {
	var out [][]byte
	for len(b) > n {
		out = append(out, b[:n])
		b = b[n:]
	}
	return append(out, b)
}

func wait(d time.Duration) *durationpb.Duration { return durationpb.New(d) }

// wantCode checks err's code and, when field is set, that the message starts with the
// field and a BadRequest detail names it.
func wantCode(t *testing.T, what string, err error, code codes.Code, field string) {
	t.Helper()
	st, _ := status.FromError(err)
	if st.Code() != code {
		t.Fatalf("%s: %v, want %v", what, err, code)
	}
	if field == "" {
		return
	}
	if !strings.HasPrefix(st.Message(), field+": ") {
		t.Errorf("%s: message %q does not start with %q", what, st.Message(), field+": ")
	}
	for _, d := range st.Details() {
		if br, ok := d.(*errdetails.BadRequest); ok && len(br.FieldViolations) == 1 && br.FieldViolations[0].Field == field {
			return
		}
	}
	t.Errorf("%s: details %v do not name field %q", what, st.Details(), field)
}

// blobCount counts the blobs stored.
func (f *farm) blobCount() int {
	n := 0
	filepath.WalkDir(filepath.Join(f.blobDir, "sha256"), func(_ string, d os.DirEntry, err error) error {
		if err == nil && !d.IsDir() {
			n++
		}
		return nil
	})
	return n
}
