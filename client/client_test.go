package client

import (
	"bytes"
	"context"
	"errors"
	"fmt"
	"io"
	"net"
	"os"
	"path/filepath"
	"strings"
	"sync"
	"testing"
	"time"

	"google.golang.org/genproto/googleapis/rpc/errdetails"
	"google.golang.org/grpc"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// fakeBlobs is an in-memory BlobService that checks uploads the way the contract says.
type fakeBlobs struct {
	pb.UnimplementedBlobServiceServer
	mu      sync.Mutex
	blobs   map[string][]byte
	uploads int
	chunks  []int
	corrupt bool // DownloadBlob flips a byte
}

func (f *fakeBlobs) UploadBlob(stream grpc.ClientStreamingServer[pb.UploadBlobRequest, pb.UploadBlobResponse]) error {
	first, err := stream.Recv()
	if err != nil {
		return err
	}
	hdr := first.GetHeader()
	if hdr == nil {
		return status.Error(codes.InvalidArgument, "header: missing")
	}
	var buf bytes.Buffer
	for {
		msg, err := stream.Recv()
		if errors.Is(err, io.EOF) {
			break
		}
		if err != nil {
			return err
		}
		f.mu.Lock()
		f.chunks = append(f.chunks, len(msg.GetChunk()))
		f.mu.Unlock()
		buf.Write(msg.GetChunk())
	}
	if int64(buf.Len()) != hdr.GetSizeBytes() {
		return status.Errorf(codes.InvalidArgument, "header.size_bytes: is %d, got %d bytes", hdr.GetSizeBytes(), buf.Len())
	}
	d := rules.DigestOf(buf.Bytes())
	if hdr.GetDigest() != "" && hdr.GetDigest() != d {
		return status.Errorf(codes.InvalidArgument, "header.digest: content has digest %s", d)
	}
	f.mu.Lock()
	f.blobs[d] = buf.Bytes()
	f.uploads++
	f.mu.Unlock()
	return stream.SendAndClose(&pb.UploadBlobResponse{Digest: d, SizeBytes: int64(buf.Len())})
}

func (f *fakeBlobs) GetBlobInfo(_ context.Context, req *pb.GetBlobInfoRequest) (*pb.GetBlobInfoResponse, error) {
	f.mu.Lock()
	defer f.mu.Unlock()
	b, ok := f.blobs[req.GetDigest()]
	if !ok {
		return nil, status.Error(codes.NotFound, "no such blob")
	}
	return &pb.GetBlobInfoResponse{Digest: req.GetDigest(), SizeBytes: int64(len(b))}, nil
}

func (f *fakeBlobs) DownloadBlob(req *pb.DownloadBlobRequest, stream grpc.ServerStreamingServer[pb.DownloadBlobResponse]) error {
	f.mu.Lock()
	b, ok := f.blobs[req.GetDigest()]
	corrupt := f.corrupt
	f.mu.Unlock()
	if !ok {
		return status.Error(codes.NotFound, "no such blob")
	}
	b = bytes.Clone(b)
	if corrupt && len(b) > 0 {
		b[len(b)/2] ^= 1
	}
	for i := 0; i == 0 || i < len(b); i += 3 {
		msg := &pb.DownloadBlobResponse{Chunk: b[i:min(i+3, len(b))]}
		if i == 0 {
			msg.SizeBytes = int64(len(b))
		}
		if err := stream.Send(msg); err != nil {
			return err
		}
	}
	return nil
}

// fakeJobs is a JobService with canned answers.
type fakeJobs struct {
	pb.UnimplementedJobServiceServer
	mu        sync.Mutex
	submitted []*pb.Scene
	job       *pb.Job
	events    []*pb.WatchJobResponse   // what a WatchJob stream sends before it ends
	cuts      [][]*pb.WatchJobResponse // first: what the next streams send before UNAVAILABLE
	watches   int                      // WatchJob calls
	tasks     []*pb.Task
	workers   []*pb.WorkerInfo
}

func (f *fakeJobs) ListWorkers(_ context.Context, req *pb.ListWorkersRequest) (*pb.ListWorkersResponse, error) {
	workers, next := pageOfTwo(f.workers, req.GetPageToken())
	return &pb.ListWorkersResponse{Workers: workers, NextPageToken: next}, nil
}

// pageOfTwo is the page of items a fake listing's token names: pages of two, to
// exercise the clients' paging loops.
func pageOfTwo[T any](items []T, token string) (page []T, next string) {
	start := 0
	if token != "" {
		fmt.Sscan(token, &start)
	}
	end := min(start+2, len(items))
	if end < len(items) {
		next = fmt.Sprint(end)
	}
	return items[start:end], next
}

func (f *fakeJobs) SubmitJob(_ context.Context, req *pb.SubmitJobRequest) (*pb.SubmitJobResponse, error) {
	for i, sh := range req.GetScene().GetShapes() {
		if r := sh.GetSphere().GetRadius(); sh.GetSphere() != nil && r <= 0 {
			// Like the coordinator: the field in the message and in a BadRequest detail.
			field := fmt.Sprintf("shapes[%d].sphere.radius", i)
			msg := fmt.Sprintf("must be > 0, got %g", r)
			desc := msg
			if i == 2 { // the coordinator repeats the field in the description
				desc = field + ": " + msg
			}
			st, _ := status.New(codes.InvalidArgument, field+": "+msg).WithDetails(&errdetails.BadRequest{
				FieldViolations: []*errdetails.BadRequest_FieldViolation{{Field: field, Description: desc}}})
			return nil, st.Err()
		}
	}
	if req.GetScene().GetFilm().GetWidth() == 0 {
		return nil, status.Error(codes.InvalidArgument, "film.width: must be > 0, got 0")
	}
	f.mu.Lock()
	defer f.mu.Unlock()
	f.submitted = append(f.submitted, req.GetScene())
	return &pb.SubmitJobResponse{Job: &pb.Job{Id: "j1", DisplayName: req.GetScene().GetName()}}, nil
}

func (f *fakeJobs) GetJob(_ context.Context, req *pb.GetJobRequest) (*pb.GetJobResponse, error) {
	if f.job == nil || req.GetJobId() != f.job.GetId() {
		return nil, status.Errorf(codes.NotFound, "job %q not found", req.GetJobId())
	}
	return &pb.GetJobResponse{Job: f.job}, nil
}

func (f *fakeJobs) WatchJob(req *pb.WatchJobRequest, stream grpc.ServerStreamingServer[pb.WatchJobResponse]) error {
	f.mu.Lock()
	f.watches++
	events, cut := f.events, len(f.cuts) > 0
	if cut {
		events, f.cuts = f.cuts[0], f.cuts[1:]
	}
	f.mu.Unlock()
	for _, ev := range events {
		if err := stream.Send(ev); err != nil {
			return err
		}
	}
	if cut {
		return status.Error(codes.Unavailable, "the coordinator went away")
	}
	return nil
}

func (f *fakeJobs) ListTasks(_ context.Context, req *pb.ListTasksRequest) (*pb.ListTasksResponse, error) {
	tasks, next := pageOfTwo(f.tasks, req.GetPageToken())
	return &pb.ListTasksResponse{Tasks: tasks, NextPageToken: next}, nil
}

func startFake(t *testing.T, opts ...Option) (*Client, *fakeBlobs, *fakeJobs) {
	t.Helper()
	lis, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		t.Fatal(err)
	}
	srv := grpc.NewServer(grpc.MaxRecvMsgSize(int(rules.RPC.GetMaxMessageBytes())))
	blobs := &fakeBlobs{blobs: map[string][]byte{}}
	jobs := &fakeJobs{}
	pb.RegisterBlobServiceServer(srv, blobs)
	pb.RegisterJobServiceServer(srv, jobs)
	go srv.Serve(lis)
	t.Cleanup(srv.Stop)
	c, err := Dial(lis.Addr().String(), opts...)
	if err != nil {
		t.Fatal(err)
	}
	t.Cleanup(func() { c.Close() })
	return c, blobs, jobs
}

const tetrahedron = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"

func writeScene(t *testing.T, dir, body string) string {
	t.Helper()
	path := filepath.Join(dir, "scene.json")
	if err := os.WriteFile(path, []byte(body), 0o644); err != nil {
		t.Fatal(err)
	}
	return path
}

func TestLoadSceneFileUploadsMeshesOnceAndSubmitsDigests(t *testing.T) {
	c, blobs, _ := startFake(t, withChunkSize(16))
	dir := t.TempDir()
	os.MkdirAll(filepath.Join(dir, "meshes"), 0o755)
	os.WriteFile(filepath.Join(dir, "meshes", "tet.obj"), []byte(tetrahedron), 0o644)
	path := writeScene(t, dir, `{"name": "s", "shapes": [
		{"sphere": {"radius": 1}},
		{"mesh": {"path": "meshes/tet.obj"}},
		{"mesh": {"path": "meshes/tet.obj", "transform": {"translation": {"x": 2}}}}]}`)

	// Run from another folder: the mesh path is relative to the scene file, not to us.
	t.Chdir(t.TempDir())
	sc, err := c.LoadSceneFile(context.Background(), path)
	if err != nil {
		t.Fatal(err)
	}
	want := rules.DigestOf([]byte(tetrahedron))
	for _, i := range []int{1, 2} {
		m := sc.GetShapes()[i].GetMesh()
		if m.GetDigest() != want || m.GetPath() != "meshes/tet.obj" {
			t.Errorf("shapes[%d].mesh = digest %q path %q, want digest %q and the path as written", i, m.GetDigest(), m.GetPath(), want)
		}
	}
	if blobs.uploads != 1 {
		t.Errorf("uploads = %d, want 1 (the same file twice)", blobs.uploads)
	}
	if !bytes.Equal(blobs.blobs[want], []byte(tetrahedron)) {
		t.Errorf("stored blob differs from the file")
	}
	for _, n := range blobs.chunks {
		if n > 16 {
			t.Errorf("chunk of %d bytes, want <= 16", n)
		}
	}

	// Loading again uploads nothing: the store has the blob.
	if _, err := c.LoadSceneFile(context.Background(), path); err != nil {
		t.Fatal(err)
	}
	if blobs.uploads != 1 {
		t.Errorf("uploads after a second load = %d, want 1", blobs.uploads)
	}
}

func TestUploadBytesLargerThanAChunk(t *testing.T) {
	c, blobs, _ := startFake(t)
	data := bytes.Repeat([]byte("0123456789abcdef"), (3*UploadChunkSize)/16+5)
	d, err := c.UploadBytes(context.Background(), data)
	if err != nil {
		t.Fatal(err)
	}
	if !bytes.Equal(blobs.blobs[d], data) {
		t.Fatal("stored blob differs")
	}
	if len(blobs.chunks) != 4 || blobs.chunks[0] != UploadChunkSize {
		t.Errorf("chunks = %v, want 3 of %d and a short one", blobs.chunks, UploadChunkSize)
	}
}

func TestReadSceneFileErrorsNameTheField(t *testing.T) {
	dir := t.TempDir()
	for _, tc := range []struct {
		name, body, want string
	}{
		{"missing mesh", `{"shapes": [{"sphere": {"radius": 1}}, {}, {}, {"mesh": {"path": "meshes/x.obj"}}]}`,
			"shapes[3].mesh.path: open meshes/x.obj: no such file or directory"},
		// A scene file's parse errors name the file first.
		{"unknown field", `{"shapes": [{"sphere": {"radus": 1}}]}`,
			`scene.json: line 1:25: shapes[0].sphere.radus: unknown field "radus" (did you mean "radius"?)`},
		{"bad json", `{"shapes": [`, "scene.json: unexpected EOF"},
	} {
		t.Run(tc.name, func(t *testing.T) {
			_, err := ReadSceneFile(context.Background(), writeScene(t, dir, tc.body))
			if err == nil {
				t.Fatal("no error")
			}
			if !strings.Contains(err.Error(), tc.want) {
				t.Errorf("error %q does not contain %q", err, tc.want)
			}
			if !IsInvalidInput(err) {
				t.Errorf("IsInvalidInput(%v) = false", err)
			}
		})
	}
	_, err := ReadSceneFile(context.Background(), filepath.Join(dir, "absent.json"))
	if err == nil || !strings.Contains(err.Error(), "absent.json") {
		t.Errorf("missing scene file: error %v does not name it", err)
	}
}

func TestSubmitInvalidSceneSurfacesTheField(t *testing.T) {
	c, _, jobs := startFake(t)
	sc := &pb.Scene{Film: &pb.Film{Width: 4, Height: 4}, Shapes: []*pb.Shape{
		{Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Radius: 1}}},
		{Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Radius: -1}}},
	}}
	_, err := c.Submit(context.Background(), sc)
	var e *Error
	if !errors.As(err, &e) {
		t.Fatalf("error %v is not an *Error", err)
	}
	if e.Field != "shapes[1].sphere.radius" || e.Error() != "shapes[1].sphere.radius: must be > 0, got -1" {
		t.Errorf("error = %q (field %q)", e, e.Field)
	}
	if status.Code(err) != codes.InvalidArgument || !IsInvalidInput(err) {
		t.Errorf("code = %v", status.Code(err))
	}
	sc.Shapes[1].GetSphere().Radius = 1
	sc.Shapes = append(sc.Shapes, &pb.Shape{Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Radius: -2}}})
	_, err = c.Submit(context.Background(), sc)
	if err == nil || err.Error() != "shapes[2].sphere.radius: must be > 0, got -2" {
		t.Errorf("error with the field repeated in the detail = %v", err)
	}

	// Without a BadRequest detail the status message is used as it is.
	_, err = c.Submit(context.Background(), &pb.Scene{})
	if err == nil || err.Error() != "film.width: must be > 0, got 0" {
		t.Errorf("error = %v", err)
	}
	if len(jobs.submitted) != 0 {
		t.Errorf("%d scenes accepted", len(jobs.submitted))
	}
}

func TestUnreachableCoordinatorIsNotInvalidInput(t *testing.T) {
	lis, _ := net.Listen("tcp", "127.0.0.1:0")
	addr := lis.Addr().String()
	lis.Close()
	c, err := Dial(addr)
	if err != nil {
		t.Fatal(err)
	}
	defer c.Close()
	_, err = c.Submit(context.Background(), &pb.Scene{})
	if err == nil || IsInvalidInput(err) || status.Code(err) != codes.Unavailable {
		t.Fatalf("error = %v (code %v), want Unavailable", err, status.Code(err))
	}
	if !strings.HasPrefix(err.Error(), "submit job: coordinator unavailable") {
		t.Errorf("error = %q", err)
	}
}

func TestWatchReturnsTheEndedJob(t *testing.T) {
	c, _, jobs := startFake(t)
	running := &pb.Job{Id: "j1", State: pb.JobState_JOB_STATE_RUNNING}
	done := &pb.Job{Id: "j1", State: pb.JobState_JOB_STATE_SUCCEEDED}
	jobs.events = []*pb.WatchJobResponse{
		{Kind: pb.JobEventKind_JOB_EVENT_KIND_SNAPSHOT, Job: running},
		{Kind: pb.JobEventKind_JOB_EVENT_KIND_TASK_UPDATED, Job: running},
		{Kind: pb.JobEventKind_JOB_EVENT_KIND_STATE_CHANGED, Job: done},
	}
	var seen int
	job, err := c.Watch(context.Background(), "j1", func(*pb.WatchJobResponse) { seen++ })
	if err != nil || job.GetState() != pb.JobState_JOB_STATE_SUCCEEDED || seen != 3 {
		t.Fatalf("Watch = %v, %v after %d events", job, err, seen)
	}

	// A stream that ends while the job runs is reopened while the job changes, and is an
	// error once it has not for the resume period.
	c.watchResumeFor = 300 * time.Millisecond
	jobs.events = jobs.events[:2]
	start := time.Now()
	if _, err := c.Watch(context.Background(), "j1", nil); err == nil {
		t.Fatal("no error for a stream that keeps ending early")
	}
	if took := time.Since(start); took < c.watchResumeFor || took > 10*c.watchResumeFor {
		t.Errorf("Watch of a stream that keeps ending early gave up after %v, want about %v", took, c.watchResumeFor)
	}
}

func TestWatchReopensAStreamTheCoordinatorCut(t *testing.T) {
	c, _, jobs := startFake(t)
	running := func(done uint32) *pb.Job {
		return &pb.Job{Id: "j1", State: pb.JobState_JOB_STATE_RUNNING, Phases: []*pb.PhaseProgress{{TasksSucceeded: done}}}
	}
	done := &pb.Job{Id: "j1", State: pb.JobState_JOB_STATE_SUCCEEDED}
	jobs.cuts = [][]*pb.WatchJobResponse{
		{{Kind: pb.JobEventKind_JOB_EVENT_KIND_SNAPSHOT, Job: running(0)}, {Kind: pb.JobEventKind_JOB_EVENT_KIND_TASK_UPDATED, Job: running(1)}},
		{}, // the replica is gone: the next call finds no one yet
		{{Kind: pb.JobEventKind_JOB_EVENT_KIND_SNAPSHOT, Job: running(2)}},
	}
	jobs.events = []*pb.WatchJobResponse{
		{Kind: pb.JobEventKind_JOB_EVENT_KIND_SNAPSHOT, Job: running(3)},
		{Kind: pb.JobEventKind_JOB_EVENT_KIND_STATE_CHANGED, Job: done},
	}
	var seen int
	job, err := c.Watch(context.Background(), "j1", func(*pb.WatchJobResponse) { seen++ })
	if err != nil || job.GetState() != pb.JobState_JOB_STATE_SUCCEEDED || seen != 5 || jobs.watches != 4 {
		t.Fatalf("Watch = %v, %v after %d events in %d streams; want SUCCEEDED after 5 in 4", job, err, seen, jobs.watches)
	}

	// A farm that cuts the first stream before any event is not waited for.
	jobs.cuts, jobs.watches = [][]*pb.WatchJobResponse{{}}, 0
	if _, err := c.Watch(context.Background(), "j1", nil); status.Code(errors.Unwrap(err)) != codes.Unavailable || jobs.watches != 1 {
		t.Errorf("Watch of a farm that never answered = %v after %d streams, want UNAVAILABLE after 1", err, jobs.watches)
	}
}

func TestListTasksFollowsPages(t *testing.T) {
	c, _, jobs := startFake(t)
	for i := range 5 {
		jobs.tasks = append(jobs.tasks, &pb.Task{Id: fmt.Sprintf("j1.%d", i), Index: uint32(i)})
	}
	tasks, err := c.ListTasks(context.Background(), "j1")
	if err != nil || len(tasks) != 5 || tasks[4].GetIndex() != 4 {
		t.Fatalf("ListTasks = %v, %v", tasks, err)
	}
}

func TestListWorkersReturnsTheWorkers(t *testing.T) {
	c, _, jobs := startFake(t)
	jobs.workers = []*pb.WorkerInfo{
		{Id: "w-1", State: pb.WorkerState_WORKER_STATE_BUSY, CurrentTaskId: "j1.0"},
		{Id: "w-2", State: pb.WorkerState_WORKER_STATE_IDLE},
		{Id: "w-3", State: pb.WorkerState_WORKER_STATE_LOST},
	}
	got, err := c.ListWorkers(context.Background())
	if err != nil || len(got) != 3 || got[0].GetCurrentTaskId() != "j1.0" || got[1].GetId() != "w-2" || got[2].GetId() != "w-3" {
		t.Fatalf("ListWorkers = %v, %v", got, err)
	}
}

func succeededJob(name string, blobs *fakeBlobs, files map[string][]byte) *pb.Job {
	job := &pb.Job{Id: "j1", DisplayName: name, State: pb.JobState_JOB_STATE_SUCCEEDED}
	for _, n := range []string{"image.exr", "preview.png"} {
		d := rules.DigestOf(files[n])
		blobs.blobs[d] = files[n]
		job.Outputs = append(job.Outputs, &pb.Artifact{Name: n, Digest: d, SizeBytes: int64(len(files[n]))})
	}
	return job
}

func TestFetchNamesFilesAfterTheJob(t *testing.T) {
	c, blobs, jobs := startFake(t)
	files := map[string][]byte{"image.exr": []byte("exr bytes here"), "preview.png": []byte("png!")}
	jobs.job = succeededJob("Cornell box / test", blobs, files)
	out := filepath.Join(t.TempDir(), "out")

	paths, err := c.Fetch(context.Background(), "j1", out)
	if err != nil {
		t.Fatal(err)
	}
	want := []string{filepath.Join(out, "Cornell-box-test.exr"), filepath.Join(out, "Cornell-box-test.png")}
	if fmt.Sprint(paths) != fmt.Sprint(want) {
		t.Fatalf("paths = %v, want %v", paths, want)
	}
	for i, n := range []string{"image.exr", "preview.png"} {
		got, _ := os.ReadFile(paths[i])
		if !bytes.Equal(got, files[n]) {
			t.Errorf("%s = %q, want %q", paths[i], got, files[n])
		}
	}

	paths, err = c.FetchAs(context.Background(), "j1", out, "cornell-box")
	if err != nil || filepath.Base(paths[0]) != "cornell-box.exr" || filepath.Base(paths[1]) != "cornell-box.png" {
		t.Fatalf("FetchAs = %v, %v", paths, err)
	}
}

func TestFetchRefusesCorruptBytesAndLeavesNoFile(t *testing.T) {
	c, blobs, jobs := startFake(t)
	jobs.job = succeededJob("s", blobs, map[string][]byte{"image.exr": []byte("exr bytes here"), "preview.png": []byte("png!")})
	blobs.corrupt = true
	out := t.TempDir()
	_, err := c.Fetch(context.Background(), "j1", out)
	if err == nil || !strings.Contains(err.Error(), "digest") {
		t.Fatalf("error = %v, want a digest mismatch", err)
	}
	entries, _ := os.ReadDir(out)
	if len(entries) != 0 {
		t.Errorf("files left behind: %v", entries)
	}
}

func TestFetchOfAnUnfinishedJobFails(t *testing.T) {
	c, _, jobs := startFake(t)
	jobs.job = &pb.Job{Id: "j1", State: pb.JobState_JOB_STATE_RUNNING}
	_, err := c.Fetch(context.Background(), "j1", t.TempDir())
	if status.Code(err) != codes.FailedPrecondition || !strings.Contains(err.Error(), "running") {
		t.Fatalf("error = %v", err)
	}
	if _, err := c.Fetch(context.Background(), "nope", t.TempDir()); status.Code(err) != codes.NotFound {
		t.Fatalf("unknown job: error = %v", err)
	}
}

func TestSafeFileName(t *testing.T) {
	for in, want := range map[string]string{
		"cornell-box": "cornell-box", "../../etc/passwd": "etc-passwd", "a b\tc": "a-b-c", "": "", "...": "",
	} {
		if got := SafeFileName(in); got != want {
			t.Errorf("SafeFileName(%q) = %q, want %q", in, got, want)
		}
	}
	if SceneStem("scenes/cornell-box.json") != "cornell-box" {
		t.Error("SceneStem")
	}
}
