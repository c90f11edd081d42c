package redistest

import (
	"bytes"
	"errors"
	"io"
	"net"
	"sync"
	"testing"

	"github.com/redis/go-redis/v9"
)

// Proxy is a TCP proxy in front of a Server that can lose an answer after the fact: armed
// with CutReplyTo, it forwards the next request that contains a given string, lets Redis
// run it and answer, drops the answer and closes the client's connection, as a network
// failure between Redis and the client would. The client cannot tell whether its command
// ran.
type Proxy struct {
	t    testing.TB
	lis  net.Listener
	addr string

	mu    sync.Mutex
	armed []byte // a request containing it is cut; nil: none
	skip  int    // how many such requests go through first
	cuts  int
	conns []net.Conn
}

// Proxy starts a proxy to s, stopped in t.Cleanup.
func (s *Server) Proxy() *Proxy {
	s.t.Helper()
	lis, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		s.t.Fatalf("proxy: %v", err)
	}
	p := &Proxy{t: s.t, lis: lis, addr: lis.Addr().String()}
	go p.accept(s.addr)
	s.t.Cleanup(p.close)
	return p
}

// Addr is the proxy's host:port.
func (p *Proxy) Addr() string { return p.addr }

// Client returns a client of the server through the proxy, closed in t.Cleanup; opts, if
// given, are used with their Addr set to the proxy's.
func (p *Proxy) Client(opts ...*redis.Options) *redis.Client {
	o := &redis.Options{}
	if len(opts) > 0 {
		o = opts[0]
	}
	o.Addr = p.addr
	c := redis.NewClient(o)
	p.t.Cleanup(func() { _ = c.Close() })
	return c
}

// CutReplyTo arms the proxy: the nth request from now (from 1) whose bytes contain what
// (say "evalsha") reaches Redis, and Redis's answer to it never reaches the client.
func (p *Proxy) CutReplyTo(what string, nth int) {
	p.mu.Lock()
	defer p.mu.Unlock()
	p.armed, p.skip = bytes.ToLower([]byte(what)), nth-1
}

// Cuts is how many answers the proxy has dropped.
func (p *Proxy) Cuts() int {
	p.mu.Lock()
	defer p.mu.Unlock()
	return p.cuts
}

func (p *Proxy) accept(server string) {
	for {
		c, err := p.lis.Accept()
		if err != nil {
			return
		}
		s, err := net.Dial("tcp", server)
		if err != nil {
			c.Close()
			continue
		}
		p.mu.Lock()
		p.conns = append(p.conns, c, s)
		p.mu.Unlock()
		go p.pipe(c, s)
	}
}

// pipe forwards one client connection c to server connection s: requests as they come,
// and answers until a request was cut, when it waits for the answer, drops it and closes
// both.
func (p *Proxy) pipe(c, s net.Conn) {
	cut := make(chan struct{})
	go func() {
		buf := make([]byte, 64<<10)
		for {
			n, err := c.Read(buf)
			if n > 0 {
				armed := p.take(buf[:n])
				if armed {
					close(cut) // before Redis can answer: what comes back now is its answer
				}
				if _, werr := s.Write(buf[:n]); werr != nil {
					return
				}
			}
			if err != nil {
				s.Close()
				return
			}
		}
	}()
	defer c.Close()
	defer s.Close()
	buf := make([]byte, 64<<10)
	for {
		n, err := s.Read(buf)
		select {
		case <-cut:
			return // Redis ran the request and answered: drop the answer
		default:
		}
		if n > 0 {
			if _, werr := c.Write(buf[:n]); werr != nil {
				return
			}
		}
		if err != nil {
			if !errors.Is(err, io.EOF) && !errors.Is(err, net.ErrClosed) {
				p.t.Logf("proxy: %v", err)
			}
			return
		}
	}
}

// take reports whether request chunk b is the one to cut, disarming the proxy if so.
func (p *Proxy) take(b []byte) bool {
	p.mu.Lock()
	defer p.mu.Unlock()
	if p.armed == nil || !bytes.Contains(bytes.ToLower(b), p.armed) {
		return false
	}
	if p.skip > 0 {
		p.skip--
		return false
	}
	p.armed = nil
	p.cuts++
	return true
}

func (p *Proxy) close() {
	p.lis.Close()
	p.mu.Lock()
	defer p.mu.Unlock()
	for _, c := range p.conns {
		c.Close()
	}
}
