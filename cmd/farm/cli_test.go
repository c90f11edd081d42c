package main

import (
	"context"
	"os"
	"path/filepath"
	"strings"
	"testing"
	"time"

	"google.golang.org/protobuf/types/known/timestamppb"

	pb "photonfarm/proto/renderfarm/v1"
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

func TestRenderWithoutWorkerBinaryFails(t *testing.T) {
	dir := t.TempDir()
	path := filepath.Join(dir, "s.json")
	os.WriteFile(path, []byte(`{"name": "s"}`), 0o644)
	code, _, stderr := runForTest(t, nil, "render", path, "--worker-bin", filepath.Join(dir, "absent"))
	if code != exitUsage || !strings.Contains(stderr, "--worker-bin") {
		t.Errorf("exit %d, stderr %q", code, stderr)
	}
}

// fakeClock is a settable time.
type fakeClock struct{ t time.Time }

func (c *fakeClock) now() time.Time { return c.t }

func job(state pb.JobState, created time.Time, render, composite uint32) *pb.Job {
	return &pb.Job{
		Id: "j1", State: state, CreateTime: timestamppb.New(created),
		Phases: []*pb.PhaseProgress{
			{Phase: pb.Phase_PHASE_RENDER, TasksTotal: 48, TasksSucceeded: render},
			{Phase: pb.Phase_PHASE_COMPOSITE, TasksTotal: 1, TasksSucceeded: composite},
		},
	}
}

func TestProgressPlainLines(t *testing.T) {
	t0 := time.Date(2030, 1, 1, 0, 0, 0, 0, time.UTC)
	clk := &fakeClock{t0}
	var out strings.Builder
	p := newProgress(&out, false, clk.now)
	running := pb.JobState_JOB_STATE_RUNNING
	p.update(job(running, t0, 0, 0))
	clk.t = t0.Add(1 * time.Second)
	p.update(job(running, t0, 6, 0)) // within plainEvery of the last line: not printed
	clk.t = t0.Add(4 * time.Second)
	p.update(job(running, t0, 24, 0))
	clk.t = t0.Add(8 * time.Second)
	p.update(job(running, t0, 48, 0)) // a new phase is printed at once
	end := job(pb.JobState_JOB_STATE_SUCCEEDED, t0, 48, 1)
	end.EndTime = timestamppb.New(t0.Add(8500 * time.Millisecond))
	p.draw(true)
	p.observe(end)
	p.draw(true)

	want := []string{
		"job j1: Render tiles 0/48 tiles (0%), elapsed 0s",
		"job j1: Render tiles 24/48 tiles (50%), elapsed 4s, ETA 4s",
		"job j1: Composite 0/1 tasks (0%), elapsed 8s",
		"job j1: succeeded (render 48/48, composite 1/1), took 8.5s",
	}
	got := strings.Split(strings.TrimRight(out.String(), "\n"), "\n")
	if strings.Join(got, "\n") != strings.Join(want, "\n") {
		t.Errorf("got\n%s\nwant\n%s", strings.Join(got, "\n"), strings.Join(want, "\n"))
	}
}

func TestProgressBarRedrawsInPlace(t *testing.T) {
	t0 := time.Date(2030, 1, 1, 0, 0, 0, 0, time.UTC)
	clk := &fakeClock{t0}
	var out strings.Builder
	p := newProgress(&out, true, clk.now)
	p.update(job(pb.JobState_JOB_STATE_RUNNING, t0, 0, 0))
	clk.t = t0.Add(3 * time.Second)
	p.update(job(pb.JobState_JOB_STATE_RUNNING, t0, 12, 0))
	s := out.String()
	frames := strings.Split(s, "\r")[1:]
	if len(frames) != 2 || strings.Contains(s, "\n") {
		t.Fatalf("output %q: want two frames, each starting with \\r, no newline", s)
	}
	last := frames[1]
	for _, want := range []string{"Render tiles", "[######------------------]", "12/48", "tiles", "25%", "elapsed 0:03", "ETA 0:09"} {
		if !strings.Contains(last, want) {
			t.Errorf("frame %q lacks %q", last, want)
		}
	}

	end := job(pb.JobState_JOB_STATE_SUCCEEDED, t0, 48, 1)
	end.EndTime = timestamppb.New(t0.Add(5 * time.Second))
	clk.t = t0.Add(6 * time.Second)
	p.update(end)
	frames = strings.Split(out.String(), "\r")
	last = frames[len(frames)-1]
	for _, want := range []string{"succeeded", "48/48", "tiles", "100%", "elapsed 0:05"} {
		if !strings.Contains(last, want) {
			t.Errorf("final frame %q lacks %q", last, want)
		}
	}
	if strings.Contains(last, "ETA") {
		t.Errorf("final frame %q shows an ETA", last)
	}
}
