package client

import (
	"context"
	"strings"
	"sync"

	"google.golang.org/grpc"
	"google.golang.org/grpc/metadata"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// WorkerSecrets is a dial option for Go programs that act as workers over a connection
// (tools, tests): it keeps the worker_secret of every RegisterWorker answer and sends it,
// as the metadata worker.proto names, with every later WorkerService call whose request
// names that worker, unless the call carries that metadata already. UnregisterWorker
// forgets it.
func WorkerSecrets() grpc.DialOption {
	var (
		mu      sync.Mutex
		secrets = map[string]string{}
	)
	prefix := "/" + pb.WorkerService_ServiceDesc.ServiceName + "/"
	return grpc.WithChainUnaryInterceptor(func(ctx context.Context, method string, req, reply any, cc *grpc.ClientConn, invoker grpc.UnaryInvoker, opts ...grpc.CallOption) error {
		if !strings.HasPrefix(method, prefix) {
			return invoker(ctx, method, req, reply, cc, opts...)
		}
		r, names := req.(interface{ GetWorkerId() string })
		if names {
			mu.Lock()
			secret, ok := secrets[r.GetWorkerId()]
			mu.Unlock()
			if md, _ := metadata.FromOutgoingContext(ctx); ok && len(md.Get(rules.WorkerSecretMetadata)) == 0 {
				ctx = metadata.AppendToOutgoingContext(ctx, rules.WorkerSecretMetadata, secret)
			}
		}
		err := invoker(ctx, method, req, reply, cc, opts...)
		if err != nil {
			return err
		}
		mu.Lock()
		defer mu.Unlock()
		switch resp := reply.(type) {
		case *pb.RegisterWorkerResponse:
			secrets[resp.GetWorkerId()] = resp.GetWorkerSecret()
		case *pb.UnregisterWorkerResponse:
			delete(secrets, r.GetWorkerId())
		}
		return nil
	})
}
