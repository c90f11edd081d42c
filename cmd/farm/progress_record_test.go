package main

import (
	"bytes"
	"compress/gzip"
	"os"
	"path/filepath"
	"testing"
	"time"

	"google.golang.org/protobuf/encoding/protojson"

	"photonfarm/client"
	"photonfarm/coordinator"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// sixRoundEvents is a real job's event stream: the Cornell box at 128² in 6 progressive rounds
// on a local farm of 2 workers, one thread each, every WatchJob event as one line of
// protobuf JSON, gzipped. TestRecordSixRoundEvents writes it.
const sixRoundEvents = "testdata/cornell-6-rounds.events.jsonl.gz"

// TestRecordSixRoundEvents renders the recording's job on a real local farm and writes
// sixRoundEvents, when FARM_RECORD_EVENTS=1 (with FARM_BIN_DIR naming the built
// binaries):
//
//	FARM_RECORD_EVENTS=1 FARM_BIN_DIR=$PWD/build/bin go test ./cmd/farm -run TestRecordSixRoundEvents
func TestRecordSixRoundEvents(t *testing.T) {
	if os.Getenv("FARM_RECORD_EVENTS") != "1" {
		t.Skip("writes " + sixRoundEvents + " from a real farm: set FARM_RECORD_EVENTS=1 and FARM_BIN_DIR")
	}
	farm, err := startLocalFarm(filepath.Join(farmtest.BinDir(t), workerBinName), 2, 1, coordinator.DefaultLeaseDuration)
	if err != nil {
		t.Fatal(err)
	}
	defer farm.stop()
	c, err := client.Dial(farm.coord.addr, client.WithToken(farm.clientToken))
	if err != nil {
		t.Fatal(err)
	}
	defer c.Close()
	sf, err := client.ReadSceneFile(t.Context(), filepath.Join(farmtest.RepoRoot(), "scenes", "cornell-box.json"))
	if err != nil {
		t.Fatal(err)
	}
	// 16 tiles a round instead of 256, for a fixture of a few hundred events.
	sf.Scene.Progressive = &pb.Progressive{MaxRounds: 6}
	sf.Scene.Film.Width, sf.Scene.Film.Height = 128, 128
	if err := c.Upload(t.Context(), sf); err != nil {
		t.Fatal(err)
	}
	job, err := c.Submit(t.Context(), sf.Scene)
	if err != nil {
		t.Fatal(err)
	}
	var lines bytes.Buffer
	zw := gzip.NewWriter(&lines)
	start := time.Now()
	last, err := c.Watch(t.Context(), job.GetId(), func(ev *pb.WatchJobResponse) {
		b, err := protojson.Marshal(ev)
		if err != nil {
			t.Fatal(err)
		}
		zw.Write(append(b, '\n'))
	})
	if err != nil || last.GetState() != pb.JobState_JOB_STATE_SUCCEEDED || len(last.GetRounds()) != 6 {
		t.Fatalf("job ended %v after %d rounds: %v", last.GetState(), len(last.GetRounds()), err)
	}
	if err := zw.Close(); err != nil {
		t.Fatal(err)
	}
	if err := os.WriteFile(sixRoundEvents, lines.Bytes(), 0o644); err != nil {
		t.Fatal(err)
	}
	t.Logf("%s: %d bytes, the job took %v", sixRoundEvents, lines.Len(), time.Since(start))
}
