package main

import (
	"regexp"
	"testing"
)

// TestRequeueRetryAndDeleteVerbs runs cancel, requeue, retry and delete against an
// in-process coordinator (no worker: the job stays queued).
func TestRequeueRetryAndDeleteVerbs(t *testing.T) {
	vars, job := embeddedWithJob(t)
	for _, tc := range []struct {
		args []string
		code int
		want string // a regular expression the output (stdout, then stderr) must match
	}{
		{[]string{"requeue", job}, exitFailure, "has not ended"},
		{[]string{"cancel", job}, exitOK, "cancelled"},
		{[]string{"requeue", job}, exitOK, "^job " + job + " queued\n$"},
		{[]string{"status", job}, exitOK, `(?m)^state\s+queued$`},
		{[]string{"retry", job + ".0"}, exitFailure, "not failed"},
		{[]string{"retry", job}, exitUsage, "task_id: is not a task id"},
		{[]string{"retry", job + ".0", "extra"}, exitUsage, "retry"},
		{[]string{"requeu", job}, exitUsage, `did you mean "requeue"`},
		{[]string{"delete", job}, exitOK, "^job " + job + " deleted \\(was cancelled\\)\n$"},
		{[]string{"status", job}, exitFailure, job},
		{[]string{"delete", job}, exitFailure, job},
		{[]string{"list"}, exitOK, "^[^j]*$"},
	} {
		code, stdout, stderr := runForTest(t, vars, tc.args...)
		if code != tc.code || !regexp.MustCompile(tc.want).MatchString(stdout+stderr) {
			t.Errorf("farm %q: exit %d, stdout %q, stderr %q; want exit %d matching %q", tc.args, code, stdout, stderr, tc.code, tc.want)
		}
	}
}
