package main

import (
	"bytes"
	"io"
	"log/slog"
	"net"
	"os"
	"path/filepath"
	"slices"
	"strings"
	"testing"
	"time"
)

func TestLoadTokens(t *testing.T) {
	file := filepath.Join(t.TempDir(), "tokens")
	os.WriteFile(file, []byte("# farm clients\nalpha\n\n  beta  \n# gamma\n"), 0o600)
	got, err := loadTokens(file, "one, two,,")
	if err != nil || !slices.Equal(got, []string{"one", "two", "alpha", "beta"}) {
		t.Errorf("loadTokens = %q, %v", got, err)
	}
	os.WriteFile(file, []byte("# only a comment\n\n"), 0o600)
	if _, err := loadTokens(file, ""); err == nil || !strings.Contains(err.Error(), "holds no token") {
		t.Errorf("a token file without tokens: %v, want an error (it must not turn auth off)", err)
	}
	if got, err := loadTokens("", ""); err != nil || len(got) != 0 {
		t.Errorf("no file, no variable: %q, %v", got, err)
	}
}

func TestCoordinatorSecurityFlagErrors(t *testing.T) {
	dir := t.TempDir()
	empty := filepath.Join(dir, "empty")
	os.WriteFile(empty, nil, 0o600)
	for _, args := range [][]string{
		{"--tls-cert", filepath.Join(dir, "c.pem")},
		{"--tls-key", filepath.Join(dir, "k.pem")},
		{"--tls-cert", filepath.Join(dir, "c.pem"), "--tls-key", filepath.Join(dir, "k.pem")},
		{"--client-token-file", filepath.Join(dir, "absent")},
		{"--worker-token-file", empty},
	} {
		args = append([]string{"coordinator", "--listen", "127.0.0.1:0", "--data-dir", dir}, args...)
		if code, _, stderr := runForTest(t, nil, args...); code != exitUsage || strings.Count(stderr, "\n") != 1 {
			t.Errorf("farm %q: exit %d, stderr %q; want exit 2 and one line", args, code, stderr)
		}
	}
}

func TestSecurityWarnings(t *testing.T) {
	var loud, logged bytes.Buffer
	log := slog.New(slog.NewTextHandler(&logged, nil))
	warnAboutSecurity(&loud, log, &net.TCPAddr{IP: net.IPv4zero, Port: 7070}, 0, 0, false)
	if !strings.Contains(loud.String(), "WARNING: authentication is OFF") {
		t.Errorf("auth off on 0.0.0.0: stderr %q, want a loud warning", loud.String())
	}
	loud.Reset()
	warnAboutSecurity(&loud, log, &net.TCPAddr{IP: net.IPv4(127, 0, 0, 1), Port: 7070}, 0, 0, false)
	if loud.Len() != 0 || !strings.Contains(logged.String(), "authentication is off") {
		t.Errorf("auth off on loopback: stderr %q, log %q; want a logged warning only", loud.String(), logged.String())
	}
	logged.Reset()
	warnAboutSecurity(&loud, log, &net.TCPAddr{IP: net.IPv4zero, Port: 7070}, 1, 1, false)
	if loud.Len() != 0 || !strings.Contains(logged.String(), "plaintext") {
		t.Errorf("tokens without TLS: stderr %q, log %q", loud.String(), logged.String())
	}
}

// TestClientVerbsSendTheToken runs the CLI against an in-process coordinator with tokens.
func TestClientVerbsSendTheToken(t *testing.T) {
	ec, err := startEmbedded(t.TempDir(), time.Second, io.Discard, "the-client-token", "the-worker-token")
	if err != nil {
		t.Fatal(err)
	}
	defer ec.stop(5 * time.Second)
	for _, tc := range []struct {
		name string
		vars map[string]string
		args []string
		code int
		want string
	}{
		{"no token", nil, nil, exitFailure, "--token or $FARM_TOKEN"},
		{"unknown token", map[string]string{"FARM_TOKEN": "not-a-token"}, nil, exitFailure, "(give a client token with --token or $FARM_TOKEN)"},
		{"token flag", nil, []string{"--token", "the-client-token"}, exitOK, ""},
		{"token variable", map[string]string{"FARM_TOKEN": "the-client-token"}, nil, exitOK, ""},
		{"worker token", nil, []string{"--token", "the-worker-token"}, exitFailure,
			"it needs a client token) (farm's verbs need one of the coordinator's client tokens, from its --client-token-file or $FARM_CLIENT_TOKENS, in --token or $FARM_TOKEN)"},
	} {
		t.Run(tc.name, func(t *testing.T) {
			args := append([]string{"list", "--coordinator", ec.addr}, tc.args...)
			code, _, stderr := runForTest(t, tc.vars, args...)
			if code != tc.code || !strings.Contains(stderr, tc.want) {
				t.Errorf("farm %q: exit %d, stderr %q; want exit %d and %q", args, code, stderr, tc.code, tc.want)
			}
		})
	}
}

func TestPlaintextTokenToAnotherMachineIsRefused(t *testing.T) {
	code, _, stderr := runForTest(t, map[string]string{"FARM_TOKEN": "t"}, "list", "--coordinator", "farm.example:7070")
	if code != exitUsage || !strings.Contains(stderr, "--tls-ca") || !strings.Contains(stderr, "--insecure") {
		t.Errorf("exit %d, stderr %q; want exit 2 naming --tls-ca and --insecure", code, stderr)
	}
}

func TestSubmitRefusesAMeshOutsideTheAssetRoot(t *testing.T) {
	root := t.TempDir()
	scenes := filepath.Join(root, "scenes")
	os.MkdirAll(scenes, 0o755)
	os.WriteFile(filepath.Join(root, "x.obj"), []byte("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), 0o644)
	path := filepath.Join(scenes, "s.json")
	os.WriteFile(path, []byte(`{"shapes": [{"mesh": {"path": "../x.obj"}}]}`), 0o644)
	code, _, stderr := runForTest(t, nil, "plan", path)
	if code != exitUsage || !strings.Contains(stderr, `shapes[0].mesh.path: "../x.obj" is outside the asset root `+scenes) {
		t.Errorf("exit %d, stderr %q", code, stderr)
	}
	// With the parent as the root the file is fine, and the scene's own rules are what
	// fail (it has no camera).
	code, _, stderr = runForTest(t, nil, "plan", path, "--asset-root", root)
	if code != exitUsage || strings.Contains(stderr, "asset root") || !strings.HasPrefix(stderr, "farm: "+path+": ") {
		t.Errorf("with --asset-root: exit %d, stderr %q", code, stderr)
	}
}
