package coordinator_test

import (
	"bytes"
	"context"
	"encoding/binary"
	"fmt"
	"net"
	"net/http"
	"net/http/httptest"
	"strings"
	"testing"
	"time"

	"golang.org/x/net/http2"
	"golang.org/x/net/http2/hpack"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"
	"google.golang.org/protobuf/types/known/emptypb"

	"photonfarm/client"
	"photonfarm/coordinator"
	"photonfarm/coordinator/service"
	pb "photonfarm/proto/renderfarm/v1"
)

// h2 is a raw HTTP/2 connection to a coordinator: what a hostile peer sees and sends.
type h2 struct {
	t    *testing.T
	conn net.Conn
	fr   *http2.Framer
}

func dialH2(t *testing.T, addr string) *h2 {
	t.Helper()
	conn, err := net.DialTimeout("tcp", addr, 5*time.Second)
	if err != nil {
		t.Fatal(err)
	}
	t.Cleanup(func() { conn.Close() })
	conn.SetDeadline(time.Now().Add(10 * time.Second))
	if _, err := conn.Write([]byte(http2.ClientPreface)); err != nil {
		t.Fatal(err)
	}
	fr := http2.NewFramer(conn, conn)
	fr.ReadMetaHeaders = hpack.NewDecoder(4096, nil)
	if err := fr.WriteSettings(); err != nil {
		t.Fatal(err)
	}
	return &h2{t: t, conn: conn, fr: fr}
}

// next reads frames until one for which ok holds, acknowledging the server's settings.
func (c *h2) next(what string, ok func(http2.Frame) bool) http2.Frame {
	c.t.Helper()
	for {
		f, err := c.fr.ReadFrame()
		if err != nil {
			c.t.Fatalf("reading until %s: %v", what, err)
		}
		if s, isSettings := f.(*http2.SettingsFrame); isSettings && !s.IsAck() {
			c.fr.WriteSettingsAck()
		}
		if ok(f) {
			return f
		}
	}
}

// TestServerSettingsBoundStreamsAndHeaders reads the SETTINGS a coordinator announces:
// at most service.MaxStreamsPerConnection calls at once per connection, and headers of at
// most service.MaxHeaderBytes (gRPC reads them before the token check).
func TestServerSettingsBoundStreamsAndHeaders(t *testing.T) {
	s := serve(t, coordinator.Config{ClientTokens: []string{clientToken}, WorkerTokens: []string{workerToken}})
	c := dialH2(t, s.Addr)
	f := c.next("the server's SETTINGS", func(f http2.Frame) bool {
		s, ok := f.(*http2.SettingsFrame)
		return ok && !s.IsAck()
	}).(*http2.SettingsFrame)
	for id, want := range map[http2.SettingID]uint32{
		http2.SettingMaxConcurrentStreams: service.MaxStreamsPerConnection,
		http2.SettingMaxHeaderListSize:    service.MaxHeaderBytes,
	} {
		if got, ok := f.Value(id); !ok || got != want {
			t.Errorf("%v = %d (announced: %v), want %d", id, got, ok, want)
		}
	}
}

// TestUnauthenticatedCallIsRefusedBeforeItsMessage starts a SubmitJob without a token
// whose message says it has 60 MB and sends only its first 16 KiB: the coordinator must
// refuse the call (UNAUTHENTICATED, and reset the stream) at once, without waiting for the
// rest of the message.
func TestUnauthenticatedCallIsRefusedBeforeItsMessage(t *testing.T) {
	s := serve(t, coordinator.Config{ClientTokens: []string{clientToken}, WorkerTokens: []string{workerToken}})
	c := dialH2(t, s.Addr)
	var hb bytes.Buffer
	enc := hpack.NewEncoder(&hb)
	for _, hf := range [][2]string{
		{":method", "POST"}, {":scheme", "http"}, {":path", pb.JobService_SubmitJob_FullMethodName},
		{":authority", s.Addr}, {"content-type", "application/grpc"}, {"te", "trailers"},
	} {
		enc.WriteField(hpack.HeaderField{Name: hf[0], Value: hf[1]})
	}
	if err := c.fr.WriteHeaders(http2.HeadersFrameParam{StreamID: 1, BlockFragment: hb.Bytes(), EndHeaders: true}); err != nil {
		t.Fatal(err)
	}
	msg := make([]byte, 16<<10)                  // one frame of the default largest size
	binary.BigEndian.PutUint32(msg[1:5], 60<<20) // the length prefix of a 60 MB message
	if err := c.fr.WriteData(1, false, msg); err != nil {
		t.Fatal(err)
	}
	start := time.Now()
	got := c.next("the refusal", func(f http2.Frame) bool {
		h, ok := f.(*http2.MetaHeadersFrame)
		return ok && h.StreamID == 1 && field(h, "grpc-status") != ""
	}).(*http2.MetaHeadersFrame)
	if code := field(got, "grpc-status"); code != "16" { // UNAUTHENTICATED
		t.Errorf("grpc-status %q (%s), want 16 UNAUTHENTICATED", code, field(got, "grpc-message"))
	}
	t.Logf("refused after %v with the message's first 16 KiB of 60 MB: %s", time.Since(start).Round(time.Millisecond), field(got, "grpc-message"))
}

// TestRefusedCallsAreCounted: a call refused by the token check never reaches the
// metrics interceptor, so farm_rpc_refused_total counts it, by method and code; a method
// the farm does not serve counts as "unknown", whatever name the caller made up.
func TestRefusedCallsAreCounted(t *testing.T) {
	s := serve(t, coordinator.Config{ClientTokens: []string{clientToken}, WorkerTokens: []string{workerToken}})
	conn := s.Dial(t)
	jobs := pb.NewJobServiceClient(conn)
	ctx := context.Background()
	for _, c := range []struct {
		call func() error
		want codes.Code
	}{
		{func() error { _, err := jobs.ListJobs(ctx, &pb.ListJobsRequest{}); return err }, codes.Unauthenticated},
		{func() error {
			_, err := jobs.ListJobs(client.ContextWithToken(ctx, "guessed-token"), &pb.ListJobsRequest{})
			return err
		}, codes.Unauthenticated},
		{func() error {
			_, err := jobs.ListJobs(client.ContextWithToken(ctx, workerToken), &pb.ListJobsRequest{})
			return err
		}, codes.PermissionDenied},
		{func() error { return conn.Invoke(ctx, "/made.up.Service/One", &emptypb.Empty{}, &emptypb.Empty{}) }, codes.Unauthenticated},
		{func() error { return conn.Invoke(ctx, "/made.up.Service/Two", &emptypb.Empty{}, &emptypb.Empty{}) }, codes.Unauthenticated},
	} {
		if err := c.call(); status.Code(err) != c.want {
			t.Fatalf("got %v, want %v", err, c.want)
		}
	}
	rec := httptest.NewRecorder()
	s.Coordinator.MetricsHandler().ServeHTTP(rec, httptest.NewRequest(http.MethodGet, "/metrics", nil))
	listJobs := pb.JobService_ListJobs_FullMethodName
	for _, want := range []string{
		fmt.Sprintf(`farm_rpc_refused_total{code="Unauthenticated",method=%q} 2`, listJobs),
		fmt.Sprintf(`farm_rpc_refused_total{code="PermissionDenied",method=%q} 1`, listJobs),
		`farm_rpc_refused_total{code="Unauthenticated",method="unknown"} 2`,
	} {
		if !strings.Contains(rec.Body.String(), want+"\n") {
			t.Errorf("the metrics lack %s", want)
		}
	}
	if strings.Contains(rec.Body.String(), "made.up") {
		t.Error("a made-up method name became a label")
	}
}

// field is the value of the header field name in h, or "".
func field(h *http2.MetaHeadersFrame, name string) string {
	for _, f := range h.Fields {
		if f.Name == name {
			return f.Value
		}
	}
	return ""
}
