package dashboard

import (
	"net"
	"net/http"
	"net/netip"
	"sync"
	"time"
)

// Refused tokens per client address (API.md, docs/limits.md): each address may present
// up to DefaultRefusedTokenBurst tokens the coordinator refuses, and one more every
// RefusedTokenEvery after that; past it, every request of that address that carries a
// token answers 429 without asking the coordinator, so guessing tokens through the
// dashboard goes at most that fast.
const (
	DefaultRefusedTokenBurst = 10
	RefusedTokenEvery        = 6 * time.Second
	// maxThrottled bounds the addresses remembered. Addresses whose budget has refilled
	// are forgotten first; when every remembered address is still throttled, a new one
	// shares the budget of all such newcomers.
	maxThrottled = 4096
)

// throttle counts refused tokens per client address in token buckets.
type throttle struct {
	mu      sync.Mutex
	burst   float64
	now     func() time.Time
	buckets map[netip.Prefix]*bucket
}

// bucket is an address's budget: tokens left at the time it was last updated.
type bucket struct {
	left float64
	at   time.Time
}

// overflow is the key newcomers share when the table is full of throttled addresses.
var overflow = netip.Prefix{}

func newThrottle(burst int, now func() time.Time) *throttle {
	return &throttle{burst: float64(burst), now: now, buckets: make(map[netip.Prefix]*bucket)}
}

// clientKey is what a request's budget is kept by: its IPv4 address, or its IPv6 /64
// (one host usually has a whole /64). Behind a reverse proxy every browser shares the
// proxy's address.
func clientKey(r *http.Request) netip.Prefix {
	host, _, err := net.SplitHostPort(r.RemoteAddr)
	if err != nil {
		host = r.RemoteAddr
	}
	a, err := netip.ParseAddr(host)
	if err != nil {
		return overflow
	}
	a = a.Unmap()
	bits := 32
	if a.Is6() {
		bits = 64
	}
	p, _ := a.Prefix(bits)
	return p
}

// left refills b to now and returns how many refusals it has left.
func (t *throttle) left(b *bucket, now time.Time) float64 {
	b.left = min(t.burst, b.left+float64(now.Sub(b.at))/float64(RefusedTokenEvery))
	b.at = now
	return b.left
}

// allowed reports whether key may present a token now.
func (t *throttle) allowed(key netip.Prefix) bool {
	t.mu.Lock()
	defer t.mu.Unlock()
	b := t.buckets[key]
	if b == nil {
		b = t.buckets[overflow]
		if b == nil || len(t.buckets) < maxThrottled {
			return true
		}
	}
	return t.left(b, t.now()) >= 1
}

// refused records that key presented a token the coordinator refused.
func (t *throttle) refused(key netip.Prefix) {
	t.mu.Lock()
	defer t.mu.Unlock()
	now := t.now()
	b := t.buckets[key]
	if b == nil {
		if len(t.buckets) >= maxThrottled {
			t.forgetRefilled(now)
		}
		if len(t.buckets) >= maxThrottled {
			key = overflow
		}
		if b = t.buckets[key]; b == nil {
			b = &bucket{left: t.burst, at: now}
			t.buckets[key] = b
		}
	}
	t.left(b, now)
	b.left = max(0, b.left-1)
}

// forgetRefilled drops the addresses whose budget is whole again.
func (t *throttle) forgetRefilled(now time.Time) {
	for k, b := range t.buckets {
		if t.left(b, now) >= t.burst {
			delete(t.buckets, k)
		}
	}
}
