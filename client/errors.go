package client

import (
	"context"
	"errors"
	"strings"

	"google.golang.org/genproto/googleapis/rpc/errdetails"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"
)

// Error is a failure with a gRPC code and, for invalid input, the field at fault. Its
// message is meant for people: "shapes[2].sphere.radius: must be > 0, got -1", without
// gRPC's "rpc error: code = ... desc = ..." wrapping. status.Code(err) works on it.
type Error struct {
	Code codes.Code
	// Field is the protobuf path of the offending field ("shapes[3].mesh.path"), if known.
	Field string
	// Message says what is wrong, without the field.
	Message string
	// Err is the underlying cause, if any.
	Err error
}

func (e *Error) Error() string {
	msg := e.Message
	if msg == "" && e.Err != nil {
		msg = e.Err.Error()
	}
	if e.Field != "" {
		return e.Field + ": " + msg
	}
	return msg
}

func (e *Error) Unwrap() error { return e.Err }

// GRPCStatus makes status.Code and status.FromError see the code.
func (e *Error) GRPCStatus() *status.Status { return status.New(e.Code, e.Error()) }

// IsInvalidInput reports whether err blames the caller's input (a scene, a job id).
func IsInvalidInput(err error) bool {
	return status.Code(err) == codes.InvalidArgument
}

func invalid(field, msg string, cause error) *Error {
	return &Error{Code: codes.InvalidArgument, Field: field, Message: msg, Err: cause}
}

// fromRPC turns a gRPC error into an *Error: the field of a BadRequest detail, when the
// server sent one, and the status message otherwise. what names the call ("submit job")
// for errors that are not the caller's fault, such as an unreachable coordinator.
func fromRPC(what string, err error) error {
	if err == nil {
		return nil
	}
	if errors.Is(err, context.Canceled) || errors.Is(err, context.DeadlineExceeded) {
		return err
	}
	st, ok := status.FromError(err)
	if !ok {
		return err
	}
	e := &Error{Code: st.Code(), Message: st.Message(), Err: err}
	for _, d := range st.Details() {
		if br, ok := d.(*errdetails.BadRequest); ok && len(br.GetFieldViolations()) > 0 {
			fv := br.GetFieldViolations()[0]
			// Some servers repeat the field in the description; say it once.
			e.Field = fv.GetField()
			e.Message = strings.TrimPrefix(fv.GetDescription(), e.Field+": ")
			break
		}
	}
	switch st.Code() {
	case codes.InvalidArgument, codes.NotFound, codes.FailedPrecondition, codes.ResourceExhausted:
		// The message says it all.
	case codes.Canceled:
		return context.Canceled
	case codes.DeadlineExceeded:
		return context.DeadlineExceeded
	case codes.Unavailable:
		e.Message = what + ": coordinator unavailable: " + st.Message()
	default:
		e.Message = what + ": " + st.Code().String() + ": " + e.Message
	}
	return e
}
