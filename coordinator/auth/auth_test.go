package auth_test

import (
	"context"
	"strings"
	"testing"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/metadata"
	"google.golang.org/grpc/status"

	"photonfarm/coordinator/auth"
	"photonfarm/coordinator/service"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestEveryServedMethodHasARule walks the services the coordinator's gRPC server really
// registers, so that a new RPC (or a new service) without a rule fails here instead of
// being refused to everyone, or worse, in production.
func TestEveryServedMethodHasARule(t *testing.T) {
	srv := service.New(service.Config{}).NewGRPCServer()
	served := map[string]bool{}
	for name, info := range srv.GetServiceInfo() {
		if auth.IsOpen("/" + name + "/x") {
			continue
		}
		for _, m := range info.Methods {
			full := "/" + name + "/" + m.Name
			served[full] = true
			if len(auth.Rules[full]) == 0 {
				t.Errorf("%s has no rule in auth.Rules: no role may call it", full)
			}
		}
	}
	if len(served) == 0 {
		t.Fatal("the server registers no methods")
	}
	for full := range auth.Rules {
		if !served[full] {
			t.Errorf("auth.Rules names %s, which the server does not serve", full)
		}
	}
}

// TestRolesPerService pins the policy: jobs are the client's, tasks the worker's, blobs
// both's.
func TestRolesPerService(t *testing.T) {
	want := map[string]string{
		pb.JobService_ServiceDesc.ServiceName:    "client",
		pb.WorkerService_ServiceDesc.ServiceName: "worker",
		pb.BlobService_ServiceDesc.ServiceName:   "client,worker",
	}
	for full, roles := range auth.Rules {
		svc, _, _ := strings.Cut(strings.TrimPrefix(full, "/"), "/")
		var got []string
		for _, r := range roles {
			got = append(got, string(r))
		}
		if g := strings.Join(got, ","); g != want[svc] {
			t.Errorf("%s: roles %s, want %s", full, g, want[svc])
		}
	}
}

func withToken(header string) context.Context {
	if header == "" {
		return context.Background()
	}
	return metadata.NewIncomingContext(context.Background(), metadata.Pairs("authorization", header))
}

func TestAuthorize(t *testing.T) {
	a, err := auth.New([]string{"client-secret"}, []string{"worker-secret", "worker-2"})
	if err != nil {
		t.Fatal(err)
	}
	lease := pb.WorkerService_LeaseTask_FullMethodName
	submit := pb.JobService_SubmitJob_FullMethodName
	upload := pb.BlobService_UploadBlob_FullMethodName
	for _, tc := range []struct {
		name, header, method string
		code                 codes.Code
		msg                  string
	}{
		{"no token", "", submit, codes.Unauthenticated, "no token"},
		{"not bearer", "Basic client-secret", submit, codes.Unauthenticated, "malformed"},
		{"empty bearer", "Bearer ", submit, codes.Unauthenticated, "malformed"},
		{"unknown token", "Bearer client-secreT", submit, codes.Unauthenticated, "unknown token"},
		{"prefix of a token", "Bearer client", submit, codes.Unauthenticated, "unknown token"},
		{"client submits", "Bearer client-secret", submit, codes.OK, ""},
		{"scheme is case-insensitive", "bearer client-secret", submit, codes.OK, ""},
		{"worker leases", "Bearer worker-2", lease, codes.OK, ""},
		{"client uploads", "Bearer client-secret", upload, codes.OK, ""},
		{"worker uploads", "Bearer worker-secret", upload, codes.OK, ""},
		{"client leases", "Bearer client-secret", lease, codes.PermissionDenied, "a client token may not call this method (it needs a worker token)"},
		{"worker submits", "Bearer worker-secret", submit, codes.PermissionDenied, "a worker token may not call this method (it needs a client token)"},
		{"unknown method", "Bearer client-secret", "/renderfarm.v1.JobService/Frobnicate", codes.PermissionDenied, "no role"},
		{"health is open", "", "/grpc.health.v1.Health/Check", codes.OK, ""},
	} {
		t.Run(tc.name, func(t *testing.T) {
			err := a.Authorize(withToken(tc.header), tc.method)
			if status.Code(err) != tc.code {
				t.Fatalf("Authorize = %v, want code %v", err, tc.code)
			}
			if err != nil && !strings.Contains(status.Convert(err).Message(), tc.msg) {
				t.Errorf("message %q does not contain %q", status.Convert(err).Message(), tc.msg)
			}
			if err != nil && !strings.Contains(status.Convert(err).Message(), tc.method) {
				t.Errorf("message %q does not name the method", status.Convert(err).Message())
			}
		})
	}
}

func TestNoTokensMeansOff(t *testing.T) {
	a, err := auth.New(nil, nil)
	if err != nil {
		t.Fatal(err)
	}
	if a.Enabled() || len(a.ServerOptions(nil)) != 0 {
		t.Error("an Authenticator without tokens is enabled")
	}
	if err := a.Authorize(context.Background(), pb.JobService_SubmitJob_FullMethodName); err != nil {
		t.Errorf("auth off refused a call: %v", err)
	}
}

func TestNewRefusesBadTokens(t *testing.T) {
	for _, tc := range []struct {
		name            string
		client, workers []string
		want            string
	}{
		{"empty", []string{""}, nil, "client token 1 is empty"},
		{"space", nil, []string{"ok", "a b"}, "worker token 2 contains white space"},
		{"newline", []string{"a\n"}, nil, "white space"},
		{"both roles", []string{"same"}, []string{"same"}, "worker token 1 is also a client token"},
	} {
		t.Run(tc.name, func(t *testing.T) {
			_, err := auth.New(tc.client, tc.workers)
			if err == nil || !strings.Contains(err.Error(), tc.want) {
				t.Errorf("New = %v, want an error containing %q", err, tc.want)
			}
		})
	}
}
