package client_test

import (
	"context"
	"os"
	"path/filepath"
	"testing"

	"photonfarm/client"
	"photonfarm/coordinator"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/coordinatortest"
	pb "photonfarm/proto/renderfarm/v1"
)

// A mesh the coordinator's store has lost, or holds damaged, is uploaded again by the next
// submit that names it, rather than trusted because the store once had it.
func TestUploadFileReplacesABlobTheStoreLostOrDamaged(t *testing.T) {
	ctx := context.Background()
	dataDir := t.TempDir()
	srv := coordinatortest.Serve(t, coordinator.Config{DataDir: dataDir})
	c := client.New(srv.Dial(t, client.CallLimits()))
	mesh := filepath.Join(t.TempDir(), "tri.obj")
	if err := os.WriteFile(mesh, []byte("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), 0o644); err != nil {
		t.Fatal(err)
	}
	stored := func(digest string) string {
		return blobstore.PathIn(filepath.Join(dataDir, "blobs"), digest)
	}
	for name, harm := range map[string]func(path string) error{
		"lost":    os.Remove,
		"damaged": func(path string) error { return os.Truncate(path, 5) },
	} {
		digest, err := c.UploadFile(ctx, mesh)
		if err != nil {
			t.Fatal(err)
		}
		if err := harm(stored(digest)); err != nil {
			t.Fatalf("%s: %v", name, err)
		}
		if _, err := c.UploadFile(ctx, mesh); err != nil {
			t.Fatalf("%s: uploading again: %v", name, err)
		}
		if _, err := c.Blobs().GetBlobInfo(ctx, &pb.GetBlobInfoRequest{Digest: digest}); err != nil {
			t.Errorf("%s: after uploading again, GetBlobInfo = %v; want the blob intact", name, err)
		}
	}
}
