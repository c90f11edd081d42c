package coordinator_test

import (
	"bytes"
	"encoding/binary"
	"net"
	"testing"
	"time"

	"golang.org/x/net/http2"
	"golang.org/x/net/http2/hpack"

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

// field is the value of the header field name in h, or "".
func field(h *http2.MetaHeadersFrame, name string) string {
	for _, f := range h.Fields {
		if f.Name == name {
			return f.Value
		}
	}
	return ""
}
