package errs_test

import (
	"errors"
	"fmt"
	"testing"

	"photonfarm/coordinator/errs"
)

func TestKindOfAndMessages(t *testing.T) {
	tests := []struct {
		err  error
		kind errs.Kind
		msg  string
	}{
		{errs.E(errs.NotFound, "no job %q", "j"), errs.NotFound, `no job "j"`},
		{errs.Field("job_id", "must be non-empty"), errs.InvalidArgument, "job_id: must be non-empty"},
		{fmt.Errorf("wrapped: %w", errs.E(errs.FailedPrecondition, "stale")), errs.FailedPrecondition, "wrapped: stale"},
		{errs.Wrap(errs.Internal, errors.New("disk"), "blobstore"), errs.Internal, "blobstore: disk"},
		{errors.New("plain"), errs.Internal, "plain"},
	}
	for _, tt := range tests {
		if got := errs.KindOf(tt.err); got != tt.kind || tt.err.Error() != tt.msg {
			t.Errorf("%v: kind %v, want %v; message %q, want %q", tt.err, got, tt.kind, tt.err.Error(), tt.msg)
		}
	}
	if errs.Wrap(errs.Internal, nil, "x") != nil {
		t.Error("Wrap(nil) != nil")
	}
}
