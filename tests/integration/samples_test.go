package integration

import (
	"fmt"
	"io"
	"net/http"
	"strings"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// Issue 14, black pixels: the camera samples every render tile counted reach the
// coordinator's metrics. At one sample per pixel and no edge supersampling a round draws
// exactly one sample per pixel, and the lit test scene has no non-finite one.
func TestTileSampleCountsReachTheCoordinatorsMetrics(t *testing.T) {
	f := farmtest.StartFarm(t, []string{"--metrics-listen", "127.0.0.1:0"})
	f.StartWorker(t)
	sc := f.TestScene(t, 48, 32, 16, 1)
	sc.Antialiasing = &pb.Antialiasing{Mode: pb.AntialiasingMode_ANTIALIASING_MODE_NONE}
	f.Render(t, sc, 90*time.Second)

	_, url, ok := strings.Cut(f.Coordinator().LogTail(200), "metrics on ")
	if !ok {
		t.Fatal("the coordinator did not say where it serves metrics")
	}
	url, _, _ = strings.Cut(url, "\n")
	resp, err := http.Get(strings.TrimSpace(url))
	if err != nil {
		t.Fatal(err)
	}
	defer resp.Body.Close()
	body, _ := io.ReadAll(resp.Body)
	for _, line := range []string{
		fmt.Sprintf(`farm_render_samples_total{outcome="all"} %d`, 48*32),
		`farm_render_samples_total{outcome="nonfinite"} 0`,
	} {
		if !strings.Contains(string(body), "\n"+line+"\n") {
			t.Errorf("metrics lack %q", line)
		}
	}
}
