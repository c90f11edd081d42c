package service_test

import (
	"errors"
	"fmt"
	"io"
	"math"
	"strings"
	"testing"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/protobuf/proto"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

func TestSubmitRenderAndWatchToSuccess(t *testing.T) {
	f := newFarm(t)
	sc := scenetest.Unlit(64, 40) // 2 x 2 tiles of 32, the bottom row partial
	job := f.submit(sc)
	if job.Id == "" || job.State != pb.JobState_JOB_STATE_QUEUED || job.Width != 64 || job.Height != 40 || job.DisplayName != sc.Name {
		t.Fatalf("submitted job = %v", job)
	}
	if len(job.Phases) != 2 || job.Phases[0].TasksTotal != 4 || job.Phases[1].TasksTotal != 1 {
		t.Errorf("phases = %v", job.Phases)
	}
	got, err := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: job.Id})
	if err != nil || !proto.Equal(got.Job, job) {
		t.Fatalf("GetJob = %v, %v; want %v", got, err, job)
	}
	list, err := f.jobs.ListJobs(f.ctx, &pb.ListJobsRequest{})
	if err != nil || len(list.Jobs) != 1 || list.Jobs[0].Id != job.Id {
		t.Fatalf("ListJobs = %v, %v", list, err)
	}
	// The stored scene is the submitted one with defaults filled in.
	data, _, err := f.download(job.SceneDigest)
	if err != nil {
		t.Fatalf("download scene: %v", err)
	}
	stored := &pb.Scene{}
	if err := proto.Unmarshal(data, stored); err != nil || !proto.Equal(stored, scene.Defaults(sc)) {
		t.Errorf("stored scene = %v, %v", stored, err)
	}

	stream, err := f.jobs.WatchJob(f.ctx, &pb.WatchJobRequest{JobId: job.Id})
	if err != nil {
		t.Fatal(err)
	}
	first, err := stream.Recv()
	if err != nil || first.Kind != pb.JobEventKind_JOB_EVENT_KIND_SNAPSHOT || first.Job.Id != job.Id {
		t.Fatalf("first event = %v, %v; want a snapshot", first, err)
	}
	watched := make(chan []*pb.WatchJobResponse, 1)
	go func() {
		var evs []*pb.WatchJobResponse
		for {
			ev, err := stream.Recv()
			if err != nil {
				if !errors.Is(err, io.EOF) {
					t.Errorf("watch: %v", err)
				}
				watched <- evs
				return
			}
			evs = append(evs, ev)
		}
	}()

	w := f.register()
	tiles := map[string]*pb.Artifact{}
	for i := 0; i < 4; i++ {
		l := f.lease(w)
		if l.SceneDigest != job.SceneDigest || l.Task.GetRenderTile() == nil || l.Task.Index != uint32(i) {
			t.Fatalf("lease %d = %v", i, l)
		}
		a := f.upload([]byte(fmt.Sprint("tile ", i)))
		a.Name = "tile.exr"
		tiles[a.Digest] = a
		if _, err := f.workers.CompleteTask(f.ctx, &pb.CompleteTaskRequest{WorkerId: w, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Outputs: []*pb.Artifact{a}}); err != nil {
			t.Fatalf("CompleteTask: %v", err)
		}
	}
	f.clock.Advance(90 * time.Second)
	comp := f.lease(w)
	spec := comp.Task.GetComposite()
	if spec == nil || len(spec.Tiles) != 4 {
		t.Fatalf("composite lease = %v, want 4 tiles", comp)
	}
	if spec.ElapsedSeconds != 90 {
		t.Errorf("composite elapsed_seconds = %v, want the 90 s since the job was created", spec.ElapsedSeconds)
	}
	if r := spec.Tiles[3].Rect; r.X != 32 || r.Y != 32 || r.Width != 32 || r.Height != 8 {
		t.Errorf("last tile rect = %v", r)
	}
	for _, ti := range spec.Tiles {
		if !proto.Equal(tiles[ti.Tile.GetDigest()], ti.Tile) {
			t.Errorf("tile input %v is not an uploaded tile", ti)
		}
	}
	img, png := f.upload([]byte("exr")), f.upload([]byte("png"))
	img.Name, png.Name = "image.exr", "preview.png"
	req := &pb.CompleteTaskRequest{WorkerId: w, TaskId: comp.Lease.TaskId, Epoch: comp.Lease.Epoch, Outputs: []*pb.Artifact{img, png}}
	for i := 0; i < 2; i++ { // the second report is a harmless repeat
		if _, err := f.workers.CompleteTask(f.ctx, req); err != nil {
			t.Fatalf("CompleteTask composite (%d): %v", i, err)
		}
	}
	done, _ := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: job.Id})
	if done.Job.State != pb.JobState_JOB_STATE_SUCCEEDED || len(done.Job.Outputs) != 2 || done.Job.Outputs[0].Digest != img.Digest {
		t.Fatalf("final job = %v", done.Job)
	}

	select {
	case evs := <-watched:
		if len(evs) == 0 {
			t.Fatal("no events after the snapshot")
		}
		last := evs[len(evs)-1]
		if last.Kind != pb.JobEventKind_JOB_EVENT_KIND_STATE_CHANGED || last.Job.State != pb.JobState_JOB_STATE_SUCCEEDED {
			t.Errorf("last event = %v, want the job SUCCEEDED", last)
		}
		sawRunning, taskEvents := false, 0
		for _, ev := range evs {
			if ev.Kind == pb.JobEventKind_JOB_EVENT_KIND_STATE_CHANGED && ev.Job.State == pb.JobState_JOB_STATE_RUNNING {
				sawRunning = true
			}
			if ev.Kind == pb.JobEventKind_JOB_EVENT_KIND_TASK_UPDATED {
				taskEvents++
			}
		}
		if !sawRunning || taskEvents != 10 { // 5 leases and 5 completions
			t.Errorf("saw RUNNING %v and %d task events; want true and 10", sawRunning, taskEvents)
		}
	case <-time.After(10 * time.Second):
		t.Fatal("WatchJob did not end after the job succeeded")
	}

	// Watching an ended job: the snapshot, then the end of the stream.
	stream, _ = f.jobs.WatchJob(f.ctx, &pb.WatchJobRequest{JobId: job.Id})
	if ev, err := stream.Recv(); err != nil || ev.Kind != pb.JobEventKind_JOB_EVENT_KIND_SNAPSHOT {
		t.Fatalf("watch ended job: %v, %v", ev, err)
	}
	if _, err := stream.Recv(); !errors.Is(err, io.EOF) {
		t.Errorf("watch ended job: %v, want the end of the stream", err)
	}
}

func TestSubmitRefusesMalformedScenes(t *testing.T) {
	missing := rules.DigestOf([]byte("a mesh nobody uploaded"))
	mesh := func(m *pb.MeshFile) func(*pb.Scene) {
		return func(s *pb.Scene) {
			s.Shapes = append(s.Shapes, &pb.Shape{Material: "white", Geometry: &pb.Shape_Mesh{Mesh: m}})
		}
	}
	tests := []struct {
		name    string
		mutate  func(*pb.Scene)
		field   string
		message string
	}{
		{"negative radius", func(s *pb.Scene) { s.Shapes[0].GetSphere().Radius = -1 }, "shapes[0].sphere.radius", "shapes[0].sphere.radius: must be > 0, got -1"},
		{"no camera", func(s *pb.Scene) { s.Camera = nil }, "camera", ""},
		{"NaN coordinate", func(s *pb.Scene) { s.Shapes[1].GetQuad().Origin.Z = math.NaN() }, "shapes[1].quad.origin.z", ""},
		{"fov out of range", func(s *pb.Scene) { s.Camera.VerticalFovDegrees = 200 }, "camera.vertical_fov_degrees", ""},
		{"huge film", func(s *pb.Scene) { s.Film.Width = 20000 }, "film.width", ""},
		{"bad tile size", func(s *pb.Scene) { s.Film.TileSize = 7 }, "film.tile_size", ""},
		{"unknown material", func(s *pb.Scene) { s.Shapes[2].Material = "nope" }, "shapes[2].material", ""},
		{"reflectance above 1", func(s *pb.Scene) { s.Materials[0].GetLambert().Reflectance.R = 2 }, "materials[0].lambert.reflectance.r", ""},
		{"no light", func(s *pb.Scene) { s.Shapes = s.Shapes[:2] }, "lights", ""},
		{"mesh path, no digest", mesh(&pb.MeshFile{Path: "bunny.obj"}), "shapes[3].mesh.digest",
			"shapes[3].mesh.digest: missing; clients upload the file named by path and set its digest"},
		{"mesh not uploaded", mesh(&pb.MeshFile{Digest: missing}), "shapes[3].mesh.digest", ""},
		{"no scene", nil, "scene", ""},
	}
	f := newFarm(t)
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			var sc *pb.Scene
			if tt.mutate != nil {
				sc = scenetest.Unlit(32, 32)
				tt.mutate(sc)
			}
			_, err := f.jobs.SubmitJob(f.ctx, &pb.SubmitJobRequest{Scene: sc})
			wantCode(t, "SubmitJob", err, codes.InvalidArgument, tt.field)
			if tt.message != "" && !containsMessage(err, tt.message) {
				t.Errorf("message = %v, want %q", err, tt.message)
			}
		})
	}
	list, err := f.jobs.ListJobs(f.ctx, &pb.ListJobsRequest{})
	if err != nil || len(list.Jobs) != 0 {
		t.Errorf("ListJobs after refusals = %v, %v; want no jobs", list, err)
	}
	if n := f.blobCount(); n != 0 {
		t.Errorf("%d blobs stored for refused scenes", n)
	}
}

func TestSubmitAcceptsUploadedMesh(t *testing.T) {
	f := newFarm(t)
	a := f.upload([]byte("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"))
	sc := scenetest.Unlit(16, 16)
	sc.Shapes = append(sc.Shapes, &pb.Shape{Material: "white", Geometry: &pb.Shape_Mesh{Mesh: &pb.MeshFile{Path: "tri.obj", Digest: a.Digest}}})
	if job := f.submit(sc); job.State != pb.JobState_JOB_STATE_QUEUED {
		t.Errorf("job = %v", job)
	}
}

func TestJobRPCsValidateFields(t *testing.T) {
	f := newFarm(t)
	_, err := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{})
	wantCode(t, "GetJob empty id", err, codes.InvalidArgument, "job_id")
	_, err = f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: "j-nope"})
	wantCode(t, "GetJob unknown", err, codes.NotFound, "")
	_, err = f.jobs.ListTasks(f.ctx, &pb.ListTasksRequest{})
	wantCode(t, "ListTasks empty id", err, codes.InvalidArgument, "job_id")
	_, err = f.jobs.ListTasks(f.ctx, &pb.ListTasksRequest{JobId: "j-nope"})
	wantCode(t, "ListTasks unknown", err, codes.NotFound, "")
	_, err = f.jobs.CancelJob(f.ctx, &pb.CancelJobRequest{})
	wantCode(t, "CancelJob empty id", err, codes.InvalidArgument, "job_id")
	_, err = f.jobs.ListJobs(f.ctx, &pb.ListJobsRequest{PageSize: -1})
	wantCode(t, "ListJobs negative page", err, codes.InvalidArgument, "page_size")
	_, err = f.jobs.ListJobs(f.ctx, &pb.ListJobsRequest{PageToken: "???"})
	wantCode(t, "ListJobs bad token", err, codes.InvalidArgument, "page_token")
	stream, err := f.jobs.WatchJob(f.ctx, &pb.WatchJobRequest{})
	if err == nil {
		_, err = stream.Recv()
	}
	wantCode(t, "WatchJob empty id", err, codes.InvalidArgument, "job_id")
	stream, _ = f.jobs.WatchJob(f.ctx, &pb.WatchJobRequest{JobId: "j-nope"})
	_, err = stream.Recv()
	wantCode(t, "WatchJob unknown", err, codes.NotFound, "")
}

func TestListJobsPages(t *testing.T) {
	f := newFarm(t)
	var ids []string
	for i := 0; i < 5; i++ {
		ids = append(ids, f.submit(scenetest.Unlit(8, 8)).Id)
	}
	var got []string
	tok := ""
	for {
		resp, err := f.jobs.ListJobs(f.ctx, &pb.ListJobsRequest{PageSize: 2, PageToken: tok})
		if err != nil {
			t.Fatal(err)
		}
		for _, j := range resp.Jobs {
			got = append(got, j.Id)
		}
		if tok = resp.NextPageToken; tok == "" {
			break
		}
	}
	if fmt.Sprint(got) != fmt.Sprint([]string{ids[4], ids[3], ids[2], ids[1], ids[0]}) {
		t.Errorf("listed %v, want newest first of %v", got, ids)
	}
	tasks, err := f.jobs.ListTasks(f.ctx, &pb.ListTasksRequest{JobId: ids[0]})
	if err != nil || len(tasks.Tasks) != 2 || tasks.Tasks[0].State != pb.TaskState_TASK_STATE_QUEUED || tasks.Tasks[1].State != pb.TaskState_TASK_STATE_WAITING {
		t.Errorf("ListTasks = %v, %v", tasks, err)
	}
}

func TestCancelRevokesLeasesAndEndsWatch(t *testing.T) {
	f := newFarm(t)
	job, w, l := f.leased(scenetest.Unlit(64, 64))
	stream, err := f.jobs.WatchJob(f.ctx, &pb.WatchJobRequest{JobId: job.Id})
	if err != nil {
		t.Fatal(err)
	}
	if _, err := stream.Recv(); err != nil {
		t.Fatal(err)
	}
	resp, err := f.jobs.CancelJob(f.ctx, &pb.CancelJobRequest{JobId: job.Id})
	if err != nil || resp.Job.State != pb.JobState_JOB_STATE_CANCELLED {
		t.Fatalf("CancelJob = %v, %v", resp, err)
	}
	ev, err := stream.Recv()
	if err != nil || ev.Kind != pb.JobEventKind_JOB_EVENT_KIND_STATE_CHANGED || ev.Job.State != pb.JobState_JOB_STATE_CANCELLED {
		t.Fatalf("event after cancel = %v, %v", ev, err)
	}
	if _, err := stream.Recv(); !errors.Is(err, io.EOF) {
		t.Errorf("watch after cancel: %v, want the end", err)
	}
	hb, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: w, Leases: []*pb.HeldLease{{TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch}}})
	if err != nil || len(hb.Revoked) != 1 || len(hb.Leases) != 0 {
		t.Errorf("heartbeat after cancel = %v, %v; want the lease revoked", hb, err)
	}
	_, err = f.jobs.CancelJob(f.ctx, &pb.CancelJobRequest{JobId: job.Id})
	wantCode(t, "second cancel", err, codes.FailedPrecondition, "")
	if r, _ := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: w}); r.GetLease() != nil {
		t.Errorf("leased %v from a cancelled job", r)
	}
}

func containsMessage(err error, msg string) bool {
	return err != nil && strings.Contains(err.Error(), msg)
}
