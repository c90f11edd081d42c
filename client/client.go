// Package client is the Go SDK of the farm: it loads scene files (uploading the meshes they
// reference), submits jobs, follows their progress and downloads their results. The farm
// CLI and the integration tests use it; so can any Go program.
//
//	c, err := client.Dial("localhost:7070")
//	sc, err := c.LoadSceneFile(ctx, "scenes/cornell-box.json")
//	job, err := c.Submit(ctx, sc)
//	job, err = c.Watch(ctx, job.GetId(), func(ev *pb.WatchJobResponse) { ... })
//	paths, err := c.Fetch(ctx, job.GetId(), "out")
//
// Errors the caller can act on are *Error values carrying a gRPC code and, for invalid
// input, the protobuf path of the offending field.
package client

import (
	"errors"
	"fmt"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials"
	"google.golang.org/grpc/credentials/insecure"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// DefaultAddress is where a coordinator listens unless told otherwise.
const DefaultAddress = "localhost:7070"

// Client talks to one coordinator over one gRPC connection. It is safe for concurrent use.
type Client struct {
	conn     grpc.ClientConnInterface
	owned    *grpc.ClientConn // the connection Dial made, which Close closes
	jobs     pb.JobServiceClient
	blobs    pb.BlobServiceClient
	chunkLen int
	// How long Watch tries to reopen a cut stream (watchResumeFor; tests shorten it).
	watchResumeFor time.Duration
}

// An Option configures Dial.
type Option func(*dialOptions)

type dialOptions struct {
	creds          credentials.TransportCredentials
	secure         bool // creds protect the connection (not plaintext)
	perRPC         credentials.PerRPCCredentials
	token          string
	allowPlaintext bool
	extra          []grpc.DialOption
	chunkLen       int
	err            error // from an option that failed (an unreadable CA file)
}

// WithTransportCredentials secures the connection (TLS, mTLS). Without it the connection
// is plaintext, which is meant for loopback and trusted networks only.
func WithTransportCredentials(c credentials.TransportCredentials) Option {
	return func(o *dialOptions) { o.creds, o.secure = c, true }
}

// WithPerRPCCredentials attaches credentials (for example a bearer token) to every call.
func WithPerRPCCredentials(c credentials.PerRPCCredentials) Option {
	return func(o *dialOptions) { o.perRPC = c }
}

// WithDialOptions passes further options to grpc.NewClient.
func WithDialOptions(opts ...grpc.DialOption) Option {
	return func(o *dialOptions) { o.extra = append(o.extra, opts...) }
}

// withChunkSize changes the upload chunk size (tests use small chunks).
func withChunkSize(n int) Option {
	return func(o *dialOptions) { o.chunkLen = n }
}

// Dial returns a Client for the coordinator at addr ("host:port", or the replicas at
// "host:port,host:port": replicas.go). The connection is made
// lazily, on the first call, so Dial fails only for a malformed address or options, or
// for a token that would travel in plaintext to another machine (ErrPlaintextToken).
func Dial(addr string, opts ...Option) (*Client, error) {
	target, targetOpts, err := ReplicaTarget(addr)
	if err != nil {
		return nil, fmt.Errorf("client: %w", err)
	}
	o := dialOptions{creds: insecure.NewCredentials(), chunkLen: UploadChunkSize}
	for _, opt := range opts {
		opt(&o)
	}
	if o.err != nil {
		return nil, o.err
	}
	if o.token != "" {
		if !o.secure && !o.allowPlaintext && !IsLoopback(addr) {
			return nil, fmt.Errorf("client: %s: %w (use TLS, or allow plaintext on a trusted network)", addr, ErrPlaintextToken)
		}
		if o.perRPC != nil {
			return nil, errors.New("client: WithToken and WithPerRPCCredentials are exclusive")
		}
		o.perRPC = bearerToken{token: o.token, requireTLS: o.secure}
	}
	dopts := append([]grpc.DialOption{grpc.WithTransportCredentials(o.creds), CallLimits()}, targetOpts...)
	if o.perRPC != nil {
		dopts = append(dopts, grpc.WithPerRPCCredentials(o.perRPC))
	}
	dopts = append(dopts, o.extra...)
	conn, err := grpc.NewClient(target, dopts...)
	if err != nil {
		return nil, fmt.Errorf("client: coordinator address %q: %w", addr, err)
	}
	c := New(conn)
	c.owned = conn
	c.chunkLen = o.chunkLen
	return c, nil
}

// CallLimits lets calls on a connection send and receive messages as large as the
// contract allows (rules.RPC: a job's 10,000 tasks, a scene with large inline meshes);
// gRPC's default would refuse answers over 4 MiB. Dial sets it; give it to connections
// made elsewhere (the dashboard's).
func CallLimits() grpc.DialOption {
	n := int(rules.RPC.GetMaxMessageBytes())
	return grpc.WithDefaultCallOptions(grpc.MaxCallRecvMsgSize(n), grpc.MaxCallSendMsgSize(n))
}

// New returns a Client using an existing connection, which Close leaves open.
func New(conn grpc.ClientConnInterface) *Client {
	return &Client{
		conn:           conn,
		jobs:           pb.NewJobServiceClient(conn),
		blobs:          pb.NewBlobServiceClient(conn),
		chunkLen:       UploadChunkSize,
		watchResumeFor: watchResumeFor,
	}
}

// Close closes the connection if Dial made it.
func (c *Client) Close() error {
	if c.owned != nil {
		return c.owned.Close()
	}
	return nil
}

// Jobs returns the raw JobService client, for calls the SDK does not wrap.
func (c *Client) Jobs() pb.JobServiceClient { return c.jobs }

// Blobs returns the raw BlobService client.
func (c *Client) Blobs() pb.BlobServiceClient { return c.blobs }
