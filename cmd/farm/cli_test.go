package main

import (
	"context"
	"os"
	"path/filepath"
	"strings"
	"testing"
	"time"

	"photonfarm/tests/farmtest"
)

func runForTest(t *testing.T, vars map[string]string, args ...string) (code int, stdout, stderr string) {
	t.Helper()
	var out, errb strings.Builder
	e := &env{stdout: &out, stderr: &errb, getenv: func(k string) string { return vars[k] }}
	code = run(context.Background(), args, e)
	return code, out.String(), errb.String()
}

func TestUsageErrorsExitTwoWithOneLine(t *testing.T) {
	for _, args := range [][]string{
		{},
		{"frobnicate"},
		{"submit"},
		{"submit", "a.json", "b.json"},
		{"submit", "a.json", "--no-such-flag"},
		{"render", "a.json", "--workers", "0"},
		{"render", "a.json", "--exposure", "21"},
		{"render", "a.json", "--exposure", "bright"},
		{"fetch"},
		{"help", "nope"},
	} {
		code, _, stderr := runForTest(t, nil, args...)
		if code != exitUsage {
			t.Errorf("farm %q: exit %d, want %d", args, code, exitUsage)
		}
		if len(args) > 0 && strings.Count(stderr, "\n") != 1 {
			t.Errorf("farm %q: stderr %q, want one line", args, stderr)
		}
	}
}

func TestHelpListsEveryVerb(t *testing.T) {
	code, stdout, _ := runForTest(t, nil, "help")
	if code != 0 {
		t.Fatalf("exit %d", code)
	}
	for _, v := range verbs {
		if !strings.Contains(stdout, "  "+v.name) {
			t.Errorf("help does not list %s", v.name)
		}
		code, out, _ := runForTest(t, nil, v.name, "-h")
		if code != 0 || !strings.HasPrefix(out, "usage: farm "+v.name) {
			t.Errorf("farm %s -h: exit %d, output %q", v.name, code, out)
		}
	}
}

func TestFlagsMayFollowArguments(t *testing.T) {
	fs := newFlags("fetch", &env{stdout: &strings.Builder{}})
	out := fs.String("o", ".", "")
	pos, err := parse(fs, []string{"job-1", "-o", "dir"}, 1, 1)
	if err != nil || len(pos) != 1 || pos[0] != "job-1" || *out != "dir" {
		t.Fatalf("parse = %v, %v, -o %q", pos, err, *out)
	}
}

func TestCoordinatorAddress(t *testing.T) {
	for _, tc := range []struct {
		env  map[string]string
		args []string
		want string
	}{
		{nil, nil, "localhost:7070"},
		{map[string]string{"FARM_COORDINATOR": "farm:1"}, nil, "farm:1"},
		{map[string]string{"FARM_COORDINATOR": "farm:1"}, []string{"--coordinator", "other:2"}, "other:2"},
	} {
		e := &env{stdout: &strings.Builder{}, getenv: func(k string) string { return tc.env[k] }}
		fs := newFlags("status", e)
		addr := coordinatorFlag(fs, e)
		if _, err := parse(fs, append(tc.args, "job"), 1, 1); err != nil {
			t.Fatal(err)
		}
		if got := addr(); got != tc.want {
			t.Errorf("env %v args %v: address %q, want %q", tc.env, tc.args, got, tc.want)
		}
	}
}

// closedAddress is a loopback address where nothing listens.
func closedAddress(t *testing.T) string { return farmtest.ClosedAddress(t) }

func TestSubmitReportsSceneErrorsBeforeTheNetwork(t *testing.T) {
	dir := t.TempDir()
	path := filepath.Join(dir, "s.json")
	os.WriteFile(path, []byte(`{"shapes": [{}, {}, {}, {"mesh": {"path": "meshes/x.obj"}}]}`), 0o644)
	code, stdout, stderr := runForTest(t, nil, "submit", path, "--coordinator", closedAddress(t))
	want := "farm: shapes[3].mesh.path: open meshes/x.obj: no such file or directory\n"
	if code != exitUsage || stderr != want || stdout != "" {
		t.Errorf("exit %d, stdout %q, stderr %q; want exit 2 and %q", code, stdout, stderr, want)
	}
}

func TestUnreachableCoordinatorExitsOne(t *testing.T) {
	code, _, stderr := runForTest(t, nil, "status", "job-1", "--coordinator", closedAddress(t))
	if code != exitFailure || !strings.Contains(stderr, "coordinator unavailable") || strings.Count(stderr, "\n") != 1 {
		t.Errorf("exit %d, stderr %q", code, stderr)
	}
}

// TestRenderChecksTheOutputFolderFirst: an -o that names a file, or a folder that cannot
// be made, is refused at once, before a farm starts (the worker binary would do nothing).
func TestRenderChecksTheOutputFolderFirst(t *testing.T) {
	dir := t.TempDir()
	path := filepath.Join(dir, "s.json")
	os.WriteFile(path, []byte(`{"name": "s"}`), 0o644)
	file := filepath.Join(dir, "out.png")
	os.WriteFile(file, []byte("not a folder"), 0o644)
	for _, out := range []string{file, filepath.Join(file, "sub")} {
		start := time.Now()
		code, _, stderr := runForTest(t, nil, "render", path, "-o", out, "--worker-bin", "/bin/true", "--no-dashboard")
		if code != exitUsage || !strings.Contains(stderr, "-o") || strings.Count(stderr, "\n") != 1 {
			t.Errorf("-o %s: exit %d, stderr %q; want exit 2 and one line naming -o", out, code, stderr)
		}
		if took := time.Since(start); took > 5*time.Second {
			t.Errorf("-o %s: refused after %v, want at once", out, took)
		}
	}
	if b, _ := os.ReadFile(file); string(b) != "not a folder" {
		t.Errorf("the file named by -o changed: %q", b)
	}
}

func TestRenderWithoutWorkerBinaryFails(t *testing.T) {
	dir := t.TempDir()
	path := filepath.Join(dir, "s.json")
	os.WriteFile(path, []byte(`{"name": "s"}`), 0o644)
	code, _, stderr := runForTest(t, nil, "render", path, "--worker-bin", filepath.Join(dir, "absent"))
	if code != exitUsage || !strings.Contains(stderr, "--worker-bin") {
		t.Errorf("exit %d, stderr %q", code, stderr)
	}
}
