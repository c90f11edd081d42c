package service

import (
	"context"
	"errors"
	"strings"
	"syscall"

	"google.golang.org/genproto/googleapis/rpc/errdetails"
	"google.golang.org/grpc"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/contract/scene"
	"photonfarm/coordinator/errs"
)

// codeOf is the one mapping from internal error kinds to gRPC codes.
var codeOf = map[errs.Kind]codes.Code{
	errs.Internal:           codes.Internal,
	errs.InvalidArgument:    codes.InvalidArgument,
	errs.NotFound:           codes.NotFound,
	errs.AlreadyExists:      codes.AlreadyExists,
	errs.FailedPrecondition: codes.FailedPrecondition,
	errs.ResourceExhausted:  codes.ResourceExhausted,
	errs.Unavailable:        codes.Unavailable,
	errs.PermissionDenied:   codes.PermissionDenied,
	errs.DataLoss:           codes.DataLoss,
	errs.OutOfRange:         codes.OutOfRange,
}

// toStatus converts a handler's error to a gRPC status error. A field error carries an
// errdetails.BadRequest naming the field.
func (s *Service) toStatus(method string, err error) error {
	if err == nil {
		return nil
	}
	if _, ok := err.(interface{ GRPCStatus() *status.Status }); ok {
		return err
	}
	var (
		code  = codes.Internal
		field string
		msg   = err.Error()
	)
	var fe *scene.FieldError
	var e *errs.Error
	switch {
	case errors.As(err, &fe):
		code, field = codes.InvalidArgument, fe.Field
	case errors.As(err, &e):
		code, field = codeOf[e.Kind], e.Field
	case errors.Is(err, context.Canceled):
		code = codes.Canceled
	case errors.Is(err, context.DeadlineExceeded):
		code = codes.DeadlineExceeded
	}
	if code == codes.Internal {
		code, msg = storageStatus(err, msg)
		// Either is for the operator: a bug, or a data folder to fix.
		s.log.Error("internal error", "method", method, "code", code.String(), "err", err)
	}
	st := status.New(code, msg)
	if field != "" {
		if d, derr := st.WithDetails(&errdetails.BadRequest{FieldViolations: []*errdetails.BadRequest_FieldViolation{
			{Field: field, Description: strings.TrimPrefix(msg, field+": ")},
		}}); derr == nil {
			st = d
		}
	}
	return st.Err()
}

// storageStatus says what a failure of the coordinator's own files (the data folder:
// blobs) means to the caller, instead of INTERNAL, which would blame a bug: a full disk
// (or quota) is RESOURCE_EXHAUSTED, a read-only or unwritable data folder UNAVAILABLE
// (the call may succeed once an operator has made room or fixed the folder; nothing was
// stored). The message keeps the failed operation and path. Other errors stay INTERNAL.
func storageStatus(err error, msg string) (codes.Code, string) {
	switch {
	case errors.Is(err, syscall.ENOSPC) || errors.Is(err, syscall.EDQUOT):
		return codes.ResourceExhausted, "the coordinator's disk is full: " + msg
	case errors.Is(err, syscall.EROFS) || errors.Is(err, syscall.EACCES) || errors.Is(err, syscall.EPERM):
		return codes.Unavailable, "the coordinator cannot write its data folder: " + msg
	}
	return codes.Internal, msg
}

func (s *Service) unaryErrors(ctx context.Context, req any, info *grpc.UnaryServerInfo, h grpc.UnaryHandler) (any, error) {
	resp, err := h(ctx, req)
	return resp, s.toStatus(info.FullMethod, err)
}

func (s *Service) streamErrors(srv any, ss grpc.ServerStream, info *grpc.StreamServerInfo, h grpc.StreamHandler) error {
	return s.toStatus(info.FullMethod, h(srv, ss))
}
