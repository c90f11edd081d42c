package dashboard

import (
	"context"
	"encoding/json"
	"errors"
	"fmt"
	"log/slog"
	"net/http"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"
	"google.golang.org/protobuf/encoding/protojson"
	"google.golang.org/protobuf/proto"
)

// httpStatusOf is the one mapping from the coordinator's gRPC codes to HTTP statuses
// (API.md, "Errors"); every other code is 500.
var httpStatusOf = map[codes.Code]int{
	codes.OK:                 http.StatusOK,
	codes.InvalidArgument:    http.StatusBadRequest,
	codes.Unauthenticated:    http.StatusUnauthorized,
	codes.PermissionDenied:   http.StatusForbidden,
	codes.NotFound:           http.StatusNotFound,
	codes.FailedPrecondition: http.StatusConflict,
	codes.ResourceExhausted:  http.StatusRequestEntityTooLarge,
	codes.Unavailable:        http.StatusServiceUnavailable,
	// A blob the coordinator holds damaged: the gateway's upstream cannot give it.
	codes.DataLoss: http.StatusBadGateway,
}

// HTTPStatus returns the HTTP status for a gRPC code.
func HTTPStatus(c codes.Code) int {
	if s, ok := httpStatusOf[c]; ok {
		return s
	}
	return http.StatusInternalServerError
}

// apiError is an error answered as {"error": message} with an HTTP status.
type apiError struct {
	status  int
	message string
}

func (e *apiError) Error() string { return e.message }

func errorf(status int, message string) error { return &apiError{status: status, message: message} }

// writeError answers err: an *apiError as it says, a refused token with the one answer
// of refuseToken, a gRPC status by its code (the coordinator's message), anything else
// as 500.
func (s *Server) writeError(w http.ResponseWriter, r *http.Request, err error) {
	dropBody(w, r)
	if refused(err) {
		s.refuseToken(w, r, presentsToken(r))
		return
	}
	code, msg := http.StatusInternalServerError, err.Error()
	var ae *apiError
	var mbe *http.MaxBytesError
	switch {
	case errors.As(err, &ae):
		code, msg = ae.status, ae.message
	case errors.As(err, &mbe):
		code, msg = http.StatusRequestEntityTooLarge, fmt.Sprintf("request body larger than the limit of %d MiB", mbe.Limit>>20)
	case errors.Is(err, context.Canceled) && r.Context().Err() != nil:
		return // the browser went away; nobody reads the answer
	default:
		if st, ok := status.FromError(err); ok {
			code, msg = HTTPStatus(st.Code()), st.Message()
		}
	}
	if code == http.StatusInternalServerError {
		s.log.Error("dashboard request failed", "method", r.Method, "path", r.URL.Path, "err", err)
	}
	writeJSON(w, code, map[string]any{"error": msg})
}

// dropBody makes an answer close the connection when the request has a body, which an
// error answer may have left unread: net/http would otherwise read up to 256 KiB of it
// first, and wait as long as the client likes for a body that never ends.
func dropBody(w http.ResponseWriter, r *http.Request) {
	if r.ContentLength != 0 {
		w.Header().Set("Connection", "close")
	}
}

// writeJSON answers v as JSON with status code.
func writeJSON(w http.ResponseWriter, code int, v any) {
	b, err := json.Marshal(v)
	if err != nil {
		slog.Error("dashboard: encode answer", "err", err)
		http.Error(w, `{"error":"encode answer"}`, http.StatusInternalServerError)
		return
	}
	w.Header().Set("Content-Type", "application/json; charset=utf-8")
	w.Header().Set("Cache-Control", "no-store")
	w.WriteHeader(code)
	w.Write(append(b, '\n'))
}

// pj is a protobuf message in the canonical JSON mapping (API.md), for embedding in
// an answer.
func pj(m proto.Message) json.RawMessage {
	b, err := protojson.Marshal(m)
	if err != nil {
		// Only invalid UTF-8 in a string field can get here; the coordinator never
		// stores that.
		return json.RawMessage("null")
	}
	return b
}

// pjs is a list of messages in the canonical JSON mapping; never null, so that an empty
// list is [].
func pjs[M proto.Message](ms []M) []json.RawMessage {
	out := make([]json.RawMessage, len(ms))
	for i, m := range ms {
		out[i] = pj(m)
	}
	return out
}
