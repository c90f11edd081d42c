package builder

import (
	"fmt"
	"os"
	"syscall"
	"testing"

	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/errs"
	pb "photonfarm/proto/renderfarm/v1"
)

// A build that cannot store its snapshot because the coordinator's disk is full blames
// no worker (resource exhaustion), while a snapshot over the blob limit is bad input.
func TestFailureKindTellsAFullDiskFromAnInputOverALimit(t *testing.T) {
	full := &os.PathError{Op: "write", Path: "blobs/tmp/upload-1", Err: syscall.ENOSPC}
	for _, tt := range []struct {
		name string
		err  error
		want pb.FailureKind
	}{
		{"disk full", fmt.Errorf("storing the snapshot: %w", errs.Wrap(errs.ResourceExhausted, full, "blobstore: the coordinator's disk is full")), pb.FailureKind_FAILURE_KIND_RESOURCE_EXHAUSTED},
		{"quota full", &os.PathError{Op: "write", Path: "x", Err: syscall.EDQUOT}, pb.FailureKind_FAILURE_KIND_RESOURCE_EXHAUSTED},
		{"over the blob limit", &errs.Error{Kind: errs.ResourceExhausted, Field: "size_bytes", Message: "blob exceeds the limit"}, pb.FailureKind_FAILURE_KIND_BAD_INPUT},
		{"lost input", blobstore.Lost("the scene", "sha256:00", errs.E(errs.NotFound, "no blob")), pb.FailureKind_FAILURE_KIND_LOST_INPUT},
		{"anything else", errs.E(errs.Internal, "boom"), pb.FailureKind_FAILURE_KIND_TRANSIENT},
	} {
		if got := failureKind(tt.err); got != tt.want {
			t.Errorf("%s: failureKind(%v) = %v, want %v", tt.name, tt.err, got, tt.want)
		}
	}
}
