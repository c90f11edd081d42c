package integration

import (
	"context"
	"os"
	"path/filepath"
	"strings"
	"syscall"
	"testing"
	"time"

	"photonfarm/client"
	"photonfarm/coordinator/tlstest"
	"photonfarm/tests/farmtest"
)

// TestWorkerNeedsTheWorkerToken runs a coordinator with tokens: a farm-worker without a
// token is refused at registration and exits 1 saying why; one with the worker token
// renders the job submitted with the client token.
func TestWorkerNeedsTheWorkerToken(t *testing.T) {
	f := farmtest.StartFarm(t, farmtest.TokenFlags(t, testClientToken, testWorkerToken), client.WithToken(testClientToken))

	anonymous := f.StartWorker(t)
	select {
	case <-anonymous.Done():
	case <-time.After(15 * time.Second):
		t.Fatal("a farm-worker without a token is still running after 15 s")
	}
	log, _ := os.ReadFile(anonymous.LogPath)
	if anonymous.ExitCode() != 1 || !strings.Contains(string(log), "refused registration") ||
		!strings.Contains(string(log), "no token") || !strings.Contains(string(log), "--token") {
		t.Errorf("worker without a token: exit %d, log:\n%s\nwant exit 1 and a refusal that names --token",
			anonymous.ExitCode(), log)
	}

	w := f.StartWorkerWithCache(t, filepath.Join(t.TempDir(), "cache"), "--token", testWorkerToken)
	w.WorkerID(t, 15*time.Second)
	f.Render(t, f.TestScene(t, 32, 32, 16, 1), 60*time.Second)
}

const (
	testClientToken = "client-token-for-the-test"
	testWorkerToken = "worker-token-for-the-test"
)

// TestWorkerOverTLS serves the coordinator over TLS with a self-signed certificate and
// tokens; the worker (grpc::SslCredentials) and the client trust it through --tls-ca and
// WithTLS.
func TestWorkerOverTLS(t *testing.T) {
	dir := t.TempDir()
	tc := tlstest.SelfSigned(t, dir)
	cert, key := tc.CertFile, tc.KeyFile
	f := farmtest.StartFarm(t, append(farmtest.TokenFlags(t, testClientToken, testWorkerToken), "--tls-cert", cert, "--tls-key", key),
		client.WithTLS(cert), client.WithToken(testClientToken))
	w := f.StartWorkerWithCache(t, filepath.Join(t.TempDir(), "cache"), "--tls-ca", cert, "--token", testWorkerToken)
	w.WorkerID(t, 15*time.Second)
	f.Render(t, f.TestScene(t, 32, 32, 16, 1), 60*time.Second)

	// Given as one of a list of replicas (the other one dead), over TLS too: every
	// connection is checked against the first address, which the certificate names.
	list := f.Addr + "," + farmtest.ClosedAddress(t)
	c, err := client.Dial(list, client.WithTLS(cert), client.WithToken(testClientToken))
	if err != nil {
		t.Fatal(err)
	}
	defer c.Close()
	w.Kill(syscall.SIGTERM)
	<-w.Done()
	listed := f.StartWorkerWithCache(t, filepath.Join(t.TempDir(), "cache"), "--coordinator", list, "--tls-ca", cert, "--token", testWorkerToken)
	listed.WorkerID(t, 15*time.Second)
	job, err := c.Submit(context.Background(), f.TestScene(t, 32, 32, 16, 1))
	if err != nil {
		t.Fatalf("submit through a list of replicas over TLS: %v", err)
	}
	f.Wait(t, job.GetId(), 60*time.Second)
}
