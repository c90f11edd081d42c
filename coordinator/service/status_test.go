package service

import (
	"errors"
	"io/fs"
	"log/slog"
	"strings"
	"syscall"
	"testing"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/coordinator/errs"
)

// TestFailuresOfTheDataFolderAnswerADefiniteCode: a write to the blob store that fails
// because the disk is full or the folder cannot be written answers RESOURCE_EXHAUSTED or
// UNAVAILABLE with a message saying so (and still naming the path), not INTERNAL, which
// blames a bug; any other failure of the store stays INTERNAL. (tests/fault's
// TestFullOrReadOnlyDataFolder does the same against a real full or read-only folder.)
func TestFailuresOfTheDataFolderAnswerADefiniteCode(t *testing.T) {
	s := &Service{log: slog.New(slog.DiscardHandler)}
	write := func(errno syscall.Errno) error {
		return errs.Wrap(errs.Internal, &fs.PathError{Op: "write", Path: "/data/blobs/tmp/upload-1", Err: errno}, "blobstore")
	}
	for _, tc := range []struct {
		name   string
		err    error
		code   codes.Code
		prefix string
	}{
		{"no space left", write(syscall.ENOSPC), codes.ResourceExhausted, "the coordinator's disk is full: "},
		{"over the quota", write(syscall.EDQUOT), codes.ResourceExhausted, "the coordinator's disk is full: "},
		{"a read-only file system", write(syscall.EROFS), codes.Unavailable, "the coordinator cannot write its data folder: "},
		{"a folder it may not write", write(syscall.EACCES), codes.Unavailable, "the coordinator cannot write its data folder: "},
		{"an I/O error", write(syscall.EIO), codes.Internal, "blobstore"},
		{"a bug", errors.New("impossible state"), codes.Internal, "impossible state"},
	} {
		t.Run(tc.name, func(t *testing.T) {
			st := status.Convert(s.toStatus("/renderfarm.v1.BlobService/UploadBlob", tc.err))
			if st.Code() != tc.code || !strings.HasPrefix(st.Message(), tc.prefix) {
				t.Errorf("got %v %q, want %v %q...", st.Code(), st.Message(), tc.code, tc.prefix)
			}
			if tc.code != codes.Internal && !strings.Contains(st.Message(), "/data/blobs/tmp/upload-1") {
				t.Errorf("%q does not name the path that failed", st.Message())
			}
		})
	}
}
