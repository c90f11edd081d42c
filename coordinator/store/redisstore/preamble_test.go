package redisstore

import (
	"context"
	"fmt"
	"testing"

	"github.com/redis/go-redis/v9"

	"photonfarm/coordinator/store/redisstore/redistest"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestPreambleStatesAndKeysAreGos runs the preamble on a real Redis and reads back what
// the scripts see: every task and job state number and name, and every key name, must be
// what Go uses.
func TestPreambleStatesAndKeysAreGos(t *testing.T) {
	rdb := redistest.Start(t).Client()
	s := &Store{prefix: "pre:"}
	probe := redis.NewScript(preamble + `
return {WAITING, QUEUED, LEASED, SUCCEEDED, FAILED, CANCELLED, TASK_STATES[LEASED],
  JQUEUED, JRUNNING, JSUCCEEDED, JFAILED, JCANCELLED, JOB_STATES[JFAILED],
  JOBS, jkey('j-1'), rkey('j-1'), tkey('j-1.3'), qkey('j-1', 5)}`)
	v, err := probe.Run(context.Background(), rdb, []string{"pre:jobs"}, s.prefix, "0").Result()
	if err != nil {
		t.Fatal(err)
	}
	got := fmt.Sprint(v)
	want := fmt.Sprint([]any{
		int64(pb.TaskState_TASK_STATE_WAITING), int64(pb.TaskState_TASK_STATE_QUEUED), int64(pb.TaskState_TASK_STATE_LEASED),
		int64(pb.TaskState_TASK_STATE_SUCCEEDED), int64(pb.TaskState_TASK_STATE_FAILED), int64(pb.TaskState_TASK_STATE_CANCELLED), "LEASED",
		int64(pb.JobState_JOB_STATE_QUEUED), int64(pb.JobState_JOB_STATE_RUNNING), int64(pb.JobState_JOB_STATE_SUCCEEDED),
		int64(pb.JobState_JOB_STATE_FAILED), int64(pb.JobState_JOB_STATE_CANCELLED), "FAILED",
		s.key(jobsKey), s.jobKey("j-1"), s.roundsKey("j-1"), s.taskKey("j-1.3"), s.key(queuePrefix + "j-1" + queueSeparator + "5"),
	})
	if got != want {
		t.Errorf("the scripts see\n%s\nGo has\n%s", got, want)
	}
}
