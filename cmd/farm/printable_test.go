package main

import (
	"context"
	"strings"
	"testing"
	"time"

	"photonfarm/client"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator"
	"photonfarm/coordinator/coordinatortest"
	pb "photonfarm/proto/renderfarm/v1"
)

func TestPrintable(t *testing.T) {
	for in, want := range map[string]string{
		"cornell-box":           "cornell-box",
		"Ünïcødé · 渲染":          "Ünïcødé · 渲染",
		"\x1b[2J\x1b[H":         `\x1b[2J\x1b[H`,
		"done\rsucceeded":       `done\rsucceeded`,
		"a\nb\tc\x7f":           `a\nb\tc\x7f`,
		"\u009b31m":             `\x9b31m`,
		"abc\u202edcba":         `abc\u202edcba`,
		"zero\u200bwidth":       `zero\u200bwidth`,
		"soft\u00adhyphen":      "soft\u00adhyphen",
		"bad \xff\xfe bytes":    `bad \xff\xfe bytes`,
		"title\x1b]0;pwned\x07": `title\x1b]0;pwned\a`,
	} {
		if got := printable(in); got != want {
			t.Errorf("printable(%q) = %q, want %q", in, got, want)
		}
	}
	if got := oneLine("first line\n\tsecond \x1b[1A line"); got != `first line second \x1b[1A line` {
		t.Errorf("oneLine = %q", got)
	}
}

// TestListStatusAndTasksPrintNoTerminalControls stores a job whose scene name, task error
// and artifact name carry terminal escape sequences, carriage returns and a forged
// line, as a hostile client and worker can: farm list, status and tasks must print none
// of those characters, and no more lines than they have rows.
func TestListStatusAndTasksPrintNoTerminalControls(t *testing.T) {
	srv := coordinatortest.Serve(t, coordinator.Config{LeaseDuration: time.Minute})
	ctx, cancel := context.WithTimeout(context.Background(), 30*time.Second)
	defer cancel()
	c, err := client.Dial(srv.Addr)
	if err != nil {
		t.Fatal(err)
	}
	defer c.Close()
	const forged = "\x1b[2J\x1b[Hj-0000000000000000  forged  succeeded\n\r"
	sc := scenetest.Unlit(64, 16) // two tiles and a composite
	sc.Name = "scene" + forged
	job, err := c.Submit(ctx, sc)
	if err != nil {
		t.Fatal(err)
	}
	w := pb.NewWorkerServiceClient(srv.Dial(t, client.WorkerSecrets()))
	reg, err := w.RegisterWorker(ctx, &pb.RegisterWorkerRequest{Hostname: "hostile"})
	if err != nil {
		t.Fatal(err)
	}
	lease := func() *pb.Lease {
		l, err := w.LeaseTask(ctx, &pb.LeaseTaskRequest{WorkerId: reg.GetWorkerId()})
		if err != nil || l.GetLease() == nil {
			t.Fatalf("LeaseTask = %v, %v", l, err)
		}
		return l.GetLease()
	}
	l := lease()
	if _, err := w.FailTask(ctx, &pb.FailTaskRequest{WorkerId: reg.GetWorkerId(), TaskId: l.GetTaskId(), Epoch: l.GetEpoch(),
		Error: "boom\x1b]0;owned\x07" + forged, Kind: pb.FailureKind_FAILURE_KIND_TRANSIENT}); err != nil {
		t.Fatal(err)
	}
	l = lease() // the other tile
	digest, err := c.UploadBytes(ctx, []byte("a tile"))
	if err != nil {
		t.Fatal(err)
	}
	if _, err := w.CompleteTask(ctx, &pb.CompleteTaskRequest{WorkerId: reg.GetWorkerId(), TaskId: l.GetTaskId(), Epoch: l.GetEpoch(),
		Outputs: []*pb.Artifact{{Name: "tile\x1b[8m.exr" + forged, Digest: digest, SizeBytes: 6}}}); err != nil {
		t.Fatal(err)
	}

	for _, tc := range []struct {
		args  []string
		lines int // at most
	}{
		{[]string{"list"}, 2},
		{[]string{"status", job.GetId()}, 12},
		{[]string{"tasks", job.GetId()}, 4},
	} {
		code, stdout, stderr := runForTest(t, nil, append(tc.args, "--coordinator", srv.Addr)...)
		if code != exitOK {
			t.Fatalf("farm %s: exit %d, %s", tc.args[0], code, stderr)
		}
		if i := strings.IndexFunc(stdout, func(r rune) bool { return r != '\n' && unsafeRune(r) }); i >= 0 {
			t.Errorf("farm %s printed %q at byte %d:\n%q", tc.args[0], stdout[i], i, stdout)
		}
		if n := strings.Count(stdout, "\n"); n > tc.lines || strings.Contains(stdout, "\nj-0000000000000000") {
			t.Errorf("farm %s printed %d lines (at most %d), or a forged one:\n%s", tc.args[0], n, tc.lines, stdout)
		}
		if !strings.Contains(stdout, `\x1b[2J`) {
			t.Errorf("farm %s does not show the escape sequence as text:\n%s", tc.args[0], stdout)
		}
	}
}
