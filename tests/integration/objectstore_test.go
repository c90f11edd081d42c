package integration

import (
	"bytes"
	"context"
	"net/url"
	"os"
	"strings"
	"sync"
	"testing"
	"time"

	"gocloud.dev/blob"
	_ "gocloud.dev/blob/s3blob"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/blobstore/s3test"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// Blobs in an S3-compatible object store (issue 17): real coordinator and worker
// processes, the coordinator started with --blobs s3://... on a real SeaweedFS server
// (s3test), against the same scene rendered with the blobs in the coordinator's folder.

func TestMain(m *testing.M) { s3test.Main(m) }

// objectStoreFarm is a farm whose coordinator keeps its blobs at url, and the bucket
// under it for looking behind the coordinator's back.
func objectStoreFarm(t *testing.T, storeURL string) (*farmtest.Farm, *blob.Bucket) {
	t.Helper()
	u, err := url.Parse(storeURL)
	if err != nil {
		t.Fatal(err)
	}
	q := u.Query()
	q.Del("stall_timeout") // the blob store's own parameter, not gocloud's
	u.RawQuery = q.Encode()
	b, err := blob.OpenBucket(context.Background(), u.String())
	if err != nil {
		t.Fatal(err)
	}
	t.Cleanup(func() { b.Close() })
	return farmtest.StartFarm(t, []string{"--blobs", storeURL}), b
}

// objectStoreScene is the scene these tests render: the small test scene with its mesh
// (uploaded to f), in 12 tiles.
func objectStoreScene(t *testing.T, f *farmtest.Farm) *pb.Scene {
	return f.TestScene(t, 64, 48, 16, 2)
}

// folderRender is the EXR of objectStoreScene rendered on a farm with its blobs in the
// coordinator's folder, made once for the tests that compare with it.
var folderRender struct {
	once sync.Once
	exr  []byte
}

func folderEXR(t *testing.T) []byte {
	t.Helper()
	folderRender.once.Do(func() {
		f := farmtest.StartFarm(t, nil)
		f.StartWorker(t)
		folderRender.exr = f.Output(t, f.Render(t, objectStoreScene(t, f), 2*time.Minute), "image.exr")
	})
	if folderRender.exr == nil {
		t.Fatal("the folder render failed in an earlier test")
	}
	return folderRender.exr
}

func TestObjectStoreRenderIsByteIdenticalToTheFolderRender(t *testing.T) {
	want := folderEXR(t)
	f, bucket := objectStoreFarm(t, s3test.Shared(t).TestURL(t))
	f.StartWorker(t)
	job := f.Render(t, objectStoreScene(t, f), 2*time.Minute)
	got := f.Output(t, job, "image.exr")
	if !bytes.Equal(farmtest.WithoutRenderTime(got), farmtest.WithoutRenderTime(want)) {
		t.Errorf("the EXR rendered with its blobs in the object store (%d bytes) differs from the folder render (%d bytes)", len(got), len(want))
	}
	// The coordinator says where its blobs are, and never logs the store's secret.
	log := f.Coordinator().LogTail(1000)
	if !strings.Contains(log, "blobs=\"s3://"+s3test.Bucket+"/") {
		t.Errorf("the coordinator's log does not say its blobs are in the bucket:\n%s", log)
	}
	if secret := os.Getenv("AWS_SECRET_ACCESS_KEY"); secret == "" || strings.Contains(log, secret) {
		t.Errorf("the coordinator's log shows the store's secret key (or there is none to check: %q)", secret)
	}
	// Every blob the job made or read is in the bucket: the scene, every task's outputs.
	digests := []string{job.GetSceneDigest()}
	for _, task := range f.Tasks(t, job.GetId()) {
		for _, a := range task.GetOutputs() {
			digests = append(digests, a.GetDigest())
		}
	}
	for _, d := range digests {
		if ok, err := bucket.Exists(context.Background(), blobstore.ObjectKey(d)); err != nil || !ok {
			t.Errorf("blob %s is not in the bucket: %v", d, err)
		}
	}
}

func TestDamagedObjectFailsItsJobAsLostInputNamingIt(t *testing.T) {
	f, bucket := objectStoreFarm(t, s3test.Shared(t).TestURL(t))
	damaged := f.Submit(t, objectStoreScene(t, f))
	digest := damaged.GetSceneDigest()
	key := blobstore.ObjectKey(digest)
	scene, err := bucket.ReadAll(context.Background(), key)
	if err != nil {
		t.Fatal(err)
	}
	if err := bucket.WriteAll(context.Background(), key, scene[:len(scene)/2], nil); err != nil {
		t.Fatal(err)
	}
	_, err = f.Client.Blobs().GetBlobInfo(context.Background(), &pb.GetBlobInfoRequest{Digest: digest})
	if status.Code(err) != codes.DataLoss || !strings.Contains(err.Error(), digest) {
		t.Errorf("GetBlobInfo of the damaged object = %v, want DATA_LOSS naming %s", err, digest)
	}
	start := time.Now()
	f.StartWorker(t)
	waitLostInput(t, f, damaged.GetId(), "the scene: blob "+digest+" is damaged", start, 10*time.Second)
}

// TestObjectStoreStoppedMidJob: the object store SIGKILLed once a task is done (an
// emission shard: the build, the tiles and the composite are still to come): a
// client's call about a blob ends within seconds as UNAVAILABLE naming the object store,
// the job neither fails nor hangs on it (workers retry), and once the store is back on
// the same data the job completes with the folder render's image.
func TestObjectStoreStoppedMidJob(t *testing.T) {
	want := folderEXR(t)

	srv, err := s3test.Start(t.TempDir())
	if err != nil {
		t.Fatal(err)
	}
	defer srv.Stop()
	f, _ := objectStoreFarm(t, srv.URL("stopped/")+"&stall_timeout=5s")
	job := f.Submit(t, objectStoreScene(t, f))
	f.StartWorker(t)
	deadline := time.Now().Add(2 * time.Minute)
	for !anyTaskSucceeded(f.Tasks(t, job.GetId())) {
		if time.Now().After(deadline) {
			t.Fatal("no task succeeded within 2 minutes")
		}
		time.Sleep(50 * time.Millisecond)
	}
	srv.Stop()

	ctx, cancel := context.WithTimeout(context.Background(), 60*time.Second)
	defer cancel()
	start := time.Now()
	_, err = f.Client.Blobs().GetBlobInfo(ctx, &pb.GetBlobInfoRequest{Digest: job.GetSceneDigest()})
	t.Logf("GetBlobInfo with the store stopped: %v after %v", err, time.Since(start).Round(time.Millisecond))
	if status.Code(err) != codes.Unavailable || !strings.Contains(err.Error(), "object store s3://"+s3test.Bucket) {
		t.Errorf("GetBlobInfo = %v, want UNAVAILABLE naming the object store", err)
	}
	if took := time.Since(start); took > 30*time.Second {
		t.Errorf("GetBlobInfo took %v with the store stopped", took)
	}
	if j, err := f.Client.GetJob(context.Background(), job.GetId()); err != nil || j.GetState() == pb.JobState_JOB_STATE_FAILED {
		t.Fatalf("the job with its store stopped: %v %v %q, %v", j.GetState(), j.GetFailureKind(), j.GetError(), err)
	}

	restart := time.Now()
	if err := srv.Restart(); err != nil {
		t.Fatal(err)
	}
	t.Logf("the store answered again %v after its restart", time.Since(restart).Round(time.Millisecond))
	done := f.Wait(t, job.GetId(), 3*time.Minute)
	t.Logf("the job completed %v after the restart", time.Since(restart).Round(time.Millisecond))
	for _, task := range f.Tasks(t, job.GetId()) {
		if task.GetAttempts() > 1 {
			t.Logf("task %s (%v) took %d attempts, last error %q", task.GetId(), task.GetPhase(), task.GetAttempts(), task.GetError())
		}
	}
	got := f.Output(t, done, "image.exr")
	if !bytes.Equal(farmtest.WithoutRenderTime(got), farmtest.WithoutRenderTime(want)) {
		t.Error("the EXR of the job whose store stopped differs from the folder render")
	}
}

func anyTaskSucceeded(tasks []*pb.Task) bool {
	for _, task := range tasks {
		if task.GetState() == pb.TaskState_TASK_STATE_SUCCEEDED {
			return true
		}
	}
	return false
}
