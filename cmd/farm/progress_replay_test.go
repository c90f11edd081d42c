package main

import (
	"bufio"
	"compress/gzip"
	"os"
	"regexp"
	"strconv"
	"strings"
	"testing"
	"time"

	"google.golang.org/protobuf/encoding/protojson"

	pb "photonfarm/proto/renderfarm/v1"
)

// readEvents reads a recording of TestRecordSixRoundEvents.
func readEvents(t *testing.T, path string) []*pb.WatchJobResponse {
	t.Helper()
	f, err := os.Open(path)
	if err != nil {
		t.Fatal(err)
	}
	defer f.Close()
	zr, err := gzip.NewReader(f)
	if err != nil {
		t.Fatal(err)
	}
	var events []*pb.WatchJobResponse
	sc := bufio.NewScanner(zr)
	sc.Buffer(nil, 1<<20)
	for sc.Scan() {
		ev := &pb.WatchJobResponse{}
		if err := protojson.Unmarshal(sc.Bytes(), ev); err != nil {
			t.Fatalf("%s:%d: %v", path, len(events)+1, err)
		}
		events = append(events, ev)
	}
	if err := sc.Err(); err != nil {
		t.Fatal(err)
	}
	return events
}

// barFrame is a drawn terminal line's bar and percentage.
var barFrame = regexp.MustCompile(`\[(#*)-*\]\s+\d+/\d+\s+\S+\s+(\d+)%`)

// TestSixRoundJobHasOneBarAndAnHonestETA replays a real 6-round job's events (the
// recording's own times as the clock, not the wall clock's) through the terminal bar:
// one line redrawn in place whose bar and percentage never go backwards, reach 100%
// only when the job has ended, and whose ETA when the bar first shows 50% is within 30%
// of the time the job really had left then.
func TestSixRoundJobHasOneBarAndAnHonestETA(t *testing.T) {
	events := readEvents(t, sixRoundEvents)
	last := events[len(events)-1].GetJob()
	if last.GetState() != pb.JobState_JOB_STATE_SUCCEEDED || len(last.GetRounds()) != 6 {
		t.Fatalf("recording ends %v after %d rounds, want a succeeded 6-round job", last.GetState(), len(last.GetRounds()))
	}
	end := last.GetEndTime().AsTime()

	clk := &fakeClock{}
	var out strings.Builder
	p := newProgress(&out, true, clk.now, 6)
	filled, pct, frames := 0, 0, 0
	var atHalf time.Time
	var etaAtHalf time.Duration
	for i, ev := range events {
		clk.t = ev.GetTime().AsTime()
		p.update(ev.GetJob(), clk.t)
		drawn := out.String()
		frame := drawn[strings.LastIndexByte(drawn, '\r')+1:]
		m := barFrame.FindStringSubmatch(frame)
		if m == nil {
			t.Fatalf("event %d: frame %q has no bar", i, frame)
		}
		frames++
		f, n := len(m[1]), atoi(t, m[2])
		if f < filled || n < pct {
			t.Errorf("event %d (%s): the bar went back from %d%% (%d #) to %d%% (%d #): %q", i, ev.GetKind(), pct, filled, n, f, frame)
		}
		if n == 100 && !strings.Contains(frame, "succeeded") {
			t.Errorf("event %d: 100%% before the job ended: %q", i, frame)
		}
		filled, pct = f, n
		if atHalf.IsZero() && p.frac.shown >= 0.5 {
			eta, ok := p.eta()
			if !ok || !strings.Contains(frame, "ETA "+clock(eta)) {
				t.Fatalf("event %d: at 50%% no ETA shown: %q", i, frame)
			}
			atHalf, etaAtHalf = clk.t, eta
		}
	}
	if strings.Contains(out.String(), "\n") || strings.Count(out.String(), "\r") != frames {
		t.Errorf("the bar is not one line redrawn in place: %d frames, output %q...", frames, out.String()[:200])
	}
	if pct != 100 {
		t.Errorf("the last frame shows %d%%, want 100%%", pct)
	}
	left := end.Sub(atHalf)
	if atHalf.IsZero() || left <= 0 {
		t.Fatalf("the bar never showed 50%% before the end (%v)", atHalf)
	}
	if off := (etaAtHalf - left).Abs(); off > left*3/10 {
		t.Errorf("ETA at 50%%: %v, but the job had %v left (off by %.0f%%, want within 30%%)", etaAtHalf, left, 100*off.Seconds()/left.Seconds())
	}
	t.Logf("at 50%% (%v into the job): ETA %v, really left %v; %d events", atHalf.Sub(last.GetCreateTime().AsTime()), etaAtHalf, left, len(events))
}

func atoi(t *testing.T, s string) int {
	t.Helper()
	n, err := strconv.Atoi(s)
	if err != nil {
		t.Fatal(err)
	}
	return n
}
