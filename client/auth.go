package client

import (
	"context"
	"crypto/tls"
	"crypto/x509"
	"errors"
	"fmt"
	"net"
	"os"
	"strings"

	"google.golang.org/grpc/credentials"
	"google.golang.org/grpc/metadata"
)

// ErrPlaintextToken is returned by Dial when a token would travel unencrypted to an
// address that is not loopback; use WithTLS, or AllowPlaintextToken on a trusted network.
var ErrPlaintextToken = errors.New("refusing to send a token without TLS to a non-loopback address")

// WithToken sends token on every call as the gRPC metadata "authorization: Bearer TOKEN"
// (a client token for JobService, a worker token for WorkerService; either for
// BlobService). An empty token sends nothing. Without TLS, Dial accepts a token only for a
// loopback address (localhost, 127.0.0.0/8, ::1, unix sockets) unless AllowPlaintextToken
// is given too.
func WithToken(token string) Option {
	return func(o *dialOptions) { o.token = token }
}

// AllowPlaintextToken lets Dial send a token without TLS to any address. Anyone on the path
// can then read the token; use it only on a trusted network.
func AllowPlaintextToken() Option {
	return func(o *dialOptions) { o.allowPlaintext = true }
}

// WithTLS connects over TLS, trusting the CA certificates in the PEM file caFile (the
// system's roots if caFile is empty). The server's certificate must name the host in the
// address.
func WithTLS(caFile string) Option {
	return func(o *dialOptions) {
		cfg := &tls.Config{MinVersion: tls.VersionTLS12}
		if caFile != "" {
			pool, err := LoadCertPool(caFile)
			if err != nil {
				o.err = err
				return
			}
			cfg.RootCAs = pool
		}
		o.creds = credentials.NewTLS(cfg)
		o.secure = true
	}
}

// LoadCertPool reads the PEM certificates in file into a pool.
func LoadCertPool(file string) (*x509.CertPool, error) {
	pem, err := os.ReadFile(file)
	if err != nil {
		return nil, fmt.Errorf("client: TLS CA file: %w", err)
	}
	pool := x509.NewCertPool()
	if !pool.AppendCertsFromPEM(pem) {
		return nil, fmt.Errorf("client: TLS CA file %s: no PEM certificate in it", file)
	}
	return pool, nil
}

// authorizationKey is the gRPC metadata key of the token, whose value is bearer(token).
const authorizationKey = "authorization"

func bearer(token string) string { return "Bearer " + token }

// ContextWithToken returns ctx carrying token for the calls made with it ("" sends none),
// for callers of the raw gRPC stubs: the dashboard forwards each browser's token so, and
// tests call as a worker so. A Client sends its token itself (WithToken).
func ContextWithToken(ctx context.Context, token string) context.Context {
	if token == "" {
		return ctx
	}
	return metadata.AppendToOutgoingContext(ctx, authorizationKey, bearer(token))
}

// bearerToken is per-RPC credentials carrying a bearer token.
type bearerToken struct {
	token      string
	requireTLS bool
}

func (b bearerToken) GetRequestMetadata(context.Context, ...string) (map[string]string, error) {
	return map[string]string{authorizationKey: bearer(b.token)}, nil
}

func (b bearerToken) RequireTransportSecurity() bool { return b.requireTLS }

// IsLoopback reports whether the gRPC target addr ("host:port", "dns:///host:port",
// "unix:path", or a comma list of "host:port" replicas, each of them) names this machine without leaving it: localhost, a loopback IP or a unix
// socket. Names are not resolved.
func IsLoopback(addr string) bool {
	if addrs, err := addresses(addr); err == nil && len(addrs) > 1 {
		for _, a := range addrs {
			if !IsLoopback(a) {
				return false
			}
		}
		return true
	}
	if strings.HasPrefix(addr, "unix:") || strings.HasPrefix(addr, "unix-abstract:") {
		return true
	}
	for _, scheme := range []string{"dns:///", "passthrough:///"} {
		addr = strings.TrimPrefix(addr, scheme)
	}
	host, _, err := net.SplitHostPort(addr)
	if err != nil {
		host = addr
	}
	host = strings.Trim(host, "[]")
	if strings.EqualFold(host, "localhost") || strings.HasSuffix(strings.ToLower(host), ".localhost") {
		return true
	}
	ip := net.ParseIP(host)
	return ip != nil && ip.IsLoopback()
}
