package integration

import (
	"testing"
	"time"

	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/tests/farmtest"
)

// The coordinator killed mid-job on Redis is tested in tests/fault, in every phase.

func TestJobAcceptedBeforeARedisRestartCompletesAfterIt(t *testing.T) {
	rs := redistest.Start(t, redistest.AppendOnly())
	f := farmtest.StartFarm(t, []string{"--redis", "redis://" + rs.Addr(), "--redis-prefix", "it:"})
	sc := f.TestScene(t, 32, 32, 16, 1)
	job := f.Submit(t, sc) // no worker yet: the job waits, queued, in Redis
	rs.Restart()
	f.StartWorker(t)
	done := f.Wait(t, job.GetId(), 120*time.Second)
	if len(f.Output(t, done, "image.exr")) == 0 {
		t.Fatal("no image")
	}
}
