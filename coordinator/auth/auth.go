// Package auth is the coordinator's access control: bearer tokens, each belonging to one
// role, and a gRPC tap handle that lets a call through only if its token's role may call
// that method, checked from the call's headers before any of its message is read.
//
// Two roles: a client submits and follows jobs (JobService), a worker leases and reports
// tasks (WorkerService); both move blobs (BlobService). Tokens travel as the gRPC metadata
// "authorization: Bearer TOKEN". A call without a token, or with one the coordinator does
// not know, fails with UNAUTHENTICATED; a known token of a role that may not call the
// method fails with PERMISSION_DENIED. gRPC's health and reflection services stay open.
//
// An Authenticator with no tokens at all is off: every call passes. That is meant for a
// coordinator on loopback (tests, `farm render` before it had tokens); cmd/farm warns when
// it happens elsewhere.
package auth

import (
	"context"
	"crypto/sha256"
	"crypto/subtle"
	"errors"
	"fmt"
	"strings"
	"unicode"

	"google.golang.org/grpc"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/metadata"
	"google.golang.org/grpc/status"
	"google.golang.org/grpc/tap"

	pb "photonfarm/proto/renderfarm/v1"
)

// Role is what a token may do.
type Role string

const (
	// Client submits, follows, cancels and fetches jobs.
	Client Role = "client"
	// Worker leases, performs and reports tasks.
	Worker Role = "worker"
)

// MetadataKey is the gRPC metadata key carrying "Bearer TOKEN".
const MetadataKey = "authorization"

// Rules maps every method of the farm's services (full gRPC names) to the roles that may
// call it. A method missing here is refused to every role; the tests fail if a service
// gains a method without a rule.
var Rules = map[string][]Role{
	pb.JobService_SubmitJob_FullMethodName:      {Client},
	pb.JobService_GetJob_FullMethodName:         {Client},
	pb.JobService_ListJobs_FullMethodName:       {Client},
	pb.JobService_ListTasks_FullMethodName:      {Client},
	pb.JobService_CancelJob_FullMethodName:      {Client},
	pb.JobService_SetJobPriority_FullMethodName: {Client},
	pb.JobService_UnblockWorker_FullMethodName:  {Client},
	pb.JobService_RequeueJob_FullMethodName:     {Client},
	pb.JobService_RetryTask_FullMethodName:      {Client},
	pb.JobService_DeleteJob_FullMethodName:      {Client},
	pb.JobService_ListWorkers_FullMethodName:    {Client},
	pb.JobService_PlanScene_FullMethodName:      {Client},
	pb.JobService_WatchJob_FullMethodName:       {Client},

	pb.WorkerService_RegisterWorker_FullMethodName:   {Worker},
	pb.WorkerService_Heartbeat_FullMethodName:        {Worker},
	pb.WorkerService_LeaseTask_FullMethodName:        {Worker},
	pb.WorkerService_CompleteTask_FullMethodName:     {Worker},
	pb.WorkerService_FailTask_FullMethodName:         {Worker},
	pb.WorkerService_ReleaseTask_FullMethodName:      {Worker},
	pb.WorkerService_UnregisterWorker_FullMethodName: {Worker},

	pb.BlobService_UploadBlob_FullMethodName:   {Client, Worker},
	pb.BlobService_DownloadBlob_FullMethodName: {Client, Worker},
	pb.BlobService_GetBlobInfo_FullMethodName:  {Client, Worker},
}

// OpenServices are the gRPC services any caller may use, token or not.
var OpenServices = []string{
	"grpc.health.v1.Health",
	"grpc.reflection.v1.ServerReflection",
	"grpc.reflection.v1alpha.ServerReflection",
}

// IsOpen reports whether fullMethod ("/package.Service/Method") belongs to an open service.
func IsOpen(fullMethod string) bool {
	svc, _, _ := strings.Cut(strings.TrimPrefix(fullMethod, "/"), "/")
	for _, s := range OpenServices {
		if svc == s {
			return true
		}
	}
	return false
}

// Authenticator knows the tokens and their roles. The zero value and one made from no
// tokens are off (Enabled reports false) and let every call through.
type Authenticator struct {
	tokens []token
}

// A token is kept as its SHA-256 digest, so that comparisons take the same time whatever
// the lengths of the presented and the known token.
type token struct {
	digest [sha256.Size]byte
	role   Role
}

// New returns an Authenticator for the given tokens of each role. A token must not be
// empty, contain white space or control characters, or belong to both roles.
func New(clientTokens, workerTokens []string) (*Authenticator, error) {
	a := &Authenticator{}
	roleOf := map[string]Role{}
	add := func(role Role, list []string) error {
		for i, t := range list {
			if t == "" {
				return fmt.Errorf("auth: %s token %d is empty", role, i+1)
			}
			if strings.IndexFunc(t, func(r rune) bool { return unicode.IsSpace(r) || unicode.IsControl(r) }) >= 0 {
				return fmt.Errorf("auth: %s token %d contains white space or a control character", role, i+1)
			}
			if prev, ok := roleOf[t]; ok {
				if prev != role {
					return fmt.Errorf("auth: %s token %d is also a %s token; a token has one role", role, i+1, prev)
				}
				continue
			}
			roleOf[t] = role
			a.tokens = append(a.tokens, token{digest: sha256.Sum256([]byte(t)), role: role})
		}
		return nil
	}
	if err := add(Client, clientTokens); err != nil {
		return nil, err
	}
	if err := add(Worker, workerTokens); err != nil {
		return nil, err
	}
	return a, nil
}

// Enabled reports whether any token is configured; if not, every call passes.
func (a *Authenticator) Enabled() bool { return a != nil && len(a.tokens) > 0 }

// roleOf returns the role of tok. Every known token is compared, in constant time, so the
// time taken says nothing about which token (or how much of one) matched.
func (a *Authenticator) roleOf(tok string) (Role, bool) {
	d := sha256.Sum256([]byte(tok))
	var found Role
	for _, t := range a.tokens {
		if subtle.ConstantTimeCompare(d[:], t.digest[:]) == 1 {
			found = t.role
		}
	}
	return found, found != ""
}

// errNoToken and errBadScheme are the reasons a call without a usable token is refused.
var (
	errNoToken   = errors.New(`no token: send the metadata "authorization: Bearer TOKEN"`)
	errBadScheme = errors.New(`malformed authorization metadata: want "Bearer TOKEN"`)
)

// bearer extracts the token from a call's metadata.
func bearer(md metadata.MD) (string, error) {
	vals := md.Get(MetadataKey)
	if len(vals) == 0 {
		return "", errNoToken
	}
	if len(vals) > 1 {
		return "", errors.New("more than one authorization metadata value")
	}
	scheme, tok, ok := strings.Cut(strings.TrimSpace(vals[0]), " ")
	tok = strings.TrimSpace(tok)
	if !ok || !strings.EqualFold(scheme, "Bearer") || tok == "" {
		return "", errBadScheme
	}
	return tok, nil
}

// Authorize returns nil if the call to fullMethod carried in ctx may proceed, else a
// status error: UNAUTHENTICATED for a missing, malformed or unknown token,
// PERMISSION_DENIED for a token whose role may not call the method.
func (a *Authenticator) Authorize(ctx context.Context, fullMethod string) error {
	md, _ := metadata.FromIncomingContext(ctx)
	return a.authorize(md, fullMethod)
}

func (a *Authenticator) authorize(md metadata.MD, fullMethod string) error {
	if !a.Enabled() || IsOpen(fullMethod) {
		return nil
	}
	tok, err := bearer(md)
	if err != nil {
		return status.Errorf(codes.Unauthenticated, "%s: %v", fullMethod, err)
	}
	role, ok := a.roleOf(tok)
	if !ok {
		return status.Errorf(codes.Unauthenticated, "%s: unknown token", fullMethod)
	}
	allowed := Rules[fullMethod]
	for _, r := range allowed {
		if r == role {
			return nil
		}
	}
	if len(allowed) == 0 {
		return status.Errorf(codes.PermissionDenied, "%s: no role may call this method", fullMethod)
	}
	return status.Errorf(codes.PermissionDenied, "%s: a %s token may not call this method (it needs a %s token)",
		fullMethod, role, joinRoles(allowed))
}

func joinRoles(roles []Role) string {
	s := make([]string, len(roles))
	for i, r := range roles {
		s[i] = string(r)
	}
	return strings.Join(s, " or ")
}

// TapHandle checks each call, unary or streaming, with Authorize's rules from the
// metadata of its headers, before gRPC creates the stream: a refused call costs the
// coordinator its headers only. (An interceptor runs after gRPC has read and decoded the
// request message, up to max_message_bytes, so an unauthenticated caller could make the
// coordinator hold 64 MiB per stream.) It is a grpc/tap.ServerInHandle.
func (a *Authenticator) TapHandle(ctx context.Context, info *tap.Info) (context.Context, error) {
	return ctx, a.authorize(info.Header, info.FullMethodName)
}

// UnknownMethod is what MethodLabel makes of a method name not in Rules.
const UnknownMethod = "unknown"

// MethodLabel is fullMethod if it is one of the farm's methods (Rules), else
// UnknownMethod: a refused caller may name any method, and a metric labelled with what
// callers make up would grow without bound.
func MethodLabel(fullMethod string) string {
	if _, ok := Rules[fullMethod]; ok {
		return fullMethod
	}
	return UnknownMethod
}

// ServerOptions returns the tap handle as a gRPC server option (none when a is off).
// refused, when not nil, is told of every call the tap handle refuses, by MethodLabel
// and code: such calls never reach an interceptor.
func (a *Authenticator) ServerOptions(refused func(method string, code codes.Code)) []grpc.ServerOption {
	if !a.Enabled() {
		return nil
	}
	handle := a.TapHandle
	if refused != nil {
		handle = func(ctx context.Context, info *tap.Info) (context.Context, error) {
			ctx, err := a.TapHandle(ctx, info)
			if err != nil {
				refused(MethodLabel(info.FullMethodName), status.Code(err))
			}
			return ctx, err
		}
	}
	return []grpc.ServerOption{grpc.InTapHandle(handle)}
}
