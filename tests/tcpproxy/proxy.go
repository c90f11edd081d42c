// Package tcpproxy is a TCP proxy for tests of network faults: it forwards connections to
// a server and can freeze them (a hung server or a cut cable that keeps the connection
// open), cut them (a server that dies, a network that drops every connection), and cut
// them once a given number of bytes came from the server (a fault in the middle of a
// transfer). It counts the bytes it forwards from the server.
package tcpproxy

import (
	"net"
	"sync"
	"sync/atomic"
	"testing"
)

// Proxy forwards TCP connections from a loopback address, Addr, to a server.
type Proxy struct {
	Addr   string
	target string
	lis    net.Listener

	downstream atomic.Int64 // bytes forwarded from the server

	mu     sync.Mutex
	thawed chan struct{} // closed while not frozen
	conns  []net.Conn
	cutAt  int64         // CutOnceAfter's mark; 0: none
	cut    chan struct{} // closed when CutOnceAfter cut
}

// New listens on a loopback port and forwards to target (host:port); it closes in
// t.Cleanup.
func New(t testing.TB, target string) *Proxy {
	t.Helper()
	lis, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		t.Fatal(err)
	}
	p := &Proxy{Addr: lis.Addr().String(), target: target, lis: lis, thawed: make(chan struct{}), cut: make(chan struct{})}
	close(p.thawed)
	go p.serve()
	t.Cleanup(p.close)
	return p
}

func (p *Proxy) serve() {
	for {
		c, err := p.lis.Accept()
		if err != nil {
			return
		}
		up, err := net.Dial("tcp", p.target)
		if err != nil {
			c.Close()
			continue
		}
		p.mu.Lock()
		p.conns = append(p.conns, c, up)
		p.mu.Unlock()
		go p.pipe(up, c, false)
		go p.pipe(c, up, true)
	}
}

// pipe copies src to dst, holding each chunk while the proxy is frozen and counting what
// comes from the server.
func (p *Proxy) pipe(dst, src net.Conn, fromServer bool) {
	defer dst.Close()
	buf := make([]byte, 32<<10)
	for {
		n, err := src.Read(buf)
		if n > 0 {
			p.mu.Lock()
			gate := p.thawed
			p.mu.Unlock()
			<-gate
			if _, werr := dst.Write(buf[:n]); werr != nil {
				return
			}
			if fromServer {
				p.forwarded(int64(n))
			}
		}
		if err != nil {
			return // the end of src (io.EOF) or a closed connection
		}
	}
}

// forwarded counts n bytes from the server and cuts every connection the first time the
// count passes CutOnceAfter's mark.
func (p *Proxy) forwarded(n int64) {
	total := p.downstream.Add(n)
	p.mu.Lock()
	defer p.mu.Unlock()
	if p.cutAt > 0 && total >= p.cutAt {
		p.cutAt = 0
		p.cutLocked()
		close(p.cut)
	}
}

// Downstream is how many bytes the proxy has forwarded from the server.
func (p *Proxy) Downstream() int64 { return p.downstream.Load() }

// CutOnceAfter makes the proxy cut every connection the first time the bytes it has
// forwarded from the server (counted from its start) pass n; the returned channel is
// closed then. Connections made afterwards go through.
func (p *Proxy) CutOnceAfter(n int64) <-chan struct{} {
	p.mu.Lock()
	defer p.mu.Unlock()
	p.cutAt = n
	return p.cut
}

// Freeze stops passing bytes; Thaw passes them again.
func (p *Proxy) Freeze() {
	p.mu.Lock()
	defer p.mu.Unlock()
	p.thawed = make(chan struct{})
}

func (p *Proxy) Thaw() {
	p.mu.Lock()
	defer p.mu.Unlock()
	select {
	case <-p.thawed:
	default:
		close(p.thawed)
	}
}

// Cut closes every connection open now, as a server that dies does; new ones go
// through.
func (p *Proxy) Cut() {
	p.mu.Lock()
	defer p.mu.Unlock()
	p.cutLocked()
}

func (p *Proxy) cutLocked() {
	for _, c := range p.conns {
		c.Close()
	}
	p.conns = nil
}

func (p *Proxy) close() {
	p.lis.Close()
	p.Thaw()
	p.Cut()
}
