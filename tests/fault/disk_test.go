package fault

import (
	"bytes"
	"context"
	"os"
	"path/filepath"
	"strings"
	"testing"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/tests/farmtest"
)

// inMountNamespace is a command line that runs the command line after it in a user and
// mount namespace of its own (so no privilege is needed and nothing outside sees the
// mount) once the shell commands prepare have made the folder $D ready.
func inMountNamespace(dir, prepare string) []string {
	return []string{"unshare", "--user", "--map-root-user", "--mount",
		"sh", "-c", `D="$1"; shift; ` + prepare + ` && exec "$@"`, "sh", dir}
}

// TestFullOrReadOnlyDataFolderAnswersADefiniteCode runs a real coordinator whose data
// folder is a 1 MiB file system, or a read-only one, and uploads a 2 MiB blob: the
// answer must be RESOURCE_EXHAUSTED "the coordinator's disk is full" or UNAVAILABLE "the
// coordinator cannot write its data folder" (before: INTERNAL, which blames a bug), with
// nothing stored; the coordinator goes on serving, and on the full disk a small blob
// still fits (the failed upload left nothing behind).
func TestFullOrReadOnlyDataFolderAnswersADefiniteCode(t *testing.T) {
	for _, tc := range []struct {
		name, prepare string
		code          codes.Code
		says          string
		smallFits     bool
	}{
		{"a full disk", `mount -t tmpfs -o size=1m tmpfs "$D"`,
			codes.ResourceExhausted, "the coordinator's disk is full: ", true},
		// The blob store's folders exist, as they would on a folder made read-only later.
		{"a read-only data folder", `mkdir -p "$D/blobs/sha256" "$D/blobs/tmp" && mount --bind "$D" "$D" && mount -o remount,bind,ro "$D"`,
			codes.Unavailable, "the coordinator cannot write its data folder: ", false},
	} {
		t.Run(tc.name, func(t *testing.T) {
			dir := filepath.Join(t.TempDir(), "data")
			if err := os.Mkdir(dir, 0o755); err != nil {
				t.Fatal(err)
			}
			f := farmtest.StartFarmIn(t, inMountNamespace(dir, tc.prepare), []string{"--data-dir", dir})
			ctx, cancel := context.WithTimeout(context.Background(), 30*time.Second)
			defer cancel()

			big := bytes.Repeat([]byte("photonfarm "), 2<<20/11)
			digest, err := f.Client.UploadBytes(ctx, big)
			if st := status.Convert(err); st.Code() != tc.code || !strings.Contains(st.Message(), tc.says) {
				t.Fatalf("uploading %d bytes: %v %q, want %v %q...", len(big), st.Code(), st.Message(), tc.code, tc.says)
			} else {
				t.Logf("uploading %d bytes: %v %s", len(big), st.Code(), st.Message())
			}
			if ok, err := f.Client.BlobExists(ctx, digest); err != nil || ok {
				t.Errorf("after the failed upload, the blob exists: %v, %v; want false, nil", ok, err)
			}
			small := []byte("a small blob")
			_, err = f.Client.UploadBytes(ctx, small)
			if tc.smallFits && err != nil {
				t.Errorf("a %d-byte upload after the failed one: %v", len(small), err)
			}
			if !tc.smallFits && status.Code(err) != tc.code {
				t.Errorf("a %d-byte upload to the read-only folder: %v, want %v", len(small), err, tc.code)
			}
			if _, err := f.Client.ListJobs(ctx); err != nil {
				t.Errorf("the coordinator after the failed upload: %v", err)
			}
		})
	}
}
