package hostile

import (
	"bytes"
	"context"
	"fmt"
	"io"
	"net/http"
	"strings"
	"sync"
	"testing"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/credentials/insecure"
	"google.golang.org/grpc/status"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// Sizes of the unauthenticated flood (issue 12, acceptance 1).
const (
	floodRequests = 16
	floodBytes    = 60 << 20
	// peakRSSLimit is the most resident memory either process may reach.
	peakRSSLimit = 200 << 20
)

// TestUnauthenticatedFloodCostsLittleMemory sends a real coordinator (tokens on) 16
// concurrent 60 MB SubmitJob calls without a token or with an unknown one, and the
// dashboard in front of it 16 concurrent 60 MB job posts without a session: every one
// must be refused, and each process's peak resident memory (VmHWM) must stay under
// 200 MB, because neither reads a request before it knows who sent it. Both must still
// serve a client with the right token afterwards.
func TestUnauthenticatedFloodCostsLittleMemory(t *testing.T) {
	f := farmtest.StartFarm(t, farmtest.TokenFlags(t, clientToken, workerToken), client.WithToken(clientToken))
	dash, url := f.StartDashboard(t)
	ctx, cancel := context.WithTimeout(context.Background(), 2*time.Minute)
	defer cancel()

	conn, err := grpc.NewClient(f.Addr, grpc.WithTransportCredentials(insecure.NewCredentials()),
		grpc.WithDefaultCallOptions(grpc.MaxCallSendMsgSize(2*floodBytes)))
	if err != nil {
		t.Fatal(err)
	}
	defer conn.Close()
	jobs := pb.NewJobServiceClient(conn)
	huge := &pb.SubmitJobRequest{Scene: &pb.Scene{Name: strings.Repeat("x", floodBytes)}}
	start := time.Now()
	flood(t, "SubmitJob", func(i int) error {
		callCtx := ctx
		if i%2 == 1 {
			callCtx = client.ContextWithToken(ctx, "guessed-token")
		}
		_, err := jobs.SubmitJob(callCtx, huge)
		if status.Code(err) != codes.Unauthenticated {
			return fmt.Errorf("got %v, want UNAUTHENTICATED", err)
		}
		return nil
	})
	t.Logf("coordinator: %d x %d MB unauthenticated SubmitJob refused in %v; peak RSS %d MB",
		floodRequests, floodBytes>>20, time.Since(start).Round(time.Millisecond), f.Coordinator().PeakRSS(t)>>20)

	body := bytes.Repeat([]byte("x"), floodBytes)
	start = time.Now()
	flood(t, "POST /api/jobs", func(i int) error {
		req, err := http.NewRequestWithContext(ctx, http.MethodPost, url+"api/jobs", bytes.NewReader(body))
		if err != nil {
			return err
		}
		req.Header.Set("Content-Type", "application/json")
		if i%2 == 1 {
			req.AddCookie(&http.Cookie{Name: "farm_token", Value: "guessed-token"})
		}
		resp, err := http.DefaultClient.Do(req)
		if err != nil {
			// The dashboard answers and closes the connection without reading the
			// body; the client may see the close before the answer.
			return nil
		}
		defer resp.Body.Close()
		io.Copy(io.Discard, resp.Body)
		if resp.StatusCode != http.StatusUnauthorized {
			return fmt.Errorf("got %s, want 401", resp.Status)
		}
		return nil
	})
	t.Logf("dashboard: %d x %d MB posts without a session refused in %v; peak RSS %d MB",
		floodRequests, floodBytes>>20, time.Since(start).Round(time.Millisecond), dash.PeakRSS(t)>>20)

	for _, p := range []*farmtest.Proc{f.Coordinator(), dash} {
		if peak := p.PeakRSS(t); peak > peakRSSLimit {
			t.Errorf("%s peaked at %d MB resident, over the limit of %d MB", p.Name, peak>>20, peakRSSLimit>>20)
		}
	}
	if _, err := f.Client.ListJobs(ctx); err != nil {
		t.Errorf("the coordinator after the flood: %v", err)
	}
	req, _ := http.NewRequestWithContext(ctx, http.MethodGet, url+"api/jobs", nil)
	req.Header.Set("Authorization", "Bearer "+clientToken)
	if resp, err := http.DefaultClient.Do(req); err != nil || resp.StatusCode != http.StatusOK {
		t.Errorf("the dashboard after the flood: %v, %v", resp, err)
	} else {
		resp.Body.Close()
	}
}

// flood runs call(0..floodRequests-1) at once and fails t with every error.
func flood(t *testing.T, what string, call func(i int) error) {
	t.Helper()
	var wg sync.WaitGroup
	errs := make([]error, floodRequests)
	for i := range floodRequests {
		wg.Go(func() { errs[i] = call(i) })
	}
	wg.Wait()
	for i, err := range errs {
		if err != nil {
			t.Errorf("%s %d: %v", what, i, err)
		}
	}
}
