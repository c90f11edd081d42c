package store

import (
	"encoding/base64"
	"strconv"

	"photonfarm/coordinator/errs"
	pb "photonfarm/proto/renderfarm/v1"
)

// Page tokens are opaque to clients: base64 of "j<seq>" (jobs older than seq) or
// "t<index>" (tasks from index on). Every implementation uses these, so a token stays
// valid across a change of store.

// EncodePageToken returns the token of position n in the listing named by prefix.
func EncodePageToken(prefix byte, n uint64) string {
	return base64.RawURLEncoding.EncodeToString([]byte(string(prefix) + strconv.FormatUint(n, 10)))
}

// DecodePageToken returns the position a token of the listing named by prefix holds, or
// an InvalidArgument error naming page_token.
func DecodePageToken(prefix byte, tok string) (uint64, error) {
	b, err := base64.RawURLEncoding.DecodeString(tok)
	if err == nil && len(b) > 1 && b[0] == prefix {
		if n, err := strconv.ParseUint(string(b[1:]), 10, 64); err == nil {
			return n, nil
		}
	}
	return 0, errs.Field("page_token", "malformed page token %q", tok)
}

// CheckLeaseArgs refuses a LeaseTask without a worker id or phases.
func CheckLeaseArgs(workerID string, phases []pb.Phase) error {
	if workerID == "" {
		return errs.Field("worker_id", "must be non-empty")
	}
	if len(phases) == 0 {
		return errs.E(errs.Internal, "LeaseTask needs the phases the caller takes")
	}
	return nil
}

// Page checks a listing's page size and decodes its page token: the position the token
// holds, and whether there was one (false for the first page).
func Page(prefix byte, pageSize int, pageToken string) (pos uint64, given bool, err error) {
	if pageSize <= 0 {
		return 0, false, errs.Field("page_size", "must be > 0, got %d", pageSize)
	}
	if pageToken == "" {
		return 0, false, nil
	}
	pos, err = DecodePageToken(prefix, pageToken)
	return pos, err == nil, err
}
