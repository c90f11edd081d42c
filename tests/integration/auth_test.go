package integration

import (
	"crypto/ecdsa"
	"crypto/elliptic"
	"crypto/rand"
	"crypto/x509"
	"crypto/x509/pkix"
	"encoding/pem"
	"math/big"
	"net"
	"os"
	"path/filepath"
	"strings"
	"testing"
	"time"

	"photonfarm/client"
	"photonfarm/tests/farmtest"
)

// TestWorkerNeedsTheWorkerToken runs a coordinator with tokens: a farm-worker without a
// token is refused at registration and exits 1 saying why; one with the worker token
// renders the job submitted with the client token.
func TestWorkerNeedsTheWorkerToken(t *testing.T) {
	f := farmtest.StartFarm(t, tokenFlags(t), client.WithToken(testClientToken))

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

// tokenFlags writes token files and returns the coordinator flags that name them.
func tokenFlags(t *testing.T) []string {
	dir := t.TempDir()
	clientFile, workerFile := filepath.Join(dir, "client-tokens"), filepath.Join(dir, "worker-tokens")
	os.WriteFile(clientFile, []byte("# clients\n"+testClientToken+"\n"), 0o600)
	os.WriteFile(workerFile, []byte(testWorkerToken+"\n"), 0o600)
	return []string{"--client-token-file", clientFile, "--worker-token-file", workerFile}
}

// TestWorkerOverTLS serves the coordinator over TLS with a self-signed certificate and
// tokens; the worker (grpc::SslCredentials) and the client trust it through --tls-ca and
// WithTLS.
func TestWorkerOverTLS(t *testing.T) {
	dir := t.TempDir()
	cert, key := selfSignedFiles(t, dir)
	f := farmtest.StartFarm(t, append(tokenFlags(t), "--tls-cert", cert, "--tls-key", key),
		client.WithTLS(cert), client.WithToken(testClientToken))
	w := f.StartWorkerWithCache(t, filepath.Join(t.TempDir(), "cache"), "--tls-ca", cert, "--token", testWorkerToken)
	w.WorkerID(t, 15*time.Second)
	f.Render(t, f.TestScene(t, 32, 32, 16, 1), 60*time.Second)
}

// selfSignedFiles writes a self-signed ECDSA certificate for 127.0.0.1 and localhost
// (cert.pem, also the CA to trust) and its key (key.pem) to dir.
func selfSignedFiles(t *testing.T, dir string) (certFile, keyFile string) {
	t.Helper()
	key, err := ecdsa.GenerateKey(elliptic.P256(), rand.Reader)
	if err != nil {
		t.Fatal(err)
	}
	tmpl := &x509.Certificate{
		SerialNumber: big.NewInt(1), Subject: pkix.Name{CommonName: "photonfarm test"},
		NotBefore: time.Now().Add(-time.Hour), NotAfter: time.Now().Add(time.Hour),
		KeyUsage:    x509.KeyUsageDigitalSignature | x509.KeyUsageCertSign,
		ExtKeyUsage: []x509.ExtKeyUsage{x509.ExtKeyUsageServerAuth}, BasicConstraintsValid: true, IsCA: true,
		IPAddresses: []net.IP{net.ParseIP("127.0.0.1")}, DNSNames: []string{"localhost"},
	}
	der, err := x509.CreateCertificate(rand.Reader, tmpl, tmpl, &key.PublicKey, key)
	if err != nil {
		t.Fatal(err)
	}
	keyDER, err := x509.MarshalECPrivateKey(key)
	if err != nil {
		t.Fatal(err)
	}
	certFile, keyFile = filepath.Join(dir, "cert.pem"), filepath.Join(dir, "key.pem")
	os.WriteFile(certFile, pem.EncodeToMemory(&pem.Block{Type: "CERTIFICATE", Bytes: der}), 0o600)
	os.WriteFile(keyFile, pem.EncodeToMemory(&pem.Block{Type: "EC PRIVATE KEY", Bytes: keyDER}), 0o600)
	return certFile, keyFile
}
