package main

import (
	"io"
	"regexp"
	"strings"
	"testing"
	"time"
)

// TestPriorityAndUnblockVerbs runs submit --priority, priority, status, list and unblock
// against an in-process coordinator.
func TestPriorityAndUnblockVerbs(t *testing.T) {
	vars, job := embeddedWithJob(t, "--priority", "7")
	for _, tc := range []struct {
		args []string
		code int
		want string // a regular expression the output (stdout, then stderr) must match
	}{
		{[]string{"status", job}, exitOK, `(?m)^priority\s+7$`},
		{[]string{"priority", job, "-5"}, exitOK, "^job " + job + " priority -5\n$"},
		{[]string{"priority", "--", job, "3"}, exitOK, "priority 3\n$"},
		{[]string{"list"}, exitOK, `(?m)^` + job + `\s+\S+\s+queued\s+3\s`},
		{[]string{"priority", job, "2000"}, exitUsage, "priority"},
		{[]string{"priority", job, "high"}, exitUsage, "N must be an integer"},
		{[]string{"priority", job}, exitUsage, "wrong number of arguments"},
		{[]string{"priority", "j-nope", "1"}, exitFailure, "j-nope"},
		{[]string{"unblock", job}, exitOK, "^job " + job + ": 0 blocked workers\n$"},
		{[]string{"unblock", job, "w-1"}, exitOK, "0 blocked workers"},
		{[]string{"unblock", "j-nope"}, exitFailure, "j-nope"},
		{[]string{"submit", "../../scenes/test-small.json", "--priority", "-1001"}, exitUsage, "priority"},
	} {
		code, stdout, stderr := runForTest(t, vars, tc.args...)
		if code != tc.code || !regexp.MustCompile(tc.want).MatchString(stdout+stderr) {
			t.Errorf("farm %q: exit %d, stdout %q, stderr %q; want exit %d matching %q", tc.args, code, stdout, stderr, tc.code, tc.want)
		}
	}
}

// embeddedWithJob starts an in-process coordinator (no worker: jobs stay queued) for the
// test and submits scenes/test-small.json to it with the flags submit; it returns the
// environment of client verbs and the job id.
func embeddedWithJob(t *testing.T, submit ...string) (vars map[string]string, job string) {
	t.Helper()
	ec, err := startEmbedded(t.TempDir(), time.Minute, io.Discard, "client-token", "worker-token")
	if err != nil {
		t.Fatal(err)
	}
	t.Cleanup(func() { ec.stop(5 * time.Second) })
	vars = map[string]string{"FARM_TOKEN": "client-token", "FARM_COORDINATOR": ec.addr}
	code, stdout, stderr := runForTest(t, vars, append([]string{"submit", "../../scenes/test-small.json"}, submit...)...)
	if code != exitOK {
		t.Fatalf("submit: exit %d, stderr %q", code, stderr)
	}
	return vars, strings.TrimSpace(stdout)
}
