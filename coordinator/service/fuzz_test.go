package service

import (
	"context"
	"os"
	"path/filepath"
	"strings"
	"testing"

	"google.golang.org/genproto/googleapis/rpc/errdetails"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/metadata"
	"google.golang.org/grpc/status"
	"google.golang.org/protobuf/proto"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/events"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/memstore"
	pb "photonfarm/proto/renderfarm/v1"
)

// The fuzz targets of the two request payloads that carry the most structure: bytes are
// unmarshalled into the request and handed to the handler in process (no network), as
// the gRPC server would after decoding. Nothing may panic, and every refusal must be a
// gRPC status that the error mapping (status.go) produced: INVALID_ARGUMENT naming the
// field in a BadRequest detail and at the start of the message, or another client-facing
// code with a message; INTERNAL (a bug) fails the target. `go test` runs the seeds;
// scripts/fuzz.sh fuzzes them for a bounded time.

// fuzzFarm is a service over a fresh in-memory store and a blob store shared by every
// input of one fuzz run (blobs are content-addressed, so inputs cannot disturb each
// other's).
type fuzzFarm struct {
	s      *Service
	jobs   *jobServer
	worker *workerServer
}

func newFuzzFarm(blobs *blobstore.Store) *fuzzFarm {
	s := New(Config{Store: memstore.New(store.Options{}), Blobs: blobs, Events: events.NewBroker(0)})
	return &fuzzFarm{s: s, jobs: &jobServer{s: s}, worker: &workerServer{s: s}}
}

func fuzzBlobs(f *testing.F) *blobstore.Store {
	bs, err := blobstore.New(f.TempDir(), 0)
	if err != nil {
		f.Fatal(err)
	}
	return bs
}

// checkRefusal fails t unless err (a handler's answer to method) maps to a proper status.
func (ff *fuzzFarm) checkRefusal(t *testing.T, method string, err error) {
	t.Helper()
	if err == nil {
		return
	}
	st := status.Convert(ff.s.toStatus(method, err))
	switch st.Code() {
	case codes.InvalidArgument:
		var field string
		for _, d := range st.Details() {
			if br, ok := d.(*errdetails.BadRequest); ok && len(br.GetFieldViolations()) == 1 {
				field = br.GetFieldViolations()[0].GetField()
			}
		}
		if field == "" || !strings.HasPrefix(st.Message(), field+": ") || len(st.Message()) == len(field)+2 {
			t.Fatalf("%s: INVALID_ARGUMENT %q does not name its field (detail %q) and what is wrong", method, st.Message(), field)
		}
	case codes.NotFound, codes.FailedPrecondition, codes.ResourceExhausted, codes.PermissionDenied:
		if st.Message() == "" {
			t.Fatalf("%s: %v without a message", method, st.Code())
		}
	default:
		t.Fatalf("%s: refused with %v: %s", method, st.Code(), st.Message())
	}
}

func marshal(f *testing.F, m proto.Message) []byte {
	b, err := proto.Marshal(m)
	if err != nil {
		f.Fatal(err)
	}
	return b
}

// triangleOBJ is a valid one-triangle mesh, stored for the seeds that name a mesh.
const triangleOBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"

func FuzzSubmitJobRequest(f *testing.F) {
	blobs := fuzzBlobs(f)
	mesh, err := blobs.Put(context.Background(), strings.NewReader(triangleOBJ), int64(len(triangleOBJ)), "")
	if err != nil {
		f.Fatal(err)
	}
	seeds, _ := filepath.Glob("../../scenes/*.json")
	for _, path := range seeds {
		data, err := os.ReadFile(path)
		if err != nil {
			f.Fatal(err)
		}
		sc, err := scene.ParseJSON(data)
		if err != nil {
			f.Fatal(err)
		}
		for _, sh := range sc.GetShapes() {
			if m := sh.GetMesh(); m != nil {
				m.Digest = mesh.Digest
			}
		}
		f.Add(marshal(f, &pb.SubmitJobRequest{Scene: sc, Priority: 5, RequestId: "r-1"}))
	}
	small := scenetest.Unlit(16, 16)
	small.Shapes = append(small.Shapes, &pb.Shape{Material: "white", Geometry: &pb.Shape_Mesh{Mesh: &pb.MeshFile{Path: "tri.obj", Digest: mesh.Digest}}})
	f.Add(marshal(f, &pb.SubmitJobRequest{Scene: small}))
	f.Add(marshal(f, &pb.SubmitJobRequest{Scene: scenetest.Valid(8, 8), Priority: 2000}))
	f.Add(marshal(f, &pb.SubmitJobRequest{Scene: scenetest.Valid(8, 8), RequestId: "has space"}))
	f.Add([]byte{})
	f.Fuzz(func(t *testing.T, data []byte) {
		req := &pb.SubmitJobRequest{}
		if proto.Unmarshal(data, req) != nil {
			return // the gRPC server would not have decoded it
		}
		ff := newFuzzFarm(blobs)
		resp, err := ff.jobs.SubmitJob(context.Background(), req)
		ff.checkRefusal(t, "SubmitJob", err)
		if err == nil && (resp.GetJob().GetId() == "" || len(resp.GetJob().GetPhases()) == 0) {
			t.Fatalf("SubmitJob accepted a job without id or phases: %v", resp.GetJob())
		}
	})
}

// FuzzCompleteTaskRequest reports completions against a job whose first task is leased
// by a worker at epoch 1, with that worker's secret: "$WORKER" in the request's worker id
// stands for its id and "$TASK" in the task id for that task's id (both are random), so
// that mutations of the outputs and metrics reach the handling behind the lease check.
func FuzzCompleteTaskRequest(f *testing.F) {
	blobs := fuzzBlobs(f)
	const tileBytes = "a tile"
	tile, err := blobs.Put(context.Background(), strings.NewReader(tileBytes), int64(len(tileBytes)), "")
	if err != nil {
		f.Fatal(err)
	}
	out := &pb.Artifact{Name: "tile.exr", Digest: tile.Digest, SizeBytes: tile.Size}
	estimate := 0.5
	for _, req := range []*pb.CompleteTaskRequest{
		{WorkerId: "$WORKER", TaskId: "$TASK", Epoch: 1, Outputs: []*pb.Artifact{out}},
		{WorkerId: "$WORKER", TaskId: "$TASK", Epoch: 1, Outputs: []*pb.Artifact{out},
			Metrics: &pb.RoundMetrics{ErrorEstimate: &estimate, LayerReferenceRmse: map[string]float64{"direct": 0.1}}},
		{WorkerId: "$WORKER", TaskId: "$TASK", Epoch: 2, Outputs: []*pb.Artifact{out}},
		{WorkerId: "w-other", TaskId: "$TASK", Epoch: 1},
		{WorkerId: "$WORKER", TaskId: "$TASK", Epoch: 1, Outputs: []*pb.Artifact{{Name: "tile.exr", Digest: tile.Digest, SizeBytes: 99}}},
		{WorkerId: "w-fuzz", TaskId: "j-none.0", Epoch: 1},
		{},
	} {
		f.Add(marshal(f, req))
	}
	f.Fuzz(func(t *testing.T, data []byte) {
		req := &pb.CompleteTaskRequest{}
		if proto.Unmarshal(data, req) != nil {
			return
		}
		ff := newFuzzFarm(blobs)
		ctx := context.Background()
		job, err := ff.s.cfg.Store.CreateJob(ctx, store.NewJob{SceneDigest: tile.Digest, Width: 16, Height: 16, Tasks: []*pb.Task{
			{Index: 0, Phase: pb.Phase_PHASE_RENDER, Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{Rect: &pb.PixelRect{Width: 16, Height: 16}}}},
			{Index: 1, Phase: pb.Phase_PHASE_COMPOSITE, Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{}}},
		}})
		if err != nil {
			t.Fatal(err)
		}
		secret, worker := newWorkerSecret()
		if l, err := ff.s.cfg.Store.LeaseTask(ctx, worker, store.WorkerPhases); err != nil || l == nil {
			t.Fatalf("lease: %v, %v", l, err)
		}
		ctx = metadata.NewIncomingContext(ctx, metadata.Pairs(rules.WorkerSecretMetadata, secret))
		req.WorkerId = strings.ReplaceAll(req.GetWorkerId(), "$WORKER", worker)
		req.TaskId = strings.ReplaceAll(req.GetTaskId(), "$TASK", store.TaskID(job.GetId(), 0))
		_, err = ff.worker.CompleteTask(ctx, req)
		ff.checkRefusal(t, "CompleteTask", err)
	})
}
