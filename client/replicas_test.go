package client

import (
	"context"
	"net"
	"strings"
	"testing"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials/insecure"
	"google.golang.org/grpc/health"
	healthpb "google.golang.org/grpc/health/grpc_health_v1"
)

func TestAddressListsSplitIntoReplicasOrSayWhatIsWrong(t *testing.T) {
	for _, tc := range []struct {
		addr    string
		want    []string
		wantErr string
	}{
		{addr: "localhost:7070", want: []string{"localhost:7070"}},
		{addr: "dns:///coordinator:7070", want: []string{"dns:///coordinator:7070"}},
		{addr: "10.0.0.1:7070,coord-b.example:7070", want: []string{"10.0.0.1:7070", "coord-b.example:7070"}},
		{addr: "[::1]:1,[::1]:2", want: []string{"[::1]:1", "[::1]:2"}},
		{addr: "", wantErr: "empty coordinator address"},
		{addr: "a:1,", wantErr: `"" in the list "a:1," is not host:port`},
		{addr: "a:1,b", wantErr: `"b" in the list`},
		{addr: "a:1,a:1", wantErr: `"a:1" is listed twice`},
	} {
		got, err := addresses(tc.addr)
		if tc.wantErr != "" {
			if err == nil || !strings.Contains(err.Error(), tc.wantErr) {
				t.Errorf("addresses(%q) = %v, %v; want an error with %q", tc.addr, got, err, tc.wantErr)
			}
			continue
		}
		if err != nil || strings.Join(got, " ") != strings.Join(tc.want, " ") {
			t.Errorf("addresses(%q) = %q, %v; want %q", tc.addr, got, err, tc.want)
		}
	}
}

func TestIsLoopbackHoldsForAListOnlyIfForEveryReplica(t *testing.T) {
	if !IsLoopback("127.0.0.1:1,localhost:2,[::1]:3") {
		t.Error("a list of loopback replicas is not loopback")
	}
	if IsLoopback("127.0.0.1:1,10.0.0.2:2") {
		t.Error("a list with a replica on another machine is loopback")
	}
}

// replica is a gRPC server on loopback whose health service knows one service, its name,
// so that a call says which replica answered it.
func replica(t *testing.T, name string) (addr string, stop func()) {
	t.Helper()
	lis, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		t.Fatal(err)
	}
	srv := grpc.NewServer()
	h := health.NewServer()
	h.SetServingStatus(name, healthpb.HealthCheckResponse_SERVING)
	healthpb.RegisterHealthServer(srv, h)
	go srv.Serve(lis)
	t.Cleanup(srv.Stop)
	return lis.Addr().String(), srv.Stop
}

// answeredBy asks the replicas behind conn n times which of them answers and counts the
// answers by replica name.
func answeredBy(conn *grpc.ClientConn, n int, names ...string) map[string]int {
	counts := map[string]int{}
	h := healthpb.NewHealthClient(conn)
	for range n {
		for _, name := range names {
			ctx, cancel := context.WithTimeout(context.Background(), 2*time.Second)
			if _, err := h.Check(ctx, &healthpb.HealthCheckRequest{Service: name}); err == nil {
				counts[name]++
			}
			cancel()
		}
	}
	return counts
}

func TestAListOfReplicasSpreadsCallsAndFailsOverToTheOthers(t *testing.T) {
	a, stopA := replica(t, "a")
	b, _ := replica(t, "b")
	target, opts, err := ReplicaTarget(a + "," + b)
	if err != nil {
		t.Fatal(err)
	}
	conn, err := grpc.NewClient(target, append(opts, grpc.WithTransportCredentials(insecure.NewCredentials()))...)
	if err != nil {
		t.Fatal(err)
	}
	defer conn.Close()
	// Round robin sends every other call to each replica once both are connected; until
	// then the calls go to the one that is.
	deadline := time.Now().Add(10 * time.Second)
	for got := answeredBy(conn, 20, "a"); got["a"] != 10; got = answeredBy(conn, 20, "a") {
		if time.Now().After(deadline) {
			t.Fatalf("replica a answers %d of 20 calls, want every other one", got["a"])
		}
	}
	stopA()
	deadline = time.Now().Add(10 * time.Second)
	for got := answeredBy(conn, 10, "b"); got["b"] < 10; got = answeredBy(conn, 10, "b") {
		if time.Now().After(deadline) {
			t.Fatalf("10 s after replica a stopped, b answers %d of 10 calls, want every one", got["b"])
		}
	}
}
