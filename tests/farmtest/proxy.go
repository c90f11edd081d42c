package farmtest

import (
	"net"
	"sync"
	"sync/atomic"
	"testing"
)

// Proxy forwards TCP connections from a loopback address to a target (a coordinator), and
// counts the bytes it forwards from the target: a worker told the proxy's address talks to
// the coordinator through it, and the test can cut every connection at once, as a network
// fault does.
type Proxy struct {
	Addr string // where to connect

	target     string
	lis        net.Listener
	downstream atomic.Int64 // bytes forwarded from the target
	mu         sync.Mutex
	conns      map[net.Conn]struct{}
	cutAt      int64 // cut every connection once downstream passes this; 0: never
	cut        chan struct{}
}

// StartProxy listens on a loopback port and forwards each connection to target until the
// test ends.
func StartProxy(t testing.TB, target string) *Proxy {
	t.Helper()
	lis, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		t.Fatal(err)
	}
	p := &Proxy{Addr: lis.Addr().String(), target: target, lis: lis, conns: map[net.Conn]struct{}{}, cut: make(chan struct{})}
	go p.serve()
	t.Cleanup(func() {
		lis.Close()
		p.closeAll()
	})
	return p
}

// CutOnceAfter makes the proxy close every connection, both ways, the first time the bytes
// it has forwarded from the target pass n (counted from its start); the returned channel is
// closed then. New connections are forwarded as before.
func (p *Proxy) CutOnceAfter(n int64) <-chan struct{} {
	p.mu.Lock()
	defer p.mu.Unlock()
	p.cutAt = n
	return p.cut
}

// Downstream is how many bytes the proxy has forwarded from the target.
func (p *Proxy) Downstream() int64 { return p.downstream.Load() }

func (p *Proxy) serve() {
	for {
		c, err := p.lis.Accept()
		if err != nil {
			return
		}
		u, err := net.Dial("tcp", p.target)
		if err != nil {
			c.Close()
			continue
		}
		p.mu.Lock()
		p.conns[c], p.conns[u] = struct{}{}, struct{}{}
		p.mu.Unlock()
		go p.pipe(u, c, false)
		go p.pipe(c, u, true)
	}
}

// pipe copies from src to dst until either ends, counting what comes from the target.
func (p *Proxy) pipe(dst, src net.Conn, fromTarget bool) {
	defer func() {
		dst.Close()
		src.Close()
		p.mu.Lock()
		delete(p.conns, dst)
		delete(p.conns, src)
		p.mu.Unlock()
	}()
	buf := make([]byte, 32<<10)
	for {
		n, err := src.Read(buf)
		if n > 0 {
			if _, werr := dst.Write(buf[:n]); werr != nil {
				return
			}
			if fromTarget && p.countAndMaybeCut(int64(n)) {
				return
			}
		}
		if err != nil {
			return // the end of either side ends both
		}
	}
}

// countAndMaybeCut adds n forwarded bytes and, the first time the total passes the cut,
// closes every connection; it reports whether it did.
func (p *Proxy) countAndMaybeCut(n int64) bool {
	total := p.downstream.Add(n)
	p.mu.Lock()
	cut := p.cutAt > 0 && total >= p.cutAt
	if cut {
		p.cutAt = 0
	}
	p.mu.Unlock()
	if cut {
		p.closeAll()
		close(p.cut)
	}
	return cut
}

func (p *Proxy) closeAll() {
	p.mu.Lock()
	defer p.mu.Unlock()
	for c := range p.conns {
		c.Close()
	}
}
