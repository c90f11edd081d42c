package dashboard

import (
	"net/http"
	"net/netip"
	"testing"
	"time"
)

func TestThrottleRefillsAndForgets(t *testing.T) {
	now := time.Date(2030, 1, 1, 0, 0, 0, 0, time.UTC)
	th := newThrottle(3, func() time.Time { return now })
	a, b := netip.MustParsePrefix("192.0.2.1/32"), netip.MustParsePrefix("192.0.2.2/32")
	for range 3 {
		if !th.allowed(a) {
			t.Fatal("refused within the burst")
		}
		th.refused(a)
	}
	if th.allowed(a) {
		t.Fatal("allowed after the burst")
	}
	if !th.allowed(b) {
		t.Fatal("another address is throttled too")
	}
	now = now.Add(RefusedTokenEvery - time.Millisecond)
	if th.allowed(a) {
		t.Fatal("allowed before a refusal was given back")
	}
	now = now.Add(time.Millisecond)
	if !th.allowed(a) {
		t.Fatalf("still throttled after %v", RefusedTokenEvery)
	}

	// A full table forgets the addresses whose budget refilled; newcomers to a table of
	// throttled addresses share one budget.
	for i := range maxThrottled {
		th.refused(netip.PrefixFrom(netip.AddrFrom4([4]byte{10, byte(i >> 16), byte(i >> 8), byte(i)}), 32))
	}
	now = now.Add(3 * RefusedTokenEvery)
	th.refused(netip.MustParsePrefix("198.51.100.1/32"))
	if n := len(th.buckets); n != 1 {
		t.Errorf("%d addresses remembered after the others refilled, want 1", n)
	}
	for i := range maxThrottled + 3 {
		th.refused(netip.PrefixFrom(netip.AddrFrom4([4]byte{11, byte(i >> 16), byte(i >> 8), byte(i)}), 32))
	}
	if n := len(th.buckets); n > maxThrottled+1 {
		t.Errorf("%d addresses remembered, want at most %d and the shared one", n, maxThrottled)
	}
	if th.allowed(netip.MustParsePrefix("203.0.113.9/32")) {
		t.Error("a newcomer to a full table is allowed though the shared budget is spent")
	}
}

func TestClientKey(t *testing.T) {
	for addr, want := range map[string]string{
		"192.0.2.7:5555":             "192.0.2.7/32",
		"[::ffff:192.0.2.7]:5555":    "192.0.2.7/32",
		"[2001:db8:1:2:3:4:5:6]:443": "2001:db8:1:2::/64",
		"[2001:db8:1:2:ffff::1]:443": "2001:db8:1:2::/64",
		"not an address":             "invalid Prefix",
		"127.0.0.1:1":                "127.0.0.1/32",
	} {
		if got := clientKey(&http.Request{RemoteAddr: addr}).String(); got != want {
			t.Errorf("clientKey(%q) = %s, want %s", addr, got, want)
		}
	}
}
