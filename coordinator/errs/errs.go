// Package errs is the coordinator's one internal error type. Every package below the
// service boundary reports failures as an *Error with a Kind; the service layer maps the
// Kind to a gRPC status code in exactly one place (service/status.go).
package errs

import (
	"errors"
	"fmt"
)

// Kind classifies an error by what the caller can do about it.
type Kind int

const (
	// Internal is a bug or an unexpected condition (the zero Kind).
	Internal Kind = iota
	// InvalidArgument: the request is malformed; Field names the culprit when known.
	InvalidArgument
	// NotFound: the named resource does not exist.
	NotFound
	// AlreadyExists: the resource exists already.
	AlreadyExists
	// FailedPrecondition: the request is well formed but the state forbids it
	// (a stale lease epoch, a job that has already ended).
	FailedPrecondition
	// ResourceExhausted: a size or count limit was exceeded.
	ResourceExhausted
	// Unavailable: the coordinator is shutting down.
	Unavailable
	// PermissionDenied: the caller may not act on the resource (a call about a worker
	// without that worker's registration secret).
	PermissionDenied
	// DataLoss: stored data is damaged (a blob whose content no longer matches its
	// digest).
	DataLoss
	// OutOfRange: a position past the end of the resource (a blob range that starts past
	// the blob's end).
	OutOfRange
)

func (k Kind) String() string {
	switch k {
	case InvalidArgument:
		return "invalid argument"
	case NotFound:
		return "not found"
	case AlreadyExists:
		return "already exists"
	case FailedPrecondition:
		return "failed precondition"
	case ResourceExhausted:
		return "resource exhausted"
	case Unavailable:
		return "unavailable"
	case PermissionDenied:
		return "permission denied"
	case DataLoss:
		return "data loss"
	case OutOfRange:
		return "out of range"
	default:
		return "internal"
	}
}

// Error is an error with a Kind and, for InvalidArgument, the field at fault.
type Error struct {
	Kind Kind
	// Field is a protobuf-style path such as "job_id" or "shapes[2].mesh.digest"; optional.
	Field string
	// Message says what is wrong, without the field.
	Message string
	// Err is the underlying cause, if any.
	Err error
}

func (e *Error) Error() string {
	msg := e.Message
	if e.Err != nil {
		if msg == "" {
			msg = e.Err.Error()
		} else {
			msg += ": " + e.Err.Error()
		}
	}
	if e.Field != "" {
		return e.Field + ": " + msg
	}
	return msg
}

func (e *Error) Unwrap() error { return e.Err }

// E builds an *Error of kind k with a formatted message.
func E(k Kind, format string, args ...any) *Error {
	return &Error{Kind: k, Message: fmt.Sprintf(format, args...)}
}

// Field builds an InvalidArgument *Error naming field.
func Field(field, format string, args ...any) *Error {
	return &Error{Kind: InvalidArgument, Field: field, Message: fmt.Sprintf(format, args...)}
}

// Wrap gives err the kind k and a message prefix; nil stays nil.
func Wrap(k Kind, err error, message string) error {
	if err == nil {
		return nil
	}
	return &Error{Kind: k, Message: message, Err: err}
}

// KindOf returns the Kind of the first *Error in err's chain, or Internal.
func KindOf(err error) Kind {
	var e *Error
	if errors.As(err, &e) {
		return e.Kind
	}
	return Internal
}

// Is reports whether err carries kind k.
func Is(err error, k Kind) bool { return err != nil && KindOf(err) == k }
